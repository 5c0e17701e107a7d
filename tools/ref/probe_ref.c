/*
 * ref/probe_ref.c - double references for SH projection and rotation (see probe_ref.h).
 */
#include "ref/probe_ref.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#include "ref/sh_ref.h"
#include "qtool.h"


void qtool_ref_probe_sh(int w, int h, const double *rgb, int bands, double out[3][25])
{
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 25; ++i)
            out[c][i] = 0.0;
    /* Y_lm(theta, phi) = Y_l|m|(theta, 0) cos(m phi) (m > 0), Y_l|m|(theta, 0) sin(|m| phi) (m < 0):
     * the appendix's product form, so the basis is evaluated once per row and the trig once per
     * column (libm), in double */
    double *trig = malloc(sizeof *trig * 9 * (size_t)w);
    if (trig == NULL)
        return;
    for (int u = 0; u < w; ++u) {
        double ph = (u + 0.5) * 2.0 * QTOOL_PI / w;
        trig[9 * u] = 1.0;
        for (int m = 1; m <= 4; ++m)
            trig[9 * u + 2 * m - 1] = cos(m * ph), trig[9 * u + 2 * m] = sin(m * ph);
    }
    for (int v = 0; v < h; ++v) {
        double t = (v + 0.5) * QTOOL_PI / h, dw = (2.0 * QTOOL_PI / w) * (QTOOL_PI / h) * sin(t), y[25];
        qtool_ref_sh_eval(sin(t), 0.0, cos(t), bands, y);
        double s[3][9] = {{0}};
        for (int u = 0; u < w; ++u) {
            const double *p = rgb + 3 * ((size_t)v * (size_t)w + (size_t)u);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 9; ++k)
                    s[c][k] += p[c] * trig[9 * u + k];
        }
        for (int l = 0; l < bands; ++l)
            for (int m = -l; m <= l; ++m) {
                int am = m < 0 ? -m : m, k = m == 0 ? 0 : m > 0 ? 2 * m - 1 : 2 * am;
                for (int c = 0; c < 3; ++c)
                    out[c][l * l + l + m] += s[c][k] * y[l * l + l + am] * dw;
            }
    }
    free(trig);
}

void qtool_ref_probe_band_factors(int bands, int irradiance, int window, double f[5])
{
    static const double a[5] = {QTOOL_PI, 2.0 * QTOOL_PI / 3.0, QTOOL_PI / 4.0, 0.0, -QTOOL_PI / 24.0};
    for (int l = 0; l < 5; ++l) {
        double s = 1.0, x = QTOOL_PI * l / bands;
        if (window == 1)
            s = 0.5 * (1.0 + cos(x));
        else if (window == 2 && l > 0)
            s = sin(x) / x;
        f[l] = l < bands ? s * (irradiance ? a[l] : 1.0) : 0.0;
    }
}

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n) */
static void gauss_legendre(int n, double *x, double *wt)
{
    for (int i = 0; i < n; ++i) {
        double z = cos(QTOOL_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16)
                break;
        }
        x[i] = z;
        wt[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

void qtool_ref_sh_rotation(const double r[3][3], int bands, double d[165])
{
    enum { NZ = 12, NP = 24 };
    double zx[NZ], zw[NZ];
    gauss_legendre(NZ, zx, zw);
    for (int i = 0; i < 165; ++i)
        d[i] = 0.0;
    for (int a = 0; a < NZ; ++a)
        for (int b = 0; b < NP; ++b) {
            double z = zx[a], s = sqrt(1.0 - z * z), ph = (b + 0.5) * 2.0 * QTOOL_PI / NP;
            double w[3] = {s * cos(ph), s * sin(ph), z}, q[3], y[25], yr[25];
            for (int i = 0; i < 3; ++i)
                q[i] = r[0][i] * w[0] + r[1][i] * w[1] + r[2][i] * w[2]; /* r^T w */
            qtool_ref_sh_eval(w[0], w[1], w[2], bands, y);
            qtool_ref_sh_eval(q[0], q[1], q[2], bands, yr);
            double wt = zw[a] * 2.0 * QTOOL_PI / NP;
            int off = 0;
            for (int l = 0; l < bands; ++l) {
                int n = 2 * l + 1;
                for (int m = 0; m < n; ++m)
                    for (int mp = 0; mp < n; ++mp)
                        d[off + m * n + mp] += wt * y[l * l + m] * yr[l * l + mp];
                off += n * n;
            }
        }
}

void qtool_ref_sh_rotate(const double d[165], int bands, const double *in, double *out)
{
    int off = 0;
    for (int l = 0; l < bands; ++l) {
        int n = 2 * l + 1;
        for (int m = 0; m < n; ++m) {
            double s = 0.0;
            for (int mp = 0; mp < n; ++mp)
                s += d[off + m * n + mp] * in[l * l + mp];
            out[l * l + m] = s;
        }
        off += n * n;
    }
}
