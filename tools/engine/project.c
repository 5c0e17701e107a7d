/*
 * engine/project.c - `qibl sh project`'s work (engine/project.h): the core's projection and its
 * output in qibl's basis or an engine's convention.
 */
#include "engine/project.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "qtool.h"

const char *const qtool_sh_window_names[3] = {"none", "hann", "lanczos"};

/* a float literal C accepts: %.9g, with ".0" when it would read as an integer */
static void c_float(FILE *f, double v)
{
    char b[64];
    if ((float)v == 0) /* below float range: the caller noted it */
        v = 0;
    snprintf(b, sizeof b, "%.9g", v);
    fprintf(f, "%s%sf", b, strpbrk(b, ".e") ? "" : ".0");
}

/* s inside a C comment: a "*" followed by "/" is split so the comment cannot end early */
static void c_comment_str(FILE *f, const char *s)
{
    for (; *s; ++s) {
        fputc(*s, f);
        if (*s == '*' && s[1] == '/')
            fputc(' ', f);
    }
}

/* An engine preset from radiance coefficients c (rotated by o->rot); px the probe (for Unity's SH9
 * error). 0, or -1 with err set. */
static int preset_out(const qtool_sh_project_opts *o, const char *path, const qibl_probe_coeffs_t *c,
                      const uint8_t *px, int w, int h, FILE *out, FILE *log, char *err, size_t errlen)
{
    char e2[256];
    qtool_engine_sh e;
    if (qtool_engine_sh_from_core(c, o->rot, &e, e2, sizeof e2) != 0)
        return qtool_errf(err, errlen, "sh project: %s: %s", path, e2);
    if (o->preset == QTOOL_ENGINE_FILAMENT) {
        double sh[9][3], cut;
        if (qtool_engine_filament(&e, o->engine_window, sh, &cut, e2, sizeof e2) != 0)
            return qtool_errf(err, errlen, "sh project: %s: %s", path, e2);
        if (cut < 0)
            fprintf(log, "%s: cmgen's sh.txt (--deploy): irradiance, no window, pre-scaled, y up mirrored in x\n", path);
        else
            fprintf(log, "%s: cmgen's sh.txt (--deploy): irradiance, window cutoff %.9g (%s), pre-scaled, y up "
                         "mirrored in x\n", path, cut, o->engine_window == QTOOL_ENGINE_WINDOW_AUTO ? "auto" : "--window");
        qtool_engine_filament_write(out, (const double(*)[3])sh);
        return 0;
    }
    if (o->preset == QTOOL_ENGINE_UNITY) {
        double sh[3][9], packed[7][4], me, mx;
        if (qtool_engine_unity(&e, sh, packed, e2, sizeof e2) != 0 ||
            qtool_engine_sh9_error(&e, px, w, h, o->rot, &me, &mx, e2, sizeof e2) != 0)
            return qtool_errf(err, errlen, "sh project: %s: %s", path, e2);
        fprintf(out, "// ");
        c_comment_str(out, path);
        fprintf(out, ": Unity's SphericalHarmonicsL2 (y up, left-handed; the panoramic skybox's placement), made by "
                "`qibl sh project --preset unity`\n// SH9 truncation error against the probe's irradiance over 1024 "
                "normals (of the mean irradiance): mean %.3f%%, max %.3f%%\n", 100 * me, 100 * mx);
        qtool_engine_unity_write(out, (const double(*)[9])sh, (const double(*)[4])packed);
        return 0;
    }
    double coef[9][3];
    if (qtool_engine_gltf(&e, coef, e2, sizeof e2) != 0)
        return qtool_errf(err, errlen, "sh project: %s: %s", path, e2);
    qtool_engine_gltf_write(out, o->name, (const double(*)[3])coef);
    return 0;
}

/* labels of the raw output: the frame, the kind and the rotation */
typedef struct {
    const char *fr, *kind, *rot, *window, *layout;
} labels;

static void write_json(const qtool_sh_project_opts *o, const char *path, int w, int h, const labels *lb,
                       const qtool_engine_sh *e, FILE *out)
{
    fprintf(out, "{\"probe\": \"");
    qtool_engine_json_str(out, path);
    fprintf(out, "\", \"layout\": \"%s\", \"width\": %d, \"height\": %d, \"bands\": %ld, \"irradiance\": %s, "
            "\"window\": \"%s\",\n \"basis\": \"qibl/sh.h: real SH, index l*l+l+m, %s%s, lat-long phi from +x "
            "toward +y\",\n \"coefficients\": [", lb->layout, w, h, o->bands, o->core.irradiance ? "true" : "false",
            lb->window, lb->fr, lb->rot);
    for (int l = 0; l < (int)o->bands; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            fprintf(out, "%s\n  {\"l\": %d, \"m\": %d, \"rgb\": [%.9g, %.9g, %.9g]}", i ? "," : "", l, m, e->c[i][0],
                    e->c[i][1], e->c[i][2]);
        }
    fprintf(out, "\n]}\n");
}

/* A float literal beyond FLT_MAX is inf (or a compile error): refused before anything is printed;
 * one below half the smallest subnormal is written as 0 with a note. 0, or -1 with err set. */
