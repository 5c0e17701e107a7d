/*
 * gles/gl.h - the GLES2 chores the tools' own GL code shares (luminaire's spotlights and passes, the
 * headless context's and the viewer's render targets): shader compilation from parts, nearest-
 * filtered clamped textures, an RGBA8 texture as a framebuffer. Only with QIBL_HAVE_GLES2; the
 * sRGBE codec in GLSL is platform/gles2's (qibl_gles2_glsl_srgbe).
 */
#ifndef QTOOL_TOOLS_GLES_GL_H
#define QTOOL_TOOLS_GLES_GL_H

#if QIBL_HAVE_GLES2
#include <stddef.h>
#include <stdint.h>

#include <GLES2/gl2.h>

/* A shader of kind from n source parts in order (a part may be ""), compiled: its name, or 0 with
 * the compiler's log in err (nothing left behind). */
GLuint qtool_gles_shader(GLenum kind, const char *const *parts, int n, char *err, size_t errlen);

/* A w x h 2D texture of format/type (data may be NULL), nearest filtering, clamped at the edges;
 * left bound to GL_TEXTURE_2D. */
GLuint qtool_gles_texture(GLenum format, GLenum type, uint32_t w, uint32_t h, const void *data);

/* A w x h RGBA8 texture as qtool_gles_texture makes it (*tex; data may be NULL) and a new framebuffer
 * (*fbo) with it as the colour attachment, left bound: glCheckFramebufferStatus's answer
 * (GL_FRAMEBUFFER_COMPLETE when usable). The caller deletes both whatever it says. */
GLenum qtool_gles_rgba8_target(uint32_t w, uint32_t h, const void *data, GLuint *tex, GLuint *fbo);
#endif

#endif
