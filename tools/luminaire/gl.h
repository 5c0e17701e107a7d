/*
 * luminaire/gl.h - what the near-field source's two GLES2 paths share (passes_gles.c accumulates
 * uploaded passes, spots_gles.c evaluates the spotlights): the sRGBE codec in GLSL, shader
 * compilation from parts, and nearest-filtered clamped textures. Only with QIBL_HAVE_GLES2.
 */
#ifndef QTOOL_LUMINAIRE_GL_H
#define QTOOL_LUMINAIRE_GL_H

#if QIBL_HAVE_GLES2
#include <stddef.h>
#include <stdint.h>

#include <GLES2/gl2.h>

/* GLSL: vec3 dec(vec4) and vec4 enc(vec3), platform/gles2's sRGBE codec (its fs_srgbe) on RGBA8
 * codes, the exponent fixed up where log2 is inexact; goes after the precision statement */
extern const char qtool_luminaire_glsl_codec[];

/* A shader of kind from n source parts in order (a part may be ""), compiled: its name, or 0 with
 * the compiler's log in err (nothing left behind). */
GLuint qtool_luminaire_gl_shader(GLenum kind, const char *const *parts, int n, char *err, size_t errlen);

/* A w x h 2D texture of format/type (data may be NULL), nearest filtering, clamped at the edges;
 * left bound to GL_TEXTURE_2D. */
GLuint qtool_luminaire_gl_texture(GLenum format, GLenum type, uint32_t w, uint32_t h, const void *data);
#endif

#endif
