/*
 * demo/ies.c - the IES lamp row of `qibl demo`: a goniometric lamp (a built-in LM-63 profile,
 * parsed by tools/io/ies like any file) carried along the light-path part's lamp track, relit by
 * the core (unshadowed maps x the track's visibility, the lamp's light scaled per pixel by its
 * octahedral table, qibl/gonio.h) against the ray tracer's goniometric lamp of the same profile in
 * double precision; beside it the same frames with the profile ignored (the isotropic lamp), which
 * says what the profile changes in the picture.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "demo/demo.h"
#include "io/ies.h"
#include "qibl/gonio.h"
#include "qtool.h"
#include "ref/psnr.h"
#include "render/rt.h"

enum { IES_N = 64 }; /* the table's side: 8 KiB, bilinear error well below the 8-bit frame's */

/* The built-in profile as LM-63-2002 text: a type C downlight of 37 x 73 angles, bright toward the
 * nadir and leaning toward horizontal angle 0, with a two-lobed variation around the axis and a dim
 * upward part (smooth, so the table's bilinear resampling is not what is measured). */
static char *profile_text(void)
{
    size_t cap = 64 * 1024, at = 0;
    char *s = malloc(cap);
    if (!s)
        return NULL;
    at += (size_t)snprintf(s + at, cap - at, "IESNA:LM-63-2002\n[TEST] qibl demo downlight\nTILT=NONE\n"
                                             "1 -1 1 37 73 1 2 0 0 0\n1 1 10\n");
    for (int i = 0; i <= 36; ++i)
        at += (size_t)snprintf(s + at, cap - at, "%d ", 5 * i);
    at += (size_t)snprintf(s + at, cap - at, "\n");
    for (int j = 0; j <= 72; ++j)
        at += (size_t)snprintf(s + at, cap - at, "%d ", 5 * j);
    at += (size_t)snprintf(s + at, cap - at, "\n");
    for (int j = 0; j <= 72; ++j) {
        for (int i = 0; i <= 36; ++i) {
            double v = 5 * i * QTOOL_DEMO_PI15 / 180, h = 5 * j * QTOOL_DEMO_PI15 / 180;
            double cd = 100 + 80 * cos(v) + 40 * sin(v) * cos(h) + 20 * sin(v) * sin(2 * h);
            at += (size_t)snprintf(s + at, cap - at, "%.4f ", cd);
        }
        at += (size_t)snprintf(s + at, cap - at, "\n");
    }
    return s;
}

/* What the row holds while it runs; every pointer owned. */
typedef struct {
    qtool_ies prof;
    qtool_ies_lamp lamp;
    qibl_gonio_t gonio;
    uint16_t *table;
    double *lin;
    float *depth;
    uint8_t *truth, *mask, *relit;
} ies_ctx;

static void ies_ctx_free(ies_ctx *c)
{
    qtool_ies_free(&c->prof);
    free(c->table), free(c->lin), free(c->depth), free(c->truth), free(c->mask), free(c->relit);
}

/* the profile, its table and frame (aim down, horizontal angle 0 toward +x), the buffers */
static int ies_setup(ies_ctx *c, size_t np, char *err, size_t errlen)
{
    char *text = profile_text(), why[512];
    if (!text)
        return qtool_errf(err, errlen, "demo: out of memory (IES row)");
    int bad = qtool_ies_decode((const uint8_t *)text, strlen(text), &c->prof, why, sizeof why) != 0;
    free(text);
    if (bad)
        return qtool_errf(err, errlen, "demo: the built-in IES profile: %s", why);
    static const double aim[3] = {0, 0, -1}, up[3] = {1, 0, 0};
    static const int32_t aimq[3] = {0, 0, -65536}, upq[3] = {65536, 0, 0};
    c->table = malloc(qibl_gonio_table_size(IES_N));
    c->lin = malloc(np * 3 * sizeof(double)), c->depth = malloc(np * sizeof(float));
    c->truth = malloc(np * 3), c->mask = malloc(np), c->relit = malloc(np * 3);
    if (!c->table || !c->lin || !c->depth || !c->truth || !c->mask || !c->relit)
        return qtool_errf(err, errlen, "demo: out of memory (IES row)");
    if (qtool_ies_gonio_table(&c->prof, IES_N, c->table, NULL) != 0 ||
        qtool_ies_lamp_init(&c->lamp, &c->prof, aim, up) != 0 ||
        qibl_gonio_init(&c->gonio, IES_N, c->table, aimq, upq) != QIBL_OK)
        return qtool_errf(err, errlen, "demo: the built-in IES profile gives no lamp");
    return 0;
}

