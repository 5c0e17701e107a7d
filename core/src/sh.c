/*
 * sh.c - real SH basis (bands 0..4) from a direction, integer only.
 *
 * Method. Y(l,m) = P(l,|m|)(z) * T_m(x, y), where
 *   T_m = Re (x + iy)^m = sin^m t cos(m p) for m > 0, Im (x + iy)^m for m < 0, 1 for m = 0,
 *   P(l,m)(z) = N(l,m) Q(l,m)(z) / sin^m t (with the 1/sqrt(2) for m = 0): a polynomial in z.
 * T_m comes from the complex-power recurrence, P from the normalised Legendre recurrence
 *   P(m,m) = K(m),  P(m+1,m) = A(m+1,m) z P(m,m),  P(l,m) = A(l,m) z P(l-1,m) - B(l,m) P(l-2,m)
 * whose constants fold N in, so every intermediate stays below 3 in magnitude:
 *   K(0) = 1/(2 sqrt(pi)), K(m) = (-1)^m (2m-1)!! sqrt((2l+1)/(2 pi (2m)!)) for m > 0,
 *   A(m+1,m) = sqrt(2m+3), A(l,m) = sqrt((4l^2-1)/(l^2-m^2)),
 *   B(l,m) = sqrt((2l+1)((l-1)^2-m^2) / ((2l-3)(l^2-m^2))).
 * Formats: unit vector and T_m in Q2.30 (|T_m| <= 1); constants and P in Q3.29 (max |P| = 2.84 at
 * l=4, m=2); every step is one exact 64-bit sum of products rounded once (half up), so each P or T
 * carries at most a few LSB of rounding, far inside the 2^-25 bound sh.h states.
 */
#include "qibl/sh.h"
#include "qibli.h"

#if QIBL_USE_SH

/* {A or K, B} in Q3.29 (round half up of the double value), at index l(l+1)/2 + m, m <= l.
 * Row l == m holds K(m); row l == m+1 holds A(m+1,m) and B = 0. */
static const int32_t sh_rec[15][2] = {
    {  151448488,          0 }, /* l=0 m=0: K  0.282094791774 */
    {  929887697,          0 }, /* l=1 m=0: A  1.732050807569 */
    { -262316476,          0 }, /* l=1 m=1: K -0.488602511903 */
    { 1039646051,  600239927 }, /* l=2 m=0: A  1.936491673104, B 1.118033988750 */
    { 1200479854,          0 }, /* l=2 m=1: A  2.236067977500 */
    {  293278736,          0 }, /* l=2 m=2: K  0.546274215296 */
    { 1058723716,  546722576 }, /* l=3 m=0: A  1.972026594367, B 1.018350154435 */
    { 1122946079,  502196753 }, /* l=3 m=1: A  2.091650066335, B 0.935414346693 */
    { 1420426919,          0 }, /* l=3 m=2: A  2.645751311065 */
    { -316777240,          0 }, /* l=3 m=3: K -0.590043589927 */
    { 1065320189,  540215934 }, /* l=4 m=0: A  1.984313483298, B 1.006230589875 */
    { 1100257961,  526023917 }, /* l=4 m=1: A  2.049390153192, B 0.979795897113 */
    { 1230125796,  464943848 }, /* l=4 m=2: A  2.291287847478, B 0.866025403784 */
    { 1610612736,          0 }, /* l=4 m=3: A  3.000000000000 */
    {  335993002,          0 }, /* l=4 m=4: K  0.625835735449 */
};

qibl_status_t qibl_sh_eval_unit(const qibl_q30_t u[3], int bands, qibl_q30_t *out)
{
    if (u == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (bands < 1 || bands > QIBL_SH_MAX_BANDS)
        return QIBL_E_BAD_BANDS;
    const qibl_q30_t x = u[0], y = u[1], z = u[2];
    qibl_q30_t c = QIBL_Q30_ONE, s = 0; /* T_m, T_-m for the current m */
    for (int m = 0; m < bands; ++m) {
        if (m > 0) { /* (c + is)(x + iy) */
            qibl_q30_t c2 = qibli_rshr_s64(qibl_mul_s32_s64(x, c) - qibl_mul_s32_s64(y, s), 30);
            s = qibli_rshr_s64(qibl_mul_s32_s64(x, s) + qibl_mul_s32_s64(y, c), 30);
            c = c2;
        }
        qibl_q29_t p2 = 0, p1 = sh_rec[m * (m + 1) / 2 + m][0]; /* P(l-2,m), P(l-1,m) */
        for (int l = m; l < bands; ++l) {
            if (l > m) {
                const int32_t *k = sh_rec[l * (l + 1) / 2 + m];
                qibl_q29_t az = qibli_rshr_s64(qibl_mul_s32_s64(k[0], z), 30); /* |A z| <= 3 */
                qibl_q29_t p = qibli_rshr_s64(qibl_mul_s32_s64(az, p1) - qibl_mul_s32_s64(k[1], p2), 29);
                p2 = p1;
                p1 = p;
            }
            qibl_q30_t *o = out + l * l + l;
            if (m == 0) {
                o[0] = qibl_sat_s32((int64_t)p1 * 2); /* Q3.29 -> Q2.30: |P(l,0)| <= 0.85 */
            } else {
                o[m] = qibli_rshr_s64(qibl_mul_s32_s64(p1, c), 29);
                o[-m] = qibli_rshr_s64(qibl_mul_s32_s64(p1, s), 29);
            }
        }
    }
    return QIBL_OK;
}

qibl_status_t qibl_sh_eval(const qibl_q16_t dir[3], int bands, qibl_q30_t *out)
{
    if (dir == 0 || out == 0)
        return QIBL_E_NULL_POINTER;
    if (bands < 1 || bands > QIBL_SH_MAX_BANDS)
        return QIBL_E_BAD_BANDS;
    qibl_q30_t u[3];
    qibl_status_t st = qibl_vec3_normalize_q30(dir, u);
    if (st != QIBL_OK)
        return st;
    return qibl_sh_eval_unit(u, bands, out);
}

#else
typedef int qibl_sh_disabled_t; /* ISO C forbids an empty translation unit */
#endif /* QIBL_USE_SH */
