/*
 * light_opts.c - relight's light options parsed into qtool_relight_light_list (relight/light.h), and
 * the library's light calls with their messages printed (cli/relight_light.h). relight parses every
 * option here; lights, probe and view take only --yaw / --rotate.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/opt.h"
#include "cli/relight_light.h"

/* three numbers after argv[i] into Q16.16 (lo..QTOOL_CLI_Q16_MAX); 0 or 2 after a message */
static int parse3(char **argv, int i, int argc, double lo, int32_t v[3])
{
    if (i + 3 >= argc)
        return qcli_usage_error("%s needs three numbers", argv[i]);
    for (int j = 0; j < 3; ++j) {
        double d;
        if (qcli_parse_num(argv[i], argv[i + 1 + j], lo, QTOOL_CLI_Q16_MAX, QTOOL_CLI_Q16_WHY, &d) != 0)
            return 2;
        v[j] = (int32_t)nearbyint(d * 65536.0);
    }
    return 0;
}

static int add_source(qtool_relight_light_list *ll, char **argv, int argc, int *i, int point)
{
    int32_t v[3];
    const int full = ll->count >= QTOOL_RELIGHT_MAX_SOURCES; /* said before the numbers are read */
    if (!full && parse3(argv, *i, argc, -QTOOL_CLI_Q16_MAX, v) != 0)
        return 2;
    if (!full && !point && v[0] == 0 && v[1] == 0 && v[2] == 0)
        return qcli_usage_error("--sun needs a non-zero direction: %s %s %s is 0 0 0 in Q16.16", argv[*i + 1],
                                argv[*i + 2], argv[*i + 3]);
    if (full || qtool_relight_light_list_add(ll, point, v) != 0)
        return qcli_usage_error("%s: at most %u --sun and --point options", argv[*i], QTOOL_RELIGHT_MAX_SOURCES);
    *i += 3;
    return 1;
}

static int rgb_opt(int argc, char **argv, int *i, qtool_relight_light_list *ll)
{
    int32_t v[3];
    if (parse3(argv, *i, argc, 0, v) != 0)
        return 2;
    if (ll->count == 0) {
        if (ll->early_rgb)
            return qcli_usage_error("--rgb given twice before the first --sun/--point");
        ll->early_rgb = 1, memcpy(ll->rgb0, v, sizeof v);
    } else {
        qtool_relight_source *s = &ll->src[ll->count - 1];
        if (s->have_rgb)
            return qcli_usage_error("--rgb given twice for the %s at %s", s->point ? "--point" : "--sun",
                                    argv[*i + 1]);
        memcpy(s->rgb, v, sizeof v), s->have_rgb = 1;
    }
    *i += 3;
    return 1;
}

#define QCLI_LAYOUT_NAME_(id, name, description) name,
const char *const qcli_probe_layout_names[QTOOL_PROBE_LAYOUT_COUNT + 1] = {
    QTOOL_PROBE_LAYOUT_LIST(QCLI_LAYOUT_NAME_) NULL};
#undef QCLI_LAYOUT_NAME_

