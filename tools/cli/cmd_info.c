/*
 * cmd_info.c - `qibl info FILE`: validate an asset with the core and print what it holds.
 */
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl/asset.h"
#include "io/asset_write.h"
#include "qibl/lightpath.h"
#include "io/file.h"
#include "cli/cli.h"
#include "opt/opt.h"

static const qtool_opt_cmd info_spec = {
    .name = "info",
    .pos = {.names = "FILE", .min = 1, .max = 1},
    QTOOL_OPT_TABLE(NULL, qtool_opt_args),
    .prose =
        "  Validates FILE with the core's qibl_asset_open (magic, version, chunk table, bounds, CRC-32s,\n"
        "  chunk fields) and prints the header, the chunk table (type, offset, size, CRC) and per known\n"
        "  chunk its fields: SHMP size, k, channels, per map and channel the Q8.24 scale and bias as\n"
        "  decimals and the min/max byte of the plane; PMAP size and the bounding box of its points;\n"
        "  YLUT face size and k. An invalid asset prints `qibl: FILE: <reason>` and exits 1.\n",
};

static const char *fourcc(uint32_t t, char s[16])
{
    char c[4] = {(char)(t & 0xFF), (char)(t >> 8 & 0xFF), (char)(t >> 16 & 0xFF), (char)(t >> 24)};
    for (int i = 0; i < 4; ++i)
        if (c[i] < 0x20 || c[i] > 0x7E) {
            snprintf(s, 16, "0x%08x", (unsigned)t);
            return s;
        }
    snprintf(s, 16, "%.4s", c);
    return s;
}

static void print_shmaps(const qibl_shmaps_t *m)
{
    printf("SHMP: %u x %u pixels, k %u maps, %u channel%s, %s layout (%zu bytes per row)\n", (unsigned)m->width,
           (unsigned)m->height, (unsigned)m->k, (unsigned)m->channels, m->channels == 1 ? "" : "s",
           m->layout == QIBL_SHMAPS_INTERLEAVED ? "interleaved" : "planar", qibl_shmaps_row_size(m));
    printf("  %3s %2s %16s %16s %4s %4s\n", "map", "ch", "scale", "bias", "min", "max");
    for (uint32_t i = 0; i < m->k; ++i)
        for (uint32_t ch = 0; ch < m->channels; ++ch) {
            unsigned lo = 255, hi = 0;
            for (uint32_t y = 0; y < m->height; ++y)
                for (uint32_t x = 0; x < m->width; ++x) {
                    unsigned v = qibl_shmaps_texel(m, i, ch, x, y);
                    lo = v < lo ? v : lo;
                    hi = v > hi ? v : hi;
                }
            printf("  %3u %2u %16.9f %16.9f %4u %4u\n", (unsigned)i, (unsigned)ch,
                   (double)qibl_shmaps_scale(m, i, ch) / 16777216.0,
                   (double)qibl_shmaps_bias(m, i, ch) / 16777216.0, lo, hi);
        }
}

static void print_pmap(const qibl_pmap_t *p)
{
    int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (uint32_t y = 0; y < p->height; ++y)
        for (uint32_t x = 0; x < p->width; ++x) {
            qibl_q16_t v[3];
            qibl_pmap_point(p, x, y, v);
            for (int c = 0; c < 3; ++c) {
                lo[c] = v[c] < lo[c] ? v[c] : lo[c];
                hi[c] = v[c] > hi[c] ? v[c] : hi[c];
            }
        }
    printf("PMAP: %u x %u points (Q16.16), bounding box\n", (unsigned)p->width, (unsigned)p->height);
    for (int c = 0; c < 3; ++c)
        printf("  %c [%.5f, %.5f]\n", "xyz"[c], lo[c] / 65536.0, hi[c] / 65536.0);
}

