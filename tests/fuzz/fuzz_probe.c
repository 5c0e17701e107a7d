/*
 * fuzz_probe.c - libFuzzer target: SH projection of probes (core/include/qibl/probe.h) and SH
 * rotation (qibl_sh_rotation_init / qibl_sh_rotate of sh.h) on small fuzzed probes in every pixel
 * format.
 *
 * Input: 12 parameter bytes (width, height, format, bands, frac_bits, options, stride padding and
 * offset, row order, light k, scale, rotation mode and bands), then the pixels, then the bytes the
 * row order, the lights, the rotation and the rotated vector take (zeros past the end of the input).
 * Workspaces are malloc'd at exactly qibl_probe_sh_workspace_size (ASan sees any access past them).
 *
 * Invariants (abort on violation): every call returns one of its documented statuses, and exactly
 * the expected one where the inputs decide it (bands, frac_bits, row out of range or added twice,
 * negative or non-finite pixels, unknown window, a workspace one byte short); a failing call leaves
 * its outputs (the projection state and workspace, the coefficients, the light, the rotation)
 * byte for byte untouched; the coefficients do not depend on the row order (rows added in a fuzzed
 * order with repeats and out-of-range rows interleaved, against qibl_probe_sh_project); an all-zero
 * probe gives all-zero coefficients with exp 0, any other has its largest |c| in [2^30, 2^31);
 * qibl_shlight_add_coeffs adds round(c 2^(exp + 16 + scale)) to the first min(k, bands^2)
 * coefficients and nothing else; qibl_shlight_add_probe equals project + add_coeffs; a rotation
 * accepted from fuzzed entries is orthonormal within 2^-16 with det > 0; rotating by the identity
 * gives back the input within sh.h's bound, by R then R^T within twice it plus 1 LSB (the first
 * rounding passes through the second matrix, whose rows' |entries| add up to at most 3).
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "qibl/probe.h"
#include "fuzz_probepx.h"

enum { MAX_W = 16, MAX_H = 8, MAX_OPS = MAX_H + 4 };

static void check_coeffs(const qibl_probe_coeffs_t *c, int bands, int zero)
{
    FUZZ_CHECK(c->bands == bands);
    int64_t top = 0;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < bands * bands; ++i) {
            const int64_t a = c->c[ch][i] < 0 ? -(int64_t)c->c[ch][i] : c->c[ch][i];
            if (a > top)
                top = a;
        }
    if (zero)
        FUZZ_CHECK(top == 0 && c->exp == 0);
    if (top == 0)
        FUZZ_CHECK(c->exp == 0);
    else
        FUZZ_CHECK(top >= (INT64_C(1) << 30) && top < (INT64_C(1) << 31));
}

static int needed_bands(uint32_t k)
{
    int b = 1;
    while ((uint32_t)(b * b) < k)
        ++b;
    return b;
}

/* a Q2.30 unit vector from two fuzzed angles */
static void unit_dir(uint16_t a, uint16_t b, qibl_q30_t d[3])
{
    const double th = a * (3.14159265358979323846 / 65535.0), ph = b * (6.28318530717958647692 / 65536.0);
    d[0] = (qibl_q30_t)lrint(sin(th) * cos(ph) * 1073741824.0);
    d[1] = (qibl_q30_t)lrint(sin(th) * sin(ph) * 1073741824.0);
    d[2] = (qibl_q30_t)lrint(cos(th) * 1073741824.0);
}

