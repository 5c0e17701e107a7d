/*
 * relight/light.c - relight's light list (light.h): the list itself, the --lights CSV reader, the
 * probe's SH in three modes and the rotation.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/hdr.h"
#include "io/lightcsv.h"
#include "qibl/probe.h"
#include "qtool.h"
#include "relight/light.h"

void qtool_relight_light_list_init(qtool_relight_light_list *ll)
{
    const qtool_relight_light_list empty = QTOOL_RELIGHT_LIGHT_LIST_DEFAULT;
    *ll = empty;
}

int qtool_relight_light_list_add(qtool_relight_light_list *ll, int point, const int32_t v[3])
{
    if (ll->count >= QTOOL_RELIGHT_MAX_SOURCES)
        return -1;
    qtool_relight_source *s = &ll->src[ll->count];
    memset(s, 0, sizeof *s);
    memcpy(s->v, v, sizeof s->v);
    s->point = point;
    s->rgb[0] = s->rgb[1] = s->rgb[2] = 65536;
    if (ll->count == 0 && ll->early_rgb) /* `--rgb R G B --sun X Y Z`: the old order still works */
        memcpy(s->rgb, ll->rgb0, sizeof s->rgb), s->have_rgb = 1;
    ++ll->count;
    if (point)
        ++ll->points;
    else
        ++ll->suns;
    return 0;
}

int qtool_relight_light_list_directional(const qtool_relight_light_list *ll)
{
    return ll->suns > 0 || ll->csv || ll->probe;
}

void qtool_relight_yaw(double deg, double r[3][3])
{
    double t = deg * QTOOL_PI / 180.0, c = cos(t), s = sin(t);
    const double m[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}}; /* about +z: +x turns toward +y */
    memcpy(r, m, sizeof m);
}

int qtool_relight_rotation_check(const double v[9], double *worst, double *det)
{
    /* the core takes r with r r^T - I within 2^-16 and det r > 0 */
    double wst = 0;
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) {
            double d = -(p == q);
            for (int k = 0; k < 3; ++k)
                d += v[3 * p + k] * v[3 * q + k];
            wst = fmax(wst, fabs(d));
        }
    *worst = wst;
    *det = v[0] * (v[4] * v[8] - v[5] * v[7]) - v[1] * (v[3] * v[8] - v[5] * v[6]) +
           v[2] * (v[3] * v[7] - v[4] * v[6]);
    return wst > 1.0 / 65536 || *det <= 0 ? -1 : 0;
}

/* ---- probes ------------------------------------------------------------------------------------- */

void qtool_relight_probe_note(const char *path, qtool_probe_layout_t want, qtool_probe_layout_t u, int iw, int ih,
                              int lw, int lh, char *note, size_t notelen)
{
    int k = snprintf(note, notelen, "%s: layout %s (%s, %s)", path, qtool_probe_layout_name(u),
                     qtool_probe_layout_describe(u), want == QTOOL_PROBE_LAYOUT_AUTO ? "detected" : "from --layout");
    size_t at = k < 0 ? 0 : (size_t)k < notelen ? (size_t)k : notelen - 1;
    if (u != QTOOL_PROBE_LAYOUT_LATLONG)
        snprintf(note + at, notelen - at, ", %d x %d resampled to a %d x %d lat-long\n", iw, ih, lw, lh);
    else if ((size_t)iw != 2 * (size_t)ih)
        snprintf(note + at, notelen - at, ", %d x %d is not 2:1: read as lat-long as asked\n", iw, ih);
    else
        snprintf(note + at, notelen - at, "\n");
    size_t len = strlen(note);
    if (len && note[len - 1] != '\n') /* a path too long for the buffer: the line still ends */
        note[len - 1] = '\n';
}

