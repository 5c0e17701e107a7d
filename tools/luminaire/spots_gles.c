/*
 * luminaire/spots_gles.c - a near-field source's spotlights evaluated on a GLES2 GPU, one pass per
 * spotlight, accumulated in 8-bit sRGBE pairs (spots_gles.h).
 *
 * Invariants: what every pass needs goes up once per frame (the P map's points and the anchors'
 * numerators n.(a_k - x) V rho / pi = base_k |x - a_k|^3, as binary32 textures, OES_texture_float);
 * every spotlight's gonio table sits in one atlas texture, fetched texel by texel as platform/gles2
 * reads a gonio table. A pass draws only over the tiles its cull rectangle may reach (a necessary
 * test: no lit pixel is left out), and after it the pair it wrote holds the sum of the passes so
 * far: read and written in place (EXT_draw_buffers + EXT_shader_framebuffer_fetch), or on GLES2's
 * core ping-ponged, each pass also drawn over the previous pass's tiles with a pixel's codes written
 * back unchanged where its term is 0. At most eight texture units: the pair (2, core way only), the
 * P map, four anchors, the atlas.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gles/gl.h"
#include "luminaire/spots_gles.h"
#include "qibl/soft.h"
#include "qibl/srgbe.h"

void qtool_luminaire_diff8(const uint8_t *a, const uint8_t *b, size_t n, int *max, double *mean)
{
    int m = 0;
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
        int d = abs((int)a[i] - (int)b[i]);
        m = d > m ? d : m;
        sum += d;
    }
    *max = m;
    *mean = n ? sum / (double)n : 0;
}

#if QIBL_HAVE_GLES2
#include <EGL/egl.h>
#include <GLES2/gl2.h>

#include "qibl/gles2.h"
#include <GLES2/gl2ext.h>

#define TILE 8u /* screen tiles of the cull: a spotlight is drawn over the tiles it may reach (8 rather
                 * than 16: an eighth fewer fragments shaded on the courtyard, four times the tiles) */

static const char *vs_src = "attribute vec2 a_pos;\n"
                            "void main() { gl_Position = vec4(a_pos, 0.0, 1.0); }\n";

/* The term of spotlight s at the pixel's point x: gonio(x - s) (platform/gles2's qibl_gles2_glsl_gonio, the
 * table at u_goff in the atlas) times the peak, times the anchors' numerators interpolated with the
 * spotlight's weights, over |x - s|^3; added to the pair as passes_gles.c adds (the sRGBE codec is
 * platform/gles2's qibl_gles2_glsl_srgbe). Where the term is 0 the codes are written back as read. */
/* the two ways a pass reads and writes the pair: GLES2's core (ping-pong, one code per draw: u_lo
 * says which) and EXT_draw_buffers with EXT_shader_framebuffer_fetch (both codes read in place and
 * written by one draw; a pixel whose term is 0 is discarded) */
static const char *fs_core = "#define READ_PAIR vec4 ah = texture2D(u_ah, uv), al = texture2D(u_al, uv)\n"
                             "#define KEEP gl_FragColor = u_lo > 0.5 ? al : ah; return\n"
                             "#define WRITE(h, l) gl_FragColor = u_lo > 0.5 ? (l) : (h)\n";
static const char *fs_fetch = "#extension GL_EXT_draw_buffers : require\n"
                              "#extension GL_EXT_shader_framebuffer_fetch : require\n"
                              "#define READ_PAIR vec4 ah = gl_LastFragData[0], al = gl_LastFragData[1]\n"
                              "#define KEEP discard\n"
                              "#define WRITE(h, l) gl_FragData[0] = (h); gl_FragData[1] = (l)\n";
static const char *fs_src = "#ifdef GL_FRAGMENT_PRECISION_HIGH\n"
                            "precision highp float;\n"
                            "#else\n"
                            "precision mediump float;\n"
                            "#endif\n"
                            "uniform sampler2D u_ah, u_al, u_p, u_s0, u_s1, u_s2, u_s3, u_g;\n"
                            "uniform vec3 u_sp, u_rgb, u_gx, u_gy, u_gz;\n"
                            "uniform vec4 u_aw;\n"
                            "uniform vec2 u_goff, u_gsz, u_inv, u_cull;\n"
                            "uniform float u_gn, u_lo;\n";
/* (the sRGBE codec in GLSL between the two: qibl_gles2_glsl_srgbe, platform/gles2's) */
static const char *fs_tex =
                            "float gonio_tex(vec2 ij) {\n"
                            "  vec4 t = texture2D(u_g, (ij + u_goff + 0.5) / u_gsz);\n"
                            "  return floor(t.r * 255.0 + 0.5) + 256.0 * floor(t.a * 255.0 + 0.5);\n"
                            "}\n";
