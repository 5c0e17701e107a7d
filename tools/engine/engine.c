/*
 * engine/engine.c - qibl's SH and lights in Filament's, Unity's and glTF's conventions (see
 * engine.h for each formula and its source). Hosted, double precision; the frame changes go
 * through ref/probe_ref.c's exact quadrature rotation (any orthogonal matrix, mirrors included),
 * user rotations through the core's qibl_sh_rotation_* as `qibl relight` does.
 */
#include "engine/engine.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/sh.h"
#include "ref/lightprobe_ref.h"
#include "ref/probe_ref.h"
#include "ref/sh_ref.h"
#include "qtool.h"


/* NULL-terminated, for the option tables' enum kind */
const char *const qtool_engine_preset_names[QTOOL_ENGINE_PRESET_COUNT + 1] = {
#define QTOOL_ENGINE_PRESET_NAME_(name, text) text,
    QTOOL_ENGINE_PRESET_LIST(QTOOL_ENGINE_PRESET_NAME_)
#undef QTOOL_ENGINE_PRESET_NAME_
    NULL};

int qtool_engine_preset_parse(const char *s, qtool_engine_preset *out)
{
    for (int i = 0; s && i < QTOOL_ENGINE_PRESET_COUNT; ++i)
        if (strcmp(s, qtool_engine_preset_names[i]) == 0) {
            *out = (qtool_engine_preset)i;
            return 0;
        }
    return -1;
}

const char *qtool_engine_preset_name(qtool_engine_preset p)
{
    return (unsigned)p < QTOOL_ENGINE_PRESET_COUNT ? qtool_engine_preset_names[p] : "?";
}

int qtool_engine_window_parse(const char *s, double *out)
{
    if (!s)
        return -1;
    if (strcmp(s, "auto") == 0)
        return *out = QTOOL_ENGINE_WINDOW_AUTO, 0;
    if (strcmp(s, "no") == 0)
        return *out = QTOOL_ENGINE_WINDOW_NO, 0;
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || !(v > 0) || !(v <= QTOOL_ENGINE_WINDOW_MAX))
        return -1;
    *out = v;
    return 0;
}

void qtool_engine_frame_matrix(qtool_engine_preset p, qtool_engine_frame frame, double m[3][3])
{
    /* rows: each engine axis as a combination of qibl's (x, y, z) */
    static const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    static const double yup[3][3] = {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}};     /* (x, z, -y) */
    static const double cmgen[3][3] = {{0, 1, 0}, {0, 0, 1}, {-1, 0, 0}};   /* (y, z, -x) */
    static const double unity[3][3] = {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}};   /* (-x, z, y) */
    const double(*src)[3] = id;
    if (p == QTOOL_ENGINE_FILAMENT || p == QTOOL_ENGINE_GLTF)
        src = cmgen;
    else if (p == QTOOL_ENGINE_UNITY)
        src = unity;
    else if (frame == QTOOL_ENGINE_FRAME_YUP)
        src = yup;
    memcpy(m, src, sizeof(double[3][3]));
}

int qtool_engine_sh_from_core(const qibl_probe_coeffs_t *c, const double r[3][3], qtool_engine_sh *out, char *err,
                              size_t errlen)
{
    if (!c || !out)
        return qtool_errf(err, errlen, "no coefficients");
    if (c->bands < 1 || c->bands > QIBL_SH_MAX_BANDS)
        return qtool_errf(err, errlen, "bands %d outside 1..%d", (int)c->bands, QIBL_SH_MAX_BANDS);
    if (c->exp < -1000 || c->exp > 900)
        return qtool_errf(err, errlen, "coefficient exponent 2^%d beyond double", (int)c->exp);
    int n = c->bands * c->bands;
    int32_t v[3][QIBL_SH_MAX_COUNT];
    int32_t e = c->exp;
    memcpy(v, c->c, sizeof v);
    if (r) {
        qibl_q30_t rq[3][3];
        qibl_sh_rotation_t rot;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                if (!(fabs(r[i][j]) <= 1.0 + 1e-6))
                    return qtool_errf(err, errlen, "rotation entry %g is not in [-1, 1]", r[i][j]);
                rq[i][j] = (qibl_q30_t)lrint(fmax(-1.0, fmin(1.0, r[i][j])) * 1073741824.0);
            }
        qibl_status_t st = qibl_sh_rotation_init(&rot, (const qibl_q30_t(*)[3])rq, c->bands);
        /* two bits of headroom: a rotated coefficient reaches at most sqrt(2l + 1) <= 3 times the
         * band's largest, and the core saturates at int32 */
        for (int ch = 0; ch < 3 && st == QIBL_OK; ++ch) {
            int32_t in[QIBL_SH_MAX_COUNT];
            for (int i = 0; i < n; ++i)
                in[i] = (int32_t)floor(v[ch][i] / 4.0 + 0.5);
            st = qibl_sh_rotate(&rot, in, v[ch]);
        }
        if (st != QIBL_OK)
            return qtool_errf(err, errlen, "rotation: %s", qibl_status_str(st));
        e += 2;
    }
    memset(out, 0, sizeof *out);
    out->bands = c->bands;
    for (int i = 0; i < n; ++i)
        for (int ch = 0; ch < 3; ++ch)
            out->c[i][ch] = ldexp((double)v[ch][i], e);
    return 0;
}

