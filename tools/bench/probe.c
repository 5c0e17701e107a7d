/*
 * probe.c - `qibl bench probe`: SH projection of a 1024 x 512 probe (row by row, integer)
 * against one plain read pass over the same bytes (64-bit words, in cache: the goal's baseline,
 * RESULT probe.project_over_read) and against loading the .hdr file (open, read, RLE decode: what a
 * tool pays to get the probe, RESULT probe.project_over_hdr_load), min and median of interleaved
 * repetitions, ns per pixel; projection error against the double reference on every fixture probe (or an
 * integer-made one when ../shared is absent); rotation error against the double reference; what
 * Hann and Lanczos windows do to the ringing of a sun probe's irradiance.
 * RESULT probe.project_over_read, probe.project_over_hdr_load, probe.project_ns_per_px,
 * probe.sh_max_rel_err, probe.rotate_max_err.
 */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/hdr.h"
#include "bench/bench.h"
#include "qtool.h"
#include "qibl/probe.h"
#include "ref/probe_ref.h"
#include "ref/sh_ref.h"


static volatile uint64_t bp_sink;

static const char *bp_dir(void)
{
    const char *d = getenv("QIBL_PROBE_DIR");
    return d && *d ? d : "../shared/fixtures/probes";
}

/* The baseline the goal names: the same Riemann sum as a plain separable double loop (per row, the
 * Fourier sums of the decoded pixels against a cos / sin table, then times Y_l|m|(theta) sin theta),
 * over the RGBE bytes, its tables built inside the call as qibl's begin builds its own; only the
 * sums the bands need (2 bands - 1 per channel), so it too gets cheaper with fewer bands. */
static void separable_double(const uint8_t *px, int w, int h, int bands, double *trig, double out[3][25])
{
    const int nk = 2 * bands - 1;
    double e2[256];
    for (int e = 0; e < 256; ++e)
        e2[e] = e ? ldexp(1.0, e - 136) : 0.0;
    for (int u = 0; u < w; ++u) {
        double ph = (u + 0.5) * 2.0 * QTOOL_PI / w;
        trig[9 * u] = 1.0;
        for (int m = 1; m <= 4; ++m)
            trig[9 * u + 2 * m - 1] = cos(m * ph), trig[9 * u + 2 * m] = sin(m * ph);
    }
    memset(out, 0, 3 * 25 * sizeof out[0][0]);
    for (int v = 0; v < h; ++v) {
        double t = (v + 0.5) * QTOOL_PI / h, dw = (2.0 * QTOOL_PI / w) * (QTOOL_PI / h) * sin(t), y[25], s[3][9] = {{0}};
        qtool_ref_sh_eval(sin(t), 0.0, cos(t), bands, y);
        const uint8_t *row = px + 4 * (size_t)v * (size_t)w;
        for (int u = 0; u < w; ++u) {
            const double sc = e2[row[4 * u + 3]], r = row[4 * u] * sc, g = row[4 * u + 1] * sc, b = row[4 * u + 2] * sc;
            for (int k = 0; k < nk; ++k)
                s[0][k] += r * trig[9 * u + k], s[1][k] += g * trig[9 * u + k], s[2][k] += b * trig[9 * u + k];
        }
        for (int l = 0; l < bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int am = m < 0 ? -m : m, k = m == 0 ? 0 : m > 0 ? 2 * m - 1 : 2 * am;
                for (int c = 0; c < 3; ++c)
                    out[c][l * l + l + m] += s[c][k] * y[l * l + l + am] * dw;
            }
    }
}

static uint8_t *int_probe(int w, int h)
{
    uint8_t *px = malloc(4 * (size_t)w * (size_t)h);
    if (!px)
        return NULL;
    uint64_t s = 99;
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        s = s * 6364136223846793005u + 1442695040888963407u;
        px[4 * i] = (uint8_t)(s >> 24), px[4 * i + 1] = (uint8_t)(s >> 32) | 64u, px[4 * i + 2] = (uint8_t)(s >> 40);
        px[4 * i + 3] = (uint8_t)(120 + (s >> 60));
    }
    px[4 * (100 * (size_t)w + 300) + 3] = 150; /* a sun */
    return px;
}

static double *to_double(const uint8_t *px, int w, int h)
{
    double *d = malloc(sizeof *d * 3 * (size_t)w * (size_t)h);
    if (!d)
        return NULL;
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i)
        for (int c = 0; c < 3; ++c)
            d[3 * i + (size_t)c] = px[4 * i + 3] ? ldexp(px[4 * i + (size_t)c], px[4 * i + 3] - 136) : 0.0;
    return d;
}

