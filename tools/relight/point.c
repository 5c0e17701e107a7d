/*
 * relight/point.c - what `--point` means without `--rgb` (render and relight), and how dark a frame
 * came out (light.h).
 *
 * A lamp of C0 = 1 a few units from the scene gives C0/|L| x albedo/pi, about 0.03 linear: an
 * almost black frame, with no hint why. The default instead scales C0 with the distance from the
 * lamp to what the panorama sees, so that a surface at the median distance facing the lamp comes out
 * near mid-grey whatever the scene's size or the falloff.
 */
#include <math.h>
#include <stdlib.h>

#include "relight/light.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int qtool_relight_point_default(const double *pts, size_t n, const double pos[3], int falloff, double *c0,
                                double *dist)
{
    double *d = malloc((n ? n : 1) * sizeof *d);
    if (!d)
        return -1;
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *p = pts + 3 * i;
        /* sky pixels sit QTOOL_RELIGHT_SKY_DIST along their ray (bake.c's P map): not part of the scene */
        if (sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) >= 0.9 * QTOOL_RELIGHT_SKY_DIST)
            continue;
        double dx = p[0] - pos[0], dy = p[1] - pos[1], dz = p[2] - pos[2];
        d[m++] = sqrt(dx * dx + dy * dy + dz * dz);
    }
    double med = 1.0; /* all sky: a unit distance, so C0 is the grey level itself */
    if (m > 0) {
        qsort(d, m, sizeof *d, cmp_double);
        med = d[m / 2] > 1e-3 ? d[m / 2] : 1e-3;
    }
    free(d);
    double c = QTOOL_RELIGHT_POINT_GREY * (falloff == 2 ? med * med : med);
    *c0 = c < QTOOL_RELIGHT_Q16_MAX ? c : QTOOL_RELIGHT_Q16_MAX;
    *dist = med;
    return 0;
}

double *qtool_relight_pmap_points(const qibl_pmap_t *pm)
{
    size_t np = (size_t)pm->width * pm->height;
    double *p = malloc(np * 3 * sizeof *p);
    for (uint32_t y = 0; p && y < pm->height; ++y)
        for (uint32_t x = 0; x < pm->width; ++x) {
            qibl_q16_t q[3];
            qibl_pmap_point(pm, x, y, q);
            for (int c = 0; c < 3; ++c)
                p[3 * ((size_t)y * pm->width + x) + (size_t)c] = q[c] / 65536.0;
        }
    return p;
}

double qtool_relight_mean8(const uint8_t *rgb, size_t np)
{
    double sum = 0;
    for (size_t i = 0; i < np * 3; ++i)
        sum += rgb[i];
    return np ? sum / (double)(np * 3) : 0;
}
