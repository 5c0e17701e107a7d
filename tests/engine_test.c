/*
 * engine_test.c - tools/engine: each preset against values derived here, in double, from each
 * source's own formulas, not from qibl's output:
 *   filament  cmgen's pipeline written out again: the equirect read through cmgen's toRectilinear
 *             after its x mirror, its basis (Legendre recurrences with the Condon-Shortley phase,
 *             K(l,m) and sqrt 2), computeTruncatedCosSh's A_l, sincWindow, preprocessSHForShader's
 *             constants / pi; every coefficient within 0.5 %; the auto window replayed where the
 *             bisection's path is known (no ringing) and checked where it is not (ringing removed).
 *   unity     ShadeSH9's formula (UnityCG.cginc) on the packed constants at many normals, with the
 *             skybox's ToRadialCoords placement, against the probe's irradiance by quadrature
 *             (exact for a band-limited sky; within the SH9 truncation for a lobe).
 *   gltf      the fragment parsed as JSON here, its coefficients evaluated as irradiance SH in glTF's
 *             frame; KHR_lights_punctual nodes' -z against the lights.
 * Skies: a smooth lobe off every axis, a constant, a degree-2 gradient; the synthetic probes go
 * through the core's projection (qibl_probe_sh_project) as `qibl sh project` does. Three real
 * probes of ../shared/fixtures/probes when present (skipped otherwise).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "engine/engine.h"
#include "io/hdr.h"
#include "qibl/probe.h"
#include "testutil.h"

/* ---- skies (qibl's frame) -------------------------------------------------------------------- */

enum { SKY_LOBE, SKY_CONST, SKY_GRAD, SKY_LOBE_YAWED };
static const double lobe_a[3] = {0.48, -0.36, 0.8}; /* normalised below; off every axis and plane */
static const double yaw_deg = 70.0;

static void unit(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= n, v[1] /= n, v[2] /= n;
}

static void sky(int kind, const double q[3], double L[3])
{
    static const double col[3] = {1.0, 0.7, 0.4};
    double a[3] = {lobe_a[0], lobe_a[1], lobe_a[2]};
    unit(a);
    if (kind == SKY_LOBE_YAWED) { /* the lobe turned about +z by yaw_deg (+x toward +y) */
        double t = yaw_deg * M_PI / 180.0, x = a[0], y = a[1];
        a[0] = cos(t) * x - sin(t) * y, a[1] = sin(t) * x + cos(t) * y;
        kind = SKY_LOBE;
    }
    for (int c = 0; c < 3; ++c) {
        if (kind == SKY_LOBE)
            L[c] = 3.0 * col[c] * exp(20.0 * (q[0] * a[0] + q[1] * a[1] + q[2] * a[2] - 1.0)) + 0.001 * col[c];
        else if (kind == SKY_CONST)
            L[c] = 0.5 * col[c];
        else
            L[c] = col[c] * (1.0 + 0.5 * q[2] + 0.3 * q[0] * q[1] - 0.2 * q[1]);
    }
}

/* qibl's pixel direction (lightprobe.h): theta = (v + 1/2) pi / h from +z, phi = (u + 1/2) 2 pi / w */
static void qdir(double u, double v, int w, int h, double q[3])
{
    double t = (v + 0.5) * M_PI / h, p = (u + 0.5) * 2.0 * M_PI / w;
    q[0] = sin(t) * cos(p), q[1] = sin(t) * sin(p), q[2] = cos(t);
}

/* from a fraction (fu, fv) of a lat-long image (fv from the top) to qibl's direction */
static void q_from_uv(double fu, double fv, double q[3])
{
    double t = fv * M_PI, p = fu * 2.0 * M_PI;
    q[0] = sin(t) * cos(p), q[1] = sin(t) * sin(p), q[2] = cos(t);
}

/* cmgen: a direction N of its (mirrored) cubemap looks at the source's (-N.x, N.y, N.z)
 * (CubemapUtils::mirrorCubemap), which toRectilinear reads from the equirect at
 * xf = atan2(x, z) / pi, yf = asin(y) 2 / pi, (xf + 1) / 2 across, (1 - yf) / 2 down. */
static void q_from_cmgen(const double s[3], double q[3])
{
    double n[3] = {-s[0], s[1], s[2]};
    double xf = atan2(n[0], n[2]) / M_PI, yf = asin(fmax(-1.0, fmin(1.0, n[1]))) * 2.0 / M_PI;
    q_from_uv((xf + 1.0) * 0.5, (1.0 - yf) * 0.5, q);
}

/* Unity's panoramic skybox (ToRadialCoords): u = 0.5 - atan2(z, x) / 2 pi, v = 1 - acos(y) / pi,
 * with v = 1 the image's top row */
static void q_from_unity(const double n[3], double q[3])
{
    double u = 0.5 - atan2(n[2], n[0]) / (2.0 * M_PI), v = 1.0 - acos(fmax(-1.0, fmin(1.0, n[1]))) / M_PI;
    q_from_uv(u - floor(u), 1.0 - v, q);
}

/* ---- quadrature over the sphere -------------------------------------------------------------- */

enum { QT = 256, QP = 512 };
typedef struct {
    double (*d)[3], (*L)[3], *w;
    int n;
} quad;