/* (gonio(), qibl_gles2_glsl_gonio, between the two) */
static const char *fs_body =
                            "void main() {\n"
                            "  vec2 uv = gl_FragCoord.xy * u_inv;\n"
                            "  READ_PAIR;\n"
                            "  vec3 d = texture2D(u_p, uv).rgb - u_sp;\n"
                            "  float g = 0.0;\n"
                            "  if (d.z < 0.0 && all(lessThanEqual(abs(d.xy), u_cull * -d.z))) g = gonio(d);\n"
                            "  vec3 b = vec3(0.0);\n"
                            "  if (g > 0.0) b = u_aw.x * texture2D(u_s0, uv).rgb + u_aw.y * texture2D(u_s1, uv).rgb\n"
                            "         + u_aw.z * texture2D(u_s2, uv).rgb + u_aw.w * texture2D(u_s3, uv).rgb;\n"
                            "  if (all(equal(b, vec3(0.0)))) {\n"
                            "    KEEP;\n"
                            "  }\n"
                            "  float r2 = dot(d, d);\n"
                            "  vec3 s = srgbe_dec(ah) + srgbe_dec(al) + b * u_rgb * (g / (r2 * sqrt(r2)));\n"
                            "  vec4 h = srgbe_enc(s);\n"
                            "  WRITE(h, srgbe_enc(s - srgbe_dec(h)));\n"
                            "}\n";

static double clock_ms(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static double now_ms(void)
{
    return clock_ms(CLOCK_MONOTONIC);
}

/* a screen tile's reached points' bounds (Q16.16), any = 0 when none */
typedef struct tilebox {
    int64_t lo[3], hi[3];
    int any;
} tilebox;

/* 1 if some point of box t may be lit by spotlight j: below it and, where it has cull bounds,
 * within |d_x| <= T_x |d_z| and |d_y| <= T_y |d_z| for the box's least |d_x|, |d_y| and largest |d_z|
 * (necessary for any point of the box, so a tile it says 0 for gets 0 from the pass) */
static int tile_lit(const qtool_luminaire_spots *s, uint32_t j, const tilebox *t)
{
    const int32_t *p = s->pos[j];
    if (!t->any || t->lo[2] >= p[2])
        return 0;
    const double dz = (double)(p[2] - t->lo[2]);
    for (int k = 0; k < 2; ++k) {
        if (s->cull[j][k] < 0)
            continue;
        double a = (double)(t->lo[k] - p[k]), b = (double)(t->hi[k] - p[k]);
        double m = a > 0 ? a : b < 0 ? -b : 0;
        if (m * 65536.0 > (double)s->cull[j][k] * dz * (1 + 1e-9) + 1)
            return 0;
    }
    return 1;
}

typedef struct rect {
    uint32_t x0, y0, x1, y1;
} rect;

/* the tiles of mask (1: drawn) as rectangles: runs along each tile row, a run extended down when
 * the row above has a rectangle of the same columns ending there (open[tx]: its index, or -1; nopen
 * the next row's). Returns the count (<= tiles). */
static uint32_t mask_rects(const uint8_t *mask, uint32_t tw, uint32_t th, uint32_t w, uint32_t h, rect *out,
                           int32_t *open, int32_t *nopen)
{
    uint32_t n = 0;
    for (uint32_t tx = 0; tx < tw; ++tx)
        open[tx] = -1;
    for (uint32_t ty = 0; ty < th; ++ty) {
        for (uint32_t tx = 0; tx < tw; ++tx)
            nopen[tx] = -1;
        for (uint32_t tx = 0; tx < tw;) {
            if (!mask[(size_t)ty * tw + tx]) {
                ++tx;
                continue;
            }
            uint32_t e = tx + 1;
            while (e < tw && mask[(size_t)ty * tw + e])
                ++e;
            const rect r = {tx * TILE, ty * TILE, e * TILE < w ? e * TILE : w,
                            (ty + 1) * TILE < h ? (ty + 1) * TILE : h};
            const int32_t o = open[tx];
            if (o >= 0 && out[o].x1 == r.x1) {
                out[o].y1 = r.y1;
                nopen[tx] = o;
            } else {
                out[n] = r;
                nopen[tx] = (int32_t)n++;
            }
            tx = e;
        }
        for (uint32_t tx = 0; tx < tw; ++tx)
            open[tx] = nopen[tx];
    }
    return n;
}

typedef struct glstate {
    GLuint vs, fs, prog, vbo, atlas, ptex, stex[4], acc[4], fbo[4], mrt; /* mrt: acc 0 and 1 (fetch) */
    int fetch;
    GLint u_sp, u_rgb, u_gx, u_gy, u_gz, u_aw, u_goff, u_lo, u_cull;
    uint32_t cols, n;
} glstate;

/* (GL ignores the name 0: what gl_setup never made is passed over) */
static void gl_free(glstate *g)
{
    glDeleteFramebuffers(4, g->fbo), glDeleteFramebuffers(1, &g->mrt);
    glDeleteTextures(4, g->acc), glDeleteTextures(4, g->stex);
    glDeleteTextures(1, &g->ptex), glDeleteTextures(1, &g->atlas);
    glDeleteBuffers(1, &g->vbo);
    glDeleteProgram(g->prog), glDeleteShader(g->vs), glDeleteShader(g->fs);
}

/* the program, the atlas of every spotlight's table, the pair's four targets (0/1 the canonical
 * hi and lo, 2/3 where a pass draws) and the per-frame textures' storage */
/* an extension named exactly in the GL's list */
static int has_ext(const char *list, const char *name)
{
    const size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == 0))
            return 1;
    return 0;
}