static void fuzz_rotation(fuzz_in *in);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    const uint32_t w = 1u + fuzz_u8(&in) % MAX_W, h = 1u + fuzz_u8(&in) % MAX_H;
    const qibl_lightprobe_format_t fmt = (qibl_lightprobe_format_t)(fuzz_u8(&in) % QIBL_LIGHTPROBE_FORMAT_COUNT);
    const int bands = fuzz_u8(&in) % 7; /* 0 and 6: refused */
    const int32_t frac_bits = (int32_t)(int8_t)fuzz_u8(&in) * 2; /* -256..254: some out of range */
    const uint8_t ob = fuzz_u8(&in);
    qibl_probe_sh_opts_t opts;
    opts.irradiance = ob & 1u;
    opts.window = (qibl_probe_window_t)((ob >> 1) % (QIBL_PROBE_WINDOW_COUNT + 1)); /* COUNT: refused */
    opts.scale_log2 = (int32_t)(int8_t)fuzz_u8(&in) * 5; /* -640..635: some beyond 512 */
    const uint8_t sb = fuzz_u8(&in);

    const size_t pb = fmt == QIBL_LIGHTPROBE_RGBE || fmt == QIBL_LIGHTPROBE_SRGBE ? 4u : 12u;
    const size_t row = pb * w, stride = row + 4u * (sb & 3u);
    const size_t span = stride * (h - 1u) + row;
    const size_t poff = pb == 4u ? (sb >> 2 & 1u) : 0u;
    uint8_t *pbuf = malloc(span + poff), *pix = pbuf + poff;
    int all_zero = 1, row_bad[MAX_H] = {0};
    for (uint32_t v = 0; v < h; ++v) {
        int nf_row = 0, neg_row = 0;
        for (uint32_t u = 0; u < w; ++u) {
            uint8_t *p = pix + v * stride + u * pb;
            for (size_t i = 0; i < pb; ++i)
                p[i] = fuzz_u8(&in);
            int z, ng, nf;
            classify(p, fmt, &z, &ng, &nf);
            all_zero &= z, neg_row |= ng, nf_row |= nf;
        }
        /* NaN / Inf is reported first */
        row_bad[v] = nf_row ? QIBL_E_PROBE_NOT_FINITE : neg_row ? QIBL_E_PROBE_NEGATIVE : QIBL_OK;
    }
    for (uint32_t v = 0; v + 1u < h; ++v) /* stride padding must not matter */
        memset(pix + v * stride + row, 0xFF, stride - row);
    int any_bad = 0;
    for (uint32_t v = 0; v < h; ++v)
        any_bad |= row_bad[v] != QIBL_OK;

    const size_t need = qibl_probe_sh_workspace_size(w, h);
    FUZZ_CHECK(need > 0);
    uint8_t *ws = malloc(need), *ws0 = malloc(need);
    const int params_ok = bands >= 1 && bands <= QIBL_SH_MAX_BANDS && frac_bits >= -128 && frac_bits <= 128;

    /* ---- row by row, in a fuzzed order with repeats and out-of-range rows ---- */
    qibl_probe_sh_t ps, ps0;
    memset(&ps, 0x5A, sizeof ps);
    ps0 = ps;
    if (params_ok) /* one byte short is refused, ps untouched */
        FUZZ_CHECK(qibl_probe_sh_begin(&ps, w, h, fmt, frac_bits, bands, ws, need - 1u) == QIBL_E_WORKSPACE &&
                   memcmp(&ps, &ps0, sizeof ps) == 0);
    qibl_status_t st = qibl_probe_sh_begin(&ps, w, h, fmt, frac_bits, bands, ws, need);
    const qibl_status_t begin_st = bands < 1 || bands > QIBL_SH_MAX_BANDS ? QIBL_E_BAD_BANDS
                                   : !params_ok                          ? QIBL_E_PROBE_FORMAT
                                                                         : QIBL_OK;
    FUZZ_CHECK(st == begin_st);
    qibl_probe_coeffs_t ca, cb, c0;
    memset(&ca, 0x3C, sizeof ca);
    memset(&cb, 0x3C, sizeof cb);
    c0 = ca;
    if (st != QIBL_OK) {
        FUZZ_CHECK(memcmp(&ps, &ps0, sizeof ps) == 0);
    } else {
        uint32_t ops[MAX_OPS], nops = h;
        for (uint32_t v = 0; v < h; ++v)
            ops[v] = v;
        for (uint32_t i = h; i > 1u; --i) { /* Fisher-Yates on fuzzed bytes */
            const uint32_t j = fuzz_u8(&in) % i, t = ops[i - 1u];
            ops[i - 1u] = ops[j], ops[j] = t;
        }
        const uint8_t xb = fuzz_u8(&in);
        for (uint32_t e = 0; e < (xb & 3u); ++e) { /* extra operations at fuzzed places */
            const uint8_t a = fuzz_u8(&in), pos = fuzz_u8(&in);
            const uint32_t r = a & 0x80u ? (a & 0x40u ? UINT32_MAX : h + (a & 0x3Fu)) : (a % h);
            const uint32_t at = pos % (nops + 1u);
            memmove(ops + at + 1u, ops + at, (nops - at) * sizeof ops[0]);
            ops[at] = r, ++nops;
        }
        uint8_t added[MAX_H] = {0};
        int complete = 1;
        for (uint32_t i = 0; i < nops; ++i) {
            const uint32_t v = ops[i];
            const qibl_status_t want = v >= h || added[v] ? QIBL_E_PROBE_ROW : (qibl_status_t)row_bad[v];
            ps0 = ps;
            memcpy(ws0, ws, need);
            st = qibl_probe_sh_add_row(&ps, v, v < h ? pix + v * stride : pix);
            FUZZ_CHECK(st == want);
            if (st != QIBL_OK)
                FUZZ_CHECK(memcmp(&ps, &ps0, sizeof ps) == 0 && memcmp(ws, ws0, need) == 0);
            else
                added[v] = 1;
        }
        for (uint32_t v = 0; v < h; ++v)
            complete &= added[v];
        FUZZ_CHECK(complete == !any_bad);
        /* an unknown window is refused first or after the rows: either way nothing is written */
        st = qibl_probe_sh_finish(&ps, &opts, &ca);
        if (!complete)
            FUZZ_CHECK(st == QIBL_E_PROBE_ROW || (st == QIBL_E_PROBE_METHOD && opts.window == QIBL_PROBE_WINDOW_COUNT));
        else if (opts.window == QIBL_PROBE_WINDOW_COUNT)
            FUZZ_CHECK(st == QIBL_E_PROBE_METHOD);
        else
            FUZZ_CHECK(st == QIBL_OK);
        if (st != QIBL_OK) {
            FUZZ_CHECK(memcmp(&ca, &c0, sizeof ca) == 0);
        } else {
            check_coeffs(&ca, bands, all_zero);
            /* finish again with defaults (finish any number of times) */
            qibl_probe_coeffs_t cd;
            FUZZ_CHECK(qibl_probe_sh_finish(&ps, NULL, &cd) == QIBL_OK);
            check_coeffs(&cd, bands, all_zero);
        }
    }

    /* ---- the same probe resident, rows in order: the same coefficients ---- */
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = pix, img.width = w, img.height = h, img.format = fmt, img.frac_bits = frac_bits;
    img.stride = (sb & 3u) ? stride : 0u;
    const qibl_status_t pst = qibl_probe_sh_project(&img, bands, &opts, ws, need, &cb);
    if (begin_st != QIBL_OK) {
        FUZZ_CHECK(pst == begin_st);
    } else if (any_bad) {
        FUZZ_CHECK(pst == QIBL_E_PROBE_NOT_FINITE || pst == QIBL_E_PROBE_NEGATIVE ||
                   (pst == QIBL_E_PROBE_METHOD && opts.window == QIBL_PROBE_WINDOW_COUNT));
        if (pst != QIBL_E_PROBE_METHOD) { /* the first bad row's status */
            uint32_t v = 0;
            while (row_bad[v] == QIBL_OK)
                ++v;
            FUZZ_CHECK(pst == (qibl_status_t)row_bad[v]);
        }
    } else {
        FUZZ_CHECK(pst == (opts.window == QIBL_PROBE_WINDOW_COUNT ? QIBL_E_PROBE_METHOD : QIBL_OK));
    }
    if (pst != QIBL_OK)
        FUZZ_CHECK(memcmp(&cb, &c0, sizeof cb) == 0);
    else
        FUZZ_CHECK(memcmp(&ca, &cb, sizeof ca) == 0); /* independent of the row order */

    /* ---- into a light ---- */
    const uint32_t k = 1u + fuzz_u8(&in) % QIBL_SH_MAX_COUNT;
    const uint8_t lb = fuzz_u8(&in);
    qibl_shlight_t l, l0, lx;
    FUZZ_CHECK(qibl_shlight_init(&l, k) == QIBL_OK);
    for (int ch = 0; ch < 3; ++ch) /* some big starting values, to reach saturation */
        for (uint32_t i = 0; i < k; ++i) {
            /* negated in 64 bits: -INT32_MIN would overflow int (a finding of this harness, not the core) */
            const int64_t v = (int64_t)(int32_t)(fuzz_u32(&in) >> (lb & 31u)) * ((lb & 0x20u) ? -1 : 1);
            l.c[ch][i] = v > INT32_MAX ? INT32_MAX : (int32_t)v;
        }
    memset(&lx, 0, sizeof lx); /* k = 0: not initialised */
    if (pst == QIBL_OK) {
        const int32_t scale = opts.scale_log2;
        l0 = l;
        st = qibl_shlight_add_coeffs(&l, &cb, scale);
        FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_RANGE || st == QIBL_E_PROBE_SATURATED);
        FUZZ_CHECK((st == QIBL_E_RANGE) == (scale > 512 || scale < -512));
        if (st != QIBL_OK) {
            FUZZ_CHECK(memcmp(&l, &l0, sizeof l) == 0);
        } else {
            const uint32_t n = k < (uint32_t)(bands * bands) ? k : (uint32_t)(bands * bands);
            for (int ch = 0; ch < 3; ++ch)
                for (uint32_t i = 0; i < QIBL_SH_MAX_COUNT; ++i) {
                    if (i >= n) {
                        FUZZ_CHECK(l.c[ch][i] == l0.c[ch][i]);
                        continue;
                    }
                    const long double add = ldexpl((long double)cb.c[ch][i], cb.exp + 16 + scale);
                    const long double got = (long double)l.c[ch][i] - (long double)l0.c[ch][i];
                    FUZZ_CHECK(fabsl(got - add) <= 0.5L);
                }
        }
        FUZZ_CHECK(qibl_shlight_add_coeffs(&lx, &cb, 0) == QIBL_E_SHMAP_K);
        qibl_probe_coeffs_t cbad = cb;
        cbad.bands = (lb & 0x40u) ? 0 : 6;
        l0 = l;
        FUZZ_CHECK(qibl_shlight_add_coeffs(&l, &cbad, 0) == QIBL_E_BAD_BANDS && memcmp(&l, &l0, sizeof l) == 0);
    }

    /* add_probe = project onto the bands k needs + add_coeffs */
    qibl_status_t probe_st;
    {
        qibl_shlight_t lp = l, lq = l;
        st = qibl_shlight_add_probe(&lp, &img, &opts, ws, need);
        qibl_probe_coeffs_t cp;
        qibl_status_t want = qibl_probe_sh_project(&img, needed_bands(k), &opts, ws, need, &cp);
        if (want == QIBL_OK)
            want = qibl_shlight_add_coeffs(&lq, &cp, opts.scale_log2);
        FUZZ_CHECK(st == want);
        probe_st = st;
        FUZZ_CHECK(memcmp(&lp, st == QIBL_OK ? &lq : &l, sizeof lp) == 0);
    }

    /* lights: unit directions, rgb >= 0 */
    {
        qibl_lightprobe_light_t L[4];
        const uint32_t count = fuzz_u8(&in) % 5u;
        const int32_t rgb_exp = (int32_t)(int8_t)fuzz_u8(&in) / 2, scale = (int32_t)(int8_t)fuzz_u8(&in) / 2;
        for (uint32_t i = 0; i < 4u; ++i) {
            const uint16_t a = fuzz_u16(&in), b = fuzz_u16(&in);
            unit_dir(a, b, L[i].dir);
            for (int c = 0; c < 3; ++c)
                L[i].rgb[c] = (int32_t)(fuzz_u32(&in) & 0x7FFFFFFFu);
            const uint8_t r0 = fuzz_u8(&in), r1 = fuzz_u8(&in);
            L[i].u0 = r0 % (w + 1u), L[i].u1 = L[i].u0 + 1u + (r0 >> 4) % (w + 1u); /* may pass the edge */
            L[i].v0 = r1 % (h + 1u), L[i].v1 = L[i].v0 + 1u + (r1 >> 4) % (h + 1u);
        }
        qibl_shlight_t ll = l;
        l0 = l;
        st = qibl_shlight_add_lights(&ll, L, count, rgb_exp, scale);
        FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_PROBE_SATURATED);
        if (st != QIBL_OK)
            FUZZ_CHECK(memcmp(&ll, &l0, sizeof ll) == 0);
        else if (count == 0u)
            FUZZ_CHECK(memcmp(&ll, &l0, sizeof ll) == 0);
        FUZZ_CHECK(qibl_shlight_add_lights(&ll, L, 65537u, rgb_exp, scale) == QIBL_E_PROBE_COUNT);
        FUZZ_CHECK(qibl_shlight_add_lights(&lx, L, count, rgb_exp, scale) == QIBL_E_SHMAP_K);

        /* sun + sky */
        const uint32_t sc = count > 2u ? 2u : count;
        int rect_bad = 0;
        for (uint32_t i = 0; i < sc; ++i)
            rect_bad |= L[i].u1 > w || L[i].v1 > h;
        ll = l;
        st = qibl_shlight_add_sun_sky(&ll, &img, &opts, L, sc, rgb_exp, ws, need);
        FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_PROBE_RECT || st == QIBL_E_PROBE_SATURATED ||
                   st == QIBL_E_RANGE || st == QIBL_E_PROBE_COUNT || st == probe_st);
        if (probe_st != QIBL_OK && probe_st != QIBL_E_PROBE_SATURATED) /* the probe itself is refused */
            FUZZ_CHECK(st == probe_st || st == QIBL_E_PROBE_RECT);
        if (rect_bad)
            FUZZ_CHECK(st != QIBL_OK);
        if (st != QIBL_OK)
            FUZZ_CHECK(memcmp(&ll, &l, sizeof ll) == 0);
        else if (sc == 0u) { /* no sun: the sky is the whole probe */
            qibl_shlight_t lp = l;
            FUZZ_CHECK(qibl_shlight_add_probe(&lp, &img, &opts, ws, need) == QIBL_OK);
            FUZZ_CHECK(memcmp(&lp, &ll, sizeof lp) == 0);
        }
    }

    fuzz_rotation(&in);
    free(ws0);
    free(ws);
    free(pbuf);
    return 0;
}

