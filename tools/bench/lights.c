/*
 * lights.c - `qibl bench lights`: light-probe sampling (qibl/lightprobe.h), speed and quality.
 *
 * Speed, on a real 1024 x 512 probe from ../shared/fixtures/probes (quarry_01_1k.hdr, else the first
 * .hdr there; QIBL_PROBE=path overrides; a procedural sun-and-sky probe when there is none) and on
 * the same probe upsampled to 4096 x 2048: milliseconds for the SAT build and for sampling, median
 * of several runs with a warm workspace (as a handheld reusing its buffer would have it), and the
 * ratio of build + 64 median-cut lights to one plain read pass over the probe's bytes (a byte sum,
 * compiled at the tools' -O3 and so vectorised) in the same run:
 * RESULT lights.sat64_over_read.
 *
 * Against a common median cut: thefranke's (dirtchamber; written again in C below, see fr_) on the
 * same probe bytes, in one interleaved loop with qibl's median cut 64 and the read pass, SAT and
 * cut stage timed apart: RESULT lights.mediancut64_over_thefranke (qibl's time / theirs, SAT
 * included), lights.cut64_over_thefranke and lights.sat_over_thefranke; the same with suffix _2 on
 * a second probe (the first in ../shared/fixtures/probes that is not the default).
 *
 * SIMD against scalar (RESULT lights.simd_speedup) is twin_lights.c, in qibl-bench: the shipped
 * qibl does not link the scalar twins.
 *
 * Quality, on every real probe: the irradiance error of each method's lights against the probe's
 * exact irradiance (tools/ref: sum over all pixels) over a Fibonacci sphere of normals, as the mean
 * and max of |E_lights - E_probe| / mean(E_probe) (Madsen & Laursen's measure), for the methods,
 * the split priorities and the two placements. The defaults of qibl_lightprobe_priority_t come from
 * this table.
 */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/hdr.h"
#include "io/probe_layout.h"
#include "bench/bench.h"
#include "qibl/lightprobe.h"
#include "ref/lightprobe_ref.h"

#define PROBE_DIR "../shared/fixtures/probes"
#define PROBE_DEFAULT "quarry_01_1k.hdr"

static volatile uint64_t sink;

/* the baseline: read every byte of the probe once */
static uint64_t read_pass(const uint8_t *p, size_t n)
{
    uint64_t s = 0;
    for (size_t i = 0; i < n; ++i)
        s += p[i];
    return s;
}

/* A procedural 1024 x 512 sun and sky as RGBE, for machines without the real probes: a sky
 * gradient, a ground, and a sun 3 x 2 pixels 2^20 times brighter than the sky. */
static uint8_t *procedural(int w, int h)
{
    uint8_t *px = malloc(4 * (size_t)w * (size_t)h);
    if (!px)
        return NULL;
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            int sky = v < h / 2;
            q[0] = (uint8_t)(sky ? 140 + v * 60 / h : 180);
            q[1] = (uint8_t)(sky ? 170 + v * 40 / h : 150);
            q[2] = (uint8_t)(sky ? 250 : 120 + (u * 13 + v * 7) % 40);
            q[3] = 128;
        }
    for (int v = h / 5; v < h / 5 + 2; ++v)
        for (int u = w / 3; u < w / 3 + 3; ++u) {
            uint8_t *q = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
            q[0] = q[1] = 255, q[2] = 230, q[3] = 148;
        }
    return px;
}

typedef struct {
    const uint8_t *px;
    int w, h;
    void *ws;
    size_t ws_size;
    qibl_lightprobe_light_t *L;
} job;

/* ms of build (method) and of sampling n lights with opts, medians of reps */
static int time_run(job *j, qibl_lightprobe_method_t build_for, const qibl_lightprobe_opts_t *o, uint32_t n, int reps,
                    double *t_build, double *t_lights, uint32_t *count)
{
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = j->px, img.width = (uint32_t)j->w, img.height = (uint32_t)j->h;
    double tb[31], tl[31];
    for (int r = 0; r < reps && r < 31; ++r) {
        qibl_lightprobe_t lp;
        qibl_lightprobe_result_t res;
        double t0 = qtool_bench_cpu_now();
        qibl_status_t st = qibl_lightprobe_build(&lp, &img, build_for, j->ws, j->ws_size);
        double t1 = qtool_bench_cpu_now();
        if (st == QIBL_OK)
            st = qibl_lightprobe_lights(&lp, o, j->L, n, &res);
        double t2 = qtool_bench_cpu_now();
        if (st != QIBL_OK) {
            fprintf(stderr, "qibl: bench lights: %s\n", qibl_status_str(st));
            return -1;
        }
        tb[r] = (t1 - t0) * 1e3, tl[r] = (t2 - t1) * 1e3;
        *count = res.count;
    }
    *t_build = qtool_bench_median(tb, reps);
    *t_lights = qtool_bench_median(tl, reps);
    return 0;
}