static int gl_setup(glstate *g, const qtool_luminaire_spots *s, uint32_t w, uint32_t h, int core_only, char *err,
                    size_t errlen)
{
    const char *ext = (const char *)glGetString(GL_EXTENSIONS);
    PFNGLDRAWBUFFERSEXTPROC draw_buffers = NULL;
    if (!core_only && has_ext(ext, "GL_EXT_draw_buffers") && has_ext(ext, "GL_EXT_shader_framebuffer_fetch"))
        draw_buffers = (PFNGLDRAWBUFFERSEXTPROC)eglGetProcAddress("glDrawBuffersEXT");
    g->fetch = draw_buffers != NULL;
    if (!has_ext(ext, "GL_OES_texture_float")) {
        snprintf(err, errlen, "the GL has no OES_texture_float (the P map and the anchors are binary32 textures)");
        return -1;
    }
    GLint units = 0, maxtex = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxtex);
    const uint32_t n = s->n, cols = (uint32_t)ceil(sqrt((double)(s->count ? s->count : 1)));
    const uint32_t rows = s->count ? (s->count + cols - 1) / cols : 1;
    if (units < 8) {
        snprintf(err, errlen, "the GL has %d fragment texture units, the passes need 8", (int)units);
        return -1;
    }
    if ((uint64_t)cols * n > (uint64_t)maxtex || (uint64_t)rows * n > (uint64_t)maxtex || w > (uint32_t)maxtex ||
        h > (uint32_t)maxtex) {
        snprintf(err, errlen, "the tables' atlas (%ux%u) or the frame (%ux%u) is above GL_MAX_TEXTURE_SIZE %d",
                 cols * n, rows * n, w, h, (int)maxtex);
        return -1;
    }
    g->cols = cols, g->n = n;
    const char *const vparts[1] = {vs_src}, *const fparts[6] = {g->fetch ? fs_fetch : fs_core, fs_src,
                                                                 qibl_gles2_glsl_srgbe, fs_tex,
                                                                 qibl_gles2_glsl_gonio, fs_body};
    g->vs = qtool_gles_shader(GL_VERTEX_SHADER, vparts, 1, err, errlen);
    g->fs = g->vs ? qtool_gles_shader(GL_FRAGMENT_SHADER, fparts, 6, err, errlen) : 0;
    if (!g->fs)
        return -1;
    g->prog = glCreateProgram();
    glAttachShader(g->prog, g->vs), glAttachShader(g->prog, g->fs);
    glBindAttribLocation(g->prog, 0, "a_pos");
    glLinkProgram(g->prog);
    GLint ok = 0;
    glGetProgramiv(g->prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        snprintf(err, errlen, "the spotlight program did not link");
        return -1;
    }
    glUseProgram(g->prog);
    static const char *const units_name[8] = {"u_ah", "u_al", "u_p", "u_s0", "u_s1", "u_s2", "u_s3", "u_g"};
    for (int k = 0; k < 8; ++k)
        glUniform1i(glGetUniformLocation(g->prog, units_name[k]), k);
    glUniform2f(glGetUniformLocation(g->prog, "u_gsz"), (float)(cols * n), (float)(rows * n));
    glUniform2f(glGetUniformLocation(g->prog, "u_inv"), 1.0f / (float)w, 1.0f / (float)h);
    glUniform1f(glGetUniformLocation(g->prog, "u_gn"), (float)n);
    g->u_sp = glGetUniformLocation(g->prog, "u_sp"), g->u_rgb = glGetUniformLocation(g->prog, "u_rgb");
    g->u_gx = glGetUniformLocation(g->prog, "u_gx"), g->u_gy = glGetUniformLocation(g->prog, "u_gy");
    g->u_gz = glGetUniformLocation(g->prog, "u_gz"), g->u_aw = glGetUniformLocation(g->prog, "u_aw");
    g->u_goff = glGetUniformLocation(g->prog, "u_goff"), g->u_lo = glGetUniformLocation(g->prog, "u_lo");
    g->u_cull = glGetUniformLocation(g->prog, "u_cull");
    /* the atlas: table c at column c % cols, row c / cols; 16 bits as low byte (L), high byte (A) */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glActiveTexture(GL_TEXTURE7);
    g->atlas = qtool_gles_texture(GL_LUMINANCE_ALPHA, GL_UNSIGNED_BYTE, cols * n, rows * n, NULL);
    uint8_t *buf = malloc(2u * n);
    if (!buf) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    for (uint32_t c = 0; c < s->count; ++c)
        for (uint32_t j = 0; j < n; ++j) {
            const uint16_t *t = s->tables + ((size_t)c * n + j) * n;
            for (uint32_t i = 0; i < n; ++i)
                buf[2 * i] = (uint8_t)t[i], buf[2 * i + 1] = (uint8_t)(t[i] >> 8);
            glTexSubImage2D(GL_TEXTURE_2D, 0, (GLint)((c % cols) * n), (GLint)((c / cols) * n + j), (GLsizei)n, 1,
                            GL_LUMINANCE_ALPHA, GL_UNSIGNED_BYTE, buf);
        }
    free(buf);
    glActiveTexture(GL_TEXTURE2);
    g->ptex = qtool_gles_texture(GL_RGB, GL_FLOAT, w, h, NULL);
    for (int k = 0; k < 4; ++k) {
        glActiveTexture((GLenum)(GL_TEXTURE3 + k));
        g->stex[k] = qtool_gles_texture(GL_RGB, GL_FLOAT, w, h, NULL);
    }
    glActiveTexture(GL_TEXTURE0);
    for (int k = 0; k < 4; ++k) {
        if (qtool_gles_rgba8_target(w, h, NULL, &g->acc[k], &g->fbo[k]) != GL_FRAMEBUFFER_COMPLETE) {
            snprintf(err, errlen, "an accumulation framebuffer is incomplete");
            return -1;
        }
    }
    if (g->fetch) {
        static const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0_EXT, GL_COLOR_ATTACHMENT1_EXT};
        glGenFramebuffers(1, &g->mrt);
        glBindFramebuffer(GL_FRAMEBUFFER, g->mrt);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0_EXT, GL_TEXTURE_2D, g->acc[0], 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1_EXT, GL_TEXTURE_2D, g->acc[1], 0);
        draw_buffers(2, bufs);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            snprintf(err, errlen, "the two-target framebuffer is incomplete");
            return -1;
        }
    }
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    if (glGetError() != GL_NO_ERROR) {
        snprintf(err, errlen, "a GL error while setting up the passes");
        return -1;
    }
    return 0;
}