static void quad_init(quad *Q, int kind)
{
    Q->n = QT * QP;
    Q->d = malloc(sizeof *Q->d * (size_t)Q->n), Q->L = malloc(sizeof *Q->L * (size_t)Q->n);
    Q->w = malloc(sizeof *Q->w * (size_t)Q->n);
    assert_non_null(Q->d), assert_non_null(Q->L), assert_non_null(Q->w);
    for (int a = 0; a < QT; ++a)
        for (int b = 0; b < QP; ++b) {
            int k = a * QP + b;
            double t = (a + 0.5) * M_PI / QT, p = (b + 0.5) * 2.0 * M_PI / QP;
            Q->d[k][0] = sin(t) * cos(p), Q->d[k][1] = sin(t) * sin(p), Q->d[k][2] = cos(t);
            Q->w[k] = sin(t) * (M_PI / QT) * (2.0 * M_PI / QP);
            sky(kind, Q->d[k], Q->L[k]);
        }
}

static void quad_free(quad *Q)
{
    free(Q->d), free(Q->L), free(Q->w);
}

/* the sky's irradiance at qibl normal n, channel c */
static double irradiance(const quad *Q, const double n[3], int c)
{
    double e = 0.0;
    for (int k = 0; k < Q->n; ++k) {
        double cs = n[0] * Q->d[k][0] + n[1] * Q->d[k][1] + n[2] * Q->d[k][2];
        if (cs > 0)
            e += Q->L[k][c] * cs * Q->w[k];
    }
    return e;
}

/* ---- cmgen's formulas ------------------------------------------------------------------------ */

static double fact_ratio(int n, int d) /* n! / d! */
{
    double r = 1.0;
    for (int i = 2; i <= n; ++i)
        r *= i;
    for (int i = 2; i <= d; ++i)
        r /= i;
    return r;
}

/* CubemapSH: K(l,m) P(l,|m|)(z) cos(m phi) / sin(|m| phi) with sqrt 2 for m != 0, phi = atan2(y, x),
 * P with the Condon-Shortley phase (Legendre()) */
static double legendre(int l, int m, double x)
{
    double pmm = 1.0, somx2 = sqrt((1.0 - x) * (1.0 + x)), fact = 1.0;
    for (int i = 1; i <= m; ++i)
        pmm *= -fact * somx2, fact += 2.0;
    if (l == m)
        return pmm;
    double pmmp1 = x * (2.0 * m + 1.0) * pmm;
    if (l == m + 1)
        return pmmp1;
    double pll = 0.0;
    for (int ll = m + 2; ll <= l; ++ll) {
        pll = ((2.0 * ll - 1.0) * x * pmmp1 - (ll + m - 1.0) * pmm) / (ll - m);
        pmm = pmmp1, pmmp1 = pll;
    }
    return pll;
}

static void cmgen_basis(const double s[3], double y[9])
{
    double phi = atan2(s[1], s[0]);
    for (int l = 0; l < 3; ++l)
        for (int m = -l; m <= l; ++m) {
            int am = abs(m);
            double K = sqrt((2 * l + 1) / (4.0 * M_PI) * fact_ratio(l - am, l + am));
            double v = K * legendre(l, am, s[2]);
            if (m > 0)
                v *= sqrt(2.0) * cos(m * phi);
            else if (m < 0)
                v *= sqrt(2.0) * sin(am * phi);
            y[l * l + l + m] = v;
        }
}

static double cmgen_truncated_cos(int l) /* computeTruncatedCosSh */
{
    if (l == 0)
        return M_PI;
    if (l == 1)
        return 2.0 * M_PI / 3.0;
    if (l & 1)
        return 0.0;
    int l2 = l / 2;
    double a0 = ((l2 & 1) ? 1.0 : -1.0) / ((l + 2) * (l - 1));
    double a1 = fact_ratio(l, l2) / (fact_ratio(l2, 0) * (1 << l));
    return 2.0 * M_PI * a0 * a1;
}

static double cmgen_sinc_window(int l, double w)
{
    if (l == 0)
        return 1.0;
    if (l >= w)
        return 0.0;
    double x = M_PI * l / w;
    return pow(sin(x) / x, 4);
}

/* preprocessSHForShader's A[i] (Sloan), typed from the source */
static double cmgen_prescale(int i)
{
    const double sp = sqrt(M_PI);
    const double A[9] = {1.0 / (2.0 * sp), -sqrt(3.0) / (2.0 * sp), sqrt(3.0) / (2.0 * sp), -sqrt(3.0) / (2.0 * sp),
                         sqrt(15.0) / (2.0 * sp), -sqrt(15.0) / (2.0 * sp), sqrt(5.0) / (4.0 * sp),
                         -sqrt(15.0) / (2.0 * sp), sqrt(15.0) / (4.0 * sp)};
    return A[i] / M_PI;
}

static int band(int i)
{
    return i == 0 ? 0 : i < 4 ? 1 : 2;
}

/* computeSH(irradiance) of a sky by quadrature over cmgen's directions s: sum L(q(s)) basis(s) dw
 * times A_l (no window, no pre-scale) */
