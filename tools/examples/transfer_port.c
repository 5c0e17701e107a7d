/*
 * examples/transfer_port.c - precomputed radiance transfer at run time, as a game does it: load the
 * per-vertex transfer `qibl transfer MESH --probe P --export MESH.qtr` wrote, validate it once, and
 * per frame rotate the SH lighting (not the mesh) and shade every vertex: colour = transfer . light.
 * docs/porting.md walks through it.
 *
 * Links only the core (plus the C library for the parts marked PLATFORM). Integer only. Built by
 * `make examples` with the core's strictness.
 *
 * usage: transfer_port FILE.qtr [FRAMES]
 *   shades the export's vertices under a sky with a low sun whose lighting turns about the zenith
 *   in eighths of a turn, FRAMES frames (default 8), and prints per frame the CRC-32 of the vertex
 *   colours (Q16.16, little-endian) and their mean.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qibl.h"

/* ---- PLATFORM: however the platform gets bytes (file, ROM, archive); here stdio ------------- */
/* The header first: the size its count and bands imply (at most the largest valid export) is
 * checked before anything is allocated, then exactly that is read; the core validates the rest. */
static unsigned char *load_export(const char *path, size_t *size)
{
    unsigned char h[QIBL_HEMI_XFER_HEADER_SIZE], *p = NULL;
    FILE *f = fopen(path, "rb");
    *size = 0;
    if (f == NULL || fread(h, 1, sizeof h, f) != sizeof h) {
        if (f != NULL)
            fclose(f);
        return NULL;
    }
    const unsigned long count = (unsigned long)h[8] | (unsigned long)h[9] << 8 | (unsigned long)h[10] << 16 |
                                (unsigned long)h[11] << 24;
    const unsigned bands = (unsigned)h[6] | (unsigned)h[7] << 8;
    if (count >= 1 && count <= QIBL_HEMI_XFER_MAX_VERTICES && bands >= 3 && bands <= 5) {
        const size_t n = QIBL_HEMI_XFER_HEADER_SIZE + (size_t)count * bands * bands * 4u;
        p = malloc(n);
        if (p != NULL) {
            memcpy(p, h, sizeof h);
            if (fread(p + sizeof h, 1, n - sizeof h, f) == n - sizeof h && fgetc(f) == EOF)
                *size = n;
            else
                free(p), p = NULL; /* short, or longer than its fields say */
        }
    }
    fclose(f);
    return p;
}

/* The scene's light once, in the export's (world, z up) frame: a warm sun 30 degrees up plus a
 * dimmer blue sky from the zenith, as 25 Q16.16 radiance SH per channel. */
static qibl_status_t scene_light(qibl_shlight_t *l)
{
    static const qibl_q16_t sun_dir[3] = {56756, 0, 32768}, sun_rgb[3] = {98304, 81920, 65536};
    static const qibl_q16_t sky_dir[3] = {0, 0, 65536}, sky_rgb[3] = {9830, 13107, 19661};
    qibl_status_t st = qibl_shlight_init(l, QIBL_HEMI_COEFFS);
    if (st == QIBL_OK)
        st = qibl_shlight_add_dir(l, sun_dir, sun_rgb);
    if (st == QIBL_OK)
        st = qibl_shlight_add_dir(l, sky_dir, sky_rgb);
    return st;
}

/* The lighting turned by frame eighths of a turn about z: the rotation matrix from an exact octagon
 * (cos and sin of k * 45 degrees in Q2.30), then each channel rotated. */
static qibl_status_t turned_light(const qibl_shlight_t *l, int frame, int32_t out[3][QIBL_HEMI_COEFFS])
{
    static const qibl_q30_t c8[8] = {1073741824, 759250125, 0, -759250125, -1073741824, -759250125, 0, 759250125};
    const qibl_q30_t c = c8[frame % 8], s = c8[(frame + 6) % 8]; /* sin(a) = cos(a - 90 degrees) */
    const qibl_q30_t r[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1073741824}};
    qibl_sh_rotation_t rot;
    qibl_status_t st = qibl_sh_rotation_init(&rot, r, 5);
    for (int ch = 0; ch < 3 && st == QIBL_OK; ++ch)
        st = qibl_sh_rotate(&rot, l->c[ch], out[ch]);
    return st;
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: transfer_port FILE.qtr [FRAMES]\n");
        return 2;
    }
    const int frames = argc == 3 ? atoi(argv[2]) : 8;
    size_t n;
    unsigned char *bytes = load_export(argv[1], &n);
    if (bytes == NULL || frames < 1) {
        fprintf(stderr, "transfer_port: cannot read %s as a transfer export (or FRAMES < 1)\n", argv[1]);
        free(bytes);
        return 1;
    }
    /* once: validate the export (header, size, CRC) */
    qibl_hemi_xfer_t x;
    qibl_shlight_t sky;
    qibl_status_t st = qibl_hemi_xfer_open(&x, bytes, n);
    if (st == QIBL_OK)
        st = scene_light(&sky);
    if (st != QIBL_OK) {
        fprintf(stderr, "transfer_port: %s: %s\n", argv[1], qibl_status_str(st));
        free(bytes);
        return 1;
    }
    printf("%s: %u vertices, %u SH coefficients each\n", argv[1], (unsigned)x.count, (unsigned)x.ncoef);
    enum { SPAN = 64 }; /* vertices per call: a vertex buffer's chunk */
    for (int f = 0; f < frames && st == QIBL_OK; ++f) {
        int32_t light[3][QIBL_HEMI_COEFFS];
        st = turned_light(&sky, f, light); /* per frame: rotate the light, a few thousand operations */
        uint32_t crc = 0;
        int64_t sum = 0;
        for (uint32_t v = 0; v < x.count && st == QIBL_OK; v += SPAN) {
            qibl_q16_t rgb[SPAN][3];
            const uint32_t cnt = x.count - v < SPAN ? x.count - v : SPAN;
            st = qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[QIBL_HEMI_COEFFS])light, v, cnt, rgb);
            for (uint32_t k = 0; k < cnt && st == QIBL_OK; ++k)
                for (int ch = 0; ch < 3; ++ch) { /* PLATFORM: here the colours would go to the vertex buffer */
                    const uint32_t u = (uint32_t)rgb[k][ch];
                    const uint8_t le[4] = {(uint8_t)u, (uint8_t)(u >> 8), (uint8_t)(u >> 16), (uint8_t)(u >> 24)};
                    crc = qibl_crc32(crc, le, 4);
                    sum += rgb[k][ch];
                }
        }
        if (st == QIBL_OK)
            printf("frame %d: crc32 %08lx, mean %ld (Q16.16)\n", f, (unsigned long)crc,
                   (long)(sum / (3 * (int64_t)x.count)));
    }
    if (st != QIBL_OK)
        fprintf(stderr, "transfer_port: %s\n", qibl_status_str(st));
    free(bytes);
    return st == QIBL_OK ? 0 : 1;
}