static int info_run(void *opts)
{
    const char *path = ((const qtool_opt_list *)opts)->v[0];
    size_t n = 0;
    uint8_t *buf = NULL;
    char err[512];
    if (qtool_io_read_asset(path, &buf, &n, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    qibl_asset_t a;
    qibl_status_t st = qtool_asset_open(&a, buf, n);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: %s\n", path, qibl_status_str(st));
        free(buf);
        return 1;
    }
    printf("%s: qibl asset version %u, %u bytes", path, (unsigned)qibl_load_u32le(buf + 8), (unsigned)a.size);
    if (n > a.size)
        printf(" (+%zu trailing bytes ignored)", n - a.size);
    printf(", %u chunk%s, table crc 0x%08x\n", (unsigned)a.chunk_count, a.chunk_count == 1 ? "" : "s",
           (unsigned)qibl_load_u32le(buf + 20));
    printf("  %2s %-10s %10s %10s %10s\n", "#", "type", "offset", "size", "crc");
    for (uint32_t i = 0; i < a.chunk_count; ++i) {
        const uint8_t *e = buf + QIBL_ASSET_HEADER_SIZE + QIBL_ASSET_ENTRY_SIZE * i;
        char t[16];
        printf("  %2u %-10s %10u %10u 0x%08x\n", (unsigned)i, fourcc(qibl_load_u32le(e), t),
               (unsigned)qibl_load_u32le(e + 4), (unsigned)qibl_load_u32le(e + 8), (unsigned)qibl_load_u32le(e + 12));
    }
    qibl_shmaps_t m;
    if (qibl_asset_shmaps(&a, &m) == QIBL_OK)
        print_shmaps(&m);
    qibl_pmap_t p;
    if (qibl_asset_pmap(&a, &p) == QIBL_OK)
        print_pmap(&p);
    qibl_ylut_t y;
    if (qibl_asset_ylut(&a, &y) == QIBL_OK)
        printf("YLUT: face size N %u (6 faces of %u x %u texels), k %u values per texel (Q2.14)\n",
               (unsigned)y.face_size, (unsigned)y.face_size, (unsigned)y.face_size, (unsigned)y.k);
    if (qibl_asset_shmaps_unshadowed(&a, &m) == QIBL_OK)
        printf("SHMU: unshadowed transfer, %u x %u pixels, k %u maps, %u channel%s (free point lights use it)\n",
               (unsigned)m.width, (unsigned)m.height, (unsigned)m.k, (unsigned)m.channels, m.channels == 1 ? "" : "s");
    for (uint32_t i = 0; i < qibl_lightpath_count(&a); ++i) {
        qibl_lightpath_t lp;
        qibl_status_t ps = qibl_lightpath_from_asset(&a, i, &lp);
        if (ps != QIBL_OK)
            printf("LPTH %u: not usable: %s\n", (unsigned)i, qibl_status_str(ps));
        else
            printf("LPTH %u: %s, %u keys, %u visibility edges (%.2f per pixel)\n", (unsigned)i,
                   lp.kind == QIBL_LIGHTPATH_DIRECTIONS ? "sun path (directions)" : "lamp track (positions)",
                   (unsigned)lp.nkeys, (unsigned)lp.nedges, (double)lp.nedges / ((double)lp.width * lp.height));
    }
    qibl_chunk_t lc;
    if (qibl_asset_find_nth(&a, QIBL_CHUNK_LOCC, 0, &lc) == QIBL_OK) {
        qibl_lampocc_t occ;
        qibl_status_t os = qibl_lightpath_occl_from_asset(&a, &occ);
        if (os != QIBL_OK)
            printf("LOCC: not usable: %s (relight draws lamps without it)\n", qibl_status_str(os));
        else
            printf("LOCC: lamp occlusion, %u x %u pixels (free lamps through SHMU are scaled by it)\n",
                   (unsigned)occ.width, (unsigned)occ.height);
    }
    free(buf);
    return 0;
}

const qcli_sub qcli_sub_info = {.opts = &info_spec, .run = info_run};
