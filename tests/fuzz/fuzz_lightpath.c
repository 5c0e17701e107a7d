/*
 * fuzz_lightpath.c - libFuzzer target for the light-path chunk parser and its span functions
 * (core/src/lightpath.c: qibl_lightpath_parse, _visibility_span, _shade_span, _at).
 *
 * Input: bytes 0..3 a little-endian t (low 16 bits) and radius (high 16 bits, taken modulo 32768),
 * then an LPTH payload (layout in qibl/lightpath.h). Invariants checked (abort on violation): a
 * refused payload leaves the view untouched and gets a light-path status; an accepted one gives, for
 * every row, visibilities in 0..65536 (exactly 0 or 65536 for a hard light), shading that is 0 where
 * the visibility is 0 and the light where it is 65536, and key interpolation that succeeds.
 * The same bytes also go to the lamp-occlusion parser (LOCC, qibl_lightpath_occl_parse): refused
 * leaves the view untouched with a light-path status; accepted, every row's scaled values keep their
 * sign and never grow in magnitude. And to the tiled-maps parser (SHMT, qibl_shmtile_parse): refused
 * leaves the view untouched with an asset status; accepted, every tile's view reads only its bytes
 * (ASan checks the reads) and has a k in 1..kmax and the tile's size.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/lightpath.h"
#include "qibl/shmtile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 4)
        return 0;
    uint32_t t = (uint32_t)data[0] | (uint32_t)data[1] << 8, radius = ((uint32_t)data[2] | (uint32_t)data[3] << 8) & 32767u;
    {
        qibl_lampocc_t o, ou;
        memset(&o, 0x5A, sizeof o);
        memcpy(&ou, &o, sizeof o);
        qibl_status_t so = qibl_lightpath_occl_parse(data + 4, size - 4, &o);
        if (so != QIBL_OK && (memcmp(&o, &ou, sizeof o) != 0 || so < QIBL_E_LIGHTPATH_SIZE || so > QIBL_E_LIGHTPATH_EDGES))
            abort();
        for (uint32_t y = 0; so == QIBL_OK && y < o.height && y < 64u; ++y) {
            uint32_t n = o.width < 256u ? o.width : 256u;
            int32_t io[768], ref[768];
            for (uint32_t i = 0; i < 3u * n; ++i)
                io[i] = ref[i] = (int32_t)((i * 2654435761u ^ t) >> 1) - (int32_t)(i & 1u ? 0x7FFFFFFF : 0);
            if (qibl_lightpath_occl_span(&o, o.width - n, y, n, io) != QIBL_OK)
                abort();
            for (uint32_t i = 0; i < 3u * n; ++i)
                if ((ref[i] >= 0 ? io[i] < 0 || io[i] > ref[i] : io[i] > 0 || io[i] < ref[i]))
                    abort();
        }
    }
    {
        qibl_shmtile_t tl, tu;
        memset(&tl, 0x5A, sizeof tl);
        memcpy(&tu, &tl, sizeof tl);
        qibl_status_t s2 = qibl_shmtile_parse(data + 4, size - 4, &tl);
        if (s2 != QIBL_OK && (memcmp(&tl, &tu, sizeof tl) != 0 || s2 < QIBL_E_ASSET_TRUNCATED_HEADER ||
                              s2 > QIBL_E_ASSET_MISMATCH))
            abort();
        volatile uint32_t sink = 0;
        for (uint32_t j = 0; s2 == QIBL_OK && j < tl.tiles_y && j < 16u; ++j)
            for (uint32_t i = 0; i < tl.tiles_x && i < 16u; ++i) {
                qibl_shmaps_t v;
                if (qibl_shmtile_view(&tl, i, j, &v, NULL, NULL) != QIBL_OK || v.k < 1u || v.k > tl.kmax ||
                    v.width < 1u || v.width > 16u || v.height < 1u || v.height > 16u)
                    abort();
                size_t nb = (size_t)v.k * v.channels * v.width * v.height;
                sink += v.planes[0] + v.planes[nb - 1u] + v.params[8u * v.k * v.channels - 1u];
            }
        (void)sink;
    }
    qibl_lightpath_t p, untouched;
    memset(&p, 0x5A, sizeof p);
    memcpy(&untouched, &p, sizeof p);
    qibl_status_t st = qibl_lightpath_parse(data + 4, size - 4, &p);
    if (st != QIBL_OK) {
        if (memcmp(&p, &untouched, sizeof p) != 0 || st < QIBL_E_LIGHTPATH_SIZE || st > QIBL_E_LIGHTPATH_EDGES)
            abort();
        return 0;
    }
    uint32_t w = p.width < 256u ? p.width : 256u;
    uint32_t vis[256];
    int32_t light[768], out[768];
    for (uint32_t i = 0; i < 3u * w; ++i)
        light[i] = (int32_t)(i * 2654435761u >> 1) - 0x20000000;
    for (uint32_t y = 0; y < p.height && y < 64u; ++y) {
        if (qibl_lightpath_visibility_span(&p, t, radius, p.width - w, y, w, vis) != QIBL_OK ||
            qibl_lightpath_shade_span(&p, t, radius, p.width - w, y, w, light, out, false) != QIBL_OK)
            abort();
        for (uint32_t i = 0; i < w; ++i) {
            if (vis[i] > 65536u || (radius == 0u && vis[i] != 0u && vis[i] != 65536u))
                abort();
            for (uint32_t c = 0; c < 3u; ++c) {
                int32_t o = out[3 * i + c], l = light[3 * i + c];
                if ((vis[i] == 0u && o != 0) || (vis[i] == 65536u && o != l))
                    abort();
            }
        }
    }
    qibl_q16_t v[3];
    if (qibl_lightpath_at(&p, t, v) != QIBL_OK)
        abort();
    return 0;
}
