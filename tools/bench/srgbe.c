/*
 * srgbe.c - `qibl bench srgbe`: the sRGBE codec against Ward's RGBE (frexp/ldexp), RGB9E5
 * (EXT_texture_shared_exponent) and plain binary32, on
 *   (a) a real HDR probe from ../shared/fixtures/probes (royal_esplanade_1k.hdr, else the first
 *       .hdr there; QIBL_PROBE=path overrides), or a procedural sky when the directory is absent;
 *   (b) signed data from that probe: its 25 SH coefficients (band 0..4, projected with the double
 *       reference tools/ref/sh_ref.c, lat-long pixels weighted by solid angle) for accuracy, and,
 *       because 25 triples are too few to time, every pixel's SH-weighted radiance L(w) Y_i(w) with
 *       i = 1 + (pixel index mod 24) for accuracy and timing.
 * Accuracy per pixel: relative error of the largest |channel| ("L"), absolute error of the two
 * others (also divided by |L|), through each format's own decoder to binary32. Throughput: bulk
 * encode and decode over the whole set, Mpixel/s, median of several runs. Unsigned formats clamp
 * negative channels to 0 (their error on signed data shows what that costs).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>

#include "io/hdr.h"
#include "bench/bench.h"
#include "qtool.h"
#include "qibl/srgbe.h"
#include "ref/rgb9e5.h"
#include "ref/sh_ref.h"
#include "ref/srgbe_ref.h"
#include "ref/ward_rgbe.h"

#define PROBE_DIR "../shared/fixtures/probes"
#define PROBE_DEFAULT "royal_esplanade_1k.hdr"

typedef struct {
    const char *name;
    size_t n;
    float *rgb;     /* 3n */
    uint32_t *bits; /* the same values as binary32 bit patterns (the sRGBE encoder's input) */
} dataset;

typedef struct {
    double max_rel, sum_rel, sum_abs_oth, sum_abs_oth_rel;
    size_t n_rel, n_oth;
} errstats;

enum { C_SRGBE, C_WARD, C_RGB9E5, C_FLOAT, NCODEC };
static const char *codec_name[NCODEC] = {"qibl sRGBE (integer, bulk)", "Ward RGBE (frexp/ldexp)",
                                         "RGB9E5 (EXT_texture_s_e)", "binary32 float (copy)"};
static const int codec_bytes[NCODEC] = {4, 4, 4, 12};
static const char *codec_signed[NCODEC] = {"yes", "no", "no", "yes"};

typedef struct {
    errstats err;
    double enc_mpx, dec_mpx; /* 0 when not timed; from the median time */
    double enc_min, dec_min; /* seconds per pass, minimum over the interleaved repetitions */
    double enc_t[31], dec_t[31]; /* every repetition's times, for ratios paired by repetition */
    int reps;
} result;

static void errs_add(errstats *e, const float *in, const float *out, size_t n)
{
    for (size_t p = 0; p < n; ++p) {
        const float *x = in + 3 * p, *y = out + 3 * p;
        int L = 0;
        for (int c = 1; c < 3; ++c)
            if (fabsf(x[c]) > fabsf(x[L]))
                L = c;
        double ax = fabs((double)x[L]);
        if (ax == 0.0)
            continue;
        double rel = fabs((double)x[L] - (double)y[L]) / ax;
        e->sum_rel += rel;
        e->n_rel++;
        if (rel > e->max_rel)
            e->max_rel = rel;
        for (int c = 0; c < 3; ++c)
            if (c != L) {
                double a = fabs((double)x[c] - (double)y[c]);
                e->sum_abs_oth += a;
                e->sum_abs_oth_rel += a / ax;
                e->n_oth++;
            }
    }
}

static void encode_with(int codec, const dataset *d, void *buf)
{
    switch (codec) {
    case C_SRGBE: QTOOL_BENCH_CALL(qibl_srgbe_encode_f32_n(d->bits, d->n, buf)); break;
    case C_WARD: qtool_ref_rgbe_encode_n(d->rgb, d->n, buf); break;
    case C_RGB9E5: qtool_ref_rgb9e5_encode_n(d->rgb, d->n, buf); break;
    default: memcpy(buf, d->rgb, d->n * 3 * sizeof *d->rgb); break;
    }
}

