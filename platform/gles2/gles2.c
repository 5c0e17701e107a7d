/*
 * gles2.c - the OpenGL ES 2.0 backend (qibl/gles2.h): textures, generated GLSL ES 1.00 shaders and
 * passes; the lighting maths per frame stays in core/ (weights, point-light preparation).
 *
 * Hosted C99 (GL calls, float maths, snprintf); no heap: shader sources are built on the stack.
 * Invariants: every GL object id in qibl_gles2_t is 0 or owned by it; a failing call deletes what
 * it created; statuses from this file are core statuses or QIBL_E_GLES2_*.
 */
#include "qibl/gles2.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <GLES2/gl2.h>

#include "qibl/asset.h"

#define SRC_SIZE 65536 /* largest generated fragment shader: k = 25 direct SH, 19 textures */

const char *qibl_gles2_status_str(qibl_status_t s)
{
#define QIBL_GLES2_STATUS_IF_(name, message) if (s == name) return message;
    QIBL_GLES2_STATUS_LIST(QIBL_GLES2_STATUS_IF_)
#undef QIBL_GLES2_STATUS_IF_
    return qibl_status_str(s);
}

static void set_log(qibl_gles2_t *g, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(g->log, sizeof g->log, fmt, ap);
    va_end(ap);
}

static qibl_status_t gl_check(qibl_gles2_t *g, const char *what)
{
    GLenum e = glGetError();
    if (e == GL_NO_ERROR)
        return QIBL_OK;
    while (glGetError() != GL_NO_ERROR) /* drain: GL may hold several flags */
        ;
    set_log(g, "glGetError 0x%04x after %s", (unsigned)e, what);
    return QIBL_E_GLES2_GL_ERROR;
}

/* ---- shader source building ------------------------------------------------------------------ */

typedef struct {
    char *p;
    size_t n, cap;
    int overflow;
} sbuf;

static void emit(sbuf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vsnprintf(b->p + b->n, b->cap - b->n, fmt, ap);
    va_end(ap);
    if (r < 0 || (size_t)r >= b->cap - b->n)
        b->overflow = 1;
    else
        b->n += (size_t)r;
}

static const char *vs_src = "attribute vec2 a_pos;\n"
                            "void main() { gl_Position = vec4(a_pos, 0.0, 1.0); }\n";

/* highp where the platform has it (GL_FRAGMENT_PRECISION_HIGH is the standard macro) */
static const char *fs_head = "#ifdef GL_FRAGMENT_PRECISION_HIGH\n"
                             "precision highp float;\n"
                             "precision highp sampler2D;\n"
                             "precision highp samplerCube;\n"
                             "#else\n"
                             "precision mediump float;\n"
                             "#endif\n";

/* sRGBE in GLSL, the paper's format bit for bit (qibl/srgbe.h): decode (t.rgb - 0.5) 2^(E - 126);
 * encode e = floor(log2 max|c|) + 2, corrected by one either way because log2 may be inexact, then
 * X = floor(255 (c 2^-e + 1/2) + 1/2). The RGBA8 store rounds X / 255 back to X exactly. A zero
 * channel writes 128 whatever its sign (the C codec writes 127 for -0); below 2^-126 the zero code. */
const char qibl_gles2_glsl_srgbe[] = "vec3 srgbe_dec(vec4 t) {\n"
                                     "  vec4 x = floor(t * 255.0 + 0.5);\n"
                                     "  return (x.rgb - 127.5) / 255.0 * exp2(x.a - 126.0);\n"
                                     "}\n"
                                     "vec4 srgbe_enc(vec3 c) {\n"
                                     "  float m = max(max(abs(c.r), abs(c.g)), abs(c.b));\n"
                                     "  if (m < 1.1754944e-38) return vec4(128.0, 128.0, 128.0, 0.0) / 255.0;\n"
                                     "  float e = floor(log2(m)) + 2.0;\n"
                                     "  if (m * exp2(-e) >= 0.5) e += 1.0;\n"
                                     "  if (m * exp2(-e) < 0.25) e -= 1.0;\n"
                                     "  e = min(e, 129.0);\n"
                                     "  vec3 x = clamp(floor(255.0 * (c * exp2(-e) + 0.5) + 0.5), 0.0, 255.0);\n"
                                     "  return vec4(x, e + 126.0) / 255.0;\n"
                                     "}\n";

/* exposure, clamp, IEC 61966-2-1 sRGB or linear; the RGBA8 store rounds to nearest */
static const char *fs_out = "uniform vec2 u_out;\n" /* x: exposure, y: 1 = sRGB */
                            "vec4 tonemap(vec3 v) {\n"
                            "  vec3 x = clamp(v * u_out.x, 0.0, 1.0);\n"
                            "  if (u_out.y > 0.5) {\n"
                            "    vec3 lo = x * 12.92;\n"
                            "    vec3 hi = 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055;\n"
                            "    x = mix(hi, lo, vec3(lessThanEqual(x, vec3(0.0031308))));\n"
                            "  }\n"
                            "  return vec4(x, 1.0);\n"
                            "}\n";

/* The LUT direction as the core samples it: its face chosen as the core does (ties go to x, then
 * y), then either the centre of the texel containing it (nearest: GPUs quantise cube coordinates,
 * llvmpipe to 1/256 texel, so a direction near a texel edge could land in the neighbour) or its
 * face coordinates clamped to the outer texel centres (bilinear, clamped at the face's edges, as the
 * core and CLAMP_TO_EDGE do); rebuilt so that the major axis is unambiguous to the GPU. */
static const char *fs_lut_dir = "uniform float u_lutn, u_lutnear;\n"
                                    "vec3 lut_dir(vec3 u) {\n"
                                    "  vec3 a = abs(u);\n"
                                    "  float ma, sc, tc;\n"
                                    "  int f = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;\n"
                                    "  if (f == 0) { ma = a.x; sc = u.x >= 0.0 ? -u.z : u.z; tc = -u.y; }\n"
                                    "  else if (f == 1) { ma = a.y; sc = u.x; tc = u.y >= 0.0 ? u.z : -u.z; }\n"
                                    "  else { ma = a.z; sc = u.z >= 0.0 ? u.x : -u.x; tc = -u.y; }\n"
                                    "  vec2 st = vec2(sc, tc) / ma;\n"
                                    "  if (u_lutnear > 0.5) {\n"
                                    "    st = floor((st + 1.0) * 0.5 * u_lutn);\n"
                                    "    st = (clamp(st, 0.0, u_lutn - 1.0) + 0.5) / u_lutn * 2.0 - 1.0;\n"
                                    "  } else {\n"
                                    "    st = clamp(st, 1.0 / u_lutn - 1.0, 1.0 - 1.0 / u_lutn);\n"
                                    "  }\n"
                                    "  if (f == 0) return u.x >= 0.0 ? vec3(1.0, -st.y, -st.x) : vec3(-1.0, -st.y, st.x);\n"
                                    "  if (f == 1) return u.y >= 0.0 ? vec3(st.x, 1.0, st.y) : vec3(st.x, -1.0, -st.y);\n"
                                    "  return u.z >= 0.0 ? vec3(st.x, -st.y, 1.0) : vec3(-st.x, -st.y, -1.0);\n"
                                    "}\n";

/* the point modes that read the LUT, and those with a goniometric table */
static int mode_lut(int mode)
{
    return mode == QIBL_GLES2_MODE_POINT_LUT || mode == QIBL_GLES2_MODE_POINT_LUT_GONIO;
}

static int mode_gonio(int mode)
{
    return mode == QIBL_GLES2_MODE_POINT_SH_GONIO || mode == QIBL_GLES2_MODE_POINT_LUT_GONIO;
}

