/*
 * cmd_relight.c - `qibl relight` (asset + light -> PNG through the core kernels and the software
 * framebuffer): the options parsed, tools/relight called, its results written and printed.
 * `qibl gen` lives in cmd_gen.c.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "io/exr.h"
#include "io/hdr_write.h"
#include "io/ies.h"
#include "io/pfm.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "cli/cli.h"
#include "cli/relight_light.h"
#include "qibl/gonio.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"
#include "relight/gles.h"
#include "relight/relight.h"

/* ---- qibl relight ------------------------------------------------------------------------------ */

#define RELIGHT_USAGE                                                                                       \
    "usage: qibl relight FILE [--sun X Y Z [--rgb R G B]]... [--point X Y Z [--rgb R G B]]... [--lights FILE.csv] \
[--probe PROBE.hdr [--layout L] [--probe-mode sh|lights|sunsky] [-n N] [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]] \
[--lut poly|nearest|bilinear|off] [--falloff 1|2] [--exposure E] [--linear] [--gles] \
[--ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]] (--png OUT | --hdr OUT.hdr | --pfm OUT.pfm | --exr OUT.exr)..."

#define PATH_USAGE                                                                                            \
    "usage: qibl relight FILE --path N|sun|lamp --t T [--rgb R G B] [--soft R] [--sky R G B] " \
    "[--ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]] (--png OUT | --pfm OUT.pfm | --exr OUT.exr)..."

/* What `qibl relight` was asked: the files, and the library's options (defaults in relight/relight.h). */
typedef struct relight_cli {
    const char *in, *png, *hdr, *pfm, *exr;
    int have_frame; /* --aim or --up given */
    qtool_relight_opts r;
} relight_cli;

/* What `qibl relight --path` was asked besides (relight/relight.h: qtool_relight_path). */
typedef struct path_cli {
    const char *spec;
    double t, rgb[3], sky[3], soft;
    int have_sky;
} path_cli;

void qcli_warn_dark(const char *path, const uint8_t *rgb, size_t np)
{
    double mean = qtool_relight_mean8(rgb, np);
    if (mean < QTOOL_CLI_DARK_MEAN)
        fprintf(stderr, "qibl: note: %s is almost black (mean %.1f of 255): try a larger --rgb or --exposure\n", path,
                mean);
}

/* --ies, --ies-size, --aim X Y Z, --up X Y Z (relight and relight --path): 1, 0 (none of them) or 2 */
static int ies_opt(int argc, char **argv, int *i, qtool_relight_opts *o, int *have_frame)
{
    const char *a = argv[*i];
    if (strcmp(a, "--ies") == 0 && *i + 1 < argc) {
        o->ies = argv[++*i];
    } else if (strcmp(a, "--ies-size") == 0 && *i + 1 < argc) {
        if (qcli_parse_int(argv[++*i], QIBL_GONIO_MIN_N, QIBL_GONIO_MAX_N, &o->ies_n) != 0)
            return qcli_usage_error("--ies-size is a table size in %u..%u", QIBL_GONIO_MIN_N, QIBL_GONIO_MAX_N);
    } else if ((strcmp(a, "--aim") == 0 || strcmp(a, "--up") == 0) && *i + 3 < argc) {
        int32_t *v = a[2] == 'a' ? o->aim : o->up;
        for (int k = 0; k < 3; ++k)
            if (qcli_parse_q16(argv[*i + 1 + k], &v[k]) != 0)
                return qcli_usage_error("%s: '%s' is not a number in the Q16.16 range", a, argv[*i + 1 + k]);
        if (v[0] == 0 && v[1] == 0 && v[2] == 0)
            return qcli_usage_error("%s: the zero vector has no direction", a);
        *have_frame = 1, *i += 3;
    } else {
        return 0;
    }
    return 1;
}

/* --png, --pfm, --exr and (hdr != 0) --hdr: 1 or 0 (none of them) */
static int out_opt(int argc, char **argv, int *i, relight_cli *c, int hdr)
{
    const char *a = argv[*i], **to = NULL;
    if (*i + 1 >= argc)
        return 0;
    if (strcmp(a, "--png") == 0)
        to = &c->png;
    else if (strcmp(a, "--hdr") == 0 && hdr)
        to = &c->hdr;
    else if (strcmp(a, "--pfm") == 0)
        to = &c->pfm;
    else if (strcmp(a, "--exr") == 0)
        to = &c->exr;
    if (to)
        *to = argv[++*i];
    return to != NULL;
}

