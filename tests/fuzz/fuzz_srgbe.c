/*
 * fuzz_srgbe.c - libFuzzer target: every sRGBE entry point (core/include/qibl/srgbe.h).
 *
 * Input: a 16-bit frac_bits, then records of 12 bytes, each read three ways: as three binary32 bit
 * patterns (encode_f32), as three int32 (encode_s32 / _q16) and as three 4-byte codes (decode_*).
 *
 * Invariants (srgbe.h, checked against double-precision or exact integer references):
 *   encode: NaN -> QIBL_E_SRGBE_NAN and the zero code; Inf -> QIBL_E_SRGBE_INF with E = 255 and
 *   the infinite channels at X = 255 / 0; |max| >= 2^128 -> QIBL_E_SRGBE_OVERFLOW with E = 255;
 *   |max| < 2^-128 -> the zero code, signs kept; otherwise E = floor(log2 max) + 2 + 126 and every
 *   channel within 2^e / 510 of its decoded value; negating every channel maps X to 255 - X;
 *   q16 = s32 with frac_bits 16.
 *   decode_f32: the correctly rounded binary32 of (2X - 255) 2^(E - 126) / 510 (half an ulp),
 *   +-FLT_MAX and QIBL_E_SRGBE_DECODE_SAT only for E = 255, X in {0, 255}; never Inf, NaN or -0.
 *   decode_s32: exactly round-half-up((2X - 255) 2^(E - 126 + frac_bits) / 510), saturated with
 *   QIBL_E_SRGBE_DECODE_SAT; q16 = s32 with 16.
 *   bulk (_n) calls: the same bytes as one-pixel calls, the most severe status; one-pixel calls
 *   give the same result when input and output overlap.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "qibl/srgbe.h"

enum { MAX_PIX = 64 };

static float f32(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static int is_nan(uint32_t u)
{
    return (u & 0x7F800000u) == 0x7F800000u && (u & 0x7FFFFFu);
}

static int is_inf(uint32_t u)
{
    return (u & 0x7FFFFFFFu) == 0x7F800000u;
}

static double decoded(const uint8_t *code, int c)
{
    return ldexp((2.0 * code[c] - 255.0) / 510.0, (int)code[3] - 126);
}

/* finite channels: E from the largest, every channel within half a step */
static void check_in_range(const double *c, const uint8_t *code)
{
    double mx = 0.0;
    for (int i = 0; i < 3; ++i)
        mx = fmax(mx, fabs(c[i]));
    int ex;
    frexp(mx, &ex); /* mx = m 2^ex, m in [1/2, 1): floor(log2 mx) = ex - 1 */
    FUZZ_CHECK(code[3] == ex + 1 + 126);
    const double step = ldexp(1.0 / 510.0, (int)code[3] - 126);
    for (int i = 0; i < 3; ++i)
        FUZZ_CHECK(fabs(c[i] - decoded(code, i)) <= step * (1.0 + 1e-12));
}

static int sev_enc(qibl_status_t s)
{
    return s == QIBL_E_SRGBE_NAN ? 3 : s == QIBL_E_SRGBE_INF ? 2 : s == QIBL_E_SRGBE_OVERFLOW ? 1 : 0;
}

static void check_encode_f32(const uint32_t rgb[3], const uint8_t code[4], qibl_status_t st)
{
    int nan = is_nan(rgb[0]) || is_nan(rgb[1]) || is_nan(rgb[2]);
    int inf = is_inf(rgb[0]) || is_inf(rgb[1]) || is_inf(rgb[2]);
    if (nan) {
        FUZZ_CHECK(st == QIBL_E_SRGBE_NAN);
        FUZZ_CHECK(code[0] == 128 && code[1] == 128 && code[2] == 128 && code[3] == 0);
        return;
    }
    if (inf) {
        FUZZ_CHECK(st == QIBL_E_SRGBE_INF && code[3] == 255);
        for (int i = 0; i < 3; ++i)
            if (is_inf(rgb[i]))
                FUZZ_CHECK(code[i] == (rgb[i] >> 31 ? 0 : 255));
        return;
    }
    FUZZ_CHECK(st == QIBL_OK);
    double c[3], mx = 0.0;
    for (int i = 0; i < 3; ++i) {
        c[i] = (double)f32(rgb[i]);
        mx = fmax(mx, fabs(c[i]));
    }
    if (mx < ldexp(1.0, -128)) {
        for (int i = 0; i < 3; ++i)
            FUZZ_CHECK(code[i] == (rgb[i] >> 31 ? 127 : 128));
        FUZZ_CHECK(code[3] == 0);
        return;
    }
    check_in_range(c, code);
}