/* the CPU's share of a frame: the P map as floats, the anchors' numerators (the core's unit lamps
 * at the anchors, base_k |x - a_k|^3, 0 where no spotlight reaches: the soft kernel's gate), the
 * tiles' bounds */
typedef struct frame_buf {
    float *pts, *num[4];
    int32_t *row, *q;
    void *ws;
    size_t wsn;
    tilebox *tb;
} frame_buf;

/* a frame's inputs: an asset's maps (mp, pm, lut: the anchors' unit lamps by the core), or the
 * points and the anchors' shading given (pts, base: the layouts of spots_gles.h) */
typedef struct frame_src {
    const qibl_shmaps_t *mp;
    const qibl_pmap_t *pm;
    const qibl_ylut_t *lut;
    const int32_t *pts, *base;
    uint32_t w, h;
} frame_src;

static qibl_status_t frame_prep(const qtool_luminaire_spots *s, const frame_src *src, frame_buf *fbuf, uint32_t tw)
{
    const uint32_t w = src->w, h = src->h;
    qibl_shmap_point_t pt[4];
    qibl_status_t st = QIBL_OK;
    for (uint32_t k = 0; st == QIBL_OK && src->mp && k < s->nanchor; ++k) {
        qibl_pointlight_t pl = {.pos = {s->anchor[k][0], s->anchor[k][1], s->anchor[k][2]},
                                .rgb = {65536, 65536, 65536},
                                .falloff = QIBL_FALLOFF_INV_DIST2,
                                .filter = src->lut ? QIBL_LUT_BILINEAR : QIBL_POINT_POLY};
        st = qibl_shmap_point_prepare(src->mp, src->pm, src->lut, &pl, &pt[k]);
    }
    for (size_t i = 0; i < (size_t)tw * ((h + TILE - 1) / TILE); ++i)
        fbuf->tb[i].any = 0;
    for (uint32_t k = 0; k < 4; ++k)
        memset(fbuf->num[k], 0, sizeof(float) * 3 * w * h);
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        uint32_t x0 = w, x1 = 0;
        for (uint32_t x = 0; x < w; ++x) {
            int32_t *q = fbuf->q + 3 * (size_t)x;
            if (src->pm)
                qibl_pmap_point(src->pm, x, y, q);
            else
                memcpy(q, src->pts + 3 * ((size_t)y * w + x), sizeof(int32_t) * 3);
            float *o = fbuf->pts + 3 * ((size_t)y * w + x);
            for (int c = 0; c < 3; ++c)
                o[c] = (float)(q[c] / 65536.0);
            if (qtool_luminaire_reaches(s, q)) {
                x0 = x < x0 ? x : x0, x1 = x + 1;
                tilebox *t = &fbuf->tb[(size_t)(y / TILE) * tw + x / TILE];
                for (int c = 0; c < 3; ++c) {
                    if (!t->any || q[c] < t->lo[c])
                        t->lo[c] = q[c];
                    if (!t->any || q[c] > t->hi[c])
                        t->hi[c] = q[c];
                }
                t->any = 1;
            }
        }
        const uint32_t nw = x1 > x0 ? x1 - x0 : 0;
        for (uint32_t k = 0; st == QIBL_OK && nw && k < s->nanchor; ++k) {
            const int32_t *b = fbuf->row;
            if (src->mp)
                st = qibl_shmap_point_span(&pt[k], x0, y, nw, fbuf->row, fbuf->ws, fbuf->wsn);
            else
                b = src->base + (size_t)k * 3 * w * h + 3 * ((size_t)y * w + x0);
            for (uint32_t i = 0; st == QIBL_OK && i < nw; ++i) {
                const int32_t *q = fbuf->q + 3 * (size_t)(x0 + i);
                if (!qtool_luminaire_reaches(s, q))
                    continue;
                double r2 = 0;
                for (int c = 0; c < 3; ++c) {
                    double d = ((double)q[c] - s->anchor[k][c]) / 65536.0;
                    r2 += d * d;
                }
                const double r3 = r2 * sqrt(r2);
                float *o = fbuf->num[k] + 3 * ((size_t)y * w + x0 + i);
                for (int c = 0; c < 3; ++c)
                    o[c] = (float)(b[3 * (size_t)i + (size_t)c] / 65536.0 * r3);
            }
        }
    }
    return st;
}

