/*
 * cmd_ies.c - `qibl ies info FILE [--png OUT]`: an IES LM-63 file's header facts, its candela range
 * and the luminous flux integrated from the distribution (io/ies.h: qtool_ies_lumens), and the
 * polar curves of its two principal planes as a labelled PNG.
 *
 * Output is all or nothing: the file is read and checked, the picture written (atomically), and only
 * then is the report printed; a refused file prints one line on stderr and nothing on stdout.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "io/ies.h"
#include "io/png.h"
#include "io/text.h"

#define PI_ 3.14159265358979323846
#define PNG_SIZE 512

static void plot(uint8_t *img, int w, int h, int x, int y, const uint8_t c[3])
{
    if (x < 0 || y < 0 || x >= w || y >= h)
        return;
    memcpy(img + 3 * ((size_t)y * (size_t)w + (size_t)x), c, 3);
}

static void line(uint8_t *img, int w, int h, double x0, double y0, double x1, double y1, const uint8_t c[3])
{
    double dx = x1 - x0, dy = y1 - y0;
    int n = (int)ceil(fmax(fabs(dx), fabs(dy))) + 1;
    for (int i = 0; i <= n; ++i) {
        double t = (double)i / n;
        int px = (int)lround(x0 + dx * t), py = (int)lround(y0 + dy * t);
        plot(img, w, h, px, py, c);
        plot(img, w, h, px + 1, py, c); /* two pixels wide: readable when scaled down */
    }
}

/* The polar diagram: centre of the image is the lamp, straight down the aim (type C nadir, type
 * A/B beam centre) drawn downwards; red the plane through the aim and the frame's y axis (type C:
 * C0 right, C180 left), blue the plane through the aim and x (C90 right, C270 left); radius
 * proportional to candela, full scale the file's maximum; rings at 25 % steps. */
static int draw_polar(const qtool_ies *e, const char *path, char *err, size_t errlen)
{
    const int W = PNG_SIZE, H = PNG_SIZE;
    uint8_t *img = malloc((size_t)W * H * 3);
    if (!img)
        return snprintf(err, errlen, "out of memory"), -1;
    memset(img, 255, (size_t)W * H * 3);
    const double cx = W / 2.0, cy = H / 2.0 + 8, R = W * 0.40;
    static const uint8_t grey[3] = {190, 190, 190}, black[3] = {0, 0, 0}, red[3] = {200, 30, 30},
                         blue[3] = {30, 60, 210};
    for (int k = 1; k <= 4; ++k) {
        double r = R * k / 4;
        for (int a = 0; a < 720; ++a)
            line(img, W, H, cx + r * cos(a * PI_ / 360), cy + r * sin(a * PI_ / 360), cx + r * cos((a + 1) * PI_ / 360),
                 cy + r * sin((a + 1) * PI_ / 360), grey);
        char lab[32];
        snprintf(lab, sizeof lab, "%.0f", e->cd_max * k / 4);
        qtool_text_draw(img, W, H, (int)(cx + 3), (int)(cy - r - 9), lab, 1, black);
    }
    for (int a = 0; a < 12; ++a)
        line(img, W, H, cx, cy, cx + R * sin(a * PI_ / 6), cy + R * cos(a * PI_ / 6), grey);
    double scale = e->cd_max > 0 ? R / e->cd_max : 0;
    for (int plane = 0; plane < 2; ++plane) {
        double px = 0, py = 0;
        for (int a = -360; a <= 360; ++a) {
            double t = a * PI_ / 360; /* from the aim, toward +y (plane 0) or +x (plane 1) on the right */
            double d[3] = {plane ? sin(t) : 0, plane ? 0 : sin(t), cos(t)};
            double r = qtool_ies_candela(e, d) * scale;
            double x = cx + r * sin(t), y = cy + r * cos(t);
            if (a > -360)
                line(img, W, H, px, py, x, y, plane ? blue : red);
            px = x, py = y;
        }
    }
    char title[96];
    snprintf(title, sizeof title, "%s CANDELA, MAX %.0f CD", e->type == QTOOL_IES_TYPE_C ? "TYPE C" :
             e->type == QTOOL_IES_TYPE_B ? "TYPE B" : "TYPE A", e->cd_max);
    qtool_text_draw(img, W, H, 8, 8, title, 2, black);
    qtool_text_draw(img, W, H, 8, 30, e->type == QTOOL_IES_TYPE_C ? "RED C0 (RIGHT) - C180" : "RED H0 PLANE, +V RIGHT",
                    1, red);
    qtool_text_draw(img, W, H, 8, 42, e->type == QTOOL_IES_TYPE_C ? "BLUE C90 (RIGHT) - C270" : "BLUE V0 PLANE, +H RIGHT",
                    1, blue);
    qtool_text_draw(img, W, H, 8, H - 14, "AIM (NADIR) DOWN, RINGS AT 25 % OF MAX", 1, black);
    int rc = qtool_png_write_rgb8(path, W, H, img, err, errlen);
    free(img);
    return rc;
}

typedef struct ies_opts {
    qtool_opt_list file;
    const char *png;
} ies_opts;
static const ies_opts ies_defaults = {.png = NULL};

static const qtool_opt ies_table[] = {
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = offsetof(ies_opts, png), .arg = "OUT.png",
     .help = "the polar curves of the two principal planes"},
    {0},
};