/* max |c - ref| / max |ref| over the 75 coefficients */
static double sh_rel_err(const uint8_t *px, int w, int h, void *ws, size_t n)
{
    qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
    qibl_probe_coeffs_t c;
    if (qibl_probe_sh_project(&img, 5, NULL, ws, n, &c) != QIBL_OK)
        return -1.0;
    double *d = to_double(px, w, h), ref[3][25], e = 0.0, mx = 0.0;
    if (!d)
        return -1.0;
    qtool_ref_probe_sh(w, h, d, 5, ref);
    free(d);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            e = fmax(e, fabs(ldexp(c.c[ch][i], c.exp) - ref[ch][i])), mx = fmax(mx, fabs(ref[ch][i]));
    return e / mx;
}

/* ringing of the irradiance sum_lm E_lm Y_lm(n) over 4096 normals: min and max, and the mean
 * relative error against the probe's true irradiance at 256 normals (double, every pixel) */
static void ringing(const uint8_t *px, int w, int h, void *ws, size_t n, const char *name)
{
    double *d = to_double(px, w, h);
    if (!d)
        return;
    enum { NT = 256 };
    double truth[NT], nrm[NT][3];
    for (int k = 0; k < NT; ++k) { /* spherical Fibonacci normals */
        double z = 1.0 - (2.0 * k + 1.0) / NT, r = sqrt(1.0 - z * z), p = k * QTOOL_PI * (3.0 - sqrt(5.0));
        nrm[k][0] = r * cos(p), nrm[k][1] = r * sin(p), nrm[k][2] = z, truth[k] = 0.0;
    }
    for (int v = 0; v < h; ++v) {
        double t = (v + 0.5) * QTOOL_PI / h, dw = (2.0 * QTOOL_PI / w) * (QTOOL_PI / h) * sin(t);
        for (int u = 0; u < w; ++u) {
            const double *q = d + 3 * ((size_t)v * (size_t)w + (size_t)u);
            double L = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
            if (L == 0.0)
                continue;
            double ph = (u + 0.5) * 2.0 * QTOOL_PI / w, dir[3] = {sin(t) * cos(ph), sin(t) * sin(ph), cos(t)};
            for (int k = 0; k < NT; ++k) {
                double c = dir[0] * nrm[k][0] + dir[1] * nrm[k][1] + dir[2] * nrm[k][2];
                if (c > 0)
                    truth[k] += L * c * dw;
            }
        }
    }
    free(d);
    printf("windowing on %s (irradiance of the luminance, %dx%d):\n", name, w, h);
    printf("  %-8s %5s %14s %14s %12s %14s\n", "window", "bands", "min E", "max E", "min/max", "mean |err|");
    static const char *wn[3] = {"none", "hann", "lanczos"};
    for (int bands = 3; bands <= 5; bands += 2)
        for (int win = 0; win < 3; ++win) {
            qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
            qibl_probe_sh_opts_t o = {1, (qibl_probe_window_t)win, 0};
            qibl_probe_coeffs_t c;
            if (qibl_probe_sh_project(&img, bands, &o, ws, n, &c) != QIBL_OK)
                return;
            double lum[25];
            for (int i = 0; i < bands * bands; ++i)
                lum[i] = ldexp(0.2126 * c.c[0][i] + 0.7152 * c.c[1][i] + 0.0722 * c.c[2][i], c.exp);
            double mn = 1e300, mx = -1e300, err = 0.0, tmean = 0.0;
            for (int k = 0; k < 4096; ++k) {
                double z = 1.0 - (2.0 * k + 1.0) / 4096, r = sqrt(1.0 - z * z), p = k * QTOOL_PI * (3.0 - sqrt(5.0)), y[25];
                qtool_ref_sh_eval(r * cos(p), r * sin(p), z, bands, y);
                double e = 0.0;
                for (int i = 0; i < bands * bands; ++i)
                    e += lum[i] * y[i];
                mn = fmin(mn, e), mx = fmax(mx, e);
            }
            for (int k = 0; k < NT; ++k) {
                double y[25], e = 0.0;
                qtool_ref_sh_eval(nrm[k][0], nrm[k][1], nrm[k][2], bands, y);
                for (int i = 0; i < bands * bands; ++i)
                    e += lum[i] * y[i];
                err += fabs(e - truth[k]), tmean += truth[k];
            }
            printf("  %-8s %5d %14.6g %14.6g %12.4f %13.2f%%\n", wn[win], bands, mn, mx, mn / mx, 100.0 * err / tmean);
            if (bands == 5 && strstr(name, "sun probe"))
                printf("RESULT probe.sun_ringing_min_over_max.%s %.4f\n", wn[win], mn / mx);
        }
}

