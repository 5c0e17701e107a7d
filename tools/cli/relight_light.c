/*
 * relight_light.c - relight's light list (relight_light.h): options, the --lights CSV reader, the
 * probe's SH in three modes, and the frame with any number of lights summed.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "io/hdr.h"
#include "io/lightcsv.h"
#include "qibl/probe.h"
#include "qibl/soft.h"

#define RL_PI 3.14159265358979323846

void qcli_light_list_init(qcli_light_list *ll)
{
    memset(ll, 0, sizeof *ll);
    ll->layout = QTOOL_PROBE_LAYOUT_AUTO;
    ll->mode = QCLI_PROBE_SH;
}

/* three numbers after argv[i] into Q16.16 (lo..QTOOL_CLI_Q16_MAX); 0 or 2 after a message */
static int parse3(char **argv, int i, int argc, double lo, int32_t v[3])
{
    if (i + 3 >= argc)
        return qcli_usage_error("%s needs three numbers", argv[i]);
    for (int j = 0; j < 3; ++j) {
        double d;
        if (qcli_parse_num(argv[i], argv[i + 1 + j], lo, QTOOL_CLI_Q16_MAX, QTOOL_CLI_Q16_WHY, &d) != 0)
            return 2;
        v[j] = (int32_t)nearbyint(d * 65536.0);
    }
    return 0;
}

static int add_source(qcli_light_list *ll, char **argv, int argc, int *i, int point)
{
    if (ll->count >= QCLI_RELIGHT_MAX_SOURCES)
        return qcli_usage_error("%s: at most %u --sun and --point options", argv[*i], QCLI_RELIGHT_MAX_SOURCES);
    qcli_relight_source *s = &ll->src[ll->count];
    memset(s, 0, sizeof *s);
    if (parse3(argv, *i, argc, -QTOOL_CLI_Q16_MAX, s->v) != 0)
        return 2;
    if (!point && s->v[0] == 0 && s->v[1] == 0 && s->v[2] == 0)
        return qcli_usage_error("--sun needs a non-zero direction: %s %s %s is 0 0 0 in Q16.16", argv[*i + 1],
                                argv[*i + 2], argv[*i + 3]);
    s->point = point;
    s->rgb[0] = s->rgb[1] = s->rgb[2] = 65536;
    if (ll->count == 0 && ll->early_rgb) /* `--rgb R G B --sun X Y Z`: the old order still works */
        memcpy(s->rgb, ll->rgb0, sizeof s->rgb), s->have_rgb = 1;
    ++ll->count;
    if (point)
        ++ll->points;
    else
        ++ll->suns;
    *i += 3;
    return 1;
}