static const qtool_opt_cmd ies_info_spec = {
    QTOOL_OPT_CMD("ies info", ies_table, ies_defaults, "FILE.ies", 1, 1, ies_opts, file),
    .prose =
        "  Reads an IES LM-63 file (1986 unlabelled, 1991, 1995, 2002 or 2019 header; keywords with [MORE];\n"
        "  TILT=NONE or INCLUDE, TILT=<file> refused by name; photometric type C, B or A; every type C\n"
        "  symmetry: axial, quadrilateral 0..90, bilateral 0..180, 90..270, full 0..360) and prints its header\n"
        "  facts, candela_min/candela_max (multiplier applied) and the line `lumens <value>`: the candela\n"
        "  (times the ballast factor, and up to 1995 the ballast-lamp factor) integrated over the sphere.\n"
        "  Quadrature (the zonal-lumen method of photometric software): along the latitude-like angle\n"
        "  (C: vertical from the nadir; A: vertical, B: horizontal, from the equator) each zone between\n"
        "  two grid angles a, b counts its mean intensity (I_a + I_b) / 2 times cos a - cos b (C) or\n"
        "  sin b - sin a (A, B), nothing outside the vertical range; along the plane angle the trapezoid\n"
        "  rule over the grid expanded by its symmetry (axial 2 pi, quadrilateral 4 x, bilateral 2 x).\n"
        "  Isotropic (4 pi I) and cosine (pi I0) lamps come out exactly. A keyword stating the\n"
        "  luminaire flux ([LUMINAIREOUTPUT], [_ABSOLUTELUMENS]...) is printed beside it (stated_lumens).\n"
        "  --png OUT.png: the polar curves of the two principal planes (type C: C0-C180 red, C90-C270 blue),\n"
        "  nadir down, rings at 25 % of the maximum, labelled. Limits: io/ies.h (docs/robustness.md).\n",
};

static int ies_info_run(void *opts)
{
    const ies_opts *o = opts;
    const char *path = o->file.v[0], *png = o->png;
    qtool_ies e;
    char err[512];
    if (qtool_ies_read(path, &e, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: ies info: %s\n", err);
        return 1;
    }
    if (png && draw_polar(&e, png, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: ies info: %s\n", err);
        qtool_ies_free(&e);
        return 1;
    }
    double lm = qtool_ies_lumens(&e);
    printf("file %s\n", path);
    printf("format LM-63-%d%s\n", e.version, e.version == 1986 ? " (no label line)" : "");
    printf("keywords %u\n", e.nkeywords);
    if (e.test[0])
        printf("test %s\n", e.test);
    if (e.manufac[0])
        printf("manufacturer %s\n", e.manufac);
    if (e.luminaire[0])
        printf("luminaire %s\n", e.luminaire);
    if (e.lamp[0])
        printf("lamp %s\n", e.lamp);
    if (e.tilt == QTOOL_IES_TILT_INCLUDE)
        printf("tilt INCLUDE (%u angles, lamp-to-luminaire geometry %d; not applied)\n", e.ntilt, e.tilt_geometry);
    else
        printf("tilt NONE\n");
    printf("photometry type %c\n", e.type == QTOOL_IES_TYPE_C ? 'C' : e.type == QTOOL_IES_TYPE_B ? 'B' : 'A');
    printf("symmetry %s\n", qtool_ies_sym_name(e.sym));
    printf("vertical_angles %u (%g..%g)\n", e.nv, e.v[0], e.v[e.nv - 1]);
    printf("horizontal_angles %u (%g..%g)\n", e.nh, e.h[0], e.h[e.nh - 1]);
    printf("lamps %d\n", e.nlamps);
    if (e.lumens_per_lamp < 0)
        printf("lamp_lumens -1 (absolute photometry)\n");
    else if (e.lumens_per_lamp == 0)
        printf("lamp_lumens 0 (not stated)\n");
    else
        printf("lamp_lumens %g per lamp (relative photometry: rated lamp flux %g lm)\n", e.lumens_per_lamp,
               e.lumens_per_lamp * e.nlamps);
    printf("multiplier %g\n", e.multiplier);
    printf("ballast_factor %g\n", e.ballast_factor);
    printf("watts %g\n", e.watts);
    printf("opening %g x %g x %g %s\n", e.width, e.length, e.height, e.units == 1 ? "feet" : "metres");
    printf("candela_min %.6g\ncandela_max %.6g\n", e.cd_min, e.cd_max);
    printf("lumens %.2f\n", lm);
    if (e.stated_lumens > 0)
        printf("stated_lumens %g (keyword; integral %+.2f %%)\n", e.stated_lumens, 100 * (lm / e.stated_lumens - 1));
    if (e.lumens_per_lamp > 0)
        printf("efficiency %.1f %% of the rated lamp flux\n", 100 * lm / (e.lumens_per_lamp * e.nlamps));
    if (e.watts > 0)
        printf("efficacy %.1f lm/W\n", lm / e.watts);
    if (png)
        printf("png %s\n", png);
    qtool_ies_free(&e);
    return 0;
}

const qcli_sub qcli_sub_ies_info = {.opts = &ies_info_spec, .run = ies_info_run};