int qtool_engine_sh_remap(const qtool_engine_sh *in, const double m[3][3], qtool_engine_sh *out, char *err,
                          size_t errlen)
{
    if (!in || !m || !out)
        return qtool_errf(err, errlen, "no coefficients");
    if (in->bands < 1 || in->bands > 5)
        return qtool_errf(err, errlen, "bands %d outside 1..5", in->bands);
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) {
            double d = -(p == q);
            for (int k = 0; k < 3; ++k)
                d += m[p][k] * m[q][k];
            if (!(fabs(d) <= 1e-9))
                return qtool_errf(err, errlen, "frame matrix is not orthogonal (m m^T - I off by %g)", d);
        }
    double d[165];
    qtool_ref_sh_rotation(m, in->bands, d);
    qtool_engine_sh t = {.bands = in->bands};
    int n = in->bands * in->bands;
    for (int ch = 0; ch < 3; ++ch) {
        double a[25], b[25];
        for (int i = 0; i < n; ++i)
            a[i] = in->c[i][ch];
        qtool_ref_sh_rotate(d, in->bands, a, b);
        for (int i = 0; i < n; ++i)
            t.c[i][ch] = b[i];
    }
    *out = t;
    return 0;
}

/* A_l of the clamped cosine (Ramamoorthi and Hanrahan; cmgen's computeTruncatedCosSh) */
static const double a_l[3] = {QTOOL_PI, 2.0 * QTOOL_PI / 3.0, QTOOL_PI / 4.0};

static int band_of(int i)
{
    return i == 0 ? 0 : i < 4 ? 1 : 2;
}

/* Y_i = s_i poly_i: Sloan's constants with the Condon-Shortley signs, poly = 1, y, z, x, yx, yz,
 * 3z^2 - 1, zx, x^2 - y^2 (cmgen's preprocessSHForShader, HDRP's ks) */
static void sloan(double s[9])
{
    double rp = sqrt(QTOOL_PI);
    s[0] = 1.0 / (2.0 * rp);
    s[1] = -sqrt(3.0) / (2.0 * rp);
    s[2] = sqrt(3.0) / (2.0 * rp);
    s[3] = -sqrt(3.0) / (2.0 * rp);
    s[4] = sqrt(15.0) / (2.0 * rp);
    s[5] = -sqrt(15.0) / (2.0 * rp);
    s[6] = sqrt(5.0) / (4.0 * rp);
    s[7] = -sqrt(15.0) / (2.0 * rp);
    s[8] = sqrt(15.0) / (4.0 * rp);
}

double qtool_engine_cmgen_window(int l, double cutoff)
{
    if (l == 0)
        return 1.0;
    if (l >= cutoff)
        return 0.0;
    double x = QTOOL_PI * l / cutoff;
    x = sin(x) / x;
    return x * x * x * x;
}