static int write_c(const qtool_sh_project_opts *o, const char *path, int w, int h, const labels *lb,
                   const qibl_probe_coeffs_t *c, const qtool_engine_sh *e, FILE *out, FILE *log, char *err,
                   size_t errlen)
{
    static const char rgbn[3] = {'R', 'G', 'B'};
    int tiny = 0;
    for (int i = 0; i < (int)(o->bands * o->bands); ++i)
        for (int ch = 0; ch < 3; ++ch) {
            double v = ldexp(c->c[ch][i], c->exp);
            if (isinf((float)v)) {
                int l = 0;
                while ((l + 1) * (l + 1) <= i)
                    ++l;
                return qtool_errf(err, errlen, "sh project: %s: coefficient [%d] (l = %d, m = %+d) %c is %.9g, beyond "
                                  "float range (FLT_MAX %.9g): --format c cannot write it (--format json or table "
                                  "can)", path, i, l, i - l * l - l, rgbn[ch], v, (double)FLT_MAX);
            }
            tiny += v != 0 && (float)v == 0;
        }
    if (tiny)
        fprintf(log, "qibl: sh project: note: %d coefficient%s below float range (under %.3g) written as 0\n", tiny,
                tiny > 1 ? "s" : "", ldexp(1, -150));
    fprintf(out, "/* ");
    c_comment_str(out, path);
    fprintf(out, ": %dx%d, layout %s, bands %ld, %s, window %s.\n * Made by `qibl sh project --format c`; "
            "basis of qibl/sh.h (real SH, %s%s), index l*l + l + m. */\n", w, h, lb->layout, o->bands, lb->kind,
            lb->window, lb->fr, lb->rot);
    fprintf(out, "#define %s_BANDS %ld\nstatic const float %s[%ld][3] = {\n", o->name, o->bands, o->name,
            o->bands * o->bands);
    for (int l = 0; l < (int)o->bands; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            fprintf(out, "    {");
            for (int ch = 0; ch < 3; ++ch) {
                c_float(out, e->c[i][ch]);
                fprintf(out, "%s", ch < 2 ? ", " : "");
            }
            fprintf(out, "}, /* [%d] l = %d, m = %+d */\n", i, l, m);
        }
    fprintf(out, "};\n");
    return 0;
}

static void write_table(const qtool_sh_project_opts *o, const char *path, int w, int h, const labels *lb,
                        const qtool_engine_sh *e, FILE *out)
{
    fprintf(out, "# %s: %dx%d lat-long, bands %ld, %s, window %s (qibl/sh.h basis, Wong et al.'s convention, %s%s)\n",
            path, w, h, o->bands, lb->kind, lb->window, lb->fr, lb->rot);
    fprintf(out, "# %2s %3s %16s %16s %16s\n", "l", "m", "R", "G", "B");
    for (int l = 0; l < (int)o->bands; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            fprintf(out, "  %2d %3d %16.9g %16.9g %16.9g\n", l, m, e->c[i][0], e->c[i][1], e->c[i][2]);
        }
}

/* raw: qibl's basis, rotated and turned to y up (frame yup) when asked */
static int raw_out(const qtool_sh_project_opts *o, const char *path, int w, int h, qtool_probe_layout_t used,
                   const char *note, const qibl_probe_coeffs_t *c, FILE *out, FILE *log, char *err, size_t errlen)
{
    qtool_engine_sh e;
    char e2[256];
    double fm[3][3];
    qtool_engine_frame_matrix(QTOOL_ENGINE_RAW, o->frame, fm);
    if (qtool_engine_sh_from_core(c, o->rot, &e, e2, sizeof e2) != 0 ||
        (o->frame == QTOOL_ENGINE_FRAME_YUP && qtool_engine_sh_remap(&e, (const double(*)[3])fm, &e, e2, sizeof e2) != 0))
        return qtool_errf(err, errlen, "sh project: %s: %s", path, e2);
    if (o->format == QTOOL_SH_FORMAT_TABLE)
        fprintf(out, "# %s", note);
    else
        fputs(note, log);
    labels lb = {o->frame == QTOOL_ENGINE_FRAME_YUP ? "y up: (x, z, -y) of qibl's" : "z up",
                 o->core.irradiance ? "irradiance (clamped cosine, A_l)" : "radiance",
                 o->rot_kind == 1 ? ", turned by --yaw" : o->rot_kind == 2 ? ", turned by --rotate" : "",
                 qtool_sh_window_names[o->core.window], qtool_probe_layout_name(used)};
    if (o->format == QTOOL_SH_FORMAT_JSON) {
        write_json(o, path, w, h, &lb, &e, out);
        return 0;
    }
    if (o->format == QTOOL_SH_FORMAT_C)
        return write_c(o, path, w, h, &lb, c, &e, out, log, err, errlen);
    write_table(o, path, w, h, &lb, &e, out);
    return 0;
}

int qtool_sh_project(const qtool_sh_project_opts *o, const char *path, const uint8_t *px, int w, int h,
                     qtool_probe_layout_t used, const char *note, FILE *out, FILE *log, char *err, size_t errlen)
{
    size_t n = qibl_probe_sh_workspace_size((uint32_t)w, (uint32_t)h);
    void *ws = n ? malloc(n) : NULL;
    if (!ws)
        return qtool_errf(err, errlen, "sh project: %s: %dx%d is beyond the probe limits or out of memory", path, w, h);
    qibl_probe_sh_t ps;
    qibl_probe_coeffs_t c;
    qibl_status_t st = qibl_probe_sh_begin(&ps, (uint32_t)w, (uint32_t)h, QIBL_LIGHTPROBE_RGBE, 0, (int)o->bands, ws, n);
    for (int v = 0; v < h && st == QIBL_OK; ++v)
        st = qibl_probe_sh_add_row(&ps, (uint32_t)v, px + 4 * (size_t)w * (size_t)v);
    if (st == QIBL_OK)
        st = qibl_probe_sh_finish(&ps, &o->core, &c);
    free(ws);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "sh project: %s: %s", path, qibl_status_str(st));
    if (o->preset != QTOOL_ENGINE_RAW) { /* presets print only the engine's text on out */
        fputs(note, log);
        return preset_out(o, path, &c, px, w, h, out, log, err, errlen);
    }
    return raw_out(o, path, w, h, used, note, &c, out, log, err, errlen);
}