/* ---- SH rotation --------------------------------------------------------------------------- */

static double rot_bound(const int32_t *in, int l)
{
    double m = 0;
    for (int i = l * l; i < (l + 1) * (l + 1); ++i)
        if (fabs((double)in[i]) > m)
            m = fabs((double)in[i]);
    return 0.5 + 3.0 * ldexp(m, -24);
}

static void fuzz_rotation(fuzz_in *in)
{
    const uint8_t mode = fuzz_u8(in) % 4u;
    const int bands = fuzz_u8(in) % 7; /* 0 and 6: refused */
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    qibl_q30_t q[3][3], qt[3][3];
    if (mode == 1) { /* a signed permutation with det +1 */
        static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        static const int odd[6] = {0, 1, 1, 0, 0, 1};
        const uint8_t b = fuzz_u8(in);
        const int p = b % 6;
        double sgn[3] = {b & 8 ? -1 : 1, b & 16 ? -1 : 1, 1};
        sgn[2] = sgn[0] * sgn[1] * (odd[p] ? -1 : 1);
        memset(r, 0, sizeof r);
        for (int i = 0; i < 3; ++i)
            r[i][perm[p][i]] = sgn[i];
    } else if (mode == 2) { /* axis-angle (Rodrigues) */
        qibl_q30_t ax[3];
        const uint16_t a = fuzz_u16(in), b = fuzz_u16(in);
        unit_dir(a, b, ax);
        const double t = fuzz_u16(in) * (6.28318530717958647692 / 65536.0), c = cos(t), s = sin(t);
        double x = ldexp(ax[0], -30), y = ldexp(ax[1], -30), z = ldexp(ax[2], -30);
        const double n = sqrt(x * x + y * y + z * z);
        x /= n, y /= n, z /= n;
        const double R[3][3] = {{c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s},
                                {y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s},
                                {z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)}};
        memcpy(r, R, sizeof r);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            q[i][j] = (qibl_q30_t)lrint(ldexp(r[i][j], 30));
    if (mode == 3) /* any entries: mostly not a rotation */
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                q[i][j] = (qibl_q30_t)fuzz_u32(in);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            qt[i][j] = q[j][i];

    qibl_sh_rotation_t rot, rot0, rt;
    memset(&rot, 0x77, sizeof rot);
    rot0 = rot;
    qibl_status_t st = qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])q, bands);
    if (bands < 1 || bands > QIBL_SH_MAX_BANDS)
        FUZZ_CHECK(st == QIBL_E_BAD_BANDS);
    else if (mode != 3)
        FUZZ_CHECK(st == QIBL_OK);
    else
        FUZZ_CHECK(st == QIBL_OK || st == QIBL_E_SH_ROTATION);
    if (st != QIBL_OK) {
        FUZZ_CHECK(memcmp(&rot, &rot0, sizeof rot) == 0);
        int32_t a[QIBL_SH_MAX_COUNT] = {0}, b[QIBL_SH_MAX_COUNT];
        memset(b, 0x11, sizeof b);
        memset(&rot, 0, sizeof rot); /* not initialised: refused, out untouched */
        FUZZ_CHECK(qibl_sh_rotate(&rot, a, b) == QIBL_E_BAD_BANDS && b[0] == 0x11111111);
        return;
    }
    if (mode == 3) { /* accepted: orthonormal within 2^-16 per entry of r r^T - I, det > 0 */
        double d[3][3], dev = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                d[i][j] = ldexp(q[i][j], -30);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double s = i == j ? -1.0 : 0.0;
                for (int c = 0; c < 3; ++c)
                    s += d[i][c] * d[j][c];
                if (fabs(s) > dev)
                    dev = fabs(s);
            }
        const double det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                           d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                           d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        FUZZ_CHECK(dev <= ldexp(1.0, -16) * (1 + 1e-6) && det > 0);
    }

    /* a vector small enough that no rotated band saturates (a band's norm is kept: <= 3 max) */
    int32_t v[QIBL_SH_MAX_COUNT], o[QIBL_SH_MAX_COUNT], back[QIBL_SH_MAX_COUNT];
    const uint8_t sh = fuzz_u8(in);
    for (int i = 0; i < QIBL_SH_MAX_COUNT; ++i) {
        const uint32_t u = fuzz_u32(in);
        const int32_t m = (int32_t)((u & 0x1FFFFFFFu) >> (sh % 30u));
        v[i] = u >> 31 ? -m : m;
    }
    memset(o, 0, sizeof o);
    FUZZ_CHECK(qibl_sh_rotate(&rot, v, o) == QIBL_OK);
    if (mode == 0) /* identity */
        for (int l = 0; l < bands; ++l)
            for (int i = l * l; i < (l + 1) * (l + 1); ++i)
                FUZZ_CHECK(fabs((double)o[i] - v[i]) <= rot_bound(v, l));
    if (mode != 3) { /* R, then R^T */
        FUZZ_CHECK(qibl_sh_rotation_init(&rt, (const qibl_q30_t(*)[3])qt, bands) == QIBL_OK);
        FUZZ_CHECK(qibl_sh_rotate(&rt, o, back) == QIBL_OK);
        for (int l = 0; l < bands; ++l)
            for (int i = l * l; i < (l + 1) * (l + 1); ++i)
                FUZZ_CHECK(fabs((double)back[i] - v[i]) <= 2.0 * rot_bound(v, l) + 1.0);
    }

    /* the light's rotation: refused when rot has fewer bands than k needs */
    const uint32_t k = 1u + fuzz_u8(in) % QIBL_SH_MAX_COUNT;
    qibl_shlight_t l, l0;
    FUZZ_CHECK(qibl_shlight_init(&l, k) == QIBL_OK);
    for (int ch = 0; ch < 3; ++ch)
        for (uint32_t i = 0; i < k; ++i)
            l.c[ch][i] = v[(i + (uint32_t)ch) % k];
    l0 = l;
    st = qibl_shlight_rotate(&l, &rot);
    if (needed_bands(k) > bands)
        FUZZ_CHECK(st == QIBL_E_BAD_BANDS && memcmp(&l, &l0, sizeof l) == 0);
    else
        FUZZ_CHECK(st == QIBL_OK);
}