static void upload_rgb_float(GLenum unit, GLuint tex, uint32_t w, uint32_t h, const float *v)
{
    glActiveTexture(unit);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)w, (GLsizei)h, GL_RGB, GL_FLOAT, v);
}

/* Every pass of a frame into the pairs (all cleared first). GLES2's core: ping-ponged, pass j reads
 * the current pair and draws the other over its own tiles and the previous pass's (where the other
 * pair missed that pass's term; there and wherever its own term is 0 the codes are copied as read),
 * so the pair it drew holds the whole sum. Fetch: pair 0 updated in place over the pass's own tiles.
 * *cur gets the pair holding the sum; fragments shaded in *frags. */
static void frame_passes(const glstate *g, const qtool_luminaire_spots *s, const frame_buf *fb, uint32_t w, uint32_t h,
                         uint32_t tw, uint32_t th, uint8_t *mask, rect *rects, int32_t *open, float *verts,
                         const uint8_t *zero, uint32_t *passes, double *frags, int *cur)
{
    upload_rgb_float(GL_TEXTURE2, g->ptex, w, h, fb->pts);
    for (uint32_t k = 0; k < 4; ++k)
        upload_rgb_float((GLenum)(GL_TEXTURE3 + k), g->stex[k], w, h, fb->num[k]);
    glActiveTexture(GL_TEXTURE0);
    for (int k = 0; k < 4; ++k) {
        glBindTexture(GL_TEXTURE_2D, g->acc[k]);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)w, (GLsizei)h, GL_RGBA, GL_UNSIGNED_BYTE, zero);
    }
    glActiveTexture(GL_TEXTURE7), glBindTexture(GL_TEXTURE_2D, g->atlas);
    if (g->fetch) { /* the pair is the target: no sampler may hold it */
        glActiveTexture(GL_TEXTURE0), glBindTexture(GL_TEXTURE_2D, 0);
        glActiveTexture(GL_TEXTURE1), glBindTexture(GL_TEXTURE_2D, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, g->mrt);
    }
    glUseProgram(g->prog);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glViewport(0, 0, (GLsizei)w, (GLsizei)h);
    glDisable(GL_BLEND), glDisable(GL_DEPTH_TEST), glDisable(GL_SCISSOR_TEST), glDisable(GL_DITHER);
    const size_t nt = (size_t)tw * th;
    uint8_t *dirty = mask + nt; /* the previous pass's tiles */
    memset(dirty, 0, nt);
    int c = 0;
    *passes = 0, *frags = 0;
    for (uint32_t j = 0; j < s->count; ++j) {
        int any = 0;
        for (size_t t = 0; t < nt; ++t) {
            mask[t] = (uint8_t)tile_lit(s, j, &fb->tb[t]);
            any |= mask[t];
        }
        if (!any)
            continue; /* no tile it may reach: its pass adds nothing, and nothing moves */
        for (size_t t = 0; t < nt && !g->fetch; ++t) { /* ping-pong: the other pair missed the last pass */
            uint8_t m = mask[t];
            mask[t] |= dirty[t];
            dirty[t] = m;
        }
        const uint32_t nr = mask_rects(mask, tw, th, w, h, rects, open, open + tw);
        for (uint32_t r = 0; r < nr; ++r) {
            const float x0 = 2.0f * (float)rects[r].x0 / (float)w - 1, x1 = 2.0f * (float)rects[r].x1 / (float)w - 1;
            const float y0 = 2.0f * (float)rects[r].y0 / (float)h - 1, y1 = 2.0f * (float)rects[r].y1 / (float)h - 1;
            const float v[12] = {x0, y0, x1, y0, x0, y1, x0, y1, x1, y0, x1, y1};
            memcpy(verts + 12 * (size_t)r, v, sizeof v);
            *frags += (double)(rects[r].x1 - rects[r].x0) * (rects[r].y1 - rects[r].y0);
        }
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 12 * nr), verts, GL_STREAM_DRAW);
        float f3[3];
        for (int k = 0; k < 3; ++k)
            f3[k] = (float)(s->pos[j][k] / 65536.0);
        glUniform3fv(g->u_sp, 1, f3);
        for (int k = 0; k < 3; ++k)
            f3[k] = (float)(s->rgb[j][k] / 65536.0);
        glUniform3fv(g->u_rgb, 1, f3);
        const qibl_gonio_t *go = &s->gonio[j];
        glUniform3f(g->u_gx, (float)ldexp(go->x[0], -30), (float)ldexp(go->x[1], -30), (float)ldexp(go->x[2], -30));
        glUniform3f(g->u_gy, (float)ldexp(go->y[0], -30), (float)ldexp(go->y[1], -30), (float)ldexp(go->y[2], -30));
        glUniform3f(g->u_gz, (float)ldexp(go->z[0], -30), (float)ldexp(go->z[1], -30), (float)ldexp(go->z[2], -30));
        glUniform4f(g->u_aw, (float)(s->aw[j][0] / 32768.0), (float)(s->aw[j][1] / 32768.0),
                    (float)(s->aw[j][2] / 32768.0), (float)(s->aw[j][3] / 32768.0));
        /* the cull's tangent bounds (1% and 2^-15 wider than the table's support: no rounding of
         * the shader's can drop a lit direction); none: every direction below */
        glUniform2f(g->u_cull, s->cull[j][0] < 0 ? 1e30f : (float)((double)s->cull[j][0] / 65536.0),
                    s->cull[j][1] < 0 ? 1e30f : (float)((double)s->cull[j][1] / 65536.0));
        glUniform2f(g->u_goff, (float)((j % g->cols) * g->n), (float)((j / g->cols) * g->n));
        if (g->fetch) { /* both codes read and written in place by one draw */
            glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(6 * nr));
            ++*passes;
            continue;
        }
        glActiveTexture(GL_TEXTURE0), glBindTexture(GL_TEXTURE_2D, g->acc[2 * c]);
        glActiveTexture(GL_TEXTURE1), glBindTexture(GL_TEXTURE_2D, g->acc[2 * c + 1]);
        /* one colour attachment in GLES2: the sum's code, then what it leaves out */
        for (int lo = 0; lo < 2; ++lo) {
            glBindFramebuffer(GL_FRAMEBUFFER, g->fbo[2 * (1 - c) + lo]);
            glUniform1f(g->u_lo, (float)lo);
            glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(6 * nr));
        }
        c = 1 - c;
        ++*passes;
    }
    *cur = c;
}

