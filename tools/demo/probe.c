/*
 * demo/probe.c - the "lit by a real probe" part of `qibl demo`: the scene under three whole probes
 * (soft, sunny, indoor), ray-traced with every direction shadowed (render/env.h) and relit by the
 * core three ways: the probe's SH through the shadowed maps, N median-cut lights (as SH) through
 * the same maps, and sun plus SH (the compact bright sources as directional lights through the
 * unshadowed maps x their baked visibility, a single-direction light path; the rest as SH).
 */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "bake/probesun.h"
#include "demo/demo.h"
#include "io/text.h"
#include "io/hdr.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/lightprobe.h"
#include "qibl/probe.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "ref/psnr.h"
#include "render/env.h"

#define PROBE_DIR "../shared/fixtures/probes"
/* every probe is scaled so that a surface facing up receives this irradiance (the demo's sun
 * delivers 2.6 / 2.4 / 2.1 at the zenith): the courtyard comes out mid-grey */
#define TARGET_E_UP QTOOL_PROBESUN_TARGET_E_UP
#define MAX_SUNS QTOOL_PROBESUN_MAX_SRC
/* bands of the unshadowed maps the sources are relit through */
#define SHMU_K QTOOL_PROBESUN_UNSHADOWED_K
/* an extended source (a softbox, a sun with its glow) is split into up to this many equal-energy
 * parts, each a direction with its own baked visibility: a penumbra of that many steps */
#define MAX_PARTS QTOOL_DEMO_MAX_PARTS
#define NLIGHTS 16

enum { NCLS = 4 };
enum { S_SH16, S_SH25, S_LIGHTS, S_SUN, NSCHEME };
static const char *scheme_key[NSCHEME] = {"sh16", "sh25", "lights", "sunsh"};

typedef struct {
    const char *role, *file, *what;
} probe_pick;

static const probe_pick demo_picks[3] = {
    {"soft", "potsdamer_platz_1k.hdr", "overcast city square, no sun"},
    {"sunny", "quarry_01_1k.hdr", "clear sky, small sun with 53 % of the energy"},
    {"indoor", "studio_small_03_1k.hdr", "photo studio, small bright softboxes"},
};

typedef struct {
    double psnr, bright, ms, bytes, psnr_cls[NCLS], share_cls[NCLS];
} row_t;


static void score(const uint8_t *relit, const uint8_t *truth, const uint8_t *cls, size_t np, row_t *r)
{
    double se[NCLS] = {0}, n[NCLS] = {0}, lr = 0, lt = 0, set = 0, nt = 0;
    for (size_t i = 0; i < np; ++i) {
        if (!cls[i])
            continue;
        for (int c = 0; c < 3; ++c) {
            double d = (double)relit[3 * i + (size_t)c] - truth[3 * i + (size_t)c];
            se[cls[i]] += d * d;
            lr += qtool_demo_lin8(relit[3 * i + (size_t)c]), lt += qtool_demo_lin8(truth[3 * i + (size_t)c]);
        }
        n[cls[i]] += 3;
    }
    for (int c = 1; c < NCLS; ++c)
        set += se[c], nt += n[c];
    r->psnr = qtool_ref_psnr8(nt > 0 ? set / nt : 0);
    for (int c = 1; c < NCLS; ++c) {
        r->psnr_cls[c] = n[c] > 0 ? qtool_ref_psnr8(se[c] / n[c]) : 0;
        r->share_cls[c] = set > 0 ? 100 * se[c] / set : 0;
    }
    r->bright = lt > 0 ? lr / lt : 0;
}


/* ---- probes ---------------------------------------------------------------------------------- */