/* The goniometric table's texel (i, j), fetched exactly (nearest filtering at its centre, the 16 bits
 * rebuilt from two bytes); qibl_gles2_glsl_gonio mixes four of them. */
static const char *fs_gonio_tex = "uniform sampler2D u_g;\n"
                                  "uniform vec3 u_gx, u_gy, u_gz;\n"
                                  "uniform float u_gn;\n"
                                  "float gonio_tex(vec2 ij) {\n"
                                  "  vec4 t = texture2D(u_g, (ij + 0.5) / u_gn);\n"
                                  "  return floor(t.r * 255.0 + 0.5) + 256.0 * floor(t.a * 255.0 + 0.5);\n"
                                  "}\n";

/* The goniometric scale toward lamp-frame direction dw (qibl/gonio.h, qibl_gonio_lookup): the
 * octahedral position, folded below the equator, as a texel position clamped to the outer texel
 * centres; the four nearest texels (gonio_tex) mixed bilinearly; the Q1.15 result rounded as the
 * core rounds it. */
const char qibl_gles2_glsl_gonio[] = "float gonio(vec3 dw) {\n"
                                     "  vec3 lf = vec3(dot(dw, u_gx), dot(dw, u_gy), dot(dw, u_gz));\n"
                                     "  vec3 al = abs(lf);\n"
                                     "  float s = al.x + al.y + al.z;\n"
                                     "  vec2 a = vec2(0.0);\n"
                                     "  if (s > 0.0) {\n"
                                     "    a = (lf.z >= 0.0 ? al.xy : vec2(s - al.y, s - al.x)) / s;\n"
                                     "    a = vec2(lf.x < 0.0 ? -a.x : a.x, lf.y < 0.0 ? -a.y : a.y);\n"
                                     "  }\n"
                                     "  vec2 f = clamp((a + 1.0) * 0.5 * u_gn - 0.5, 0.0, u_gn - 1.0);\n"
                                     "  vec2 i0 = floor(f), tf = f - i0, i1 = min(i0 + 1.0, u_gn - 1.0);\n"
                                     "  float r0 = mix(gonio_tex(i0), gonio_tex(vec2(i1.x, i0.y)), tf.x);\n"
                                     "  float r1 = mix(gonio_tex(vec2(i0.x, i1.y)), gonio_tex(i1), tf.x);\n"
                                     "  return floor(mix(r0, r1, tf.y) + 0.5) / 32768.0;\n"
                                     "}\n";

static const char swz[4] = {'x', 'y', 'z', 'w'};
static const char rgbc[3] = {'r', 'g', 'b'};

/* Y_i(u) for i < k in straight-line GLSL: Re/Im (x + iy)^m times the Legendre polynomial reduced
 * by sin^m (so no square root), normalisation folded into the constants. Same convention as
 * qibl/sh.h (Wong et al.'s appendix, Condon-Shortley phase), computed differently from sh.c. */
static void emit_sh(sbuf *b, uint32_t k)
{
    int bands = 1;
    while ((uint32_t)(bands * bands) < k)
        ++bands;
    emit(b, "  float c0 = 1.0, s0 = 0.0;\n");
    for (int m = 1; m < bands; ++m)
        emit(b, "  float c%d = c%d * u.x - s%d * u.y, s%d = c%d * u.y + s%d * u.x;\n", m, m - 1, m - 1, m, m - 1,
             m - 1);
    for (int m = 0; m < bands; ++m) {
        double pmm = 1.0; /* (-1)^m (2m-1)!! */
        for (int j = 1; j <= m; ++j)
            pmm *= -(double)(2 * j - 1);
        for (int l = m; l < bands; ++l) {
            if (l == m)
                emit(b, "  float p%d_%d = %.9e;\n", l, m, pmm);
            else if (l == m + 1)
                emit(b, "  float p%d_%d = %.9e * u.z * p%d_%d;\n", l, m, (double)(2 * m + 1), m, m);
            else
                emit(b, "  float p%d_%d = %.9e * u.z * p%d_%d - %.9e * p%d_%d;\n", l, m,
                     (double)(2 * l - 1) / (double)(l - m), l - 1, m, (double)(l + m - 1) / (double)(l - m), l - 2, m);
            double f = 1.0; /* (l - m)! / (l + m)! */
            for (int j = l - m + 1; j <= l + m; ++j)
                f /= (double)j;
            double n = sqrt((double)(2 * l + 1) / (2.0 * 3.14159265358979323846) * f);
            if (m == 0) {
                uint32_t i = (uint32_t)(l * l + l);
                if (i < k)
                    emit(b, "  y[%u] = %.9e * p%d_0;\n", i, n / sqrt(2.0), l);
            } else {
                uint32_t ip = (uint32_t)(l * l + l + m), im = (uint32_t)(l * l + l - m);
                if (ip < k)
                    emit(b, "  y[%u] = %.9e * p%d_%d * c%d;\n", ip, n, l, m, m);
                if (im < k)
                    emit(b, "  y[%u] = %.9e * p%d_%d * s%d;\n", im, n, l, m, m);
            }
        }
    }
}

/* textures [t0, t1) of the maps; the planes they hold: plane p = 4 j + q = map i * channels + ch */
static void pass_maps(const qibl_gles2_t *g, uint32_t t0, uint32_t t1, uint32_t *i0, uint32_t *i1)
{
    uint32_t p1 = 4u * t1 < g->planes ? 4u * t1 : g->planes;
    *i0 = 4u * t0 / g->channels;
    *i1 = (p1 - 1u) / g->channels + 1u;
}

/* Units and uniform vectors a pass over textures [t0, t1) of mode needs. */
static void pass_cost(const qibl_gles2_t *g, int mode, uint32_t t0, uint32_t t1, int acc, uint32_t *units,
                      uint32_t *uvecs)
{
    uint32_t n = t1 - t0, i0, i1;
    pass_maps(g, t0, t1, &i0, &i1);
    *units = n + (acc ? (g->float_acc ? 1u : 2u) : 0u); /* float, or the high and low sRGBE codes */
    *uvecs = 4u; /* u_size + u_bias/u_out + slack for drivers that pack badly */
    if (mode == QIBL_GLES2_MODE_DIR) {
        *uvecs += n * (g->channels == 3u ? 1u : 3u);
    } else {
        *units += 3u + (mode_gonio(mode) ? 1u : 0u);
        *uvecs += 2u * n + 5u + (mode_gonio(mode) ? 4u : 0u);
        if (mode_lut(mode))
            *units += (i1 - 1u) / 2u - i0 / 2u + 1u;
    }
}

/* Splits the map textures of mode into passes greedily. */
static qibl_status_t plan(qibl_gles2_t *g, int mode)
{
    uint32_t np = 0, t0 = 0;
    while (t0 < g->ntex) {
        uint32_t t1 = t0 + 1u, u, v;
        /* the accumulation unit is needed by every pass but a lone first one: assume it unless one
         * pass holds everything */
        pass_cost(g, mode, 0, g->ntex, 0, &u, &v);
        int single = t0 == 0 && u <= g->units && v <= g->uvecs;
        if (single) {
            t1 = g->ntex;
        } else {
            pass_cost(g, mode, t0, t1, t0 > 0, &u, &v);
            if (u > g->units || v > g->uvecs) {
                set_log(g, "one map texture needs %u units and %u uniform vectors, the pass has %u and %u", u, v,
                      g->units, g->uvecs);
                return QIBL_E_GLES2_UNITS;
            }
            while (t1 < g->ntex) {
                pass_cost(g, mode, t0, t1 + 1u, t0 > 0, &u, &v);
                if (u > g->units || v > g->uvecs)
                    break;
                ++t1;
            }
            /* the first pass writes the accumulator but does not read it: no units for it */
        }
        if (np >= QIBL_GLES2_MAX_PASSES)
            return QIBL_E_GLES2_UNITS;
        g->pass_first[mode][np++] = (uint8_t)t0;
        t0 = t1;
    }
    g->pass_first[mode][np] = (uint8_t)g->ntex;
    g->npass[mode] = np;
    return QIBL_OK;
}

