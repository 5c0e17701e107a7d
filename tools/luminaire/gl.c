/*
 * luminaire/gl.c - the GLES2 helpers and GLSL the near-field source's GPU paths share (gl.h).
 */
#include "luminaire/gl.h"

#if QIBL_HAVE_GLES2
#include <stdio.h>

const char qtool_luminaire_glsl_codec[] =
    "vec3 dec(vec4 t) {\n"
    "  vec4 x = floor(t * 255.0 + 0.5);\n"
    "  return (x.rgb - 127.5) / 255.0 * exp2(x.a - 126.0);\n"
    "}\n"
    "vec4 enc(vec3 c) {\n"
    "  float m = max(max(abs(c.r), abs(c.g)), abs(c.b));\n"
    "  if (m < 1.1754944e-38) return vec4(128.0, 128.0, 128.0, 0.0) / 255.0;\n"
    "  float e = floor(log2(m)) + 2.0;\n"
    "  if (m * exp2(-e) >= 0.5) e += 1.0;\n"
    "  if (m * exp2(-e) < 0.25) e -= 1.0;\n"
    "  e = min(e, 129.0);\n"
    "  vec3 x = clamp(floor(255.0 * (c * exp2(-e) + 0.5) + 0.5), 0.0, 255.0);\n"
    "  return vec4(x, e + 126.0) / 255.0;\n"
    "}\n";

GLuint qtool_luminaire_gl_shader(GLenum kind, const char *const *parts, int n, char *err, size_t errlen)
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

GLuint qtool_luminaire_gl_texture(GLenum format, GLenum type, uint32_t w, uint32_t h, const void *data)
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
#else
typedef int qtool_luminaire_gl_unused; /* ISO C: a translation unit is not empty */
#endif
