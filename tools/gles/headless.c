/*
 * gles/headless.c - headless EGL + GLES2 context (see headless.h). Built only where the EGL and
 * GLES2 headers exist (QIBL_HAVE_GLES2); elsewhere its calls fail, saying so.
 */
#include "gles/headless.h"

#include <stdio.h>
#include <string.h>

#if QIBL_HAVE_GLES2
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2.h>

#include "gles/gl.h"

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif

static EGLDisplay get_display(void)
{
    const char *ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (ext != NULL && strstr(ext, "EGL_MESA_platform_surfaceless") != NULL) {
        PFNEGLGETPLATFORMDISPLAYEXTPROC gpd =
            (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
        if (gpd != NULL) {
            EGLDisplay d = gpd(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
            if (d != EGL_NO_DISPLAY)
                return d;
        }
    }
    return eglGetDisplay(EGL_DEFAULT_DISPLAY);
}

int qt_gles_open(qt_gles_ctx *c, uint32_t w, uint32_t h, char *why, size_t why_size)
{
    memset(c, 0, sizeof *c);
    EGLDisplay d = get_display();
    EGLint major = 0, minor = 0;
    if (d == EGL_NO_DISPLAY || !eglInitialize(d, &major, &minor)) {
        snprintf(why, why_size, "no EGL display (eglInitialize error 0x%x)", (unsigned)eglGetError());
        return -1;
    }
    c->display = d;
    const EGLint cfg_attr[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES2_BIT,
                               EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    const EGLint cfg_attr_nosurf[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES2_BIT, EGL_NONE};
    EGLConfig cfg;
    EGLint n = 0;
    int pbuffer = eglChooseConfig(d, cfg_attr, &cfg, 1, &n) && n == 1;
    if (!pbuffer && !(eglChooseConfig(d, cfg_attr_nosurf, &cfg, 1, &n) && n == 1)) {
        snprintf(why, why_size, "no EGL config with OpenGL ES 2 (error 0x%x)", (unsigned)eglGetError());
        qt_gles_close(c);
        return -1;
    }
    eglBindAPI(EGL_OPENGL_ES_API);
    const EGLint ctx_attr[] = {EGL_CONTEXT_CLIENT_VERSION, 2, EGL_NONE};
    EGLContext ctx = eglCreateContext(d, cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT) {
        snprintf(why, why_size, "eglCreateContext failed (error 0x%x)", (unsigned)eglGetError());
        qt_gles_close(c);
        return -1;
    }
    c->context = ctx;
    EGLSurface s = EGL_NO_SURFACE;
    if (pbuffer) {
        const EGLint pb_attr[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
        s = eglCreatePbufferSurface(d, cfg, pb_attr);
    }
    c->surface = s;
    if (!eglMakeCurrent(d, s, s, ctx)) {
        snprintf(why, why_size, "eglMakeCurrent failed (error 0x%x)", (unsigned)eglGetError());
        qt_gles_close(c);
        return -1;
    }
    const char *r = (const char *)glGetString(GL_RENDERER);
    snprintf(c->renderer, sizeof c->renderer, "%s", r ? r : "?");
    GLuint tex = 0, fbo = 0;
    GLenum fs = qtool_gles_rgba8_target(w, h, NULL, &tex, &fbo);
    c->tex = tex, c->fbo = fbo, c->width = w, c->height = h;
    if (fs != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(why, why_size, "RGBA8 framebuffer %ux%u incomplete (0x%x)", w, h, (unsigned)fs);
        qt_gles_close(c);
        return -1;
    }
    return 0;
}

int qt_gles_read(const qt_gles_ctx *c, uint8_t *rgba)
{
    glBindFramebuffer(GL_FRAMEBUFFER, c->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, (GLsizei)c->width, (GLsizei)c->height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void qt_gles_close(qt_gles_ctx *c)
{
    if (c->context != NULL) {
        GLuint fbo = c->fbo, tex = c->tex;
        if (fbo != 0u)
            glDeleteFramebuffers(1, &fbo);
        if (tex != 0u)
            glDeleteTextures(1, &tex);
    }
    if (c->display != NULL) {
        eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (c->surface != NULL)
            eglDestroySurface(c->display, c->surface);
        if (c->context != NULL)
            eglDestroyContext(c->display, c->context);
        eglTerminate(c->display);
    }
    memset(c, 0, sizeof *c);
}
#else
/* built without EGL/GLES2: every open fails with that reason, so a caller (luminaire passes --gles)
 * links and says why instead of failing the link */
int qt_gles_open(qt_gles_ctx *c, uint32_t w, uint32_t h, char *why, size_t why_size)
{
    (void)w, (void)h;
    memset(c, 0, sizeof *c);
    snprintf(why, why_size, "built without EGL/GLES2");
    return -1;
}

int qt_gles_read(const qt_gles_ctx *c, uint8_t *rgba)
{
    (void)c, (void)rgba;
    return -1;
}

void qt_gles_close(qt_gles_ctx *c)
{
    memset(c, 0, sizeof *c);
}
#endif