int qtool_relight_probe_load(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w,
                             int *h, uint8_t **rgbe, qtool_probe_layout_t *used, char *err, size_t errlen)
{
    int iw, ih, lw, lh;
    uint8_t *px, *ll;
    char why[512];
    qtool_probe_layout_t u;
    if (qtool_hdr_read_rgbe(path, &iw, &ih, &px, why, sizeof why) != 0)
        return qtool_errf(err, errlen, "%s", why);
    if (want == QTOOL_PROBE_LAYOUT_LATLONG || (want == QTOOL_PROBE_LAYOUT_AUTO && (size_t)iw == 2 * (size_t)ih)) {
        u = QTOOL_PROBE_LAYOUT_LATLONG, lw = iw, lh = ih, ll = px; /* as it is: no copy of the input */
    } else {
        if (qtool_probe_layout_rgbe_to_latlong(want, iw, ih, px, &u, &lw, &lh, &ll, why, sizeof why) != 0) {
            free(px);
            return qtool_errf(err, errlen, "%s: %s", path, why);
        }
        free(px);
    }
    if (note && notelen)
        qtool_relight_probe_note(path, want, u, iw, ih, lw, lh, note, notelen);
    *w = lw, *h = lh, *rgbe = ll;
    if (used)
        *used = u;
    return 0;
}

/* solid angle of a region of a w x h lat-long: (u1 - u0) 2 pi / w times the sum of pi / h sin theta_v */
static double region_sr(const qibl_lightprobe_light_t *l, uint32_t w, uint32_t h)
{
    double s = 0;
    for (uint32_t v = l->v0; v < l->v1 && v < h; ++v)
        s += sin((v + 0.5) * QTOOL_PI / h);
    return (double)(l->u1 - l->u0) * (2.0 * QTOOL_PI / w) * (QTOOL_PI / h) * s;
}

static double region_density(const qibl_lightprobe_light_t *l, uint32_t w, uint32_t h)
{
    double sr = region_sr(l, w, h);
    return sr > 0 ? (0.2126 * l->rgb[0] + 0.7152 * l->rgb[1] + 0.0722 * l->rgb[2]) / sr : 0;
}

uint32_t qtool_relight_probe_suns(const qibl_lightprobe_light_t *l, uint32_t count, uint32_t w, uint32_t h,
                                  uint32_t *idx)
{
    /* the regions cover every lit pixel, so their sum over 4 pi is the probe's mean radiance */
    double total = 0;
    for (uint32_t i = 0; i < count; ++i)
        total += 0.2126 * l[i].rgb[0] + 0.7152 * l[i].rgb[1] + 0.0722 * l[i].rgb[2];
    double floor_d = QTOOL_RELIGHT_SUN_CONTRAST * total / (4 * QTOOL_PI), last = INFINITY;
    uint32_t n = 0;
    while (n < QTOOL_RELIGHT_SUN_MAX) { /* densest first: repeated selection (count is small) */
        double bd = -1;
        uint32_t bi = count;
        for (uint32_t i = 0; i < count; ++i) {
            double d = region_density(&l[i], w, h);
            int taken = 0;
            for (uint32_t j = 0; j < n; ++j)
                taken |= idx[j] == i;
            if (!taken && d <= last && d > bd)
                bd = d, bi = i;
        }
        if (bi == count || bd < floor_d || bd <= 0)
            break;
        idx[n++] = bi, last = bd;
    }
    return n;
}

/* dst += src coefficient by coefficient; -1 (dst untouched) if a sum leaves int32 */
static int shlight_sum(qibl_shlight_t *dst, const qibl_shlight_t *src)
{
    for (int c = 0; c < 3; ++c)
        for (uint32_t i = 0; i < dst->k; ++i) {
            int64_t s = (int64_t)dst->c[c][i] + src->c[c][i];
            if (s > INT32_MAX || s < INT32_MIN)
                return -1;
        }
    for (int c = 0; c < 3; ++c)
        for (uint32_t i = 0; i < dst->k; ++i)
            dst->c[c][i] += src->c[c][i];
    return 0;
}

static const char *mode_name(qtool_relight_probe_mode m)
{
    return m == QTOOL_RELIGHT_PROBE_SH ? "SH" : m == QTOOL_RELIGHT_PROBE_LIGHTS ? "median-cut lights" : "sun plus sky";
}

/* the probe's median-cut lights into p: all of them (mode lights), or the sun regions as lights and
 * the rest as SH (mode sunsky); notes on note. A status, QIBL_E_NULL_POINTER for out of memory. */