static void cmgen_irradiance_sh(int kind, double f[3][9])
{
    memset(f, 0, sizeof(double[3][9]));
    for (int a = 0; a < QT; ++a)
        for (int b = 0; b < QP; ++b) {
            double t = (a + 0.5) * M_PI / QT, p = (b + 0.5) * 2.0 * M_PI / QP;
            double s[3] = {sin(t) * cos(p), sin(t) * sin(p), cos(t)}, q[3], L[3], y[9];
            double w = sin(t) * (M_PI / QT) * (2.0 * M_PI / QP);
            q_from_cmgen(s, q);
            sky(kind, q, L);
            cmgen_basis(s, y);
            for (int c = 0; c < 3; ++c)
                for (int i = 0; i < 9; ++i)
                    f[c][i] += L[c] * y[i] * w;
        }
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 9; ++i)
            f[c][i] *= cmgen_truncated_cos(band(i));
}

static void cmgen_expect(const double f[3][9], double cutoff, double want[9][3])
{
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c)
            want[i][c] = f[c][i] * (cutoff < 0 ? 1.0 : cmgen_sinc_window(band(i), cutoff)) * cmgen_prescale(i);
}

/* each coefficient within 0.5 % (plus 1e-5 of the largest, for those that are 0 by symmetry) */
static void within(const double got[9][3], const double want[9][3], double rel, const char *what)
{
    double big = 0.0;
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c)
            big = fmax(big, fabs(want[i][c]));
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c)
            if (!(fabs(got[i][c] - want[i][c]) <= rel * fabs(want[i][c]) + 1e-5 * big))
                fail_msg("%s: coefficient %d channel %d is %.9g, the source's formulas give %.9g", what, i, c,
                         got[i][c], want[i][c]);
}

/* ---- the sky through the core, as `qibl sh project` sees it ----------------------------------- */

static void project(int kind, const double r[3][3], qtool_engine_sh *e)
{
    enum { W = 512, H = 256 };
    uint32_t *px = malloc(sizeof *px * 3 * W * H);
    assert_non_null(px);
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
            double q[3], L[3];
            qdir(u, v, W, H, q);
            sky(kind, q, L);
            for (int c = 0; c < 3; ++c) {
                float f = (float)L[c];
                memcpy(&px[3 * ((size_t)v * W + (size_t)u) + (size_t)c], &f, 4);
            }
        }
    qibl_lightprobe_image_t img = {px, W, H, 0, QIBL_LIGHTPROBE_LINEAR_F32, 0};
    size_t n = qibl_probe_sh_workspace_size(W, H);
    void *ws = malloc(n);
    qibl_probe_coeffs_t c;
    assert_non_null(ws);
    assert_int_equal(qibl_probe_sh_project(&img, 3, NULL, ws, n, &c), QIBL_OK);
    free(ws), free(px);
    char err[256];
    if (qtool_engine_sh_from_core(&c, r, e, err, sizeof err) != 0)
        fail_msg("%s", err);
}

/* ---- filament -------------------------------------------------------------------------------- */

static void test_filament_formulas(void **state)
{
    (void)state;
    static const int kinds[] = {SKY_LOBE, SKY_CONST, SKY_GRAD};
    static const double windows[] = {QTOOL_ENGINE_WINDOW_NO, 6.0, 2.5, 1.0};
    for (size_t k = 0; k < 3; ++k) {
        qtool_engine_sh e;
        double f[3][9], got[9][3], want[9][3], cut;
        char err[256], what[64];
        project(kinds[k], NULL, &e);
        cmgen_irradiance_sh(kinds[k], f);
        for (size_t j = 0; j < sizeof windows / sizeof windows[0]; ++j) {
            if (qtool_engine_filament(&e, windows[j], got, &cut, err, sizeof err) != 0)
                fail_msg("%s", err);
            assert_true(cut == (windows[j] < 0 ? -1.0 : windows[j]));
            cmgen_expect((const double(*)[9])f, windows[j], want);
            snprintf(what, sizeof what, "sky %d, window %g", kinds[k], windows[j]);
            within((const double(*)[3])got, (const double(*)[3])want, 0.005, what);
        }
    }
}

/* a yaw of the probe (relight's --yaw: +x toward +y) gives what cmgen gives for the turned sky */
static void test_filament_yaw(void **state)
{
    (void)state;
    double t = yaw_deg * M_PI / 180.0, r[3][3] = {{cos(t), -sin(t), 0}, {sin(t), cos(t), 0}, {0, 0, 1}};
    qtool_engine_sh e;
    double f[3][9], got[9][3], want[9][3];
    project(SKY_LOBE, (const double(*)[3])r, &e);
    cmgen_irradiance_sh(SKY_LOBE_YAWED, f);
    assert_int_equal(qtool_engine_filament(&e, QTOOL_ENGINE_WINDOW_NO, got, NULL, NULL, 0), 0);
    cmgen_expect((const double(*)[9])f, -1.0, want);
    within((const double(*)[3])got, (const double(*)[3])want, 0.005, "yawed lobe");
}

/* auto: without ringing every bisection step keeps the larger half, channel after channel from the
 * cutoff so far (windowSH), so the cutoff is known; with ringing the window must remove it */