static void decode_with(int codec, const dataset *d, const void *buf, float *out, uint32_t *out_bits)
{
    switch (codec) {
    case C_SRGBE: QTOOL_BENCH_CALL(qibl_srgbe_decode_f32_n(buf, d->n, out_bits)); break;
    case C_WARD: qtool_ref_rgbe_decode_n(buf, d->n, out); break;
    case C_RGB9E5: qtool_ref_rgb9e5_decode_n(buf, d->n, out); break;
    default: memcpy(out, buf, d->n * 3 * sizeof *out); break;
    }
}

/* Accuracy of every codec on d, and (reps > 0) throughput: each repetition times every codec in
 * turn, so a change of machine load hits all of them alike, and the medians are compared. */
static void run_codecs(const dataset *d, int reps, result res[NCODEC], float *out, uint32_t *out_bits, void *buf)
{
    double te[NCODEC][31], td[NCODEC][31];
    for (int k = 0; k <= reps && reps > 0; ++k) /* repetition 0 warms caches and is not kept */
        for (int c = 0; c < NCODEC; ++c) {
            /* each timed call right after the same call untimed: every codec's encode and decode
             * from its own warm caches (the ratios compare minima, so Ward's baseline must not pay
             * for sRGBE's, and an encode must not start from the caches its decode left: 6 MB of
             * decoded output evict the encoder's input, which costs a memory-bound encoder and
             * not a compute-bound one) */
            encode_with(c, d, buf);
            const double t0 = qtool_bench_cpu_now();
            encode_with(c, d, buf);
            const double t1 = qtool_bench_cpu_now();
            decode_with(c, d, buf, out, out_bits);
            const double t2 = qtool_bench_cpu_now();
            decode_with(c, d, buf, out, out_bits);
            const double t3 = qtool_bench_cpu_now();
            if (k > 0) {
                te[c][k - 1] = t1 - t0;
                td[c][k - 1] = t3 - t2;
            }
        }
    for (int c = 0; c < NCODEC; ++c) {
        encode_with(c, d, buf);
        decode_with(c, d, buf, out, out_bits);
        if (c == C_SRGBE)
            memcpy(out, out_bits, d->n * 3 * sizeof *out); /* binary32 bits to float, no arithmetic */
        memset(&res[c].err, 0, sizeof res[c].err);
        errs_add(&res[c].err, d->rgb, out, d->n);
        res[c].reps = reps; /* copied before the medians sort te and td in place */
        for (int k = 0; k < reps; ++k)
            res[c].enc_t[k] = te[c][k], res[c].dec_t[k] = td[c][k];
        res[c].enc_mpx = reps > 0 ? (double)d->n / qtool_bench_median(te[c], reps) / 1e6 : 0.0;
        res[c].dec_mpx = reps > 0 ? (double)d->n / qtool_bench_median(td[c], reps) / 1e6 : 0.0;
        res[c].enc_min = reps > 0 ? qtool_bench_min(te[c], reps) : 0.0;
        res[c].dec_min = reps > 0 ? qtool_bench_min(td[c], reps) : 0.0;

    }
}

static void print_header(void)
{
    printf("  %-28s %4s %4s %10s %10s %13s %13s %10s %10s\n", "codec", "B/px", "sign", "max rel L", "mean rel L",
           "mean|err|oth", "  ... / |L|", "enc Mpx/s", "dec Mpx/s");
}

static void print_row(int codec, const result *r)
{
    const errstats *e = &r->err;
    char enc[32] = "-", dec[32] = "-";
    if (r->enc_mpx > 0) {
        snprintf(enc, sizeof enc, "%.1f", r->enc_mpx);
        snprintf(dec, sizeof dec, "%.1f", r->dec_mpx);
    }
    printf("  %-28s %4d %4s %9.4f%% %9.4f%% %13.4g %12.4f%% %10s %10s\n", codec_name[codec], codec_bytes[codec],
           codec_signed[codec], 100.0 * e->max_rel, e->n_rel ? 100.0 * e->sum_rel / (double)e->n_rel : 0.0,
           e->n_oth ? e->sum_abs_oth / (double)e->n_oth : 0.0,
           e->n_oth ? 100.0 * e->sum_abs_oth_rel / (double)e->n_oth : 0.0, enc, dec);
}