int qcli_light_list_opt(int argc, char **argv, int *i, qcli_light_list *ll)
{
    const char *a = argv[*i];
    int more = *i + 1 < argc;
    if (strcmp(a, "--sun") == 0 || strcmp(a, "--point") == 0)
        return add_source(ll, argv, argc, i, a[2] == 'p');
    if (strcmp(a, "--rgb") == 0) {
        int32_t v[3];
        if (parse3(argv, *i, argc, 0, v) != 0)
            return 2;
        if (ll->count == 0) {
            if (ll->early_rgb)
                return qcli_usage_error("--rgb given twice before the first --sun/--point");
            ll->early_rgb = 1, memcpy(ll->rgb0, v, sizeof v);
        } else {
            qcli_relight_source *s = &ll->src[ll->count - 1];
            if (s->have_rgb)
                return qcli_usage_error("--rgb given twice for the %s at %s", s->point ? "--point" : "--sun",
                                        argv[*i + 1]);
            memcpy(s->rgb, v, sizeof v), s->have_rgb = 1;
        }
        *i += 3;
        return 1;
    }
    if (strcmp(a, "--lights") == 0 && more) {
        if (ll->csv)
            return qcli_usage_error("--lights given twice (%s and %s)", ll->csv, argv[*i + 1]);
        ll->csv = argv[++*i];
        return 1;
    }
    if (strcmp(a, "--probe") == 0 && more) {
        if (ll->probe)
            return qcli_usage_error("--probe given twice (%s and %s)", ll->probe, argv[*i + 1]);
        ll->probe = argv[++*i];
        return 1;
    }
    if (strcmp(a, "--layout") == 0 && more) {
        if (qtool_probe_layout_parse(argv[++*i], &ll->layout) != 0)
            return qcli_usage_error("--layout: '%s' is not a probe layout (auto, latlong, angular, ball, vcross or "
                                    "hcross)", argv[*i]);
        return 1;
    }
    if (strcmp(a, "--probe-mode") == 0 && more) {
        const char *m = argv[++*i];
        if (strcmp(m, "sh") == 0)
            ll->mode = QCLI_PROBE_SH;
        else if (strcmp(m, "lights") == 0)
            ll->mode = QCLI_PROBE_LIGHTS;
        else if (strcmp(m, "sunsky") == 0)
            ll->mode = QCLI_PROBE_SUNSKY;
        else
            return qcli_usage_error("--probe-mode: '%s' is not sh, lights or sunsky", m);
        return 1;
    }
    if (strcmp(a, "-n") == 0 && more) {
        if (qcli_parse_int(argv[++*i], 1, 65536, &ll->n) != 0 || (ll->n & (ll->n - 1)) != 0)
            return qcli_usage_error("-n: '%s' is not a power of two in 1..65536 (median-cut lights)", argv[*i]);
        return 1;
    }
    if (strcmp(a, "--yaw") == 0 && more) {
        if (ll->rotate)
            return qcli_usage_error("--yaw: give one of --yaw and --rotate, once");
        if (qcli_parse_num(a, argv[++*i], -36000.0, 36000.0, "degrees", &ll->yaw) != 0)
            return 2;
        double t = ll->yaw * RL_PI / 180.0, c = cos(t), s = sin(t);
        double r[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}}; /* about +z: +x turns toward +y */
        memcpy(ll->r, r, sizeof r);
        ll->rotate = 1;
        return 1;
    }
    if (strcmp(a, "--rotate") == 0 && more) {
        if (ll->rotate)
            return qcli_usage_error("--rotate: give one of --yaw and --rotate, once");
        const char *s = argv[++*i];
        double v[9];
        char *end;
        for (int k = 0; k < 9; ++k) {
            errno = 0;
            v[k] = strtod(s, &end);
            if (end == s || errno == ERANGE || !isfinite(v[k]) || (k < 8 ? *end != ',' : *end != '\0'))
                return qcli_usage_error("--rotate: '%s' is not nine comma-separated numbers a,b,c,d,e,f,g,h,i",
                                        argv[*i]);
            s = end + 1;
        }
        /* the core takes r with r r^T - I within 2^-16 and det r > 0; say so here, by name */
        double worst = 0, det;
        for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q) {
                double d = -(p == q);
                for (int k = 0; k < 3; ++k)
                    d += v[3 * p + k] * v[3 * q + k];
                worst = fmax(worst, fabs(d));
            }
        det = v[0] * (v[4] * v[8] - v[5] * v[7]) - v[1] * (v[3] * v[8] - v[5] * v[6]) +
              v[2] * (v[3] * v[7] - v[4] * v[6]);
        if (worst > 1.0 / 65536 || det <= 0)
            return qcli_usage_error("--rotate: '%s' is not a rotation (rows orthonormal within 2^-16: off by %.3g; "
                                    "det %.3g, must be +1)", argv[*i], worst, det);
        for (int k = 0; k < 9; ++k)
            ll->r[k / 3][k % 3] = v[k];
        ll->rotate = 2;
        return 1;
    }
    return 0;
}

int qcli_light_list_check(const qcli_light_list *ll)
{
    if (ll->early_rgb && ll->count == 0)
        return qcli_usage_error("--rgb colours a --sun or --point; there is none");
    if (!ll->probe && (ll->rotate || ll->n || ll->mode != QCLI_PROBE_SH || ll->layout != QTOOL_PROBE_LAYOUT_AUTO))
        return qcli_usage_error("--yaw, --rotate, --probe-mode, -n and --layout need --probe PROBE.hdr");
    if (ll->probe && ll->n && ll->mode == QCLI_PROBE_SH)
        return qcli_usage_error("-n counts median-cut lights: it needs --probe-mode lights or sunsky");
    return 0;
}

int qcli_light_list_directional(const qcli_light_list *ll)
{
    return ll->suns > 0 || ll->csv || ll->probe;
}

/* ---- probes ------------------------------------------------------------------------------------- */

