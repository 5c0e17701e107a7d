/*
 * demo/nearfield.c - the near-field row of `qibl demo`: the built-in luminaire (a patterned shade
 * around an emitter) captured as Granier et al.'s near-field source, rendered as its grid of
 * textured spotlights against the luminaire ray-traced through its shade, beside the same source
 * treated as a far-field (IES-like) point lamp, at several distances from the lamp; then the
 * near-field kernel's time per frame in the courtyard (the library calls of `qibl luminaire study`,
 * sized by the demo's sizes table, with the default hierarchy, whose time it prints beside the full
 * sum's); then ms per frame per pass count on the demo's own asset, every spotlight everywhere.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "demo/demo.h"
#include "io/asset_write.h"
#include "luminaire/luminaire.h"
#include "qibl/asset.h"
#include "qtool.h"

static int cmp_ms(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* ms per frame per pass count: the built-in luminaire captured on 4x4, 8x8 and 16x16 grids (one
 * pass per spotlight that reaches below it), hung two lamp sizes above the courtyard's ground 2.5
 * units from the viewpoint as the study's, relit on the demo's k = 16 asset (its point maps, P map
 * and LUT, as `qibl luminaire render` does); the median of 3 frames' CPU time on this thread */
static int pass_times(const qtool_demo_view *v, const uint8_t *asset, size_t n, char *err, size_t errlen)
{
    qtool_luminaire_views av;
    qibl_status_t st = qtool_luminaire_views_open(asset, n, &av);
    const qibl_shmaps_t mp = av.mp;
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "demo: near-field passes: the k = 16 asset: %s", qibl_status_str(st));
    qtool_luminaire_model *m = qtool_luminaire_builtin();
    uint8_t *rgb = malloc((size_t)mp.width * mp.height * 3);
    int rc = m && rgb ? 0 : qtool_errf(err, errlen, "demo: out of memory (near-field passes)");
    const int32_t pos[3] = {0, (int32_t)(2.5 * 65536), (int32_t)((-1.6 + 2 * QTOOL_LUMINAIRE_SIZE) * 65536)};
    static const uint32_t grids[3] = {4, 8, 16};
    uint32_t passes[3] = {0, 0, 0};
    double med[3] = {0, 0, 0};
    fprintf(v->out, "\nnear-field source in the courtyard (k = 16 asset, %ux%u): CPU ms per frame by pass count "
                    "(one pass per spotlight reaching below the lamp, every spotlight everywhere: the study above "
                    "times the hierarchy)\n\n| supports | passes | ms/frame |\n|---------:|-------:|---------:|\n",
            mp.width, mp.height);
    for (int g = 0; rc == 0 && g < 3; ++g) {
        qtool_luminaire l;
        qtool_luminaire_spots s = {0};
        qtool_luminaire_capture_opts co = {.grid = grids[g], .res = 32, .threads = v->threads};
        double ms[3];
        if (qtool_luminaire_capture(m, &co, &l) != 0) {
            rc = qtool_errf(err, errlen, "demo: out of memory (near-field capture)");
            break;
        }
        if (qtool_luminaire_spots_make(&l, pos, 0, 0, &s, err, errlen) != 0)
            rc = -1;
        for (int r = 0; rc == 0 && r < 3; ++r)
            if (qtool_luminaire_relight(&s, &av.mp, &av.pm, av.lut, 65536, 1, rgb, NULL, &ms[r], &st) != 0)
                rc = qtool_errf(err, errlen, "demo: near-field passes: %s", qibl_status_str(st));
        if (rc == 0) {
            qsort(ms, 3, sizeof ms[0], cmp_ms);
            passes[g] = s.count, med[g] = ms[1];
            fprintf(v->out, "| %8u | %6u | %8.2f |\n", grids[g] * grids[g], s.count, ms[1]);
        }
        qtool_luminaire_spots_free(&s);
        qtool_luminaire_free(&l);
    }
    for (int g = 0; rc == 0 && g < 3; ++g)
        fprintf(v->out, "RESULT demo.nearfield_passes_g%u %u\nRESULT demo.nearfield_ms_g%u %.2f\n", grids[g], passes[g],
                grids[g], med[g]);
    free(rgb);
    qtool_luminaire_model_free(m);
    return rc;
}

int qtool_demo_nearfield(const qtool_demo_view *v, const qtool_demo_size *sz, const uint8_t *asset, size_t n,
                         char *err, size_t errlen)
{
    clock_t c0 = clock(); /* the process's CPU time: the ray tracer's threads included */
    double t0 = qtool_demo_now();
    qibl_asset_t a; /* the asset first: a bad one costs no study */
    qibl_shmaps_t mp;
    qibl_pmap_t pm;
    if (asset == NULL || qtool_asset_open(&a, asset, n) != QIBL_OK || qibl_asset_point_shmaps(&a, &mp) != QIBL_OK ||
        qibl_asset_pmap(&a, &pm) != QIBL_OK)
        return qtool_errf(err, errlen, "demo: near-field row: the k = 16 asset has no usable point maps and P map");
    const int quick = sz->nf_size < 96u;
    qtool_luminaire_study_opts o = {.grid = sz->nf_grid, .res = 32, .size = sz->nf_size, .quick = quick,
                                    .threads = v->threads, .tol = QTOOL_LUMINAIRE_DEFAULT_TOL};
    fprintf(v->out, "\nnear-field source (Granier et al.): the built-in luminaire captured on a %ux%u grid, its "
                    "spotlights against the luminaire ray-traced through its shade and against its far-field "
                    "(point lamp) treatment, on a %ux%u ground patch at %s heights (in lamp sizes), then in the "
                    "courtyard\n", sz->nf_grid, sz->nf_grid, sz->nf_size, sz->nf_size, quick ? "3" : "5");
    fflush(v->out);
    if (qtool_luminaire_study(&o, v->out) != 0)
        return qtool_errf(err, errlen, "demo: the near-field row failed (out of memory)");
    if (pass_times(v, asset, n, err, errlen) != 0)
        return -1;
    fprintf(v->out, "near-field row: %.1f s wall, %.1f s CPU\n", qtool_demo_now() - t0,
            (double)(clock() - c0) / CLOCKS_PER_SEC);
    return 0;
}