double qtool_engine_cmgen_shmin(const double f[9])
{
    double s[9];
    sloan(s);
    /* the optimal linear direction (Y11 = -c x, Y1-1 = -c y, Y10 = c z), turned to +z */
    double v[3] = {-f[3], -f[1], f[2]}, len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0))
        return NAN; /* cmgen normalises a zero vector: NaN, which never compares below 0 */
    double dir[3] = {v[0] / len, v[1] / len, v[2] / len}, za[3] = {-dir[0], -dir[1], -dir[2]};
    double xa[3] = {-za[2], 0.0, za[0]}, xl = sqrt(xa[0] * xa[0] + xa[2] * xa[2]); /* cross(z_axis, +y) */
    if (!(xl > 0))
        return NAN; /* the same for a linear part along +-y */
    xa[0] /= xl, xa[2] /= xl;
    double ya[3] = {xa[1] * za[2] - xa[2] * za[1], xa[2] * za[0] - xa[0] * za[2], xa[0] * za[1] - xa[1] * za[0]};
    double m[3][3] = {{xa[0], xa[1], xa[2]}, {ya[0], ya[1], ya[2]}, {dir[0], dir[1], dir[2]}};
    qtool_engine_sh in = {.bands = 3}, g;
    for (int i = 0; i < 9; ++i)
        in.c[i][0] = f[i];
    if (qtool_engine_sh_remap(&in, (const double(*)[3])m, &g, NULL, 0) != 0)
        return NAN;
#define G(i) g.c[i][0]
    /* |m| = 2 bounded by m2max (z^2 - 1), folded into the zonal quadratic in z */
    double m2max = s[8] * sqrt(G(8) * G(8) + G(4) * G(4));
    double a = 3.0 * s[6] * G(6) + m2max, b = s[2] * G(2), c = s[0] * G(0) - s[6] * G(6) - m2max;
    double m0min = fmin(a + b + c, a - b + c);
    if (a > 0) {
        double zmin = -b / (2.0 * a);
        if (zmin >= -1.0 && zmin <= 1.0)
            m0min = a * zmin * zmin + b * zmin + c;
    }
    double d = s[4] * sqrt(G(5) * G(5) + G(7) * G(7));
#undef G
    double minimum = m0min - 0.5 * d;
    if (minimum < 0) { /* Newton on ZH + |m| = 2 + |m| = 1, from z = -1/sqrt 2 */
        double z = -sqrt(0.5), dz;
        int it = 0;
        do {
            double q = sqrt(1.0 - z * z);
            minimum = (a * z * z + b * z + c) + d * z * q;
            dz = (z * z - 1.0) * (d - 2.0 * d * z * z + (b + 2.0 * a * z) * q) /
                 (3.0 * d * z - 2.0 * d * z * z * z - 2.0 * a * pow(1.0 - z * z, 1.5));
            z -= dz;
        } while (fabs(z) <= 1.0 && fabs(dz) > 1e-5 && ++it < QTOOL_ENGINE_NEWTON_MAX);
        if (fabs(z) > 1.0)
            minimum = fmin(a + b + c, a - b + c); /* func(1), func(-1): the |m| = 1 term is 0 there */
    }
    return minimum;
}

double qtool_engine_cmgen_auto_cutoff(const double f[9], double start)
{
    double lo = 3.0, hi = start; /* numBands, the cutoff so far */
    for (int i = 0; i < 16 && lo + 0.1 < hi; ++i) {
        double mid = 0.5 * (lo + hi), w[9];
        for (int k = 0; k < 9; ++k)
            w[k] = f[k] * qtool_engine_cmgen_window(band_of(k), mid);
        if (qtool_engine_cmgen_shmin(w) < 0)
            hi = mid;
        else
            lo = mid;
    }
    return lo;
}

static int need3(const qtool_engine_sh *rad, char *err, size_t errlen)
{
    if (!rad)
        return qtool_errf(err, errlen, "no coefficients");
    if (rad->bands < 3 || rad->bands > 5)
        return qtool_errf(err, errlen, "the engine presets need 3 bands (9 coefficients); got %d", rad->bands);
    for (int i = 0; i < 9; ++i)
        for (int ch = 0; ch < 3; ++ch)
            if (!isfinite(rad->c[i][ch]))
                return qtool_errf(err, errlen, "coefficient %d is not finite", i);
    return 0;
}

/* the first 9 coefficients of rad in preset p's frame */
static int in_frame(const qtool_engine_sh *rad, qtool_engine_preset p, qtool_engine_sh *out, char *err, size_t errlen)
{
    double m[3][3];
    if (need3(rad, err, errlen) != 0)
        return -1;
    qtool_engine_sh t = *rad;
    t.bands = 3;
    qtool_engine_frame_matrix(p, QTOOL_ENGINE_FRAME_ZUP, m);
    return qtool_engine_sh_remap(&t, (const double(*)[3])m, out, err, errlen);
}