static void check_encode_s32(const int32_t rgb[3], int fb, const uint8_t code[4], qibl_status_t st)
{
    int lg = INT32_MIN; /* floor(log2 max|c|) */
    for (int i = 0; i < 3; ++i) {
        uint32_t m = rgb[i] < 0 ? 0u - (uint32_t)rgb[i] : (uint32_t)rgb[i];
        if (m) {
            int b = 31;
            while (!(m >> b))
                --b;
            if (b - fb > lg)
                lg = b - fb;
        }
    }
    if (lg != INT32_MIN && lg >= 128) {
        FUZZ_CHECK(st == QIBL_E_SRGBE_OVERFLOW && code[3] == 255);
        for (int i = 0; i < 3; ++i) {
            uint32_t m = rgb[i] < 0 ? 0u - (uint32_t)rgb[i] : (uint32_t)rgb[i];
            int b = 31;
            while (m && !(m >> b))
                --b;
            if (m && b - fb >= 128) /* at or above 2^128: the largest code of its sign */
                FUZZ_CHECK(code[i] == (rgb[i] < 0 ? 0 : 255));
        }
        return;
    }
    FUZZ_CHECK(st == QIBL_OK);
    if (lg == INT32_MIN || lg < -128) {
        for (int i = 0; i < 3; ++i)
            FUZZ_CHECK(code[i] == (rgb[i] < 0 ? 127 : 128));
        FUZZ_CHECK(code[3] == 0);
        return;
    }
    if (fb < -900 || fb > 900)
        return; /* the values leave double's exponent range; the exponent check above still ran */
    double c[3];
    for (int i = 0; i < 3; ++i)
        c[i] = ldexp((double)rgb[i], -fb);
    check_in_range(c, code);
}

static void check_decode_f32(const uint8_t code[4], const uint32_t rgb[3], qibl_status_t st)
{
    int sat = 0;
    for (int i = 0; i < 3; ++i) {
        FUZZ_CHECK(!is_nan(rgb[i]) && !is_inf(rgb[i]) && rgb[i] != 0x80000000u);
        if (code[3] == 255 && (code[i] == 0 || code[i] == 255)) {
            FUZZ_CHECK(rgb[i] == (code[i] ? 0x7F7FFFFFu : 0xFF7FFFFFu));
            sat = 1;
            continue;
        }
        const double want = decoded(code, i), got = (double)f32(rgb[i]);
        int ex;
        frexp(fabs(want), &ex);
        const double half_ulp = ldexp(1.0, (ex - 1 < -126 ? -126 : ex - 1) - 24);
        FUZZ_CHECK(fabs(got - want) <= half_ulp * (1.0 + 1e-6));
    }
    FUZZ_CHECK(st == (sat ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK));
}

static __int128 floor_div(__int128 a, __int128 d) /* d > 0 */
{
    __int128 q = a / d;
    return (a % d != 0 && a < 0) ? q - 1 : q;
}