/* the pair read back, decoded by the core's codec, rounded once (qtool_luminaire_q16) and written
 * through platform/soft as qtool_luminaire_relight writes its frame */
static qibl_status_t frame_read(const glstate *g, int cur, uint32_t w, uint32_t h, uint32_t exposure, int srgb,
                                uint8_t *back, int32_t *row, uint8_t *pix, uint8_t *rgb8)
{
    const size_t npix = (size_t)w * h;
    for (int lo = 0; lo < 2; ++lo) {
        glBindFramebuffer(GL_FRAMEBUFFER, g->fbo[2 * cur + lo]);
        glReadPixels(0, 0, (GLsizei)w, (GLsizei)h, GL_RGBA, GL_UNSIGNED_BYTE, back + 4 * npix * (size_t)lo);
    }
    qibl_fb_desc_t fb = {
        .pixels = pix, .width = w, .height = h, .format = QIBL_FB_RGBA8888, .srgb = srgb ? 1 : 0, .exposure = exposure};
    qibl_status_t st = QIBL_OK;
    for (uint32_t y = 0; st == QIBL_OK && y < h; ++y) {
        for (uint32_t x = 0; st == QIBL_OK && x < w; ++x) {
            const size_t i = (size_t)y * w + x;
            int32_t hi[3], lo[3];
            st = qibl_srgbe_decode_s32(back + 4 * i, 24, hi);
            if (st == QIBL_OK)
                st = qibl_srgbe_decode_s32(back + 4 * (npix + i), 24, lo);
            for (int c = 0; st == QIBL_OK && c < 3; ++c)
                row[3 * (size_t)x + (size_t)c] = qtool_luminaire_q16((int64_t)hi[c] + lo[c]);
        }
        if (st == QIBL_OK)
            st = qibl_fb_write_row(&fb, 0, y, w, row);
    }
    for (size_t i = 0; st == QIBL_OK && i < npix; ++i)
        memcpy(rgb8 + 3 * i, pix + 4 * i, 3);
    return st;
}