static void test_filament_auto_window(void **state)
{
    (void)state;
    static const int calm[] = {SKY_CONST, SKY_GRAD};
    for (int k = 0; k < 2; ++k) {
        qtool_engine_sh e;
        double f[3][9], got[9][3], want[9][3], cut, r = 13.0;
        project(calm[k], NULL, &e);
        for (int c = 0; c < 3; ++c) {
            double l = 3.0;
            for (int i = 0; i < 16 && l + 0.1 < r; ++i)
                l = 0.5 * (l + r);
            r = fmin(r, l);
        }
        assert_int_equal(qtool_engine_filament(&e, QTOOL_ENGINE_WINDOW_AUTO, got, &cut, NULL, 0), 0);
        if (fabs(cut - r) > 1e-12)
            fail_msg("sky %d: auto cutoff %.9g, the bisection without ringing ends at %.9g", calm[k], cut, r);
        cmgen_irradiance_sh(calm[k], f);
        cmgen_expect((const double(*)[9])f, r, want);
        within((const double(*)[3])got, (const double(*)[3])want, 0.005, "auto window, no ringing");
    }
    /* the lobe rings: its unwindowed SH9 irradiance goes negative; the auto window must end that */
    qtool_engine_sh e;
    double f[3][9], cut, got[9][3];
    project(SKY_LOBE, NULL, &e);
    cmgen_irradiance_sh(SKY_LOBE, f);
    assert_int_equal(qtool_engine_filament(&e, QTOOL_ENGINE_WINDOW_AUTO, got, &cut, NULL, 0), 0);
    assert_true(cut >= 3.0 && cut < 12.0);
    double min0 = 1e300, minw = 1e300;
    tu_rng rng = {7};
    for (int k = 0; k < 20000; ++k) {
        double z = 2.0 * tu_unit(&rng) - 1.0, p = 2.0 * M_PI * tu_unit(&rng), s = sqrt(1.0 - z * z);
        double n[3] = {s * cos(p), s * sin(p), z}, y[9];
        cmgen_basis(n, y);
        for (int c = 0; c < 3; ++c) {
            double e0 = 0.0, ew = 0.0;
            for (int i = 0; i < 9; ++i) {
                e0 += f[c][i] * y[i];
                ew += f[c][i] * cmgen_sinc_window(band(i), cut) * y[i];
            }
            min0 = fmin(min0, e0 / f[c][0]), minw = fmin(minw, ew / f[c][0]);
        }
    }
    if (!(min0 < -0.01))
        fail_msg("the lobe does not ring (min %g): the test needs a sharper lobe", min0);
    if (!(minw >= -1e-9))
        fail_msg("auto window %.6g leaves negative irradiance (%g of L00)", cut, minw);
    /* the sh.txt lines: cmgen's outputSh layout */
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    assert_non_null(m);
    qtool_engine_filament_write(m, (const double(*)[3])got);
    fclose(m);
    int n = 0;
    for (char *line = strtok(buf, "\n"); line; line = strtok(NULL, "\n"), ++n) {
        double v[3];
        int l, mm, used = 0;
        assert_true(strlen(line) > 60);
        if (sscanf(line, "(%18lf, %18lf, %18lf); // L%1d%d, irradiance, pre-scaled base%n", &v[0], &v[1], &v[2], &l, &mm,
                   &used) != 5 || line[used] != '\0' || l * l + l + mm != n || line[1 + 18] != ',')
            fail_msg("line %d '%s' is not cmgen's '(%%18.15f, ...); // Llm, irradiance, pre-scaled base'", n, line);
        for (int c = 0; c < 3; ++c)
            assert_true(fabs(v[c] - got[n][c]) <= 1e-14 + 1e-12 * fabs(got[n][c]));
    }
    free(buf);
    assert_int_equal(n, 9);
}

/* ---- unity ----------------------------------------------------------------------------------- */

static double shade_sh9(const double p[7][4], int c, const double n[3])
{
    /* UnityCG.cginc: SHEvalLinearL0L1 + SHEvalLinearL2 */
    double x1 = p[c][0] * n[0] + p[c][1] * n[1] + p[c][2] * n[2] + p[c][3];
    double vb[4] = {n[0] * n[1], n[1] * n[2], n[2] * n[2], n[2] * n[0]};
    double x2 = p[3 + c][0] * vb[0] + p[3 + c][1] * vb[1] + p[3 + c][2] * vb[2] + p[3 + c][3] * vb[3];
    return x1 + x2 + p[6][c] * (n[0] * n[0] - n[1] * n[1]);
}