static double time_read(const uint8_t *px, size_t n, int reps)
{
    double t[31];
    for (int r = 0; r < reps && r < 31; ++r) {
        double t0 = qtool_bench_cpu_now();
        sink = read_pass(px, n);
        t[r] = (qtool_bench_cpu_now() - t0) * 1e3;
    }
    return qtool_bench_median(t, reps);
}

/* the read pass is memory-bound and its minimum swings with the machine's memory bandwidth (a
 * 15-rep minimum moved by a quarter between two runs back to back): more reps for a steadier one */
enum { SAT_REPS = 61 };

/* RESULT lights.sat64_over_read from interleaved minima: the read pass and build + median cut 64
 * take turns in one loop, each run twice in a row and the second run timed (its own warm caches),
 * so load swings hit both alike; the ratio of the two minima. Returns -1 on a core error. */
static double sat64_over_read_interleaved(job *j, int reps, double *min_mc, double *min_rd)
{
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = j->px, img.width = (uint32_t)j->w, img.height = (uint32_t)j->h;
    const qibl_lightprobe_opts_t mc = {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0};
    const size_t bytes = 4 * (size_t)j->w * (size_t)j->h;
    double mn[2] = {1e30, 1e30};
    for (int r = 0; r < reps; ++r)
        for (int i = 0; i < 4; ++i) {
            const int kind = (i / 2 + r) % 2; /* 0 read, 1 build + cut */
            double t0 = qtool_bench_cpu_now();
            if (kind == 0) {
                sink = read_pass(j->px, bytes);
            } else {
                qibl_lightprobe_t lp;
                qibl_lightprobe_result_t res;
                qibl_status_t st = qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, j->ws, j->ws_size);
                if (st == QIBL_OK)
                    st = qibl_lightprobe_lights(&lp, &mc, j->L, 64, &res);
                if (st != QIBL_OK)
                    return -1;
            }
            const double dt = (qtool_bench_cpu_now() - t0) * 1e3;
            if (i % 2 == 1 && dt < mn[kind])
                mn[kind] = dt;
        }
    *min_rd = mn[0], *min_mc = mn[1];
    return mn[1] / mn[0];
}

/* ---- the baseline: thefranke's median cut ------------------------------------------------------ */

/* Tobias Franke's median cut (github.com/thefranke/dirtchamber, src/dune/summed_area_tables.cpp and
 * .h), written again in C from its reading, for one comparison in one process. What it follows:
 * a float SAT of the luminance squared (0.2126 r + 0.7152 g + 0.0722 b, then v * v, as its
 * luminance() returns), each entry built through I(x, y) with its bounds checks; regions hold their
 * float sum; a region splits along its longer side in pixels (w > h, else h), by a linear search
 * from the first column (row) creating the left (top) part until 2 A.sum >= sum, each step a four-read
 * SAT sum; B starts at A's last column (row), as in its code; the recursion stops at depth n (2^n
 * regions for n levels) or where w < 2 or h < 2; each light is the centroid from the same two linear
 * searches, theta and phi from it, and a flux of the centroid pixel times the region's sum. Where it
 * differs: C instead of C++ (arrays the caller allocates once instead of std::vector pushes and a
 * resize per call, which only helps it), and the input is the probe's RGBE bytes (qibl's input)
 * decoded to float through a 256-entry exponent table where it reads 8-bit RGBA. Its sums are floats,
 * its directions unweighted by sin theta and its colours one pixel's: it is not what qibl computes,
 * only the work that a common median cut does. */
typedef struct {
    int x, y, w, h;
    float sum;
} fr_region;

typedef struct {
    int w, h;
    float *sat;     /* w x h, inclusive */
    float exp2[256]; /* 2^(E - 136), 0 for E = 0 */
} fr_sat;

typedef struct {
    float theta, phi, pos[2], flux[3];
} fr_light;

static float fr_I(const fr_sat *s, int x, int y)
{
    if (x < 0 || y < 0)
        return 0;
    return s->sat[(size_t)y * (size_t)s->w + (size_t)x];
}

