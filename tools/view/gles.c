/*
 * view/gles.c - `qibl view --gles`: the viewer's frame drawn by platform/gles2 on a headless EGL
 * context opened once (gles/headless.h), the maps uploaded once, each frame's weights from the same
 * light as the soft path (qtool_view_light), read back into the window's BGRX buffer; or, with a
 * window (qtool_view_gles_window), a second context on the X11 display drawing into the window
 * through an EGL window surface.
 */
#include "view/view.h"

#include <stdio.h>
#include <stdlib.h>

#if QIBL_HAVE_GLES2
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2.h>

#include "gles/gl.h"
#include "gles/headless.h"
#include "qibl/gles2.h"

#ifndef EGL_PLATFORM_X11_EXT
#define EGL_PLATFORM_X11_EXT 0x31D5
#endif

/* the window's GL: its own display, context and surface (EGL objects cannot cross displays), the
 * maps uploaded there, a texture the frame is relit into and the program that draws it upright */
typedef struct window_gl {
    EGLDisplay d;
    EGLContext ctx;
    EGLSurface surf;
    qibl_gles2_t g;
    int have_g;
    GLuint tex, fbo, prog;
    uint32_t w, h;
} window_gl;

struct qtool_view_gles {
    qt_gles_ctx c;
    qibl_gles2_t g;
    uint8_t *rgba;
    int have_g;
    qibl_shmaps_t maps; /* the caller's maps (uploaded again for the window) */
    window_gl win;      /* win.d: drawing into the window */
};

qtool_view_gles *qtool_view_gles_open(const qtool_view *v, char *err, size_t errlen)
{
    qtool_view_gles *vg = calloc(1, sizeof *vg);
    if (!vg)
        return snprintf(err, errlen, "view --gles: out of memory"), NULL;
    char why[256];
    if (qt_gles_open(&vg->c, v->maps.width, v->maps.height, why, sizeof why) != 0) {
        snprintf(err, errlen, "view --gles: %s", why);
        free(vg);
        return NULL;
    }
    vg->maps = v->maps;
    vg->rgba = malloc((size_t)v->maps.width * v->maps.height * 4u);
    qibl_status_t st = vg->rgba ? qibl_gles2_init(&vg->g, NULL) : QIBL_E_NULL_POINTER;
    vg->have_g = st == QIBL_OK;
    if (st == QIBL_OK)
        st = qibl_gles2_upload(&vg->g, &v->maps, NULL, NULL);
    if (st != QIBL_OK) {
        snprintf(err, errlen, "view --gles: %s", vg->rgba ? qibl_gles2_status_str(st) : "out of memory");
        qtool_view_gles_close(vg);
        return NULL;
    }
    return vg;
}

/* The view's light relit by g into the framebuffer bound now (the offscreen and the window path). */
static qibl_status_t relight(qibl_gles2_t *g, const qtool_view *v)
{
    qibl_shlight_t l;
    qibl_shmap_weights_t w;
    const qibl_gles2_out_t out = {v->exposure, (uint8_t)!v->linear};
    qibl_status_t st = qtool_view_light(v, &l);
    if (st == QIBL_OK)
        st = qibl_shmap_weights(&v->maps, &l, &w);
    if (st == QIBL_OK)
        st = qibl_gles2_relight(g, &w, &out);
    return st;
}

int qtool_view_gles_frame(void *user, qtool_view *v, uint8_t *bgrx, size_t stride)
{
    qtool_view_gles *vg = user;
    qibl_status_t st = relight(&vg->g, v);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: view --gles: %s\n", qibl_gles2_status_str(st));
        return -1;
    }
    if (qt_gles_read(&vg->c, vg->rgba) != 0) {
        fprintf(stderr, "qibl: view --gles: glReadPixels failed\n");
        return -1;
    }
    for (uint32_t y = 0; y < v->maps.height; ++y)
        for (uint32_t x = 0; x < v->maps.width; ++x) {
            const uint8_t *p = vg->rgba + 4 * ((size_t)y * v->maps.width + x);
            uint8_t *o = bgrx + (size_t)y * stride + 4 * (size_t)x;
            o[0] = p[2], o[1] = p[1], o[2] = p[0], o[3] = 255;
        }
    return 0;
}