static void test_unity(void **state)
{
    (void)state;
    static const int kinds[] = {SKY_GRAD, SKY_CONST, SKY_LOBE};
    for (int k = 0; k < 3; ++k) {
        qtool_engine_sh e;
        quad Q;
        double sh[3][9], packed[7][4], trunc = 0.0, worst = 0.0, mean = 0.0;
        project(kinds[k], NULL, &e);
        assert_int_equal(qtool_engine_unity(&e, sh, packed, NULL, 0), 0);
        for (int c = 0; c < 3; ++c) { /* the packing is SphericalHarmonicsL2's, per HDRP's PackCoefficients */
            assert_true(packed[c][0] == sh[c][3] && packed[c][1] == sh[c][1] && packed[c][2] == sh[c][2]);
            assert_true(packed[c][3] == sh[c][0] - sh[c][6] && packed[3 + c][2] == 3.0 * sh[c][6]);
            assert_true(packed[6][c] == sh[c][8]);
        }
        assert_true(packed[6][3] == 1.0);
        quad_init(&Q, kinds[k]);
        tu_rng rng = {11};
        /* SH9 truncation, derived here: the sky's own 9-term irradiance against the full one */
        double f[3][9];
        memset(f, 0, sizeof f);
        for (int j = 0; j < Q.n; ++j) {
            double y[9];
            cmgen_basis(Q.d[j], y); /* an orthonormal real basis in qibl's frame */
            for (int c = 0; c < 3; ++c)
                for (int i = 0; i < 9; ++i)
                    f[c][i] += Q.L[j][c] * y[i] * Q.w[j];
        }
        for (int t = 0; t < 160; ++t) {
            double z = 2.0 * tu_unit(&rng) - 1.0, p = 2.0 * M_PI * tu_unit(&rng), s = sqrt(1.0 - z * z);
            double nu[3] = {s * cos(p), s * sin(p), z}, nq[3], y[9];
            q_from_unity(nu, nq);
            cmgen_basis(nq, y);
            for (int c = 0; c < 3; ++c) {
                double E = irradiance(&Q, nq, c), E9 = 0.0;
                for (int i = 0; i < 9; ++i)
                    E9 += cmgen_truncated_cos(band(i)) * f[c][i] * y[i];
                double got = M_PI * shade_sh9((const double(*)[4])packed, c, nu);
                mean += E / (3 * 160.0);
                trunc = fmax(trunc, fabs(E9 - E));
                worst = fmax(worst, fabs(got - E));
            }
        }
        quad_free(&Q);
        /* band-limited skies: exact to the quadrature; the lobe: within its truncation */
        double allow = 0.005 * mean + trunc * 1.01;
        if (!(worst <= allow))
            fail_msg("sky %d: pi ShadeSH9 is %.4g off the irradiance (mean %.4g, SH9 truncation %.4g)", kinds[k], worst,
                     mean, trunc);
        if (kinds[k] != SKY_LOBE)
            assert_true(trunc <= 0.002 * mean);
    }
}

/* ---- gltf: a minimal JSON reader ------------------------------------------------------------- */

static const char *js_ws(const char *p)
{
    while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r')
        ++p;
    return p;
}

static const char *js_value(const char *p, int depth);

static const char *js_string(const char *p)
{
    if (*p != '"')
        return NULL;
    for (++p; *p && *p != '"'; ++p) {
        if ((unsigned char)*p < 0x20)
            return NULL;
        if (*p == '\\') {
            ++p;
            if (*p == 'u') {
                for (int i = 1; i <= 4; ++i)
                    if (!isxdigit((unsigned char)p[i]))
                        return NULL;
                p += 4;
            } else if (!strchr("\"\\/bfnrt", *p) || !*p) {
                return NULL;
            }
        }
    }
    return *p == '"' ? p + 1 : NULL;
}

static const char *js_number(const char *p)
{
    const char *s = p;
    if (*p == '-')
        ++p;
    if (!isdigit((unsigned char)*p))
        return NULL;
    if (*p == '0')
        ++p;
    else
        while (isdigit((unsigned char)*p))
            ++p;
    if (*p == '.') {
        if (!isdigit((unsigned char)*++p))
            return NULL;
        while (isdigit((unsigned char)*p))
            ++p;
    }
    if (*p == 'e' || *p == 'E') {
        ++p;
        if (*p == '+' || *p == '-')
            ++p;
        if (!isdigit((unsigned char)*p))
            return NULL;
        while (isdigit((unsigned char)*p))
            ++p;
    }
    return p > s ? p : NULL;
}

static const char *js_value(const char *p, int depth)
{
    p = js_ws(p);
    if (depth > 64)
        return NULL;
    if (*p == '{' || *p == '[') {
        char close = *p == '{' ? '}' : ']';
        int obj = *p == '{';
        p = js_ws(p + 1);
        if (*p == close)
            return p + 1;
        for (;;) {
            if (obj) {
                p = js_string(js_ws(p));
                if (!p || *(p = js_ws(p)) != ':')
                    return NULL;
                ++p;
            }
            p = js_value(p, depth + 1);
            if (!p)
                return NULL;
            p = js_ws(p);
            if (*p == close)
                return p + 1;
            if (*p != ',')
                return NULL;
            ++p;
        }
    }
    if (*p == '"')
        return js_string(p);
    if (strncmp(p, "true", 4) == 0 || strncmp(p, "null", 4) == 0)
        return p + 4;
    if (strncmp(p, "false", 5) == 0)
        return p + 5;
    return js_number(p);
}

static void json_valid(const char *doc)
{
    const char *e = js_value(doc, 0);
    if (!e || *js_ws(e) != '\0')
        fail_msg("not JSON (at byte %ld): %s", e ? (long)(e - doc) : -1L, doc);
}

/* the numbers of the array after "key": into v (at most n); returns how many */
static int json_numbers(const char *doc, const char *key, double *v, int n)
{
    const char *p = strstr(doc, key);
    if (!p)
        return 0;
    p += strlen(key);
    int depth = 0, k = 0;
    for (; *p; ++p) {
        if (*p == '[')
            ++depth;
        else if (*p == ']' && --depth == 0)
            break;
        else if (depth > 0 && (*p == '-' || isdigit((unsigned char)*p))) {
            char *end;
            double x = strtod(p, &end);
            if (k < n)
                v[k] = x;
            ++k, p = end - 1;
        }
    }
    return k;
}

