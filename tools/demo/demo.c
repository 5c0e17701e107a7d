/*
 * demo/demo.c - the main part of `qibl demo`: bake -> assets for k = 9, 16, 25 -> relight by the
 * core (sun sweep, moving lamp) -> PNG frames, APNGs, contact sheet against ground truth; the sizes
 * table and the helpers the other parts share.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "demo/demo.h"
#include "io/asset_write.h"
#include "io/atomic.h"
#include "io/png.h"
#include "io/text.h"
#include "qibl/asset.h"
#include "qtool.h"
#include "ref/psnr.h"

/* The one home of the demo's sizes (demo.h). */
static const qtool_demo_size demo_sizes[] = {
    {.name = "small", .w = 256, .h = 64, .ndirs = 128, .frames = 6, .path_steps = 32, .sky_dirs = 128, .probe_spp = 512,
     .ies_pos = 4, .nf_grid = 8, .nf_size = 48},
    {.name = "default", .w = 512, .h = 128, .ndirs = 256, .frames = 12, .path_steps = 32, .sky_dirs = 128, .probe_spp = 256,
     .ies_pos = 8, .nf_grid = 8, .nf_size = 64},
    {.name = "full", .w = 1024, .h = 256, .ndirs = 512, .frames = 24, .path_steps = 64, .sky_dirs = 256, .probe_spp = 256,
     .ies_pos = 16, .nf_grid = 16, .nf_size = 96},
};

const uint32_t qtool_demo_ks[QTOOL_DEMO_NK] = {9, 16, 25};

const qtool_demo_size *qtool_demo_size_named(const char *name)
{
    for (size_t i = 0; i < sizeof demo_sizes / sizeof demo_sizes[0]; ++i)
        if (strcmp(demo_sizes[i].name, name) == 0)
            return &demo_sizes[i];
    return NULL;
}

/* ---- shared helpers --------------------------------------------------------------------------- */

void qtool_demo_heat(const uint8_t *a, const uint8_t *b, const uint8_t *cls, size_t np, uint8_t *out)
{
    for (size_t i = 0; i < np; ++i) {
        int d = 0;
        for (int c = 0; c < 3; ++c) {
            int x = abs((int)a[3 * i + (size_t)c] - (int)b[3 * i + (size_t)c]);
            d = x > d ? x : d;
        }
        double t = cls[i] ? fmin(1.0, d / 48.0) : 0;
        double r = fmin(1, fmax(0, 3 * t - 1)), g = fmin(1, fmax(0, 3 * t - 2)), bl = t < 1.0 / 3 ? 3 * t : fmax(0, 2 - 3 * t);
        out[3 * i] = (uint8_t)lrint(255 * r), out[3 * i + 1] = (uint8_t)lrint(255 * g);
        out[3 * i + 2] = (uint8_t)lrint(255 * fmax(bl, 0.25 * g));
    }
}

double qtool_demo_chunk_bytes(const uint8_t *asset, size_t n, uint32_t type, uint32_t index)
{
    qibl_asset_t a;
    qibl_chunk_t c;
    if (qtool_asset_open(&a, asset, n) != QIBL_OK || qibl_asset_find_nth(&a, type, index, &c) != QIBL_OK)
        return 0;
    return c.size;
}