static qibl_status_t probe_mediancut(const qtool_relight_light_list *ll, const qibl_lightprobe_image_t *img,
                                     const qibl_probe_sh_opts_t *opts, size_t wsn, FILE *note, qibl_shlight_t *p)
{
    long n = ll->n ? ll->n : QTOOL_RELIGHT_PROBE_DEFAULT_N;
    size_t lwn = qibl_lightprobe_workspace_size(img->width, img->height, QIBL_LIGHTPROBE_MEDIANCUT);
    void *lws = lwn ? malloc(lwn) : NULL, *ws = NULL;
    qibl_lightprobe_light_t *L = malloc(sizeof *L * (size_t)n);
    qibl_status_t st = QIBL_E_NULL_POINTER;
    qibl_lightprobe_t lp;
    qibl_lightprobe_result_t res;
    if (!lws || !L)
        goto out;
    st = qibl_lightprobe_build(&lp, img, QIBL_LIGHTPROBE_MEDIANCUT, lws, lwn);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, NULL, L, (uint32_t)n, &res);
    if (st == QIBL_E_PROBE_BLACK) {
        fprintf(note, "%s: an all-black probe: no light from it\n", ll->probe);
        st = QIBL_OK;
    } else if (st == QIBL_OK && ll->mode == QTOOL_RELIGHT_PROBE_LIGHTS) {
        st = qibl_shlight_add_lights(p, L, res.count, res.rgb_exp, 0);
        fprintf(note, "%s: %u median-cut lights\n", ll->probe, res.count);
    } else if (st == QIBL_OK) {
        uint32_t idx[QTOOL_RELIGHT_SUN_MAX];
        qibl_lightprobe_light_t suns[QTOOL_RELIGHT_SUN_MAX];
        uint32_t ns = qtool_relight_probe_suns(L, res.count, img->width, img->height, idx);
        for (uint32_t i = 0; i < ns; ++i)
            suns[i] = L[idx[i]];
        ws = malloc(wsn);
        st = ws ? qibl_shlight_add_sun_sky(p, img, opts, suns, ns, res.rgb_exp, ws, wsn) : QIBL_E_NULL_POINTER;
        if (ws)
            fprintf(note, "%s: sun = %u of %u median-cut regions (those at least %g times the probe's mean "
                          "radiance), sky = SH of the rest\n", ll->probe, ns, res.count, QTOOL_RELIGHT_SUN_CONTRAST);
    }
out:
    free(ws), free(lws), free(L);
    return st;
}

/* the probe's light rotated by ll->r (k = bands^2 coefficients) */
static qibl_status_t rotate_part(const qtool_relight_light_list *ll, qibl_shlight_t *p)
{
    int bands = 1;
    while ((uint32_t)(bands * bands) < p->k)
        ++bands;
    qibl_q30_t r[3][3];
    qibl_sh_rotation_t rot;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r[i][j] = (qibl_q30_t)lrint(ll->r[i][j] * 1073741824.0);
    qibl_status_t st = qibl_sh_rotation_init(&rot, r, bands);
    return st == QIBL_OK ? qibl_shlight_rotate(p, &rot) : st;
}

/* 1 if the probe has light while its SH rounds to nothing in Q16.16 (no exposure brings such a
 * frame back) */
static int faint_part(const uint8_t *px, size_t np, const qibl_shlight_t *p)
{
    int lit = 0, any = 0;
    for (size_t i = 0; i < np && !lit; ++i)
        lit = px[4 * i + 3] != 0 && (px[4 * i] | px[4 * i + 1] | px[4 * i + 2]) != 0;
    for (int c = 0; c < 3; ++c)
        for (uint32_t i = 0; i < p->k; ++i)
            any |= p->c[c][i] != 0;
    return lit && !any;
}