/* Procedural stand-ins when ../shared is absent (1024 x 512 lat-long, row v at theta (v + 1/2) pi / H). */
static float *procedural(int role, int w, int h)
{
    float *p = malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
    if (!p)
        return NULL;
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            double th = (v + 0.5) * QTOOL_PI / h, ph = (u + 0.5) * 2 * QTOOL_PI / w, z = cos(th);
            double d[3] = {sin(th) * cos(ph), sin(th) * sin(ph), z}, c[3];
            if (role == 0) { /* overcast: brighter towards the zenith and to one side, grey ground */
                double k = z > 0 ? 0.6 + 0.6 * z + 0.3 * d[0] : 0.18;
                c[0] = k * 0.95, c[1] = k, c[2] = k * 1.08;
            } else if (role == 1) { /* clear sky, ground, a sun of 0.3 degrees at 35 degrees elevation */
                double sd[3] = {cos(0.61) * cos(1.0), cos(0.61) * sin(1.0), sin(0.61)};
                double cs = d[0] * sd[0] + d[1] * sd[1] + d[2] * sd[2];
                double k = z > 0 ? 0.25 + 0.25 * (1 - z) : 0.12;
                c[0] = k * 0.6, c[1] = k * 0.8, c[2] = k * 1.3;
                if (cs > cos(0.3 * QTOOL_PI / 180 * 4)) /* 4 x the real sun's radius: a few pixels */
                    c[0] = 9000, c[1] = 8400, c[2] = 7600;
            } else { /* a dim room, a window on one side, a small ceiling lamp */
                double k = 0.05;
                c[0] = c[1] = c[2] = k;
                if (fabs(d[1]) < 0.35 && fabs(d[2] - 0.1) < 0.25 && d[0] > 0.8)
                    c[0] = 2.2, c[1] = 2.4, c[2] = 2.8;
                if (d[2] > 0.985)
                    c[0] = 300, c[1] = 260, c[2] = 200;
            }
            for (int q = 0; q < 3; ++q)
                p[3 * ((size_t)v * (size_t)w + (size_t)u) + (size_t)q] = (float)c[q];
        }
    return p;
}


static int probe_lights_sh(const float *p, uint32_t w, uint32_t h, uint32_t k, qibl_shlight_t *l, double *ms)
{
    uint32_t *bits = malloc(sizeof(float) * 3 * (size_t)w * h);
    size_t wsn = qibl_lightprobe_workspace_size(w, h, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = malloc(wsn);
    qibl_lightprobe_image_t img;
    qibl_lightprobe_t lp;
    qibl_lightprobe_light_t lights[NLIGHTS];
    qibl_lightprobe_result_t res;
    int rc = -1;
    if (bits && ws) {
        qtool_probesun_f32_image(p, w, h, bits, &img);
        double t0 = qtool_demo_now();
        if (qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws, wsn) == QIBL_OK &&
            qibl_lightprobe_lights(&lp, NULL, lights, NLIGHTS, &res) == QIBL_OK && qibl_shlight_init(l, k) == QIBL_OK &&
            qibl_shlight_add_lights(l, lights, res.count, res.rgb_exp, 0) == QIBL_OK)
            rc = 0;
        if (ms)
            *ms = (qtool_demo_now() - t0) * 1e3;
    }
    free(bits), free(ws);
    return rc;
}


/* ---- the demo part --------------------------------------------------------------------------- */

typedef struct {
    const qtool_demo_view *v;
    const uint8_t *a16, *a25;
    size_t n16, n25;
    const qtool_gen_maps *m25, *mu;
    uint32_t spp;
    int kparts;
    char *err;
    size_t errlen;
    double *lin, *ha, *hb;
    uint8_t *truth, *cls, *tmp, *heatb, *best;
    const probe_pick *picks; /* the probes: the three of picks, or the user's one */
    int npicks;
    const char *user;        /* the user's probe file (demo --probe), or NULL */
} ctx_t;

/* relights the environment five times (the minimum ms: the machine is shared) */
static int relight_env(const ctx_t *c, const uint8_t *as, size_t an, const qibl_shlight_t *l, uint8_t *out, double *ms)
{
    qibl_status_t st = QIBL_OK;
    *ms = 1e30;
    for (int r = 0; r < 5; ++r) {
        double t;
        if (qtool_bake_relight_env8(as, an, l, out, &t, &st) != 0)
            return qtool_errf(c->err, c->errlen, "demo: probe relight failed: %s", qibl_status_str(st));
        *ms = fmin(*ms, t);
    }
    return 0;
}