static double rotate_err(void)
{
    double worst = 0.0;
    uint64_t s = 31;
    for (int k = 0; k < 200; ++k) {
        double q[4], n = 0.0;
        for (int i = 0; i < 4; ++i) {
            s = s * 6364136223846793005u + 1442695040888963407u;
            q[i] = (double)(s >> 11) / 9007199254740992.0 * 2.0 - 1.0, n += q[i] * q[i];
        }
        n = sqrt(n);
        double a = q[0] / n, b = q[1] / n, c = q[2] / n, d = q[3] / n;
        double m[3][3] = {{1 - 2 * (c * c + d * d), 2 * (b * c - a * d), 2 * (b * d + a * c)},
                          {2 * (b * c + a * d), 1 - 2 * (b * b + d * d), 2 * (c * d - a * b)},
                          {2 * (b * d - a * c), 2 * (c * d + a * b), 1 - 2 * (b * b + c * c)}};
        qibl_q30_t r[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                r[i][j] = (int32_t)lrint(m[i][j] * 1073741824.0), m[i][j] = r[i][j] / 1073741824.0;
        qibl_sh_rotation_t rot;
        double ref[165];
        if (qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])r, 5) != QIBL_OK)
            return -1.0;
        qtool_ref_sh_rotation(m, 5, ref);
        for (int i = 0; i < 165; ++i)
            worst = fmax(worst, fabs(rot.d[i] / 1073741824.0 - ref[i]));
    }
    return worst;
}