/* the probe's part of the light, rotated; 0 or -1 with err set */
static int probe_part(const qtool_relight_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *p, int *faint,
                      char *err, size_t errlen)
{
    int w, h;
    uint8_t *px;
    char line[4200 + 256]; /* a path of PATH_MAX and the rest of the line */
    if (!note)
        note = stderr;
    if (qtool_relight_probe_load(ll->probe, ll->layout, line, sizeof line, &w, &h, &px, NULL, err, errlen) != 0)
        return -1;
    fputs(line, note);
    qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
    qibl_probe_sh_opts_t opts = {0, QIBL_PROBE_WINDOW_NONE, 0}; /* radiance: the maps hold the cosine */
    void *ws = NULL;
    int rc = -1;
    qibl_status_t st = qibl_shlight_init(p, k);
    size_t wsn = qibl_probe_sh_workspace_size(img.width, img.height);
    if (!wsn) {
        qtool_errf(err, errlen, "%s: %d x %d is beyond the probe limits", ll->probe, w, h);
        goto out;
    }
    if (st == QIBL_OK && ll->mode == QTOOL_RELIGHT_PROBE_SH) {
        ws = malloc(wsn);
        st = ws ? qibl_shlight_add_probe(p, &img, &opts, ws, wsn) : QIBL_E_NULL_POINTER;
    } else if (st == QIBL_OK) {
        st = probe_mediancut(ll, &img, &opts, wsn, note, p);
    }
    if (st == QIBL_OK && ll->rotate)
        st = rotate_part(ll, p);
    if (st == QIBL_E_NULL_POINTER)
        qtool_errf(err, errlen, "relight: out of memory for %s", ll->probe);
    else if (st == QIBL_E_PROBE_SATURATED)
        qtool_errf(err, errlen, "%s: the probe's SH is beyond the Q16.16 light (too bright for the core's lights)",
                   ll->probe);
    else if (st != QIBL_OK)
        qtool_errf(err, errlen, "%s: %s", ll->probe, qibl_status_str(st));
    if (st != QIBL_OK)
        goto out;
    if (ll->rotate)
        fprintf(note, "%s: %s, rotated once in SH (%s)\n", ll->probe, mode_name(ll->mode),
                ll->rotate == 1 ? "--yaw" : "--rotate");
    if (faint)
        *faint = faint_part(px, (size_t)w * (size_t)h, p);
    rc = 0;
out:
    free(ws), free(px);
    return rc;
}

/* the suns' part of the light */
static int sun_part(const qtool_relight_light_list *ll, uint32_t k, qibl_shlight_t *tot, char *err, size_t errlen)
{
    qibl_shlight_t part;
    for (uint32_t i = 0; i < ll->count; ++i) {
        const qtool_relight_source *s = &ll->src[i];
        if (s->point)
            continue;
        qibl_status_t st = qibl_shlight_init(&part, k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_dir(&part, s->v, s->rgb);
        if (st != QIBL_OK)
            return qtool_errf(err, errlen, "relight: --sun %g %g %g: %s", s->v[0] / 65536.0, s->v[1] / 65536.0,
                              s->v[2] / 65536.0, qibl_status_str(st));
        if (shlight_sum(tot, &part) != 0)
            return qtool_errf(err, errlen, "relight: the suns add up beyond the Q16.16 light");
    }
    return 0;
}

int qtool_relight_light_sh(const qtool_relight_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out,
                           int *faint, char *err, size_t errlen)
{
    qibl_shlight_t tot, part;
    qibl_status_t st = qibl_shlight_init(&tot, k);
    if (faint)
        *faint = 0;
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "relight: %s", qibl_status_str(st));
    if (sun_part(ll, k, &tot, err, errlen) != 0)
        return -1;
    if (ll->csv) {
        qibl_lightprobe_light_t *L;
        uint32_t n;
        int32_t e;
        char why[600];
        if (qtool_lightcsv_read(ll->csv, &L, &n, &e, why, sizeof why) != 0)
            return qtool_errf(err, errlen, "%s", why);
        st = qibl_shlight_init(&part, k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_lights(&part, L, n, e, 0);
        free(L);
        if (st != QIBL_OK)
            return qtool_errf(err, errlen, "%s: %s", ll->csv, qibl_status_str(st));
        if (shlight_sum(&tot, &part) != 0)
            return qtool_errf(err, errlen, "%s: the lights add up beyond the Q16.16 light", ll->csv);
    }
    if (ll->probe) {
        if (probe_part(ll, k, note, &part, faint, err, errlen) != 0)
            return -1;
        if (shlight_sum(&tot, &part) != 0)
            return qtool_errf(err, errlen, "%s: the probe and the other lights add up beyond the Q16.16 light",
                              ll->probe);
    }
    *out = tot;
    return 0;
}