int qtool_engine_filament(const qtool_engine_sh *rad, double window, double out[9][3], double *cutoff_used,
                          char *err, size_t errlen)
{
    qtool_engine_sh l;
    if (!out)
        return qtool_errf(err, errlen, "no output");
    if (!(window == QTOOL_ENGINE_WINDOW_AUTO || window == QTOOL_ENGINE_WINDOW_NO ||
          (window > 0 && window <= QTOOL_ENGINE_WINDOW_MAX)))
        return qtool_errf(err, errlen, "window %g is not auto, no or a cutoff in (0, %g]", window, QTOOL_ENGINE_WINDOW_MAX);
    if (in_frame(rad, QTOOL_ENGINE_FILAMENT, &l, err, errlen) != 0)
        return -1;
    double f[3][9], s[9], cutoff = window;
    sloan(s);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 9; ++i)
            f[ch][i] = l.c[i][ch] * a_l[band_of(i)]; /* computeSH(irradiance): A_l L */
    if (window == QTOOL_ENGINE_WINDOW_AUTO) {
        cutoff = QTOOL_ENGINE_AUTO_START; /* each channel's search starts from the cutoff so far */
        for (int ch = 0; ch < 3; ++ch)
            cutoff = fmin(cutoff, qtool_engine_cmgen_auto_cutoff(f[ch], cutoff));
    }
    for (int i = 0; i < 9; ++i)
        for (int ch = 0; ch < 3; ++ch) {
            double w = window == QTOOL_ENGINE_WINDOW_NO ? 1.0 : qtool_engine_cmgen_window(band_of(i), cutoff);
            out[i][ch] = f[ch][i] * w * s[i] / QTOOL_PI; /* preprocessSHForShader */
        }
    if (cutoff_used)
        *cutoff_used = window == QTOOL_ENGINE_WINDOW_NO ? -1.0 : cutoff;
    return 0;
}

void qtool_engine_filament_write(FILE *f, const double out[9][3])
{
    for (int l = 0; l < 3; ++l)
        for (int m = -l; m <= l; ++m) {
            int i = l * l + l + m;
            fprintf(f, "(%18.15f, %18.15f, %18.15f); // L%d%d, irradiance, pre-scaled base\n", out[i][0], out[i][1],
                    out[i][2], l, m);
        }
}

int qtool_engine_unity(const qtool_engine_sh *rad, double sh[3][9], double packed[7][4], char *err, size_t errlen)
{
    qtool_engine_sh l;
    if (!sh || !packed)
        return qtool_errf(err, errlen, "no output");
    if (in_frame(rad, QTOOL_ENGINE_UNITY, &l, err, errlen) != 0)
        return -1;
    double s[9];
    sloan(s);
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < 9; ++i) /* N_i = Y's constant times A_l / pi (kNormalizationConstants) */
            sh[ch][i] = l.c[i][ch] * s[i] * a_l[band_of(i)] / QTOOL_PI;
    for (int ch = 0; ch < 3; ++ch) {
        const double *u = sh[ch];
        double a[4] = {u[3], u[1], u[2], u[0] - u[6]}, b[4] = {u[4], u[5], 3.0 * u[6], u[7]};
        memcpy(packed[ch], a, sizeof a);
        memcpy(packed[3 + ch], b, sizeof b);
    }
    packed[6][0] = sh[0][8], packed[6][1] = sh[1][8], packed[6][2] = sh[2][8], packed[6][3] = 1.0;
    return 0;
}

void qtool_engine_unity_write(FILE *f, const double sh[3][9], const double packed[7][4])
{
    static const char *names[7] = {"unity_SHAr", "unity_SHAg", "unity_SHAb", "unity_SHBr",
                                   "unity_SHBg", "unity_SHBb", "unity_SHC"};
    static const char *lm[9] = {"L00", "L1-1", "L10", "L11", "L2-2", "L2-1", "L20", "L21", "L22"};
    fprintf(f, "var sh = new UnityEngine.Rendering.SphericalHarmonicsL2();\n");
    for (int i = 0; i < 9; ++i)
        fprintf(f, "sh[0, %d] = %.9gf; sh[1, %d] = %.9gf; sh[2, %d] = %.9gf; // %s\n", i, sh[0][i], i, sh[1][i], i,
                sh[2][i], lm[i]);
    fprintf(f, "// ShadeSH9 constants (UnityCG.cginc) for a shader of your own: ShadeSH9(n) = E(n) / pi\n");
    for (int k = 0; k < 7; ++k)
        fprintf(f, "var %s = new Vector4(%.9gf, %.9gf, %.9gf, %.9gf);\n", names[k], packed[k][0], packed[k][1],
                packed[k][2], packed[k][3]);
}