static void fr_create_lum(fr_sat *s, const uint8_t *rgbe)
{
    for (int y = 0; y < s->h; ++y)
        for (int x = 0; x < s->w; ++x) {
            size_t i = (size_t)y * (size_t)s->w + (size_t)x;
            const float f = s->exp2[rgbe[4 * i + 3]];
            const float r = rgbe[4 * i] * f, g = rgbe[4 * i + 1] * f, b = rgbe[4 * i + 2] * f;
            float v = (float)(0.2126 * r + 0.7152 * g + 0.0722 * b);
            s->sat[i] = v * v + fr_I(s, x - 1, y) + fr_I(s, x, y - 1) - fr_I(s, x - 1, y - 1);
        }
}

static float fr_sum(const fr_sat *s, int ax, int ay, int bx, int by, int cx, int cy, int dx, int dy)
{
    return fr_I(s, cx, cy) + fr_I(s, ax, ay) - fr_I(s, bx, by) - fr_I(s, dx, dy);
}

static void fr_create(fr_region *r, const fr_sat *s, int x, int y, int w, int h, float init_sum)
{
    r->x = x, r->y = y, r->w = w, r->h = h, r->sum = init_sum;
    if (r->sum < 0)
        r->sum = fr_sum(s, x, y, x + (w - 1), y, x + (w - 1), y + (h - 1), x, y + (h - 1));
}

static void fr_split_w(const fr_region *r, const fr_sat *s, fr_region *a)
{
    *a = *r; /* a region 0 wide (B can be) leaves A unset in its code: here it is the region */
    for (int w = 1; w <= r->w; ++w) {
        fr_create(a, s, r->x, r->y, w, r->h, -1);
        if (a->sum * 2.f >= r->sum)
            break;
    }
}

static void fr_split_h(const fr_region *r, const fr_sat *s, fr_region *a)
{
    *a = *r; /* a region 0 wide (B can be) leaves A unset in its code: here it is the region */
    for (int h = 1; h <= r->h; ++h) {
        fr_create(a, s, r->x, r->y, r->w, h, -1);
        if (a->sum * 2.f >= r->sum)
            break;
    }
}

static void fr_split(const fr_region *r, const fr_sat *s, int n, fr_region *out, int *count)
{
    if (r->w < 2 || r->h < 2 || n == 0) {
        out[(*count)++] = *r;
        return;
    }
    fr_region a, b;
    if (r->w > r->h) {
        fr_split_w(r, s, &a);
        fr_create(&b, s, r->x + (a.w - 1), r->y, r->w - a.w, r->h, r->sum - a.sum);
    } else {
        fr_split_h(r, s, &a);
        fr_create(&b, s, r->x, r->y + (a.h - 1), r->w, r->h - a.h, r->sum - a.sum);
    }
    fr_split(&a, s, n - 1, out, count);
    fr_split(&b, s, n - 1, out, count);
}

/* its cut stage: the regions (depth levels), then one light per region; returns the count */
static int fr_lights(const fr_sat *s, const uint8_t *rgbe, int levels, fr_region *reg, fr_light *L)
{
    int nr = 0, nl = 0;
    fr_region all;
    fr_create(&all, s, 0, 0, s->w, s->h, -1);
    fr_split(&all, s, levels, reg, &nr);
    for (int i = 0; i < nr; ++i) {
        fr_region a;
        fr_light l;
        fr_split_w(&reg[i], s, &a);
        l.pos[0] = (float)(a.x + (a.w - 1));
        fr_split_h(&reg[i], s, &a);
        l.pos[1] = (float)(a.y + (a.h - 1));
        l.theta = (float)(2.0 * acos(sqrt(1.0 - l.pos[1])));
        l.phi = (float)(l.pos[0] * 3.14159265358979);
        if (l.pos[1] < 0 || l.pos[0] < 0)
            continue;
        size_t ci = ((size_t)l.pos[1] * (size_t)s->w + (size_t)l.pos[0]) * 4;
        const float f = s->exp2[rgbe[ci + 3]];
        for (int c = 0; c < 3; ++c)
            l.flux[c] = rgbe[ci + (size_t)c] * f * reg[i].sum;
        L[nl++] = l;
    }
    return nl;
}

