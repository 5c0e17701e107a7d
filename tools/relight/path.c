/*
 * relight/path.c - a light on one of the asset's baked paths (LPTH) at parameter t, relit as
 * unshadowed SH x visibility(t), optionally over a sky through the shadowed maps (sky + sun in one
 * frame): `qibl relight FILE --path N --t T ...` (relight.h).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "qibl/soft.h"
#include "qtool.h"
#include "relight/relight.h"

/* a decimal index in 0..4095 (the whole string, as strtol reads it); 0 or -1 */
static int parse_index(const char *s, long *v)
{
    char *end;
    errno = 0;
    *v = strtol(s, &end, 10);
    return end != s && *end == '\0' && errno != ERANGE && *v >= 0 && *v <= 4095 ? 0 : -1;
}

int qtool_relight_pick_path(const qibl_asset_t *a, const char *in, const char *spec, uint32_t *index, char *err,
                            size_t errlen)
{
    uint32_t n = qibl_lightpath_count(a);
    long v;
    if (n == 0)
        return qtool_errf(err, errlen, "%s: no light paths (bake with --sun-path or --lamp-track)", in);
    if (strcmp(spec, "sun") == 0 || strcmp(spec, "lamp") == 0) {
        uint32_t want = spec[0] == 's' ? QIBL_LIGHTPATH_DIRECTIONS : QIBL_LIGHTPATH_POSITIONS;
        for (uint32_t i = 0; i < n; ++i) {
            qibl_lightpath_t p;
            if (qibl_lightpath_from_asset(a, i, &p) == QIBL_OK && p.kind == want) {
                *index = i;
                return 0;
            }
        }
        return qtool_errf(err, errlen, "%s: no %s path among its %u light path%s", in, spec[0] == 's' ? "sun" : "lamp",
                          n, n == 1 ? "" : "s");
    }
    if (parse_index(spec, &v) != 0) {
        qtool_errf(err, errlen, "--path needs an index, sun or lamp: '%s'", spec);
        return -2;
    }
    if ((uint32_t)v >= n)
        return qtool_errf(err, errlen, "%s: --path %ld, but the asset has %u light path%s (0..%u)", in, v, n,
                          n == 1 ? "" : "s", n - 1);
    *index = (uint32_t)v;
    return 0;
}

int qtool_relight_path(const uint8_t *bytes, size_t n, const qibl_asset_t *a, const char *in,
                       const qtool_relight_path_req *r, uint8_t *rgb8, float *lin, double *ms, int *point, char *err,
                       size_t errlen)
{
    /* the light at t as the asset stores it (the core's interpolation of the keys) */
    qibl_lightpath_t p;
    qibl_q16_t v[3];
    qibl_status_t st = qibl_lightpath_from_asset(a, r->index, &p);
    if (st == QIBL_OK)
        st = qibl_lightpath_at(&p, r->tq, v);
    if (st != QIBL_OK)
        return qtool_errf(err, errlen, "%s: light path %u: %s", in, r->index, qibl_soft_status_str(st));
    qtool_rt_light l;
    memset(&l, 0, sizeof l);
    l.point = p.kind == QIBL_LIGHTPATH_POSITIONS, l.falloff = 1;
    for (int c = 0; c < 3; ++c) {
        (l.point ? l.pos : l.dir)[c] = v[c] / 65536.0;
        l.rgb[c] = r->rgb[c];
    }
    *point = l.point;
    if (!rgb8 || (r->lin && !lin))
        return qtool_errf(err, errlen, "relight: out of memory");
    if (r->gonio && !l.point)
        return qtool_errf(err, errlen, "relight: --ies shapes a lamp: path %u of %s is a sun path", r->index, in);
    qibl_shlight_t skysh;
    if (r->sky)
        qtool_bake_sky_sh(r->sky, QIBL_SH_MAX_COUNT, &skysh);
    uint32_t radius = r->radius > QIBL_LIGHTPATH_MAX_RADIUS ? QIBL_LIGHTPATH_MAX_RADIUS : r->radius;
    if (qtool_bake_relight_path8_gonio(bytes, n, &l, r->gonio, r->index, r->tq, radius, r->sky ? &skysh : NULL, rgb8,
                                       lin, ms, &st) != 0)
        return qtool_errf(err, errlen, "relight: %s: %s", in, qtool_status_str(st));
    return 0;
}
