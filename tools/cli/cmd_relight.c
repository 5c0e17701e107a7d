/*
 * cmd_relight.c - `qibl relight` (asset + light -> PNG through the core kernels and the software
 * framebuffer). `qibl gen` lives in cmd_gen.c.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "gen/scene.h"
#include "io/asset_write.h"
#include "io/exr.h"
#include "io/hdr_write.h"
#include "io/ies.h"
#include "io/pfm.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "cli/gles_cli.h"
#include "io/file.h"
#include "cli/cli.h"
#include "cli/relight_light.h"
#include "qibl/gonio.h"
#include "qibl/shmap.h"
#include "qibl/soft.h"

/* ---- qibl relight ------------------------------------------------------------------------------ */

#define RELIGHT_USAGE                                                                                       \
    "usage: qibl relight FILE [--sun X Y Z [--rgb R G B]]... [--point X Y Z [--rgb R G B]]... [--lights FILE.csv] \
[--probe PROBE.hdr [--layout L] [--probe-mode sh|lights|sunsky] [-n N] [--yaw DEG | --rotate a,b,c,d,e,f,g,h,i]] \
[--lut poly|nearest|bilinear|off] [--falloff 1|2] [--exposure E] [--linear] [--gles] \
[--ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]] (--png OUT | --hdr OUT.hdr | --pfm OUT.pfm | --exr OUT.exr)..."

/* the P map's points as doubles (n * 3), for the default lamp colour; NULL when out of memory */
static double *pmap_points(const qibl_pmap_t *pm)
{
    size_t np = (size_t)pm->width * pm->height;
    double *p = malloc(np * 3 * sizeof *p);
    for (uint32_t y = 0; p && y < pm->height; ++y)
        for (uint32_t x = 0; x < pm->width; ++x) {
            qibl_q16_t q[3];
            qibl_pmap_point(pm, x, y, q);
            for (int c = 0; c < 3; ++c)
                p[3 * ((size_t)y * pm->width + x) + (size_t)c] = q[c] / 65536.0;
        }
    return p;
}

/* "1 sun, 2 points, lights.csv, probe.hdr (SH)" for the messages */
static void describe(const qcli_light_list *ll, int lut_mode, char *buf, size_t n)
{
    size_t o = 0;
    buf[0] = '\0';
    if (ll->suns)
        o += (size_t)snprintf(buf + o, n - o, "%u sun%s", ll->suns, ll->suns == 1 ? "" : "s");
    if (ll->points && o < n)
        o += (size_t)snprintf(buf + o, n - o, "%s%u point%s (%s)", o ? ", " : "", ll->points,
                              ll->points == 1 ? "" : "s",
                              lut_mode == 2   ? "point/LUT nearest"
                              : lut_mode == 1 ? "point/LUT bilinear"
                              : lut_mode == 3 ? "point/poly"
                                              : "point/direct");
    if (ll->csv && o < n)
        o += (size_t)snprintf(buf + o, n - o, "%s%s", o ? ", " : "", ll->csv);
    if (ll->probe && o < n)
        snprintf(buf + o, n - o, "%sprobe %s (%s)", o ? ", " : "", ll->probe,
                 ll->mode == QCLI_PROBE_SH ? "SH" : ll->mode == QCLI_PROBE_LIGHTS ? "lights" : "sun plus sky");
}

