/*
 * luminaire/passes_gles.c - the passes of qtool_luminaire_passes accumulated on a GLES2 GPU in
 * 8-bit sRGBE targets (two per sum, as platform/gles2 accumulates: the running sum's code and the
 * code of what it leaves out), ping-ponged, one pass per spotlight. The caller's context is current
 * (tools/gles/headless.h makes one). Separate from passes.c so that programs without GL need not
 * link it.
 *
 * Invariants: each pass's term reaches the GPU as an sRGBE pair made by the core's codec (about
 * 2^-16 of the term: far below one 8-bit level), so what is measured is the GPU's accumulation; the
 * result comes back as codes and is decoded by the core's codec.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles/gl.h"
#include "luminaire/luminaire.h"
#include "qibl/soft.h"
#include "qibl/srgbe.h"

#if QIBL_HAVE_GLES2
#include <GLES2/gl2.h>

#include "qibl/gles2.h"

static const char *vs_src = "attribute vec2 a_pos;\n"
                            "varying vec2 v_uv;\n"
                            "void main() { v_uv = a_pos * 0.5 + 0.5; gl_Position = vec4(a_pos, 0.0, 1.0); }\n";

/* the GLSL codec is platform/gles2's (qibl_gles2_glsl_srgbe), exponent fixed up where log2 is inexact */
static const char *fs_src =
    "#ifdef GL_FRAGMENT_PRECISION_HIGH\n"
    "precision highp float;\n"
    "uniform highp sampler2D u_ah, u_al, u_th, u_tl;\n"
    "#else\n"
    "precision mediump float;\n"
    "uniform sampler2D u_ah, u_al, u_th, u_tl;\n"
    "#endif\n"
    "uniform float u_lo;\n"
    "varying vec2 v_uv;\n";
/* (the sRGBE codec in GLSL between the two: qibl_gles2_glsl_srgbe, platform/gles2's) */
static const char *fs_body =
    "void main() {\n"
    "  vec3 s = srgbe_dec(texture2D(u_ah, v_uv)) + srgbe_dec(texture2D(u_al, v_uv))\n"
    "         + srgbe_dec(texture2D(u_th, v_uv)) + srgbe_dec(texture2D(u_tl, v_uv));\n"
    "  vec4 h = srgbe_enc(s);\n"
    "  gl_FragColor = u_lo > 0.5 ? srgbe_enc(s - srgbe_dec(h)) : h;\n"
    "}\n";