/* the sRGBE error in units of its bound 2^e/510, against the exact decode of each code */
static void srgbe_bound(const dataset *d, double *max_all, double *max_nz)
{
    uint8_t c[4];
    *max_all = *max_nz = 0.0;
    for (size_t p = 0; p < d->n; ++p) {
        QTOOL_BENCH_CALL(qibl_srgbe_encode_f32(d->bits + 3 * p, c));
        double mx = fmax(fabs(d->rgb[3 * p]), fmax(fabs(d->rgb[3 * p + 1]), fabs(d->rgb[3 * p + 2])));
        if (mx < 0x1p-128)
            continue; /* flushed: no bound */
        for (int k = 0; k < 3; ++k) {
            double e = qtool_ref_srgbe_err_in_bounds(d->rgb[3 * p + k], c[k], c[3]);
            if (e > *max_all)
                *max_all = e;
            if (d->rgb[3 * p + k] != 0.0f && e > *max_nz)
                *max_nz = e;
        }
    }
}

static int dataset_alloc(dataset *d, size_t n)
{
    d->n = n;
    d->rgb = malloc(n * 3 * sizeof *d->rgb);
    d->bits = malloc(n * 3 * sizeof *d->bits);
    return d->rgb && d->bits ? 0 : -1;
}

static void dataset_free(dataset *d)
{
    free(d->rgb);
    free(d->bits);
}

static void dataset_sync_bits(dataset *d)
{
    memcpy(d->bits, d->rgb, d->n * 3 * sizeof *d->bits); /* binary32 bits, no arithmetic */
}

/* A clear-sky lat-long (top row = zenith): blue-to-white gradient, darker ground, a 0.5 degree sun
 * of radiance 5e4 with a glow: about 2^30 : 1 like the real probes. */
static void procedural_sky(float *rgb, int w, int h)
{
    const double st = 50.0 * QTOOL_PI / 180.0, sp = 1.3; /* sun: 50 degrees from zenith */
    const double sx = sin(st) * cos(sp), sy = sin(st) * sin(sp), sz = cos(st);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double t = (y + 0.5) * QTOOL_PI / h, p = (x + 0.5) * 2.0 * QTOOL_PI / w;
            double dx = sin(t) * cos(p), dy = sin(t) * sin(p), dz = cos(t);
            double cosg = dx * sx + dy * sy + dz * sz, g = acos(fmax(-1.0, fmin(1.0, cosg)));
            double c[3];
            if (dz >= 0) {
                double k = pow(1.0 - dz, 3.0);
                c[0] = 0.25 + 0.9 * k, c[1] = 0.45 + 0.75 * k, c[2] = 1.1 + 0.3 * k;
            } else {
                c[0] = 0.09, c[1] = 0.07, c[2] = 0.05;
                c[0] *= 1.0 + 0.3 * sin(13 * p) * sin(7 * t), c[2] *= 1.0 + 0.2 * cos(5 * p);
            }
            double glow = 40.0 * exp(-g * 12.0) + 3.0 * exp(-g * 3.0);
            for (int k = 0; k < 3; ++k)
                c[k] += glow * (k == 2 ? 0.8 : 1.0);
            if (g < 0.5 * QTOOL_PI / 180.0)
                c[0] = 5.2e4, c[1] = 5.0e4, c[2] = 4.6e4;
            float *o = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
            o[0] = (float)c[0], o[1] = (float)c[1], o[2] = (float)c[2];
        }
}

/* finds the probe: QIBL_PROBE, else PROBE_DIR/PROBE_DEFAULT, else the first .hdr in PROBE_DIR */
static int find_probe(char *path, size_t len)
{
    const char *env = getenv("QIBL_PROBE");
    if (env && *env) {
        snprintf(path, len, "%s", env);
        return 0;
    }
    DIR *dir = opendir(PROBE_DIR);
    if (!dir)
        return -1;
    char first[512] = "";
    int found_default = 0;
    struct dirent *de;
    while ((de = readdir(dir)) != NULL) {
        size_t nl = strlen(de->d_name);
        if (nl < 5 || strcmp(de->d_name + nl - 4, ".hdr") != 0)
            continue;
        if (strcmp(de->d_name, PROBE_DEFAULT) == 0)
            found_default = 1;
        if (!first[0] || strcmp(de->d_name, first) < 0)
            snprintf(first, sizeof first, "%s", de->d_name);
    }
    closedir(dir);
    if (!first[0])
        return -1;
    snprintf(path, len, "%s/%s", PROBE_DIR, found_default ? PROBE_DEFAULT : first);
    return 0;
}

