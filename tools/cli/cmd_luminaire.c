/*
 * cmd_luminaire.c - `qibl luminaire capture|info|render|study`: near-field light sources (the
 * library is tools/luminaire: the .qnf file, the simulated acquisition, the textured spotlights).
 *
 * Output is all or nothing: files are written atomically, and a report is printed only once
 * everything it describes has succeeded.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "io/file.h"
#include "io/obj.h"
#include "io/png.h"
#include "luminaire/luminaire.h"
#include "qibl/asset.h"
#include "qibl/soft.h"

const char qcli_luminaire_usage[] =
    "usage: qibl luminaire capture builtin|MESH.obj --out F.qnf [--grid N] [--res R] [--basis box|tent]\n"
    "                                [--emitter Z HALF] [--threads T]\n"
    "       qibl luminaire info F.qnf\n"
    "       qibl luminaire render ASSET F.qnf --at X Y Z --out F.png [--far] [--exposure E] [--table N]\n"
    "       qibl luminaire study [--grid N] [--res R] [--size S] [--quick] [--threads T]\n"
    "  A near-field light source (Granier et al.): its light on a sampling plane S projected onto a\n"
    "  grid of N x N filter supports, each with an R x R emission texture on a measurement plane.\n"
    "  capture: the built-in luminaire (a 0.4 box shade with a checkerboard of holes in its bottom\n"
    "  plate around a square emitter) ray-traced through the paper's acquisition (Figure 1: the\n"
    "  filter on S, the plane M behind it) into F.qnf (default N 16, R 32, box basis). MESH.obj: a shade\n"
    "  as it is (z up, every vertex above S: z > 0; at most 65536 triangles) around a square emitter\n"
    "  facing down at height Z with half-size HALF (default: the built-in one's proportions of the\n"
    "  mesh's box); the grid covers the mesh's extent. info: the file's header and its flux.\n"
    "  render: an asset frame (its point maps and P map) lit by the source hanging with S's centre\n"
    "  at X Y Z, facing down (-z): one textured spotlight per lit support, each a goniometric lamp\n"
    "  of the core (qibl/gonio.h), shaded from four anchors' point-map spans, summed pass by pass in\n"
    "  integers; prints the frame's CPU time. --far: the same source as one far-field lamp\n"
    "  (IES-like). study: near and far field against the ray-traced luminaire on a ground plane at\n"
    "  0.5..8 lamp sizes (PSNR), and the near field's CPU time per 1024x256 frame (a courtyard\n"
    "  panorama, and a ground patch lit everywhere); RESULT lines. Format: tools/luminaire/luminaire.h.\n";

static int parse_u(const char *opt, const char *s, long lo, long hi, uint32_t *out)
{
    long v;
    if (qcli_parse_int(s, lo, hi, &v) != 0)
        return qcli_usage_error("luminaire: %s takes an integer in %ld..%ld", opt, lo, hi);
    *out = (uint32_t)v;
    return 0;
}

static int cmd_capture(int argc, char **argv)
{
    const char *src = NULL, *out = NULL;
    qtool_luminaire_capture_opts o = {.grid = 16};
    double ez = 0, eh = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        int more = i + 1 < argc;
        if (strcmp(a, "--out") == 0 && more)
            out = argv[++i];
        else if (strcmp(a, "--grid") == 0 && more) {
            if (parse_u(a, argv[++i], 1, QTOOL_LUMINAIRE_MAX_GRID, &o.grid))
                return 2;
        } else if (strcmp(a, "--res") == 0 && more) {
            if (parse_u(a, argv[++i], QTOOL_LUMINAIRE_MIN_RES, QTOOL_LUMINAIRE_MAX_RES, &o.res))
                return 2;
        } else if (strcmp(a, "--threads") == 0 && more) {
            uint32_t t = 1;
            if (parse_u(a, argv[++i], 1, 256, &t))
                return 2;
            o.threads = (int)t;
        } else if (strcmp(a, "--emitter") == 0 && i + 2 < argc) {
            if (qcli_parse_num(a, argv[i + 1], 1e-6, 1e6, "its height above S", &ez) != 0 ||
                qcli_parse_num(a, argv[i + 2], 1e-6, 1e6, "its half-size", &eh) != 0)
                return 2;
            i += 2;
        } else if (strcmp(a, "--basis") == 0 && more) {
            const char *b = argv[++i];
            if (strcmp(b, "box") == 0)
                o.basis = QTOOL_LUMINAIRE_BOX;
            else if (strcmp(b, "tent") == 0)
                o.basis = QTOOL_LUMINAIRE_TENT;
            else
                return qcli_usage_error("luminaire capture: --basis is box or tent, not '%s'", b);
        } else if (a[0] == '-' && a[1])
            return qcli_usage_error("luminaire capture: unknown option or missing value '%s'", a);
        else if (src)
            return qcli_usage_error("luminaire capture: one luminaire only ('%s' and '%s')", src, a);
        else
            src = a;
    }
    if (!src || !out)
        return qcli_usage_error("usage: qibl luminaire capture builtin|MESH.obj --out F.qnf [--grid N] [--res R]");
    int builtin = strcmp(src, "builtin") == 0;
    if (builtin && (ez > 0 || eh > 0))
        return qcli_usage_error("luminaire capture: --emitter places the emitter in a mesh, not in 'builtin'");
    if (qcli_parse_only)
        return 0;
    qtool_luminaire_model *m = NULL;
    char err[512] = "";
    if (builtin) {
        m = qtool_luminaire_builtin();
    } else {
        qtool_obj_mesh mesh;
        if (qtool_obj_read_max(src, 1u << 16, &mesh, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: luminaire capture: %s\n", err);
            return 1;
        }
        m = qtool_luminaire_from_mesh(&mesh, ez, eh, err, sizeof err);
        qtool_obj_free(&mesh);
        if (!m) {
            fprintf(stderr, "qibl: luminaire capture: %s: %s\n", src, err);
            return 1;
        }
    }
    qtool_luminaire l;
    if (!m || qtool_luminaire_capture(m, &o, &l) != 0) {
        qtool_luminaire_model_free(m);
        fprintf(stderr, "qibl: luminaire capture: out of memory\n");
        return 1;
    }
    qtool_luminaire_model_free(m);
    qtool_luminaire_err e = qtool_luminaire_write(out, &l, err, sizeof err);
    if (e != QTOOL_LUMINAIRE_OK) {
        fprintf(stderr, "qibl: luminaire capture: %s: %s\n", out, err[0] ? err : qtool_luminaire_err_str(e));
        qtool_luminaire_free(&l);
        return 1;
    }
    printf("wrote %s: %ux%u supports, %ux%u texels each, %s basis\n", out, l.nx, l.ny, l.res, l.res,
           l.basis == QTOOL_LUMINAIRE_TENT ? "tent" : "box");
    qtool_luminaire_free(&l);
    return 0;
}

static int cmd_info(int argc, char **argv)
{
    if (argc != 3 || argv[2][0] == '-')
        return qcli_usage_error("usage: qibl luminaire info F.qnf");
    if (qcli_parse_only)
        return 0;
    qtool_luminaire l;
    qtool_luminaire_err e = qtool_luminaire_read(argv[2], &l);
    if (e != QTOOL_LUMINAIRE_OK) {
        fprintf(stderr, "qibl: luminaire info: %s: %s\n", argv[2], qtool_luminaire_err_str(e));
        return 1;
    }
    uint32_t dark = 0;
    float lo = 0, hi = 0;
    for (uint32_t m = 0; m < l.nx * l.ny; ++m) {
        int lit = 0;
        for (size_t k = 0; k < (size_t)l.res * l.res * 3; ++k) {
            float v = l.tex[(size_t)m * l.res * l.res * 3 + k];
            lit |= v > 0;
            lo = v < lo ? v : lo, hi = v > hi ? v : hi;
        }
        dark += !lit;
    }
    double flux[3];
    qtool_luminaire_flux(&l, flux);
    printf("file %s\nformat QNF version %u\n", argv[2], QTOOL_LUMINAIRE_VERSION);
    printf("grid %ux%u spacing %.6g\n", l.nx, l.ny, (double)l.spacing);
    printf("basis %s\n", l.basis == QTOOL_LUMINAIRE_TENT ? "tent" : "box");
    printf("texture %ux%u window_half_tan %.6g plane_distance %.6g\n", l.res, l.res, (double)l.half_tan,
           (double)l.distance);
    printf("supports %u dark %u\n", l.nx * l.ny, dark);
    printf("texel_min %.6g texel_max %.6g\n", (double)lo, (double)hi);
    printf("flux %.6g %.6g %.6g\n", flux[0], flux[1], flux[2]);
    qtool_luminaire_free(&l);
    return 0;
}

static int cmd_render(int argc, char **argv)
{
    const char *asset = NULL, *qnf = NULL, *out = NULL;
    int32_t at[3];
    int have_at = 0, far = 0;
    uint32_t table = 64;
    double expo = 1;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--at") == 0 && i + 3 < argc) {
            for (int k = 0; k < 3; ++k)
                if (qcli_parse_q16(argv[i + 1 + k], &at[k]) != 0)
                    return qcli_usage_error("luminaire render: --at takes X Y Z in the Q16.16 range, not '%s'",
                                            argv[i + 1 + k]);
            have_at = 1, i += 3;
        } else if (strcmp(a, "--out") == 0 && i + 1 < argc)
            out = argv[++i];
        else if (strcmp(a, "--far") == 0)
            far = 1;
        else if (strcmp(a, "--table") == 0 && i + 1 < argc) {
            if (parse_u(a, argv[++i], QIBL_GONIO_MIN_N, QIBL_GONIO_MAX_N, &table))
                return 2;
        } else if (strcmp(a, "--exposure") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], 1.0 / 65536, 65535, NULL, &expo) != 0)
                return 2;
        } else if (a[0] == '-' && a[1])
            return qcli_usage_error("luminaire render: unknown option or missing value '%s'", a);
        else if (!asset)
            asset = a;
        else if (!qnf)
            qnf = a;
        else
            return qcli_usage_error("luminaire render: one asset and one source ('%s' too many)", a);
    }
    if (!asset || !qnf || !out || !have_at)
        return qcli_usage_error("usage: qibl luminaire render ASSET F.qnf --at X Y Z --out F.png");
    if (qcli_parse_only)
        return 0;
    qtool_luminaire l;
    qtool_luminaire_err le = qtool_luminaire_read(qnf, &l);
    if (le != QTOOL_LUMINAIRE_OK) {
        fprintf(stderr, "qibl: luminaire render: %s: %s\n", qnf, qtool_luminaire_err_str(le));
        return 1;
    }
    char err[512];
    qtool_luminaire_spots s;
    if (qtool_luminaire_spots_make(&l, at, table, far, &s, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: luminaire render: %s: %s\n", qnf, err);
        qtool_luminaire_free(&l);
        return 1;
    }
    qtool_luminaire_free(&l);
    uint8_t *bytes = NULL;
    size_t n;
    if (qtool_io_read_asset(asset, &bytes, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        qtool_luminaire_spots_free(&s);
        return 1;
    }
    qibl_asset_t a;
    qibl_shmaps_t mp;
    qibl_pmap_t pm;
    qibl_ylut_t lut;
    qibl_status_t st = qibl_asset_open(&a, bytes, n);
    if (st == QIBL_OK)
        st = qibl_asset_point_shmaps(&a, &mp);
    if (st == QIBL_OK)
        st = qibl_asset_pmap(&a, &pm);
    int have_lut = st == QIBL_OK && qibl_asset_ylut(&a, &lut) == QIBL_OK;
    uint8_t *rgb = st == QIBL_OK ? malloc((size_t)mp.width * mp.height * 3) : NULL;
    double ms = 0;
    if (st == QIBL_OK && !rgb)
        st = QIBL_E_NULL_POINTER;
    if (st == QIBL_OK)
        qtool_luminaire_relight(&s, &mp, &pm, have_lut ? &lut : NULL, (uint32_t)lround(expo * 65536), 1, rgb, NULL,
                                &ms, &st);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: luminaire render: %s: %s\n", asset, qibl_soft_status_str(st));
        free(rgb), free(bytes), qtool_luminaire_spots_free(&s);
        return 1;
    }
    int rc = qtool_png_write_rgb8(out, (int)mp.width, (int)mp.height, rgb, err, sizeof err);
    if (rc != 0)
        fprintf(stderr, "qibl: luminaire render: %s\n", err);
    else
        printf("wrote %s: %ux%u, %u %s, %.1f ms CPU\n", out, mp.width, mp.height, s.count,
               far ? "far-field lamp" : "spotlights", ms);
    free(rgb), free(bytes), qtool_luminaire_spots_free(&s);
    return rc == 0 ? 0 : 1;
}

static int cmd_study(int argc, char **argv)
{
    qtool_luminaire_study_opts o = {.grid = 16};
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        int more = i + 1 < argc;
        if (strcmp(a, "--grid") == 0 && more) {
            if (parse_u(a, argv[++i], 1, QTOOL_LUMINAIRE_MAX_GRID, &o.grid))
                return 2;
        } else if (strcmp(a, "--res") == 0 && more) {
            if (parse_u(a, argv[++i], QTOOL_LUMINAIRE_MIN_RES, QTOOL_LUMINAIRE_MAX_RES, &o.res))
                return 2;
        } else if (strcmp(a, "--size") == 0 && more) {
            if (parse_u(a, argv[++i], 8, 1024, &o.size))
                return 2;
        } else if (strcmp(a, "--threads") == 0 && more) {
            uint32_t t = 1;
            if (parse_u(a, argv[++i], 1, 256, &t))
                return 2;
            o.threads = (int)t;
        } else if (strcmp(a, "--quick") == 0)
            o.quick = 1;
        else
            return qcli_usage_error("luminaire study: unknown option or missing value '%s'", a);
    }
    if (qcli_parse_only)
        return 0;
    if (qtool_luminaire_study(&o, stdout) != 0) {
        fprintf(stderr, "qibl: luminaire study: out of memory\n");
        return 1;
    }
    return 0;
}

int qcli_cmd_luminaire(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "capture") == 0)
        return cmd_capture(argc, argv);
    if (argc >= 2 && strcmp(argv[1], "info") == 0)
        return cmd_info(argc, argv);
    if (argc >= 2 && strcmp(argv[1], "render") == 0)
        return cmd_render(argc, argv);
    if (argc >= 2 && strcmp(argv[1], "study") == 0)
        return cmd_study(argc, argv);
    return qcli_usage_error("usage: qibl luminaire capture|info|render|study ... (qibl help luminaire)");
}