int qtool_engine_gltf(const qtool_engine_sh *rad, double coef[9][3], char *err, size_t errlen)
{
    qtool_engine_sh l;
    if (!coef)
        return qtool_errf(err, errlen, "no output");
    if (in_frame(rad, QTOOL_ENGINE_GLTF, &l, err, errlen) != 0)
        return -1;
    for (int i = 0; i < 9; ++i)
        for (int ch = 0; ch < 3; ++ch)
            coef[i][ch] = l.c[i][ch] * a_l[band_of(i)];
    return 0;
}

void qtool_engine_json_str(FILE *f, const char *s)
{
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
}

void qtool_engine_gltf_write(FILE *f, const char *name, const double coef[9][3])
{
    fprintf(f, "{\"extensionsUsed\": [\"EXT_lights_image_based\"],\n \"extensions\": {\"EXT_lights_image_based\": "
               "{\"lights\": [{\"name\": \"");
    qtool_engine_json_str(f, name ? name : "qibl");
    fprintf(f, "\", \"intensity\": 1.0, \"rotation\": [0.0, 0.0, 0.0, 1.0],\n  \"irradianceCoefficients\": [");
    for (int i = 0; i < 9; ++i)
        fprintf(f, "%s\n   [%.9g, %.9g, %.9g]", i ? "," : "", coef[i][0], coef[i][1], coef[i][2]);
    fprintf(f, "],\n  \"extras\": {\"qibl\": \"irradiance SH (A_l L_lm, y up); add specularImageSize and "
               "specularImages, which EXT_lights_image_based requires\"}}]}},\n \"scenes\": [{\"extensions\": "
               "{\"EXT_lights_image_based\": {\"light\": 0}}}]}\n");
}

void qtool_engine_gltf_light_rotation(const double dir[3], double q[4])
{
    /* the shortest turn of +z onto dir; -z then points along -dir, where the light travels */
    double w = 1.0 + dir[2];
    if (w < 1e-12) { /* dir = -z: half a turn about x */
        q[0] = 1.0, q[1] = 0.0, q[2] = 0.0, q[3] = 0.0;
        return;
    }
    double x = -dir[1], y = dir[0], n = sqrt(x * x + y * y + w * w);
    q[0] = x / n, q[1] = y / n, q[2] = 0.0, q[3] = w / n;
}

int qtool_engine_gltf_lights_write(FILE *f, const double (*dir)[3], const double (*rgb)[3], uint32_t n, char *err,
                                   size_t errlen)
{
    double m[3][3];
    if (n && (!dir || !rgb))
        return qtool_errf(err, errlen, "no lights");
    for (uint32_t k = 0; k < n; ++k) {
        double len = sqrt(dir[k][0] * dir[k][0] + dir[k][1] * dir[k][1] + dir[k][2] * dir[k][2]);
        if (!(len > 0) || !isfinite(len))
            return qtool_errf(err, errlen, "light %u: direction is zero or not finite", k);
        for (int c = 0; c < 3; ++c)
            if (!(rgb[k][c] >= 0) || !isfinite(rgb[k][c]))
                return qtool_errf(err, errlen, "light %u: colour is negative or not finite", k);
    }
    qtool_engine_frame_matrix(QTOOL_ENGINE_GLTF, QTOOL_ENGINE_FRAME_ZUP, m);
    fprintf(f, "{\"extensionsUsed\": [\"KHR_lights_punctual\"],\n \"extensions\": {\"KHR_lights_punctual\": "
               "{\"lights\": [");
    for (uint32_t k = 0; k < n; ++k) {
        double i = fmax(rgb[k][0], fmax(rgb[k][1], rgb[k][2]));
        double c[3] = {1.0, 1.0, 1.0};
        if (i > 0)
            c[0] = rgb[k][0] / i, c[1] = rgb[k][1] / i, c[2] = rgb[k][2] / i;
        fprintf(f, "%s\n  {\"name\": \"qibl_light_%u\", \"type\": \"directional\", \"color\": [%.9g, %.9g, %.9g], "
                   "\"intensity\": %.9g}",
                k ? "," : "", k, c[0], c[1], c[2], i);
    }
    fprintf(f, "]}},\n \"nodes\": [");
    for (uint32_t k = 0; k < n; ++k) {
        double len = sqrt(dir[k][0] * dir[k][0] + dir[k][1] * dir[k][1] + dir[k][2] * dir[k][2]), g[3], q[4];
        for (int r = 0; r < 3; ++r)
            g[r] = (m[r][0] * dir[k][0] + m[r][1] * dir[k][1] + m[r][2] * dir[k][2]) / len;
        qtool_engine_gltf_light_rotation(g, q);
        fprintf(f, "%s\n  {\"name\": \"qibl_light_%u\", \"rotation\": [%.9g, %.9g, %.9g, %.9g], \"extensions\": "
                   "{\"KHR_lights_punctual\": {\"light\": %u}}}",
                k ? "," : "", k, q[0], q[1], q[2], q[3], k);
    }
    fprintf(f, "]}\n");
    return 0;
}