/* SH projection of a lat-long image: coef[25][3] (double) and the per-pixel signed set */
static void sh_project(const float *rgb, int w, int h, double coef[25][3], float *signed_rgb)
{
    memset(coef, 0, 25 * 3 * sizeof(double));
    const double dt = QTOOL_PI / h, dp = 2.0 * QTOOL_PI / w;
    for (int y = 0; y < h; ++y) {
        double t = (y + 0.5) * dt, dw = sin(t) * dt * dp;
        for (int x = 0; x < w; ++x) {
            double p = (x + 0.5) * dp, Y[25];
            qtool_ref_sh_eval(sin(t) * cos(p), sin(t) * sin(p), cos(t), 5, Y);
            size_t idx = (size_t)y * (size_t)w + (size_t)x;
            const float *L = rgb + 3 * idx;
            for (int i = 0; i < 25; ++i)
                for (int k = 0; k < 3; ++k)
                    coef[i][k] += L[k] * Y[i] * dw;
            int i = 1 + (int)(idx % 24u);
            for (int k = 0; k < 3; ++k)
                signed_rgb[3 * idx + (size_t)k] = (float)(L[k] * Y[i]);
        }
    }
}

static void bench_table(const char *title, const dataset *d, int reps, result res[NCODEC], float *out,
                        uint32_t *out_bits, void *buf)
{
    printf("%s\n", title);
    print_header();
    run_codecs(d, reps, res, out, out_bits, buf);
    for (int c = 0; c < NCODEC; ++c)
        print_row(c, &res[c]);
    double ba, bn;
    srgbe_bound(d, &ba, &bn);
    printf("  sRGBE error / (2^e/510), exact decode: max %.9f (channels != 0: %.9f)\n", ba, bn);
}