int qcli_probe_load_note(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w, int *h,
                         uint8_t **rgbe, qtool_probe_layout_t *used)
{
    int iw, ih, lw, lh;
    uint8_t *px, *ll;
    char err[512];
    qtool_probe_layout_t u;
    if (qtool_hdr_read_rgbe(path, &iw, &ih, &px, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (want == QTOOL_PROBE_LAYOUT_LATLONG || (want == QTOOL_PROBE_LAYOUT_AUTO && (size_t)iw == 2 * (size_t)ih)) {
        u = QTOOL_PROBE_LAYOUT_LATLONG, lw = iw, lh = ih, ll = px; /* as it is: no copy of the input */
    } else {
        if (qtool_probe_layout_rgbe_to_latlong(want, iw, ih, px, &u, &lw, &lh, &ll, err, sizeof err) != 0) {
            free(px);
            return fprintf(stderr, "qibl: %s: %s\n", path, err), 1;
        }
        free(px);
    }
    if (note && notelen) {
        int k = snprintf(note, notelen, "%s: layout %s (%s, %s)", path, qtool_probe_layout_name(u),
                         qtool_probe_layout_describe(u), want == QTOOL_PROBE_LAYOUT_AUTO ? "detected" : "from --layout");
        size_t at = k < 0 ? 0 : (size_t)k < notelen ? (size_t)k : notelen - 1;
        if (u != QTOOL_PROBE_LAYOUT_LATLONG)
            k = snprintf(note + at, notelen - at, ", %d x %d resampled to a %d x %d lat-long\n", iw, ih, lw, lh);
        else if ((size_t)iw != 2 * (size_t)ih)
            k = snprintf(note + at, notelen - at, ", %d x %d is not 2:1: read as lat-long as asked\n", iw, ih);
        else
            k = snprintf(note + at, notelen - at, "\n");
        size_t len = strlen(note);
        if (len && note[len - 1] != '\n') /* a path too long for the buffer: the line still ends */
            note[len - 1] = '\n';
        (void)k;
    }
    *w = lw, *h = lh, *rgbe = ll;
    if (used)
        *used = u;
    return 0;
}

int qcli_probe_load(const char *path, qtool_probe_layout_t want, FILE *note, int *w, int *h, uint8_t **rgbe,
                    qtool_probe_layout_t *used)
{
    char buf[4200 + 256]; /* a path of PATH_MAX and the rest of the line */
    if (qcli_probe_load_note(path, want, buf, sizeof buf, w, h, rgbe, used) != 0)
        return 1;
    if (note)
        fputs(buf, note);
    return 0;
}

/* solid angle of a region of a w x h lat-long: (u1 - u0) 2 pi / w times the sum of pi / h sin theta_v */
static double region_sr(const qibl_lightprobe_light_t *l, uint32_t w, uint32_t h)
{
    double s = 0;
    for (uint32_t v = l->v0; v < l->v1 && v < h; ++v)
        s += sin((v + 0.5) * RL_PI / h);
    return (double)(l->u1 - l->u0) * (2.0 * RL_PI / w) * (RL_PI / h) * s;
}

static double region_density(const qibl_lightprobe_light_t *l, uint32_t w, uint32_t h)
{
    double sr = region_sr(l, w, h);
    return sr > 0 ? (0.2126 * l->rgb[0] + 0.7152 * l->rgb[1] + 0.0722 * l->rgb[2]) / sr : 0;
}

uint32_t qcli_probe_suns(const qibl_lightprobe_light_t *l, uint32_t count, uint32_t w, uint32_t h, uint32_t *idx)
{
    /* the regions cover every lit pixel, so their sum over 4 pi is the probe's mean radiance */
    double total = 0;
    for (uint32_t i = 0; i < count; ++i)
        total += 0.2126 * l[i].rgb[0] + 0.7152 * l[i].rgb[1] + 0.0722 * l[i].rgb[2];
    double floor_d = QCLI_SUN_CONTRAST * total / (4 * RL_PI), last = INFINITY;
    uint32_t n = 0;
    while (n < QCLI_SUN_MAX) { /* densest first: repeated selection (count is small) */
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

static const char *mode_name(qcli_probe_mode m)
{
    return m == QCLI_PROBE_SH ? "SH" : m == QCLI_PROBE_LIGHTS ? "median-cut lights" : "sun plus sky";
}

/* the probe's part of the light, rotated; 0 or 1 after a message */
static int probe_part(const qcli_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *p)
{
    int w, h;
    uint8_t *px;
    if (!note)
        note = stderr;
    if (qcli_probe_load(ll->probe, ll->layout, note, &w, &h, &px, NULL) != 0)
        return 1;
    int bands = 1;
    while ((uint32_t)(bands * bands) < k)
        ++bands;
    qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
    qibl_probe_sh_opts_t opts = {0, QIBL_PROBE_WINDOW_NONE, 0}; /* radiance: the maps hold the cosine */
    qibl_lightprobe_light_t *L = NULL;
    void *ws = NULL, *lws = NULL;
    int rc = 1;
    qibl_status_t st = qibl_shlight_init(p, k);
    size_t wsn = qibl_probe_sh_workspace_size(img.width, img.height);
    long n = ll->n ? ll->n : QCLI_PROBE_DEFAULT_N;
    if (!wsn) {
        fprintf(stderr, "qibl: %s: %d x %d is beyond the probe limits\n", ll->probe, w, h);
        goto out;
    }
    if (ll->mode == QCLI_PROBE_SH) {
        ws = malloc(wsn);
        if (!ws)
            goto oom;
        st = qibl_shlight_add_probe(p, &img, &opts, ws, wsn);
    } else {
        size_t lwn = qibl_lightprobe_workspace_size(img.width, img.height, QIBL_LIGHTPROBE_MEDIANCUT);
        lws = lwn ? malloc(lwn) : NULL;
        L = malloc(sizeof *L * (size_t)n);
        if (!lws || !L)
            goto oom;
        qibl_lightprobe_t lp;
        qibl_lightprobe_result_t res;
        st = qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, lws, lwn);
        if (st == QIBL_OK)
            st = qibl_lightprobe_lights(&lp, NULL, L, (uint32_t)n, &res);
        if (st == QIBL_E_PROBE_BLACK) {
            fprintf(note, "%s: an all-black probe: no light from it\n", ll->probe);
            st = QIBL_OK, res.count = 0;
        } else if (st == QIBL_OK && ll->mode == QCLI_PROBE_LIGHTS) {
            st = qibl_shlight_add_lights(p, L, res.count, res.rgb_exp, 0);
            fprintf(note, "%s: %u median-cut lights\n", ll->probe, res.count);
        } else if (st == QIBL_OK) {
            uint32_t idx[QCLI_SUN_MAX];
            qibl_lightprobe_light_t suns[QCLI_SUN_MAX];
            uint32_t ns = qcli_probe_suns(L, res.count, img.width, img.height, idx);
            for (uint32_t i = 0; i < ns; ++i)
                suns[i] = L[idx[i]];
            ws = malloc(wsn);
            if (!ws)
                goto oom;
            st = qibl_shlight_add_sun_sky(p, &img, &opts, suns, ns, res.rgb_exp, ws, wsn);
            fprintf(note, "%s: sun = %u of %u median-cut regions (those at least %g times the probe's mean "
                    "radiance), sky = SH of the rest\n", ll->probe, ns, res.count, QCLI_SUN_CONTRAST);
        }
    }
    if (st == QIBL_OK && ll->rotate) {
        qibl_q30_t r[3][3];
        qibl_sh_rotation_t rot;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                r[i][j] = (qibl_q30_t)lrint(ll->r[i][j] * 1073741824.0);
        st = qibl_sh_rotation_init(&rot, r, bands);
        if (st == QIBL_OK)
            st = qibl_shlight_rotate(p, &rot);
    }
    if (st == QIBL_E_PROBE_SATURATED) {
        fprintf(stderr, "qibl: %s: the probe's SH is beyond the Q16.16 light (too bright for the core's "
                        "lights)\n", ll->probe);
        goto out;
    }
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: %s\n", ll->probe, qibl_status_str(st));
        goto out;
    }
    if (note && ll->rotate)
        fprintf(note, "%s: %s, rotated once in SH (%s)\n", ll->probe, mode_name(ll->mode),
                ll->rotate == 1 ? "--yaw" : "--rotate");
    {
        /* a probe with light whose SH rounds to nothing in Q16.16 relights to exact zero: say so
         * (no exposure brings such a frame back) */
        int lit = 0, any = 0;
        for (size_t i = 0; i < (size_t)w * (size_t)h && !lit; ++i)
            lit = px[4 * i + 3] != 0 && (px[4 * i] | px[4 * i + 1] | px[4 * i + 2]) != 0;
        for (int c = 0; c < 3; ++c)
            for (uint32_t i = 0; i < p->k; ++i)
                any |= p->c[c][i] != 0;
        if (lit && !any)
            fprintf(stderr, "qibl: note: %s: its light is below the resolution of the core's SH light (2^-16 in "
                            "Q16.16): it relights to exact zero; scale the probe up\n", ll->probe);
    }
    rc = 0;
    goto out;
oom:
    fprintf(stderr, "qibl: relight: out of memory for %s\n", ll->probe);
out:
    free(ws), free(lws), free(L), free(px);
    return rc;
}

int qcli_light_list_sh(const qcli_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out)
{
    qibl_shlight_t tot, part;
    qibl_status_t st = qibl_shlight_init(&tot, k);
    if (st != QIBL_OK)
        return fprintf(stderr, "qibl: relight: %s\n", qibl_status_str(st)), 1;
    for (uint32_t i = 0; i < ll->count; ++i) {
        const qcli_relight_source *s = &ll->src[i];
        if (s->point)
            continue;
        st = qibl_shlight_init(&part, k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_dir(&part, s->v, s->rgb);
        if (st != QIBL_OK)
            return fprintf(stderr, "qibl: relight: --sun %g %g %g: %s\n", s->v[0] / 65536.0, s->v[1] / 65536.0,
                           s->v[2] / 65536.0, qibl_status_str(st)), 1;
        if (shlight_sum(&tot, &part) != 0)
            return fprintf(stderr, "qibl: relight: the suns add up beyond the Q16.16 light\n"), 1;
    }
    if (ll->csv) {
        qibl_lightprobe_light_t *L;
        uint32_t n;
        int32_t e;
        char err[600];
        if (qtool_lightcsv_read(ll->csv, &L, &n, &e, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: %s\n", err), 1;
        st = qibl_shlight_init(&part, k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_lights(&part, L, n, e, 0);
        free(L);
        if (st != QIBL_OK)
            return fprintf(stderr, "qibl: %s: %s\n", ll->csv, qibl_status_str(st)), 1;
        if (shlight_sum(&tot, &part) != 0)
            return fprintf(stderr, "qibl: %s: the lights add up beyond the Q16.16 light\n", ll->csv), 1;
    }
    if (ll->probe) {
        if (probe_part(ll, k, note, &part) != 0)
            return 1;
        if (shlight_sum(&tot, &part) != 0)
            return fprintf(stderr, "qibl: %s: the probe and the other lights add up beyond the Q16.16 light\n",
                           ll->probe), 1;
    }
    *out = tot;
    return 0;
}

/* ---- the frame ------------------------------------------------------------------------------------ */

int qcli_relight_frame(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
                       const qibl_pmap_t *pm, const qibl_ylut_t *lut, const qibl_lampocc_t *occ,
                       const qibl_pointlight_t *points, uint32_t npoints, uint32_t exposure, int srgb, uint8_t *rgb8,
                       float *lin, double *ms, qibl_status_t *status)
{
    return qcli_relight_frame_gonio(m, sh, mp, pm, lut, occ, points, NULL, npoints, exposure, srgb, rgb8, lin, ms,
                                    status);
}

int qcli_relight_frame_gonio(const qibl_shmaps_t *m, const qibl_shlight_t *sh, const qibl_shmaps_t *mp,
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
        st = QIBL_E_NULL_POINTER;
        goto out;
    }
    qibl_fb_desc_t fb = {0};
    fb.pixels = pix, fb.width = w, fb.height = h, fb.format = QIBL_FB_RGBA8888;
    fb.srgb = srgb ? 1 : 0, fb.exposure = exposure;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
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
            st = qibl_fb_write_row(&fb, 0, y, w, row);
        if (st == QIBL_OK && lin) {
            float *o = lin + (size_t)y * w * 3;
            for (size_t i = 0; i < (size_t)w * 3; ++i)
                o[i] = row[i] > 0 ? (float)(row[i] / 65536.0) : 0.0f;
        }
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (ms)
        *ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    for (size_t i = 0; st == QIBL_OK && i < (size_t)w * h; ++i)
        memcpy(rgb8 + 3 * i, pix + 4 * i, 3);
out:
    free(pix), free(row), free(acc), free(pt), free(ws);
    if (status)
        *status = st;
    return st == QIBL_OK ? 0 : -1;
}
