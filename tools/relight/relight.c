/*
 * relight/relight.c - an asset relit by relight's light (relight.h): the IES lamp, the asset and
 * its maps, the point lamps with their default colours, and the frame with any number of lights
 * summed per pixel in 64 bits.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "io/asset_write.h"
#include "io/file.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "relight/relight.h"

int qtool_relight_uses_lut(qtool_relight_point_mode m)
{
    return m == QTOOL_RELIGHT_POINT_NEAREST || m == QTOOL_RELIGHT_POINT_BILINEAR;
}

/* ---- an IES lamp ------------------------------------------------------------------------------- */

int qtool_relight_ies_load(const char *path, uint32_t n, const int32_t aim[3], const int32_t up[3],
                           qtool_relight_ies *out, char *err, size_t errlen)
{
    qtool_ies prof;
    char why[512];
    memset(out, 0, sizeof *out);
    if (qtool_ies_read(path, &prof, why, sizeof why) != 0)
        return qtool_errf(err, errlen, "relight: %s", why);
    out->lumens = qtool_ies_lumens(&prof);
    out->type = prof.type == QTOOL_IES_TYPE_C ? 'C' : prof.type == QTOOL_IES_TYPE_B ? 'B' : 'A';
    out->sym = prof.sym;
    out->table = malloc(qibl_gonio_table_size(n));
    int bad = !out->table || qtool_ies_gonio_table(&prof, n, out->table, &out->peak) != 0;
    qtool_ies_free(&prof);
    if (bad) {
        qtool_errf(err, errlen, "relight: %s: %s", path,
                   out->table ? "the profile is dark (peak 0 cd)" : "out of memory");
        qtool_relight_ies_free(out);
        return -1;
    }
    out->status = qibl_gonio_init(&out->gonio, n, out->table, aim, up);
    if (out->status != QIBL_OK) {
        free(out->table), out->table = NULL;
        return -2;
    }
    return 0;
}

void qtool_relight_ies_free(qtool_relight_ies *ies)
{
    free(ies->table);
    ies->table = NULL;
}

/* ---- the asset --------------------------------------------------------------------------------- */

int qtool_relight_asset_read(const char *path, uint8_t **bytes, size_t *n, qibl_asset_t *a, qibl_shmaps_t *m,
                             char *err, size_t errlen)
{
    char why[512];
    if (qtool_io_read_asset(path, bytes, n, why, sizeof why) != 0) {
        *bytes = NULL;
        return qtool_errf(err, errlen, "%s", why);
    }
    qibl_status_t st = QIBL_OK;
    if (a)
        st = qtool_asset_open(a, *bytes, *n);
    if (st == QIBL_OK && a && m)
        st = qibl_asset_shmaps(a, m);
    if (st != QIBL_OK) {
        free(*bytes), *bytes = NULL;
        return qtool_errf(err, errlen, "%s: %s", path, qibl_soft_status_str(st));
    }
    return 0;
}

int qtool_relight_asset_open(qtool_relight_asset *s, const char *path, int points, int lut, char *err,
                             size_t errlen)
{
    memset(s, 0, sizeof *s);
    if (qtool_relight_asset_read(path, &s->bytes, &s->n, &s->a, &s->m, err, errlen) != 0)
        return -1;
    qibl_status_t st = QIBL_OK;
    if (points) /* free point lights: the unshadowed set when the asset has one */
        st = qibl_asset_point_shmaps(&s->a, &s->mp);
    if (st == QIBL_OK && points)
        st = qibl_asset_pmap(&s->a, &s->pm);
    if (st == QIBL_OK && points && lut)
        st = qibl_asset_ylut(&s->a, &s->lut);
    if (st != QIBL_OK) {
        qtool_relight_asset_free(s);
        return qtool_errf(err, errlen, "%s: %s", path, qibl_soft_status_str(st));
    }
    /* lamps through the unshadowed maps get the asset's lamp occlusion (LOCC) when it has one; one
     * that does not open is reported (occ_unusable), never dropped without a word */
    qibl_chunk_t shmu, locc;
    const int has_shmu = qibl_asset_find_nth(&s->a, QIBL_CHUNK_SHMU, 0, &shmu) == QIBL_OK;
    const int has_locc = qibl_asset_find_nth(&s->a, QIBL_CHUNK_LOCC, 0, &locc) == QIBL_OK;
    s->occ_status = has_locc ? qibl_lightpath_occl_from_asset(&s->a, &s->occ) : QIBL_E_ASSET_MISSING_CHUNK;
    s->use_occ = points && has_shmu && s->occ_status == QIBL_OK;
    s->occ_unusable = points && has_shmu && has_locc && s->occ_status != QIBL_OK;
    return 0;
}

