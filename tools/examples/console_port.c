/*
 * examples/console_port.c - what a console or handheld port of qibl needs: load the asset bytes
 * however the platform does, validate them once, and per frame turn a light into weights and run
 * rows into the framebuffer. docs/porting.md walks through it.
 *
 * Links only the core and platform/soft (plus the C library for the parts marked PLATFORM, which a
 * port replaces with its own file loading and display). Built by `make examples`, run by CI on a
 * generated asset and cross-compiled by `make ports` for every configuration, so it cannot rot.
 *
 * usage: console_port ASSET [FRAMES] [OUT.ppm]
 *   relights ASSET under a sun that circles the sky for FRAMES frames (default 4) into an RGBA8888
 *   sRGB framebuffer, prints the CRC-32 of each frame, and writes the last one as a PPM if asked.
 */
#include <stdio.h>
#include <stdlib.h>

#include "qibl.h"
#include "qibl/soft.h"

/* ---- PLATFORM: however the platform gets bytes (file, ROM, archive); here stdio ------------- */
static unsigned char *load_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    unsigned char *p = NULL;
    long n;
    if (f != NULL && fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (p = malloc((size_t)n)) != NULL && fread(p, 1, (size_t)n, f) != (size_t)n) {
        free(p);
        p = NULL;
    }
    if (f != NULL)
        fclose(f);
    *size = p != NULL ? (size_t)n : 0;
    return p;
}

/* A sun on a circle around the zenith, 30 degrees up; integer only (an octagon of directions is
 * plenty for an example; a game passes its own light). */
static void sun_at_frame(int frame, qibl_q16_t dir[3])
{
    static const int32_t c[8] = {65536, 46341, 0, -46341, -65536, -46341, 0, 46341}; /* cos(k 45 deg) */
    dir[0] = c[frame % 8];
    dir[1] = c[(frame + 6) % 8]; /* sin = cos shifted by 90 degrees */
    dir[2] = 37837;              /* tan(30 deg) for a 30-degree elevation */
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 4) {
        fprintf(stderr, "usage: console_port ASSET [FRAMES] [OUT.ppm]\n");
        return 2;
    }
    /* ---- once, at start-up: this program was compiled with the library's config.h options and
     *      release (else its structs may not match the library's: QIBL_E_CONFIG_MISMATCH) -------- */
    qibl_status_t st = qibl_init_check();
    if (st != QIBL_OK) {
        fprintf(stderr, "console_port: qibl %s (config %08lx, ours %08lx): %s\n", qibl_version(),
                (unsigned long)qibl_config_id(), (unsigned long)QIBL_CONFIG_ID, qibl_status_str(st));
        return 1;
    }
    int frames = argc > 2 ? atoi(argv[2]) : 4;
    size_t size;
    unsigned char *bytes = load_file(argv[1], &size); /* PLATFORM */
    if (bytes == NULL) {
        fprintf(stderr, "console_port: cannot read %s\n", argv[1]);
        return 1;
    }

    /* ---- the port: validate once ------------------------------------------------------------ */
    qibl_asset_t asset;
    qibl_shmaps_t maps;
    st = qibl_asset_open(&asset, bytes, size);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&asset, &maps);
    if (st != QIBL_OK) {
        fprintf(stderr, "console_port: %s: %s\n", argv[1], qibl_soft_status_str(st));
        return 1;
    }
    /* memory the port owns: one row of Q16.16 RGB, the span workspace, the framebuffer */
    int32_t *row = malloc(sizeof(int32_t) * 3u * maps.width);
    size_t ws_size = qibl_shmap_span_workspace_size(maps.width);
    void *ws = malloc(ws_size);
    qibl_fb_desc_t fb = {0}; /* zero means default: RGBA8888, packed rows, exposure 1 */
    fb.width = maps.width, fb.height = maps.height, fb.srgb = 1;
    fb.pixels = malloc((size_t)maps.width * maps.height * 4u);
    if (row == NULL || ws == NULL || fb.pixels == NULL || qibl_soft_fb_check(&fb) != QIBL_OK) {
        fprintf(stderr, "console_port: out of memory\n");
        return 1;
    }

    for (int frame = 0; frame < frames; ++frame) {
        /* ---- per frame: light -> weights (a few hundred integer operations) ------------------ */
        qibl_q16_t sun[3], rgb[3] = {98304, 91750, 78643}; /* warm white, 1.5 x (1, 0.93, 0.8) */
        qibl_shlight_t light;
        qibl_shmap_weights_t w;
        sun_at_frame(frame, sun);
        st = qibl_shlight_init(&light, maps.k);
        if (st == QIBL_OK)
            st = qibl_shlight_add_dir(&light, sun, rgb);
        if (st == QIBL_OK)
            st = qibl_shmap_weights(&maps, &light, &w);
        /* ---- per row: relight into Q16.16, write into the framebuffer (any split of rows into
         *      spans, threads or frames gives the same bytes) ----------------------------------- */
        for (uint32_t y = 0; y < maps.height && st == QIBL_OK; ++y) {
            st = qibl_shmap_relight_span(&maps, &w, 0, y, maps.width, row, ws, ws_size);
            if (st == QIBL_OK)
                st = qibl_soft_fb_write_row(&fb, 0, y, maps.width, row);
        }
        if (st != QIBL_OK) {
            fprintf(stderr, "console_port: frame %d: %s\n", frame, qibl_soft_status_str(st));
            return 1;
        }
        /* PLATFORM: present the framebuffer; here its CRC-32 (the core's) stands in */
        printf("frame %d: sun (%ld, %ld, %ld)/65536, %ux%u RGBA8888 sRGB, crc32 %08lx\n", frame, (long)sun[0],
               (long)sun[1], (long)sun[2], (unsigned)maps.width, (unsigned)maps.height,
               (unsigned long)qibl_crc32(0, fb.pixels, (size_t)maps.width * maps.height * 4u));
    }

    if (argc > 3) { /* PLATFORM: a PPM of the last frame for looking at */
        FILE *f = fopen(argv[3], "wb");
        const unsigned char *px = fb.pixels;
        int ok = f != NULL && fprintf(f, "P6\n%u %u\n255\n", (unsigned)maps.width, (unsigned)maps.height) > 0;
        for (size_t i = 0; ok && i < (size_t)maps.width * maps.height; ++i)
            ok = fwrite(px + 4 * i, 1, 3, f) == 3;
        if (f == NULL || fclose(f) != 0 || !ok) {
            fprintf(stderr, "console_port: cannot write %s\n", argv[3]);
            return 1;
        }
    }
    free(row), free(ws), free(fb.pixels), free(bytes);
    return 0;
}