static void window_close(window_gl *W)
{
    if (!W->d)
        return;
    if (W->ctx && eglMakeCurrent(W->d, W->surf, W->surf, W->ctx)) {
        if (W->have_g)
            qibl_gles2_destroy(&W->g);
        glDeleteFramebuffers(1, &W->fbo), glDeleteTextures(1, &W->tex); /* GL ignores the name 0 */
        glDeleteProgram(W->prog);
    }
    eglMakeCurrent(W->d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (W->surf)
        eglDestroySurface(W->d, W->surf);
    if (W->ctx)
        eglDestroyContext(W->d, W->ctx);
    eglTerminate(W->d);
    memset(W, 0, sizeof *W);
}

/* the upright copy: a full-window triangle pair, texel (x, h - 1 - y) at window pixel (x, y) */
static GLuint blit_program(void)
{
    static const char *const vs = "attribute vec2 p;\nvarying highp vec2 t;\n"
                                  "void main() { t = vec2(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5); gl_Position = vec4(p, 0.0, 1.0); }\n";
    static const char *const fs = "precision highp float;\nuniform highp sampler2D s;\nvarying highp vec2 t;\n"
                                  "void main() { gl_FragColor = texture2D(s, t); }\n";
    GLuint sh[2] = {glCreateShader(GL_VERTEX_SHADER), glCreateShader(GL_FRAGMENT_SHADER)}, prog = glCreateProgram();
    GLint ok = 1, k;
    for (int i = 0; i < 2; ++i) {
        glShaderSource(sh[i], 1, i ? &fs : &vs, NULL);
        glCompileShader(sh[i]);
        glGetShaderiv(sh[i], GL_COMPILE_STATUS, &k);
        ok &= k;
        glAttachShader(prog, sh[i]);
    }
    glBindAttribLocation(prog, 0, "p");
    glLinkProgram(prog);
    glGetProgramiv(prog, GL_LINK_STATUS, &k);
    glDeleteShader(sh[0]), glDeleteShader(sh[1]);
    if (!ok || !k) {
        glDeleteProgram(prog);
        return 0;
    }
    return prog;
}

/* the EGL config of the window's visual that renders GLES2 into windows */
static int window_config(EGLDisplay d, unsigned long visual, EGLConfig *out)
{
    const EGLint attr[] = {EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES2_BIT, EGL_RED_SIZE, 8,
                           EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLConfig cfg[64];
    EGLint n = 0;
    if (!eglChooseConfig(d, attr, cfg, 64, &n))
        return -1;
    for (EGLint i = 0; i < n; ++i) {
        EGLint vid = 0, r = 0, g = 0, b = 0;
        eglGetConfigAttrib(d, cfg[i], EGL_NATIVE_VISUAL_ID, &vid);
        eglGetConfigAttrib(d, cfg[i], EGL_RED_SIZE, &r), eglGetConfigAttrib(d, cfg[i], EGL_GREEN_SIZE, &g);
        eglGetConfigAttrib(d, cfg[i], EGL_BLUE_SIZE, &b);
        if ((unsigned long)vid == visual && r == 8 && g == 8 && b == 8) {
            *out = cfg[i];
            return 0;
        }
    }
    return -1;
}

/* the context, the surface on the window, current: NULL, or what failed */
static const char *window_context(window_gl *W, void *native_display, unsigned long native_window,
                                  unsigned long visual)
{
    const char *ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    PFNEGLGETPLATFORMDISPLAYEXTPROC gpd = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC cws =
        (PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC)eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT");
    if (!ext || !strstr(ext, "EGL_EXT_platform_x11") || !gpd || !cws)
        return "EGL has no X11 platform (EGL_EXT_platform_x11)";
    W->d = gpd(EGL_PLATFORM_X11_EXT, native_display, NULL);
    if (W->d == EGL_NO_DISPLAY || !eglInitialize(W->d, NULL, NULL)) {
        W->d = NULL;
        return "no EGL display on the X server";
    }
    EGLConfig cfg;
    const EGLint ctx_attr[] = {EGL_CONTEXT_CLIENT_VERSION, 2, EGL_NONE};
    unsigned long xid = native_window; /* the X11 platform takes a pointer to the Window */
    if (window_config(W->d, visual, &cfg) != 0)
        return "no EGL config renders GLES2 into the window's visual";
    if (!eglBindAPI(EGL_OPENGL_ES_API) || (W->ctx = eglCreateContext(W->d, cfg, EGL_NO_CONTEXT, ctx_attr)) == EGL_NO_CONTEXT)
        return W->ctx = NULL, "eglCreateContext failed";
    if ((W->surf = cws(W->d, cfg, &xid, NULL)) == EGL_NO_SURFACE)
        return W->surf = NULL, "eglCreatePlatformWindowSurfaceEXT failed";
    if (!eglMakeCurrent(W->d, W->surf, W->surf, W->ctx))
        return "eglMakeCurrent failed";
    return NULL;
}

static int window_attach(void *user, void *native_display, unsigned long native_window, unsigned long visual,
                         uint32_t w, uint32_t h, char *err, size_t errlen)
{
    qtool_view_gles *vg = user;
    window_gl *W = &vg->win;
    const char *why = window_context(W, native_display, native_window, visual);
    if (why) {
        snprintf(err, errlen, "%s (EGL error 0x%x)", why, (unsigned)eglGetError());
        window_close(W);
        return -1;
    }
    W->w = w, W->h = h;
    qibl_status_t st = qibl_gles2_init(&W->g, NULL);
    W->have_g = st == QIBL_OK;
    if (st == QIBL_OK)
        st = qibl_gles2_upload(&W->g, &vg->maps, NULL, NULL);
    if (st == QIBL_OK) {
        const GLenum fs = qtool_gles_rgba8_target(w, h, NULL, &W->tex, &W->fbo);
        W->prog = blit_program();
        if (fs != GL_FRAMEBUFFER_COMPLETE || !W->prog)
            why = "the window's RGBA8 texture or its copy program failed";
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    if (st != QIBL_OK || why) {
        snprintf(err, errlen, "%s", why ? why : qibl_gles2_status_str(st));
        window_close(W);
        return -1;
    }
    return 0;
}

static int window_draw(void *user, qtool_view *v)
{
    qtool_view_gles *vg = user;
    window_gl *W = &vg->win;
    glBindFramebuffer(GL_FRAMEBUFFER, W->fbo);
    qibl_status_t st = relight(&W->g, v);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: view --gles: %s\n", qibl_gles2_status_str(st));
        return -1;
    }
    static const GLfloat quad[8] = {-1, -1, 1, -1, -1, 1, 1, 1};
    glViewport(0, 0, (GLsizei)W->w, (GLsizei)W->h);
    glUseProgram(W->prog);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, W->tex);
    glUniform1i(glGetUniformLocation(W->prog, "s"), 0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, quad);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    if (glGetError() != GL_NO_ERROR || !eglSwapBuffers(W->d, W->surf)) {
        fprintf(stderr, "qibl: view --gles: drawing into the window failed\n");
        return -1;
    }
    return 0;
}

static void window_detach(void *user)
{
    window_close(&((qtool_view_gles *)user)->win);
}

const qtool_view_window_gl qtool_view_gles_window = {.attach = window_attach, .draw = window_draw,
                                                     .detach = window_detach};

void qtool_view_gles_close(qtool_view_gles *vg)
{
    if (!vg)
        return;
    window_close(&vg->win);
    if (vg->have_g)
        qibl_gles2_destroy(&vg->g);
    free(vg->rgba);
    qt_gles_close(&vg->c);
    free(vg);
}
#else
struct qtool_view_gles {
    int unused;
};

qtool_view_gles *qtool_view_gles_open(const qtool_view *v, char *err, size_t errlen)
{
    (void)v;
    snprintf(err, errlen, "view --gles: this qibl was built without the EGL/GLES2 headers (Debian: apt-get install "
                          "libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri)");
    return NULL;
}

int qtool_view_gles_frame(void *user, qtool_view *v, uint8_t *bgrx, size_t stride)
{
    (void)user, (void)v, (void)bgrx, (void)stride;
    return -1;
}

void qtool_view_gles_close(qtool_view_gles *g)
{
    (void)g;
}

const qtool_view_window_gl qtool_view_gles_window = {.attach = NULL, .draw = NULL, .detach = NULL};
#endif