void qtool_relight_asset_free(qtool_relight_asset *s)
{
    free(s->bytes);
    s->bytes = NULL;
}

/* ---- the lights and the frame ------------------------------------------------------------------- */

int qtool_relight_points(qtool_relight_opts *o, const qtool_relight_asset *s, qibl_pointlight_t *pts,
                         uint32_t *npts, qtool_relight_point_note *notes, char *err, size_t errlen)
{
    qtool_relight_light_list *ll = &o->lights;
    const int use_lut = qtool_relight_uses_lut(o->point_mode);
    const uint8_t lut = use_lut ? (o->point_mode == QTOOL_RELIGHT_POINT_NEAREST ? QIBL_LUT_NEAREST : QIBL_LUT_BILINEAR)
                        : o->point_mode == QTOOL_RELIGHT_POINT_POLY ? QIBL_POINT_POLY
                                                                    : QIBL_LUT_BILINEAR;
    double *pmp = NULL;
    uint32_t n = 0;
    for (uint32_t j = 0; j < ll->count; ++j) {
        qtool_relight_source *src = &ll->src[j];
        notes[j].set = 0;
        if (!src->point)
            continue;
        if (!src->have_rgb) {
            /* C0 = 1 lights a scene a few units away almost black: scale it with the scene's distance */
            double c0, d, lp[3] = {src->v[0] / 65536.0, src->v[1] / 65536.0, src->v[2] / 65536.0};
            if (!pmp)
                pmp = qtool_relight_pmap_points(&s->pm);
            if (!pmp || qtool_relight_point_default(pmp, (size_t)s->m.width * s->m.height, lp, (int)o->falloff, &c0,
                                                    &d) != 0) {
                free(pmp);
                return qtool_errf(err, errlen, "relight: out of memory");
            }
            src->rgb[0] = src->rgb[1] = src->rgb[2] = (qibl_q16_t)nearbyint(c0 * 65536.0);
            notes[j].set = 1, notes[j].c0 = c0, notes[j].d = d;
        }
        qibl_pointlight_t pl = {{src->v[0], src->v[1], src->v[2]}, {src->rgb[0], src->rgb[1], src->rgb[2]},
                                o->falloff == 2 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0, lut};
        pts[n++] = pl;
    }
    free(pmp);
    *npts = n;
    return 0;
}

int qtool_relight_render(const qtool_relight_opts *o, const qtool_relight_asset *s, const qibl_shlight_t *sh,
                         const qibl_pointlight_t *pts, uint32_t npts, const qtool_relight_ies *ies, uint8_t *rgb8,
                         float *lin, double *ms, qibl_status_t *status)
{
    const qibl_gonio_t *gl[QTOOL_RELIGHT_MAX_SOURCES];
    for (uint32_t j = 0; j < npts; ++j)
        gl[j] = ies ? &ies->gonio : NULL;
    return qtool_relight_frame_gonio(&s->m, sh, &s->mp, &s->pm, qtool_relight_uses_lut(o->point_mode) ? &s->lut : NULL,
                                     s->use_occ ? &s->occ : NULL, pts, ies ? gl : NULL, npts, (uint32_t)o->exposure,
                                     !o->linear, rgb8, lin, ms, status);
}

