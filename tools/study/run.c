/*
 * run.c - `qibl study`: every method at every N on every probe, against the ground truth; the CSV,
 * the SVG plots, the PNG overlays, summary.md and the RESULT lines.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "io/atomic.h"
#include "io/hdr.h"
#include "io/png.h"
#include "io/probe_layout.h"
#include "study/study.h"

#define MAXP 24
#define NLIST 15
static const int nlist[NLIST] = {1, 2, 3, 4, 5, 8, 12, 16, 24, 32, 48, 64, 96, 128, 256};
#define SUNSKY_KMAX 16
#define OVERLAY_N 16

typedef struct {
    int probe, method, nreq, n, numbers, conv, iters;
    qtool_study_err e;
    double ms;
} row;

typedef struct {
    char name[128];
    int w, h;
    int sunny;
    double gt_brute, gt_half, gt_ms;
} pinfo;

static row *rows;
static int nrows, caprows;

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

static void add_row(int probe, int method, int nreq, const qtool_study_model *md, const qtool_study_err *e, double ms,
                    int conv, int iters)
{
    if (nrows == caprows) {
        int nc = caprows ? 2 * caprows : 1024;
        row *r = realloc(rows, sizeof *r * (size_t)nc);
        if (!r)
            return;
        rows = r, caprows = nc;
    }
    row *r = &rows[nrows++];
    r->probe = probe, r->method = method, r->nreq = nreq, r->n = md->n + md->sh_n;
    r->numbers = qtool_study_model_numbers(md), r->conv = conv, r->iters = iters, r->e = *e, r->ms = ms;
}

static const row *find(int probe, int method, int nreq)
{
    for (int i = 0; i < nrows; ++i)
        if (rows[i].probe == probe && rows[i].method == method && rows[i].nreq == nreq)
            return &rows[i];
    return NULL;
}

/* ---- probes ---------------------------------------------------------------------------------- */

static const char *base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

/* 2x box downsampling of RGBE (through floats) */
static uint8_t *half_rgbe(const uint8_t *px, int w, int h)
{
    int w2 = w / 2, h2 = h / 2;
    float *f = calloc(3 * (size_t)w2 * (size_t)h2, sizeof *f);
    uint8_t *o = malloc(4 * (size_t)w2 * (size_t)h2);
    if (!f || !o) {
        free(f), free(o);
        return NULL;
    }
    for (int v = 0; v < 2 * h2; ++v)
        for (int u = 0; u < 2 * w2; ++u) {
            const uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            for (int c = 0; c < 3; ++c)
                f[3 * ((size_t)(v / 2) * (size_t)w2 + (size_t)(u / 2)) + (size_t)c] +=
                    q[3] ? (float)(ldexp(q[c], q[3] - 136) / 4) : 0.0f;
        }
    qtool_probe_layout_rgbe_encode(f, (size_t)w2 * (size_t)h2, o);
    free(f);
    return o;
}

/* A probe is sunny when its brightest 0.1 % of directions hold over a third of its energy. */
static int is_sunny(const qtool_study_probe *p)
{
    size_t n = (size_t)p->w * (size_t)p->h, top = n / 1000 + 1;
    double *e = malloc(sizeof *e * n), tot = 0;
    if (!e)
        return 0;
    for (size_t i = 0; i < n; ++i)
        tot += e[i] = p->q[3 * i] + p->q[3 * i + 1] + p->q[3 * i + 2];
    /* partial selection: a threshold by bisection on the value */
    double lo = 0, hi = 0;
    for (size_t i = 0; i < n; ++i)
        hi = fmax(hi, e[i]);
    for (int it = 0; it < 60; ++it) {
        double mid = (lo + hi) / 2;
        size_t c = 0;
        for (size_t i = 0; i < n; ++i)
            c += e[i] > mid;
        if (c > top)
            lo = mid;
        else
            hi = mid;
    }
    double s = 0;
    for (size_t i = 0; i < n; ++i)
        if (e[i] > lo)
            s += e[i];
    free(e);
    return tot > 0 && s > tot / 3;
}

/* ---- one probe ------------------------------------------------------------------------------- */

typedef struct {
    int quick, threads, m, nmax, io_max, io_fit, io_iter, km_iter;
} cfg;

typedef struct {
    qtool_study_model *ov[QTOOL_STUDY_METHOD_COUNT]; /* the models drawn in the overlay */
} overlay;

static int n_allowed(int method, int n, const cfg *c)
{
    if (n > c->nmax)
        return 0;
    if ((method == QTOOL_STUDY_MEDIANCUT || method == QTOOL_STUDY_REFIT_MC) && (n & (n - 1)))
        return 0;
    if (method == QTOOL_STUDY_IRROPT && n > c->io_max)
        return 0;
    return 1;
}

static void keep(overlay *ov, int method, const qtool_study_model *md)
{
    if (!ov->ov[method])
        ov->ov[method] = malloc(sizeof *md);
    if (ov->ov[method])
        *ov->ov[method] = *md;
}

