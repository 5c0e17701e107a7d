/*
 * ref/sh_ref.c - double-precision SH basis from the appendix of Wong et al.
 */
#include "ref/sh_ref.h"

#include <math.h>
#include "qtool.h"


static double factorial(int n)
{
    double f = 1.0;
    for (int i = 2; i <= n; ++i)
        f *= i;
    return f;
}

double qtool_ref_sh_q(int l, int m, double x)
{
    if (l == 0 && m == 0)
        return 1.0;
    if (l == m)
        return (1 - 2 * m) * sqrt(fmax(0.0, 1.0 - x * x)) * qtool_ref_sh_q(m - 1, m - 1, x);
    if (l == m + 1)
        return (2 * m + 1) * x * qtool_ref_sh_q(m, m, x);
    return ((2.0 * l - 1) / (l - m)) * x * qtool_ref_sh_q(l - 1, m, x) -
           ((double)(l + m - 1) / (l - m)) * qtool_ref_sh_q(l - 2, m, x);
}

int qtool_ref_sh_eval(double x, double y, double z, int bands, double *out)
{
    double r = sqrt(x * x + y * y + z * z);
    if (!(r > 0.0) || bands < 1 || bands > 8)
        return -1;
    double theta = acos(fmax(-1.0, fmin(1.0, z / r)));
    double phi = atan2(y, x); /* 0 at the poles, where every m != 0 term has a sin(theta) factor */
    double ct = cos(theta);
    for (int l = 0; l < bands; ++l) {
        for (int m = -l; m <= l; ++m) {
            int am = m < 0 ? -m : m;
            double n = sqrt((2.0 * l + 1) / (2.0 * QTOOL_PI) * factorial(l - am) / factorial(l + am));
            double q = qtool_ref_sh_q(l, am, ct);
            double v;
            if (m > 0)
                v = n * q * cos(m * phi);
            else if (m == 0)
                v = n * q / sqrt(2.0);
            else
                v = n * q * sin(am * phi);
            out[l * l + l + m] = v;
        }
    }
    return 0;
}