int qtool_luminaire_passes_gles(qtool_luminaire_passes *r, char *err, size_t errlen)
{
    const uint32_t n = r->size;
    const size_t npix = (size_t)n * n;
    const int f = r->frac_bits;
    uint8_t *buf = malloc(8 * npix), *back = malloc(8 * npix);
    int32_t *q = malloc(sizeof(int32_t) * 3 * npix);
    uint8_t *shown = malloc(4 * npix);
    GLuint vs = 0, fs = 0, prog = 0, vbo = 0, acc[4] = {0, 0, 0, 0}, fbo[4] = {0, 0, 0, 0}, th = 0, tl = 0;
    GLint oldfb = 0;
    int rc = -1;
    const char *const vparts[1] = {vs_src}, *const fparts[3] = {fs_src, qibl_gles2_glsl_srgbe, fs_body};
    err[0] = 0;
    if (!buf || !back || !q || !shown) {
        snprintf(err, errlen, "out of memory");
        goto out;
    }
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &oldfb);
    vs = qtool_gles_shader(GL_VERTEX_SHADER, vparts, 1, err, errlen);
    fs = vs ? qtool_gles_shader(GL_FRAGMENT_SHADER, fparts, 3, err, errlen) : 0;
    if (!fs)
        goto out;
    prog = glCreateProgram();
    glAttachShader(prog, vs), glAttachShader(prog, fs);
    glBindAttribLocation(prog, 0, "a_pos");
    glLinkProgram(prog);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        snprintf(err, errlen, "the program did not link");
        goto out;
    }
    static const float quad[8] = {-1, -1, 1, -1, -1, 1, 1, 1};
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    /* accumulators: 0/1 hi and lo of ping, 2/3 of pong, all the zero code at first */
    qtool_luminaire_srgbe_clear(buf, (uint32_t)npix);
    for (int k = 0; k < 4; ++k) {
        if (qtool_gles_rgba8_target(n, n, buf, &acc[k], &fbo[k]) != GL_FRAMEBUFFER_COMPLETE) {
            snprintf(err, errlen, "an accumulation framebuffer is incomplete");
            goto out;
        }
    }
    th = qtool_gles_texture(GL_RGBA, GL_UNSIGNED_BYTE, n, n, NULL);
    tl = qtool_gles_texture(GL_RGBA, GL_UNSIGNED_BYTE, n, n, NULL);
    glUseProgram(prog);
    glUniform1i(glGetUniformLocation(prog, "u_ah"), 0), glUniform1i(glGetUniformLocation(prog, "u_al"), 1);
    glUniform1i(glGetUniformLocation(prog, "u_th"), 2), glUniform1i(glGetUniformLocation(prog, "u_tl"), 3);
    const GLint ulo = glGetUniformLocation(prog, "u_lo");
    glViewport(0, 0, (GLsizei)n, (GLsizei)n);
    glDisable(GL_BLEND), glDisable(GL_DEPTH_TEST), glDisable(GL_SCISSOR_TEST), glDisable(GL_DITHER);
    int cur = 0;
    for (uint32_t j = 0; j < r->passes; ++j) {
        /* the pass's term as an sRGBE pair (hi, and what hi leaves out) */
        const int64_t *t = r->terms + (size_t)j * 3 * npix;
        for (size_t i = 0; i < npix; ++i) {
            int32_t v[3], h[3], e[3];
            for (int k = 0; k < 3; ++k) {
                int64_t x = t[3 * i + (size_t)k];
                x = f >= 24 ? x : x / ((int64_t)1 << (24 - f)); /* |x| < 2^30 at f (passes_run's choice) */
                v[k] = (int32_t)x;
            }
            if (qibl_srgbe_encode_s32(v, f, buf + 4 * i) != QIBL_OK ||
                qibl_srgbe_decode_s32(buf + 4 * i, f, h) != QIBL_OK)
                goto out;
            for (int k = 0; k < 3; ++k)
                e[k] = v[k] - h[k];
            if (qibl_srgbe_encode_s32(e, f, buf + 4 * (npix + i)) != QIBL_OK)
                goto out;
        }
        glActiveTexture(GL_TEXTURE2), glBindTexture(GL_TEXTURE_2D, th);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)n, (GLsizei)n, GL_RGBA, GL_UNSIGNED_BYTE, buf);
        glActiveTexture(GL_TEXTURE3), glBindTexture(GL_TEXTURE_2D, tl);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)n, (GLsizei)n, GL_RGBA, GL_UNSIGNED_BYTE, buf + 4 * npix);
        glActiveTexture(GL_TEXTURE0), glBindTexture(GL_TEXTURE_2D, acc[2 * cur]);
        glActiveTexture(GL_TEXTURE1), glBindTexture(GL_TEXTURE_2D, acc[2 * cur + 1]);
        /* one colour attachment in GLES2: the sum's code, then what it leaves out */
        for (int lo = 0; lo < 2; ++lo) {
            glBindFramebuffer(GL_FRAMEBUFFER, fbo[2 * (1 - cur) + lo]);
            glUniform1f(ulo, (float)lo);
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        }
        cur = 1 - cur;
    }
    for (int lo = 0; lo < 2; ++lo) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo[2 * cur + lo]);
        glReadPixels(0, 0, (GLsizei)n, (GLsizei)n, GL_RGBA, GL_UNSIGNED_BYTE, back + 4 * npix * (size_t)lo);
    }
    if (glGetError() != GL_NO_ERROR) {
        snprintf(err, errlen, "a GL error");
        goto out;
    }
    for (size_t i = 0; i < npix; ++i) {
        int32_t h[3], l[3];
        if (qibl_srgbe_decode_s32(back + 4 * i, 24, h) != QIBL_OK ||
            qibl_srgbe_decode_s32(back + 4 * (npix + i), 24, l) != QIBL_OK)
            goto out;
        for (int k = 0; k < 3; ++k)
            q[3 * i + (size_t)k] = qtool_luminaire_q16((int64_t)h[k] + l[k]);
    }
    /* the same display as passes_run's images; against its core and two-target ones */
    qibl_fb_desc_t fb = {.pixels = shown, .width = n, .height = n, .format = QIBL_FB_RGBA8888, .srgb = 1,
                         .exposure = r->exposure};
    for (uint32_t y = 0; y < n; ++y)
        if (qibl_soft_fb_write_row(&fb, 0, y, n, q + (size_t)y * 3 * n) != QIBL_OK)
            goto out;
    r->gles_vs_core = r->gles_vs_srgbe2 = 0;
    for (size_t i = 0; i < npix; ++i)
        for (int k = 0; k < 3; ++k) {
            int g = shown[4 * i + (size_t)k], c = r->shown[4 * i + (size_t)k],
                s2 = r->shown[4 * (3 * npix + i) + (size_t)k];
            r->gles_vs_core = abs(g - c) > r->gles_vs_core ? abs(g - c) : r->gles_vs_core;
            r->gles_vs_srgbe2 = abs(g - s2) > r->gles_vs_srgbe2 ? abs(g - s2) : r->gles_vs_srgbe2;
        }
    r->gles = 1;
    rc = 0;
out:
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)oldfb);
    /* GL ignores the name 0: what was never made is passed over */
    glDeleteFramebuffers(4, fbo), glDeleteTextures(4, acc), glDeleteTextures(1, &th), glDeleteTextures(1, &tl);
    glDeleteBuffers(1, &vbo), glDeleteProgram(prog), glDeleteShader(vs), glDeleteShader(fs);
    if (rc != 0 && !err[0])
        snprintf(err, errlen, "the core's codec refused a value");
    free(buf), free(back), free(q), free(shown);
    return rc;
}
#else
int qtool_luminaire_passes_gles(qtool_luminaire_passes *r, char *err, size_t errlen)
{
    (void)r;
    snprintf(err, errlen, "built without EGL/GLES2");
    return -1;
}
#endif
