/*
 * cli/relight_light.h - the CLI's side of relight's light (relight/light.h): the options that build
 * it (light_opts.c), and the load and SH calls with their messages printed. The old qcli_ names of
 * what moved to tools/relight are aliases here for the commands that still use them (probe, probe
 * info, view).
 */
#ifndef QTOOL_CLI_RELIGHT_LIGHT_H
#define QTOOL_CLI_RELIGHT_LIGHT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "relight/light.h"

#define qcli_light_list qtool_relight_light_list
#define qcli_light_list_init qtool_relight_light_list_init
#define qcli_light_list_directional qtool_relight_light_list_directional
#define qcli_probe_suns qtool_relight_probe_suns
#define QCLI_PROBE_SH QTOOL_RELIGHT_PROBE_SH
#define QCLI_PROBE_LIGHTS QTOOL_RELIGHT_PROBE_LIGHTS
#define QCLI_PROBE_SUNSKY QTOOL_RELIGHT_PROBE_SUNSKY
#define QCLI_SUN_CONTRAST QTOOL_RELIGHT_SUN_CONTRAST
#define QCLI_SUN_MAX QTOOL_RELIGHT_SUN_MAX

#include "relight/spec.h"

/* --yaw DEG / --rotate a,...,i as relight, lights and sh project take them: the rotation (ll's rotate, yaw
 * and r; relight/spec.h's rules) and the room for --rotate's reason, a field of the command's options
 * that QCLI_TURN_OPTS's two entries fill through one pair of callbacks. */
typedef struct qcli_turn {
    qtool_relight_light_list ll; /* only its rotate, yaw and r */
    char why[192];
} qcli_turn;
#define QCLI_TURN_DEFAULT {.ll = QTOOL_RELIGHT_LIGHT_LIST_DEFAULT}
const char *qcli_turn_yaw(void *turn, const char *v);
const char *qcli_turn_rotate(void *turn, const char *v);
/* the two table entries for the qcli_turn at member of type, with their help lines */
#define QCLI_TURN_OPTS(type, member, yaw_help, rotate_help)                                                     \
    {.name = "--yaw", .kind = QTOOL_OPT_CALL, .off = offsetof(type, member), .field = 1, .arg = "DEG",          \
     .call = qcli_turn_yaw, .help = yaw_help},                                                                    \
    {.name = "--rotate", .kind = QTOOL_OPT_CALL, .off = offsetof(type, member), .field = 1,                      \
     .arg = "a,b,c,d,e,f,g,h,i", .call = qcli_turn_rotate, .help = rotate_help}

/* --layout L of lights, probe info and sh project: the probe's layout, an int (qtool_probe_layout_t) at
 * member of type */
#define QCLI_LAYOUT_OPT(type, member)                                                                            \
    {.name = "--layout", .kind = QTOOL_OPT_ENUM, .off = offsetof(type, member),                                 \
     .names = qtool_relight_probe_layout_names, .arg = "L",                                                      \
     .help = "the probe's layout: auto (detected, and said so), latlong, angular, ball, vcross or hcross"}

/* qtool_relight_light_sh with its messages on stderr (and the faint-probe note): 0, or 1. */
int qcli_light_list_sh(const qtool_relight_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out);

/* qtool_relight_probe_load with its error on stderr: 0, or 1. */
int qcli_probe_load_note(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w, int *h,
                         uint8_t **rgbe, qtool_probe_layout_t *used);

#endif