/* Fragment shader of pass `pass` of mode. */
static int build_fs(const qibl_gles2_t *g, int mode, uint32_t pass, sbuf *b)
{
    uint32_t np = g->npass[mode], t0 = g->pass_first[mode][pass], t1 = g->pass_first[mode][pass + 1u];
    int first = pass == 0, last = pass + 1u == np;
    uint32_t n = t1 - t0, i0, i1;
    pass_maps(g, t0, t1, &i0, &i1);
    emit(b, "%s", fs_head);
    emit(b, "uniform vec2 u_size;\nuniform vec3 u_bias;\n");
    for (uint32_t j = 0; j < n; ++j)
        emit(b, "uniform sampler2D u_t%u;\n", j);
    if (!first)
        emit(b, g->float_acc ? "uniform sampler2D u_acc;\n" : "uniform sampler2D u_acc, u_acclo;\n");
    if (!last && !g->float_acc)
        emit(b, "uniform float u_lo;\n");
    if (mode == QIBL_GLES2_MODE_DIR) {
        emit(b, "uniform vec4 u_w[%u];\n", n * (g->channels == 3u ? 1u : 3u));
    } else {
        emit(b, "uniform vec4 u_s[%u];\nuniform vec4 u_b[%u];\n", n, n);
        emit(b, "uniform sampler2D u_p0, u_p1, u_p2;\nuniform vec3 u_poff, u_pscale, u_lpos, u_lrgb;\n"
                "uniform vec2 u_lpar;\n"); /* x: min_dist, y: 1 = 1/d^2 */
        if (mode_lut(mode)) {
            for (uint32_t c = i0 / 2u; c <= (i1 - 1u) / 2u; ++c)
                emit(b, "uniform samplerCube u_y%u;\n", c);
            emit(b, "%s", fs_lut_dir);
        }
        if (mode_gonio(mode))
            emit(b, "%s%s", fs_gonio_tex, qibl_gles2_glsl_gonio);
    }
    emit(b, "%s%s", qibl_gles2_glsl_srgbe, fs_out);
    emit(b, "void main() {\n  vec2 tc = gl_FragCoord.xy * u_size;\n  vec4 t;\n  vec3 acc = u_bias;\n");
    if (mode != QIBL_GLES2_MODE_DIR) {
        /* P from three split-byte textures: 24-bit integers, exact in highp */
        /* P from three split-byte textures: 24-bit integers, exact in highp. The texels go through
         * variables first: texture2D's result has the sampler's precision (lowp by default), which
         * would carry into every operation that follows (Mesa then computes in fp16) */
        emit(b, "  vec3 q0 = texture2D(u_p0, tc).rgb, q1 = texture2D(u_p1, tc).rgb, q2 = texture2D(u_p2, tc).rgb;\n"
                "  const vec3 bytes = vec3(1.0, 256.0, 65536.0);\n"
                "  vec3 pu = vec3(dot(floor(q0 * 255.0 + 0.5), bytes), dot(floor(q1 * 255.0 + 0.5), bytes),\n"
                "                 dot(floor(q2 * 255.0 + 0.5), bytes));\n"
                "  vec3 l = u_lpos - (u_poff + pu * u_pscale);\n"
                "  float d = max(length(l), u_lpar.x);\n"
                "  vec3 u = length(l) > 0.0 ? l / length(l) : vec3(0.0, 0.0, 1.0);\n"
                "  float att = u_lpar.y > 0.5 ? 1.0 / (d * d) : 1.0 / d;\n"
                "  float y[%u];\n",
             2u * ((i1 - 1u) / 2u) + 2u); /* the LUT fills pairs */
        if (!mode_lut(mode)) {
            emit_sh(b, i1);
        } else {
            emit(b, "  vec3 ul = lut_dir(u);\n");
            for (uint32_t c = i0 / 2u; c <= (i1 - 1u) / 2u; ++c) {
                emit(b, "  t = textureCube(u_y%u, ul);\n  t = floor(t * (255.0 * 64.0) + 0.5) / 64.0;\n", c);
                /* bilinear filtering returns fractions of a byte: keep them (the 1/64 rounding only
                 * absorbs the 8-bit unorm's own error) */
                emit(b, "  y[%u] = (t.y * 256.0 + t.x - 32768.0) / 16384.0;\n", 2u * c);
                if (2u * c + 1u < g->lut_k)
                    emit(b, "  y[%u] = (t.w * 256.0 + t.z - 32768.0) / 16384.0;\n", 2u * c + 1u);
            }
        }
        emit(b, "  vec3 s = vec3(0.0);\n");
    }
    for (uint32_t j = 0; j < n; ++j) {
        emit(b, "  t = texture2D(u_t%u, tc);\n  t = floor(t * 255.0 + 0.5);\n", j); /* the bytes, exactly */
        for (uint32_t q = 0; q < 4u; ++q) {
            uint32_t p = 4u * (t0 + j) + q;
            if (p >= g->planes)
                break;
            uint32_t i = p / g->channels, ch = p % g->channels;
            if (mode == QIBL_GLES2_MODE_DIR) {
                if (g->channels == 3u)
                    emit(b, "  acc.%c += u_w[%u].%c * t.%c;\n", rgbc[ch], j, swz[q], swz[q]);
                else
                    emit(b, "  acc += vec3(u_w[%u].%c, u_w[%u].%c, u_w[%u].%c) * t.%c;\n", 3u * j, swz[q], 3u * j + 1u,
                         swz[q], 3u * j + 2u, swz[q], swz[q]);
            } else if (g->channels == 3u) {
                emit(b, "  s.%c += y[%u] * (u_s[%u].%c * t.%c + u_b[%u].%c);\n", rgbc[ch], i, j, swz[q], swz[q], j,
                     swz[q]);
            } else {
                emit(b, "  s += y[%u] * (u_s[%u].%c * t.%c + u_b[%u].%c);\n", i, j, swz[q], swz[q], j, swz[q]);
            }
        }
    }
    if (mode_gonio(mode)) /* the lamp's direction toward the pixel: -l */
        emit(b, "  acc += s * u_lrgb * att * gonio(-l);\n");
    else if (mode != QIBL_GLES2_MODE_DIR)
        emit(b, "  acc += s * u_lrgb * att;\n");
    if (!first && g->float_acc)
        emit(b, "  t = texture2D(u_acc, tc);\n  acc += t.rgb;\n");
    else if (!first)
        emit(b, "  t = texture2D(u_acc, tc);\n  acc += srgbe_dec(t);\n  t = texture2D(u_acclo, tc);\n  acc += srgbe_dec(t);\n");
    if (last)
        emit(b, "  gl_FragColor = tonemap(acc);\n");
    else if (g->float_acc)
        emit(b, "  gl_FragColor = vec4(acc, 1.0);\n");
    else /* two draws: the sRGBE code of the sum, then that of what the code leaves out */
        emit(b, "  vec4 hi = srgbe_enc(acc);\n  gl_FragColor = u_lo > 0.5 ? srgbe_enc(acc - srgbe_dec(hi)) : hi;\n");
    emit(b, "}\n");
    return b->overflow ? -1 : 0;
}

/* A shader's compile or a program's link status (is, log, del: the shader's or the program's calls):
 * on failure the object's log is kept in g->log and the object deleted. */
