/*
 * relight/spec.c - the light list from its textual specification (relight/spec.h): the rules of
 * --sun, --point, --rgb, --lights, --probe, --probe-mode, -n, --layout, --yaw and --rotate as the
 * CLI's option tables call them.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "opt/opt.h"
#include "relight/spec.h"

const char *qtool_relight_spec_xyz(char *const *v, double lo, double out[3], char *why, size_t n)
{
    double d[3];
    for (int j = 0; j < 3; ++j) {
        int r = qtool_opt_num_value(v[j], lo, QTOOL_RELIGHT_Q16_MAX, &d[j]);
        if (r == 1 || r == 2)
            snprintf(why, n, "'%s' is not a %snumber", v[j], r == 2 ? "finite " : "");
        else if (r != 0)
            snprintf(why, n, "%s is outside %.10g..%.10g (" QTOOL_RELIGHT_Q16_WHY ")", v[j], lo, QTOOL_RELIGHT_Q16_MAX);
        if (r != 0)
            return why;
    }
    memcpy(out, d, sizeof d);
    return NULL;
}

/* three numbers into Q16.16 (lo..QTOOL_RELIGHT_Q16_MAX): NULL, or what is wrong (in why) */
static const char *parse3(char *const *v, double lo, int32_t q[3], char *why, size_t n)
{
    double d[3];
    if (qtool_relight_spec_xyz(v, lo, d, why, n))
        return why;
    for (int j = 0; j < 3; ++j)
        q[j] = (int32_t)nearbyint(d[j] * 65536.0);
    return NULL;
}

const char *qtool_relight_spec_source(qtool_relight_light_list *ll, int point, char *const *v, char *why, size_t n)
{
    int32_t q[3];
    const int full = ll->count >= QTOOL_RELIGHT_MAX_SOURCES; /* said before the numbers are read */
    if (!full && parse3(v, -QTOOL_RELIGHT_Q16_MAX, q, why, n))
        return why;
    if (!full && !point && q[0] == 0 && q[1] == 0 && q[2] == 0) {
        snprintf(why, n, "%s %s %s is 0 0 0 in Q16.16: --sun needs a non-zero direction", v[0], v[1], v[2]);
        return why;
    }
    if (full || qtool_relight_light_list_add(ll, point, q) != 0) {
        snprintf(why, n, "at most %u --sun and --point options", QTOOL_RELIGHT_MAX_SOURCES);
        return why;
    }
    return NULL;
}

const char *qtool_relight_spec_rgb(qtool_relight_light_list *ll, char *const *v, char *why, size_t n)
{
    int32_t q[3];
    if (parse3(v, 0, q, why, n))
        return why;
    if (ll->count == 0) {
        if (ll->early_rgb)
            return "given twice before the first --sun/--point";
        ll->early_rgb = 1, memcpy(ll->rgb0, q, sizeof q);
    } else {
        qtool_relight_source *s = &ll->src[ll->count - 1];
        if (s->have_rgb) {
            snprintf(why, n, "given twice for the %s before it", s->point ? "--point" : "--sun");
            return why;
        }
        memcpy(s->rgb, q, sizeof q), s->have_rgb = 1;
    }
    return NULL;
}

/* a flag given at most once: its value kept in *slot, or why not */
static const char *once(const char **slot, const char *v, const char *flag, char *why, size_t n)
{
    if (*slot) {
        snprintf(why, n, "is a second %s (the first: %s): give one", flag, *slot);
        return why;
    }
    *slot = v;
    return NULL;
}

const char *qtool_relight_spec_csv(qtool_relight_light_list *ll, const char *v, char *why, size_t n)
{
    return once(&ll->csv, v, "--lights", why, n);
}

const char *qtool_relight_spec_probe(qtool_relight_light_list *ll, const char *v, char *why, size_t n)
{
    return once(&ll->probe, v, "--probe", why, n);
}