/* the truth: two renders with different seeds into ha and hb, their mean in lin; truth is ha's 8-bit
 * frame and tmp hb's (their difference states the noise) */
static int probe_truth(ctx_t *c, int role, const char *label, const qtool_env *env, double *truth_s)
{
    const qtool_demo_view *v = c->v;
    size_t np = (size_t)v->w * v->h;
    double t0 = qtool_demo_now();
    if (qtool_env_render(v->scene, v->w, v->h, v->kind, env, c->spp, 2 * (uint64_t)role + 1, 1, v->threads, c->ha) != 0 ||
        qtool_env_render(v->scene, v->w, v->h, v->kind, env, c->spp, 2 * (uint64_t)role + 2, 1, v->threads, c->hb) != 0)
        return qtool_errf(c->err, c->errlen, "demo: %s: the ground truth failed", label);
    *truth_s = qtool_demo_now() - t0;
    qtool_bake_lin_to8(c->ha, v->w, v->h, c->truth);
    qtool_bake_lin_to8(c->hb, v->w, v->h, c->tmp);
    for (size_t i = 0; i < np * 3; ++i)
        c->lin[i] = 0.5 * (c->ha[i] + c->hb[i]);
    return 0;
}

/* The four schemes under one probe (the truth in c->lin, the sky without its suns in sky), scored
 * into rows; c->tmp ends with the sun + SH frame when there are suns. 0 or -1 (c->err). */
static int score_schemes(ctx_t *c, const float *probe, const float *sky, uint32_t pw, uint32_t ph, row_t rows[NSCHEME],
                         const qtool_probesun_src *suns, int ns, const qtool_probesun_src *parts, const int *part_src, int nparts,
                         uint8_t *const *lp, const size_t *lpn, qibl_shlight_t ls[3])
{
    size_t np = (size_t)c->v->w * c->v->h;
    double shmp25 = qtool_demo_chunk_bytes(c->a25, c->n25, QIBL_CHUNK_SHMP, 0), prep;
    qibl_shlight_t lsky, *l16 = &ls[0], *l25 = &ls[1], *ll = &ls[2];
    /* (a) the probe's SH */
    if (qtool_probesun_sh(probe, pw, ph, 16, l16, &prep) != 0 || qtool_probesun_sh(probe, pw, ph, 25, l25, &prep) != 0)
        return qtool_errf(c->err, c->errlen, "demo: the probe's SH failed (out of memory)");
    if (relight_env(c, c->a16, c->n16, l16, c->tmp, &rows[S_SH16].ms) != 0)
        return -1;
    score(c->tmp, c->truth, c->cls, np, &rows[S_SH16]);
    rows[S_SH16].bytes = qtool_demo_chunk_bytes(c->a16, c->n16, QIBL_CHUNK_SHMP, 0);
    if (relight_env(c, c->a25, c->n25, l25, c->tmp, &rows[S_SH25].ms) != 0)
        return -1;
    score(c->tmp, c->truth, c->cls, np, &rows[S_SH25]);
    rows[S_SH25].bytes = shmp25;
    /* (b) N median-cut lights, projected to SH (what N directional lights through the maps add up to) */
    if (probe_lights_sh(probe, pw, ph, 25, ll, &prep) != 0)
        return qtool_errf(c->err, c->errlen, "demo: the probe's median-cut lights failed");
    if (relight_env(c, c->a25, c->n25, ll, c->tmp, &rows[S_LIGHTS].ms) != 0)
        return -1;
    score(c->tmp, c->truth, c->cls, np, &rows[S_LIGHTS]);
    rows[S_LIGHTS].bytes = shmp25;
    /* (c) sun + SH: the suns through SHMU x their single-direction paths, the rest as SH k = 25 */
    if (qtool_probesun_sh(sky, pw, ph, 25, &lsky, &prep) != 0)
        return qtool_errf(c->err, c->errlen, "demo: the sky's SH failed (out of memory)");
    if (ns == 0) {
        rows[S_SUN] = rows[S_SH25];
        return 0;
    }
    uint8_t *asset = NULL;
    size_t an = 0;
    int rc = qtool_bake_asset_ex(c->m25, c->mu, 32, lp, lpn, &asset, &an) != 0
                 ? qtool_errf(c->err, c->errlen, "demo: out of memory (probes)") : 0;
    rows[S_SUN].ms = 1e30;
    for (int r = 0; rc == 0 && r < 5; ++r) {
        double ms = 1e30;
        rc = qtool_probesun_relight(asset, an, &lsky, suns, ns, parts, part_src, nparts, c->tmp, &ms, c->err, c->errlen);
        if (rc == 0)
            rows[S_SUN].ms = fmin(rows[S_SUN].ms, ms);
    }
    if (rc == 0) {
        score(c->tmp, c->truth, c->cls, np, &rows[S_SUN]);
        rows[S_SUN].bytes = qtool_demo_chunk_bytes(asset, an, QIBL_CHUNK_SHMP, 0) +
                            qtool_demo_chunk_bytes(asset, an, QIBL_CHUNK_SHMU, 0);
        for (int k = 0; k < nparts; ++k)
            rows[S_SUN].bytes += (double)lpn[k];
    }
    free(asset);
    return rc;
}