int qtool_demo_ies(const qtool_demo_view *v, const uint8_t *asset, size_t n, uint32_t path,
                   const qtool_bake_path *track, uint32_t npos, char *err, size_t errlen)
{
    size_t np = (size_t)v->w * v->h;
    ies_ctx c;
    memset(&c, 0, sizeof c);
    clock_t c0 = clock(); /* the process's CPU time: the ray tracer's threads included */
    double t0 = qtool_demo_now(), se_g = 0, se_i = 0, ms[QTOOL_DEMO_MAX_IES_POS];
    int rc = npos < 1 || npos > QTOOL_DEMO_MAX_IES_POS ? qtool_errf(err, errlen, "demo: %u IES positions", npos)
                                                       : ies_setup(&c, np, err, errlen);
    for (uint32_t i = 0; rc == 0 && i < npos; ++i) {
        /* positions between the baked steps, as the light-path part's */
        uint32_t tq = (uint32_t)lrint(65535.0 * (i + 0.37) / npos);
        qtool_rt_light l;
        qibl_status_t st = QIBL_OK;
        qtool_bake_path_light(track, tq / 65535.0, &l);
        if (qtool_rt_render_gonio(v->scene, v->w, v->h, v->kind, &l, qtool_ies_lamp_scale, &c.lamp, v->threads, c.lin,
                                  c.depth, NULL) != 0)
            rc = qtool_errf(err, errlen, "demo: out of memory (IES truth)");
        if (rc != 0)
            break;
        qtool_bake_lin_to8(c.lin, v->w, v->h, c.truth);
        for (size_t p = 0; p < np; ++p)
            c.mask[p] = c.depth[p] > 0;
        for (int g = 0; rc == 0 && g < 2; ++g) {
            if (qtool_bake_relight_path8_gonio(asset, n, &l, g ? NULL : &c.gonio, path, tq, 0, NULL, c.relit, NULL,
                                               g ? NULL : &ms[i], &st) != 0)
                rc = qtool_errf(err, errlen, "demo: relight (IES lamp on the track) failed: %s", qibl_status_str(st));
            else
                *(g ? &se_i : &se_g) += qtool_bake_mse(c.relit, c.truth, c.mask, np) / npos;
        }
    }
    if (rc == 0) {
        FILE *o = v->out;
        fprintf(o, "\nIES lamp on the lamp track: a built-in LM-63 profile (type C, %u x %u angles, %.0f lm), "
                   "%dx%d table, aimed down, at %u positions between the baked steps, against the ray-traced "
                   "lamp of the same profile\n\n", c.prof.nv, c.prof.nh, qtool_ies_lumens(&c.prof), IES_N, IES_N, npos);
        fprintf(o, "| %-58s | ms/frame | PSNR dB |\n|%s|---------:|--------:|\n",
                "relit by the core", "------------------------------------------------------------");
        fprintf(o, "| %-58s | %8.3f | %7.2f |\n", "IES lamp: unshadowed k16 x track visibility x gonio table",
                qtool_demo_median(ms, (int)npos), qtool_ref_psnr8(se_g));
        fprintf(o, "| %-58s | %8s | %7.2f |\n", "the profile ignored (isotropic lamp, same track)", "",
                qtool_ref_psnr8(se_i));
        fprintf(o, "RESULT demo.ies_track_psnr %.2f\nRESULT demo.ies_track_isotropic_psnr %.2f\n"
                   "RESULT demo.ies_track_ms %.3f\n", qtool_ref_psnr8(se_g), qtool_ref_psnr8(se_i),
                qtool_demo_median(ms, (int)npos));
        fprintf(o, "IES row: %.1f s wall, %.1f s CPU (truths and relighting)\n", qtool_demo_now() - t0,
                (double)(clock() - c0) / CLOCKS_PER_SEC);
    }
    ies_ctx_free(&c);
    return rc;
}