static double min_ms(const double *t, int n)
{
    double m = t[0];
    for (int i = 1; i < n; ++i)
        m = t[i] < m ? t[i] : m;
    return m;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int qtool_bench_probe(int quick)
{
    const int reps = quick ? 7 : 31;
    char path[600], err[512];
    snprintf(path, sizeof path, "%.500s/quarry_01_1k.hdr", bp_dir());
    int w = 1024, h = 512, have_file = 1;
    uint8_t *px = NULL;
    const char *name = "quarry_01_1k";
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, sizeof err) != 0) {
        have_file = 0;
        printf("(%s not found: an integer-made 1024x512 probe with a sun instead)\n", path);
        w = 1024, h = 512, px = int_probe(w, h), name = "integer-made 1024x512 probe";
        if (!px)
            return fprintf(stderr, "qibl: bench probe: out of memory\n"), 1;
    }
    size_t n = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h), bytes = 4 * (size_t)w * (size_t)h;
    void *ws = malloc(n);
    double *tp = malloc(sizeof *tp * (size_t)reps), *tr = malloc(sizeof *tr * (size_t)reps);
    double *tb = malloc(sizeof *tb * (size_t)reps), *tt = malloc(sizeof *tt * (size_t)reps);
    double *th = malloc(sizeof *th * (size_t)reps), *tq = malloc(sizeof *tq * (size_t)reps);
    double *ts = malloc(sizeof *ts * (size_t)reps), *ts3 = malloc(sizeof *ts3 * (size_t)reps);
    double *strig = malloc(sizeof *strig * 9 * (size_t)w), sep[3][25];
    if (!ws || !tp || !tr || !tb || !tt || !th || !tq || !ts || !ts3 || !strig)
        return fprintf(stderr, "qibl: bench probe: out of memory\n"), 1;
    qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
    qibl_probe_coeffs_t c;
    bp_sink = qtool_bench_read_u64(px, bytes);
    for (int r = 0; r < reps; ++r) { /* interleaved: load the file, read, project, begin only, rotate */
        th[r] = 0.0;
        if (have_file) {
            int fw, fh;
            uint8_t *fp = NULL;
            double h0 = qtool_bench_cpu_now();
            if (qtool_hdr_read_rgbe(path, &fw, &fh, &fp, err, sizeof err) == 0)
                bp_sink += fp[0], free(fp);
            th[r] = (qtool_bench_cpu_now() - h0) * 1e3;
        }
        bp_sink += qtool_bench_read_u64(px, bytes); /* untimed: the bytes in cache, as the baselines of `bench baselines` */
        double t0 = qtool_bench_cpu_now();
        bp_sink += qtool_bench_read_u64(px, bytes);
        double t1 = qtool_bench_cpu_now();
        (void)qibl_probe_sh_project(&img, 5, NULL, ws, n, &c);
        double t2 = qtool_bench_cpu_now();
        qibl_probe_sh_t ps;
        (void)qibl_probe_sh_begin(&ps, (uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n);
        double t3 = qtool_bench_cpu_now();
        qibl_q30_t rm[3][3] = {{0, -(1 << 30), 0}, {1 << 30, 0, 0}, {0, 0, 1 << 30}};
        qibl_sh_rotation_t rot;
        int32_t out[25];
        (void)qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])rm, 5);
        for (int ch = 0; ch < 3; ++ch)
            (void)qibl_sh_rotate(&rot, c.c[ch], out), bp_sink += (uint64_t)out[3];
        double t4 = qtool_bench_cpu_now();
        tr[r] = (t1 - t0) * 1e3, tp[r] = (t2 - t1) * 1e3, tb[r] = (t3 - t2) * 1e3, tt[r] = (t4 - t3) * 1e6;
        qibl_probe_coeffs_t c3; /* the same loop: 3 bands, and the separable double loop at 5 and 3 */
        double t5 = qtool_bench_cpu_now();
        (void)qibl_probe_sh_project(&img, 3, NULL, ws, n, &c3);
        double t6 = qtool_bench_cpu_now();
        separable_double(px, w, h, 5, strig, sep);
        double t7 = qtool_bench_cpu_now();
        separable_double(px, w, h, 3, strig, sep);
        double t8 = qtool_bench_cpu_now();
        tq[r] = (t6 - t5) * 1e3, ts3[r] = (t8 - t7) * 1e3, ts[r] = (t7 - t6) * 1e3;
        bp_sink += (uint64_t)c3.c[0][0] + (uint64_t)(sep[0][0] != 0.0);
    }
    /* the baseline computes the same sum: its 5-band coefficients against qibl's */
    separable_double(px, w, h, 5, strig, sep);
    double sep_err = 0.0, sep_max = 0.0;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            sep_err = fmax(sep_err, fabs(ldexp(c.c[ch][i], c.exp) - sep[ch][i])), sep_max = fmax(sep_max, fabs(sep[ch][i]));
    const double x5 = qtool_bench_paired_ratio(ts, tp, reps), x3 = qtool_bench_paired_ratio(ts3, tq, reps);
    const double b35 = qtool_bench_paired_ratio(tq, tp, reps), x5min = min_ms(ts, reps) / min_ms(tp, reps);
    qsort(tp, (size_t)reps, sizeof *tp, cmp_double), qsort(tr, (size_t)reps, sizeof *tr, cmp_double);
    qsort(tb, (size_t)reps, sizeof *tb, cmp_double), qsort(tt, (size_t)reps, sizeof *tt, cmp_double);
    qsort(th, (size_t)reps, sizeof *th, cmp_double), qsort(tq, (size_t)reps, sizeof *tq, cmp_double);
    qsort(ts, (size_t)reps, sizeof *ts, cmp_double), qsort(ts3, (size_t)reps, sizeof *ts3, cmp_double);
    const double npx = (double)w * (double)h;
    printf("== bench probe: SH projection (bands 0..4, 3 channels) of %s, %d interleaved repetitions\n", name, reps);
#ifdef __VERSION__
    printf("compiler: %s; core flags: %s%s\n", __VERSION__, QIBL_BENCH_CORE_FLAGS,
           QIBL_CONFIG_NATIVE_MUL64 ? "" : ", portable M0 paths");
#endif
    printf("%-52s %9s %9s %8s %8s %8s\n", "run", "min ms", "median ms", "min ns/px", "x read", "x load");
#define BP_ROW(label, t, hload)                                                                                     \
    printf("%-52s %9.3f %9.3f %9.3f %8.2f %8s\n", label, t[0], t[reps / 2], t[0] * 1e6 / npx, t[0] / tr[0], hload)
    char xl[32];
    BP_ROW("one read pass (64-bit words of the RGBE bytes, in cache)", tr, "-");
    if (have_file)
        BP_ROW("load the .hdr file (open, read, RLE decode, free)", th, "1.00");
    snprintf(xl, sizeof xl, "%.2f", have_file ? tp[0] / th[0] : 0.0);
    BP_ROW("qibl_probe_sh_project (begin + rows + finish)", tp, have_file ? xl : "-");
    BP_ROW("  of which begin (trig table)", tb, "-");
    BP_ROW("qibl_probe_sh_project, 3 bands", tq, "-");
    BP_ROW("separable double loop (same sum, 5 bands)", ts, "-");
    BP_ROW("separable double loop (same sum, 3 bands)", ts3, "-");