/* the best scheme's frame into c->best (ties: the cheaper); its index, or -1 (c->err) */
static int keep_best(ctx_t *c, const row_t rows[NSCHEME], int ns, const qibl_shlight_t ls[3])
{
    size_t np = (size_t)c->v->w * c->v->h;
    double best_psnr = -1, prep;
    int best = 0, rc = 0;
    for (int q = 0; q < NSCHEME; ++q)
        if (rows[q].psnr > best_psnr + 0.05)
            best_psnr = rows[q].psnr, best = q;
    if (best == S_SUN && ns > 0) {
        /* c->tmp holds it */
    } else if (best == S_SH16) {
        rc = relight_env(c, c->a16, c->n16, &ls[0], c->tmp, &prep);
    } else {
        rc = relight_env(c, c->a25, c->n25, best == S_LIGHTS ? &ls[2] : &ls[1], c->tmp, &prep);
    }
    if (rc != 0)
        return -1;
    memcpy(c->best, c->tmp, np * 3);
    return best;
}

static int run_probe(ctx_t *c, int role, const char *label, float *probe, uint32_t pw, uint32_t ph, row_t rows[NSCHEME],
                     double *noise, int *nsuns, qtool_probesun_src *suns, int *nparts_out, double *scale_out, double *truth_s)
{
    const qtool_demo_view *v = c->v;
    size_t np = (size_t)v->w * v->h, npp = (size_t)pw * ph;
    char err[512];
    *scale_out = qtool_probesun_scale(probe, pw, ph);
    qtool_env env;
    if (qtool_env_build(&env, pw, ph, probe, err, sizeof err) != 0)
        return qtool_errf(c->err, c->errlen, "demo: %s: %s", label, err);
    if (probe_truth(c, role, label, &env, truth_s) != 0) {
        qtool_env_free(&env);
        return -1;
    }
    /* suns, and the classes of the brightest one's light for the error split */
    float *sky = malloc(sizeof(float) * 3 * npp);
    enum { LPMAX = MAX_SUNS * MAX_PARTS };
    uint8_t *lp[LPMAX + 1] = {NULL};
    size_t lpn[LPMAX + 1] = {0};
    qtool_probesun_src parts[LPMAX];
    int nparts = 0, part_src[LPMAX];
    int rc = -1, ns = 0;
    qibl_shlight_t ls[3];
    if (!sky) {
        qtool_errf(c->err, c->errlen, "demo: out of memory (probes)");
        goto done;
    }
    memcpy(sky, probe, sizeof(float) * 3 * npp);
    ns = qtool_probesun_find(&env, sky, suns, parts, part_src, &nparts, c->kparts);
    if (ns < 0) {
        ns = 0;
        qtool_errf(c->err, c->errlen, "demo: out of memory (probes)");
        goto done;
    }
    *nsuns = ns, *nparts_out = nparts;
    for (int i = 0; i < nparts; ++i)
        if (qtool_probesun_path(v->scene, v->w, v->h, v->kind, v->threads, &parts[i], c->cls, &lp[i], &lpn[i]) != 0) {
            qtool_errf(c->err, c->errlen, "demo: out of memory (probe light paths)");
            goto done;
        }
    { /* the error split follows the brightest source (the zenith when there is none) */
        qtool_probesun_src up = {{0, 0, 1}, {1, 1, 1}, 0, 0};
        if (qtool_probesun_path(v->scene, v->w, v->h, v->kind, v->threads, ns ? &suns[0] : &up, c->cls, &lp[LPMAX], &lpn[LPMAX]) != 0) {
            qtool_errf(c->err, c->errlen, "demo: out of memory (probe light paths)");
            goto done;
        }
        free(lp[LPMAX]), lp[LPMAX] = NULL;
    }
    *noise = qtool_ref_psnr8(qtool_bake_mse(c->truth, c->tmp, c->cls, np));
    qtool_bake_lin_to8(c->lin, v->w, v->h, c->truth);
    if (score_schemes(c, probe, sky, pw, ph, rows, suns, ns, parts, part_src, nparts, lp, lpn, ls) == 0)
        rc = keep_best(c, rows, ns, ls);
done:
    for (int i = 0; i <= LPMAX; ++i)
        free(lp[i]);
    free(sky);
    qtool_env_free(&env);
    return rc;
}

