/*
 * relight/spec.h - the light list (relight/light.h) from its textual specification: each call is the
 * body of one option (the CLI's option tables, opt/opt.h, call them; so can any front end). The order
 * of --sun, --point and --rgb is the list's: an --rgb colours the light before it, or the first one.
 * Each returns NULL, or what is wrong with the value (why, n bytes, holds a reason with the value in
 * it; the three-value options' reasons name the values themselves). Nothing is changed on failure.
 */
#ifndef QTOOL_RELIGHT_SPEC_H
#define QTOOL_RELIGHT_SPEC_H

#include <stddef.h>
#include <stdint.h>

#include "relight/light.h"

/* The Q16.16 range the core's lights take (relight, and render, its ground truth, parse to it). */
#define QTOOL_RELIGHT_Q16_MAX (2147483647.0 / 65536.0)
#define QTOOL_RELIGHT_Q16_WHY "the Q16.16 range of the core's lights"

/* X Y Z as three finite numbers in lo..QTOOL_RELIGHT_Q16_MAX into out: NULL, or the reason in why. */
const char *qtool_relight_spec_xyz(char *const *v, double lo, double out[3], char *why, size_t n);

/* The probe layouts' names by value (io/probe_layout.h), NULL-ended: an option table's ENUM. */
extern const char *const qtool_relight_probe_layout_names[QTOOL_PROBE_LAYOUT_COUNT + 1];

/* --yaw DEG and --rotate a,...,i into ll, for option tables' CALL kind (opt/opt.h): NULL, or what is
 * wrong with the value (a second --yaw or --rotate included). rotate's reason carries numbers:
 * why (n bytes, the options struct's) holds it. */
const char *qtool_relight_spec_yaw(qtool_relight_light_list *ll, const char *v);
const char *qtool_relight_spec_rotate(qtool_relight_light_list *ll, const char *v, char *why, size_t n);

/* relight's other light options, each as a CALL's body (the order of --sun, --point and --rgb is
 * the list's: an --rgb colours the light before it, or the first one): NULL, or what is wrong.
 * values: the option's three arguments; why (n bytes) holds a reason with the value in it, and the
 * reasons of the three-value options name the value themselves. */
const char *qtool_relight_spec_source(qtool_relight_light_list *ll, int point, char *const *v, char *why, size_t n);
const char *qtool_relight_spec_rgb(qtool_relight_light_list *ll, char *const *v, char *why, size_t n);
const char *qtool_relight_spec_csv(qtool_relight_light_list *ll, const char *v, char *why, size_t n);
const char *qtool_relight_spec_probe(qtool_relight_light_list *ll, const char *v, char *why, size_t n);
const char *qtool_relight_spec_layout(qtool_relight_light_list *ll, const char *v);
const char *qtool_relight_spec_mode(qtool_relight_light_list *ll, const char *v);
const char *qtool_relight_spec_count(qtool_relight_light_list *ll, const char *v);

/* The options together after parsing (an early --rgb with no light, -n without a probe, a
 * rotation without a probe, ...): NULL, or what is wrong. */
const char *qtool_relight_spec_check(const qtool_relight_light_list *ll);

#endif