int qcli_cmd_relight(int argc, char **argv)
{
    if (qcli_relight_has_path(argc, argv)) /* a light on a baked path: relight_path.c */
        return qcli_relight_path(argc, argv);
    const char *in = NULL, *png = NULL, *hdr = NULL, *pfm = NULL, *exr = NULL;
    /* poly: the default point mode (QIBL_POINT_POLY, the fastest); off: direct SH in Q2.30 */
    int use_lut = 0, nearest = 0, linear = 0, poly = 1, r;
    int gles = 0; /* --gles: platform/gles2 instead of the core + platform/soft (relight_gles.c) */
    long falloff = 1;
    qibl_q16_t exposure = 65536;
    /* --ies: goniometric lamps (qibl/gonio.h); aim and up in Q16.16, the table's size */
    const char *ies = NULL;
    int have_aim = 0, have_up = 0;
    int32_t aim[3] = {0, 0, -65536}, up[3] = {65536, 0, 0};
    long ies_n = 64;
    qcli_light_list ll; /* --sun, --point, --rgb, --lights, --probe and its options (relight_light.c) */
    qcli_light_list_init(&ll);
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if ((r = qcli_light_list_opt(argc, argv, &i, &ll)) != 0) {
            if (r != 1)
                return 2;
        } else if (strcmp(a, "--exposure") == 0 && i + 1 < argc) {
            double e;
            if (qcli_parse_num(a, argv[++i], 1.0 / 65536, QTOOL_CLI_Q16_MAX, "a positive Q16.16 factor", &e) != 0)
                return 2;
            exposure = (qibl_q16_t)nearbyint(e * 65536.0);
        } else if (strcmp(a, "--falloff") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 2, &falloff) != 0)
                return qcli_usage_error("--falloff is 1 (C0/|L|) or 2 (C0/|L|^2)");
        } else if (strcmp(a, "--lut") == 0) {
            /* --lut MODE; a bare --lut (the old on/off switch) is bilinear: the next word is then an
             * option or the asset, never a mode name, so the two spellings cannot be confused */
            const char *m = i + 1 < argc ? argv[i + 1] : "";
            if (strcmp(m, "nearest") == 0 || strcmp(m, "bilinear") == 0 || strcmp(m, "off") == 0 ||
                strcmp(m, "poly") == 0) {
                use_lut = m[0] == 'n' || m[0] == 'b', nearest = m[0] == 'n', poly = m[0] == 'p', ++i;
            } else if (m[0] != '-' && m[0] != '\0' && in) {
                return qcli_usage_error("--lut: '%s' is not a mode (poly, nearest, bilinear or off)", m);
            } else {
                use_lut = 1, nearest = 0, poly = 0;
                fprintf(stderr, "qibl: note: a bare --lut is deprecated; say --lut bilinear\n");
            }
        } else if (strcmp(a, "--nearest") == 0) {
            use_lut = 1, nearest = 1, poly = 0;
            fprintf(stderr, "qibl: note: --nearest is deprecated; say --lut nearest\n");
        } else if (strcmp(a, "--linear") == 0)
            linear = 1;
        else if (strcmp(a, "--png") == 0 && i + 1 < argc)
            png = argv[++i];
        else if (strcmp(a, "--hdr") == 0 && i + 1 < argc)
            hdr = argv[++i];
        else if (strcmp(a, "--pfm") == 0 && i + 1 < argc)
            pfm = argv[++i];
        else if (strcmp(a, "--exr") == 0 && i + 1 < argc)
            exr = argv[++i];
        else if (strcmp(a, "--gles") == 0)
            gles = 1;
        else if (strcmp(a, "--ies") == 0 && i + 1 < argc)
            ies = argv[++i];
        else if (strcmp(a, "--ies-size") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], QIBL_GONIO_MIN_N, QIBL_GONIO_MAX_N, &ies_n) != 0)
                return qcli_usage_error("--ies-size is a table size in %u..%u", QIBL_GONIO_MIN_N, QIBL_GONIO_MAX_N);
        } else if ((strcmp(a, "--aim") == 0 || strcmp(a, "--up") == 0) && i + 3 < argc) {
            int32_t *v = a[2] == 'a' ? aim : up;
            for (int k = 0; k < 3; ++k)
                if (qcli_parse_q16(argv[i + 1 + k], &v[k]) != 0)
                    return qcli_usage_error("%s: '%s' is not a number in the Q16.16 range", a, argv[i + 1 + k]);
            if (v[0] == 0 && v[1] == 0 && v[2] == 0)
                return qcli_usage_error("%s: the zero vector has no direction", a);
            *(a[2] == 'a' ? &have_aim : &have_up) = 1;
            i += 3;
        }
        else if (a[0] != '-' && !in)
            in = a;
        else
            return qcli_usage_error(RELIGHT_USAGE);
    }
    if (!in || (!png && !hdr && !pfm && !exr))
        return qcli_usage_error("relight needs FILE, a light (--sun, --point, --lights or --probe), and --png, --hdr, "
                                "--pfm or --exr OUT");
    if (ll.count == 0 && !ll.csv && !ll.probe)
        return qcli_usage_error("relight needs a light: --sun, --point, --lights FILE.csv or --probe PROBE.hdr");
    if (qcli_light_list_check(&ll) != 0)
        return 2;
    if (gles && (ll.count != 1 || ll.csv || ll.probe))
        return qcli_usage_error("--gles takes exactly one --sun or --point (no --lights or --probe)");
    if ((have_aim || have_up) && !ies)
        return qcli_usage_error("--aim and --up orient an --ies lamp: give --ies FILE.ies");
    if (ies && ll.points == 0)
        return qcli_usage_error("--ies shapes the --point lamps: give at least one --point X Y Z");
    if (ies && gles)
        return qcli_usage_error("--ies: goniometric lamps are relit on the soft framebuffer only (not --gles)");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    /* the profile first: a bad file costs no asset read; its table and the lamp's frame */
    qibl_gonio_t gon;
    uint16_t *gtab = NULL;
    if (ies) {
        qtool_ies prof;
        char ierr[512];
        if (qtool_ies_read(ies, &prof, ierr, sizeof ierr) != 0) {
            fprintf(stderr, "qibl: relight: %s\n", ierr);
            return 1;
        }
        double peak = 0, lm = qtool_ies_lumens(&prof);
        gtab = malloc(qibl_gonio_table_size((uint32_t)ies_n));
        int bad = !gtab || qtool_ies_gonio_table(&prof, (uint32_t)ies_n, gtab, &peak) != 0;
        if (bad)
            fprintf(stderr, "qibl: relight: %s: %s\n", ies, gtab ? "the profile is dark (peak 0 cd)" : "out of memory");
        qibl_status_t gs = bad ? QIBL_OK : qibl_gonio_init(&gon, (uint32_t)ies_n, gtab, aim, up);
        if (!bad && gs != QIBL_OK) {
            fprintf(stderr, "qibl: relight: --aim/--up: %s\n", qibl_status_str(gs));
            bad = 1;
        }
        if (!bad)
            fprintf(stderr, "qibl: note: %s: type %c, %s, peak %.6g cd, %.2f lm; each --point lamp scaled by "
                    "I / I_peak (%ldx%ld table)\n", ies, prof.type == QTOOL_IES_TYPE_C ? 'C' :
                    prof.type == QTOOL_IES_TYPE_B ? 'B' : 'A', qtool_ies_sym_name(prof.sym), peak, lm, ies_n, ies_n);
        qtool_ies_free(&prof);
        if (bad) {
            free(gtab);
            return 1;
        }
    }
    size_t n;
    uint8_t *bytes = NULL;
    char rerr[512];
    if (qtool_io_read_asset(in, &bytes, &n, rerr, sizeof rerr) != 0) {
        fprintf(stderr, "qibl: %s\n", rerr);
        free(gtab);
        return 1;
    }
    qibl_asset_t a;
    qibl_shmaps_t m, mp;
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    int have_point = ll.points > 0;
    qibl_status_t st = qibl_asset_open(&a, bytes, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &m);
    if (st == QIBL_OK && have_point) /* free point lights: the unshadowed set when the asset has one */
        st = qibl_asset_point_shmaps(&a, &mp);
    if (st == QIBL_OK && have_point)
        st = qibl_asset_pmap(&a, &pm);
    if (st == QIBL_OK && have_point && use_lut)
        st = qibl_asset_ylut(&a, &lut);
    /* lamps through the unshadowed maps get the asset's lamp occlusion (LOCC) when it has one */
    qibl_lampocc_t occ;
    qibl_chunk_t shmu, locc;
    const int has_shmu = qibl_asset_find_nth(&a, QIBL_CHUNK_SHMU, 0, &shmu) == QIBL_OK;
    const int has_locc = qibl_asset_find_nth(&a, QIBL_CHUNK_LOCC, 0, &locc) == QIBL_OK;
    const qibl_status_t occ_st = has_locc ? qibl_lightpath_occl_from_asset(&a, &occ) : QIBL_E_ASSET_MISSING_CHUNK;
    const int use_occ = st == QIBL_OK && have_point && has_shmu && occ_st == QIBL_OK;
    if (st == QIBL_OK && have_point && has_shmu && has_locc && occ_st != QIBL_OK) /* never dropped without a word */
        fprintf(stderr, "qibl: note: %s: its LOCC chunk is not usable (%s): the lamps are drawn without lamp "
                        "occlusion\n", in, qibl_soft_status_str(occ_st));
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: %s\n", in, qibl_soft_status_str(st));
        free(bytes), free(gtab);
        return 1;
    }
    uint32_t w = m.width, h = m.height;
    size_t np = (size_t)w * h;
    /* the directional part as one SH light (suns, --lights, --probe); notes on stdout */
    qibl_shlight_t sl;
    if (qcli_light_list_directional(&ll) && qcli_light_list_sh(&ll, m.k, stdout, &sl) != 0) {
        free(bytes), free(gtab);
        return 1;
    }
    qibl_pointlight_t pts[QCLI_RELIGHT_MAX_SOURCES];
    uint32_t npts = 0;
    double *pmp = NULL;
    for (uint32_t j = 0; j < ll.count; ++j) {
        qcli_relight_source *s = &ll.src[j];
        if (!s->point)
            continue;
        if (!s->have_rgb) {
            /* C0 = 1 lights a scene a few units away almost black: scale it with the scene's distance */
            double c0, d, lp[3] = {s->v[0] / 65536.0, s->v[1] / 65536.0, s->v[2] / 65536.0};
            if (!pmp)
                pmp = pmap_points(&pm);
            if (!pmp || qcli_point_default(pmp, np, lp, (int)falloff, &c0, &d) != 0) {
                fprintf(stderr, "qibl: relight: out of memory\n");
                free(pmp), free(bytes), free(gtab);
                return 1;
            }
            s->rgb[0] = s->rgb[1] = s->rgb[2] = (qibl_q16_t)nearbyint(c0 * 65536.0);
            fprintf(stderr, "qibl: note: --point without --rgb: C0 = %.4g (%.2g x d%s, d = %.3g the median distance "
                    "from the lamp to the scene); give --rgb R G B to choose\n", c0, QTOOL_CLI_POINT_GREY,
                    falloff == 2 ? "^2" : "", d);
        }
        qibl_pointlight_t pl = {{s->v[0], s->v[1], s->v[2]}, {s->rgb[0], s->rgb[1], s->rgb[2]},
                                falloff == 2 ? QIBL_FALLOFF_INV_DIST2 : QIBL_FALLOFF_INV_DIST, 0,
                                use_lut ? (nearest ? QIBL_LUT_NEAREST : QIBL_LUT_BILINEAR)
                                        : poly ? QIBL_POINT_POLY : QIBL_LUT_BILINEAR};
        pts[npts++] = pl;
    }
    free(pmp);
    const qibl_gonio_t *gl[QCLI_RELIGHT_MAX_SOURCES];
    for (uint32_t j = 0; j < npts; ++j)
        gl[j] = ies ? &gon : NULL;
    const qibl_gonio_t *const *gptr = ies ? gl : NULL;
    uint8_t *pix = malloc(np * 3);
    float *lin = hdr || pfm || exr ? malloc(np * 3 * sizeof(float)) : NULL;
    if (!pix || ((hdr || pfm || exr) && !lin)) {
        fprintf(stderr, "qibl: relight: out of memory\n");
        free(bytes), free(pix), free(lin), free(gtab);
        return 1;
    }
    double ms = 0;
    int rc = 0;
    if (gles) { /* the GPU path: same asset, same core weights, platform/gles2 (one light) */
        const qcli_relight_source *s = &ll.src[0];
        qtool_gles_relight_req req = {&m, have_point ? &pm : NULL, have_point && use_lut ? &lut : NULL,
                                     {s->point ? 0 : s->v[0], s->point ? 0 : s->v[1], s->point ? 0 : s->v[2]},
                                     {s->point ? s->v[0] : 0, s->point ? s->v[1] : 0, s->point ? s->v[2] : 0},
                                     {s->rgb[0], s->rgb[1], s->rgb[2]}, (int)falloff, nearest, linear,
                                     (qibl_uq16_t)exposure};
        uint32_t passes = 0;
        char renderer[64] = "";
        char err[512];
        if (qtool_gles_relight(&req, pix, &passes, renderer) != 0)
            rc = 1;
        else if (qtool_png_write_rgb8(png, (int)w, (int)h, pix, err, sizeof err) != 0)
            fprintf(stderr, "qibl: %s\n", err), rc = 1;
        else
            printf("wrote %s (%ux%u, k = %u, GLES2 on %s, %u pass%s)\n", png, w, h, m.k, renderer, passes,
                   passes == 1 ? "" : "es");
    } else if (qcli_relight_frame_gonio(&m, qcli_light_list_directional(&ll) ? &sl : NULL, &mp, &pm,
                                        use_lut ? &lut : NULL, use_occ ? &occ : NULL, pts, gptr, npts,
                                        (uint32_t)exposure, !linear, pix, lin, &ms, &st) != 0) {
        fprintf(stderr, "qibl: relight: %s\n", st == QIBL_E_NULL_POINTER ? "out of memory" : qibl_soft_status_str(st));
        rc = 1;
    } else {
        char err[1200], how[600];
        describe(&ll, use_lut ? (nearest ? 2 : 1) : poly ? 3 : 0, how, sizeof how);
        if (png && qtool_png_write_rgb8(png, (int)w, (int)h, pix, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (png) {
            printf("wrote %s (%ux%u, k = %u, %s, %.1f ms incl. framebuffer conversion)\n", png, w, h, m.k, how, ms);
            qcli_warn_dark(png, pix, np);
        }
        /* linear frames: the core's Q16.16 output before exposure and the transfer curve */
        if (rc == 0 && hdr && qtool_hdr_write(hdr, (int)w, (int)h, lin, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (rc == 0 && hdr) {
            printf("wrote %s (%ux%u Radiance RGBE, linear, before exposure, %s)\n", hdr, w, h, how);
        }
        if (rc == 0 && pfm && qtool_pfm_write(pfm, (int)w, (int)h, 3, lin, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (rc == 0 && pfm) {
            printf("wrote %s (%ux%u PFM, linear, before exposure, %s)\n", pfm, w, h, how);
        }
        if (rc == 0 && exr && qtool_exr_write(exr, (int)w, (int)h, lin, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (rc == 0 && exr) {
            printf("wrote %s (%ux%u OpenEXR FLOAT ZIP, linear, before exposure, %s)\n", exr, w, h, how);
        }
    }
    free(bytes), free(pix), free(lin), free(gtab);
    return rc;
}