/* --lut MODE, and the deprecated spellings: 1, 0 (none of them) or 2 */
static int lut_opt(int argc, char **argv, int *i, const char *in, qtool_relight_opts *o)
{
    const char *a = argv[*i];
    if (strcmp(a, "--nearest") == 0) {
        o->point_mode = QTOOL_RELIGHT_POINT_NEAREST;
        fprintf(stderr, "qibl: note: --nearest is deprecated; say --lut nearest\n");
        return 1;
    }
    if (strcmp(a, "--lut") != 0)
        return 0;
    /* --lut MODE; a bare --lut (the old on/off switch) is bilinear: the next word is then an option or
     * the asset, never a mode name, so the two spellings cannot be confused */
    const char *m = *i + 1 < argc ? argv[*i + 1] : "";
    if (strcmp(m, "nearest") == 0 || strcmp(m, "bilinear") == 0 || strcmp(m, "off") == 0 || strcmp(m, "poly") == 0) {
        o->point_mode = m[0] == 'n'   ? QTOOL_RELIGHT_POINT_NEAREST
                        : m[0] == 'b' ? QTOOL_RELIGHT_POINT_BILINEAR
                        : m[0] == 'p' ? QTOOL_RELIGHT_POINT_POLY
                                      : QTOOL_RELIGHT_POINT_DIRECT;
        ++*i;
    } else if (m[0] != '-' && m[0] != '\0' && in) {
        return qcli_usage_error("--lut: '%s' is not a mode (poly, nearest, bilinear or off)", m);
    } else {
        o->point_mode = QTOOL_RELIGHT_POINT_BILINEAR;
        fprintf(stderr, "qibl: note: a bare --lut is deprecated; say --lut bilinear\n");
    }
    return 1;
}

/* relight's own options after the light's: 1, 0 (none of them) or 2 */
static int relight_opt(int argc, char **argv, int *i, relight_cli *c)
{
    const char *a = argv[*i];
    qtool_relight_opts *o = &c->r;
    int r;
    if ((r = lut_opt(argc, argv, i, c->in, o)) != 0 || (r = ies_opt(argc, argv, i, o, &c->have_frame)) != 0)
        return r;
    if (out_opt(argc, argv, i, c, 1))
        return 1;
    if (strcmp(a, "--exposure") == 0 && *i + 1 < argc) {
        double e;
        if (qcli_parse_num(a, argv[++*i], 1.0 / 65536, QTOOL_CLI_Q16_MAX, "a positive Q16.16 factor", &e) != 0)
            return 2;
        o->exposure = (qibl_q16_t)nearbyint(e * 65536.0);
    } else if (strcmp(a, "--falloff") == 0 && *i + 1 < argc) {
        if (qcli_parse_int(argv[++*i], 1, 2, &o->falloff) != 0)
            return qcli_usage_error("--falloff is 1 (C0/|L|) or 2 (C0/|L|^2)");
    } else if (strcmp(a, "--linear") == 0) {
        o->linear = 1;
    } else if (strcmp(a, "--gles") == 0) {
        o->gles = 1;
    } else {
        return 0;
    }
    return 1;
}

/* the options together, after parsing: 0, or 2 after a message */
static int relight_check(const relight_cli *c)
{
    const qtool_relight_opts *o = &c->r;
    const qtool_relight_light_list *ll = &o->lights;
    if (!c->in || (!c->png && !c->hdr && !c->pfm && !c->exr))
        return qcli_usage_error("relight needs FILE, a light (--sun, --point, --lights or --probe), and --png, --hdr, "
                                "--pfm or --exr OUT");
    if (ll->count == 0 && !ll->csv && !ll->probe)
        return qcli_usage_error("relight needs a light: --sun, --point, --lights FILE.csv or --probe PROBE.hdr");
    if (qcli_light_list_check(ll) != 0)
        return 2;
    if (o->gles && (ll->count != 1 || ll->csv || ll->probe))
        return qcli_usage_error("--gles takes exactly one --sun or --point (no --lights or --probe)");
    if (c->have_frame && !o->ies)
        return qcli_usage_error("--aim and --up orient an --ies lamp: give --ies FILE.ies");
    if (o->ies && ll->points == 0)
        return qcli_usage_error("--ies shapes the --point lamps: give at least one --point X Y Z");
    if (o->ies && o->gles)
        return qcli_usage_error("--ies: goniometric lamps are relit on the soft framebuffer only (not --gles)");
    return 0;
}