static char *capture_gltf(const double coef[9][3])
{
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    assert_non_null(m);
    qtool_engine_gltf_write(m, "sky \"one\"", coef);
    fclose(m);
    return buf;
}

static void test_gltf_ibl(void **state)
{
    (void)state;
    static const int kinds[] = {SKY_GRAD, SKY_LOBE};
    for (int k = 0; k < 2; ++k) {
        qtool_engine_sh e;
        quad Q;
        double coef[9][3], v[32], worst = 0.0, mean = 0.0, trunc = 0.0, f[3][9];
        project(kinds[k], NULL, &e);
        assert_int_equal(qtool_engine_gltf(&e, coef, NULL, 0), 0);
        char *doc = capture_gltf((const double(*)[3])coef);
        json_valid(doc);
        assert_non_null(strstr(doc, "\"EXT_lights_image_based\": {\"light\": 0}"));
        assert_non_null(strstr(doc, "\"name\": \"sky \\\"one\\\"\""));
        assert_int_equal(json_numbers(doc, "\"irradianceCoefficients\":", v, 32), 27);
        free(doc);
        quad_init(&Q, kinds[k]);
        memset(f, 0, sizeof f);
        for (int j = 0; j < Q.n; ++j) {
            double y[9];
            cmgen_basis(Q.d[j], y);
            for (int c = 0; c < 3; ++c)
                for (int i = 0; i < 9; ++i)
                    f[c][i] += Q.L[j][c] * y[i] * Q.w[j];
        }
        tu_rng rng = {5};
        for (int t = 0; t < 120; ++t) {
            double z = 2.0 * tu_unit(&rng) - 1.0, p = 2.0 * M_PI * tu_unit(&rng), s = sqrt(1.0 - z * z);
            double ng[3] = {s * cos(p), s * sin(p), z}, nq[3], yg[9], yq[9];
            q_from_cmgen(ng, nq); /* glTF placement: as Filament shows cmgen's output */
            cmgen_basis(ng, yg), cmgen_basis(nq, yq);
            for (int c = 0; c < 3; ++c) {
                double E = irradiance(&Q, nq, c), got = 0.0, E9 = 0.0;
                for (int i = 0; i < 9; ++i) {
                    got += v[3 * i + c] * yg[i]; /* Ramamoorthi and Hanrahan: E(n) = sum E_lm Y_lm(n) */
                    E9 += cmgen_truncated_cos(band(i)) * f[c][i] * yq[i];
                }
                mean += E / 360.0;
                worst = fmax(worst, fabs(got - E));
                trunc = fmax(trunc, fabs(E9 - E));
            }
        }
        quad_free(&Q);
        if (!(worst <= 0.005 * mean + 1.01 * trunc))
            fail_msg("sky %d: the glTF coefficients are %.4g off the irradiance (mean %.4g, truncation %.4g)", kinds[k],
                     worst, mean, trunc);
    }
}

static void test_gltf_lights(void **state)
{
    (void)state;
    double dir[4][3] = {{0.3, -0.5, 0.81}, {0, 0, 1}, {0, 0, -1}, {-1, 0, 0}}, rgb[4][3] = {
        {2, 1, 0.5}, {0, 0, 0}, {0.1, 0.2, 0.3}, {5, 5, 5}};
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    assert_non_null(m);
    assert_int_equal(qtool_engine_gltf_lights_write(m, (const double(*)[3])dir, (const double(*)[3])rgb, 4, NULL, 0), 0);
    fclose(m);
    json_valid(buf);
    char *nodes = strstr(buf, "\"nodes\"");
    assert_non_null(nodes);
    char *lp = buf;
    for (int k = 0; k < 4; ++k) {
        double q[4], col[3], in;
        lp = strstr(lp, "\"type\": \"directional\"");
        assert_non_null(lp);
        assert_int_equal(json_numbers(lp, "\"color\":", col, 3), 3);
        assert_int_equal(sscanf(strstr(lp, "\"intensity\":") + 12, "%lf", &in), 1);
        ++lp;
        for (int c = 0; c < 3; ++c)
            assert_true(fabs(in * col[c] - rgb[k][c]) <= 1e-8 * (1 + rgb[k][c]));
        nodes = strstr(nodes + 1, "\"rotation\":");
        assert_non_null(nodes);
        assert_int_equal(json_numbers(nodes, "\"rotation\":", q, 4), 4);
        /* the node's -z, turned by q, is where the light travels: away from the light's direction
         * as glTF sees it (cmgen's placement) */
        double v[3] = {0, 0, -1}, x = q[0], y = q[1], z = q[2], w = q[3];
        double t[3] = {2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])};
        double out[3] = {v[0] + w * t[0] + (y * t[2] - z * t[1]), v[1] + w * t[1] + (z * t[0] - x * t[2]),
                         v[2] + w * t[2] + (x * t[1] - y * t[0])};
        double d[3] = {dir[k][0], dir[k][1], dir[k][2]}, back[3];
        unit(d);
        unit(out);
        double g[3] = {-out[0], -out[1], -out[2]}; /* glTF direction toward the light */
        q_from_cmgen(g, back);
        for (int c = 0; c < 3; ++c)
            if (fabs(back[c] - d[c]) > 1e-7)
                fail_msg("light %d: node points at qibl (%g, %g, %g), want (%g, %g, %g)", k, back[0], back[1], back[2],
                         d[0], d[1], d[2]);
        assert_true(fabs(x * x + y * y + z * z + w * w - 1.0) < 1e-8);
    }
    free(buf);
    double bad[1][3] = {{0, 0, 0}}, ok[1][3] = {{1, 1, 1}};
    char err[128];
    m = open_memstream(&buf, &len);
    assert_int_equal(qtool_engine_gltf_lights_write(m, (const double(*)[3])bad, (const double(*)[3])ok, 1, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "direction is zero"));
    double neg[1][3] = {{1, -1, 0}};
    assert_int_equal(qtool_engine_gltf_lights_write(m, (const double(*)[3])ok, (const double(*)[3])neg, 1, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "colour is negative"));
    assert_int_equal(qtool_engine_gltf_lights_write(m, NULL, NULL, 0, NULL, 0), 0); /* no lights: still a document */
    fclose(m);
    json_valid(buf);
    free(buf);
}