static int run(const qtool_luminaire_spots *s, const frame_src *src, uint32_t exposure, int srgb,
               const qtool_luminaire_gles_opts *o, uint8_t *rgb8, qtool_luminaire_gles_stats *st, char *err,
               size_t errlen)
{
    uint32_t frames = o && o->frames ? o->frames : 1;
    if (s->nlevel != 0u) { /* the shader evaluates level 0 only: a hierarchy's frame would differ */
        snprintf(err, errlen, "the spotlights were merged by a hierarchy (tol > 0); the GPU evaluates every "
                              "spotlight: build them with tol 0");
        return -1;
    }
    const uint32_t w = src->w, h = src->h, tw = (w + TILE - 1) / TILE, th = (h + TILE - 1) / TILE;
    const size_t npix = (size_t)w * h;
    glstate g;
    memset(&g, 0, sizeof g);
    frame_buf fb;
    memset(&fb, 0, sizeof fb);
    fb.wsn = src->mp ? qibl_shmap_point_workspace_size(src->mp->k, w) : 0;
    fb.pts = malloc(sizeof(float) * 3 * npix);
    for (int k = 0; k < 4; ++k)
        fb.num[k] = malloc(sizeof(float) * 3 * npix);
    fb.row = malloc(sizeof(int32_t) * 3 * w), fb.q = malloc(sizeof(int32_t) * 3 * w);
    fb.ws = malloc(fb.wsn ? fb.wsn : 1);
    fb.tb = malloc(sizeof(tilebox) * tw * th);
    rect *rects = malloc(sizeof(rect) * tw * th);
    uint8_t *mask = malloc(2 * (size_t)tw * th);
    int32_t *open = malloc(sizeof(int32_t) * 2 * tw);
    float *verts = malloc(sizeof(float) * 12 * tw * th);
    uint8_t *back = malloc(8 * npix), *pix = malloc(4 * npix), *out = malloc(3 * npix), *zero = malloc(4 * npix);
    GLint oldfb = 0, oldprog = 0;
    int rc = -1;
    err[0] = 0;
    if (!fb.pts || !fb.num[0] || !fb.num[1] || !fb.num[2] || !fb.num[3] || !fb.row || !fb.q || !fb.ws || !fb.tb ||
        !rects || !mask || !open || !verts || !back || !pix || !out || !zero) {
        snprintf(err, errlen, "out of memory");
        goto done;
    }
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &oldfb);
    glGetIntegerv(GL_CURRENT_PROGRAM, &oldprog);
    while (glGetError() != GL_NO_ERROR)
        ;
    if (gl_setup(&g, s, w, h, o && o->core_only, err, errlen) != 0)
        goto done;
    qtool_luminaire_srgbe_clear(zero, (uint32_t)npix); /* the zero code, uploaded at each frame's start */
    qtool_luminaire_gles_stats sum = {0};
    for (uint32_t f = 0; f <= frames; ++f) { /* frame 0: the warm-up (llvmpipe compiles at first draw) */
        double t0 = now_ms(), c0 = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
        qibl_status_t cs = frame_prep(s, src, &fb, tw);
        if (cs != QIBL_OK) {
            snprintf(err, errlen, "the anchors' shading: %s", qibl_soft_status_str(cs));
            goto done;
        }
        double t1 = now_ms();
        uint32_t passes = 0;
        double frags = 0;
        int cur = 0;
        frame_passes(&g, s, &fb, w, h, tw, th, mask, rects, open, verts, zero, &passes, &frags, &cur);
        glFinish();
        double t2 = now_ms();
        cs = frame_read(&g, cur, w, h, exposure, srgb, back, fb.row, pix, out);
        double t3 = now_ms(), c3 = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
        if (cs != QIBL_OK) {
            snprintf(err, errlen, "the core's codec refused a code: %s", qibl_soft_status_str(cs));
            goto done;
        }
        if (glGetError() != GL_NO_ERROR) {
            snprintf(err, errlen, "a GL error in the passes");
            goto done;
        }
        if (f > 0) {
            sum.prep_ms += t1 - t0, sum.gpu_ms += t2 - t1, sum.read_ms += t3 - t2, sum.cpu_ms += c3 - c0;
            sum.passes = passes;
            sum.coverage = passes ? frags / ((double)passes * (double)npix) : 0;
        }
    }
    sum.prep_ms /= frames, sum.gpu_ms /= frames, sum.read_ms /= frames, sum.cpu_ms /= frames;
    sum.fetch = g.fetch;
    memcpy(rgb8, out, 3 * npix);
    if (st)
        *st = sum;
    rc = 0;