static int built(qibl_gles2_t *g, GLuint obj, GLenum pname, void(GL_APIENTRY *is)(GLuint, GLenum, GLint *),
                 void(GL_APIENTRY *log)(GLuint, GLsizei, GLsizei *, GLchar *), void(GL_APIENTRY *del)(GLuint))
{
    GLint ok = 0;
    is(obj, pname, &ok);
    if (ok)
        return 1;
    GLsizei len = 0;
    log(obj, (GLsizei)sizeof g->log, &len, g->log);
    del(obj);
    return 0;
}

static qibl_status_t compile(qibl_gles2_t *g, GLenum type, const char *src, GLuint *out)
{
    GLuint s = glCreateShader(type);
    if (s == 0)
        return gl_check(g, "glCreateShader") != QIBL_OK ? QIBL_E_GLES2_GL_ERROR : QIBL_E_GLES2_COMPILE;
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    if (!built(g, s, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader))
        return QIBL_E_GLES2_COMPILE;
    *out = s;
    return QIBL_OK;
}

static qibl_status_t link_program(qibl_gles2_t *g, const char *fs_src, GLuint *out)
{
    GLuint fs = 0;
    qibl_status_t st = compile(g, GL_FRAGMENT_SHADER, fs_src, &fs);
    if (st != QIBL_OK)
        return st;
    GLuint p = glCreateProgram();
    glAttachShader(p, g->vs);
    glAttachShader(p, fs);
    glBindAttribLocation(p, 0, "a_pos");
    glLinkProgram(p);
    glDeleteShader(fs); /* flagged: freed with the program */
    if (!built(g, p, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram))
        return QIBL_E_GLES2_LINK;
    /* a GL error after the link: the program is deleted here, so a failing call hands back nothing */
    qibl_status_t gst = gl_check(g, "glLinkProgram");
    if (gst != QIBL_OK) {
        glDeleteProgram(p);
        return gst;
    }
    *out = p;
    return QIBL_OK;
}

/* ---- init / upload / destroy ----------------------------------------------------------------- */

static void delete_upload(qibl_gles2_t *g)
{
    GLuint *lists[3] = {g->map_tex, g->p_tex, g->lut_tex};
    uint32_t counts[3] = {QIBL_GLES2_MAX_TEX, 3u, QIBL_GLES2_MAX_LUT_TEX};
    for (int l = 0; l < 3; ++l)
        for (uint32_t i = 0; i < counts[l]; ++i)
            if (lists[l][i] != 0u) {
                glDeleteTextures(1, &lists[l][i]);
                lists[l][i] = 0;
            }
    if (g->gonio_tex != 0u)
        glDeleteTextures(1, &g->gonio_tex);
    g->gonio_tex = g->gonio_n = 0;
    for (int i = 0; i < 4; ++i) {
        if (g->acc_tex[i] != 0u)
            glDeleteTextures(1, &g->acc_tex[i]);
        g->acc_tex[i] = 0;
    }
    for (int i = 0; i < 2; ++i) {
        if (g->fbo[i] != 0u)
            glDeleteFramebuffers(1, &g->fbo[i]);
        g->fbo[i] = 0;
    }
    GLint cur = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &cur);
    for (int m = 0; m < QIBL_GLES2_MODE_COUNT; ++m) {
        for (uint32_t i = 0; i < QIBL_GLES2_MAX_PASSES; ++i)
            if (g->prog[m][i] != 0u) {
                if ((GLuint)cur == g->prog[m][i]) /* a program in use is only flagged for deletion */
                    glUseProgram(0);
                glDeleteProgram(g->prog[m][i]);
                g->prog[m][i] = 0;
            }
        g->npass[m] = 0;
    }
    g->loaded = 0;
    g->has_pmap = g->has_lut = 0;
}

void qibl_gles2_destroy(qibl_gles2_t *g)
{
    if (g == NULL)
        return;
    delete_upload(g);
    if (g->vbo != 0u)
        glDeleteBuffers(1, &g->vbo);
    if (g->vs != 0u)
        glDeleteShader(g->vs);
    memset(g, 0, sizeof *g);
}

qibl_status_t qibl_gles2_init(qibl_gles2_t *g, const qibl_gles2_desc_t *d)
{
    if (g == NULL)
        return QIBL_E_NULL_POINTER;
    memset(g, 0, sizeof *g);
    if (glGetString(GL_VERSION) == NULL) {
        set_log(g, "glGetString(GL_VERSION) returned NULL: no current context");
        return QIBL_E_GLES2_CONTEXT;
    }
    while (glGetError() != GL_NO_ERROR)
        ;
    GLint units = 0, uvecs = 0, tsize = 0, csize = 0, range[2] = {0, 0}, prec = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    glGetIntegerv(GL_MAX_FRAGMENT_UNIFORM_VECTORS, &uvecs);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &tsize);
    glGetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &csize);
    glGetShaderPrecisionFormat(GL_FRAGMENT_SHADER, GL_HIGH_FLOAT, range, &prec);
    g->units = units > 0 ? (uint32_t)units : 0u;
    g->uvecs = uvecs > 0 ? (uint32_t)uvecs : 0u;
    if (d != NULL && d->max_units != 0u && d->max_units < g->units)
        g->units = d->max_units;
    if (d != NULL && d->max_uniform_vectors != 0u && d->max_uniform_vectors < g->uvecs)
        g->uvecs = d->max_uniform_vectors;
    if (d != NULL && d->float_accum) {
        const char *ext = (const char *)glGetString(GL_EXTENSIONS);
        g->want_float = ext != NULL && strstr(ext, "GL_OES_texture_float") != NULL;
    }
    g->max_tex_size = tsize > 0 ? (uint32_t)tsize : 0u;
    g->max_cube_size = csize > 0 ? (uint32_t)csize : 0u;
    g->highp = prec >= 23; /* fp32 significand; 0 when the GPU has no highp in fragment shaders */
    if (g->units < 2u || g->uvecs < 8u) {
        set_log(g, "%u texture units and %u uniform vectors: at least 2 and 8 are needed", g->units, g->uvecs);
        return QIBL_E_GLES2_UNITS;
    }
    GLuint vs = 0;
    qibl_status_t st = compile(g, GL_VERTEX_SHADER, vs_src, &vs);
    if (st != QIBL_OK)
        return st;
    g->vs = vs;
    static const float quad[8] = {-1.0f, -1.0f, 1.0f, -1.0f, -1.0f, 1.0f, 1.0f, 1.0f};
    GLuint vbo = 0;
    glGenBuffers(1, &vbo);
    g->vbo = vbo;
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof quad, quad, GL_STATIC_DRAW);
    st = gl_check(g, "creating the quad");
    if (st != QIBL_OK) {
        qibl_gles2_destroy(g);
        set_log(g, "glGetError after creating the quad");
        return st;
    }
    g->ready = 1;
    return QIBL_OK;
}

static GLuint new_tex(GLenum target, GLint filter)
{
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(target, t);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

enum { CHUNK = 1024 }; /* pixels per upload call: a 4 KiB stack buffer, no heap */

static void upload_maps(qibl_gles2_t *g, const qibl_shmaps_t *m)
{
    uint8_t buf[4 * CHUNK];
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (uint32_t j = 0; j < g->ntex; ++j) {
        g->map_tex[j] = new_tex(GL_TEXTURE_2D, GL_NEAREST);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, (GLsizei)m->width, (GLsizei)m->height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     NULL);
        for (uint32_t y = 0; y < m->height; ++y)
            for (uint32_t x0 = 0; x0 < m->width; x0 += CHUNK) {
                uint32_t n = m->width - x0 < CHUNK ? m->width - x0 : CHUNK;
                for (uint32_t q = 0; q < 4u; ++q) {
                    uint32_t p = 4u * j + q;
                    /* plane p is map p / channels, channel p % channels; either layout of shmaps.h */
                    for (uint32_t x = 0; x < n; ++x)
                        buf[4u * x + q] = p < g->planes ? qibl_shmaps_texel(m, p / m->channels, p % m->channels,
                                                                            x0 + x, y)
                                                        : 0u;
                }
                glTexSubImage2D(GL_TEXTURE_2D, 0, (GLint)x0, (GLint)y, (GLsizei)n, 1, GL_RGBA, GL_UNSIGNED_BYTE, buf);
            }
    }
}

