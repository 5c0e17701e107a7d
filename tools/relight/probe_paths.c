/*
 * relight/probe_paths.c - `qibl relight ASSET --probe P.hdr` on a probe-lit asset (bake --probe):
 * the probe's compact sources through the unshadowed maps x their baked single-direction paths,
 * the rest of the probe as SH through the shadowed maps (bake/probesun.h), once the asset's PSUN
 * chunk says it was baked with this probe and yaw (relight.h).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/probesun.h"
#include "qtool.h"
#include "relight/relight.h"

int qtool_relight_probe_paths(const qtool_relight_asset *s, const char *in, const char *probe, double yaw,
                              uint8_t *rgb8, double *ms, qtool_relight_probe_paths_note *note, char *err,
                              size_t errlen)
{
    qibl_chunk_t ch;
    if (qibl_asset_find(&s->a, QTOOL_PROBESUN_CHUNK, &ch) != QIBL_OK)
        return 1; /* not a probe-lit asset: the caller relights the probe as SH */
    qtool_probesun ps;
    if (qtool_probesun_load(probe, yaw, QTOOL_PROBESUN_MAX_PARTS, &ps, err, errlen) != 0)
        return -1;
    qibl_shlight_t sky;
    int rc = qtool_probesun_check(&s->a, in, &ps, err, errlen);
    if (rc == 0 && qtool_probesun_sh(ps.sky, ps.w, ps.h, s->m.k, &sky, NULL) != 0)
        rc = qtool_errf(err, errlen, "%s: the sky's SH failed (out of memory)", probe);
    if (rc == 0)
        rc = qtool_probesun_relight(s->bytes, s->n, &sky, ps.src, ps.nsrc, ps.parts, ps.part_src, ps.nparts, rgb8, ms,
                                    err, errlen);
    if (rc == 0 && note) {
        note->nsrc = ps.nsrc, note->nparts = ps.nparts, note->scale = ps.scale;
        note->share = ps.nsrc ? ps.src[0].share : 0;
    }
    qtool_probesun_free(&ps);
    return rc;
}
