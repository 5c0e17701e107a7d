/*
 * relight_path.c - `qibl relight FILE --path N --t T ...`: a light on one of the asset's baked paths
 * (LPTH) at parameter T, relit as unshadowed SH x visibility(T), optionally over the demo's sky
 * through the shadowed maps (--sky R G B: sky + sun in one frame). cmd_relight.c hands any command
 * line holding --path to qcli_relight_path.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "cli/cli.h"
#include "io/file.h"
#include "io/exr.h"
#include "io/ies.h"
#include "io/pfm.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "qibl/gonio.h"
#include "qibl/lightpath.h"
#include "qibl/soft.h"

#define PATH_USAGE                                                                                            \
    "usage: qibl relight FILE --path N|sun|lamp --t T [--rgb R G B] [--soft R] [--sky R G B] " \
    "[--ies FILE.ies [--aim X Y Z] [--up X Y Z] [--ies-size N]] (--png OUT | --pfm OUT.pfm | --exr OUT.exr)..."

int qcli_relight_has_path(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i)
        if (strcmp(argv[i], "--path") == 0)
            return 1;
    return 0;
}

/* the path's index: a number, or the first path of a kind ("sun" directions, "lamp" positions) */
static int pick_path(const qibl_asset_t *a, const char *in, const char *spec, uint32_t *index)
{
    uint32_t n = qibl_lightpath_count(a);
    long v;
    if (n == 0) {
        fprintf(stderr, "qibl: %s: no light paths (bake with --sun-path or --lamp-track)\n", in);
        return -1;
    }
    if (strcmp(spec, "sun") == 0 || strcmp(spec, "lamp") == 0) {
        uint32_t want = spec[0] == 's' ? QIBL_LIGHTPATH_DIRECTIONS : QIBL_LIGHTPATH_POSITIONS;
        for (uint32_t i = 0; i < n; ++i) {
            qibl_lightpath_t p;
            if (qibl_lightpath_from_asset(a, i, &p) == QIBL_OK && p.kind == want) {
                *index = i;
                return 0;
            }
        }
        fprintf(stderr, "qibl: %s: no %s path among its %u light path%s\n", in, spec[0] == 's' ? "sun" : "lamp", n,
                n == 1 ? "" : "s");
        return -1;
    }
    if (qcli_parse_int(spec, 0, 4095, &v) != 0) {
        fprintf(stderr, "qibl: --path needs an index, sun or lamp: '%s'\n", spec);
        return -2;
    }
    if ((uint32_t)v >= n) {
        fprintf(stderr, "qibl: %s: --path %ld, but the asset has %u light path%s (0..%u)\n", in, v, n, n == 1 ? "" : "s",
                n - 1);
        return -1;
    }
    *index = (uint32_t)v;
    return 0;
}