static void upload_pmap(qibl_gles2_t *g, const qibl_pmap_t *p)
{
    uint8_t buf[3 * CHUNK];
    size_t npx = (size_t)p->width * p->height;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (uint32_t c = 0; c < 3u; ++c) {
        int32_t lo = INT32_MAX, hi = INT32_MIN;
        for (size_t i = 0; i < npx; ++i) {
            int32_t v = qibl_load_s32le(p->points + 12u * i + 4u * c);
            lo = v < lo ? v : lo, hi = v > hi ? v : hi;
        }
        uint32_t range = (uint32_t)((int64_t)hi - lo), s = 0;
        while ((range >> s) > 0xFFFFFFu)
            ++s;
        g->poff[c] = (float)((double)lo / 65536.0);
        g->pscale[c] = (float)ldexp(1.0, (int)s - 16);
        g->p_tex[c] = new_tex(GL_TEXTURE_2D, GL_NEAREST);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, (GLsizei)p->width, (GLsizei)p->height, 0, GL_RGB, GL_UNSIGNED_BYTE, NULL);
        for (uint32_t y = 0; y < p->height; ++y)
            for (uint32_t x0 = 0; x0 < p->width; x0 += CHUNK) {
                uint32_t n = p->width - x0 < CHUNK ? p->width - x0 : CHUNK;
                for (uint32_t x = 0; x < n; ++x) {
                    size_t i = (size_t)y * p->width + x0 + x;
                    uint64_t u = (uint64_t)((int64_t)qibl_load_s32le(p->points + 12u * i + 4u * c) - lo);
                    if (s > 0u)
                        u = (u + (1u << (s - 1u))) >> s; /* round half up, then keep 24 bits */
                    if (u > 0xFFFFFFu)
                        u = 0xFFFFFFu;
                    buf[3u * x] = (uint8_t)u, buf[3u * x + 1u] = (uint8_t)(u >> 8), buf[3u * x + 2u] = (uint8_t)(u >> 16);
                }
                glTexSubImage2D(GL_TEXTURE_2D, 0, (GLint)x0, (GLint)y, (GLsizei)n, 1, GL_RGB, GL_UNSIGNED_BYTE, buf);
            }
    }
}

/* LUT: two maps per RGBA cube map, each Q2.14 value + 32768 as low byte, high byte. Filter: linear
 * (bilinear mode) is set per draw. */
static void upload_lut(qibl_gles2_t *g, const qibl_ylut_t *t)
{
    uint8_t buf[4 * 256];
    uint32_t n = t->face_size, k = t->k;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (uint32_t c = 0; c < (k + 1u) / 2u; ++c) {
        g->lut_tex[c] = new_tex(GL_TEXTURE_CUBE_MAP, GL_NEAREST);
        for (uint32_t f = 0; f < 6u; ++f) {
            GLenum face = (GLenum)(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f);
            glTexImage2D(face, 0, GL_RGBA, (GLsizei)n, (GLsizei)n, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
            for (uint32_t v = 0; v < n; ++v) {
                for (uint32_t u = 0; u < n; ++u)
                    for (uint32_t h = 0; h < 2u; ++h) {
                        uint32_t i = 2u * c + h;
                        uint32_t val = 32768u;
                        if (i < k) {
                            size_t off = 2u * ((((size_t)f * n + v) * n + u) * k + i);
                            val = (uint32_t)((int32_t)qibl_load_s16le(t->values + off) + 32768);
                        }
                        buf[4u * u + 2u * h] = (uint8_t)val, buf[4u * u + 2u * h + 1u] = (uint8_t)(val >> 8);
                    }
                glTexSubImage2D(face, 0, 0, (GLint)v, (GLsizei)n, 1, GL_RGBA, GL_UNSIGNED_BYTE, buf);
            }
        }
    }
}

qibl_status_t qibl_gles2_upload(qibl_gles2_t *g, const qibl_shmaps_t *m, const qibl_pmap_t *p, const qibl_ylut_t *lut)
{
    if (g == NULL || m == NULL)
        return QIBL_E_NULL_POINTER;
    if (!g->ready)
        return QIBL_E_GLES2_STATE;
    qibl_status_t st = qibl_shmap_check(m);
    if (st != QIBL_OK)
        return st;
    if ((p != NULL && (p->points == NULL)) || (lut != NULL && lut->values == NULL))
        return QIBL_E_NULL_POINTER;
    if ((p != NULL && (p->width != m->width || p->height != m->height)) ||
        (lut != NULL && (lut->k < m->k || lut->k > (uint32_t)QIBL_SH_MAX_COUNT || lut->face_size == 0u ||
                         lut->face_size > QIBL_ASSET_MAX_LUT)))
        return QIBL_E_SHMAP_MISMATCH;
    /* upload_lut reads 12 N N k bytes: the view must hold them */
    if (lut != NULL && (st = qibl_ylut_check(lut)) != QIBL_OK)
        return st;
    if (m->width > g->max_tex_size || m->height > g->max_tex_size ||
        (lut != NULL && lut->face_size > g->max_cube_size)) {
        set_log(g, "maps %ux%u (LUT faces %u) against GL_MAX_TEXTURE_SIZE %u, cube %u", m->width, m->height,
              lut ? lut->face_size : 0u, g->max_tex_size, g->max_cube_size);
        return QIBL_E_GLES2_SIZE;
    }
    delete_upload(g);
    GLint caller_fb = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &caller_fb);
    g->width = m->width, g->height = m->height, g->k = m->k, g->channels = m->channels;
    g->planes = m->k * m->channels;
    g->ntex = (g->planes + 3u) / 4u;
    for (uint32_t i = 0; i < g->planes; ++i) {
        g->scale[i] = (float)((double)qibl_load_s32le(m->params + 8u * i) / 16777216.0);
        g->bias[i] = (float)((double)qibl_load_s32le(m->params + 8u * i + 4u) / 16777216.0);
    }
    while (glGetError() != GL_NO_ERROR)
        ;
    upload_maps(g, m);
    if (p != NULL)
        upload_pmap(g, p), g->has_pmap = 1;
    if (lut != NULL)
        upload_lut(g, lut), g->has_lut = 1, g->lut_n = lut->face_size, g->lut_k = lut->k;
    /* accumulation ping-pong: RGBA8 sRGBE, nearest (texel i is pixel i) */
    for (int i = 0; i < 2; ++i) {
        GLuint fb = 0;
        glGenFramebuffers(1, &fb);
        g->fbo[i] = fb;
    }
    g->float_acc = 0;
    /* float accumulators if they can be rendered to, else the sRGBE pair. Formats tried: the
     * GLES2 + OES_texture_float form (unsized RGBA, FLOAT), then RGBA32F (0x8814: a GLES3 context
     * with EXT_color_buffer_float, as Mesa gives), both fp32. */
    static const GLint fl_internal[2] = {GL_RGBA, 0x8814};
    for (int f = 0; g->want_float && f < 2 && !g->float_acc; ++f) {
        while (glGetError() != GL_NO_ERROR)
            ;
        g->float_acc = 1;
        for (int i = 0; i < 2 && g->float_acc; ++i) {
            g->acc_tex[i] = new_tex(GL_TEXTURE_2D, GL_NEAREST);
            glTexImage2D(GL_TEXTURE_2D, 0, fl_internal[f], (GLsizei)m->width, (GLsizei)m->height, 0, GL_RGBA, GL_FLOAT,
                         NULL);
            glBindFramebuffer(GL_FRAMEBUFFER, g->fbo[i]);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->acc_tex[i], 0);
            g->float_acc = glGetError() == GL_NO_ERROR && glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        }
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)caller_fb);
        if (!g->float_acc)
            for (int i = 0; i < 2; ++i)
                if (g->acc_tex[i] != 0u)
                    glDeleteTextures(1, &g->acc_tex[i]), g->acc_tex[i] = 0;
        while (glGetError() != GL_NO_ERROR)
            ;
    }
    for (int i = 0; i < 4 && !g->float_acc; ++i) {
        g->acc_tex[i] = new_tex(GL_TEXTURE_2D, GL_NEAREST);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, (GLsizei)m->width, (GLsizei)m->height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     NULL);
    }
    st = gl_check(g, "uploading textures");
    for (int mode = 0; st == QIBL_OK && mode < QIBL_GLES2_MODE_COUNT; ++mode)
        if (plan(g, mode) != QIBL_OK)
            g->npass[mode] = 0; /* reported by the draw of that mode */
    if (st != QIBL_OK) {
        char keep[QIBL_GLES2_LOG_SIZE];
        memcpy(keep, g->log, sizeof keep);
        delete_upload(g);
        memcpy(g->log, keep, sizeof keep);
        return st;
    }
    g->loaded = 1;
    return QIBL_OK;
}

