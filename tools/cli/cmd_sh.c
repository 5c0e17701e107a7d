/*
 * cmd_sh.c - `qibl sh eval`: the core's integer SH basis, printed as decimals.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/png.h"
#include "cli/cli.h"
#include "qibl/sh.h"

#define M_PI_VALUE 3.14159265358979323846

/* `qibl sh plot --png FILE [--tile W]`: every basis function as a lat-long tile (theta down,
 * phi across), orange positive, blue negative, arranged as the usual band pyramid. */
static int sh_plot(int argc, char **argv)
{
    const char *path = NULL;
    long tw = 128;
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--png") == 0 && i + 1 < argc)
            path = argv[++i];
        else if (strcmp(argv[i], "--tile") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 8, 1024, &tw) != 0)
                return qcli_usage_error("--tile needs an even width in 8..1024");
        } else
            return qcli_usage_error("usage: qibl sh plot --png FILE [--tile W]");
    }
    if (!path)
        return qcli_usage_error("usage: qibl sh plot --png FILE [--tile W]");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    const int B = QIBL_SH_MAX_BANDS, th = (int)tw / 2, pad = 4;
    const int W = (2 * B - 1) * ((int)tw + pad) + pad, H = B * (th + pad) + pad;
    uint8_t *img = calloc((size_t)W * (size_t)H, 3);
    if (!img)
        return fprintf(stderr, "qibl: sh plot: out of memory\n"), 1;
    for (int ty = 0; ty < th; ++ty)
        for (int tx = 0; tx < (int)tw; ++tx) {
            double t = (ty + 0.5) * M_PI_VALUE / th, p = (tx + 0.5) * 2.0 * M_PI_VALUE / (double)tw;
            qibl_q16_t d[3] = {(int32_t)lrint(sin(t) * cos(p) * 1073741824.0),
                               (int32_t)lrint(sin(t) * sin(p) * 1073741824.0),
                               (int32_t)lrint(cos(t) * 1073741824.0)};
            qibl_q30_t y[QIBL_SH_MAX_COUNT];
            if (qibl_sh_eval(d, B, y) != QIBL_OK)
                continue;
            for (int l = 0; l < B; ++l)
                for (int m = -l; m <= l; ++m) {
                    double v = y[l * l + l + m] / 1073741824.0 / 0.9; /* max |Y| for l <= 4 is 0.85 */
                    double a = fmin(1.0, fabs(v));
                    int col = (B - 1) + m, x0 = pad + col * ((int)tw + pad), y0 = pad + l * (th + pad);
                    uint8_t *px = img + 3 * ((size_t)(y0 + ty) * (size_t)W + (size_t)(x0 + tx));
                    px[0] = (uint8_t)lrint(v > 0 ? 255 * a : 50 * a);
                    px[1] = (uint8_t)lrint(v > 0 ? 150 * a : 140 * a);
                    px[2] = (uint8_t)lrint(v > 0 ? 30 * a : 255 * a);
                }
        }
    char err[512];
    int rc = qtool_png_write_rgb8(path, W, H, img, err, sizeof err);
    free(img);
    if (rc != 0)
        return fprintf(stderr, "qibl: %s\n", err), 1;
    printf("wrote %s (%dx%d): Y(l,m) for l = 0..%d, m = -l..l left to right\n", path, W, H, B - 1);
    return 0;
}

int qcli_cmd_sh(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "plot") == 0)
        return sh_plot(argc, argv);
    if (argc >= 2 && strcmp(argv[1], "project") == 0)
        return qcli_cmd_sh_project(argc, argv); /* cmd_probe.c */
    if (argc < 2 || strcmp(argv[1], "eval") != 0)
        return qcli_usage_error("usage: qibl sh eval [--bands B] X Y Z | qibl sh plot --png FILE");
    long bands = QIBL_SH_MAX_BANDS;
    const char *xyz[3];
    int n = 0;
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--bands") == 0) {
            if (i + 1 >= argc || qcli_parse_int(argv[i + 1], 1, QIBL_SH_MAX_BANDS, &bands) != 0)
                return qcli_usage_error("--bands needs an integer in 1..%d", QIBL_SH_MAX_BANDS);
            ++i;
        } else if (n < 3) {
            xyz[n++] = argv[i];
        } else {
            return qcli_usage_error("sh eval takes exactly three coordinates X Y Z");
        }
    }
    if (n != 3)
        return qcli_usage_error("sh eval takes exactly three coordinates X Y Z");
    qibl_q16_t dir[3];
    for (int k = 0; k < 3; ++k)
        if (qcli_parse_q16(xyz[k], &dir[k]) != 0)
            return qcli_usage_error("'%s' is not a number in the Q16.16 range [-32768, 32768)", xyz[k]);
    qibl_q30_t y[QIBL_SH_MAX_COUNT];
    qibl_status_t st = qibl_sh_eval(dir, (int)bands, y);
    if (st != QIBL_OK)
        return qcli_usage_error("sh eval: %s", qibl_status_str(st));
    /* one line per basis function, labelled: index i = l*l + l + m, band l, order m */
    for (int l = 0; l < (int)bands; ++l)
        for (int m = -l; m <= l; ++m)
            printf("Y[%2d] l=%d m=%+d %12.9f\n", l * l + l + m, l, m, (double)y[l * l + l + m] / 1073741824.0);
    return 0;
}