/* the maps and assets every probe is relit through: shadowed k16 and k25, unshadowed SHMU_K */
typedef struct {
    qtool_gen_maps m16, m25, mu;
    qtool_bake_sums us;
    uint8_t *a16, *a25;
} probe_assets;

static int bake_assets(ctx_t *c, const qtool_bake_sums *sums, uint32_t ndirs, probe_assets *pa)
{
    const qtool_demo_view *v = c->v;
    if (qtool_bake_coeffs(sums, 16, QTOOL_PROJ_QUADRATURE, &pa->m16) != 0 ||
        qtool_bake_coeffs(sums, 25, QTOOL_PROJ_QUADRATURE, &pa->m25) != 0 ||
        qtool_bake_asset(&pa->m16, 0, &pa->a16, &c->n16) != 0 || qtool_bake_asset(&pa->m25, 0, &pa->a25, &c->n25) != 0 ||
        qtool_bake_run_unshadowed(v->scene, v->w, v->h, v->kind, ndirs, SHMU_K, v->threads, &pa->us) != 0 ||
        qtool_bake_coeffs(&pa->us, SHMU_K, QTOOL_PROJ_QUADRATURE, &pa->mu) != 0)
        return qtool_errf(c->err, c->errlen, "demo: out of memory (probes)");
    c->a16 = pa->a16, c->a25 = pa->a25, c->m25 = &pa->m25, c->mu = &pa->mu;
    return 0;
}

static void assets_free(probe_assets *pa)
{
    qtool_gen_free(&pa->m16), qtool_gen_free(&pa->m25), qtool_gen_free(&pa->mu);
    qtool_bake_sums_free(&pa->us);
    free(pa->a16), free(pa->a25);
}

/* probe p: the user's file, or ../shared's when present, else the procedural stand-in; its label.
 * 0 or -1. */
static int load_probe(ctx_t *c, int have, int p, float **probe, int *pw, int *ph, char *label, size_t labn)
{
    if (c->user) {
        char err[1200];
        if (qtool_hdr_read(c->user, pw, ph, probe, err, sizeof err) != 0)
            return qtool_errf(c->err, c->errlen, "demo: %s", err);
        if ((size_t)*pw != 2 * (size_t)*ph) {
            free(*probe), *probe = NULL;
            return qtool_errf(c->err, c->errlen, "demo: --probe %s: %d x %d is not a 2:1 lat-long probe", c->user, *pw,
                              *ph);
        }
        snprintf(label, labn, "%s", c->user);
        return 0;
    }
    if (have) {
        char err[1200], path[600];
        snprintf(path, sizeof path, "%s/%s", PROBE_DIR, c->picks[p].file);
        if (qtool_hdr_read(path, pw, ph, probe, err, sizeof err) != 0)
            return qtool_errf(c->err, c->errlen, "demo: %s", err);
        snprintf(label, labn, "%s (%s)", c->picks[p].file, c->picks[p].what);
        return 0;
    }
    *pw = 1024, *ph = 512;
    *probe = procedural(p, *pw, *ph);
    snprintf(label, labn, "procedural %s probe (no %s)", c->picks[p].role, PROBE_DIR);
    return *probe ? 0 : qtool_errf(c->err, c->errlen, "demo: out of memory (probes)");
}