static void check_decode_s32(const uint8_t code[4], int fb, const int32_t rgb[3], qibl_status_t st)
{
    int sat = 0;
    const long s = (long)code[3] - 126 + fb;
    for (int i = 0; i < 3; ++i) {
        const __int128 m = 2 * (__int128)code[i] - 255; /* odd: never 0 */
        __int128 r;
        if (s > 40)
            r = m > 0 ? (__int128)INT64_MAX : (__int128)INT64_MIN; /* |value| >= 2^41 / 510 */
        else if (s >= 0)
            r = floor_div(m * ((__int128)1 << s) + 255, 510);
        else if (s >= -100)
            r = floor_div(m + 255 * ((__int128)1 << -s), 510 * ((__int128)1 << -s));
        else
            r = 0; /* |value| < 2^-90 */
        if (r > INT32_MAX)
            r = INT32_MAX, sat = 1;
        else if (r < INT32_MIN)
            r = INT32_MIN, sat = 1;
        FUZZ_CHECK(rgb[i] == (int32_t)r);
    }
    FUZZ_CHECK(st == (sat ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in = {data, size};
    const int fb = (int)(int16_t)fuzz_u16(&in);
    const size_t n = in.n / 12 < MAX_PIX ? in.n / 12 : MAX_PIX;
    if (n == 0)
        return 0;
    uint32_t *fin = malloc(12 * n), *fout = malloc(12 * n), *fout_n = malloc(12 * n);
    int32_t *sin_ = malloc(12 * n), *sout = malloc(12 * n), *sout_n = malloc(12 * n);
    uint8_t *cf = malloc(4 * n), *cs = malloc(4 * n), *cq = malloc(4 * n), *c_n = malloc(4 * n);
    const uint8_t *codes = in.p; /* 3n codes of 4 bytes: the same 12n bytes */
    memcpy(fin, in.p, 12 * n);
    memcpy(sin_, in.p, 12 * n);
    int sev_f = 0, sev_s = 0, sev_q = 0, sat_df = 0, sat_ds = 0, sat_dq = 0;

    for (size_t p = 0; p < n; ++p) {
        /* encode f32, its sign symmetry, and in place */
        qibl_status_t st = qibl_srgbe_encode_f32(fin + 3 * p, cf + 4 * p);
        check_encode_f32(fin + 3 * p, cf + 4 * p, st);
        sev_f = sev_enc(st) > sev_f ? sev_enc(st) : sev_f;
        uint32_t neg[3], buf[3];
        uint8_t cn[4];
        for (int i = 0; i < 3; ++i)
            neg[i] = fin[3 * p + (size_t)i] ^ 0x80000000u;
        FUZZ_CHECK(qibl_srgbe_encode_f32(neg, cn) == st);
        if (st != QIBL_E_SRGBE_NAN)
            for (int i = 0; i < 3; ++i)
                FUZZ_CHECK(cn[i] == 255 - cf[4 * p + (size_t)i] && cn[3] == cf[4 * p + 3]);
        memcpy(buf, fin + 3 * p, 12);
        FUZZ_CHECK(qibl_srgbe_encode_f32(buf, (uint8_t *)buf) == st && memcmp(buf, cf + 4 * p, 4) == 0);

        /* encode s32 at the fuzzed frac_bits, q16 */
        st = qibl_srgbe_encode_s32(sin_ + 3 * p, fb, cs + 4 * p);
        check_encode_s32(sin_ + 3 * p, fb, cs + 4 * p, st);
        sev_s = sev_enc(st) > sev_s ? sev_enc(st) : sev_s;
        uint8_t c16[4];
        qibl_status_t s16 = qibl_srgbe_encode_s32(sin_ + 3 * p, 16, c16);
        st = qibl_srgbe_encode_q16(sin_ + 3 * p, cq + 4 * p);
        FUZZ_CHECK(st == s16 && memcmp(c16, cq + 4 * p, 4) == 0 && st == QIBL_OK);
        sev_q = sev_enc(st) > sev_q ? sev_enc(st) : sev_q;
    }
    for (size_t p = 0; p < 3 * n; ++p) {
        /* decode each 4-byte code: f32, s32 at the fuzzed frac_bits, q16, and in place */
        const uint8_t *code = codes + 4 * p;
        qibl_status_t st = qibl_srgbe_decode_f32(code, fout + 3 * (p % n));
        check_decode_f32(code, fout + 3 * (p % n), st);
        uint32_t buf[3];
        memcpy(buf, code, 4);
        FUZZ_CHECK(qibl_srgbe_decode_f32((const uint8_t *)buf, buf) == st && memcmp(buf, fout + 3 * (p % n), 12) == 0);
        if (p < n)
            sat_df |= st != QIBL_OK;
        st = qibl_srgbe_decode_s32(code, fb, sout + 3 * (p % n));
        check_decode_s32(code, fb, sout + 3 * (p % n), st);
        if (p < n)
            sat_ds |= st != QIBL_OK;
        int32_t q[3], r16[3];
        qibl_status_t s16 = qibl_srgbe_decode_s32(code, 16, r16);
        FUZZ_CHECK(qibl_srgbe_decode_q16(code, q) == s16 && memcmp(q, r16, 12) == 0);
        if (p < n)
            sat_dq |= s16 != QIBL_OK;
    }
    /* bulk calls over the first n codes / pixels: the same bytes, the most severe status.
     * (fout and sout hold pixels n..3n-1 decoded last: recompute the first n for the compare) */
    for (size_t p = 0; p < n; ++p) {
        QIBL_DROP_STATUS(qibl_srgbe_decode_f32(codes + 4 * p, fout + 3 * p));
        QIBL_DROP_STATUS(qibl_srgbe_decode_s32(codes + 4 * p, fb, sout + 3 * p));
    }
    static const qibl_status_t enc_st[4] = {QIBL_OK, QIBL_E_SRGBE_OVERFLOW, QIBL_E_SRGBE_INF, QIBL_E_SRGBE_NAN};
    FUZZ_CHECK(qibl_srgbe_encode_f32_n(fin, n, c_n) == enc_st[sev_f] && memcmp(c_n, cf, 4 * n) == 0);
    FUZZ_CHECK(qibl_srgbe_encode_s32_n(sin_, n, fb, c_n) == enc_st[sev_s] && memcmp(c_n, cs, 4 * n) == 0);
    FUZZ_CHECK(qibl_srgbe_encode_q16_n(sin_, n, c_n) == enc_st[sev_q] && memcmp(c_n, cq, 4 * n) == 0);
    FUZZ_CHECK(qibl_srgbe_decode_f32_n(codes, n, fout_n) == (sat_df ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK) &&
               memcmp(fout_n, fout, 12 * n) == 0);
    FUZZ_CHECK(qibl_srgbe_decode_s32_n(codes, n, fb, sout_n) == (sat_ds ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK) &&
               memcmp(sout_n, sout, 12 * n) == 0);
    for (size_t p = 0; p < n; ++p)
        QIBL_DROP_STATUS(qibl_srgbe_decode_q16(codes + 4 * p, sout + 3 * p));
    FUZZ_CHECK(qibl_srgbe_decode_q16_n(codes, n, sout_n) == (sat_dq ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK) &&
               memcmp(sout_n, sout, 12 * n) == 0);
    /* NULL pointers write nothing, even for n = 0 */
    FUZZ_CHECK(qibl_srgbe_encode_f32_n(NULL, 0, c_n) == QIBL_E_NULL_POINTER);
    FUZZ_CHECK(qibl_srgbe_decode_s32_n(codes, 0, fb, NULL) == QIBL_E_NULL_POINTER);

    free(fin), free(fout), free(fout_n), free(sin_), free(sout), free(sout_n);
    free(cf), free(cs), free(cq), free(c_n);
    return 0;
}
