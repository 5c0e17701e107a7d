/*
 * gles/gl.c - the GLES2 chores the tools' GL code shares (gl.h).
 */
#include "gles/gl.h"

#if QIBL_HAVE_GLES2
#include <stdio.h>

GLuint qtool_gles_shader(GLenum kind, const char *const *parts, int n, char *err, size_t errlen)
{
    GLuint s = glCreateShader(kind);
    GLint ok = 0;
    glShaderSource(s, n, parts, NULL);
    glCompileShader(s);
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[256] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        snprintf(err, errlen, "a shader did not compile: %s", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

GLuint qtool_gles_texture(GLenum format, GLenum type, uint32_t w, uint32_t h, const void *data)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)format, (GLsizei)w, (GLsizei)h, 0, format, type, data);
    return t;
}

GLenum qtool_gles_rgba8_target(uint32_t w, uint32_t h, const void *data, GLuint *tex, GLuint *fbo)
{
    *tex = qtool_gles_texture(GL_RGBA, GL_UNSIGNED_BYTE, w, h, data);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER);
}
#else
typedef int qtool_gles_gl_unused; /* ISO C: a translation unit is not empty */
#endif
