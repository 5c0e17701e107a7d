/*
 * light_opts.c - the library's light calls with their messages printed (cli/relight_light.h);
 * the light options' rules are relight/spec.h.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/relight_light.h"

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

const char *qcli_turn_yaw(void *turn, const char *v)
{
    return qtool_relight_spec_yaw(&((qcli_turn *)turn)->ll, v);
}

const char *qcli_turn_rotate(void *turn, const char *v)
{
    qcli_turn *t = turn;
    return qtool_relight_spec_rotate(&t->ll, v, t->why, sizeof t->why);
}

int qcli_probe_load_note(const char *path, qtool_probe_layout_t want, char *note, size_t notelen, int *w, int *h,
                         uint8_t **rgbe, qtool_probe_layout_t *used)
{
    char err[4200 + 600];
    if (qtool_relight_probe_load(path, want, note, notelen, w, h, rgbe, used, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    return 0;
}