static int run_probe(int pi, const qtool_study_probe *p, const cfg *c, pinfo *info, overlay *ov)
{
    char err[512];
    qtool_study_gt g;
    double t0 = now_ms();
    if (qtool_study_gt_compute(&g, p, c->m, c->threads) != 0)
        return fprintf(stderr, "qibl: study: %s: out of memory for the ground truth\n", info->name), -1;
    info->gt_ms = now_ms() - t0;
    qtool_study_gt_accuracy(&g, p, p->w >= 2048 ? 4 : c->quick ? 8 : 32, &info->gt_brute, &info->gt_half);
    info->sunny = is_sunny(p);
    printf("study: %s %d x %d%s: ground truth %d normals in %.0f ms, max rel. diff. to the pixel sum %.1e, "
           "mean rel. diff. to the probe at half size %.2e\n",
           info->name, p->w, p->h, info->sunny ? " (sunny)" : "", g.m, info->gt_ms, info->gt_brute, info->gt_half);
    fflush(stdout);
    qtool_study_model *md = malloc(sizeof *md), *src = malloc(sizeof *src);
    if (!md || !src) {
        free(md), free(src), qtool_study_gt_free(&g);
        return -1;
    }
    qtool_study_err e;
    for (int k = 0; k < NLIST; ++k) {
        int n = nlist[k];
        /* the core's three samplers, and the refits of median cut and varmin */
        for (int m = QTOOL_STUDY_MEDIANCUT; m <= QTOOL_STUDY_VARMIN; ++m) {
            if (!n_allowed(m, n, c))
                continue;
            double t = now_ms();
            if (qtool_study_core_lights(p, m, n, src, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: study: %s: %s\n", info->name, err);
                continue;
            }
            double tm = now_ms() - t;
            qtool_study_model_error(src, &g, &e);
            add_row(pi, m, n, src, &e, tm, -1, 0);
            if (n == OVERLAY_N)
                keep(ov, m, src);
            int rm = m == QTOOL_STUDY_MEDIANCUT ? QTOOL_STUDY_REFIT_MC : m == QTOOL_STUDY_VARMIN ? QTOOL_STUDY_REFIT_VM : -1;
            if (rm >= 0) {
                *md = *src;
                t = now_ms();
                if (qtool_study_refit(md, &g) == 0) {
                    double tr = now_ms() - t + tm;
                    qtool_study_model_error(md, &g, &e);
                    add_row(pi, rm, n, md, &e, tr, -1, 0);
                    if (n == OVERLAY_N)
                        keep(ov, rm, md);
                }
            }
            if (m == QTOOL_STUDY_ADAPTIVE && n_allowed(QTOOL_STUDY_IRROPT, n, c)) {
                /* irradiance optimisation, started from the adaptive median cut's lights */
                *md = *src;
                int iters = 0;
                t = now_ms();
                int conv = qtool_study_irropt(md, &g, c->io_fit, c->io_iter, &iters);
                double ti = now_ms() - t + tm;
                if (conv >= 0) {
                    qtool_study_model_error(md, &g, &e);
                    add_row(pi, QTOOL_STUDY_IRROPT, n, md, &e, ti, conv, iters);
                    if (n == OVERLAY_N)
                        keep(ov, QTOOL_STUDY_IRROPT, md);
                }
            }
        }
        if (n_allowed(QTOOL_STUDY_KMEANS, n, c)) {
            double t = now_ms();
            if (qtool_study_kmeans(p, n, c->km_iter, md) == 0) {
                double tk = now_ms() - t;
                qtool_study_model_error(md, &g, &e);
                add_row(pi, QTOOL_STUDY_KMEANS, n, md, &e, tk, -1, 0);
                if (n == OVERLAY_N)
                    keep(ov, QTOOL_STUDY_KMEANS, md);
            }
        }
    }
    static const int shn[4] = {4, 9, 16, 25};
    for (int k = 0; k < 4; ++k) {
        double t = now_ms();
        if (qtool_study_core_sh(p, shn[k], md, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: study: %s: %s\n", info->name, err);
            continue;
        }
        double ts = now_ms() - t;
        qtool_study_model_error(md, &g, &e);
        add_row(pi, QTOOL_STUDY_SH, shn[k], md, &e, ts, -1, 0);
    }
    qtool_study_err se[SUNSKY_KMAX + 1];
    double sms[SUNSKY_KMAX + 1];
    if (qtool_study_sunsky_sweep(p, &g, SUNSKY_KMAX, se, sms, md, err, sizeof err) == 0) {
        for (int k = 0; k <= SUNSKY_KMAX; ++k) {
            qtool_study_model t = {0};
            t.n = k, t.sh_n = 9;
            add_row(pi, QTOOL_STUDY_SUNSKY, k, &t, &se[k], sms[k], -1, 0);
        }
        keep(ov, QTOOL_STUDY_SUNSKY, md);
    } else {
        fprintf(stderr, "qibl: study: %s: %s\n", info->name, err);
    }
    free(md), free(src);
    qtool_study_gt_free(&g);
    return 0;
}

/* ---- overlays -------------------------------------------------------------------------------- */

static const int ov_methods[] = {QTOOL_STUDY_MEDIANCUT, QTOOL_STUDY_ADAPTIVE, QTOOL_STUDY_VARMIN,
                                 QTOOL_STUDY_KMEANS,    QTOOL_STUDY_IRROPT,   QTOOL_STUDY_SUNSKY};
#define NOV (int)(sizeof ov_methods / sizeof ov_methods[0])

/* 0, or -1 with the reason said on stderr */
static int write_overlay(const char *path, const qtool_study_probe *p, const overlay *ov)
{
    const int W = 512, H = 256;
    uint8_t *img = malloc(3 * (size_t)W * (size_t)H * NOV);
    if (!img)
        return fprintf(stderr, "qibl: study: %s: out of memory for the overlay\n", path), -1;
    /* tone map: luminance scaled so the mean maps to 0.3, Reinhard, gamma 2.2 */
    double mean = 0;
    for (int v = 0; v < p->h; ++v)
        for (int u = 0; u < p->w; ++u) {
            const uint8_t *q = p->rgbe + 4 * ((size_t)v * (size_t)p->w + (size_t)u);
            mean += q[3] ? ldexp(q[0] + q[1] + q[2], q[3] - 136) / 3 : 0;
        }
    mean /= (double)p->w * p->h;
    double k = mean > 0 ? 0.3 / mean : 1;
    for (int pan = 0; pan < NOV; ++pan)
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                int u = x * p->w / W, v = y * p->h / H;
                const uint8_t *q = p->rgbe + 4 * ((size_t)v * (size_t)p->w + (size_t)u);
                uint8_t *o = img + 3 * (((size_t)pan * H + (size_t)y) * W + (size_t)x);
                for (int c = 0; c < 3; ++c) {
                    double l = q[3] ? ldexp(q[c], q[3] - 136) * k : 0;
                    o[c] = (uint8_t)(255 * pow(l / (1 + l), 1 / 2.2) + 0.5);
                }
                if (y == 0) /* a separator line between the panels */
                    o[0] = o[1] = o[2] = 255;
            }
    static const uint8_t col[NOV][3] = {{255, 40, 40}, {40, 255, 40}, {60, 120, 255},
                                        {255, 230, 0}, {255, 0, 255}, {0, 255, 255}};
    for (int pan = 0; pan < NOV; ++pan) {
        const qtool_study_model *md = ov->ov[ov_methods[pan]];
        if (!md)
            continue;
        for (int i = 0; i < md->n; ++i) {
            double th = acos(fmax(-1, fmin(1, md->dir[i][2]))), ph = atan2(md->dir[i][1], md->dir[i][0]);
            if (ph < 0)
                ph += 2 * 3.14159265358979323846;
            int cx = (int)(ph / (2 * 3.14159265358979323846) * W), cy = (int)(th / 3.14159265358979323846 * H);
            for (int dy = -3; dy <= 3; ++dy)
                for (int dx = -3; dx <= 3; ++dx) {
                    if (dx * dx + dy * dy > 10)
                        continue;
                    int xx = ((cx + dx) % W + W) % W, yy = cy + dy;
                    if (yy < 0 || yy >= H)
                        continue;
                    uint8_t *o = img + 3 * (((size_t)pan * H + (size_t)yy) * W + (size_t)xx);
                    int edge = dx * dx + dy * dy > 5;
                    for (int c = 0; c < 3; ++c)
                        o[c] = edge ? 0 : col[pan][c];
                }
        }
    }
    char err[512];
    int rc = qtool_png_write_rgb8(path, W, H * NOV, img, err, sizeof err);
    if (rc != 0)
        fprintf(stderr, "qibl: study: %s\n", err);
    free(img);
    return rc != 0 ? -1 : 0;
}

/* ---- plots ----------------------------------------------------------------------------------- */

/* mean (solid) and max (dashed) relative error against N for every method; probe -1 = averaged */
static int plot_n(const char *path, const char *title, int probe, int np)
{
    qtool_study_series s[2 * QTOOL_STUDY_METHOD_COUNT];
    static double X[2 * QTOOL_STUDY_METHOD_COUNT][NLIST + SUNSKY_KMAX + 1], Y[2 * QTOOL_STUDY_METHOD_COUNT][NLIST + SUNSKY_KMAX + 1];
    int ns = 0;
    for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m)
        for (int mx = 0; mx < 2; ++mx) {
            int k = 0;
            int cand[NLIST + SUNSKY_KMAX + 1], nc = 0;
            if (m == QTOOL_STUDY_SH) {
                cand[nc++] = 4, cand[nc++] = 9, cand[nc++] = 16, cand[nc++] = 25;
            } else if (m == QTOOL_STUDY_SUNSKY) {
                for (int j = 1; j <= SUNSKY_KMAX; ++j)
                    cand[nc++] = j;
            } else {
                for (int j = 0; j < NLIST; ++j)
                    cand[nc++] = nlist[j];
            }
            for (int j = 0; j < nc; ++j) {
                double sum = 0;
                int cnt = 0;
                for (int q = 0; q < np; ++q) {
                    if (probe >= 0 && q != probe)
                        continue;
                    const row *r = find(q, m, cand[j]);
                    if (r) {
                        sum += mx ? r->e.max_rel : r->e.mean_rel;
                        ++cnt;
                    }
                }
                if (cnt == (probe >= 0 ? 1 : np)) {
                    X[ns][k] = cand[j], Y[ns][k++] = 100 * sum / cnt;
                }
            }
            if (k == 0)
                continue;
            s[ns] = (qtool_study_series){mx ? NULL : qtool_study_method_name(m), k, X[ns], Y[ns], m, mx};
            ++ns;
        }
    char err[512];
    if (qtool_study_svg_plot(path, title, "N (lights; SH: coefficients; sun+sky: lights besides SH9)",
                             "relative irradiance error % (solid mean, dashed max)", 1, 1, 1, s, ns, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: study: %s\n", err), -1;
    return 0;
}

static int plot_time(const char *path, const char *title, int probe)
{
    qtool_study_series s[QTOOL_STUDY_METHOD_COUNT];
    static double X[QTOOL_STUDY_METHOD_COUNT][NLIST + SUNSKY_KMAX + 1], Y[QTOOL_STUDY_METHOD_COUNT][NLIST + SUNSKY_KMAX + 1];
    int ns = 0;
    for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m) {
        int k = 0;
        for (int i = 0; i < nrows; ++i)
            if (rows[i].probe == probe && rows[i].method == m && (m != QTOOL_STUDY_SUNSKY || rows[i].nreq > 0) &&
                k < NLIST + SUNSKY_KMAX + 1)
                X[ns][k] = fmax(rows[i].ms, 1e-3), Y[ns][k++] = 100 * rows[i].e.mean_rel;
        if (k == 0)
            continue;
        s[ns] = (qtool_study_series){qtool_study_method_name(m), k, X[ns], Y[ns], m, 0};
        ++ns;
    }
    char err[512];
    if (qtool_study_svg_plot(path, title, "wall time ms (one thread; core build included)", "mean relative error %", 1, 0,
                             1, s, ns, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: study: %s\n", err), -1;
    return 0;
}

/* ---- summary --------------------------------------------------------------------------------- */

/* the smallest N (or k) whose mean relative error is <= thr, -1 if none; its floats in *num */
static int n_to_reach(int probe, int method, double thr, int *num)
{
    int best = -1;
    *num = 0;
    for (int i = 0; i < nrows; ++i) {
        const row *r = &rows[i];
        if (r->probe != probe || r->method != method || !(r->e.mean_rel <= thr))
            continue;
        if (best < 0 || r->nreq < best)
            best = r->nreq, *num = r->numbers;
    }
    return best;
}

static int reached(int probe, int method, double thr)
{
    int num;
    return n_to_reach(probe, method, thr, &num) >= 0;
}

/* mkdir -p: the parents too (out/study in a fresh checkout) */
static int mkdir_p(const char *dir)
{
    char buf[1024];
    size_t n = strlen(dir);
    if (n == 0 || n >= sizeof buf)
        return errno = ENAMETOOLONG, -1;
    memcpy(buf, dir, n + 1);
    for (size_t i = 1; i <= n; ++i)
        if (buf[i] == '/' || buf[i] == '\0') {
            char c = buf[i];
            buf[i] = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST)
                return -1;
            buf[i] = c;
        }
    return 0;
}

static overlay ovs[MAXP + 1];

/* writes text through the atomic writer (io/atomic.h); 0, or -1 with the reason on stderr */
static int open_out(qtool_io_atomic *a, const char *path)
{
    char err[1200];
    if (qtool_io_atomic_open(a, path, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: study: %s\n", err), -1;
    return 0;
}

static int commit_out(qtool_io_atomic *a)
{
    char err[1200];
    if (qtool_io_atomic_commit(a, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: study: %s\n", err), -1;
    return 0;
}

/* probe i as a 2:1 RGBE lat-long: a procedural sky (no paths) or the file, halved for --quick;
 * its name into pi. 0, or 1 with the reason on stderr. */
static int load_probe(const char *const *paths, int i, int procedural, const qtool_study_opts *o, pinfo *pi, int *w_out,
                      int *h_out, uint8_t **px_out)
{
    int w, h;
    uint8_t *px = NULL;
    char err[512];
    if (procedural) {
        w = o->quick ? 256 : 1024, h = w / 2;
        px = qtool_study_procedural(w, h, i == 0);
        snprintf(pi->name, sizeof pi->name, "procedural_%s", i == 0 ? "sunny" : "overcast");
        if (!px)
            return fprintf(stderr, "qibl: study: out of memory\n"), 1;
    } else {
        if (qtool_hdr_read_rgbe(paths[i], &w, &h, &px, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: study: %s\n", err), 1;
        snprintf(pi->name, sizeof pi->name, "%.120s", base_name(paths[i]));
        char *dot = strrchr(pi->name, '.');
        if (dot)
            *dot = '\0';
    }
    if (w != 2 * h) {
        free(px);
        return fprintf(stderr, "qibl: study: %s: %d x %d is not a 2:1 lat-long probe\n", procedural ? pi->name : paths[i],
                       w, h), 1;
    }
    if (o->quick && w > 512) { /* --quick: the probe at half size */
        uint8_t *hp = half_rgbe(px, w, h);
        free(px);
        if (!hp)
            return fprintf(stderr, "qibl: study: out of memory\n"), 1;
        px = hp, w /= 2, h /= 2;
    }
    *w_out = w, *h_out = h, *px_out = px;
    return 0;
}

/* one probe's rows, overlay and plot; *count advances when it was studied. 0, or 1 to stop. */
static int study_one(const qtool_study_probe *p, int w, int h, const cfg *c, const qtool_study_opts *o, pinfo *info,
                     int *count)
{
    int q = *count;
    info[q].w = w, info[q].h = h;
    if (run_probe(q, p, c, &info[q], &ovs[q]) != 0)
        return 0;
    char path[1024], title[256];
    snprintf(path, sizeof path, "%s/overlay_%s.png", o->out_dir, info[q].name);
    snprintf(title, sizeof title, "%s (%d x %d): irradiance error against N", info[q].name, w, h);
    int bad = write_overlay(path, p, &ovs[q]);
    snprintf(path, sizeof path, "%s/plot_%s.svg", o->out_dir, info[q].name);
    if (bad || plot_n(path, title, q, q + 1) != 0)
        return 1;
    ++*count;
    return 0;
}

/* the speed case: the first probe at 4x (4096 x 2048 for a 1k probe) as row set MAXP */
static void study_x4(const uint8_t *px, int w, int h, const cfg *c, pinfo *info)
{
    uint8_t *big = qtool_probe_layout_rgbe_up4(px, w, h);
    qtool_study_probe pb;
    char err[512];
    if (big && qtool_study_probe_init(&pb, 4 * w, 4 * h, big, err, sizeof err) == 0) {
        snprintf(info[MAXP].name, sizeof info[MAXP].name, "%.100s_x4", info[0].name);
        info[MAXP].w = 4 * w, info[MAXP].h = 4 * h;
        if (run_probe(MAXP, &pb, c, &info[MAXP], &ovs[MAXP]) != 0)
            info[MAXP].w = 0;
        qtool_study_probe_free(&pb);
    }
    free(big);
}

/* every probe studied in turn; *count how many gave rows */
static int study_probes(const char *const *paths, int np, const cfg *c, const qtool_study_opts *o, pinfo *info,
                        int *count)
{
    int procedural = np == 0, total = procedural ? 2 : np;
    for (int i = 0; i < total; ++i) {
        int w, h;
        uint8_t *px = NULL;
        char err[512];
        if (load_probe(paths, i, procedural, o, &info[*count], &w, &h, &px) != 0)
            return 1;
        qtool_study_probe p;
        if (qtool_study_probe_init(&p, w, h, px, err, sizeof err) != 0) {
            free(px);
            return fprintf(stderr, "qibl: study: %s: %s\n", info[*count].name, err), 1;
        }
        int rc = 0;
        if (qtool_study_probe_lit(&p, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: study: %s: %s\n", info[*count].name, err);
            rc = 1;
        } else if (study_one(&p, w, h, c, o, info, count) != 0) {
            rc = 1;
        } else if (i == 0 && !o->quick && w * 4 <= 8192) { /* full runs only */
            study_x4(px, w, h, c, info);
        }
        qtool_study_probe_free(&p);
        free(px);
        if (rc)
            return rc;
    }
    return 0;
}

static int write_csv(const char *path, const pinfo *info)
{
    qtool_io_atomic at;
    if (open_out(&at, path) != 0)
        return 1;
    FILE *f = at.f;
    fprintf(f, "probe,width,height,method,n_requested,n,floats,mean_rel,max_rel,mean_norm,max_norm,ms,converged,iterations\n");
    for (int i = 0; i < nrows; ++i) {
        const row *r = &rows[i];
        const pinfo *pi = &info[r->probe];
        fprintf(f, "%s,%d,%d,%s,%d,%d,%d,%.6g,%.6g,%.6g,%.6g,%.3f,%s,%d\n", pi->name, pi->w, pi->h,
                qtool_study_method_name(r->method), r->nreq, r->n, r->numbers, r->e.mean_rel, r->e.max_rel, r->e.mean_norm,
                r->e.max_norm, r->ms, r->conv < 0 ? "" : r->conv ? "yes" : "no", r->iters);
    }
    return commit_out(&at) != 0;
}

/* a probe's error-against-time plot (rows of set q) */
static int plot_time_of(const char *dir, const pinfo *pi, int q)
{
    char path[1024], title[256];
    snprintf(path, sizeof path, "%s/time_%s.svg", dir, pi->name);
    snprintf(title, sizeof title, "%s (%d x %d): error against time", pi->name, pi->w, pi->h);
    return plot_time(path, title, q);
}

/* the average plot and the error-against-time plots of the first probe and its 4x case */
static int write_plots(const char *dir, const pinfo *info, int count)
{
    char path[1024], title[256];
    snprintf(path, sizeof path, "%s/plot_average.svg", dir);
    snprintf(title, sizeof title, "irradiance error against N, averaged over %d probe%s", count, count > 1 ? "s" : "");
    if (plot_n(path, title, -1, count) != 0 || plot_time_of(dir, &info[0], 0) != 0)
        return 1;
    return info[MAXP].w && plot_time_of(dir, &info[MAXP], MAXP) != 0;
}

/* the figures the findings and the RESULT lines quote */
typedef struct {
    double ratio16, ss_num, io_factor, rio;
    int count, nr16, halved, halved_cases, io_max_conv, ss_cnt, ss_wins, sunny, fac_cnt, nrio;
} findings;

static const double thresholds[3] = {0.10, 0.05, 0.02}; /* mean errors the tables and findings ask for */

/* the refit against median cut: mean-error ratio at 16, and how often it at least halves the error */
static void refit_figures(int count, findings *fd)
{
    for (int q = 0; q < count; ++q) {
        const row *a = find(q, QTOOL_STUDY_MEDIANCUT, 16), *b = find(q, QTOOL_STUDY_REFIT_MC, 16);
        if (a && b && a->e.mean_rel > 0)
            fd->ratio16 += b->e.mean_rel / a->e.mean_rel, ++fd->nr16;
        for (int n = 1; n <= 64; n *= 2) {
            a = find(q, QTOOL_STUDY_MEDIANCUT, n), b = find(q, QTOOL_STUDY_REFIT_MC, n);
            if (a && b)
                fd->halved_cases++, fd->halved += b->e.mean_rel <= 0.5 * a->e.mean_rel;
        }
    }
    /* where the refit lands: its mean error at 16 against irradiance optimisation's */
    for (int q = 0; q < count; ++q) {
        const row *a = find(q, QTOOL_STUDY_IRROPT, 16), *b = find(q, QTOOL_STUDY_REFIT_VM, 16);
        if (a && b && a->e.mean_rel > 0)
            fd->rio += b->e.mean_rel / a->e.mean_rel, ++fd->nrio;
    }
}

/* irradiance optimisation: the largest N converged on every probe, and N_mc / N_io at the
 * thresholds both reach (geometric mean) */
static void irropt_figures(int count, findings *fd)
{
    for (int j = 0; j < NLIST; ++j) {
        int all = 1, any = 0;
        for (int q = 0; q < count; ++q) {
            const row *r = find(q, QTOOL_STUDY_IRROPT, nlist[j]);
            if (r)
                any = 1, all &= r->conv == 1;
            else
                all = 0;
        }
        if (any && all)
            fd->io_max_conv = nlist[j];
    }
    double fac_sum = 0;
    for (int q = 0; q < count; ++q)
        for (int t = 0; t < 3; ++t) {
            int a, b, num;
            a = n_to_reach(q, QTOOL_STUDY_MEDIANCUT, thresholds[t], &num);
            b = n_to_reach(q, QTOOL_STUDY_IRROPT, thresholds[t], &num);
            if (a > 0 && b > 0)
                fac_sum += log((double)a / b), ++fd->fac_cnt;
        }
    fd->io_factor = fd->fac_cnt ? exp(fac_sum / fd->fac_cnt) : NAN;
}

/* sun plus sky: floats to reach 2 %, and on how many sunny probes no other method needs as few */
static void sunsky_figures(int count, const pinfo *info, findings *fd)
{
    for (int q = 0; q < count; ++q) {
        int num;
        if (n_to_reach(q, QTOOL_STUDY_SUNSKY, 0.02, &num) >= 0) {
            fd->ss_num += num, ++fd->ss_cnt;
            if (info[q].sunny) {
                int win = 1;
                for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m) {
                    int nm;
                    if (m == QTOOL_STUDY_SUNSKY)
                        continue;
                    if (n_to_reach(q, m, 0.02, &nm) >= 0 && nm <= num)
                        win = 0;
                }
                fd->ss_wins += win;
            }
        }
        fd->sunny += info[q].sunny;
    }
}

/* a table's "| probe | method ... |" header and its rule */
static void method_header(FILE *f)
{
    for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m)
        fprintf(f, " %s |", qtool_study_method_name(m));
    fprintf(f, "\n|---|");
    for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m)
        fprintf(f, "---|");
    fprintf(f, "\n");
}

static void summary_tables(FILE *f, int count, const pinfo *info)
{
    fprintf(f, "\n## Probes and the accuracy of the ground truth\n\n| probe | size | sunny | gt ms | max rel. diff. to the "
               "plain pixel sum | mean rel. diff. to the probe at half size |\n|---|---|---|---|---|---|\n");
    for (int q = 0; q <= MAXP; ++q) {
        if (q >= count && (q != MAXP || !info[MAXP].w))
            continue;
        fprintf(f, "| %s | %d x %d | %s | %.0f | %.1e | %.2e |\n", info[q].name, info[q].w, info[q].h,
                info[q].sunny ? "yes" : "no", info[q].gt_ms, info[q].gt_brute, info[q].gt_half);
    }
    fprintf(f, "\n## N needed for 10 %% / 5 %% / 2 %% mean error\n\n"
               "Lights for the light methods, coefficients for SH, lights besides the 9 SH coefficients for sun+sky "
               "(0 = SH9 alone); `-` = not reached within the N tried.\n\n| probe |");
    method_header(f);
    for (int q = 0; q < count; ++q) {
        fprintf(f, "| %s |", info[q].name);
        for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m) {
            fprintf(f, " ");
            for (int t = 0; t < 3; ++t) {
                int num, n = n_to_reach(q, m, thresholds[t], &num);
                if (reached(q, m, thresholds[t]))
                    fprintf(f, "%s%d", t ? "/" : "", n);
                else
                    fprintf(f, "%s-", t ? "/" : "");
            }
            fprintf(f, " |");
        }
        fprintf(f, "\n");
    }
    fprintf(f, "\n## Floats stored to reach 2 %% mean error (6 per light, 3 per SH coefficient)\n\n| probe |");
    method_header(f);
    for (int q = 0; q < count; ++q) {
        fprintf(f, "| %s%s |", info[q].name, info[q].sunny ? " (sunny)" : "");
        for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m) {
            int num;
            n_to_reach(q, m, 0.02, &num);
            if (reached(q, m, 0.02))
                fprintf(f, " %d |", num);
            else
                fprintf(f, " - |");
        }
        fprintf(f, "\n");
    }
    fprintf(f, "\n## Irradiance optimisation convergence\n\n| probe | N: iterations (no = not converged) |\n|---|---|\n");
    for (int q = 0; q < count; ++q) {
        fprintf(f, "| %s |", info[q].name);
        for (int j = 0; j < NLIST; ++j) {
            const row *r = find(q, QTOOL_STUDY_IRROPT, nlist[j]);
            if (r)
                fprintf(f, " %d: %d%s", nlist[j], r->iters, r->conv == 1 ? "" : " no");
        }
        fprintf(f, " |\n");
    }
}

static void summary_findings(FILE *f, const cfg *c, const findings *fd)
{
    fprintf(f, "\n## Findings\n\n");
    fprintf(f, "- Irradiance optimisation against median cut: median cut needs %.2fx the lights of irradiance "
               "optimisation for the same mean error (geometric mean over %d probe-threshold pairs both reach). "
               "Madsen & Laursen's \"2-3x fewer\" is %s here.\n",
            fd->io_factor, fd->fac_cnt,
            !(fd->io_factor == fd->io_factor) ? "not testable" : fd->io_factor >= 2 ? "reproduced" : "not reproduced");
    fprintf(f, "- Irradiance optimisation converged on every probe up to N = %d (largest N of the list with convergence "
               "on all probes; tried up to %d).\n", fd->io_max_conv, c->io_max);
    fprintf(f, "- The refit (median-cut directions, NNLS RGB): mean error %.3f of median cut's at N = 16 (averaged over "
               "probes); it at least halves median cut's mean error in %d of %d (probe, N <= 64) cases. The refit of "
               "varmin's directions reaches %.2fx irradiance optimisation's error at N = 16 (averaged), without an "
               "iteration that can fail.\n",
            fd->nr16 ? fd->ratio16 / fd->nr16 : NAN, fd->halved, fd->halved_cases, fd->nrio ? fd->rio / fd->nrio : NAN);
    fprintf(f, "- Sun plus sky reaches 2 %% on %d of %d probes, with %.1f floats on average; it needs fewer floats than "
               "every other method on %d of %d sunny probes.\n",
            fd->ss_cnt, fd->count, fd->ss_cnt ? fd->ss_num / fd->ss_cnt : NAN, fd->ss_wins, fd->sunny);
    fprintf(f, "\nPlots: plot_average.svg, plot_<probe>.svg, time_<probe>.svg; lights drawn in overlay_<probe>.png (panels "
               "top to bottom: median cut, adaptive, varmin, kmeans, irropt at N = %d, sun+sky with %d lights).\n",
            OVERLAY_N, SUNSKY_KMAX);
}

/* summary.md; *wall the study's wall time, as its last line says */
static int write_summary(const char *path, const cfg *c, const qtool_study_opts *o, const pinfo *info, int procedural,
                         const findings *fd, double t_all, double *wall)
{
    qtool_io_atomic at;
    if (open_out(&at, path) != 0)
        return 1;
    FILE *f = at.f;
    fprintf(f, "# Light-probe approximation study%s\n\n", o->quick ? " (--quick)" : "");
    fprintf(f, "Ground truth: Madsen & Laursen eq. 4 over every pixel at %d spherical-Fibonacci normals, per channel.\n"
               "Error: per-normal relative irradiance error |E - E_gt| / max(E_gt, mean E_gt / 10) (floored: "
               "near-black normals cannot blow it up), mean over normals and RGB "
               "(study.csv also has the max and the error normalised by the mean irradiance).\n",
            c->m);
    if (procedural)
        fprintf(f, "\n**No fixture probes were found: procedural skies from tools/study stand in.**\n");
    if (o->quick)
        fprintf(f, "\n--quick: probes at half size, %d normals, N <= %d, irradiance optimisation N <= %d.\n", c->m, c->nmax,
                c->io_max);
    fprintf(f, "\nSunny: the brightest 0.1 %% of the probe's pixels hold over a third of its energy (a sun, or lamps).\n");
    summary_tables(f, fd->count, info);
    summary_findings(f, c, fd);
    *wall = (now_ms() - t_all) / 1e3;
    fprintf(f, "\nWall time of the study: %.1f s.\n", *wall);
    return commit_out(&at) != 0;
}

static int run_all(const char *const *paths, int np, const qtool_study_opts *o)
{
    cfg c = {o->quick, o->threads > 0 ? o->threads : 2, o->quick ? 2000 : 20000, o->quick ? 64 : 256,
             o->quick ? 16 : 96, o->quick ? 400 : 600, 100, o->quick ? 8 : 20};
    if (mkdir_p(o->out_dir) != 0)
        return fprintf(stderr, "qibl: study: cannot create %s: %s\n", o->out_dir, strerror(errno)), 1;
    double t_all = now_ms();
    static pinfo info[MAXP + 1];
    int count = 0, procedural = np == 0;
    if (np > MAXP)
        return fprintf(stderr, "qibl: study: %d probes (at most %d)\n", np, MAXP), 1;
    if (procedural)
        printf("study: no probes given (../shared/fixtures/probes absent?): procedural skies from tools/study "
               "(a sunny and an overcast sky) stand in\n");
    if (study_probes(paths, np, &c, o, info, &count) != 0)
        return 1;
    if (count == 0)
        return fprintf(stderr, "qibl: study: no probe could be studied\n"), 1;
    char path[1024];
    snprintf(path, sizeof path, "%s/study.csv", o->out_dir);
    if (write_csv(path, info) != 0 || write_plots(o->out_dir, info, count) != 0)
        return 1;
    findings fd = {.count = count};
    refit_figures(count, &fd);
    irropt_figures(count, &fd);
    sunsky_figures(count, info, &fd);
    double wall = 0;
    snprintf(path, sizeof path, "%s/summary.md", o->out_dir);
    if (write_summary(path, &c, o, info, procedural, &fd, t_all, &wall) != 0)
        return 1;
    printf("study: %d probe%s, %d rows, wall %.1f s; wrote %s/study.csv, summary.md, plot_*.svg, time_*.svg, overlay_*.png\n",
           count, count > 1 ? "s" : "", nrows, wall, o->out_dir);
    printf("RESULT study.refit_over_mc_n16 %.4f\n", fd.nr16 ? fd.ratio16 / fd.nr16 : NAN);
    printf("RESULT study.io_converged_max_n %d\n", fd.io_max_conv);
    printf("RESULT study.sunsky_numbers_at_2pct %.1f\n", fd.ss_cnt ? fd.ss_num / fd.ss_cnt : NAN);
    printf("RESULT study.io_lights_factor_vs_mc %.2f\n", fd.io_factor);
    printf("RESULT study.wall_s %.1f\n", wall);
    return 0;
}

int qtool_study_run(const char *const *paths, int np, const qtool_study_opts *o)
{
    int rc = run_all(paths, np, o);
    for (int q = 0; q <= MAXP; ++q) {
        for (int m = 0; m < QTOOL_STUDY_METHOD_COUNT; ++m)
            free(ovs[q].ov[m]), ovs[q].ov[m] = NULL;
    }
    free(rows);
    rows = NULL, nrows = caprows = 0;
    return rc;
}