/* the sheet: a title strip (column names and the heat scale, 0 .. 48), then per probe a label strip
 * and best | truth | error */
typedef struct {
    uint8_t *px;
    int w, h, ts, strip;
} sheet_t;

static const uint8_t sheet_fg[3] = {235, 235, 235};

static void sheet_title(const sheet_t *sh, uint32_t w)
{
    int ts = sh->ts;
    memset(sh->px, 24, (size_t)sh->w * (size_t)sh->h * 3);
    qtool_text_draw(sh->px, sh->w, sh->h, 4, ts, "relit by the core (best scheme)", ts, sheet_fg);
    qtool_text_draw(sh->px, sh->w, sh->h, (int)w + 4, ts, "truth: ray-traced, all shadowed", ts, sheet_fg);
    qtool_text_draw(sh->px, sh->w, sh->h, 2 * (int)w + 4, ts, "error 0", ts, sheet_fg);
    int x0 = 2 * (int)w + 4 + 8 * 6 * ts, bw = (int)w / 3;
    for (int x = 0; bw >= 2 && x < bw; ++x) {
        uint8_t a[3] = {0, 0, 0}, b[3], o[3];
        b[0] = (uint8_t)lrint(255.0 * x / (bw - 1)), b[1] = b[2] = 0;
        qtool_demo_heat(b, a, (const uint8_t[]){1}, 1, o);
        for (int y = ts; y < 8 * ts; ++y)
            memcpy(sh->px + 3 * ((size_t)y * (size_t)sh->w + (size_t)(x0 + x)), o, 3);
    }
    qtool_text_draw(sh->px, sh->w, sh->h, x0 + bw + 4, ts, "48+ of 255", ts, sheet_fg);
}

static void sheet_row(const sheet_t *sh, ctx_t *c, int p, int have, const row_t rows[NSCHEME], int best)
{
    static const char *sn[NSCHEME] = {"probe SH k16", "probe SH k25", "16 median-cut lights", "sun + SH"};
    uint32_t w = c->v->w, h = c->v->h;
    int ts = sh->ts;
    qtool_demo_heat(c->best, c->truth, c->cls, (size_t)w * h, c->heatb);
    const uint8_t *src[3] = {c->best, c->truth, c->heatb};
    int y0 = sh->strip + p * (sh->strip + (int)h);
    char lab[200], nm[64];
    snprintf(nm, sizeof nm, "%s", have ? c->picks[p].file : "procedural");
    char *cut = strstr(nm, "_1k.hdr");
    if (cut)
        *cut = 0;
    snprintf(lab, sizeof lab, "%s, %s: %s %.1f dB", c->picks[p].role, nm, sn[best], rows[best].psnr);
    qtool_text_draw(sh->px, sh->w, sh->h, 4, y0 + ts, lab, ts, sheet_fg);
    snprintf(lab, sizeof lab, "(SH k25 alone: %.1f dB)", rows[S_SH25].psnr);
    qtool_text_draw(sh->px, sh->w, sh->h, (int)w + 4, y0 + ts, lab, ts, sheet_fg);
    for (int q = 0; q < 3; ++q)
        qtool_demo_blit(sh->px, (size_t)sh->w, (size_t)q * w, (size_t)(y0 + sh->strip), src[q], w, h);
}

/* what the three probes measured, for the report */
typedef struct {
    row_t rows[3][NSCHEME];
    double noise[3], scale[3], truth_s[3];
    int best[3], nsuns[3], nparts[3];
    qtool_probesun_src suns[3][MAX_SUNS];
    char label[3][300];
} probe_results;