done:
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)oldfb);
    glUseProgram((GLuint)oldprog);
    glActiveTexture(GL_TEXTURE0);
    gl_free(&g);
    free(fb.pts), free(fb.row), free(fb.q), free(fb.ws), free(fb.tb);
    for (int k = 0; k < 4; ++k)
        free(fb.num[k]);
    free(rects), free(mask), free(open), free(verts), free(back), free(pix), free(out), free(zero);
    return rc;
}

int qtool_luminaire_relight_gles(const qtool_luminaire_spots *s, const qibl_shmaps_t *mp, const qibl_pmap_t *pm,
                                 const qibl_ylut_t *lut, uint32_t exposure, int srgb,
                                 const qtool_luminaire_gles_opts *o, uint8_t *rgb8, qtool_luminaire_gles_stats *st,
                                 char *err, size_t errlen)
{
    const frame_src src = {.mp = mp, .pm = pm, .lut = lut, .w = mp->width, .h = mp->height};
    return run(s, &src, exposure, srgb, o, rgb8, st, err, errlen);
}

int qtool_luminaire_spots_gles(const qtool_luminaire_spots *s, uint32_t w, uint32_t h, const int32_t *pts,
                               const int32_t *base, uint32_t exposure, int srgb, const qtool_luminaire_gles_opts *o,
                               uint8_t *rgb8, qtool_luminaire_gles_stats *st, char *err, size_t errlen)
{
    const frame_src src = {.pts = pts, .base = base, .w = w, .h = h};
    return run(s, &src, exposure, srgb, o, rgb8, st, err, errlen);
}
#else
int qtool_luminaire_relight_gles(const qtool_luminaire_spots *s, const qibl_shmaps_t *mp, const qibl_pmap_t *pm,
                                 const qibl_ylut_t *lut, uint32_t exposure, int srgb,
                                 const qtool_luminaire_gles_opts *o, uint8_t *rgb8, qtool_luminaire_gles_stats *st,
                                 char *err, size_t errlen)
{
    (void)s, (void)mp, (void)pm, (void)lut, (void)exposure, (void)srgb, (void)o, (void)rgb8, (void)st;
    snprintf(err, errlen, "built without EGL/GLES2");
    return -1;
}

int qtool_luminaire_spots_gles(const qtool_luminaire_spots *s, uint32_t w, uint32_t h, const int32_t *pts,
                               const int32_t *base, uint32_t exposure, int srgb, const qtool_luminaire_gles_opts *o,
                               uint8_t *rgb8, qtool_luminaire_gles_stats *st, char *err, size_t errlen)
{
    (void)s, (void)w, (void)h, (void)pts, (void)base, (void)exposure, (void)srgb, (void)o, (void)rgb8, (void)st;
    snprintf(err, errlen, "built without EGL/GLES2");
    return -1;
}
#endif