/* ---- raw, frames, rotation, errors ----------------------------------------------------------- */

static void test_raw_and_frames(void **state)
{
    (void)state;
    qibl_probe_coeffs_t c = {.bands = 5, .exp = -28};
    tu_rng rng = {3};
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            c.c[ch][i] = (int32_t)(tu_s32(&rng) / 2);
    qtool_engine_sh e, y;
    assert_int_equal(qtool_engine_sh_from_core(&c, NULL, &e, NULL, 0), 0);
    for (int ch = 0; ch < 3; ++ch) /* raw: today's numbers exactly */
        for (int i = 0; i < 25; ++i)
            assert_true(e.c[i][ch] == ldexp(c.c[ch][i], c.exp));
    /* --frame yup: the same function, read at (x, z, -y) */
    double m[3][3];
    qtool_engine_frame_matrix(QTOOL_ENGINE_RAW, QTOOL_ENGINE_FRAME_YUP, m);
    assert_int_equal(qtool_engine_sh_remap(&e, (const double(*)[3])m, &y, NULL, 0), 0);
    for (int t = 0; t < 50; ++t) {
        double z = 2.0 * tu_unit(&rng) - 1.0, p = 2.0 * M_PI * tu_unit(&rng), s = sqrt(1.0 - z * z);
        double q[3] = {s * cos(p), s * sin(p), z}, g[3] = {q[0], q[2], -q[1]}, a = 0, b = 0;
        for (int l = 0; l < 5; ++l) /* band by band: its own basis, Wong et al.'s, through P(l,m) */
            for (int mm = -l; mm <= l; ++mm) {
                int am = abs(mm), i = l * l + l + mm;
                double K = sqrt((2 * l + 1) / (4.0 * M_PI) * fact_ratio(l - am, l + am));
                double yq = K * legendre(l, am, q[2]), yg = K * legendre(l, am, g[2]);
                double pq = atan2(q[1], q[0]), pg = atan2(g[1], g[0]);
                if (mm)
                    yq *= sqrt(2.0) * (mm > 0 ? cos(am * pq) : sin(am * pq)),
                        yg *= sqrt(2.0) * (mm > 0 ? cos(am * pg) : sin(am * pg));
                a += e.c[i][0] * yq, b += y.c[i][0] * yg;
            }
        assert_true(fabs(a - b) <= 1e-9 * (1 + fabs(a)));
    }
}