/* ---- drawing --------------------------------------------------------------------------------- */

static void set1i(GLuint prog, const char *name, GLint v)
{
    GLint loc = glGetUniformLocation(prog, name);
    if (loc >= 0)
        glUniform1i(loc, v);
}

static void set3f(GLuint prog, const char *name, const float v[3])
{
    GLint loc = glGetUniformLocation(prog, name);
    if (loc >= 0)
        glUniform3f(loc, v[0], v[1], v[2]);
}

/* What a draw needs per pass besides the maps: the per-plane uniforms and the light. */
typedef struct {
    int mode;
    float pw[75][3]; /* directional: weight of plane p to output channel ch, per byte value */
    float bias[3];
    float pass_bias[QIBL_GLES2_MAX_PASSES][3]; /* the part of bias each pass adds */
    float ps[75], pb[75]; /* point: per plane scale and bias, per byte value */
    float lpos[3], lrgb[3], lpar[2];
    int lut_linear;
    float gx[3], gy[3], gz[3]; /* the goniometric lamp's frame (gonio modes) */
} drawdesc;

/* Passes accumulate in sRGBE, whose error is relative to the pixel's largest partial sum. The core
 * folds all the maps' range-packing biases into one B = sum bias_i L_i, which cancels the large sum
 * of c_i W_i only at the end; so each pass adds the bias of its own planes (W_p 2^shift bias_p /
 * scale_p) and the first pass the remainder of B, which keeps every partial sum the size of the
 * decoded terms T_i L_i. */
static void split_bias(const qibl_gles2_t *g, drawdesc *dd, int mode, uint32_t np)
{
    for (uint32_t pass = 0; pass < np; ++pass)
        dd->pass_bias[pass][0] = dd->pass_bias[pass][1] = dd->pass_bias[pass][2] = 0.0f;
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        double rest = (double)dd->bias[ch];
        if (mode == QIBL_GLES2_MODE_DIR && np > 1u)
            for (uint32_t pass = 0; pass < np; ++pass)
                for (uint32_t p = 4u * g->pass_first[mode][pass]; p < 4u * g->pass_first[mode][pass + 1u] && p < g->planes;
                     ++p) {
                    if (g->scale[p] == 0.0f || (g->channels == 3u && p % 3u != ch))
                        continue;
                    double share = (double)dd->pw[p][ch] * (double)g->bias[p] / (double)g->scale[p];
                    dd->pass_bias[pass][ch] += (float)share;
                    rest -= share;
                }
        dd->pass_bias[0][ch] += (float)rest;
    }
}

/* the pass's program, generated and linked on its first use */
static qibl_status_t pass_program(qibl_gles2_t *g, int mode, uint32_t pass, GLuint *prog)
{
    if (g->prog[mode][pass] == 0u) {
        char local[SRC_SIZE]; /* on the stack: a static scratch would break reentrancy */
        sbuf b = {local, 0, sizeof local, 0};
        if (build_fs(g, mode, pass, &b) != 0) {
            set_log(g, "generated fragment shader longer than %d bytes", SRC_SIZE);
            return QIBL_E_GLES2_COMPILE;
        }
        GLuint p = 0;
        qibl_status_t st = link_program(g, local, &p);
        if (st != QIBL_OK)
            return st;
        g->prog[mode][pass] = p;
    }
    *prog = g->prog[mode][pass];
    return QIBL_OK;
}

/* the point modes' P maps, light and (POINT_LUT) Y tables; *unit the next free texture unit */
static void point_uniforms(const qibl_gles2_t *g, const drawdesc *dd, int mode, GLuint prog, uint32_t t0, uint32_t t1,
                           uint32_t *unit)
{
    char name[32];
    for (uint32_t c = 0; c < 3u; ++c) {
        glActiveTexture(GL_TEXTURE0 + *unit);
        glBindTexture(GL_TEXTURE_2D, g->p_tex[c]);
        snprintf(name, sizeof name, "u_p%u", c);
        set1i(prog, name, (GLint)(*unit)++);
    }
    set3f(prog, "u_poff", g->poff);
    set3f(prog, "u_pscale", g->pscale);
    set3f(prog, "u_lpos", dd->lpos);
    set3f(prog, "u_lrgb", dd->lrgb);
    glUniform2f(glGetUniformLocation(prog, "u_lpar"), dd->lpar[0], dd->lpar[1]);
    if (mode_gonio(mode)) {
        glActiveTexture(GL_TEXTURE0 + *unit);
        glBindTexture(GL_TEXTURE_2D, g->gonio_tex);
        set1i(prog, "u_g", (GLint)(*unit)++);
        set3f(prog, "u_gx", dd->gx);
        set3f(prog, "u_gy", dd->gy);
        set3f(prog, "u_gz", dd->gz);
        glUniform1f(glGetUniformLocation(prog, "u_gn"), (float)g->gonio_n);
    }
    if (!mode_lut(mode))
        return;
    GLint ln = glGetUniformLocation(prog, "u_lutn"), lnear = glGetUniformLocation(prog, "u_lutnear");
    if (ln >= 0)
        glUniform1f(ln, (float)g->lut_n);
    if (lnear >= 0)
        glUniform1f(lnear, dd->lut_linear ? 0.0f : 1.0f);
    uint32_t i0, i1;
    pass_maps(g, t0, t1, &i0, &i1);
    for (uint32_t c = i0 / 2u; c <= (i1 - 1u) / 2u; ++c) {
        glActiveTexture(GL_TEXTURE0 + *unit);
        glBindTexture(GL_TEXTURE_CUBE_MAP, g->lut_tex[c]);
        GLint f = dd->lut_linear ? GL_LINEAR : GL_NEAREST;
        glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, f);
        glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, f);
        snprintf(name, sizeof name, "u_y%u", c);
        set1i(prog, name, (GLint)(*unit)++);
    }
}

/* the pass's maps and per-plane weights (directional) or scales and biases (point); *unit the next
 * free texture unit */
