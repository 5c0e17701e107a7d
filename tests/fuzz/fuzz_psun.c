/*
 * fuzz_psun.c - libFuzzer target for the PSUN chunk reader (tools/bake/probesun.c,
 * qtool_probesun_check): the record of the probe a probe-lit asset was baked with, read back by
 * `qibl relight ASSET --probe P` before it trusts the asset's light paths.
 *
 * Input: byte 0 chooses the probe the check compares with (its id, size, yaw and counts from the
 * PSUN header itself, or from fixed values), byte 1 how many LPTH chunks to add (0..3), the rest
 * is the PSUN payload, wrapped into a valid asset (a 1 x 1 k = 1 SHMP) by the tools' writer.
 * Invariants (abort on violation): the check returns 0, 1 or -1; -1 leaves a non-empty one-line
 * message; a payload shorter than its fixed header is never accepted; ASan checks every read.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bake/probesun.h"
#include "io/asset_write.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static uint32_t u32le(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    const uint8_t mode = data[0], nlp = (uint8_t)(data[1] % 4u);
    const uint8_t *pl = data + 2;
    const size_t n = size - 2;
    qtool_asset_builder b;
    qtool_asset_builder_init(&b);
    const int32_t scale[3] = {1 << 24, 1 << 24, 1 << 24}, bias[3] = {0, 0, 0};
    const uint8_t planes[3] = {1, 2, 3};
    uint8_t *bytes = NULL;
    size_t nb = 0;
    if (qtool_asset_add_shmp(&b, 1, 1, 1, 3, scale, bias, planes) != 0 ||
        qtool_asset_builder_add(&b, QTOOL_PROBESUN_CHUNK, n ? pl : NULL, n) != 0)
        goto done;
    for (uint8_t i = 0; i < nlp; ++i)
        if (qtool_asset_builder_add(&b, QIBL_CHUNK_LPTH, "path", 4) != 0)
            goto done;
    if (qtool_asset_serialize(&b, &bytes, &nb) != 0)
        goto done;
    qibl_asset_t a;
    if (qibl_asset_open(&a, bytes, nb) != QIBL_OK)
        goto done; /* the writer's asset always opens: a LPTH of 4 bytes is not checked by open */
    qtool_probesun *ps = calloc(1, sizeof *ps);
    if (!ps)
        goto done;
    if ((mode & 1) && n >= 36) { /* the probe the chunk names: the deep checks are reached */
        ps->id = u32le(pl + 4), ps->w = u32le(pl + 8), ps->h = u32le(pl + 12);
        memcpy(&ps->yaw, pl + 16, sizeof ps->yaw);
        ps->kparts = (int)(u32le(pl + 24) & 0xFF), ps->nsrc = (int)(u32le(pl + 28) & 0xFF),
        ps->nparts = (int)(u32le(pl + 32) & 0xFF);
    } else {
        ps->id = 0x12345678u, ps->w = 64, ps->h = 32, ps->yaw = 0.0, ps->kparts = 1, ps->nsrc = 1, ps->nparts = 1;
    }
    strcpy(ps->name, "fuzz.hdr");
    char err[512];
    err[0] = 0;
    const int rc = qtool_probesun_check(&a, "fuzz.qibl", ps, err, sizeof err);
    if (rc != 0 && rc != 1 && rc != -1)
        abort();
    if (rc == -1 && (err[0] == 0 || strchr(err, '\n')))
        abort();
    if (rc == 0 && n < 36)
        abort();
    free(ps);
done:
    free(bytes);
    qtool_asset_builder_free(&b);
    return 0;
}