static void test_errors(void **state)
{
    (void)state;
    qtool_engine_preset p;
    double w;
    char err[256];
    assert_int_equal(qtool_engine_preset_parse("filament", &p), 0);
    assert_int_equal(p, QTOOL_ENGINE_FILAMENT);
    assert_int_equal(qtool_engine_preset_parse("unreal", &p), -1);
    assert_int_equal(qtool_engine_preset_parse(NULL, &p), -1);
    assert_string_equal(qtool_engine_preset_name(QTOOL_ENGINE_GLTF), "gltf");
    assert_int_equal(qtool_engine_window_parse("auto", &w), 0);
    assert_true(w == QTOOL_ENGINE_WINDOW_AUTO);
    assert_int_equal(qtool_engine_window_parse("no", &w), 0);
    assert_true(w < 0);
    assert_int_equal(qtool_engine_window_parse("4.5", &w), 0);
    assert_true(w == 4.5);
    static const char *bad[] = {"0", "-1", "1e7", "nan", "inf", "4x", "", "none"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i)
        if (qtool_engine_window_parse(bad[i], &w) != -1)
            fail_msg("--window '%s' accepted", bad[i]);
    qtool_engine_sh e = {.bands = 2};
    double out[9][3], sh[3][9], packed[7][4];
    assert_int_equal(qtool_engine_filament(&e, QTOOL_ENGINE_WINDOW_AUTO, out, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "need 3 bands"));
    assert_int_equal(qtool_engine_unity(&e, sh, packed, err, sizeof err), -1);
    assert_int_equal(qtool_engine_gltf(&e, out, err, sizeof err), -1);
    e.bands = 3;
    e.c[4][1] = NAN;
    assert_int_equal(qtool_engine_gltf(&e, out, err, sizeof err), -1);
    assert_non_null(strstr(err, "not finite"));
    e.c[4][1] = 0;
    assert_int_equal(qtool_engine_filament(&e, -5.0, out, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "window"));
    double skew[3][3] = {{1, 0.1, 0}, {0, 1, 0}, {0, 0, 1}};
    assert_int_equal(qtool_engine_sh_remap(&e, (const double(*)[3])skew, &e, err, sizeof err), -1);
    assert_non_null(strstr(err, "not orthogonal"));
    qibl_probe_coeffs_t c = {.bands = 6};
    assert_int_equal(qtool_engine_sh_from_core(&c, NULL, &e, err, sizeof err), -1);
    assert_non_null(strstr(err, "bands 6"));
    c.bands = 3;
    assert_int_equal(qtool_engine_sh_from_core(&c, (const double(*)[3])skew, &e, err, sizeof err), -1);
    assert_non_null(strstr(err, "rotation"));
    double mirror[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; /* the core rotates, never mirrors */
    assert_int_equal(qtool_engine_sh_from_core(&c, (const double(*)[3])mirror, &e, err, sizeof err), -1);
}

/* ---- three real probes ----------------------------------------------------------------------- */

static void test_real_probes(void **state)
{
    (void)state;
    static const char *names[] = {"royal_esplanade_1k.hdr", "venice_sunset_1k.hdr", "studio_small_03_1k.hdr"};
    int done = 0;
    for (int k = 0; k < 3; ++k) {
        char path[256], err[256];
        int w, h;
        uint8_t *px;
        snprintf(path, sizeof path, "../shared/fixtures/probes/%s", names[k]);
        FILE *t = fopen(path, "rb");
        if (!t)
            continue;
        fclose(t);
        if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, sizeof err) != 0)
            fail_msg("%s", err);
        qibl_lightprobe_image_t img = {px, (uint32_t)w, (uint32_t)h, 0, QIBL_LIGHTPROBE_RGBE, 0};
        size_t n = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h);
        void *ws = malloc(n);
        qibl_probe_coeffs_t c;
        qtool_engine_sh e;
        assert_non_null(ws);
        assert_int_equal(qibl_probe_sh_project(&img, 3, NULL, ws, n, &c), QIBL_OK);
        free(ws);
        assert_int_equal(qtool_engine_sh_from_core(&c, NULL, &e, NULL, 0), 0);
        /* cmgen's formulas on the same pixels: each pixel's light at its cmgen direction */
        double f[3][9];
        memset(f, 0, sizeof f);
        for (int v = 0; v < h; ++v)
            for (int u = 0; u < w; ++u) {
                const uint8_t *p = px + 4 * ((size_t)v * (size_t)w + (size_t)u);
                double q[3], s[3], y[9], dw = (2.0 * M_PI / w) * (M_PI / h) * sin((v + 0.5) * M_PI / h);
                qdir(u, v, w, h, q);
                /* invert q_from_cmgen: toRectilinear's angles, then the mirror */
                double fu = (u + 0.5) / w, fv = (v + 0.5) / h, yf = 1.0 - 2.0 * fv, xf = 2.0 * fu - 1.0;
                double ny = sin(yf * M_PI / 2.0), ch = cos(yf * M_PI / 2.0);
                s[0] = -(sin(xf * M_PI) * ch), s[1] = ny, s[2] = cos(xf * M_PI) * ch;
                cmgen_basis(s, y);
                for (int cc = 0; cc < 3; ++cc) {
                    double L = p[3] ? ldexp(p[cc], p[3] - 136) : 0.0;
                    for (int i = 0; i < 9; ++i)
                        f[cc][i] += L * y[i] * dw;
                }
            }
        for (int cc = 0; cc < 3; ++cc)
            for (int i = 0; i < 9; ++i)
                f[cc][i] *= cmgen_truncated_cos(band(i));
        free(px);
        static const double windows[] = {QTOOL_ENGINE_WINDOW_NO, 5.0, QTOOL_ENGINE_WINDOW_AUTO};
        for (int j = 0; j < 3; ++j) {
            double got[9][3], want[9][3], cut;
            assert_int_equal(qtool_engine_filament(&e, windows[j], got, &cut, err, sizeof err), 0);
            if (windows[j] == QTOOL_ENGINE_WINDOW_AUTO)
                assert_true(cut >= 3.0 && cut <= 13.0); /* the cutoff is cmgen's search; its formula applied: */
            cmgen_expect((const double(*)[9])f, cut, want);
            within((const double(*)[3])got, (const double(*)[3])want, 0.005, names[k]);
        }
        ++done;
    }
    if (done < 3)
        skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_filament_formulas), cmocka_unit_test(test_filament_yaw),
        cmocka_unit_test(test_filament_auto_window), cmocka_unit_test(test_unity),
        cmocka_unit_test(test_gltf_ibl), cmocka_unit_test(test_gltf_lights),
        cmocka_unit_test(test_raw_and_frames), cmocka_unit_test(test_errors),
        cmocka_unit_test(test_real_probes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
