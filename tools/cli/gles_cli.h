/*
 * cli/gles_cli.h - the CLI's OpenGL ES 2.0 bench (platform/gles2 on a headless EGL context):
 * `qibl bench gles`; `qibl relight --gles` lives in relight/gles.h. Without the EGL/GLES2 headers at
 * build time the bench prints one line saying so and skips.
 */
#ifndef QTOOL_TOOLS_GLES_CLI_H
#define QTOOL_TOOLS_GLES_CLI_H

#include <stdint.h>

#include "relight/gles.h" /* qtool_gles_relight: relight --gles */

#endif