static void print_report(FILE *o, const ctx_t *c, const probe_results *r, int have, double t0)
{
    static const char *sname[NSCHEME] = {"probe SH k16, shadowed maps", "probe SH k25, shadowed maps",
                                         "16 median-cut lights as SH k25, shadowed", "sun + SH: parts SHMU k16 x vis., SH k25"};
    fprintf(o, "\nlit by a real probe (%s): truth ray-traced with every direction shadowed, %u samples per pixel in each of "
               "two renders (bright set + MIS of probe CDF and cosine); bake of the unshadowed maps and probes %.1f s\n",
            c->user ? c->user : have ? PROBE_DIR : "procedural probes", c->spp, qtool_demo_now() - t0);
    for (int p = 0; p < c->npicks; ++p) {
        fprintf(o, "%s: %s, scaled x %.4g (irradiance %.1f facing up); truth %.1f s, halves agree to %.2f dB (the mean is "
                   "about 3 dB less noisy); %d compact source%s",
                c->picks[p].role, r->label[p], r->scale[p], TARGET_E_UP, r->truth_s[p], r->noise[p], r->nsuns[p],
                r->nsuns[p] == 1 ? "" : "s");
        for (int k = 0; k < r->nsuns[p]; ++k)
            fprintf(o, "%s %.0f %% of the energy within %.1f deg", k ? ";" : ":", 100 * r->suns[p][k].share,
                    r->suns[p][k].radius_deg);
        fprintf(o, "; %d directions with their own visibility\n", r->nparts[p]);
    }
    fprintf(o, "\nPSNR against the truth over scene pixels, and split by the brightest source's classes (lit / its cast "
               "shadow / facing away) with each class's share of the squared error; bright = linear mean relit / truth; "
               "bytes = chunks read\n\n");
    fprintf(o, "| probe  | %-42s | PSNR dB | lit            | cast shadow    | facing away    | bright | ms/frame | bytes   |\n",
            "scheme");
    fprintf(o, "|--------|%s|--------:|---------------:|---------------:|---------------:|-------:|---------:|--------:|\n",
            "--------------------------------------------");
    for (int p = 0; p < c->npicks; ++p)
        for (int q = 0; q < NSCHEME; ++q) {
            const row_t *row = &r->rows[p][q];
            fprintf(o, "| %-6s | %-42s | %7.2f | %6.2f (%4.1f%%) | %6.2f (%4.1f%%) | %6.2f (%4.1f%%) | %6.3f | %8.3f | %7.0f |\n",
                    c->picks[p].role, sname[q], row->psnr, row->psnr_cls[1], row->share_cls[1], row->psnr_cls[2],
                    row->share_cls[2], row->psnr_cls[3], row->share_cls[3], row->bright, row->ms, row->bytes);
        }
    fprintf(o, "\n");
    for (int p = 0; p < c->npicks; ++p) {
        const char *role = c->picks[p].role;
        for (int q = 0; q < NSCHEME; ++q)
            fprintf(o, "RESULT demo.probe_%s_%s_psnr %.2f\nRESULT demo.probe_%s_%s_brightness %.3f\n"
                       "RESULT demo.probe_%s_%s_ms %.3f\nRESULT demo.probe_%s_%s_bytes %.0f\n",
                    role, scheme_key[q], r->rows[p][q].psnr, role, scheme_key[q], r->rows[p][q].bright, role,
                    scheme_key[q], r->rows[p][q].ms, role, scheme_key[q], r->rows[p][q].bytes);
        fprintf(o, "RESULT demo.probe_%s_best_psnr %.2f\nRESULT demo.probe_%s_truth_halves_psnr %.2f\n", role,
                r->rows[p][r->best[p]].psnr, role, r->noise[p]);
    }
    fprintf(o, "RESULT demo.probe_s %.2f\n", qtool_demo_now() - t0);
    fprintf(o, "wrote %s/probe_sheet.png (rows: %s; columns: best scheme | truth | error 0..48)\n", c->v->dir,
            c->user ? "your probe" : "soft, sunny, indoor");
}

