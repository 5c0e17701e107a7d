/*
 * gles/headless.h - a headless EGL + OpenGL ES 2.0 context for the tools and tests (Mesa's
 * surfaceless platform, else the default display with a pbuffer), so platform/gles2 can run
 * without a window. The backend itself never creates contexts: this is the caller's side.
 */
#ifndef QTOOL_TOOLS_GLES_HEADLESS_H
#define QTOOL_TOOLS_GLES_HEADLESS_H

#include <stddef.h>
#include <stdint.h>

typedef struct qt_gles_ctx {
    void *display, *context, *surface; /* EGLDisplay, EGLContext, EGLSurface */
    uint32_t fbo, tex, width, height;  /* an RGBA8 render target of width x height */
    char renderer[128];                /* GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" */
} qt_gles_ctx;

/* Creates and makes current a GLES2 context and an RGBA8 framebuffer of w x h bound to it.
 * Returns 0, or -1 with a one-line reason in why (why_size bytes). */
int qt_gles_open(qt_gles_ctx *c, uint32_t w, uint32_t h, char *why, size_t why_size);

/* Reads the bound framebuffer (w x h RGBA8, rows in GL order: row 0 first) into rgba. 0 or -1. */
int qt_gles_read(const qt_gles_ctx *c, uint8_t *rgba);

/* Releases everything qt_gles_open made; safe on a zeroed c. */
void qt_gles_close(qt_gles_ctx *c);

#endif