/* "1 sun, 2 points, lights.csv, probe.hdr (SH)" for the messages */
static void describe(const qtool_relight_opts *o, char *buf, size_t n)
{
    const qtool_relight_light_list *ll = &o->lights;
    static const char *const how[] = {"point/poly", "point/direct", "point/LUT nearest", "point/LUT bilinear"};
    size_t at = 0;
    buf[0] = '\0';
    if (ll->suns)
        at += (size_t)snprintf(buf + at, n - at, "%u sun%s", ll->suns, ll->suns == 1 ? "" : "s");
    if (ll->points && at < n)
        at += (size_t)snprintf(buf + at, n - at, "%s%u point%s (%s)", at ? ", " : "", ll->points,
                               ll->points == 1 ? "" : "s", how[o->point_mode]);
    if (ll->csv && at < n)
        at += (size_t)snprintf(buf + at, n - at, "%s%s", at ? ", " : "", ll->csv);
    if (ll->probe && at < n)
        snprintf(buf + at, n - at, "%sprobe %s (%s)", at ? ", " : "", ll->probe,
                 ll->mode == QTOOL_RELIGHT_PROBE_SH       ? "SH"
                 : ll->mode == QTOOL_RELIGHT_PROBE_LIGHTS ? "lights"
                                                          : "sun plus sky");
}

/* the linear frame (the core's Q16.16 output before exposure and the transfer curve) to each file
 * asked for, each with its line ending in tail; 0, or 1 after a message */