int qtool_bench_srgbe(int quick)
{
    const int reps = quick ? 3 : 31; /* run_codecs keeps at most 31 */
    int w = 1024, h = 512, rc = 0, have_probe = 0;
    float *img = NULL;
    char path[1024], err[512], src[1200];
    if (find_probe(path, sizeof path) == 0) {
        if (qtool_hdr_read(path, &w, &h, &img, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: bench srgbe: %s\n", err);
            return 1;
        }
        snprintf(src, sizeof src, "probe %s", path);
        have_probe = 1;
    } else {
        printf("SKIP bench srgbe: %s not found: using a procedural sky instead of a real probe\n", PROBE_DIR);
        img = malloc((size_t)w * (size_t)h * 3 * sizeof *img);
        if (!img)
            return fprintf(stderr, "qibl: bench srgbe: out of memory\n"), 1;
        procedural_sky(img, w, h);
        snprintf(src, sizeof src, "procedural sky (sun 5e4, sky ~1, ground ~0.07)");
    }
    size_t n = (size_t)w * (size_t)h;
    dataset a = {0}, sky = {0}, b = {0}, coef = {0};
    float *out = malloc(n * 3 * sizeof *out);
    uint32_t *out_bits = malloc(n * 3 * sizeof *out_bits);
    void *buf = malloc(n * 12 + 64);
    if (!out || !out_bits || !buf || dataset_alloc(&a, n) || dataset_alloc(&b, n) || dataset_alloc(&coef, 25) ||
        (have_probe && dataset_alloc(&sky, (size_t)1024 * 512))) {
        fprintf(stderr, "qibl: bench srgbe: out of memory\n");
        rc = 1;
        goto done;
    }
    memcpy(a.rgb, img, n * 3 * sizeof *img);
    dataset_sync_bits(&a);
    double c[25][3];
    sh_project(img, w, h, c, b.rgb);
    dataset_sync_bits(&b);
    for (int i = 0; i < 25; ++i)
        for (int k = 0; k < 3; ++k)
            coef.rgb[3 * i + k] = (float)c[i][k];
    dataset_sync_bits(&coef);

    printf("== bench srgbe: shared-exponent colour formats; throughput: median of %d runs over the whole set, "
           "the codecs taking turns\n",
           reps);
    printf("   (rel L: relative error of the largest |channel|; oth: absolute error of the two others, and the same "
           "divided by |L|)\n");
    result ra[NCODEC], rs[NCODEC], rb[NCODEC], rc25[NCODEC];
    char title[1400];
    snprintf(title, sizeof title, "(a) %s: %dx%d = %zu pixels, unsigned HDR", src, w, h, n);
    bench_table(title, &a, reps, ra, out, out_bits, buf);
    if (have_probe) {
        printf("  note: the probe file is itself Ward RGBE (8-bit mantissas): RGB9E5 holds such values exactly "
               "in its range, and Ward RGBE\n"
               "  re-encodes them to the same bytes (its error is then exactly its +1/2 decode offset). (a') "
               "has no such quantisation.\n");
        procedural_sky(sky.rgb, 1024, 512);
        dataset_sync_bits(&sky);
        bench_table("(a') procedural sky (sun 5e4, sky ~1, ground ~0.07): 1024x512 = 524288 pixels, unsigned HDR",
                    &sky, reps, rs, out, out_bits, buf);
    }
    snprintf(title, sizeof title,
             "(b) signed: SH-weighted radiance L(w) Y_i(w), i = 1 + (pixel mod 24), of the image of (a): %zu "
             "triples",
             n);
    bench_table(title, &b, reps, rb, out, out_bits, buf);
    printf("(b') signed: the 25 SH coefficients of the image of (a) (bands 0..4; accuracy only, too few to time)\n");
    print_header();
    run_codecs(&coef, 0, rc25, out, out_bits, buf);
    for (int k = 0; k < NCODEC; ++k)
        print_row(k, &rc25[k]);
    /* ratios of the minimum times (the least disturbed of the interleaved runs; the machine may be
     * shared), the ratio of the medians beside them */
    /* RESULT: Ward over sRGBE paired by repetition (each pair timed back to back in one loop), the
     * median of those ratios; the ratio of the minima beside it */
    double enc_x = qtool_bench_paired_ratio(ra[C_WARD].enc_t, ra[C_SRGBE].enc_t, ra[C_SRGBE].reps),
           dec_x = qtool_bench_paired_ratio(ra[C_WARD].dec_t, ra[C_SRGBE].dec_t, ra[C_SRGBE].reps);
    const double enc_xmin = ra[C_WARD].enc_min / ra[C_SRGBE].enc_min, dec_xmin = ra[C_WARD].dec_min / ra[C_SRGBE].dec_min;
    double enc_xm = ra[C_SRGBE].enc_mpx / ra[C_WARD].enc_mpx, dec_xm = ra[C_SRGBE].dec_mpx / ra[C_WARD].dec_mpx;
    double max_rel = fmax(ra[C_SRGBE].err.max_rel, fmax(rb[C_SRGBE].err.max_rel, rc25[C_SRGBE].err.max_rel));
    if (have_probe)
        max_rel = fmax(max_rel, rs[C_SRGBE].err.max_rel);
    printf("speed, same run: qibl's integer sRGBE encoder / Ward's frexp encoder = %.2fx on (a) (target >= 4x)",
           enc_x);
    if (have_probe)
        printf(", %.2fx on (a')", rs[C_SRGBE].enc_mpx / rs[C_WARD].enc_mpx);
    printf(", %.2fx on (b); decoder / Ward's ldexp decoder = %.2fx on (a)\n", rb[C_SRGBE].enc_mpx / rb[C_WARD].enc_mpx,
           dec_x);
    printf("sRGBE bound: |err| <= 2^e/510 per channel, so the largest channel's relative error is < 4/510 = "
           "0.784%%; measured max %.4f%% over all sets\n",
           100.0 * max_rel);
    printf("sRGBE bulk on (a), %s, core %s: encode %.2f ns/px min, %.2f median (Ward %.2f min); decode %.2f ns/px "
           "min, %.2f median (Ward %.2f min); speedup paired by repetition (median): encode %.2fx, decode %.2fx "
           "(of the minima: %.2fx, %.2fx; of the medians: %.2fx, %.2fx)\n",
           QTOOL_BENCH_COMPILER, QIBL_BENCH_CORE_FLAGS,
           1e9 * ra[C_SRGBE].enc_min / (double)a.n, 1e3 / ra[C_SRGBE].enc_mpx, 1e9 * ra[C_WARD].enc_min / (double)a.n,
           1e9 * ra[C_SRGBE].dec_min / (double)a.n, 1e3 / ra[C_SRGBE].dec_mpx, 1e9 * ra[C_WARD].dec_min / (double)a.n,
           enc_x, dec_x, enc_xmin, dec_xmin, enc_xm, dec_xm);
    printf("RESULT srgbe.encode_speedup %.2f\n", enc_x);
    printf("RESULT srgbe.decode_speedup %.2f\n", dec_x);
    printf("RESULT srgbe.max_rel_err %.4e\n", max_rel);
    printf("RESULT srgbe.encode_mpix_s %.1f\n", ra[C_SRGBE].enc_mpx);
    printf("RESULT srgbe.decode_mpix_s %.1f\n", ra[C_SRGBE].dec_mpx);
done:
    free(img);
    free(out);
    free(out_bits);
    free(buf);
    dataset_free(&a);
    dataset_free(&sky);
    dataset_free(&b);
    dataset_free(&coef);
    return rc;
}