static void pass_uniforms(const qibl_gles2_t *g, const drawdesc *dd, const qibl_gles2_out_t *out, int mode,
                          uint32_t pass, GLuint prog, uint32_t *unit)
{
    GLint loc = glGetUniformLocation(prog, "u_size");
    glUniform2f(loc, 1.0f / (float)g->width, 1.0f / (float)g->height);
    set3f(prog, "u_bias", dd->pass_bias[pass]);
    loc = glGetUniformLocation(prog, "u_out");
    if (loc >= 0)
        glUniform2f(loc, out && out->exposure ? (float)out->exposure / 65536.0f : 1.0f, out && out->srgb ? 1.0f : 0.0f);
    uint32_t t0 = g->pass_first[mode][pass], t1 = g->pass_first[mode][pass + 1u];
    char name[32];
    float vec[75 * 4];
    for (uint32_t j = 0; j < t1 - t0; ++j) {
        glActiveTexture(GL_TEXTURE0 + *unit);
        glBindTexture(GL_TEXTURE_2D, g->map_tex[t0 + j]);
        snprintf(name, sizeof name, "u_t%u", j);
        set1i(prog, name, (GLint)(*unit)++);
        for (uint32_t q = 0; q < 4u; ++q) {
            uint32_t p = 4u * (t0 + j) + q;
            int in = p < g->planes;
            if (mode == QIBL_GLES2_MODE_DIR && g->channels == 3u) {
                vec[4u * j + q] = in ? dd->pw[p][p % 3u] : 0.0f;
            } else if (mode == QIBL_GLES2_MODE_DIR) {
                for (uint32_t ch = 0; ch < 3u; ++ch)
                    vec[4u * (3u * j + ch) + q] = in ? dd->pw[p][ch] : 0.0f;
            } else {
                vec[4u * j + q] = in ? dd->ps[p] : 0.0f;
                vec[4u * (t1 - t0 + j) + q] = in ? dd->pb[p] : 0.0f;
            }
        }
    }
    if (mode == QIBL_GLES2_MODE_DIR) {
        glUniform4fv(glGetUniformLocation(prog, "u_w"), (GLsizei)((t1 - t0) * (g->channels == 3u ? 1u : 3u)), vec);
    } else {
        glUniform4fv(glGetUniformLocation(prog, "u_s"), (GLsizei)(t1 - t0), vec);
        glUniform4fv(glGetUniformLocation(prog, "u_b"), (GLsizei)(t1 - t0), vec + 4u * (t1 - t0));
        point_uniforms(g, dd, mode, prog, t0, t1, unit);
    }
}

/* pass i reads the codes pass i - 1 wrote (acc_tex[2 ((i + 1) % 2) + 0 and 1]) and writes
 * acc_tex[2 (i % 2) + 0 and 1], high code then low code, each its own draw (GLES2 has one colour
 * attachment); the last pass draws into the caller's framebuffer */
static qibl_status_t pass_draws(qibl_gles2_t *g, GLuint prog, uint32_t pass, uint32_t np, uint32_t unit,
                                GLint caller_fb)
{
    int first = pass == 0, last = pass + 1u == np;
    const uint32_t per = g->float_acc ? 1u : 2u; /* accumulator textures per pass */
    if (!first) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(GL_TEXTURE_2D, g->acc_tex[per * ((pass + 1u) % 2u)]);
        set1i(prog, "u_acc", (GLint)unit++);
        if (!g->float_acc) {
            glActiveTexture(GL_TEXTURE0 + unit);
            glBindTexture(GL_TEXTURE_2D, g->acc_tex[2u * ((pass + 1u) % 2u) + 1u]);
            set1i(prog, "u_acclo", (GLint)unit++);
        }
    }
    GLint lo_loc = glGetUniformLocation(prog, "u_lo");
    for (uint32_t h = 0; h < (last ? 1u : per); ++h) {
        if (last) {
            glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)caller_fb);
        } else {
            glBindFramebuffer(GL_FRAMEBUFFER, g->fbo[pass % 2u]);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->acc_tex[per * (pass % 2u) + h],
                                   0);
            GLenum fs = glCheckFramebufferStatus(GL_FRAMEBUFFER);
            if (fs != GL_FRAMEBUFFER_COMPLETE) {
                set_log(g, "glCheckFramebufferStatus 0x%04x for the RGBA8 accumulator", (unsigned)fs);
                return QIBL_E_GLES2_FRAMEBUFFER;
            }
            if (lo_loc >= 0)
                glUniform1f(lo_loc, (float)h);
        }
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        qibl_status_t st = gl_check(g, "a relighting pass");
        if (st != QIBL_OK)
            return st;
    }
    return QIBL_OK;
}

static qibl_status_t draw(qibl_gles2_t *g, drawdesc *dd, const qibl_gles2_out_t *out)
{
    int mode = dd->mode;
    if (g->npass[mode] == 0u) {
        qibl_status_t st = plan(g, mode);
        if (st != QIBL_OK)
            return st;
    }
    while (glGetError() != GL_NO_ERROR)
        ;
    GLint caller_fb = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &caller_fb);
    glViewport(0, 0, (GLsizei)g->width, (GLsizei)g->height);
    glDisable(GL_BLEND), glDisable(GL_DEPTH_TEST), glDisable(GL_SCISSOR_TEST), glDisable(GL_STENCIL_TEST);
    glDisable(GL_CULL_FACE), glDisable(GL_DITHER);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    uint32_t np = g->npass[mode];
    split_bias(g, dd, mode, np);
    for (uint32_t pass = 0; pass < np; ++pass) {
        GLuint prog = 0;
        qibl_status_t st = pass_program(g, mode, pass, &prog);
        if (st == QIBL_OK) {
            uint32_t unit = 0;
            glUseProgram(prog);
            pass_uniforms(g, dd, out, mode, pass, prog, &unit);
            st = pass_draws(g, prog, pass, np, unit, caller_fb);
        }
        if (st != QIBL_OK) { /* the caller's framebuffer bound again, as on success */
            glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)caller_fb);
            return st;
        }
    }
    glActiveTexture(GL_TEXTURE0);
    g->last_passes = np;
    return QIBL_OK;
}

static qibl_status_t draw_checks(qibl_gles2_t *g, const void *w)
{
    if (g == NULL || w == NULL)
        return QIBL_E_NULL_POINTER;
    if (!g->ready || !g->loaded)
        return QIBL_E_GLES2_STATE;
    return QIBL_OK;
}

qibl_status_t qibl_gles2_relight(qibl_gles2_t *g, const qibl_shmap_weights_t *w, const qibl_gles2_out_t *out)
{
    qibl_status_t st = draw_checks(g, w);
    if (st != QIBL_OK)
        return st;
    if (w->k != g->k || w->channels != g->channels)
        return QIBL_E_GLES2_MISMATCH;
    drawdesc dd;
    memset(&dd, 0, sizeof dd);
    dd.mode = QIBL_GLES2_MODE_DIR;
    /* out = acc * 2^shift + bias in Q16.16 with acc = sum c W: per plane and output channel the
     * float weight W 2^shift / 2^16 (the shader rebuilds the byte c) */
    for (uint32_t ch = 0; ch < 3u; ++ch) {
        double unit = ldexp(1.0, w->shift[ch] - 16);
        for (uint32_t i = 0; i < g->k; ++i) {
            if (g->channels == 3u)
                dd.pw[i * 3u + ch][ch] = (float)(w->w[ch][i] * unit);
            else
                dd.pw[i][ch] = (float)(w->w[ch][i] * unit);
        }
        dd.bias[ch] = (float)((double)w->bias[ch] / 65536.0);
    }
    return draw(g, &dd, out);
}