int qcli_relight_path(int argc, char **argv)
{
    const char *in = NULL, *png = NULL, *pfm = NULL, *exr = NULL, *spec = NULL;
    double t = -1, rgb[3] = {1, 1, 1}, sky[3] = {0, 0, 0}, soft = 0;
    int have_sky = 0;
    /* --ies: a goniometric lamp on the track (as relight --ies) */
    const char *ies = NULL;
    int have_aim = 0;
    int32_t aim[3] = {0, 0, -65536}, up[3] = {65536, 0, 0};
    long ies_n = 64;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--path") == 0 && i + 1 < argc)
            spec = argv[++i];
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
            have_aim = 1, i += 3;
        }
        else if (strcmp(a, "--t") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], 0, 1, "a path parameter in 0..1", &t) != 0)
                return 2;
        } else if (strcmp(a, "--soft") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], 0, 0.5, "a half-width in path units, 0..0.5", &soft) != 0)
                return 2;
        } else if ((strcmp(a, "--rgb") == 0 || strcmp(a, "--sky") == 0) && i + 3 < argc) {
            double *d = a[2] == 'r' ? rgb : sky;
            for (int c = 0; c < 3; ++c)
                if (qcli_parse_num(a, argv[i + 1 + c], 0, 32767, "a colour component in 0..32767", &d[c]) != 0)
                    return 2;
            have_sky |= a[2] == 's';
            i += 3;
        } else if (strcmp(a, "--png") == 0 && i + 1 < argc)
            png = argv[++i];
        else if (strcmp(a, "--pfm") == 0 && i + 1 < argc)
            pfm = argv[++i];
        else if (strcmp(a, "--exr") == 0 && i + 1 < argc)
            exr = argv[++i];
        else if (a[0] != '-' && !in)
            in = a;
        else
            return qcli_usage_error(PATH_USAGE);
    }
    if (!in || !spec || t < 0 || (!png && !pfm && !exr))
        return qcli_usage_error("relight --path needs FILE, --path N|sun|lamp, --t T and --png, --pfm or --exr OUT");
    if (have_aim && !ies)
        return qcli_usage_error("--aim and --up orient an --ies lamp: give --ies FILE.ies");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    qibl_gonio_t gon;
    uint16_t *gtab = NULL;
    if (ies) {
        qtool_ies prof;
        char ierr[512];
        if (qtool_ies_read(ies, &prof, ierr, sizeof ierr) != 0) {
            fprintf(stderr, "qibl: relight: %s\n", ierr);
            return 1;
        }
        gtab = malloc(qibl_gonio_table_size((uint32_t)ies_n));
        qibl_status_t gs = QIBL_E_NULL_POINTER;
        if (gtab && qtool_ies_gonio_table(&prof, (uint32_t)ies_n, gtab, NULL) == 0)
            gs = qibl_gonio_init(&gon, (uint32_t)ies_n, gtab, aim, up);
        else if (gtab)
            gs = QIBL_E_GONIO_TABLE;
        qtool_ies_free(&prof);
        if (gs != QIBL_OK) {
            fprintf(stderr, "qibl: relight: %s: %s\n", ies,
                    gs == QIBL_E_GONIO_TABLE ? "the profile is dark (peak 0 cd)"
                    : gs == QIBL_E_NULL_POINTER ? "out of memory" : qibl_status_str(gs));
            free(gtab);
            return 1;
        }
    }
    size_t n;
    uint8_t *bytes = NULL;
    char err[1200];
    if (qtool_io_read_asset(in, &bytes, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        free(gtab);
        return 1;
    }
    qibl_asset_t a;
    qibl_lightpath_t p;
    qibl_shmaps_t m;
    uint32_t index = 0;
    qibl_status_t st = qibl_asset_open(&a, bytes, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&a, &m);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: %s\n", in, qibl_soft_status_str(st));
        free(bytes), free(gtab);
        return 1;
    }
    int r = pick_path(&a, in, spec, &index);
    if (r != 0) {
        free(bytes), free(gtab);
        return r == -2 ? 2 : 1;
    }
    /* the light at t as the asset stores it (the core's interpolation of the keys) */
    uint32_t tq = (uint32_t)lrint(t * QIBL_LIGHTPATH_T_MAX), radius = (uint32_t)lrint(soft * QIBL_LIGHTPATH_T_MAX);
    qibl_q16_t v[3];
    st = qibl_lightpath_from_asset(&a, index, &p);
    if (st == QIBL_OK)
        st = qibl_lightpath_at(&p, tq, v);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: light path %u: %s\n", in, index, qibl_soft_status_str(st));
        free(bytes), free(gtab);
        return 1;
    }
    if (radius > QIBL_LIGHTPATH_MAX_RADIUS)
        radius = QIBL_LIGHTPATH_MAX_RADIUS;
    qtool_rt_light l;
    memset(&l, 0, sizeof l);
    l.point = p.kind == QIBL_LIGHTPATH_POSITIONS, l.falloff = 1;
    for (int c = 0; c < 3; ++c) {
        (l.point ? l.pos : l.dir)[c] = v[c] / 65536.0;
        l.rgb[c] = rgb[c];
    }
    qibl_shlight_t skysh;
    if (have_sky)
        qtool_bake_sky_sh(sky, QIBL_SH_MAX_COUNT, &skysh);
    size_t np = (size_t)m.width * m.height;
    uint8_t *pix = malloc(np * 3);
    float *lin = pfm || exr ? malloc(np * 3 * sizeof(float)) : NULL;
    double ms = 0;
    int rc = 0;
    if (!pix || ((pfm || exr) && !lin)) {
        fprintf(stderr, "qibl: relight: out of memory\n");
        rc = 1;
    } else if (ies && !l.point) {
        fprintf(stderr, "qibl: relight: --ies shapes a lamp: path %u of %s is a sun path\n", index, in);
        rc = 1;
    } else if (qtool_bake_relight_path8_gonio(bytes, n, &l, ies ? &gon : NULL, index, tq, radius,
                                              have_sky ? &skysh : NULL, pix, lin, &ms, &st) != 0) {
        fprintf(stderr, "qibl: relight: %s: %s\n", in,
                st == QIBL_E_NULL_POINTER ? "out of memory" : qibl_soft_status_str(st));
        rc = 1;
    } else {
        const char *what = l.point ? "lamp" : "sun";
        if (png && qtool_png_write_rgb8(png, (int)m.width, (int)m.height, pix, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (png) {
            printf("wrote %s (%ux%u, %s on path %u at t = %.4f (%u/65535)%s%s, %.1f ms)\n", png, m.width, m.height, what,
                   index, t, tq, radius ? ", soft" : "", have_sky ? ", over the sky" : "", ms);
            qcli_warn_dark(png, pix, np); /* as every other relight does */
        }
        if (rc == 0 && pfm && qtool_pfm_write(pfm, (int)m.width, (int)m.height, 3, lin, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (rc == 0 && pfm) {
            printf("wrote %s (%ux%u PFM, linear, %s on path %u)\n", pfm, m.width, m.height, what, index);
        }
        if (rc == 0 && exr &&
            qtool_exr_write(exr, (int)m.width, (int)m.height, lin, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else if (rc == 0 && exr) {
            printf("wrote %s (%ux%u OpenEXR FLOAT ZIP, linear, %s on path %u)\n", exr, m.width, m.height, what, index);
        }
    }
    free(bytes), free(pix), free(lin), free(gtab);
    return rc;
}
