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

/* The probe layouts' names by value (io/probe_layout.h), NULL-ended: an option table's ENUM. */
extern const char *const qcli_probe_layout_names[QTOOL_PROBE_LAYOUT_COUNT + 1];

/* --yaw DEG and --rotate a,...,i into ll, for option tables' CALL kind (cli/opt.h): NULL, or what is
 * wrong with the value (a second --yaw or --rotate included). rotate's reason carries numbers:
 * why (n bytes, the options struct's) holds it. */
const char *qcli_light_yaw(qtool_relight_light_list *ll, const char *v);
const char *qcli_light_rotate(qtool_relight_light_list *ll, const char *v, char *why, size_t n);

/* relight's other light options, each as a CALL's body (the order of --sun, --point and --rgb is
 * the list's: an --rgb colours the light before it, or the first one): NULL, or what is wrong.
 * values: the option's three arguments; why (n bytes) holds a reason with the value in it, and the
 * reasons of the three-value options name the value themselves. */
const char *qcli_light_source(qtool_relight_light_list *ll, int point, char *const *v, char *why, size_t n);
const char *qcli_light_rgb(qtool_relight_light_list *ll, char *const *v, char *why, size_t n);
const char *qcli_light_csv(qtool_relight_light_list *ll, const char *v, char *why, size_t n);
const char *qcli_light_probe(qtool_relight_light_list *ll, const char *v, char *why, size_t n);
const char *qcli_light_layout(qtool_relight_light_list *ll, const char *v);
const char *qcli_light_mode(qtool_relight_light_list *ll, const char *v);
const char *qcli_light_count(qtool_relight_light_list *ll, const char *v);

/* The options together after parsing (an early --rgb with no light, -n without a probe, a
 * rotation without a probe, ...): NULL, or what is wrong. */
const char *qcli_light_list_check(const qtool_relight_light_list *ll);

/* qtool_relight_light_sh with its messages on stderr (and the faint-probe note): 0, or 1. */
int qcli_light_list_sh(const qtool_relight_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out);

/* qtool_relight_probe_load with its error on stderr: 0, or 1. */
int qcli_probe_load_note(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w, int *h,
                         uint8_t **rgbe, qtool_probe_layout_t *used);

#endif
