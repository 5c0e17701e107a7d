/*
 * bake/check.c - `qibl check`'s work (bake/job.h): a file decoded in full by the reader of its kind
 * (PNG/APNG, PFM, OpenEXR, Radiance HDR by name or magic, else a qibl asset opened by the core).
 */
#include <stdlib.h>
#include <string.h>

#include "bake/job.h"
#include "io/asset_write.h"
#include "io/exr.h"
#include "io/file.h"
#include "io/hdr.h"
#include "io/pfm.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "qtool.h"

static int has_ext(const char *ext, const char *want)
{
    return ext && strcmp(ext, want) == 0;
}

int qtool_bake_check_file(const char *p, char *line, size_t linelen, char *err, size_t errlen)
{
    const char *ext = strrchr(p, '.');
    int w, h;
    float *px;
    if (has_ext(ext, ".png")) {
        int fr;
        uint8_t *rgb;
        if (qtool_png_read_rgb8(p, &w, &h, &fr, &rgb, err, errlen) != 0)
            return -1;
        free(rgb);
        snprintf(line, linelen, "PNG %dx%d, %d frame%s, CRCs, zlib and Adler-32 good", w, h, fr, fr == 1 ? "" : "s");
    } else if (has_ext(ext, ".pfm")) {
        int ch;
        if (qtool_pfm_read(p, &w, &h, &ch, &px, err, errlen) != 0)
            return -1;
        free(px);
        snprintf(line, linelen, "PFM %dx%d, %d channel%s", w, h, ch, ch == 1 ? "" : "s");
    } else if (has_ext(ext, ".exr") || qtool_exr_sniff(p)) {
        qtool_exr_info in;
        if (qtool_exr_read(p, &in, &px, err, errlen) != 0)
            return -1;
        free(px);
        snprintf(line, linelen, "OpenEXR %dx%d (data window), %s, compression %d, every chunk decoded", in.w, in.h,
                 in.tiled ? "tiled" : "scanline", in.compression);
    } else if (has_ext(ext, ".hdr") || has_ext(ext, ".pic")) {
        /* the Radiance probes lights reads: header, resolution line and every scanline decoded */
        if (qtool_hdr_read(p, &w, &h, &px, err, errlen) != 0)
            return -1;
        double mx = 0;
        for (size_t j = 0; j < (size_t)w * (size_t)h * 3; ++j)
            mx = px[j] > mx ? px[j] : mx;
        free(px);
        snprintf(line, linelen, "Radiance HDR %dx%d, every scanline decoded, largest channel %.6g", w, h, mx);
    } else {
        size_t n;
        uint8_t *b = NULL;
        if (qtool_io_read_asset(p, &b, &n, err, errlen) != 0)
            return -1;
        qibl_asset_t a;
        qibl_status_t st = qtool_asset_open(&a, b, n);
        free(b);
        if (st != QIBL_OK)
            return qtool_errf(err, errlen, "%s: %s", p, qibl_status_str(st));
        snprintf(line, linelen, "qibl asset, %u chunks, all CRCs good", a.chunk_count);
    }
    return 0;
}
