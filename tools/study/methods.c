/*
 * methods.c - the study's wrappers around the core: the three samplers of qibl/lightprobe.h and
 * the SH irradiance projection of qibl/probe.h, turned into study models (double).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/lightprobe.h"
#include "qibl/probe.h"
#include "study/study.h"

const char *qtool_study_method_name(int method)
{
    static const char *const names[QTOOL_STUDY_METHOD_COUNT] = {
#define QTOOL_STUDY_METHOD_NAME_(name, text) text,
        QTOOL_STUDY_METHOD_LIST(QTOOL_STUDY_METHOD_NAME_)
#undef QTOOL_STUDY_METHOD_NAME_
    };
    return method >= 0 && method < QTOOL_STUDY_METHOD_COUNT ? names[method] : "?";
}

static qibl_lightprobe_image_t image_of(const qtool_study_probe *p)
{
    qibl_lightprobe_image_t img;
    memset(&img, 0, sizeof img);
    img.pixels = p->rgbe, img.width = (uint32_t)p->w, img.height = (uint32_t)p->h;
    return img;
}

int qtool_study_probe_lights(const qtool_study_probe *p, qibl_lightprobe_method_t m, qibl_lightprobe_light_t *L, int n,
                             qibl_lightprobe_result_t *res, const char *what, char *err, size_t errlen)
{
    qibl_lightprobe_image_t img = image_of(p);
    size_t wsz = qibl_lightprobe_workspace_size(img.width, img.height, m);
    void *ws = malloc(wsz ? wsz : 1);
    if (!ws) {
        snprintf(err, errlen, "%s: out of memory", what);
        return -1;
    }
    qibl_lightprobe_t lp;
    qibl_lightprobe_opts_t o = {m, 0, 0};
    qibl_status_t st = qibl_lightprobe_build(&lp, &img, m, ws, wsz);
    if (st == QIBL_OK)
        st = qibl_lightprobe_lights(&lp, &o, L, (uint32_t)n, res);
    free(ws);
    if (st != QIBL_OK) {
        snprintf(err, errlen, "%s: %s", what, qibl_status_str(st));
        return -1;
    }
    return 0;
}

int qtool_study_core_lights(const qtool_study_probe *p, int method, int n, qtool_study_model *md, char *err,
                            size_t errlen)
{
    if (n < 1 || n > QTOOL_STUDY_MAX_LIGHTS || method < QTOOL_STUDY_MEDIANCUT || method > QTOOL_STUDY_VARMIN) {
        snprintf(err, errlen, "core lights: bad method %d or count %d", method, n);
        return -1;
    }
    qibl_lightprobe_method_t m = (qibl_lightprobe_method_t)method; /* the same order */
    qibl_lightprobe_light_t *L = malloc(sizeof *L * (size_t)n);
    qibl_lightprobe_result_t res;
    if (!L) {
        snprintf(err, errlen, "core lights: out of memory");
        return -1;
    }
    if (qtool_study_probe_lights(p, m, L, n, &res, "core lights", err, errlen) != 0) {
        free(L);
        return -1;
    }
    memset(md, 0, sizeof *md);
    md->n = (int)res.count;
    for (int i = 0; i < md->n; ++i)
        for (int c = 0; c < 3; ++c) {
            md->dir[i][c] = L[i].dir[c] / 1073741824.0;
            md->rgb[i][c] = ldexp(L[i].rgb[c], res.rgb_exp);
        }
    free(L);
    return 0;
}

int qtool_study_core_sh(const qtool_study_probe *p, int coeffs, qtool_study_model *md, char *err, size_t errlen)
{
    int bands = coeffs == 4 ? 2 : coeffs == 9 ? 3 : coeffs == 16 ? 4 : coeffs == 25 ? 5 : 0;
    if (!bands) {
        snprintf(err, errlen, "SH: %d coefficients (4, 9, 16 or 25)", coeffs);
        return -1;
    }
    qibl_lightprobe_image_t img = image_of(p);
    size_t wsz = qibl_probe_sh_workspace_size(img.width, img.height);
    void *ws = malloc(wsz ? wsz : 1);
    if (!ws) {
        snprintf(err, errlen, "SH: out of memory");
        return -1;
    }
    qibl_probe_sh_opts_t o;
    memset(&o, 0, sizeof o);
    o.irradiance = 1;
    qibl_probe_coeffs_t c;
    qibl_status_t st = qibl_probe_sh_project(&img, bands, &o, ws, wsz, &c);
    free(ws);
    if (st != QIBL_OK) {
        snprintf(err, errlen, "SH: %s", qibl_status_str(st));
        return -1;
    }
    memset(md, 0, sizeof *md);
    md->sh_n = coeffs;
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < coeffs; ++i)
            md->sh[ch][i] = ldexp(c.c[ch][i], c.exp);
    return 0;
}