const char *qcli_light_yaw(qtool_relight_light_list *ll, const char *v)
{
    if (ll->rotate)
        return "comes after a --yaw or --rotate: give one of them, once";
    switch (qcli_opt_num_value(v, -36000.0, 36000.0, &ll->yaw)) {
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

const char *qcli_light_rotate(qtool_relight_light_list *ll, const char *v, char *why, size_t n)
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

/* the probe's options: --lights, --probe, --layout, --probe-mode, -n; 1, 0 (none) or 2 */
static int probe_opt(char **argv, int *i, qtool_relight_light_list *ll)
{
    const char *a = argv[*i];
    if (strcmp(a, "--lights") == 0) {
        if (ll->csv)
            return qcli_usage_error("--lights given twice (%s and %s)", ll->csv, argv[*i + 1]);
        ll->csv = argv[++*i];
    } else if (strcmp(a, "--probe") == 0) {
        if (ll->probe)
            return qcli_usage_error("--probe given twice (%s and %s)", ll->probe, argv[*i + 1]);
        ll->probe = argv[++*i];
    } else if (strcmp(a, "--layout") == 0) {
        if (qtool_probe_layout_parse(argv[++*i], &ll->layout) != 0)
            return qcli_usage_error("--layout: '%s' is not a probe layout (auto, latlong, angular, ball, vcross or "
                                    "hcross)", argv[*i]);
    } else if (strcmp(a, "--probe-mode") == 0) {
        const char *m = argv[++*i];
        if (strcmp(m, "sh") == 0)
            ll->mode = QTOOL_RELIGHT_PROBE_SH;
        else if (strcmp(m, "lights") == 0)
            ll->mode = QTOOL_RELIGHT_PROBE_LIGHTS;
        else if (strcmp(m, "sunsky") == 0)
            ll->mode = QTOOL_RELIGHT_PROBE_SUNSKY;
        else
            return qcli_usage_error("--probe-mode: '%s' is not sh, lights or sunsky", m);
    } else if (strcmp(a, "-n") == 0) {
        if (qcli_parse_int(argv[++*i], 1, 65536, &ll->n) != 0 || (ll->n & (ll->n - 1)) != 0)
            return qcli_usage_error("-n: '%s' is not a power of two in 1..65536 (median-cut lights)", argv[*i]);
    } else {
        return 0;
    }
    return 1;
}

int qcli_light_list_opt(int argc, char **argv, int *i, qtool_relight_light_list *ll)
{
    const char *a = argv[*i];
    int more = *i + 1 < argc, r;
    if (strcmp(a, "--sun") == 0 || strcmp(a, "--point") == 0)
        return add_source(ll, argv, argc, i, a[2] == 'p');
    if (strcmp(a, "--rgb") == 0)
        return rgb_opt(argc, argv, i, ll);
    if (more && (r = probe_opt(argv, i, ll)) != 0)
        return r;
    if ((strcmp(a, "--yaw") == 0 || strcmp(a, "--rotate") == 0) && more) {
        char why[192];
        const char *v = argv[++*i], *bad = a[2] == 'y' ? qcli_light_yaw(ll, v) : qcli_light_rotate(ll, v, why, sizeof why);
        return bad ? qcli_usage_error("%s: '%s' %s", a, v, bad) : 1;
    }
    return 0;
}

int qcli_light_list_check(const qtool_relight_light_list *ll)
{
    if (ll->early_rgb && ll->count == 0)
        return qcli_usage_error("--rgb colours a --sun or --point; there is none");
    if (!ll->probe &&
        (ll->rotate || ll->n || ll->mode != QTOOL_RELIGHT_PROBE_SH || ll->layout != QTOOL_PROBE_LAYOUT_AUTO))
        return qcli_usage_error("--yaw, --rotate, --probe-mode, -n and --layout need --probe PROBE.hdr");
    if (ll->probe && ll->n && ll->mode == QTOOL_RELIGHT_PROBE_SH)
        return qcli_usage_error("-n counts median-cut lights: it needs --probe-mode lights or sunsky");
    return 0;
}

int qcli_light_list_sh(const qtool_relight_light_list *ll, uint32_t k, FILE *note, qibl_shlight_t *out)
{
    char err[4200 + 600];
    int faint = 0, rc = qtool_relight_light_sh(ll, k, note, out, &faint, err, sizeof err);
    if (faint) /* no exposure brings such a frame back */
        fprintf(stderr, "qibl: note: %s: its light is below the resolution of the core's SH light (2^-16 in "
                        "Q16.16): it relights to exact zero; scale the probe up\n", ll->probe);
    if (rc != 0)
        fprintf(stderr, "qibl: %s\n", err);
    return rc != 0;
}

int qcli_probe_load_note(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w, int *h,
                         uint8_t **rgbe, qtool_probe_layout_t *used)
{
    char err[4200 + 600];
    if (qtool_relight_probe_load(path, want, note, notelen, w, h, rgbe, used, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    return 0;
}