/* every probe relit, scored and drawn into its sheet row */
static int run_probes(ctx_t *c, int have, const sheet_t *sh, probe_results *r)
{
    for (int p = 0; p < c->npicks; ++p) {
        float *probe = NULL;
        int pw = 0, ph = 0;
        if (load_probe(c, have, p, &probe, &pw, &ph, r->label[p], sizeof r->label[p]) != 0)
            return -1;
        memset(r->rows[p], 0, sizeof r->rows[p]);
        r->best[p] = run_probe(c, p, r->label[p], probe, (uint32_t)pw, (uint32_t)ph, r->rows[p], &r->noise[p],
                               &r->nsuns[p], r->suns[p], &r->nparts[p], &r->scale[p], &r->truth_s[p]);
        free(probe);
        if (r->best[p] < 0)
            return -1;
        if (p == 0)
            sheet_title(sh, c->v->w);
        sheet_row(sh, c, p, have, r->rows[p], r->best[p]);
    }
    return 0;
}

/* the part over the probes of c (picks, npicks, user set) */
static int probe_part(ctx_t c, const qtool_bake_sums *sums, uint32_t ndirs)
{
    const qtool_demo_view *v = c.v;
    char *err = c.err;
    size_t errlen = c.errlen, np = (size_t)v->w * v->h;
    if (c.kparts < 1 || c.kparts > MAX_PARTS)
        return qtool_errf(err, errlen, "demo: %d parts per extended source is outside 1..%d", c.kparts, MAX_PARTS);
    probe_assets pa;
    memset(&pa, 0, sizeof pa);
    probe_results *r = malloc(sizeof *r);
    c.lin = malloc(np * 3 * sizeof(double)), c.ha = malloc(np * 3 * sizeof(double)), c.hb = malloc(np * 3 * sizeof(double));
    c.truth = malloc(np * 3), c.cls = malloc(np), c.tmp = malloc(np * 3), c.heatb = malloc(np * 3), c.best = malloc(np * 3);
    sheet_t sh = {.ts = v->w >= 768 ? 2 : 1};
    sh.strip = 10 * sh.ts, sh.w = (int)v->w * 3, sh.h = sh.strip + c.npicks * (sh.strip + (int)v->h);
    sh.px = malloc((size_t)sh.w * (size_t)sh.h * 3);
    double t0 = qtool_demo_now();
    int rc = -1;
    if (!r || !c.lin || !c.ha || !c.hb || !c.truth || !c.cls || !c.tmp || !c.heatb || !c.best || !sh.px)
        qtool_errf(err, errlen, "demo: out of memory (probes)");
    else if (bake_assets(&c, sums, ndirs, &pa) == 0) {
        DIR *d = c.user ? NULL : opendir(PROBE_DIR);
        int have = c.user || d != NULL;
        if (d)
            closedir(d);
        if (run_probes(&c, have, &sh, r) == 0 &&
            qtool_demo_save_png(v->dir, "probe_sheet.png", sh.w, sh.h, sh.px, err, errlen) == 0) {
            print_report(v->out, &c, r, have, t0);
            rc = 0;
        }
    }
    assets_free(&pa);
    free(r), free(sh.px);
    free(c.lin), free(c.ha), free(c.hb), free(c.truth), free(c.cls), free(c.tmp), free(c.heatb), free(c.best);
    return rc;
}

int qtool_demo_probe(const qtool_demo_view *v, uint32_t probe_spp, int kparts, const qtool_bake_sums *sums,
                     uint32_t ndirs, char *err, size_t errlen)
{
    ctx_t c = {.v = v, .spp = probe_spp, .kparts = kparts, .err = err, .errlen = errlen, .picks = demo_picks,
               .npicks = 3};
    return probe_part(c, sums, ndirs);
}

int qtool_demo_probe_file(const qtool_demo_view *v, const char *path, uint32_t probe_spp, int kparts,
                          const qtool_bake_sums *sums, uint32_t ndirs, char *err, size_t errlen)
{
    const char *base = strrchr(path, '/');
    const probe_pick user = {"user", base ? base + 1 : path, "your probe"};
    ctx_t c = {.v = v, .spp = probe_spp, .kparts = kparts, .err = err, .errlen = errlen, .picks = &user,
               .npicks = 1, .user = path};
    return probe_part(c, sums, ndirs);
}