const char *qtool_relight_spec_layout(qtool_relight_light_list *ll, const char *v)
{
    return qtool_probe_layout_parse(v, &ll->layout) != 0
               ? "is not a probe layout (auto, latlong, angular, ball, vcross or hcross)"
               : NULL;
}

const char *qtool_relight_spec_mode(qtool_relight_light_list *ll, const char *v)
{
    if (strcmp(v, "sh") == 0)
        ll->mode = QTOOL_RELIGHT_PROBE_SH;
    else if (strcmp(v, "lights") == 0)
        ll->mode = QTOOL_RELIGHT_PROBE_LIGHTS;
    else if (strcmp(v, "sunsky") == 0)
        ll->mode = QTOOL_RELIGHT_PROBE_SUNSKY;
    else
        return "is not sh, lights or sunsky";
    return NULL;
}

const char *qtool_relight_spec_count(qtool_relight_light_list *ll, const char *v)
{
    long k;
    if (qtool_opt_int_value(v, 1, 65536, &k) != 0 || (k & (k - 1)) != 0)
        return "is not a power of two in 1..65536 (median-cut lights)";
    ll->n = k;
    return NULL;
}

#define QTOOL_RELIGHT_LAYOUT_NAME_(id, name, description) name,
const char *const qtool_relight_probe_layout_names[QTOOL_PROBE_LAYOUT_COUNT + 1] = {
    QTOOL_PROBE_LAYOUT_LIST(QTOOL_RELIGHT_LAYOUT_NAME_) NULL};
#undef QTOOL_RELIGHT_LAYOUT_NAME_

const char *qtool_relight_spec_yaw(qtool_relight_light_list *ll, const char *v)
{
    if (ll->rotate)
        return "comes after a --yaw or --rotate: give one of them, once";
    switch (qtool_opt_num_value(v, -36000.0, 36000.0, &ll->yaw)) {
    case 0:
        break;
    case 1:
        return "is not a number";
    case 2:
        return "is not a finite number";
    default:
        return "is outside -36000..36000 (degrees)";
    }
    qtool_relight_yaw(ll->yaw, ll->r);
    ll->rotate = 1;
    return NULL;
}

const char *qtool_relight_spec_rotate(qtool_relight_light_list *ll, const char *v, char *why, size_t n)
{
    if (ll->rotate)
        return "comes after a --yaw or --rotate: give one of them, once";
    const char *s = v;
    double m[9], worst, det;
    char *end;
    for (int k = 0; k < 9; ++k) {
        errno = 0;
        m[k] = strtod(s, &end);
        if (end == s || errno == ERANGE || !isfinite(m[k]) || (k < 8 ? *end != ',' : *end != '\0'))
            return "is not nine comma-separated numbers a,b,c,d,e,f,g,h,i";
        s = end + 1;
    }
    /* the core's condition, said here by name */
    if (qtool_relight_rotation_check(m, &worst, &det) != 0) {
        snprintf(why, n, "is not a rotation (rows orthonormal within 2^-16: off by %.3g; det %.3g, must be +1)",
                 worst, det);
        return why;
    }
    for (int k = 0; k < 9; ++k)
        ll->r[k / 3][k % 3] = m[k];
    ll->rotate = 2;
    return NULL;
}

const char *qtool_relight_spec_check(const qtool_relight_light_list *ll)
{
    if (ll->early_rgb && ll->count == 0)
        return "--rgb colours a --sun or --point; there is none";
    if (!ll->probe &&
        (ll->rotate || ll->n || ll->mode != QTOOL_RELIGHT_PROBE_SH || ll->layout != QTOOL_PROBE_LAYOUT_AUTO))
        return "--yaw, --rotate, --probe-mode, -n and --layout need --probe PROBE.hdr";
    if (ll->probe && ll->n && ll->mode == QTOOL_RELIGHT_PROBE_SH)
        return "-n counts median-cut lights: it needs --probe-mode lights or sunsky";
    return NULL;
}

