/*
 * cmd_sh.c - `qibl sh eval`: the core's integer SH basis, printed as decimals.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/png.h"
#include "cli/cli.h"
#include "opt/opt.h"
#include "qibl/sh.h"

#define M_PI_VALUE 3.14159265358979323846

/* `qibl sh plot --png FILE [--tile W]`: every basis function as a lat-long tile (theta down,
 * phi across), orange positive, blue negative, arranged as the usual band pyramid. */
typedef struct plot_opts {
    const char *png;
    long tile;
} plot_opts;
static const plot_opts plot_defaults = {.png = NULL, .tile = 128};

static const qtool_opt plot_table[] = {
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = offsetof(plot_opts, png), .arg = "FILE", .required = 1,
     .help = "the picture to write"},
    {.name = "--tile", .kind = QTOOL_OPT_INT, .off = offsetof(plot_opts, tile), .arg = "W", .lo = 8, .hi = 1024,
     .what = "a tile width", .help = "each basis function's tile width in pixels"},
    {0},
};

static const qtool_opt_cmd plot_spec = {
    .name = "sh plot",
    QTOOL_OPT_TABLE(plot_table, plot_defaults),
    .prose = "  Writes a PNG of every basis function as a lat-long tile (orange > 0, blue < 0), evaluated by\n"
             "  the integer core.\n",
};

static int plot_run(void *opts)
{
    const plot_opts *o = opts;
    const char *path = o->png;
    long tw = o->tile;
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

const qcli_sub qcli_sub_sh_plot = {.opts = &plot_spec, .run = plot_run};

typedef struct eval_opts {
    qtool_opt_list xyz;
    long bands;
} eval_opts;
static const eval_opts eval_defaults = {.bands = QIBL_SH_MAX_BANDS};

static const qtool_opt eval_table[] = {
    {.name = "--bands", .kind = QTOOL_OPT_INT, .off = offsetof(eval_opts, bands), .arg = "B", .lo = 1,
     .hi = QIBL_SH_MAX_BANDS, .help = "bands 0..B-1: B*B values"},
    {0},
};

static const qtool_opt_cmd eval_spec = {
    .name = "sh eval",
    QTOOL_OPT_TABLE(eval_table, eval_defaults),
    .pos = {.names = "X Y Z", .min = 3, .max = 3, .off = offsetof(eval_opts, xyz), .numbers = 1},
    .prose =
        "  Prints the B*B real SH basis values Y_0 .. Y_{B*B-1} (bands 0..B-1),\n"
        "  one per line as `Y[i] l=L m=M value` (value as %.9f), at the direction (X, Y, Z).\n"
        "  X, Y, Z are decimals converted to Q16.16; the vector need not be unit length but must not\n"
        "  be zero. The values are the core's Q2.30 integers divided by 2^30. Convention: Wong et al.\n"
        "  appendix, index i = l*l + l + m, Condon-Shortley phase (Y_3 = -0.488603 at (1, 0, 0)).\n",
};

static int eval_run(void *opts)
{
    const eval_opts *o = opts;
    long bands = o->bands;
    qibl_q16_t dir[3];
    for (int k = 0; k < 3; ++k)
        if (qcli_parse_q16(o->xyz.v[k], &dir[k]) != 0)
            return qtool_opt_error(&eval_spec, "'%s' is not a number in the Q16.16 range [-32768, 32768)",
                                  o->xyz.v[k]);
    qibl_q30_t y[QIBL_SH_MAX_COUNT];
    qibl_status_t st = qibl_sh_eval(dir, (int)bands, y);
    if (st != QIBL_OK)
        return qtool_opt_error(&eval_spec, "%s", qibl_status_str(st));
    /* one line per basis function, labelled: index i = l*l + l + m, band l, order m */
    for (int l = 0; l < (int)bands; ++l)
        for (int m = -l; m <= l; ++m)
            printf("Y[%2d] l=%d m=%+d %12.9f\n", l * l + l + m, l, m, (double)y[l * l + l + m] / 1073741824.0);
    return 0;
}

/* it reads nothing and prints a few numbers: fuzz_cliopts runs it whole */
const qcli_sub qcli_sub_sh_eval = {.opts = &eval_spec, .run = eval_run, .whole = 1};