#undef BP_ROW
    printf("%-52s %9.1f %9.1f %9s %8s %8s\n", "rotation: init + 3 channels (microseconds)", tt[0], tt[reps / 2], "-",
           "-", "-");
    printf("goal: projection <= 2x the read pass (ratio of the minima; medians %.2f)\n", tp[reps / 2] / tr[reps / 2]);
    printf("separable double loop / qibl, paired by repetition (median): %.2fx at 5 bands (of the minima %.2fx), "
           "%.2fx at 3 bands; qibl 3 bands / 5 bands %.2f; the loop's max |c - qibl| / max |c| %.1e\n",
           x5, x5min, x3, b35, sep_err / sep_max);
    printf("RESULT probe.project_over_read %.2f\n", tp[0] / tr[0]);
    printf("RESULT probe.project_over_separable %.2f\n", x5);
    printf("RESULT probe.project3_over_separable3 %.2f\n", x3);
    printf("RESULT probe.project3_over_project5 %.2f\n", b35);
    if (have_file)
        printf("RESULT probe.project_over_hdr_load %.2f\n", tp[0] / th[0]);
    printf("RESULT probe.project_ns_per_px %.3f\n", tp[0] * 1e6 / npx);
    printf("RESULT probe.project_ms %.3f\n", tp[0]);

    /* accuracy: every fixture probe, or the integer-made one */
    double worst = 0.0;
    int count = 0;
    DIR *dir = opendir(bp_dir());
    if (dir) {
        struct dirent *de;
        while ((de = readdir(dir)) != NULL) {
            size_t l = strlen(de->d_name);
            if (l < 5 || strcmp(de->d_name + l - 4, ".hdr") != 0)
                continue;
            int pw, ph;
            uint8_t *pp;
            snprintf(path, sizeof path, "%.300s/%.250s", bp_dir(), de->d_name);
            if (qtool_hdr_read_rgbe(path, &pw, &ph, &pp, err, sizeof err) != 0)
                continue;
            size_t pn = qibl_probe_sh_workspace_size((uint32_t)pw, (uint32_t)ph);
            void *pws = malloc(pn);
            double e = pws ? sh_rel_err(pp, pw, ph, pws, pn) : -1.0;
            if (!quick || count < 2)
                printf("  %-36s max |err| / max |L| %.3e\n", de->d_name, e);
            worst = fmax(worst, e), ++count;
            free(pws), free(pp);
        }
        closedir(dir);
    }
    if (count == 0)
        worst = sh_rel_err(px, w, h, ws, n), count = 1;
    double rerr = rotate_err();
    printf("projection against the double reference (tools/ref/probe_ref.c) on %d probe(s): max |err| / max |L| "
           "%.3e\n", count, worst);
    printf("rotation against the double reference (integrated rotated basis), 200 random rotations: max |D - D_ref| "
           "%.3e (bound 2^-24 = %.3e)\n", rerr, 1.0 / 16777216.0);
    printf("RESULT probe.sh_max_rel_err %.3e\n", worst);
    printf("RESULT probe.rotate_max_err %.3e\n", rerr);
    /* a sun probe: a dim uniform sky (2^-12) and a 3 x 3 sun 2^20 brighter (256), 45 degrees up */
    uint8_t *sun = malloc(bytes);
    if (sun) {
        for (size_t i = 0; i < (size_t)w * (size_t)h; ++i)
            sun[4 * i] = sun[4 * i + 1] = sun[4 * i + 2] = 128, sun[4 * i + 3] = 136 - 12 - 7;
        for (int v = h / 4 - 1; v <= h / 4 + 1; ++v)
            for (int u = w / 3 - 1; u <= w / 3 + 1; ++u)
                sun[4 * ((size_t)v * (size_t)w + (size_t)u) + 3] = 136 + 8 - 7;
        ringing(sun, w, h, ws, n, "a sun probe (3x3 sun 2^20 x a uniform sky)");
        free(sun);
    }
    if (!quick)
        ringing(px, w, h, ws, n, name);
    free(ws), free(tp), free(tr), free(tb), free(tt), free(th), free(tq), free(ts), free(ts3), free(strig), free(px);
    return 0;
}
