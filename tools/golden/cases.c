/*
 * golden/cases.c - the list of golden groups and the helpers of golden/casesi.h.
 */
#include "golden/casesi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/config.h"
#include "qibl/status.h"

/* Groups of modules that config.h compiles out are left out (a reduced port still runs the rest). */
const qtool_goldens_group_t qtool_goldens_groups[] = {
    {"fixed", "fixed-point primitives: sqrt, rsqrt, reciprocal, division, normalisation sweeps", qtool_goldens_fixed},
#if QIBL_USE_SH
    {"sh", "SH basis bands 0..4: lattice, random and hard-case directions, unit and band-count paths", qtool_goldens_sh},
#endif
#if QIBL_USE_SRGBE
    {"srgbe", "sRGBE: encode of binary32/int32 edge cases and random patterns, decode of a code sweep", qtool_goldens_srgbe},
#endif
#if QIBL_USE_ASSET
    {"asset", "asset container: status and parsed fields of valid, damaged and truncated assets", qtool_goldens_asset},
#endif
#if QIBL_USE_SHMAP
    {"relight", "shmap: directional and point-light relighting into every framebuffer format", qtool_goldens_relight},
#endif
#if QIBL_USE_LIGHTPATH
    {"lightpath", "light paths: visibility spans, key interpolation, damaged payloads, sun (+ sky) x visibility",
     qtool_goldens_lightpath},
#endif
#if QIBL_USE_GONIO
    {"gonio", "goniometric lamps: table lookups in several frames, refusals, P-map spans scaled per pixel",
     qtool_goldens_gonio},
#endif
    {"soft", "platform/soft: a gradient in every framebuffer format, accumulation and resolve", qtool_goldens_soft},
    {"raster", "platform/soft raster: z-buffered Gouraud triangles (shared edges, guard band, culling, slivers)",
     qtool_goldens_raster},
#if QIBL_USE_PROBE
    {"probe", "probe SH projection (formats, sizes, rows in any order, irradiance, windows, bad pixels) and SH rotation", qtool_goldens_probe},
#endif
#if QIBL_USE_HEMI
    {"hemi", "hemispherical rasterization: LUT and basis tables, triangle masks, transfer vectors, frames", qtool_goldens_hemi},
#endif
#if QIBL_USE_LIGHTPROBE && QIBL_USE_SRGBE
    {"lightprobe", "light lists: median cut, adaptive, variance minimisation on integer-made probes", qtool_goldens_lightprobe},
#endif
};
const size_t qtool_goldens_group_count = sizeof qtool_goldens_groups / sizeof qtool_goldens_groups[0];

int qtool_goldens_run(const char *name, const qtool_goldens_sink_t *s)
{
    for (size_t i = 0; i < qtool_goldens_group_count; ++i)
        if (strcmp(qtool_goldens_groups[i].name, name) == 0)
            return qtool_goldens_groups[i].run(s);
    return -1;
}

/* ---- output bytes, hashed as produced --------------------------------------------------------- */

void qtool_gbuf_bytes(qtool_gbuf *b, const void *data, size_t n)
{
    if (!b->started) {
        qtool_sha256_init(&b->sha);
        b->started = 1;
    }
    qtool_sha256_update(&b->sha, data, n);
    b->n += n;
}

void qtool_gbuf_u8(qtool_gbuf *b, uint32_t v)
{
    uint8_t c = (uint8_t)v;
    qtool_gbuf_bytes(b, &c, 1);
}

void qtool_gbuf_u16(qtool_gbuf *b, uint32_t v)
{
    uint8_t c[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
    qtool_gbuf_bytes(b, c, 2);
}

void qtool_gbuf_u32(qtool_gbuf *b, uint32_t v)
{
    uint8_t c[4];
    qtool_gput_u32(c, v);
    qtool_gbuf_bytes(b, c, 4);
}

void qtool_gbuf_s32(qtool_gbuf *b, int32_t v)
{
    qtool_gbuf_u32(b, (uint32_t)v);
}

void qtool_gbuf_u64(qtool_gbuf *b, uint64_t v)
{
    qtool_gbuf_u32(b, (uint32_t)v);
    qtool_gbuf_u32(b, (uint32_t)(v >> 32));
}

void qtool_gbuf_free(qtool_gbuf *b)
{
    b->n = 0, b->started = 0;
}

int qtool_gbuf_emit(const qtool_goldens_sink_t *s, const char *name, qtool_gbuf *b)
{
    uint8_t d[32];
    char hex[65];
    if (!b->started)
        qtool_sha256_init(&b->sha);
    qtool_sha256_final(&b->sha, d);
    qtool_sha256_to_hex(d, hex);
    uint64_t n = b->n;
    qtool_gbuf_free(b);
    return s->emit(s->user, name, hex, n) != 0;
}

int qtool_gcase_emit(const qtool_goldens_sink_t *s, const char *name, const void *data, size_t n)
{
    static const uint8_t none = 0;
    char hex[65];
    qtool_sha256_hex(data ? data : &none, n, hex);
    return s->emit(s->user, name, hex, n) != 0;
}

int qtool_gcase_status_error(const qtool_goldens_sink_t *s, const char *name, const char *call, qibl_status_t st)
{
    char what[200];
    snprintf(what, sizeof what, "%s returned %d (%s)", call, (int)st, qibl_status_str(st));
    s->error(s->user, name, what);
    return 1;
}

void qtool_gcase_fb_set(qibl_fb_desc_t *fb, const qtool_gcase_fb *c)
{
    fb->format = c->format, fb->srgb = c->srgb, fb->dither = c->dither, fb->exposure = c->exposure;
}

int qtool_gcase_oom(const qtool_goldens_sink_t *s, const char *name)
{
    s->error(s->user, name, "out of memory");
    return 1;
}

#if QIBL_USE_SHMAP
qibl_status_t qtool_gcase_dir_lights(qibl_shlight_t *l, uint32_t k, uint32_t n, const qibl_q16_t (*dir)[3],
                                     const qibl_q16_t (*rgb)[3])
{
    qibl_status_t st = qibl_shlight_init(l, k);
    for (uint32_t i = 0; i < n && st == QIBL_OK; ++i)
        st = qibl_shlight_add_dir(l, dir[i], rgb[i]);
    return st;
}
#endif

int qtool_gcase_oom_size(const qtool_goldens_sink_t *s, const char *name, size_t bytes)
{
    char what[80];
    if (bytes == 0)
        snprintf(what, sizeof what, "out of memory: needs more bytes than size_t holds");
    else
        snprintf(what, sizeof what, "out of memory: needs %lu bytes", (unsigned long)bytes);
    s->error(s->user, name, what);
    return 1;
}

void qtool_gput_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

void qtool_gput_s32(uint8_t *p, int32_t v)
{
    qtool_gput_u32(p, (uint32_t)v);
}

int32_t qtool_gs32(uint32_t u)
{
    return u <= (uint32_t)INT32_MAX ? (int32_t)u : (int32_t)(u - 0x80000000u) - INT32_MAX - 1;
}

/* ---- PRNG ------------------------------------------------------------------------------------ */

uint64_t qtool_grng_next(qtool_grng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

uint32_t qtool_grng_u32(qtool_grng *r)
{
    return (uint32_t)(qtool_grng_next(r) >> 32);
}
