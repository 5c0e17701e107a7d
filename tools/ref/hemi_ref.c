/*
 * ref/hemi_ref.c - ray-cast transfer vectors (ref/hemi_ref.h).
 */
#include "ref/hemi_ref.h"

#include <math.h>
#include <string.h>

#include "ref/sh_ref.h"
#include "qtool.h"


/* the estimator of both: each cosine-weighted ray weighted by max(0, refl . l)^e when refl is set */
static void ref_rays(const qtool_rt_scene *rt, const double p[3], const double ax[3][3], int side, int world,
                     const double *refl, double e, uint64_t seed, double out[25], double *noise)
{
    qtool_rt_hit hit;
    memset(&hit, 0, sizeof hit);
    hit.hit = 1;
    for (int k = 0; k < 3; ++k)
        hit.p[k] = p[k], hit.ng[k] = hit.n[k] = ax[2][k];
    double half[2][25] = {{0}};
    uint64_t rs = seed;
    const int S = side;
    for (int a = 0; a < S; ++a)
        for (int b = 0; b < S; ++b) {
            rs = rs * 6364136223846793005u + 1442695040888963407u;
            const double u1 = (a + (double)(rs >> 40) / 16777216.0) / S;
            rs = rs * 6364136223846793005u + 1442695040888963407u;
            const double u2 = (b + (double)(rs >> 40) / 16777216.0) / S;
            const double r = sqrt(u1), ph = 2 * QTOOL_PI * u2;
            const double l[3] = {r * cos(ph), r * sin(ph), sqrt(fmax(0, 1 - u1))};
            double w[3];
            for (int k = 0; k < 3; ++k)
                w[k] = l[0] * ax[0][k] + l[1] * ax[1][k] + l[2] * ax[2][k];
            if (qtool_rt_occluded(rt, &hit, w, 1e30))
                continue;
            double y[25], g = 1;
            if (refl) {
                const double c = refl[0] * l[0] + refl[1] * l[1] + refl[2] * l[2];
                if (c <= 0)
                    continue;
                g = pow(c, e);
            }
            if (world)
                qtool_ref_sh_eval(w[0], w[1], w[2], 5, y);
            else
                qtool_ref_sh_eval(l[0], l[1], l[2], 5, y);
            for (int i = 0; i < 25; ++i)
                half[(a + b) & 1][i] += g * y[i];
        }
    const double wgt = QTOOL_PI / (S * S);
    double d2 = 0, n2 = 0;
    for (int i = 0; i < 25; ++i) {
        out[i] = (half[0][i] + half[1][i]) * wgt;
        const double diff = (half[0][i] - half[1][i]) * 2 * wgt; /* each half estimates the whole */
        d2 += diff * diff, n2 += out[i] * out[i];
    }
    if (noise)
        *noise = n2 > 0 ? sqrt(d2) / 2 / sqrt(n2) : 0;
}

void qtool_hemi_ref(const qtool_rt_scene *rt, const double p[3], const double ax[3][3], int side, int world,
                    uint64_t seed, double out[25], double *noise)
{
    ref_rays(rt, p, ax, side, world, NULL, 0, seed, out, noise);
}

void qtool_hemi_ref_phong(const qtool_rt_scene *rt, const double p[3], const double ax[3][3], int side,
                          const double refl[3], double e, uint64_t seed, double out[25], double *noise)
{
    const double l = sqrt(refl[0] * refl[0] + refl[1] * refl[1] + refl[2] * refl[2]);
    const double r[3] = {refl[0] / l, refl[1] / l, refl[2] / l};
    ref_rays(rt, p, ax, side, 0, r, e, seed, out, noise);
}