/* qibl's median cut 64 (SAT included) against fr_ (same probe bytes), the plain read and qibl's
 * low-memory path (qibl_lightprobe_workspace_min: marginals instead of the SAT, the same lights),
 * in one interleaved loop: each rep runs the four in a rotating order, each twice in a row with the
 * second run timed (its own warm caches), in thread CPU time. Prints minima and paired medians;
 * RESULT lines (suffix sfx) from the minima. 0, or 1 after a message. */
static int versus_thefranke(int quick, const char *name, const uint8_t *px, int w, int h, const char *sfx)
{
    enum { REPS = 31 };
    const int reps = quick ? 5 : 21;
    const size_t bytes = 4 * (size_t)w * (size_t)h;
    const size_t wsz = qibl_lightprobe_workspace_size((uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_MEDIANCUT);
    const size_t wmin = qibl_lightprobe_workspace_min((uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = malloc(wsz);
    qibl_lightprobe_light_t *L = malloc(sizeof *L * 64), *LM = malloc(sizeof *LM * 64);
    fr_sat s = {w, h, malloc(sizeof(float) * (size_t)w * (size_t)h), {0}};
    fr_region *reg = malloc(sizeof *reg * 64);
    fr_light *fl = malloc(sizeof *fl * 64);
    int rc = 0;
    if (!ws || !L || !LM || !s.sat || !reg || !fl) {
        rc = 1;
        fprintf(stderr, "qibl: bench lights: out of memory\n");
        goto out;
    }
    memset(ws, 0, wsz);
    memset(s.sat, 0, sizeof(float) * (size_t)w * (size_t)h);
    for (int e = 1; e < 256; ++e)
        s.exp2[e] = (float)ldexp(1.0, e - 136);
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = px, img.width = (uint32_t)w, img.height = (uint32_t)h;
    const qibl_lightprobe_opts_t mc = {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0};
    /* [kind][rep]: kind 0 read, 1 qibl total, 2 theirs total, 3 qibl SAT, 4 qibl cut, 5 theirs SAT,
     * 6 theirs cut, 7 qibl low-memory total, 8 its build (the total), 9 its cut */
    double t[10][REPS];
    uint32_t nq = 0, nm = 0;
    int nf = 0;
    for (int r = 0; r < reps; ++r)
        for (int i = 0; i < 8; ++i) {
            const int kind = (i / 2 + r) % 4;
            double t0 = qtool_bench_cpu_now(), t1 = t0;
            if (kind == 0) {
                sink = read_pass(px, bytes);
            } else if (kind == 1 || kind == 3) {
                qibl_lightprobe_t lp;
                qibl_lightprobe_result_t res;
                qibl_status_t st = qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws, kind == 1 ? wsz : wmin);
                t1 = qtool_bench_cpu_now();
                if (st == QIBL_OK)
                    st = qibl_lightprobe_lights(&lp, &mc, kind == 1 ? L : LM, 64, &res);
                if (st != QIBL_OK) {
                    rc = 1;
                    fprintf(stderr, "qibl: bench lights: %s\n", qibl_status_str(st));
                    goto out;
                }
                *(kind == 1 ? &nq : &nm) = res.count;
            } else {
                fr_create_lum(&s, px);
                t1 = qtool_bench_cpu_now();
                nf = fr_lights(&s, px, 6, reg, fl);
                sink += (uint64_t)nf;
            }
            const double t2 = qtool_bench_cpu_now();
            if (i % 2 == 1) {
                const int tot = kind == 3 ? 7 : kind, part = kind == 3 ? 8 : 2 * kind + 1;
                t[tot][r] = (t2 - t0) * 1e3;
                if (kind > 0)
                    t[part][r] = (t1 - t0) * 1e3, t[part + 1][r] = (t2 - t1) * 1e3;
            }
        }
    if (nm != nq || memcmp(L, LM, sizeof *L * nq) != 0) {
        rc = 1;
        fprintf(stderr, "qibl: bench lights: the low-memory path's lights differ from the SAT path's\n");
        goto out;
    }
    double mn[10], md[10];
    for (int k = 0; k < 10; ++k) {
        double c[REPS];
        memcpy(c, t[k], sizeof c);
        mn[k] = qtool_bench_min(c, reps);
        md[k] = qtool_bench_median(c, reps);
    }
    const double pr_total = qtool_bench_paired_ratio(t[1], t[2], reps), pr_cut = qtool_bench_paired_ratio(t[4], t[6], reps),
                 pr_sat = qtool_bench_paired_ratio(t[3], t[5], reps), pr_low = qtool_bench_paired_ratio(t[7], t[1], reps);
    printf("\n== bench lights: qibl's median cut 64 against thefranke's (dirtchamber, float SAT, in C here): %s, "
           "%d x %d, %d interleaved reps, thread CPU ms\n", name, w, h, reps);
    printf("%-40s %7s %9s %9s %9s %9s %9s %9s\n", "run", "lights", "SAT min", "SAT med", "cut min", "cut med",
           "total min", "total med");
    printf("%-40s %7s %9s %9s %9s %9s %9.3f %9.3f\n", "plain read pass over the probe bytes", "-", "-", "-", "-", "-",
           mn[0], md[0]);
    printf("%-40s %7u %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f\n", "qibl median cut 64 (exact, coloured)", nq, mn[3], md[3],
           mn[4], md[4], mn[1], md[1]);
    printf("%-40s %7d %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f\n", "thefranke median cut, 6 levels", nf, mn[5], md[5],
           mn[6], md[6], mn[2], md[2]);
    printf("%-40s %7u %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f\n", "qibl median cut 64, low-memory path", nm, mn[8], md[8],
           mn[9], md[9], mn[7], md[7]);
    printf("qibl / theirs: total %.3f (minima), %.3f (paired medians); SAT %.3f, %.3f; cut %.3f, %.3f\n",
           mn[1] / mn[2], pr_total, mn[3] / mn[5], pr_sat, mn[4] / mn[6], pr_cut);
    printf("RESULT lights.mediancut64_over_thefranke%s %.3f\n", sfx, mn[1] / mn[2]);
    printf("RESULT lights.cut64_over_thefranke%s %.3f\n", sfx, mn[4] / mn[6]);
    printf("RESULT lights.sat_over_thefranke%s %.3f\n", sfx, mn[3] / mn[5]);
    printf("low-memory path (%zu B of workspace, not %zu) / SAT path: total %.3f (minima), %.3f (paired medians)\n",
           wmin, wsz, mn[7] / mn[1], pr_low);
    printf("RESULT lights.lowmem64_over_sat%s %.3f\n", sfx, mn[7] / mn[1]);
out:
    free(ws), free(L), free(LM), free(s.sat), free(reg), free(fl);
    return rc;
}

static int speed(int quick, const char *name, const uint8_t *px, int w, int h)
{
    const int reps = quick ? 3 : 15;
    size_t bytes = 4 * (size_t)w * (size_t)h;
    job j = {px, w, h, NULL, 0, NULL};
    j.ws_size = qibl_lightprobe_workspace_size((uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_VARMIN);
    j.ws = malloc(j.ws_size);
    j.L = malloc(sizeof *j.L * 256);
    if (!j.ws || !j.L) {
        free(j.ws), free(j.L);
        return fprintf(stderr, "qibl: bench lights: out of memory\n"), 1;
    }
    /* touch the workspace once: timings are for a warm buffer */
    memset(j.ws, 0, j.ws_size);
    qibl_lightprobe_opts_t mc = {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0}, ad = {QIBL_LIGHTPROBE_ADAPTIVE, 0, 0},
                           vm = {QIBL_LIGHTPROBE_VARMIN, 0, 0};
    double rd = time_read(px, bytes, reps);
    double b64, l64, b256, l256, ba, la, bv, lv;
    uint32_t n64, n256, na, nv;
    if (time_run(&j, QIBL_LIGHTPROBE_MEDIANCUT, &mc, 64, reps, &b64, &l64, &n64) ||
        time_run(&j, QIBL_LIGHTPROBE_MEDIANCUT, &mc, 256, reps, &b256, &l256, &n256) ||
        time_run(&j, QIBL_LIGHTPROBE_MEDIANCUT, &ad, 64, reps, &ba, &la, &na) ||
        time_run(&j, QIBL_LIGHTPROBE_VARMIN, &vm, 64, quick ? 1 : 5, &bv, &lv, &nv)) {
        free(j.ws), free(j.L);
        return 1;
    }
    double rd2 = time_read(px, bytes, reps); /* again after: the ratio uses the faster of the two */
    if (rd2 < rd)
        rd = rd2;
    printf("== bench lights: %s, %d x %d (%.1f MB of RGBE), median of %d runs, warm workspace\n", name, w, h,
           bytes / 1e6, reps);
    printf("%-44s %8s %9s %9s %9s %8s\n", "run", "lights", "SAT ms", "cut ms", "total ms", "x read");
    printf("%-44s %8s %9s %9s %9.3f %8.2f\n", "plain read pass over the probe bytes", "-", "-", "-", rd, 1.0);
    printf("%-44s %8u %9.3f %9.3f %9.3f %8.2f\n", "median cut 64 (SAT included)", n64, b64, l64, b64 + l64,
           (b64 + l64) / rd);
    printf("%-44s %8u %9.3f %9.3f %9.3f %8.2f\n", "median cut 256", n256, b256, l256, b256 + l256, (b256 + l256) / rd);
    printf("%-44s %8u %9.3f %9.3f %9.3f %8.2f\n", "adaptive median cut 64", na, ba, la, ba + la, (ba + la) / rd);
    printf("%-44s %8u %9.3f %9.3f %9.3f %8.2f\n", "variance minimisation 64 (5 moment SATs more)", nv, bv, lv,
           bv + lv, (bv + lv) / rd);
    const char *tag = w >= 4096 ? "4k_" : "";
    double imc = 0, ird = 0;
    const double ratio = sat64_over_read_interleaved(&j, quick ? 3 : SAT_REPS, &imc, &ird);
    if (ratio < 0) {
        free(j.ws), free(j.L);
        return fprintf(stderr, "qibl: bench lights: median cut failed\n"), 1;
    }
    printf("ratio from minima of %d interleaved reps (each run twice, the second timed): median cut 64 %.3f ms, "
           "read %.3f ms\n", quick ? 3 : SAT_REPS, imc, ird);
    printf("RESULT lights.%ssat64_over_read %.2f\n", tag, ratio);
    printf("RESULT lights.%smediancut64_ms %.3f\n", tag, b64 + l64);
    printf("RESULT lights.%smediancut256_ms %.3f\n", tag, b256 + l256);
    printf("RESULT lights.%sadaptive64_ms %.3f\n", tag, ba + la);
    printf("RESULT lights.%svarmin64_ms %.3f\n", tag, bv + lv);
    free(j.ws), free(j.L);
    return 0;
}


/* ---- quality -------------------------------------------------------------------------------- */

typedef struct {
    const char *label;
    qibl_lightprobe_opts_t o;
    uint32_t n;
} config;

static const config configs[] = {
    {"median cut 64", {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0}, 64},
    {"median cut 64, geometric centres", {QIBL_LIGHTPROBE_MEDIANCUT, 0, QIBL_LIGHTPROBE_PLACE_CENTRE}, 64},
    {"adaptive 64, priority energy", {QIBL_LIGHTPROBE_ADAPTIVE, QIBL_LIGHTPROBE_PRIORITY_ENERGY, 0}, 64},
    {"adaptive 64, priority energy x size", {QIBL_LIGHTPROBE_ADAPTIVE, QIBL_LIGHTPROBE_PRIORITY_ENERGY_SIZE, 0}, 64},
    {"adaptive 64, priority variance", {QIBL_LIGHTPROBE_ADAPTIVE, QIBL_LIGHTPROBE_PRIORITY_VARIANCE, 0}, 64},
    {"varmin 64, levels (Viriyothai-Debevec)", {QIBL_LIGHTPROBE_VARMIN, QIBL_LIGHTPROBE_PRIORITY_LEVELS, 0}, 64},
    {"varmin 64, priority energy", {QIBL_LIGHTPROBE_VARMIN, QIBL_LIGHTPROBE_PRIORITY_ENERGY, 0}, 64},
    {"varmin 64, priority energy x size", {QIBL_LIGHTPROBE_VARMIN, QIBL_LIGHTPROBE_PRIORITY_ENERGY_SIZE, 0}, 64},
    {"varmin 64, priority variance", {QIBL_LIGHTPROBE_VARMIN, QIBL_LIGHTPROBE_PRIORITY_VARIANCE, 0}, 64},
    {"varmin 64, geometric centres", {QIBL_LIGHTPROBE_VARMIN, 0, QIBL_LIGHTPROBE_PLACE_CENTRE}, 64},
    {"median cut 16", {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0}, 16},
    {"adaptive 16 (default priority)", {QIBL_LIGHTPROBE_ADAPTIVE, 0, 0}, 16},
    {"varmin 16 (default priority)", {QIBL_LIGHTPROBE_VARMIN, 0, 0}, 16},
    {"median cut 256", {QIBL_LIGHTPROBE_MEDIANCUT, 0, 0}, 256},
    {"adaptive 256 (default priority)", {QIBL_LIGHTPROBE_ADAPTIVE, 0, 0}, 256},
    {"varmin 256 (default priority)", {QIBL_LIGHTPROBE_VARMIN, 0, 0}, 256},
};
#define NCONF (int)(sizeof configs / sizeof configs[0])

static int quality(int quick, char names[][256], int np)
{
    const int nn = quick ? 256 : 1024;
    if (quick && np > 2)
        np = 2;
    double (*nrm)[3] = malloc(sizeof *nrm * (size_t)nn), *E = malloc(sizeof *E * (size_t)nn);
    double me[NCONF], mx[NCONF], sum_me[NCONF] = {0}, sum_mx[NCONF] = {0};
    qibl_lightprobe_light_t *L = malloc(sizeof *L * 256);
    qtool_ref_light *R = malloc(sizeof *R * 256);
    if (!nrm || !E || !L || !R) {
        free(nrm), free(E), free(L), free(R);
        return fprintf(stderr, "qibl: bench lights: out of memory\n"), 1;
    }
    qtool_ref_sphere_dirs(nn, nrm);
    printf("\n== bench lights: irradiance error against the full probe over %d normals, mean %% (max %%) of the "
           "mean irradiance\n", nn);
    printf("%-26s", "probe");
    for (int c = 0; c < NCONF; ++c) {
        char tag[16]; /* room for any int: gcc's range analysis under ASan cannot see c < NCONF */
        snprintf(tag, sizeof tag, "c%d", c);
        printf(" %7s", tag);
    }
    printf("\n");
    for (int i = 0; i < np; ++i) {
        char path[600], err[512];
        snprintf(path, sizeof path, "%s/%.250s", PROBE_DIR, names[i]);
        int w, h;
        uint8_t *px;
        if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            continue;
        }
        double *d = malloc(sizeof *d * 3 * (size_t)w * (size_t)h);
        size_t wsz = qibl_lightprobe_workspace_size((uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_VARMIN);
        void *ws = malloc(wsz);
        qtool_ref_probe rp;
        if (!d || !ws) {
            free(d), free(ws), free(px);
            continue;
        }
        for (size_t k = 0; k < (size_t)w * (size_t)h; ++k)
            for (int c = 0; c < 3; ++c)
                d[3 * k + (size_t)c] = px[4 * k + 3] ? ldexp(px[4 * k + (size_t)c], px[4 * k + 3] - 136) : 0.0;
        if (qtool_ref_probe_init(&rp, w, h, d) != 0) {
            free(d), free(ws), free(px);
            continue;
        }
        qtool_ref_probe_irradiance(&rp, nn, (const double (*)[3])nrm, E, 4);
        qibl_lightprobe_image_t img;
        memset(&img, 0, sizeof img);
        img.pixels = px, img.width = (uint32_t)w, img.height = (uint32_t)h;
        qibl_lightprobe_t lp;
        if (qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_VARMIN, ws, wsz) != QIBL_OK)
            continue;
        char shortname[27];
        snprintf(shortname, sizeof shortname, "%.26s", names[i]);
        printf("%-26s", shortname);
        for (int c = 0; c < NCONF; ++c) {
            qibl_lightprobe_result_t res;
            if (qibl_lightprobe_lights(&lp, &configs[c].o, L, configs[c].n, &res) != QIBL_OK) {
                me[c] = mx[c] = NAN;
                continue;
            }
            for (uint32_t k = 0; k < res.count; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    R[k].dir[ch] = L[k].dir[ch] / 1073741824.0;
                    R[k].rgb[ch] = ldexp(L[k].rgb[ch], res.rgb_exp);
                }
            qtool_ref_irradiance_error(R, (int)res.count, nn, (const double (*)[3])nrm, E, &me[c], &mx[c]);
            sum_me[c] += me[c], sum_mx[c] += mx[c];
            printf(" %7.3f", 100 * me[c]);
        }
        printf("\n");
        qtool_ref_probe_free(&rp);
        free(d), free(ws), free(px);
    }
    printf("\n%-4s %-42s %14s %14s\n", "col", "configuration", "mean error %", "max error %");
    for (int c = 0; c < NCONF; ++c)
        printf("c%-3d %-42s %14.3f %14.3f\n", c, configs[c].label, 100 * sum_me[c] / np, 100 * sum_mx[c] / np);
    printf("(averages over %d probes)\n", np);
    printf("RESULT lights.err_mean_mediancut64_pct %.3f\n", 100 * sum_me[0] / np);
    printf("RESULT lights.err_mean_adaptive64_pct %.3f\n", 100 * sum_me[3] / np);
    printf("RESULT lights.err_mean_varmin64_pct %.3f\n", 100 * sum_me[8] / np);
    printf("RESULT lights.err_max_mediancut64_pct %.3f\n", 100 * sum_mx[0] / np);
    printf("RESULT lights.err_max_varmin64_pct %.3f\n", 100 * sum_mx[8] / np);
    free(nrm), free(E), free(L), free(R);
    return 0;
}

static int list_probes(char names[][256], int max)
{
    DIR *dir = opendir(PROBE_DIR);
    int n = 0;
    if (!dir)
        return 0;
    struct dirent *de;
    while ((de = readdir(dir)) != NULL && n < max) {
        size_t l = strlen(de->d_name);
        if (l > 4 && l < 250 && strcmp(de->d_name + l - 4, ".hdr") == 0)
            snprintf(names[n++], 256, "%.250s", de->d_name);
    }
    closedir(dir);
    qsort(names, (size_t)n, sizeof names[0], (int (*)(const void *, const void *))strcmp);
    return n;
}

static int load_probe(uint8_t **px, int *w, int *h, char *label, size_t label_len)
{
    static char names[64][256];
    const int np = list_probes(names, 64);
    const char *env = getenv("QIBL_PROBE");
    char path[600], err[512];
    *w = 1024, *h = 512, *px = NULL;
    if (env && *env) {
        snprintf(path, sizeof path, "%.590s", env);
    } else if (np > 0) {
        int pick = 0;
        for (int i = 0; i < np; ++i)
            if (strcmp(names[i], PROBE_DEFAULT) == 0)
                pick = i;
        snprintf(path, sizeof path, "%s/%.250s", PROBE_DIR, names[pick]);
    } else {
        path[0] = '\0';
    }
    if (path[0]) {
        if (qtool_hdr_read_rgbe(path, w, h, px, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: %s\n", err), 1;
        snprintf(label, label_len, "%.590s", path);
        return 0;
    }
    *px = procedural(*w, *h);
    snprintf(label, label_len, "procedural sun and sky (no probes in %s)", PROBE_DIR);
    if (!*px)
        return fprintf(stderr, "qibl: bench lights: out of memory\n"), 1;
    return 0;
}

int qtool_bench_lights_on_probe(int quick, qtool_bench_probe_run run)
{
    char label[600];
    int w, h;
    uint8_t *px;
    int rc = load_probe(&px, &w, &h, label, sizeof label);
    if (rc == 0)
        rc = run(quick, label, px, w, h);
    free(px);
    return rc;
}

/* bench lights on its probe: speed, against thefranke there and on a second probe, and upsampled 4x */
static int on_probe(int quick, const char *label, const uint8_t *px, int w, int h)
{
    static char names[64][256];
    const int np = list_probes(names, 64);
    int rc = speed(quick, label, px, w, h);
    if (rc == 0)
        rc = versus_thefranke(quick, label, px, w, h, "");
    if (rc == 0 && np > 0) {
        /* a second probe for the same figure: the first listed one that is not the default */
        int pick = strcmp(names[0], PROBE_DEFAULT) == 0 && np > 1 ? 1 : 0;
        char path[600], err[512];
        int w2, h2;
        uint8_t *px2;
        snprintf(path, sizeof path, "%s/%.250s", PROBE_DIR, names[pick]);
        if (qtool_hdr_read_rgbe(path, &w2, &h2, &px2, err, sizeof err) != 0)
            return fprintf(stderr, "qibl: %s\n", err), 1;
        rc = versus_thefranke(quick, path, px2, w2, h2, "_2");
        free(px2);
    }
    if (rc == 0) {
        /* the 4096 x 2048 case with real content */
        uint8_t *big = qtool_probe_layout_rgbe_up4(px, w, h);
        if (big) {
            char l4[700];
            snprintf(l4, sizeof l4, "%s upsampled 4x", label);
            printf("\n");
            rc = speed(quick, l4, big, 4 * w, 4 * h);
            free(big);
        }
    }
    return rc;
}

int qtool_bench_lights(int quick)
{
    static char names[64][256];
    const int np = list_probes(names, 64);
    int rc = qtool_bench_lights_on_probe(quick, on_probe);
    if (rc == 0 && np > 0)
        rc = quality(quick, names, np);
    else if (np == 0)
        printf("SKIP bench lights quality: no probes in %s\n", PROBE_DIR);
    return rc;
}