double qtool_engine_sh9_irradiance(const qtool_engine_sh *rad, int ch, const double n[3])
{
    double y[9], e = 0.0;
    if (qtool_ref_sh_eval(n[0], n[1], n[2], 3, y) != 0)
        return 0.0;
    for (int i = 0; i < 9; ++i)
        e += a_l[band_of(i)] * rad->c[i][ch] * y[i];
    return e;
}

int qtool_engine_sh9_error(const qtool_engine_sh *rad, const uint8_t *rgbe, int w, int h, const double r[3][3],
                           double *mean, double *max, char *err, size_t errlen)
{
    enum { NN = 1024 };
    if (need3(rad, err, errlen) != 0)
        return -1;
    if (!rgbe || w < 1 || h < 1 || !mean || !max)
        return qtool_errf(err, errlen, "no probe");
    size_t np = (size_t)w * (size_t)h;
    double *d = malloc(sizeof *d * 3 * np), (*nrm)[3] = malloc(sizeof *nrm * NN), (*src)[3] = malloc(sizeof *src * NN);
    double *E = malloc(sizeof *E * NN);
    qtool_ref_probe rp;
    int rc = -1;
    if (!d || !nrm || !src || !E) {
        qtool_errf(err, errlen, "out of memory for the SH9 error");
        goto out;
    }
    for (size_t i = 0; i < np; ++i)
        for (int c = 0; c < 3; ++c) {
            uint8_t e = rgbe[4 * i + 3];
            d[3 * i + (size_t)c] = e ? ldexp(rgbe[4 * i + (size_t)c], e - 136) : 0.0;
        }
    if (qtool_ref_probe_init(&rp, w, h, d) != 0) {
        qtool_errf(err, errlen, "out of memory for the SH9 error");
        goto out;
    }
    qtool_ref_sphere_dirs(NN, nrm);
    for (int k = 0; k < NN; ++k) /* rad was rotated by r: its normal n looks at the probe's r^T n */
        for (int i = 0; i < 3; ++i)
            src[k][i] = r ? r[0][i] * nrm[k][0] + r[1][i] * nrm[k][1] + r[2][i] * nrm[k][2] : nrm[k][i];
    qtool_ref_probe_irradiance(&rp, NN, (const double(*)[3])src, E, 2);
    qtool_ref_probe_free(&rp);
    double sum = 0.0, es = 0.0, mx = 0.0;
    for (int k = 0; k < NN; ++k) {
        double s = QTOOL_REF_LUMA_R * qtool_engine_sh9_irradiance(rad, 0, nrm[k]) +
                   QTOOL_REF_LUMA_G * qtool_engine_sh9_irradiance(rad, 1, nrm[k]) +
                   QTOOL_REF_LUMA_B * qtool_engine_sh9_irradiance(rad, 2, nrm[k]);
        double e = fabs(s - E[k]);
        sum += E[k], es += e, mx = fmax(mx, e);
    }
    double me = sum / NN;
    *mean = me > 0 ? es / NN / me : 0.0;
    *max = me > 0 ? mx / me : 0.0;
    rc = 0;
out:
    free(d), free(nrm), free(src), free(E);
    return rc;
}
