/*
 * procedural.c - stand-in skies for machines without the fixture probes: a sunny sky (a gradient,
 * a ground, a sun disc 2^14 times the sky at 40 degrees elevation) and an overcast one (a smooth
 * bright zenith, a dim ground, no sun), as RGBE bytes in the lat-long layout of qibl/lightprobe.h.
 */
#include <math.h>
#include <stdlib.h>

#include "io/probe_layout.h"
#include "study/study.h"
#include "qtool.h"


uint8_t *qtool_study_procedural(int w, int h, int sunny)
{
    if (w < 2 || h < 1)
        return NULL;
    float *f = malloc(3 * sizeof *f * (size_t)w * (size_t)h);
    uint8_t *o = malloc(4 * (size_t)w * (size_t)h);
    if (!f || !o) {
        free(f), free(o);
        return NULL;
    }
    const double sth = (90 - 40) * QTOOL_PI / 180, sph = 1.1;
    const double sd[3] = {sin(sth) * cos(sph), sin(sth) * sin(sph), cos(sth)};
    const double rad = 0.6 * QTOOL_PI / 180 + 1.5 * QTOOL_PI / h; /* at least a pixel or so */
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            double th = (v + 0.5) * QTOOL_PI / h, ph = (u + 0.5) * 2 * QTOOL_PI / w;
            double d[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
            float *p = f + 3 * ((size_t)v * (size_t)w + (size_t)u);
            double z = d[2];
            if (sunny) {
                if (z > 0) {
                    p[0] = (float)(0.3 + 0.3 * (1 - z)), p[1] = (float)(0.45 + 0.25 * (1 - z)), p[2] = (float)(0.9);
                } else {
                    p[0] = 0.25f, p[1] = 0.2f, p[2] = (float)(0.12 + 0.02 * sin(7 * ph));
                }
                double c = d[0] * sd[0] + d[1] * sd[1] + d[2] * sd[2];
                if (acos(fmin(1, c)) < rad)
                    p[0] = 16384.0f, p[1] = 15000.0f, p[2] = 12000.0f;
            } else {
                double l = z > 0 ? 0.6 + 1.2 * z : 0.15 + 0.05 * (1 + z);
                p[0] = (float)l, p[1] = (float)l, p[2] = (float)(l * 1.05);
            }
        }
    qtool_probe_layout_rgbe_encode(f, (size_t)w * (size_t)h, o);
    free(f);
    return o;
}
