/*
 * transfer/light.c - the SH light of `qibl transfer` (transfer/job.h): a probe's radiance SH
 * (bands 0..4) in Q16.16, or its median-cut lights projected to SH at the same scale.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "io/hdr.h"
#include "qibl/lightprobe.h"
#include "qibl/probe.h"
#include "qtool.h"
#include "transfer/job.h"

/* A light list from median cut, projected to SH (qibl_shlight_add_lights), the same Q16.16 radiance
 * SH as the probe's own projection; 0 or -1 with the reason in err */
static int lights_light(const uint8_t *ll, int ow, int oh, int nlights, int32_t light[3][25], char *err, size_t errlen)
{
    const size_t n = qibl_lightprobe_workspace_size((uint32_t)ow, (uint32_t)oh, QIBL_LIGHTPROBE_MEDIANCUT);
    void *ws = n ? malloc(n) : NULL;
    qibl_lightprobe_light_t *lt = malloc(sizeof *lt * (size_t)nlights);
    if (!ws || !lt) {
        free(ws), free(lt);
        return qtool_errf(err, errlen, "--lights: out of memory");
    }
    const qibl_lightprobe_image_t img = {ll, (uint32_t)ow, (uint32_t)oh, 0, QIBL_LIGHTPROBE_RGBE, 0};
    qibl_lightprobe_t lp;
    qibl_lightprobe_result_t res;
    qibl_shlight_t sl;
    qibl_status_t st = qibl_lightprobe_build(&lp, &img, QIBL_LIGHTPROBE_MEDIANCUT, ws, n);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, NULL, lt, (uint32_t)nlights, &res);
    if (st == QIBL_OK)
        st = qibl_shlight_init(&sl, 25);
    /* the brightest channel's rgb is in [2^30, 2^31): 2^-16 of it per light keeps the sum of up to
     * 1024 lights within Q16.16 */
    if (st == QIBL_OK)
        st = qibl_shlight_add_lights(&sl, lt, res.count, res.rgb_exp, -16 - res.rgb_exp);
    free(ws), free(lt);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "--lights %d: %s", nlights, qibl_status_str(st));
    /* the probe path's scale: the largest |coefficient| in [1/4, 1/2) (the image's exposure is
     * automatic; this keeps the shading sums as far from int32 as the probe's) */
    int32_t mx = 0;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            mx = abs(sl.c[ch][i]) > mx ? abs(sl.c[ch][i]) : mx;
    int sh = 0;
    while (mx > 0 && (mx >> sh) >= (1 << 15))
        ++sh;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            light[ch][i] = sl.c[ch][i] / (1 << sh);
    return 0;
}

/* the lat-long probe's radiance SH, bands 0..4 (qibl_probe_sh_*) */
static int project(const char *path, const uint8_t *ll, int ow, int oh, qibl_probe_coeffs_t *c, char *err,
                   size_t errlen)
{
    const size_t n = qibl_probe_sh_workspace_size((uint32_t)ow, (uint32_t)oh);
    void *ws = n ? malloc(n) : NULL;
    if (!ws)
        return qtool_errf(err, errlen, "%s: %dx%d is beyond the probe limits or out of memory", path, ow, oh);
    qibl_probe_sh_t ps;
    qibl_status_t st = qibl_probe_sh_begin(&ps, (uint32_t)ow, (uint32_t)oh, QIBL_LIGHTPROBE_RGBE, 0, 5, ws, n);
    for (int v = 0; v < oh && st == QIBL_OK; ++v)
        st = qibl_probe_sh_add_row(&ps, (uint32_t)v, ll + 4 * (size_t)ow * (size_t)v);
    if (st == QIBL_OK)
        st = qibl_probe_sh_finish(&ps, NULL, c);
    free(ws);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "%s: %s", path, qibl_status_str(st));
    return 0;
}

int qtool_transfer_probe_light(const char *path, qtool_probe_layout_t layout, int nlights, int32_t light[3][25],
                               char *desc, size_t dlen, char *err, size_t errlen)
{
    int w, h, ow, oh;
    uint8_t *px, *ll;
    qtool_probe_layout_t used;
    if (qtool_hdr_read_rgbe(path, &w, &h, &px, err, errlen) != 0)
        return -1;
    int rc = qtool_probe_layout_rgbe_to_latlong(layout, w, h, px, &used, &ow, &oh, &ll, err, errlen);
    free(px);
    if (rc != 0)
        return -1;
    int32_t ml[3][25];
    qibl_probe_coeffs_t c;
    if ((nlights > 0 && lights_light(ll, ow, oh, nlights, ml, err, errlen) != 0) ||
        project(path, ll, ow, oh, &c, err, errlen) != 0)
        return free(ll), -1;
    free(ll);
    /* the largest |c| is in [2^30, 2^31): shift to [2^15, 2^16) / 2, i.e. 0.25 .. 0.5 in Q16.16 */
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 25; ++i)
            light[ch][i] = c.c[ch][i] / (1 << 16); /* truncation toward zero: 2^-16 relative */
    snprintf(desc, dlen, "%dx%d %s", ow, oh, qtool_probe_layout_name(used));
    if (nlights > 0) { /* the lights replace the projection; how far apart, each scaled by its own DC */
        double d2 = 0, n2 = 0;
        for (int ch = 0; ch < 3 && ml[1][0] != 0 && light[1][0] != 0; ++ch)
            for (int i = 0; i < 25; ++i) {
                const double a = (double)ml[ch][i] / ml[1][0], b = (double)light[ch][i] / light[1][0];
                d2 += (a - b) * (a - b), n2 += b * b;
            }
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 25; ++i)
                light[ch][i] = ml[ch][i];
        snprintf(desc, dlen, "%dx%d %s, %d median-cut lights as SH: relative L2 %.4f from its own projection", ow, oh,
                 qtool_probe_layout_name(used), nlights, n2 > 0 ? sqrt(d2 / n2) : 0.0);
    }
    return 0;
}