static int write_linear(const relight_cli *c, uint32_t w, uint32_t h, const float *lin, const char *tail)
{
    char err[1200];
    if (c->hdr && qtool_hdr_write(c->hdr, (int)w, (int)h, lin, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (c->hdr)
        printf("wrote %s (%ux%u Radiance RGBE, linear, %s)\n", c->hdr, w, h, tail);
    if (c->pfm && qtool_pfm_write(c->pfm, (int)w, (int)h, 3, lin, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (c->pfm)
        printf("wrote %s (%ux%u PFM, linear, %s)\n", c->pfm, w, h, tail);
    if (c->exr && qtool_exr_write(c->exr, (int)w, (int)h, lin, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    if (c->exr)
        printf("wrote %s (%ux%u OpenEXR FLOAT ZIP, linear, %s)\n", c->exr, w, h, tail);
    return 0;
}

/* the 8-bit frame as c->png (0 when not asked), or 1 after a message */
static int write_png(const relight_cli *c, uint32_t w, uint32_t h, const uint8_t *pix)
{
    char err[1200];
    if (c->png && qtool_png_write_rgb8(c->png, (int)w, (int)h, pix, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    return 0;
}

/* the IES profile of o, its note on stderr (note != 0); 0, or 1 after a message */
static int load_ies(const qtool_relight_opts *o, qtool_relight_ies *ies, int note)
{
    char err[1200];
    int r = qtool_relight_ies_load(o->ies, (uint32_t)o->ies_n, o->aim, o->up, ies, err, sizeof err);
    if (r == -2 && note)
        fprintf(stderr, "qibl: relight: --aim/--up: %s\n", qibl_status_str(ies->status));
    else if (r == -2)
        fprintf(stderr, "qibl: relight: %s: %s\n", o->ies, qibl_status_str(ies->status));
    else if (r != 0)
        fprintf(stderr, "qibl: %s\n", err);
    else if (note)
        fprintf(stderr, "qibl: note: %s: type %c, %s, peak %.6g cd, %.2f lm; each --point lamp scaled by "
                        "I / I_peak (%ldx%ld table)\n", o->ies, ies->type, qtool_ies_sym_name(ies->sym), ies->peak,
                ies->lumens, o->ies_n, o->ies_n);
    return r != 0;
}

/* the light's SH part and lamps, their notes printed; 0, or 1 after a message */
static int relight_lights(relight_cli *c, const qtool_relight_asset *s, qibl_shlight_t *sl, qibl_pointlight_t *pts,
                          uint32_t *npts)
{
    qtool_relight_opts *o = &c->r;
    qtool_relight_point_note notes[QTOOL_RELIGHT_MAX_SOURCES];
    char err[600];
    /* the directional part as one SH light (suns, --lights, --probe); notes on stdout */
    if (qtool_relight_light_list_directional(&o->lights) && qcli_light_list_sh(&o->lights, s->m.k, stdout, sl) != 0)
        return 1;
    memset(notes, 0, sizeof notes);
    int r = qtool_relight_points(o, s, pts, npts, notes, err, sizeof err);
    for (uint32_t j = 0; j < o->lights.count; ++j)
        if (notes[j].set)
            fprintf(stderr, "qibl: note: --point without --rgb: C0 = %.4g (%.2g x d%s, d = %.3g the median distance "
                    "from the lamp to the scene); give --rgb R G B to choose\n", notes[j].c0, QTOOL_RELIGHT_POINT_GREY,
                    o->falloff == 2 ? "^2" : "", notes[j].d);
    if (r != 0)
        fprintf(stderr, "qibl: %s\n", err);
    return r != 0;
}

/* the GPU path: same asset, same core weights, platform/gles2 (one light) */
static int relight_gles(const relight_cli *c, const qtool_relight_asset *s, uint8_t *pix)
{
    const qtool_relight_opts *o = &c->r;
    const qtool_relight_source *l = &o->lights.src[0];
    const int point = o->lights.points > 0;
    qtool_gles_relight_req req = {&s->m, point ? &s->pm : NULL,
                                  point && qtool_relight_uses_lut(o->point_mode) ? &s->lut : NULL,
                                  {l->point ? 0 : l->v[0], l->point ? 0 : l->v[1], l->point ? 0 : l->v[2]},
                                  {l->point ? l->v[0] : 0, l->point ? l->v[1] : 0, l->point ? l->v[2] : 0},
                                  {l->rgb[0], l->rgb[1], l->rgb[2]}, (int)o->falloff,
                                  o->point_mode == QTOOL_RELIGHT_POINT_NEAREST, o->linear, (qibl_uq16_t)o->exposure};
    uint32_t passes = 0;
    char renderer[64] = "", err[1200];
    if (qtool_gles_relight(&req, pix, &passes, renderer) != 0)
        return 1;
    if (qtool_png_write_rgb8(c->png, (int)s->m.width, (int)s->m.height, pix, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    printf("wrote %s (%ux%u, k = %u, GLES2 on %s, %u pass%s)\n", c->png, s->m.width, s->m.height, s->m.k, renderer,
           passes, passes == 1 ? "" : "es");
    return 0;
}

/* the soft path: the frame, then its files and lines */
static int relight_soft(const relight_cli *c, const qtool_relight_asset *s, const qibl_shlight_t *sl,
                        const qibl_pointlight_t *pts, uint32_t npts, const qtool_relight_ies *ies, uint8_t *pix,
                        float *lin)
{
    const qtool_relight_opts *o = &c->r;
    const uint32_t w = s->m.width, h = s->m.height;
    double ms = 0;
    qibl_status_t st;
    if (qtool_relight_render(o, s, qtool_relight_light_list_directional(&o->lights) ? sl : NULL, pts, npts, ies, pix,
                             lin, &ms, &st) != 0) {
        fprintf(stderr, "qibl: relight: %s\n", st == QIBL_E_NULL_POINTER ? "out of memory" : qibl_soft_status_str(st));
        return 1;
    }
    char how[600], tail[640];
    describe(o, how, sizeof how);
    if (write_png(c, w, h, pix) != 0)
        return 1;
    if (c->png) {
        printf("wrote %s (%ux%u, k = %u, %s, %.1f ms incl. framebuffer conversion)\n", c->png, w, h, s->m.k, how, ms);
        qcli_warn_dark(c->png, pix, (size_t)w * h);
    }
    snprintf(tail, sizeof tail, "before exposure, %s", how);
    return write_linear(c, w, h, lin, tail);
}

static int relight_run(relight_cli *c)
{
    qtool_relight_opts *o = &c->r;
    qtool_relight_ies ies;
    qtool_relight_asset s;
    char err[1200];
    if (o->ies && load_ies(o, &ies, 1) != 0) /* the profile first: a bad file costs no asset read */
        return 1;
    if (qtool_relight_asset_open(&s, c->in, o->lights.points > 0, qtool_relight_uses_lut(o->point_mode), err,
                                 sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        if (o->ies)
            qtool_relight_ies_free(&ies);
        return 1;
    }
    if (s.occ_unusable) /* never dropped without a word */
        fprintf(stderr, "qibl: note: %s: its LOCC chunk is not usable (%s): the lamps are drawn without lamp "
                        "occlusion\n", c->in, qibl_soft_status_str(s.occ_status));
    qibl_shlight_t sl;
    qibl_pointlight_t pts[QTOOL_RELIGHT_MAX_SOURCES];
    uint32_t npts = 0;
    size_t np = (size_t)s.m.width * s.m.height;
    uint8_t *pix = NULL;
    float *lin = NULL;
    int rc = 1;
    if (relight_lights(c, &s, &sl, pts, &npts) != 0)
        goto out;
    pix = malloc(np * 3);
    lin = c->hdr || c->pfm || c->exr ? malloc(np * 3 * sizeof(float)) : NULL;
    if (!pix || ((c->hdr || c->pfm || c->exr) && !lin))
        fprintf(stderr, "qibl: relight: out of memory\n");
    else if (o->gles)
        rc = relight_gles(c, &s, pix);
    else
        rc = relight_soft(c, &s, &sl, pts, npts, o->ies ? &ies : NULL, pix, lin);
out:
    if (o->ies)
        qtool_relight_ies_free(&ies);
    qtool_relight_asset_free(&s);
    free(pix), free(lin);
    return rc;
}

/* ---- qibl relight --path: a light on one of the asset's baked paths (LPTH) ------------------------- */

static int path_opt(int argc, char **argv, int *i, path_cli *p)
{
    const char *a = argv[*i];
    if (strcmp(a, "--path") == 0 && *i + 1 < argc) {
        p->spec = argv[++*i];
    } else if (strcmp(a, "--t") == 0 && *i + 1 < argc) {
        if (qcli_parse_num(a, argv[++*i], 0, 1, "a path parameter in 0..1", &p->t) != 0)
            return 2;
    } else if (strcmp(a, "--soft") == 0 && *i + 1 < argc) {
        if (qcli_parse_num(a, argv[++*i], 0, 0.5, "a half-width in path units, 0..0.5", &p->soft) != 0)
            return 2;
    } else if ((strcmp(a, "--rgb") == 0 || strcmp(a, "--sky") == 0) && *i + 3 < argc) {
        double *d = a[2] == 'r' ? p->rgb : p->sky;
        for (int k = 0; k < 3; ++k)
            if (qcli_parse_num(a, argv[*i + 1 + k], 0, 32767, "a colour component in 0..32767", &d[k]) != 0)
                return 2;
        p->have_sky |= a[2] == 's';
        *i += 3;
    } else {
        return 0;
    }
    return 1;
}

/* the frame's files and lines */
static int path_write(const relight_cli *c, const path_cli *p, const qibl_shmaps_t *m, const qtool_relight_path_req *q,
                      int point, const uint8_t *pix, const float *lin, double ms)
{
    const char *what = point ? "lamp" : "sun";
    char tail[64];
    if (write_png(c, m->width, m->height, pix) != 0)
        return 1;
    if (c->png) {
        printf("wrote %s (%ux%u, %s on path %u at t = %.4f (%u/65535)%s%s, %.1f ms)\n", c->png, m->width, m->height,
               what, q->index, p->t, q->tq, q->radius ? ", soft" : "", p->have_sky ? ", over the sky" : "", ms);
        qcli_warn_dark(c->png, pix, (size_t)m->width * m->height); /* as every other relight does */
    }
    snprintf(tail, sizeof tail, "%s on path %u", what, q->index);
    return write_linear(c, m->width, m->height, lin, tail);
}

static int path_run(const relight_cli *c, const path_cli *p)
{
    const qtool_relight_opts *o = &c->r;
    qtool_relight_ies ies;
    uint8_t *bytes;
    size_t n;
    qibl_asset_t a;
    qibl_shmaps_t m;
    char err[1200];
    if (o->ies && load_ies(o, &ies, 0) != 0)
        return 1;
    qtool_relight_path_req q = {.tq = (uint32_t)lrint(p->t * QIBL_LIGHTPATH_T_MAX),
                                .radius = (uint32_t)lrint(p->soft * QIBL_LIGHTPATH_T_MAX),
                                .rgb = {p->rgb[0], p->rgb[1], p->rgb[2]}, .sky = p->have_sky ? p->sky : NULL,
                                .gonio = o->ies ? &ies.gonio : NULL, .lin = c->pfm || c->exr};
    int rc = qtool_relight_asset_read(c->in, &bytes, &n, &a, &m, err, sizeof err) != 0 ? 1
             : qtool_relight_pick_path(&a, c->in, p->spec, &q.index, err, sizeof err);
    if (rc != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        rc = rc == -2 ? 2 : 1;
    } else {
        size_t np = (size_t)m.width * m.height;
        uint8_t *pix = malloc(np * 3);
        float *lin = q.lin ? malloc(np * 3 * sizeof(float)) : NULL;
        double ms = 0;
        int point = 0;
        if (qtool_relight_path(bytes, n, &a, c->in, &q, pix, lin, &ms, &point, err, sizeof err) != 0)
            rc = 1, fprintf(stderr, "qibl: %s\n", err);
        else
            rc = path_write(c, p, &m, &q, point, pix, lin, ms);
        free(pix), free(lin);
    }
    free(bytes);
    if (o->ies)
        qtool_relight_ies_free(&ies);
    return rc;
}

static int relight_path_cmd(int argc, char **argv)
{
    relight_cli c = {.r = QTOOL_RELIGHT_OPTS_DEFAULT};
    path_cli p = {.t = -1, .rgb = {1, 1, 1}};
    for (int i = 1; i < argc; ++i) {
        int r;
        if ((r = path_opt(argc, argv, &i, &p)) != 0 || (r = ies_opt(argc, argv, &i, &c.r, &c.have_frame)) != 0) {
            if (r != 1)
                return 2;
        } else if (out_opt(argc, argv, &i, &c, 0)) {
            continue;
        } else if (argv[i][0] != '-' && !c.in) {
            c.in = argv[i];
        } else {
            return qcli_usage_error(PATH_USAGE);
        }
    }
    if (!c.in || !p.spec || p.t < 0 || (!c.png && !c.pfm && !c.exr))
        return qcli_usage_error("relight --path needs FILE, --path N|sun|lamp, --t T and --png, --pfm or --exr OUT");
    if (c.have_frame && !c.r.ies)
        return qcli_usage_error("--aim and --up orient an --ies lamp: give --ies FILE.ies");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    return path_run(&c, &p);
}

int qcli_cmd_relight(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i)
        if (strcmp(argv[i], "--path") == 0) /* a light on a baked path */
            return relight_path_cmd(argc, argv);
    relight_cli c = {.r = QTOOL_RELIGHT_OPTS_DEFAULT};
    for (int i = 1; i < argc; ++i) {
        int r;
        if ((r = qcli_light_list_opt(argc, argv, &i, &c.r.lights)) != 0 || (r = relight_opt(argc, argv, &i, &c)) != 0) {
            if (r != 1)
                return 2;
        } else if (argv[i][0] != '-' && !c.in) {
            c.in = argv[i];
        } else {
            return qcli_usage_error(RELIGHT_USAGE);
        }
    }
    if (relight_check(&c) != 0)
        return 2;
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    return relight_run(&c);
}
