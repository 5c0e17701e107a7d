/*
 * fuzz_lightprobe.c - libFuzzer target: light-probe sampling (core/include/qibl/lightprobe.h) on
 * small fuzzed probes in every pixel format, method, priority and placement.
 *
 * Input: 8 parameter bytes (width, height, format, method/priority/place, light count, frac_bits,
 * stride padding and offsets, a rectangle), then the pixels (zeros past the end of the input).
 * The probe and the workspace live in buffers of exactly the documented sizes (ASan sees any
 * access past them); byte formats and the workspace get odd addresses ("any alignment").
 *
 * Invariants (abort on violation): build refuses exactly the probes with a negative or non-finite
 * channel (or frac_bits out of range) and leaves lp untouched then; an all-zero probe gives
 * QIBL_E_PROBE_BLACK from lights, any other never; every region lies inside the probe, is lit and
 * cropped to its energy's bounding box, and no two regions share a pixel; every lit pixel is in a
 * region and the regions' energies add up to the probe's total (so nothing is lost or counted
 * twice); lights come brightest first (ties: smaller v0, then u0); counts are as documented
 * (min(count, lit pixels) for ADAPTIVE/VARMIN unless priority VARIANCE); the largest channel is in
 * [2^30, 2^31); each direction is a unit vector (within 4 LSB of Q2.30) pointing inside its
 * region (centroid or centre); region sums are additive; a failing call writes nothing.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "qibl/lightprobe.h"
#include "fuzz_probepx.h"

enum { MAX_W = 24, MAX_H = 16, MAX_LIGHTS = 48 };

static const double PI = 3.14159265358979323846;

static uint64_t energy(const qibl_lightprobe_t *lp, uint32_t u0, uint32_t v0, uint32_t u1, uint32_t v1)
{
    uint64_t e = ~(uint64_t)0;
    FUZZ_CHECK(qibl_lightprobe_region_energy(lp, u0, v0, u1, v1, &e) == QIBL_OK);
    return e;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    const uint32_t w = 1u + fuzz_u8(&in) % MAX_W, h = 1u + fuzz_u8(&in) % MAX_H;
    const qibl_lightprobe_format_t fmt = (qibl_lightprobe_format_t)(fuzz_u8(&in) % QIBL_LIGHTPROBE_FORMAT_COUNT);
    const uint8_t mb = fuzz_u8(&in);
    qibl_lightprobe_opts_t opts;
    opts.method = (qibl_lightprobe_method_t)(mb % 3u);
    opts.priority = (qibl_lightprobe_priority_t)((mb >> 2) % QIBL_LIGHTPROBE_PRIORITY_COUNT);
    opts.place = (qibl_lightprobe_place_t)((mb >> 5) & 1u);
    const uint8_t cb = fuzz_u8(&in);
    /* mostly powers of two (MEDIANCUT needs them), sometimes any count */
    const uint32_t max_lights = cb & 0x80u ? 1u + cb % MAX_LIGHTS : 1u << (cb % 6u);
    const int32_t frac_bits = (int32_t)(int8_t)fuzz_u8(&in) * 2; /* -256..254: some out of range */
    const uint8_t sb = fuzz_u8(&in);
    const uint8_t rb = fuzz_u8(&in);

    const size_t pb = fmt == QIBL_LIGHTPROBE_RGBE || fmt == QIBL_LIGHTPROBE_SRGBE ? 4u : 12u;
    const size_t row = pb * w, stride = row + 4u * (sb & 3u);
    const size_t span = stride * (h - 1u) + row;
    const size_t poff = pb == 4u ? (sb >> 2 & 1u) : 0u; /* odd address for byte formats */
    uint8_t *pbuf = malloc(span + poff), *pix = pbuf + poff;
    int any_lit = 0, any_neg = 0, any_nf = 0;
    for (uint32_t v = 0; v < h; ++v)
        for (uint32_t u = 0; u < w; ++u) {
            uint8_t *p = pix + v * stride + u * pb;
            for (size_t i = 0; i < pb; ++i)
                p[i] = fuzz_u8(&in);
            int z, ng, nf;
            classify(p, fmt, &z, &ng, &nf);
            any_lit |= !z && !ng && !nf, any_neg |= ng, any_nf |= nf;
        }
    for (uint32_t v = 0; v + 1u < h; ++v) /* stride padding: fuzzed too, must not matter */
        memset(pix + v * stride + row, 0xFF, stride - row);

    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = pix, img.width = w, img.height = h, img.format = fmt, img.frac_bits = frac_bits;
    img.stride = (sb & 3u) ? stride : 0u;
    const qibl_lightprobe_method_t build_m = (sb >> 3 & 1u) ? QIBL_LIGHTPROBE_VARMIN : opts.method;
    const size_t need = qibl_lightprobe_workspace_size(w, h, build_m);
    FUZZ_CHECK(need > 0);
    const size_t woff = sb >> 4 & 7u;
    uint8_t *wbuf = malloc(need + woff);
    qibl_lightprobe_t lp, lp0;
    memset(&lp, 0x5A, sizeof lp);
    lp0 = lp;
    qibl_status_t st = qibl_lightprobe_build(&lp, &img, build_m, wbuf + woff, need);
    if (frac_bits < -128 || frac_bits > 128) { /* checked whatever the format */
        FUZZ_CHECK(st == QIBL_E_PROBE_FORMAT);
    } else if (any_neg || any_nf) {
        FUZZ_CHECK((any_nf && st == QIBL_E_PROBE_NOT_FINITE) || (any_neg && st == QIBL_E_PROBE_NEGATIVE));
    } else {
        /* lightprobe.h lists QIBL_E_PROBE_BLACK among build's errors; lightprobe.c returns OK */
        FUZZ_CHECK(st == QIBL_OK || (st == QIBL_E_PROBE_BLACK && !any_lit));
    }
    if (st != QIBL_OK) {
        FUZZ_CHECK(memcmp(&lp, &lp0, sizeof lp) == 0 || st == QIBL_E_PROBE_BLACK);
        goto done;
    }
    /* a workspace below the low-memory path's minimum is refused, writing nothing */
    const size_t least = qibl_lightprobe_workspace_min(w, h, build_m);
    FUZZ_CHECK(least > 0u && least <= need);
    FUZZ_CHECK(qibl_lightprobe_build(&lp0, &img, build_m, wbuf + woff, least - 1u) == QIBL_E_WORKSPACE);
    {
        qibl_lightprobe_t pattern;
        memset(&pattern, 0x5A, sizeof pattern);
        FUZZ_CHECK(memcmp(&lp0, &pattern, sizeof lp0) == 0);
    }

    const uint64_t total = energy(&lp, 0, 0, w, h);
    FUZZ_CHECK((total != 0u) == (any_lit != 0));
    /* additivity of region sums on a fuzzed rectangle split at a fuzzed column */
    {
        uint32_t u0 = rb % (w + 1u), u1 = u0 + (uint32_t)(rb >> 4) % (w + 1u - u0);
        uint32_t v0 = (rb >> 2) % (h + 1u), v1 = h, um = u0 + (u1 - u0) / 2u;
        FUZZ_CHECK(energy(&lp, u0, v0, u1, v1) == energy(&lp, u0, v0, um, v1) + energy(&lp, um, v0, u1, v1));
        uint64_t e = 7u;
        FUZZ_CHECK(qibl_lightprobe_region_energy(&lp, u1, v0, u0 == u1 ? u1 + w + 1u : u0, v1, &e) ==
                       QIBL_E_PROBE_RECT &&
                   e == 7u);
    }
    uint32_t lit = 0;
    for (uint32_t v = 0; v < h; ++v)
        for (uint32_t u = 0; u < w; ++u)
            lit += energy(&lp, u, v, u + 1u, v + 1u) != 0u;

    qibl_lightprobe_light_t *L = malloc(max_lights * sizeof *L);
    memset(L, 0x3C, max_lights * sizeof *L);
    qibl_lightprobe_result_t res = {12345u, 678};
    st = qibl_lightprobe_lights(&lp, &opts, L, max_lights, &res);
    const qibl_lightprobe_priority_t pr = opts.priority;
    const int levels = opts.method == QIBL_LIGHTPROBE_MEDIANCUT || pr == QIBL_LIGHTPROBE_PRIORITY_LEVELS;
    const int variance = pr == QIBL_LIGHTPROBE_PRIORITY_VARIANCE ||
                         (opts.method == QIBL_LIGHTPROBE_VARMIN && pr == QIBL_LIGHTPROBE_PRIORITY_DEFAULT);
    if (opts.method == QIBL_LIGHTPROBE_MEDIANCUT && pr != QIBL_LIGHTPROBE_PRIORITY_DEFAULT &&
        pr != QIBL_LIGHTPROBE_PRIORITY_LEVELS) {
        FUZZ_CHECK(st == QIBL_E_PROBE_METHOD);
    } else if (levels && (max_lights & (max_lights - 1u)) != 0u) {
        FUZZ_CHECK(st == QIBL_E_PROBE_COUNT);
    } else if ((opts.method == QIBL_LIGHTPROBE_VARMIN || variance) && build_m != QIBL_LIGHTPROBE_VARMIN) {
        FUZZ_CHECK(st == QIBL_E_PROBE_MISMATCH);
    } else if (total == 0u) {
        FUZZ_CHECK(st == QIBL_E_PROBE_BLACK);
    } else {
        FUZZ_CHECK(st == QIBL_OK);
    }
    if (st != QIBL_OK) {
        FUZZ_CHECK(res.count == 12345u && res.rgb_exp == 678);
        for (size_t i = 0; i < max_lights * sizeof *L; ++i)
            FUZZ_CHECK(((const uint8_t *)L)[i] == 0x3C);
        free(L);
        goto done;
    }

    const uint32_t n = res.count;
    const uint32_t expect = max_lights < lit ? max_lights : lit;
    FUZZ_CHECK(n >= 1u && n <= expect);
    if (!levels && !variance)
        FUZZ_CHECK(n == expect);
    uint64_t sum = 0;
    int32_t top = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const qibl_lightprobe_light_t *l = &L[i];
        FUZZ_CHECK(l->u0 < l->u1 && l->u1 <= w && l->v0 < l->v1 && l->v1 <= h);
        const uint64_t e = energy(&lp, l->u0, l->v0, l->u1, l->v1);
        FUZZ_CHECK(e > 0u);
        /* cropped: every edge row and column of the region holds energy */
        FUZZ_CHECK(energy(&lp, l->u0, l->v0, l->u0 + 1u, l->v1) > 0u);
        FUZZ_CHECK(energy(&lp, l->u1 - 1u, l->v0, l->u1, l->v1) > 0u);
        FUZZ_CHECK(energy(&lp, l->u0, l->v0, l->u1, l->v0 + 1u) > 0u);
        FUZZ_CHECK(energy(&lp, l->u0, l->v1 - 1u, l->u1, l->v1) > 0u);
        sum += e;
        if (i > 0) {
            const qibl_lightprobe_light_t *k = &L[i - 1u];
            const uint64_t ek = energy(&lp, k->u0, k->v0, k->u1, k->v1);
            FUZZ_CHECK(ek > e || (ek == e && (k->v0 < l->v0 || (k->v0 == l->v0 && k->u0 < l->u0))));
        }
        for (uint32_t j = 0; j < i; ++j) { /* disjoint */
            const qibl_lightprobe_light_t *k = &L[j];
            FUZZ_CHECK(k->u1 <= l->u0 || l->u1 <= k->u0 || k->v1 <= l->v0 || l->v1 <= k->v0);
        }
        for (int c = 0; c < 3; ++c) {
            FUZZ_CHECK(l->rgb[c] >= 0);
            if (l->rgb[c] > top)
                top = l->rgb[c];
        }
        /* a unit vector pointing inside the region */
        const double x = l->dir[0], y = l->dir[1], z = l->dir[2];
        const double len = sqrt(x * x + y * y + z * z);
        FUZZ_CHECK(fabs(len - 1073741824.0) <= 4.0);
        const double theta = acos(z / len);
        double phi = atan2(y, x);
        if (phi < 0)
            phi += 2.0 * PI;
        const double uc = phi * w / (2.0 * PI), vc = theta * h / PI, tol = 1e-4;
        FUZZ_CHECK(uc >= l->u0 + 0.5 - tol && uc <= l->u1 - 0.5 + tol);
        FUZZ_CHECK(vc >= l->v0 + 0.5 - tol && vc <= l->v1 - 0.5 + tol);
    }
    FUZZ_CHECK(sum == total);
    FUZZ_CHECK(top >= (1 << 30));
    /* covering: every lit pixel is in exactly one region (disjointness makes it at most one) */
    for (uint32_t v = 0; v < h; ++v)
        for (uint32_t u = 0; u < w; ++u) {
            if (energy(&lp, u, v, u + 1u, v + 1u) == 0u)
                continue;
            int found = 0;
            for (uint32_t i = 0; i < n; ++i)
                found += L[i].u0 <= u && u < L[i].u1 && L[i].v0 <= v && v < L[i].v1;
            FUZZ_CHECK(found == 1);
        }
    /* the low-memory path (no SAT, a workspace of the minimum): the same lights, bit for bit */
    {
        uint8_t *mbuf = malloc(least + woff);
        qibl_lightprobe_t lm;
        qibl_lightprobe_light_t *M = malloc(max_lights * sizeof *M);
        qibl_lightprobe_result_t rm = {0u, 0};
        FUZZ_CHECK(qibl_lightprobe_build(&lm, &img, build_m, mbuf + woff, least) == QIBL_OK);
        FUZZ_CHECK(energy(&lm, 0, 0, w, h) == total);
        FUZZ_CHECK(qibl_lightprobe_lights(&lm, &opts, M, max_lights, &rm) == QIBL_OK);
        FUZZ_CHECK(rm.count == res.count && rm.rgb_exp == res.rgb_exp && memcmp(M, L, n * sizeof *L) == 0);
        free(M);
        free(mbuf);
    }
    free(L);

    /* the row weights: a mantissa in [2^31, 2^32) within 2^-30 of sin((v + 1/2) pi / h) */
    {
        const uint32_t hh = 1u + (uint32_t)(rb * 131u + w * 7919u) % QIBL_LIGHTPROBE_MAX_DIM;
        const uint32_t vv = (uint32_t)(sb * 257u + h) % hh;
        uint32_t mant = 0;
        int32_t kap = 0;
        FUZZ_CHECK(qibl_lightprobe_row_weight(hh, vv, &mant, &kap) == QIBL_OK);
        FUZZ_CHECK(mant >> 31 == 1u);
        const double s = ldexp((double)mant, -(32 + kap)), ref = sin((vv + 0.5) * PI / hh);
        FUZZ_CHECK(fabs(s - ref) <= ref * ldexp(1.0, -29));
        FUZZ_CHECK(qibl_lightprobe_row_weight(hh, hh, &mant, &kap) == QIBL_E_PROBE_SIZE);
    }
done:
    free(wbuf);
    free(pbuf);
    return 0;
}