double qtool_demo_lin8(int v)
{
    double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double qtool_demo_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double qtool_demo_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void qtool_demo_blit(uint8_t *sheet, size_t sheet_w, size_t x0, size_t y0, const uint8_t *src, uint32_t w, uint32_t h)
{
    for (uint32_t y = 0; y < h; ++y)
        memcpy(sheet + ((y0 + y) * sheet_w + x0) * 3, src + (size_t)y * w * 3, (size_t)w * 3);
}

/* dir/name in a malloc'ed string (no fixed-size buffer: a long --out is never truncated); NULL if
 * out of memory */
static char *join(const char *dir, const char *name)
{
    size_t a = strlen(dir), b = strlen(name);
    char *p = malloc(a + b + 2);
    if (p) {
        memcpy(p, dir, a);
        p[a] = '/';
        memcpy(p + a + 1, name, b + 1);
    }
    return p;
}

int qtool_demo_save_png(const char *dir, const char *name, int w, int h, const uint8_t *rgb, char *err, size_t errlen)
{
    char *path = join(dir, name);
    if (!path)
        return qtool_errf(err, errlen, "demo: out of memory");
    int rc = qtool_png_write_rgb8(path, w, h, rgb, err, errlen) != 0 ? -1 : 0;
    free(path);
    return rc;
}

/* ---- the output directory --------------------------------------------------------------------- */

/* every name the demo writes: these, then the frames sun_00.png .. and lamp_00.png .. */
static const char *const fixed_names[] = {"scene_k9.qibl",   "scene_k16.qibl",    "scene_k25.qibl", "sun_sweep.png",
                                          "lamp_sweep.png",  "contact_sheet.png", "relit_sun.png",  "truth_sun.png",
                                          "paths_sheet.png", "paths_readme.png",  "probe_sheet.png"};
enum { NFIXED = sizeof fixed_names / sizeof fixed_names[0] };

static void out_name(long i, long frames, char *name, size_t n)
{
    if (i < NFIXED)
        snprintf(name, n, "%s", fixed_names[i]);
    else
        snprintf(name, n, "%s_%02ld.png", i - NFIXED < frames ? "sun" : "lamp", (i - NFIXED) % frames);
}

int qtool_demo_check_out(const char *dir, long frames, char *err, size_t errlen)
{
    struct stat st;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return qtool_errf(err, errlen, "%s: cannot create the output directory: %s", dir, strerror(errno));
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return qtool_errf(err, errlen, "%s: not a directory", dir);
    char name[64];
    for (long i = 0; i < NFIXED + 2 * frames; ++i) {
        out_name(i, frames, name, sizeof name);
        char *path = join(dir, name);
        if (!path)
            return qtool_errf(err, errlen, "demo: out of memory");
        int bad = qtool_io_check_replaceable(path, err, errlen) != 0;
        if (!bad && i == 0) { /* one real temporary file: the directory takes new files */
            qtool_io_atomic a;
            bad = qtool_io_atomic_open(&a, path, err, errlen) != 0;
            if (!bad)
                qtool_io_atomic_abort(&a);
        }
        free(path);
        if (bad)
            return -1;
    }
    return 0;
}

/* ---- the main part ---------------------------------------------------------------------------- */

int qtool_demo_bake(const qtool_demo_view *v, uint32_t ndirs, qtool_demo_main *m, char *err, size_t errlen)
{
    memset(m, 0, sizeof *m);
    double t0 = qtool_demo_now();
    if (qtool_bake_run(v->scene, v->w, v->h, v->kind, ndirs, 25, 0, 1, v->threads, 1, &m->sums) != 0)
        return qtool_errf(err, errlen, "demo: out of memory");
    m->bake_s = qtool_demo_now() - t0;
    return 0;
}

void qtool_demo_main_free(qtool_demo_main *m)
{
    for (int q = 0; q < QTOOL_DEMO_NK; ++q)
        free(m->asset[q]), m->asset[q] = NULL;
    qtool_bake_sums_free(&m->sums);
}

/* the buffers of the main part: ground truth of every evaluation light, its scene mask, scratch */
typedef struct {
    const qtool_demo_view *v;
    const qtool_rt_light *ev;
    size_t np;
    uint8_t *truth[QTOOL_DEMO_NEVAL], *mask, *tmp, *heatb;
} main_ctx;

/* qtool_bake_relight8 with its failure named: 0 or -1 */
static int relight(const uint8_t *asset, size_t n, const qtool_rt_light *l, int use_lut, uint8_t *rgb8, double *ms,
                   char *err, size_t errlen)
{
    if (qtool_bake_relight8(asset, n, l, use_lut, rgb8, ms) == 0)
        return 0;
    return qtool_errf(err, errlen, "demo: relighting the baked asset failed (%zu bytes)", n);
}

static int truths(main_ctx *c, char *err, size_t errlen)
{
    const qtool_demo_view *v = c->v;
    c->mask = malloc(c->np), c->tmp = malloc(c->np * 3), c->heatb = malloc(c->np * 3);
    for (int i = 0; i < QTOOL_DEMO_NEVAL; ++i) {
        c->truth[i] = malloc(c->np * 3);
        if (!c->truth[i] || !c->mask || !c->tmp || !c->heatb ||
            qtool_bake_truth8(v->scene, v->w, v->h, v->kind, &c->ev[i], v->threads, c->truth[i], c->mask) != 0)
            return qtool_errf(err, errlen, "demo: out of memory");
    }
    return 0;
}

/* scene_k{9,16,25}.qibl, each scored over the suns and the lamps */
static int score_assets(main_ctx *c, qtool_demo_main *m, char *err, size_t errlen)
{
    char name[64];
    for (int q = 0; q < QTOOL_DEMO_NK; ++q) {
        qtool_gen_maps maps;
        if (qtool_bake_coeffs(&m->sums, qtool_demo_ks[q], QTOOL_PROJ_QUADRATURE, &maps) != 0)
            return qtool_errf(err, errlen, "demo: out of memory");
        int bad = qtool_bake_asset(&maps, 32, &m->asset[q], &m->asize[q]) != 0;
        qtool_gen_free(&maps);
        if (bad)
            return qtool_errf(err, errlen, "demo: out of memory");
        snprintf(name, sizeof name, "scene_k%u.qibl", qtool_demo_ks[q]);
        char *path = join(c->v->dir, name);
        if (!path)
            return qtool_errf(err, errlen, "demo: out of memory");
        bad = qtool_io_write_atomic(path, m->asset[q], m->asize[q], err, errlen) != 0;
        free(path);
        if (bad)
            return -1;
        double mse_d = 0, mse_p = 0, tms[QTOOL_DEMO_NEVAL];
        for (int i = 0; i < QTOOL_DEMO_NEVAL; ++i) {
            if (relight(m->asset[q], m->asize[q], &c->ev[i], 1, c->tmp, &tms[i], err, errlen) != 0)
                return -1;
            double e = qtool_bake_mse(c->tmp, c->truth[i], c->mask, c->np);
            if (i < QTOOL_DEMO_NSUN)
                mse_d += e / QTOOL_DEMO_NSUN;
            else
                mse_p += e / QTOOL_DEMO_NLAMP;
        }
        m->psnr_dir[q] = qtool_ref_psnr8(mse_d);
        m->psnr_pt[q] = qtool_ref_psnr8(mse_p);
        m->ms_dir[q] = qtool_demo_median(tms, QTOOL_DEMO_NSUN);
        m->ms_pt[q] = qtool_demo_median(tms + QTOOL_DEMO_NSUN, QTOOL_DEMO_NLAMP);
    }
    return 0;
}

/* quadrature against least squares, k = 16, suns. The least-squares coefficients fail when the
 * Gram matrix of too few directions is singular: the table then says 0 dB, as it always has. */
static int score_lsq(main_ctx *c, qtool_demo_main *m, char *err, size_t errlen)
{
    qtool_gen_maps maps;
    uint8_t *b = NULL;
    size_t n = 0;
    m->lsq_dir = 0;
    if (qtool_bake_coeffs(&m->sums, 16, QTOOL_PROJ_LSQ, &maps) != 0)
        return 0;
    int rc = qtool_bake_asset(&maps, 0, &b, &n) != 0 ? qtool_errf(err, errlen, "demo: out of memory") : 0;
    double mse = 0;
    for (int i = 0; rc == 0 && i < QTOOL_DEMO_NSUN; ++i) {
        rc = relight(b, n, &c->ev[i], 0, c->tmp, NULL, err, errlen);
        mse += qtool_bake_mse(c->tmp, c->truth[i], c->mask, c->np) / QTOOL_DEMO_NSUN;
    }
    if (rc == 0)
        m->lsq_dir = qtool_ref_psnr8(mse);
    qtool_gen_free(&maps);
    free(b);
    return rc;
}

/* frame f of the sun sweep (pass 0) or the lamp's circle (pass 1) */
static qtool_rt_light sweep_light(int pass, long f, long frames, int prop)
{
    double t = (double)f / frames, a = 2 * QTOOL_DEMO_PI15 * t;
    if (pass == 0) {
        double el = 0.35 + 0.45 * sin(QTOOL_DEMO_PI15 * t);
        qtool_rt_light sl = {0, {cos(el) * cos(a), cos(el) * sin(a), sin(el)}, {0, 0, 0}, {2.6, 2.4, 2.1}, 1};
        return sl;
    }
    double cx = prop ? QTOOL_RT_PROP_X : 0.0, r = prop ? 2.2 : 2.8;
    qtool_rt_light pl = {1, {0, 0, 1}, {cx + r * cos(a), r * sin(a), -0.5 + 0.4 * sin(2 * a)}, {5.0, 4.4, 3.6}, 1};
    return pl;
}

/* sun sweep and moving lamp, k = 16: sun_NN.png, lamp_NN.png and their APNGs */
static int sweeps(const qtool_demo_view *v, long frames, const qtool_demo_main *m, char *err, size_t errlen)
{
    size_t np = (size_t)v->w * v->h;
    uint8_t *anim = malloc(np * 3 * (size_t)frames);
    if (!anim)
        return qtool_errf(err, errlen, "demo: out of memory");
    int rc = 0;
    char name[64];
    for (int pass = 0; pass < 2 && rc == 0; ++pass) {
        for (long f = 0; f < frames && rc == 0; ++f) {
            qtool_rt_light l = sweep_light(pass, f, frames, v->prop);
            uint8_t *fr = anim + np * 3 * (size_t)f;
            snprintf(name, sizeof name, "%s_%02ld.png", pass ? "lamp" : "sun", f);
            rc = relight(m->asset[1], m->asize[1], &l, 1, fr, NULL, err, errlen) != 0 ||
                 qtool_demo_save_png(v->dir, name, (int)v->w, (int)v->h, fr, err, errlen) != 0;
        }
        char *path = rc ? NULL : join(v->dir, pass ? "lamp_sweep.png" : "sun_sweep.png");
        if (rc == 0 && !path)
            rc = qtool_errf(err, errlen, "demo: out of memory");
        else if (rc == 0)
            rc = qtool_apng_write_rgb8(path, (int)v->w, (int)v->h, (int)frames, anim, 1, 8, err, errlen) != 0;
        free(path);
    }
    free(anim);
    return rc ? -1 : 0;
}

/* contact sheet: relit (k = 16) | ground truth | error heat map, for 3 suns and 2 lamps, each column
 * and row under a label; then the README's pair, one relit sun frame and its truth */
static int contact_sheet(main_ctx *c, const qtool_demo_main *m, char *err, size_t errlen)
{
    static const int rows[5] = {0, 3, 6, QTOOL_DEMO_NSUN, QTOOL_DEMO_NSUN + 2};
    static const char *cols[3] = {"relit by the core, k = 16", "truth: ray-traced", "error, 0 .. 48+ of 255"};
    static const uint8_t fg[3] = {235, 235, 235};
    uint32_t w = c->v->w, h = c->v->h;
    int ts = w >= 512 ? 2 : 1, strip = (QTOOL_TEXT_HEIGHT + 3) * ts;
    size_t sw = (size_t)w * 3, shh = ((size_t)h + (size_t)strip) * 5;
    uint8_t *sheet = malloc(sw * 3 * shh);
    if (!sheet)
        return qtool_errf(err, errlen, "demo: out of memory");
    memset(sheet, 24, sw * 3 * shh);
    int rc = 0;
    for (int r = 0; r < 5 && rc == 0; ++r) {
        int i = rows[r];
        size_t y0 = (size_t)r * (h + (size_t)strip);
        rc = relight(m->asset[1], m->asize[1], &c->ev[i], 1, c->tmp, NULL, err, errlen);
        if (rc != 0)
            break;
        qtool_demo_heat(c->tmp, c->truth[i], c->mask, c->np, c->heatb);
        const uint8_t *src[3] = {c->tmp, c->truth[i], c->heatb};
        char lab[120];
        snprintf(lab, sizeof lab, "%s %d: %s", i < QTOOL_DEMO_NSUN ? "sun" : "lamp",
                 i < QTOOL_DEMO_NSUN ? i + 1 : i - QTOOL_DEMO_NSUN + 1, cols[0]);
        for (int col = 0; col < 3; ++col) {
            qtool_text_draw(sheet, (int)sw, (int)shh, col * (int)w + 4, (int)y0 + ts, col == 0 ? lab : cols[col], ts, fg);
            qtool_demo_blit(sheet, sw, (size_t)col * w, y0 + (size_t)strip, src[col], w, h);
        }
    }
    if (rc == 0)
        rc = qtool_demo_save_png(c->v->dir, "contact_sheet.png", (int)sw, (int)shh, sheet, err, errlen);
    free(sheet);
    if (rc == 0)
        rc = relight(m->asset[1], m->asize[1], &c->ev[0], 1, c->tmp, NULL, err, errlen);
    if (rc == 0)
        rc = qtool_demo_save_png(c->v->dir, "relit_sun.png", (int)w, (int)h, c->tmp, err, errlen);
    if (rc == 0)
        rc = qtool_demo_save_png(c->v->dir, "truth_sun.png", (int)w, (int)h, c->truth[0], err, errlen);
    return rc;
}

int qtool_demo_relight(const qtool_demo_view *v, const qtool_rt_light ev[QTOOL_DEMO_NEVAL], long frames,
                       qtool_demo_main *m, char *err, size_t errlen)
{
    main_ctx c = {.v = v, .ev = ev, .np = (size_t)v->w * v->h};
    int rc = truths(&c, err, errlen);
    if (rc == 0)
        rc = score_assets(&c, m, err, errlen);
    if (rc == 0)
        rc = score_lsq(&c, m, err, errlen);
    if (rc == 0)
        rc = sweeps(v, frames, m, err, errlen);
    if (rc == 0)
        rc = contact_sheet(&c, m, err, errlen);
    for (int i = 0; i < QTOOL_DEMO_NEVAL; ++i)
        free(c.truth[i]);
    free(c.mask), free(c.tmp), free(c.heatb);
    return rc;
}