/* ---- the frame ------------------------------------------------------------------------------------ */

int qtool_relight_frame(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                       const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                       const qibl_pointlight_t *points, uint32_t npoints, uint32_t exposure, int srgb, uint8_t *rgb8,
                       float *lin, double *ms, qibl_status_t *status)
{
    return qtool_relight_frame_gonio(m, sh, mp, pm, lut, occ, points, NULL, npoints, exposure, srgb, rgb8, lin, ms,
                                    status);
}

int qtool_relight_frame_gonio(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                             const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                             const qibl_pointlight_t *points, const qibl_gonio_t *const *gonio, uint32_t npoints,
                             uint32_t exposure, int srgb, uint8_t *rgb8, float *lin, double *ms,
                             qibl_status_t *status)
{
    uint32_t w = m->width, h = m->height;
    size_t wsn = qibl_shmap_span_workspace_size(w);
    if (npoints && qibl_shmap_point_workspace_size(mp->k, w) > wsn)
        wsn = qibl_shmap_point_workspace_size(mp->k, w);
    uint8_t *pix = malloc((size_t)w * h * 4);
    int32_t *row = malloc(sizeof(int32_t) * 3 * w);
    int64_t *acc = malloc(sizeof(int64_t) * 3 * w);
    qibl_shmap_point_t *pt = malloc(sizeof *pt * (npoints ? npoints : 1));
    void *ws = malloc(wsn);
    qibl_status_t st = QIBL_OK;
    if (!pix || !row || !acc || !pt || !ws) {
        st = QTOOL_E_NOMEM;
        goto out;
    }
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = h, fb.format = QIBL_FB_RGBA8888;
    fb.srgb = srgb ? 1 : 0, fb.exposure = exposure;
    const double t0 = qtool_bake_now();
    qibl_shmap_weights_t wt;
    if (sh)
        st = qibl_shmap_weights(m, sh, &wt);
    for (uint32_t j = 0; st == QIBL_OK && j < npoints; ++j)
        st = qibl_shmap_point_prepare(mp, pm, lut, &points[j], &pt[j]);
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        memset(acc, 0, sizeof(int64_t) * 3 * w);
        if (sh) {
            st = qibl_shmap_relight_span(m, &wt, 0, y, w, row, ws, wsn);
            for (size_t i = 0; st == QIBL_OK && i < (size_t)w * 3; ++i)
                acc[i] += row[i];
        }
        for (uint32_t j = 0; st == QIBL_OK && j < npoints; ++j) {
            st = qibl_shmap_point_span(&pt[j], 0, y, w, row, ws, wsn);
            /* a goniometric lamp: its intensity toward each pixel's point (qibl/gonio.h) */
            if (st == QIBL_OK && gonio && gonio[j])
                st = qibl_gonio_scale_span(gonio[j], pm, points[j].pos, 0, y, w, row);
            if (st == QIBL_OK && occ)
                st = qibl_lightpath_occl_span(occ, 0, y, w, row);
            for (size_t i = 0; st == QIBL_OK && i < (size_t)w * 3; ++i)
                acc[i] += row[i];
        }
        for (size_t i = 0; i < (size_t)w * 3; ++i) /* saturate once: the sum, not each light */
            row[i] = acc[i] > INT32_MAX ? INT32_MAX : acc[i] < INT32_MIN ? INT32_MIN : (int32_t)acc[i];
        if (st == QIBL_OK)
            st = qtool_bake_frame_row(&fb, y, w, row, lin);
    }
    qtool_bake_frame_done(st, t0, ms, pix, w, h, rgb8, NULL); /* ms, and rgb8 when st is QIBL_OK */
out:
    free(pix), free(row), free(acc), free(pt), free(ws);
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}