/* qibl_gles2_point's checks and its draw description */
static qibl_status_t point_desc(qibl_gles2_t *g, const qibl_shmap_point_t *pt, drawdesc *dd)
{
    qibl_status_t st = draw_checks(g, pt);
    if (st != QIBL_OK)
        return st;
    if (pt->maps == NULL || pt->maps->k != g->k || pt->maps->channels != g->channels)
        return QIBL_E_GLES2_MISMATCH;
    if (!g->has_pmap || (pt->lut != NULL && !g->has_lut)) {
        set_log(g, "point light needs %s, not uploaded", g->has_pmap ? "the LUT" : "the P map");
        return QIBL_E_GLES2_STATE;
    }
    if (!g->highp) {
        set_log(g, "GL_HIGH_FLOAT in fragment shaders has under 23 bits: the P map cannot be rebuilt");
        return QIBL_E_GLES2_NO_HIGHP;
    }
    memset(dd, 0, sizeof *dd);
    dd->mode = pt->lut != NULL ? QIBL_GLES2_MODE_POINT_LUT : QIBL_GLES2_MODE_POINT_SH;
    for (uint32_t p = 0; p < g->planes; ++p)
        dd->ps[p] = g->scale[p], dd->pb[p] = g->bias[p];
    for (uint32_t c = 0; c < 3u; ++c) {
        dd->lpos[c] = (float)((double)pt->pos[c] / 65536.0);
        dd->lrgb[c] = (float)((double)pt->rgb[c] / 65536.0);
    }
    dd->lpar[0] = (float)(sqrt((double)pt->min_d2) / 65536.0);
    dd->lpar[1] = pt->falloff == (uint32_t)QIBL_FALLOFF_INV_DIST2 ? 1.0f : 0.0f;
    dd->lut_linear = pt->filter == (uint32_t)QIBL_LUT_BILINEAR;
    return QIBL_OK;
}

qibl_status_t qibl_gles2_point(qibl_gles2_t *g, const qibl_shmap_point_t *pt, const qibl_gles2_out_t *out)
{
    drawdesc dd;
    qibl_status_t st = point_desc(g, pt, &dd);
    return st != QIBL_OK ? st : draw(g, &dd, out);
}

/* the table as a 16-bit LUMINANCE_ALPHA texture (low byte, high byte), row j of the table on
 * texture row j; the texture is made once per side and refilled at every draw */
static qibl_status_t upload_gonio(qibl_gles2_t *g, const qibl_gonio_t *gonio)
{
    uint8_t buf[2u * QIBL_GONIO_MAX_N];
    const uint32_t n = gonio->n;
    while (glGetError() != GL_NO_ERROR)
        ;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (g->gonio_tex == 0u || g->gonio_n != n) {
        if (g->gonio_tex != 0u)
            glDeleteTextures(1, &g->gonio_tex);
        g->gonio_tex = new_tex(GL_TEXTURE_2D, GL_NEAREST);
        g->gonio_n = n;
        glTexImage2D(GL_TEXTURE_2D, 0, GL_LUMINANCE_ALPHA, (GLsizei)n, (GLsizei)n, 0, GL_LUMINANCE_ALPHA,
                     GL_UNSIGNED_BYTE, NULL);
    } else {
        glBindTexture(GL_TEXTURE_2D, g->gonio_tex);
    }
    for (uint32_t j = 0; j < n; ++j) {
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t v = gonio->table[(size_t)j * n + i];
            buf[2u * i] = (uint8_t)v, buf[2u * i + 1u] = (uint8_t)(v >> 8);
        }
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, (GLint)j, (GLsizei)n, 1, GL_LUMINANCE_ALPHA, GL_UNSIGNED_BYTE, buf);
    }
    qibl_status_t st = gl_check(g, "uploading the goniometric table");
    if (st != QIBL_OK) {
        glDeleteTextures(1, &g->gonio_tex);
        g->gonio_tex = g->gonio_n = 0;
    }
    return st;
}

qibl_status_t qibl_gles2_point_gonio(qibl_gles2_t *g, const qibl_shmap_point_t *pt, const qibl_gonio_t *gonio,
                                     const qibl_gles2_out_t *out)
{
    if (g == NULL || pt == NULL || gonio == NULL || gonio->table == NULL)
        return QIBL_E_NULL_POINTER;
    drawdesc dd;
    qibl_status_t st = point_desc(g, pt, &dd);
    if (st != QIBL_OK)
        return st;
    if (gonio->n < QIBL_GONIO_MIN_N || gonio->n > QIBL_GONIO_MAX_N || gonio->n > g->max_tex_size)
        return QIBL_E_GONIO_SIZE;
    dd.mode = pt->lut != NULL ? QIBL_GLES2_MODE_POINT_LUT_GONIO : QIBL_GLES2_MODE_POINT_SH_GONIO;
    for (uint32_t c = 0; c < 3u; ++c) {
        dd.gx[c] = (float)ldexp((double)gonio->x[c], -30);
        dd.gy[c] = (float)ldexp((double)gonio->y[c], -30);
        dd.gz[c] = (float)ldexp((double)gonio->z[c], -30);
    }
    st = upload_gonio(g, gonio);
    return st != QIBL_OK ? st : draw(g, &dd, out);
}

uint32_t qibl_gles2_passes(const qibl_gles2_t *g)
{
    return g != NULL ? g->last_passes : 0u;
}

const char *qibl_gles2_log(const qibl_gles2_t *g)
{
    return g != NULL ? g->log : "";
}

qibl_status_t qibl_gles2_srgbe_check(qibl_gles2_t *g, const uint8_t *codes, uint32_t n, float mul, uint8_t *out)
{
    if (g == NULL || codes == NULL || out == NULL)
        return QIBL_E_NULL_POINTER;
    if (!g->ready)
        return QIBL_E_GLES2_STATE;
    if (n == 0u || n > g->max_tex_size)
        return QIBL_E_GLES2_SIZE;
    char src[4096];
    sbuf b = {src, 0, sizeof src, 0};
    emit(&b, "%s%suniform sampler2D u_in;\nuniform float u_mul;\nuniform vec2 u_size;\n"
             "void main() { gl_FragColor = srgbe_enc(srgbe_dec(texture2D(u_in, gl_FragCoord.xy * u_size)) * u_mul); }\n",
         fs_head, qibl_gles2_glsl_srgbe);
    GLuint prog = 0, tex[2] = {0, 0}, fb = 0;
    GLint caller_fb = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &caller_fb);
    qibl_status_t st = link_program(g, src, &prog);
    if (st != QIBL_OK)
        return st;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int i = 0; i < 2; ++i) {
        tex[i] = new_tex(GL_TEXTURE_2D, GL_NEAREST);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, (GLsizei)n, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, i == 0 ? codes : NULL);
    }
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[1], 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        st = QIBL_E_GLES2_FRAMEBUFFER;
    } else {
        glViewport(0, 0, (GLsizei)n, 1);
        glDisable(GL_BLEND), glDisable(GL_DITHER);
        glUseProgram(prog);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, tex[0]);
        set1i(prog, "u_in", 0);
        glUniform1f(glGetUniformLocation(prog, "u_mul"), mul);
        glUniform2f(glGetUniformLocation(prog, "u_size"), 1.0f / (float)n, 1.0f);
        glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        glReadPixels(0, 0, (GLsizei)n, 1, GL_RGBA, GL_UNSIGNED_BYTE, out);
        st = gl_check(g, "the sRGBE check pass");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)caller_fb);
    glDeleteFramebuffers(1, &fb);
    glDeleteTextures(2, tex);
    glDeleteProgram(prog);
    return st;
}
