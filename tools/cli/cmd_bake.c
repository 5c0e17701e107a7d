/*
 * cmd_bake.c - `qibl render` (ground truth), `qibl bake` (reference renders -> SH maps -> asset,
 * shards, --budget), `qibl merge` (shards -> asset), `qibl check` (validate PNG/APNG/PFM/HDR/asset
 * files).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/bake.h"
#include "bake/extras.h"
#include "bake/path.h"
#include "io/exr.h"
#include "io/hdr.h"
#include "io/mesh.h"
#include "io/obj.h"
#include "io/ply.h"
#include "io/pfm.h"
#include "io/ies.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "io/atomic.h"
#include "io/file.h"
#include "cli/cli.h"
#include "qibl/shmap.h"
#include "ref/psnr.h"
#include "render/rt.h"

/* ---- shared options ------------------------------------------------------------------------------ */

/* X Y Z after argv[i], each in lo..QTOOL_CLI_Q16_MAX (render is the ground truth of what relight
 * can take); 0, or 2 after a message naming the option and the value */
static int parse_d3(char **argv, int i, int argc, double lo, double v[3])
{
    if (i + 3 >= argc)
        return qcli_usage_error("%s needs three numbers", argv[i]);
    for (int j = 0; j < 3; ++j)
        if (qcli_parse_num(argv[i], argv[i + 1 + j], lo, QTOOL_CLI_Q16_MAX, QTOOL_CLI_Q16_WHY, &v[j]) != 0)
            return 2;
    return 0;
}

/* Consumes the scene/panorama options at argv[*i]; 1 if consumed, 0 if not ours, -1 on a bad value
 * (message printed). */
int qcli_scene_opt(int argc, char **argv, int *i, qcli_scene *o)
{
    const char *a = argv[*i];
    if (strcmp(a, "--scene") == 0 && *i + 1 < argc) {
        o->scene = argv[++*i];
    } else if (strcmp(a, "--zup") == 0) {
        o->zup = 1;
    } else if (strcmp(a, "--raw") == 0) {
        o->raw = 1;
    } else if (strcmp(a, "--equirect") == 0) {
        o->kind = QTOOL_PANO_EQUIRECT;
    } else if (strcmp(a, "--size") == 0 && *i + 1 < argc) {
        long w, h;
        if (qcli_parse_size(a, argv[++*i], QIBL_ASSET_MAX_DIM, &w, &h) != 0)
            return -1;
        if (w * h > (long)QIBL_ASSET_MAX_PIXELS) {
            qcli_usage_error("--size %ldx%ld is above the asset's %u pixels", w, h, QIBL_ASSET_MAX_PIXELS);
            return -1;
        }
        o->w = (uint32_t)w, o->h = (uint32_t)h;
    } else if (strcmp(a, "--threads") == 0 && *i + 1 < argc) {
        long t;
        if (qcli_parse_int(argv[++*i], 1, 256, &t) != 0) {
            qcli_usage_error("--threads needs an integer in 1..256");
            return -1;
        }
        o->threads = (int)t;
    } else {
        return 0;
    }
    return 1;
}

void qcli_scene_defaults(qcli_scene *o)
{
    memset(o, 0, sizeof *o);
    o->w = 1024, o->h = 256, o->kind = QTOOL_PANO_CYLINDRICAL;
    o->threads = qcli_default_threads(); /* the job's CPUs (affinity, SLURM_CPUS_PER_TASK), not the machine's */
}

/* Loads the scene: built-in when o->scene is NULL or "builtin", else a glTF (by its name or GLB
 * magic), PLY (by its first line) or OBJ mesh, with its materials (io/mesh.h). 0, or 1 after printing the error. */
int qcli_scene_load(const qcli_scene *o, qtool_rt_scene *s)
{
    if (!o->scene || strcmp(o->scene, "builtin") == 0) {
        if (qtool_rt_scene_builtin(s) != 0) {
            fprintf(stderr, "qibl: out of memory building the scene\n");
            return 1;
        }
        return 0;
    }
    qtool_obj_mesh m;
    char err[1200];
    /* glTF by its name or GLB magic, PLY by its first line (whatever the extension), else OBJ */
    uint8_t head[8] = {0};
    FILE *f = fopen(o->scene, "rb");
    size_t nh = f ? fread(head, 1, sizeof head, f) : 0;
    int opened = f != NULL;
    if (f)
        fclose(f);
    int known = qtool_ply_sniff(head, nh) || qtool_gltf_sniff_glb(head, nh) || qtool_mesh_is_gltf_name(o->scene);
    /* the scene cap before the mesh is allocated (each reader counts its triangles first) */
    if (qtool_mesh_read_max(o->scene, QCLI_SCENE_MAX_TRIANGLES, &m, NULL, NULL, err, sizeof err) != 0) {
        const char *ext = strrchr(o->scene, '.');
        fprintf(stderr, "qibl: %s%s\n", err,
                !opened || known || (ext && strcmp(ext, ".obj") == 0)
                    ? ""
                    : " (read as OBJ: meshes are Wavefront OBJ or PLY, or glTF 2.0 .gltf/.glb)");
        return 1;
    }
    int rc = qtool_rt_scene_from_obj(s, &m, o->zup, o->raw);
    qtool_obj_free(&m);
    if (rc != 0) {
        fprintf(stderr, "qibl: %s: out of memory building the scene\n", o->scene);
        return 1;
    }
    return 0;
}

/* ---- qibl render --------------------------------------------------------------------------------- */

/* --point without --rgb: C0 from the distance to what the panorama sees, as relight does from the
 * asset's P map (the same points: the primary hits, sky QTOOL_CLI_SKY_DIST along the ray). 0, or 1
 * after a message. */
static int point_default(const qtool_rt_scene *s, const qcli_scene *so, qtool_rt_light *l)
{
    size_t np = (size_t)so->w * so->h;
    double *pts = malloc(np * 3 * sizeof *pts), c0, d;
    for (uint32_t y = 0; pts && y < so->h; ++y)
        for (uint32_t x = 0; x < so->w; ++x) {
            double dir[3], *p = pts + 3 * ((size_t)y * so->w + x);
            qtool_rt_hit h;
            qtool_rt_pixel_dir(so->w, so->h, (qtool_pano_kind)so->kind, x, y, dir);
            qtool_rt_primary(s, dir, &h);
            for (int c = 0; c < 3; ++c)
                p[c] = h.hit ? h.p[c] : dir[c] * QTOOL_CLI_SKY_DIST;
        }
    if (!pts || qcli_point_default(pts, np, l->pos, l->falloff, &c0, &d) != 0) {
        free(pts);
        fprintf(stderr, "qibl: render: out of memory\n");
        return 1;
    }
    free(pts);
    l->rgb[0] = l->rgb[1] = l->rgb[2] = c0;
    fprintf(stderr, "qibl: note: --point without --rgb: C0 = %.4g (%.2g x d%s, d = %.3g the median distance from the "
            "lamp to the scene); give --rgb R G B to choose\n", c0, QTOOL_CLI_POINT_GREY, l->falloff == 2 ? "^2" : "", d);
    return 0;
}

int qcli_cmd_render(int argc, char **argv)
{
    qcli_scene so;
    qcli_scene_defaults(&so);
    qtool_rt_light l = {0, {0, 0, 1}, {0, 0, 0}, {1, 1, 1}, 1};
    int have = 0, have_rgb = 0;
    long falloff = 1;
    const char *png = NULL, *pfm = NULL, *exr = NULL, *depth = NULL;
    /* --ies: a goniometric lamp (io/ies.h), oriented as relight --ies orients it */
    const char *ies = NULL;
    double aim[3] = {0, 0, -1}, up[3] = {1, 0, 0};
    int have_aim = 0;
    for (int i = 1; i < argc; ++i) {
        int r = qcli_scene_opt(argc, argv, &i, &so);
        if (r < 0)
            return 2;
        if (r)
            continue;
        const char *a = argv[i];
        if (strcmp(a, "--sun") == 0 || strcmp(a, "--point") == 0) {
            int pt = a[2] == 'p';
            double *v = pt ? l.pos : l.dir;
            if (parse_d3(argv, i, argc, -QTOOL_CLI_Q16_MAX, v) != 0)
                return 2;
            /* as relight sees it: a direction that rounds to 0 0 0 in Q16.16 has none */
            if (!pt && fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2]))) < 0.5 / 65536)
                return qcli_usage_error("--sun needs a non-zero direction: %s %s %s is 0 0 0 in Q16.16",
                                            argv[i + 1], argv[i + 2], argv[i + 3]);
            l.point = pt, have++, i += 3;
        } else if (strcmp(a, "--rgb") == 0) {
            if (parse_d3(argv, i, argc, 0, l.rgb) != 0)
                return 2;
            have_rgb = 1, i += 3;
        } else if (strcmp(a, "--falloff") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 2, &falloff) != 0)
                return qcli_usage_error("--falloff is 1 (C0/|L|) or 2 (C0/|L|^2)");
        } else if (strcmp(a, "--png") == 0 && i + 1 < argc) {
            png = argv[++i];
        } else if (strcmp(a, "--pfm") == 0 && i + 1 < argc) {
            pfm = argv[++i];
        } else if (strcmp(a, "--exr") == 0 && i + 1 < argc) {
            exr = argv[++i];
        } else if (strcmp(a, "--depth") == 0 && i + 1 < argc) {
            depth = argv[++i];
        } else if (strcmp(a, "--ies") == 0 && i + 1 < argc) {
            ies = argv[++i];
        } else if (strcmp(a, "--aim") == 0 || strcmp(a, "--up") == 0) {
            if (parse_d3(argv, i, argc, -QTOOL_CLI_Q16_MAX, a[2] == 'a' ? aim : up) != 0)
                return 2;
            have_aim = 1, i += 3;
        } else {
            return qcli_usage_error("render: unknown argument '%s' (see qibl help render)", a);
        }
    }
    if (have != 1 || (!png && !pfm && !exr && !depth))
        return qcli_usage_error("render needs exactly one of --sun/--point and at least one of --png/--pfm/--exr/--depth");
    if ((ies || have_aim) && !l.point)
        return qcli_usage_error("render: --ies, --aim and --up shape a --point lamp");
    if (have_aim && !ies)
        return qcli_usage_error("render: --aim and --up orient an --ies lamp: give --ies FILE.ies");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    l.falloff = (int)falloff;
    qtool_ies prof;
    qtool_ies_lamp lamp;
    if (ies) {
        char ierr[512];
        if (qtool_ies_read(ies, &prof, ierr, sizeof ierr) != 0) {
            fprintf(stderr, "qibl: render: %s\n", ierr);
            return 1;
        }
        if (qtool_ies_lamp_init(&lamp, &prof, aim, up) != 0) {
            fprintf(stderr, "qibl: render: %s: a zero --aim, an --up parallel to it, or a dark profile\n", ies);
            qtool_ies_free(&prof);
            return 1;
        }
    }
    qtool_rt_scene s;
    if (qcli_scene_load(&so, &s) != 0) {
        if (ies)
            qtool_ies_free(&prof);
        return 1;
    }
    size_t np = (size_t)so.w * so.h;
    double *lin = malloc(np * 3 * sizeof(double));
    float *dep = malloc(np * sizeof(float)), *f3 = malloc(np * 3 * sizeof(float));
    uint8_t *rgb8 = malloc(np * 3);
    int rc = 1;
    char err[512];
    if (!lin || !dep || !f3 || !rgb8) {
        fprintf(stderr, "qibl: render: out of memory\n");
        goto done;
    }
    if (l.point && !have_rgb && point_default(&s, &so, &l) != 0)
        goto done;
    double t0 = qcli_now();
    qtool_rt_render_gonio(&s, so.w, so.h, so.kind, &l, ies ? qtool_ies_lamp_scale : NULL, ies ? &lamp : NULL,
                          so.threads, lin, dep, NULL);
    double ms = (qcli_now() - t0) * 1e3;
    if (png) {
        if (ies) /* the frame just rendered, through the same framebuffer code as truth8 */
            qtool_bake_lin_to8(lin, so.w, so.h, rgb8);
        else
            qtool_bake_truth8(&s, so.w, so.h, so.kind, &l, so.threads, rgb8, NULL);
        if (qtool_png_write_rgb8(png, (int)so.w, (int)so.h, rgb8, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            goto done;
        }
        qcli_warn_dark(png, rgb8, np);
    }
    if (pfm || exr) {
        for (size_t i = 0; i < np * 3; ++i)
            f3[i] = (float)lin[i];
        if ((pfm && qtool_pfm_write(pfm, (int)so.w, (int)so.h, 3, f3, err, sizeof err) != 0) ||
            (exr && qtool_exr_write(exr, (int)so.w, (int)so.h, f3, QTOOL_EXR_FLOAT, QTOOL_EXR_ZIP, err, sizeof err) != 0)) {
            fprintf(stderr, "qibl: %s\n", err);
            goto done;
        }
    }
    if (depth && qtool_pfm_write(depth, (int)so.w, (int)so.h, 1, dep, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto done;
    }
    printf("rendered %ux%u %s panorama of %s, %zu triangles, %s light, %.0f ms on %d threads\n", so.w, so.h,
           so.kind == QTOOL_PANO_CYLINDRICAL ? "cylindrical" : "equirectangular", so.scene ? so.scene : "the built-in courtyard",
           s.ntri, l.point ? "point" : "directional", ms, so.threads);
    rc = 0;
done:
    free(lin), free(dep), free(f3), free(rgb8);
    qtool_rt_scene_free(&s);
    if (ies)
        qtool_ies_free(&prof);
    return rc;
}

/* ---- evaluation set ------------------------------------------------------------------------------ */

/* Novel lights: suns in the upper hemisphere not in the bake's direction set, lamps in the scene. */
void qcli_eval_lights(int obj_prop, int ndir, int npoint, qtool_rt_light *out)
{
    for (int i = 0; i < ndir; ++i) {
        double el = 0.35 + 1.0 * (i + 0.37) / ndir, az = 2.39996 * i + 0.61;
        qtool_rt_light l = {0, {cos(el) * cos(az), cos(el) * sin(az), sin(el)}, {0, 0, 0}, {2.6, 2.4, 2.1}, 1};
        out[i] = l;
    }
    for (int i = 0; i < npoint; ++i) {
        double a = 2.39996 * i + 1.1, r = 1.6 + 1.2 * ((i * 7) % 5) / 5.0;
        double cx = obj_prop ? QTOOL_RT_PROP_X : 0.0;
        qtool_rt_light l = {1, {0, 0, 1}, {cx + r * cos(a), r * sin(a), -0.6 + 0.35 * (i % 4)}, {5.0, 4.4, 3.6}, 1};
        out[ndir + i] = l;
    }
}

typedef struct {
    int n, ndir;
    qtool_rt_light *l;
    uint8_t **truth, *mask;
    size_t np;
} evalset;

static int eval_build(evalset *e, const qtool_rt_scene *s, const qcli_scene *so, int ndir, int npoint)
{
    e->n = ndir + npoint, e->ndir = ndir, e->np = (size_t)so->w * so->h;
    e->l = malloc(sizeof *e->l * (size_t)e->n);
    e->truth = calloc((size_t)e->n, sizeof *e->truth);
    e->mask = malloc(e->np);
    if (!e->l || !e->truth || !e->mask)
        return -1;
    qcli_eval_lights(so->scene && !so->raw && strcmp(so->scene, "builtin") != 0, ndir, npoint, e->l);
    for (int i = 0; i < e->n; ++i) {
        e->truth[i] = malloc(e->np * 3);
        if (!e->truth[i] || qtool_bake_truth8(s, so->w, so->h, so->kind, &e->l[i], so->threads, e->truth[i], e->mask) != 0)
            return -1;
    }
    return 0;
}

static void eval_free(evalset *e)
{
    for (int i = 0; e->truth && i < e->n; ++i)
        free(e->truth[i]);
    free(e->truth), free(e->l), free(e->mask);
}

/* PSNR (of the mean MSE) of an asset over the directional [0, ndir) or point [ndir, n) lights */
static double eval_psnr(const evalset *e, const uint8_t *asset, size_t n, int point, int use_lut, uint8_t *tmp)
{
    double mse = 0;
    int cnt = 0;
    for (int i = point ? e->ndir : 0; i < (point ? e->n : e->ndir); ++i) {
        if (qtool_bake_relight8(asset, n, &e->l[i], use_lut, tmp, NULL) != 0)
            return -1;
        mse += qtool_bake_mse(tmp, e->truth[i], e->mask, e->np), ++cnt;
    }
    mse /= cnt ? cnt : 1;
    return qtool_ref_psnr8(mse);
}

/* ---- qibl bake / merge --------------------------------------------------------------------------- */

static int write_bytes(const char *path, const uint8_t *b, size_t n)
{
    char err[1200];
    if (qtool_io_write_atomic(path, b, n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return -1;
    }
    return 0;
}

/* what `qibl bake` adds beside the shadowed maps: unshadowed maps (SHMU), light paths (LPTH) and
 * lamp occlusion (LOCC) */
typedef struct {
    const qtool_gen_maps *mu; /* NULL: none */
    uint8_t *paths[9];       /* NULL-terminated */
    size_t sizes[9];
    int npaths;
    uint8_t *locc; /* NULL: none */
    size_t locc_n;
} extras;

/* SUMS.u (the unshadowed partial sums) and SUMS.x (the extras file) beside a partial-sums file */
static void side_name(char *buf, size_t n, const char *sums, const char *ext)
{
    snprintf(buf, n, "%s.%s", sums, ext);
}

static int finish_asset(const qtool_bake_sums *sums, uint32_t k, uint32_t lut, qtool_proj_method method,
                        uint32_t layout, const char *out, const extras *x)
{
    qtool_gen_maps m;
    uint8_t *bytes = NULL;
    size_t n = 0;
    if (qtool_bake_coeffs(sums, k, method, &m) != 0) {
        if (method == QTOOL_PROJ_LSQ)
            fprintf(stderr, "qibl: %s: cannot project by least squares: %u directions are too few for k = %u (or out "
                    "of memory)\n", out, sums->ndirs, k);
        else
            fprintf(stderr, "qibl: %s: cannot project: out of memory\n", out);
        return 1;
    }
    int rc = qtool_bake_asset_full(&m, x->mu, lut, layout, x->paths, x->sizes, &bytes, &n);
    qtool_gen_free(&m);
    if (rc == 0 && x->locc) {
        uint8_t *b2 = NULL;
        size_t n2 = 0;
        rc = qtool_bake_asset_add(bytes, n, QIBL_CHUNK_LOCC, x->locc, x->locc_n, &b2, &n2);
        free(bytes);
        bytes = b2, n = n2;
    }
    if (rc != 0) {
        fprintf(stderr, "qibl: %s: cannot build the asset (out of memory)\n", out);
        return 1;
    }
    rc = write_bytes(out, bytes, n);
    free(bytes);
    if (rc != 0)
        return 1;
    printf("wrote %s: %ux%u, k = %u (%s), %u light directions, %s", out, sums->w, sums->h, k,
           method == QTOOL_PROJ_LSQ ? "least squares" : "quadrature", sums->ndirs,
           lut ? "P map and cube-map Y LUT" : "P map");
    if (x->mu)
        printf(", unshadowed maps k = %u", x->mu->k);
    if (x->npaths)
        printf(", %d light path%s", x->npaths, x->npaths > 1 ? "s" : "");
    if (x->locc)
        printf(", lamp occlusion");
    printf(", %zu bytes\n", n);
    return 0;
}

/* --progress=lines for a stage without rows (a light path, the lamp occlusion): done of total */
static void progress_line(const char *stage, uint32_t done, uint32_t total)
{
    fprintf(stderr, "progress: stage=%s done=%u total=%u fraction=%.4f\n", stage, done, total, (double)done / total);
    fflush(stderr);
}

int qcli_cmd_bake(int argc, char **argv)
{
    qcli_scene so;
    qcli_scene_defaults(&so);
    const char *out = NULL, *sums_out = NULL;
    long k = 16, lut = 32, ndirs = 512, shard = 0, nshards = 1, uk = 9, steps = 64, lamp_samples = 64;
    double budget = 0, lamp_box[6];
    int has_box = 0;
    int lsq = 0, quiet = 0, npaths = 0, progress = -1; /* -1: bar on a terminal, lines elsewhere */
    uint32_t layout = QIBL_SHMAPS_PLANAR;
    qtool_bake_path paths[8];
    char perr[400];
    for (int i = 1; i < argc; ++i) {
        int r = qcli_scene_opt(argc, argv, &i, &so);
        if (r < 0)
            return 2;
        if (r)
            continue;
        const char *a = argv[i];
        if (strcmp(a, "-o") == 0 && i + 1 < argc)
            out = argv[++i];
        else if (strcmp(a, "--k") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 25, &k) != 0)
                return qcli_usage_error("--k needs an integer in 1..25");
        } else if ((r = qcli_lut_size_opt(argc, argv, &i, 0, &lut)) != 0) {
            if (r < 0)
                return 2;
        } else if (strcmp(a, "--dirs") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 16, 65536, &ndirs) != 0)
                return qcli_usage_error("--dirs needs an integer in 16..65536");
        } else if (strcmp(a, "--shard") == 0 && i + 1 < argc) {
            char tail;
            if (sscanf(argv[++i], "%ld/%ld%c", &shard, &nshards, &tail) != 2 || nshards < 1 || nshards > 4096 ||
                shard < 0 || shard >= nshards)
                return qcli_usage_error("--shard needs I/N with 0 <= I < N <= 4096");
        } else if (strcmp(a, "--sums") == 0 && i + 1 < argc)
            sums_out = argv[++i];
        else if (strcmp(a, "--budget") == 0 && i + 1 < argc) {
            char *end;
            budget = strtod(argv[++i], &end);
            if (*end || !(budget > 0 && budget < 99))
                return qcli_usage_error("--budget needs a PSNR in dB (0..99)");
        } else if (strcmp(a, "--unshadowed-k") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 0, 25, &uk) != 0)
                return qcli_usage_error("--unshadowed-k needs an integer in 0..25 (0: no unshadowed maps)");
        } else if (strcmp(a, "--path-steps") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 2, 4096, &steps) != 0)
                return qcli_usage_error("--path-steps needs an integer in 2..4096");
        } else if ((strcmp(a, "--sun-path") == 0 || strcmp(a, "--lamp-track") == 0) && i + 1 < argc) {
            if (npaths == 8)
                return qcli_usage_error("%s: at most 8 light paths per asset", a);
            qtool_bake_path *pp = &paths[npaths];
            memset(pp, 0, sizeof *pp);
            int bad = a[2] == 's' ? qtool_bake_path_parse_sun(argv[++i], pp, perr, sizeof perr)
                                  : qtool_bake_path_parse_track(argv[++i], pp, perr, sizeof perr);
            if (bad)
                return qcli_usage_error("%s", perr);
            npaths++;
        } else if (strcmp(a, "--lamp-box") == 0 && i + 1 < argc) {
            char tail;
            double *b = lamp_box;
            if (sscanf(argv[++i], "%lf,%lf,%lf,%lf,%lf,%lf%c", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &tail) != 6 ||
                !(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5]) || !(fabs(b[0]) < 1e6 && fabs(b[1]) < 1e6 &&
                fabs(b[2]) < 1e6 && fabs(b[3]) < 1e6 && fabs(b[4]) < 1e6 && fabs(b[5]) < 1e6))
                return qcli_usage_error("--lamp-box needs X0,Y0,Z0,X1,Y1,Z1 with X0 <= X1, Y0 <= Y1, Z0 <= Z1 (|v| < 1e6): "
                                        "'%s'", argv[i]);
            has_box = 1;
        } else if (strcmp(a, "--lamp-samples") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 4096, &lamp_samples) != 0)
                return qcli_usage_error("--lamp-samples needs an integer in 1..4096");
        } else if (strcmp(a, "--lsq") == 0)
            lsq = 1;
        else if (strcmp(a, "--quiet") == 0)
            quiet = 1;
        else if (strncmp(a, "--progress=", 11) == 0 || (strcmp(a, "--progress") == 0 && i + 1 < argc)) {
            const char *m = a[10] == '=' ? a + 11 : argv[++i];
            progress = strcmp(m, "none") == 0 ? 0 : strcmp(m, "bar") == 0 ? 1 : strcmp(m, "lines") == 0 ? 2 : -2;
            if (progress == -2)
                return qcli_usage_error("--progress is bar, lines or none: '%s'", m);
        } else if (strcmp(a, "--layout") == 0 && i + 1 < argc) {
            if (qcli_parse_layout(argv[++i], &layout) != 0)
                return qcli_usage_error("--layout is planar or interleaved");
        } else
            return qcli_usage_error("bake: unknown argument '%s' (see qibl help bake)", a);
    }
    if (quiet)
        progress = 0;
    else if (progress < 0)
        progress = isatty(2) ? 1 : 2;
    if (nshards > 1 && !sums_out)
        return qcli_usage_error("bake --shard needs --sums FILE (the partial sums for qibl merge)");
    if (!out && !sums_out)
        return qcli_usage_error("bake needs -o ASSET (or --sums FILE)");
    uint32_t nblocks = (uint32_t)((ndirs + QTOOL_BAKE_BLOCK - 1) / QTOOL_BAKE_BLOCK);
    if ((uint32_t)nshards > nblocks)
        return qcli_usage_error("--shard: %ld shards but only %u blocks of %u directions", nshards, nblocks,
                                    QTOOL_BAKE_BLOCK);
    if (out && nshards > 1)
        return qcli_usage_error("a shard writes partial sums only (--sums); qibl merge writes the asset");
    if ((npaths || has_box) && uk == 0)
        return qcli_usage_error("light paths and --lamp-box need the unshadowed maps (--unshadowed-k 1..25)");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    qtool_rt_scene s;
    if (qcli_scene_load(&so, &s) != 0)
        return 1;
    qtool_bake_sums sums;
    double t0 = qcli_now();
    uint32_t kacc = budget > 0 ? 25 : (uint32_t)k;
    if (qtool_bake_run_progress(&s, so.w, so.h, so.kind, (uint32_t)ndirs, kacc, (uint32_t)shard, (uint32_t)nshards,
                                so.threads, progress, 0, &sums) != 0) {
        fprintf(stderr, "qibl: bake: out of memory\n");
        qtool_rt_scene_free(&s);
        return 1;
    }
    double secs = qcli_now() - t0;
    if (!quiet)
        fprintf(stderr, "bake: %ux%u, %ld directions%s, %zu triangles, %.1f s on %d threads\n", so.w, so.h, ndirs,
                nshards > 1 ? " (this shard's share)" : "", s.ntri, secs, so.threads);
    int rc = 0;
    char err[512];
    /* the unshadowed maps and the light paths, for the asset (shards carry the shadowed sums only) */
    extras x;
    qtool_gen_maps mu = {0};
    memset(&x, 0, sizeof x);
    /* a shard (partial sums, no asset) carries its share of the unshadowed sums in SUMS.u and, from
     * shard 0, the per-pixel chunks in SUMS.x, so qibl merge makes the same asset as one bake */
    int shard_mode = !out && sums_out;
    char side[2][4200];
    if (shard_mode)
        side_name(side[0], sizeof side[0], sums_out, "u"), side_name(side[1], sizeof side[1], sums_out, "x");
    if ((out || shard_mode) && uk > 0) {
        qtool_bake_sums us;
        double t1 = qcli_now();
        if (qtool_bake_run_progress(&s, so.w, so.h, so.kind, (uint32_t)ndirs, (uint32_t)uk, (uint32_t)shard,
                                    (uint32_t)nshards, so.threads, progress == 2 ? 2 : 0, 1, &us) != 0 ||
            (out && qtool_bake_coeffs(&us, (uint32_t)uk, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, &mu) != 0)) {
            fprintf(stderr, "qibl: bake: out of memory (unshadowed maps)\n");
            rc = 1;
        } else if (shard_mode && qtool_bake_sums_write(&us, side[0], err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        }
        qtool_bake_sums_free(&us);
        x.mu = rc == 0 && out ? &mu : NULL;
        /* per-pixel chunks: each shard bakes its rows (y % nshards == shard), merge joins them */
        for (int p = 0; rc == 0 && p < npaths; ++p) {
            double st[2];
            if (qtool_bake_path_chunk_shard(&s, so.w, so.h, so.kind, &paths[p], (uint32_t)steps, 65, (uint32_t)shard,
                                           (uint32_t)nshards, so.threads, &x.paths[p], &x.sizes[p], st) != 0) {
                fprintf(stderr, "qibl: bake: out of memory (light path %d)\n", p + 1);
                rc = 1;
            } else if (!quiet) {
                fprintf(stderr, "bake: light path %d (%s): %.2f visibility edges per pixel%s%s\n", p + 1,
                        paths[p].kind ? "lamp track" : "sun path", st[0], nshards > 1 ? " (this shard's rows)" : "",
                        st[1] > 0 ? " (some pixels clipped at 255 edges)" : "");
                if (progress == 2)
                    progress_line("path", (uint32_t)p + 1, (uint32_t)npaths);
            }
            x.npaths = p + 1;
        }
        if (rc == 0 && has_box) {
            uint8_t *occ = malloc((size_t)so.w * so.h);
            if (!occ || qtool_bake_lamp_occlusion_shard(&s, so.w, so.h, so.kind, lamp_box, (uint32_t)lamp_samples,
                                                        (uint32_t)shard, (uint32_t)nshards, so.threads, occ) != 0 ||
                qtool_bake_locc_payload(so.w, so.h, occ, &x.locc, &x.locc_n) != 0) {
                fprintf(stderr, "qibl: bake: out of memory (lamp occlusion)\n");
                rc = 1;
            }
            free(occ);
            if (rc == 0 && progress == 2)
                progress_line("occlusion", 1, 1);
        }
        if (shard_mode && rc == 0) {
            qtool_extras xf;
            memset(&xf, 0, sizeof xf);
            xf.shard = (uint32_t)shard, xf.nshards = (uint32_t)nshards;
            for (int p = 0; p < x.npaths; ++p)
                xf.type[xf.count] = QIBL_CHUNK_LPTH, xf.data[xf.count] = x.paths[p], xf.size[xf.count++] = x.sizes[p];
            if (x.locc)
                xf.type[xf.count] = QIBL_CHUNK_LOCC, xf.data[xf.count] = x.locc, xf.size[xf.count++] = x.locc_n;
            /* written also with no chunk: a shard baked without --sun-path is then refused by name at
             * the merge instead of its rows (or the whole path) going missing */
            if (qtool_extras_write(&xf, side[1], err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                rc = 1;
            }
        }
        if (!quiet && rc == 0)
            fprintf(stderr, "bake: unshadowed maps (k = %ld) and %d light path%s: %.1f s\n", uk, npaths,
                    npaths == 1 ? "" : "s", qcli_now() - t1);
    } else if (shard_mode) {
        (void)unlink(side[0]), (void)unlink(side[1]);
    }
    if (rc == 0 && sums_out) { /* "wrote" only for sums that were written (not after a failure) */
        if (qtool_bake_sums_write(&sums, sums_out, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            rc = 1;
        } else {
            printf("wrote %s: partial sums of shard %ld/%ld\n", sums_out, shard, nshards);
        }
    }
    if (rc == 0 && out && budget > 0) {
        /* smallest band-complete k (and LUT) whose held-out PSNR reaches the budget */
        evalset e = {0};
        uint8_t *tmp = malloc(sums.w * (size_t)sums.h * 3);
        uint32_t chosen = 0, chosen_lut = 0;
        int reached = 0, lut_reached = 0; /* whether the chosen k (LUT) met its target, for the summary */
        double pk = 0;
        if (!tmp || eval_build(&e, &s, &so, 8, 4) != 0) {
            fprintf(stderr, "qibl: bake: out of memory\n");
            rc = 1;
        }
        printf("budget %.2f dB: PSNR of the core's relit frames against ground truth, 8 novel suns (mean MSE):\n", budget);
        for (uint32_t kk = 1; rc == 0 && kk <= 25 && !chosen; kk = (uint32_t)((sqrt(kk) + 1) * (sqrt(kk) + 1) + 0.5)) {
            qtool_gen_maps m;
            uint8_t *b = NULL;
            size_t n = 0;
            if (qtool_bake_coeffs(&sums, kk, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, &m) != 0 ||
                qtool_bake_asset(&m, 0, &b, &n) != 0) {
                rc = 1;
                break;
            }
            qtool_gen_free(&m);
            pk = eval_psnr(&e, b, n, 0, 0, tmp);
            printf("  k = %2u: %6.2f dB %s\n", kk, pk, pk >= budget ? "<- reaches the budget" : "");
            if (pk >= budget || kk == 25)
                chosen = kk, reached = pk >= budget;
            free(b);
        }
        if (rc == 0) {
            if (pk < budget)
                printf("  no k <= 25 reaches %.2f dB; using k = 25 (more directions or a smoother scene would be needed)\n",
                       budget);
            /* LUT: the smallest face size whose point-light PSNR is within 0.1 dB of direct SH evaluation */
            qtool_gen_maps m;
            uint8_t *b = NULL;
            size_t n = 0;
            qtool_bake_coeffs(&sums, chosen, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, &m);
            qtool_bake_asset(&m, 0, &b, &n);
            double direct = eval_psnr(&e, b, n, 1, 0, tmp);
            free(b);
            printf("point lights (4 lamps), k = %u: direct SH evaluation %.2f dB; cube-map LUT face size:\n", chosen, direct);
            for (uint32_t f = 8; f <= 128; f *= 2) {
                qtool_bake_asset(&m, f, &b, &n);
                double p = eval_psnr(&e, b, n, 1, 1, tmp);
                free(b);
                printf("  %3u^2: %6.2f dB%s\n", f, p, p >= direct - 0.1 ? " <- within 0.1 dB of direct evaluation" : "");
                if (p >= direct - 0.1 || f == 128) {
                    chosen_lut = f, lut_reached = p >= direct - 0.1;
                    break;
                }
            }
            qtool_gen_free(&m);
            /* one summary that agrees with the table above: the k line says "reaches" only if it did */
            if (reached)
                printf("chose k = %u: the smallest k whose novel-sun PSNR reaches %.2f dB", chosen, budget);
            else
                printf("chose k = %u: the largest k, since none reaches %.2f dB (best %.2f dB)", chosen, budget, pk);
            if (lut_reached)
                printf("; a %u^2 LUT: the smallest that costs point lights under 0.1 dB against evaluating the SH "
                       "polynomials per pixel\n", chosen_lut);
            else
                printf("; a %u^2 LUT: the largest tried, none within 0.1 dB of evaluating the SH polynomials per "
                       "pixel\n", chosen_lut);
            rc = finish_asset(&sums, chosen, chosen_lut, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, layout, out, &x);
        }
        eval_free(&e);
        free(tmp);
    } else if (rc == 0 && out) {
        rc = finish_asset(&sums, (uint32_t)k, (uint32_t)lut, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, layout, out, &x);
    }
    for (int p = 0; p < 8; ++p)
        free(x.paths[p]);
    free(x.locc);
    qtool_gen_free(&mu);
    qtool_bake_sums_free(&sums);
    qtool_rt_scene_free(&s);
    return rc;
}

static int file_exists(const char *p)
{
    return *p && access(p, F_OK) == 0;
}

/* input i's side file: the one its manifest line names (side[i], "" for none), else SUMS.ext */
static void side_of(char *buf, size_t n, char *const *in, char *const *side, int i, const char *ext)
{
    if (side && side[i])
        snprintf(buf, n, "%s", side[i]);
    else
        side_name(buf, n, in[i], ext);
}

/* A manifest (qibl merge --manifest): one line per shard, "shard I/N SUMS [SUMS.u [SUMS.x]]" ("-"
 * for a side file the shard does not have; blank lines and lines from '#' skipped; names without
 * blanks). At most QCLI_MANIFEST_MAX_BYTES and QTOOL_BAKE_MAX_SHARDS lines, checked before use. The
 * entries are appended to in/side_u/side_x/want (want[i] = I * 65536 + N, -1 for a plain argument),
 * pointing into *buf (kept until the merge ends). 0, or -1 after a message naming the line. */
#define QCLI_MANIFEST_MAX_BYTES ((size_t)16 << 20)
static int read_manifest(const char *path, uint8_t **buf, char **in, char **side_u, char **side_x, long *want, int *nin,
                         int cap)
{
    static const qtool_io_kind kind = {"a shard manifest", 1, QCLI_MANIFEST_MAX_BYTES, 0, NULL};
    char err[1200];
    size_t n;
    if (qtool_io_load(path, &kind, buf, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return -1;
    }
    uint8_t *grown = realloc(*buf, n + 1);
    if (!grown) {
        fprintf(stderr, "qibl: %s: out of memory\n", path);
        return -1;
    }
    *buf = grown;
    char *t = (char *)grown;
    t[n] = '\0';
    if (strlen(t) != n) {
        fprintf(stderr, "qibl: %s: a NUL byte: not a text manifest\n", path);
        return -1;
    }
    int line = 0, shards = 0;
    for (char *l = t, *next; l; l = next) {
        next = strchr(l, '\n');
        if (next)
            *next++ = '\0';
        ++line;
        char *tok[6];
        int nt = 0;
        for (char *w = strtok(l, " \t\r"); w && nt < 6; w = strtok(NULL, " \t\r"))
            tok[nt++] = w;
        if (nt == 0 || tok[0][0] == '#')
            continue;
        long i, nn;
        char tail;
        if (nt < 3 || nt > 5 || strcmp(tok[0], "shard") != 0 || sscanf(tok[1], "%ld/%ld%c", &i, &nn, &tail) != 2 ||
            nn < 1 || nn > (long)QTOOL_BAKE_MAX_SHARDS || i < 0 || i >= nn) {
            fprintf(stderr, "qibl: %s:%d: not \"shard I/N SUMS [SUMS.u [SUMS.x]]\" with 0 <= I < N <= %u\n", path, line,
                    QTOOL_BAKE_MAX_SHARDS);
            return -1;
        }
        if (++shards > (int)QTOOL_BAKE_MAX_SHARDS || *nin >= cap) {
            fprintf(stderr, "qibl: %s:%d: more than %u shards\n", path, line, QTOOL_BAKE_MAX_SHARDS);
            return -1;
        }
        in[*nin] = tok[2];
        side_u[*nin] = nt > 3 ? (strcmp(tok[3], "-") == 0 ? (char *)"" : tok[3]) : NULL;
        side_x[*nin] = nt > 4 ? (strcmp(tok[4], "-") == 0 ? (char *)"" : tok[4]) : NULL;
        want[*nin] = i * 65536 + nn;
        ++*nin;
    }
    if (shards == 0) {
        fprintf(stderr, "qibl: %s: no shard line\n", path);
        return -1;
    }
    return 0;
}

/* The unshadowed maps from the given shards' SUMS.u (all or none: a bake writes them for every
 * shard) and their light paths and lamp occlusion joined from every SUMS.x, into x. seen[s] - 1 is the
 * input of shard s, 0 when absent (a partial merge). partial_out (the merge's --sums, may be NULL): the
 * unshadowed sums and the joined extras are also written beside it (.u, .x) as shard total->shard of
 * total->nshards, so a later merge of it alone loses nothing; project: the unshadowed maps into mu
 * (for an asset). 0, or -1 with a message naming the file. */
static int merge_extras(char **in, char *const *side_u, char *const *side_x, const int *seen, uint32_t nsh,
                        const qtool_bake_sums *total, int lsq, const char *partial_out, int project,
                        qtool_gen_maps *mu, qtool_extras *xx, extras *x)
{
    char name[4200], err[1200];
    uint32_t have = 0, given = 0, first = nsh;
    for (uint32_t s = 0; s < nsh; ++s) {
        if (!seen[s])
            continue;
        first = first < s ? first : s;
        given++;
        side_of(name, sizeof name, in, side_u, seen[s] - 1, "u");
        have += file_exists(name) ? 1u : 0u;
    }
    if (have != 0 && have != given) {
        for (uint32_t s = 0; s < nsh; ++s) {
            if (!seen[s])
                continue;
            side_of(name, sizeof name, in, side_u, seen[s] - 1, "u");
            if (!file_exists(name)) {
                fprintf(stderr, "qibl: merge: %s is missing (the unshadowed sums of shard %u/%u; %u other shard%s "
                        "have theirs)\n", name, s, nsh, have, have == 1 ? "" : "s");
                return -1;
            }
        }
    }
    qtool_bake_sums tu = {0}, part;
    int rc = -1;
    for (uint32_t s = 0; have && s < nsh; ++s) {
        if (!seen[s])
            continue;
        side_of(name, sizeof name, in, side_u, seen[s] - 1, "u");
        if (qtool_bake_sums_read(name, &part, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            goto done;
        }
        if (part.shard != s || part.nshards != nsh || part.w != total->w || part.h != total->h ||
            part.ndirs != total->ndirs || part.kind != total->kind ||
            memcmp(part.pmap, total->pmap, (size_t)part.w * part.h * 12) != 0) {
            fprintf(stderr, "qibl: %s: not the unshadowed sums of %s (shard %u/%u of another bake)\n", name,
                    in[seen[s] - 1], part.shard, part.nshards);
            qtool_bake_sums_free(&part);
            goto done;
        }
        if (s == first) {
            tu = part;
            continue;
        }
        if (qtool_bake_sums_add(&tu, &part, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s: %s\n", name, err);
            qtool_bake_sums_free(&part);
            goto done;
        }
        qtool_bake_sums_free(&part);
    }
    if (have && project) {
        if (qtool_bake_coeffs(&tu, tu.k, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, mu) != 0) {
            fprintf(stderr, "qibl: merge: cannot project the unshadowed sums (too few directions or no memory)\n");
            goto done;
        }
        x->mu = mu;
    }
    /* every given shard's extras (its rows of the light paths and lamp occlusion): all or none */
    uint32_t hx = 0;
    for (uint32_t s = 0; s < nsh; ++s) {
        if (!seen[s])
            continue;
        side_of(name, sizeof name, in, side_x, seen[s] - 1, "x");
        hx += file_exists(name) ? 1u : 0u;
    }
    if (hx != 0 && !have) {
        fprintf(stderr, "qibl: merge: light paths (.x files) without the unshadowed sums (.u files)\n");
        goto done;
    }
    if (hx != 0 && hx != given) {
        for (uint32_t s = 0; s < nsh; ++s) {
            if (!seen[s])
                continue;
            side_of(name, sizeof name, in, side_x, seen[s] - 1, "x");
            if (!file_exists(name)) {
                fprintf(stderr, "qibl: merge: %s is missing (the light paths and lamp occlusion of shard %u/%u; %u other "
                        "shard%s have theirs)\n", name, s, nsh, hx, hx == 1 ? "" : "s");
                goto done;
            }
        }
    }
    if (hx) {
        qtool_extras *parts = calloc(nsh, sizeof *parts);
        const qtool_extras **byshard = calloc(nsh, sizeof *byshard);
        char **names = calloc(nsh, sizeof *names);
        int bad = !parts || !names || !byshard;
        if (bad)
            fprintf(stderr, "qibl: merge: out of memory\n");
        for (uint32_t s = 0; !bad && s < nsh; ++s) {
            if (!seen[s])
                continue;
            side_of(name, sizeof name, in, side_x, seen[s] - 1, "x");
            names[s] = malloc(strlen(name) + 1);
            if (!names[s]) {
                fprintf(stderr, "qibl: merge: out of memory\n");
                bad = 1;
            } else if (strcpy(names[s], name), qtool_extras_read(name, &parts[s], err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
            } else {
                byshard[s] = &parts[s];
            }
        }
        if (!bad && qtool_extras_join(byshard, (const char *const *)names, nsh, total->w, total->h, xx, err,
                                      sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            bad = 1;
        }
        for (uint32_t s = 0; parts && names && s < nsh; ++s)
            qtool_extras_free(&parts[s]), free(names[s]);
        free(parts), free(names), free(byshard);
        if (bad)
            goto done;
        for (uint32_t i = 0; i < xx->count; ++i) {
            if (xx->type[i] == QIBL_CHUNK_LOCC && !x->locc)
                x->locc = xx->data[i], x->locc_n = xx->size[i];
            else if (xx->type[i] == QIBL_CHUNK_LPTH && x->npaths < 8)
                x->paths[x->npaths] = xx->data[i], x->sizes[x->npaths++] = xx->size[i];
            else {
                fprintf(stderr, "qibl: merge: more than 8 light paths or two lamp occlusions\n");
                goto done;
            }
        }
    }
    if (partial_out) { /* a partial sum: its side files as one shard of the coarser split */
        char side[4200];
        side_name(side, sizeof side, partial_out, "u");
        if (have) {
            tu.shard = total->shard, tu.nshards = total->nshards;
            if (qtool_bake_sums_write(&tu, side, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                goto done;
            }
        } else {
            (void)unlink(side); /* a stale one must not reach the next merge */
        }
        side_name(side, sizeof side, partial_out, "x");
        if (hx) {
            xx->shard = total->shard, xx->nshards = total->nshards;
            if (qtool_extras_write(xx, side, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                goto done;
            }
        } else {
            (void)unlink(side);
        }
    }
    rc = 0;
done:
    qtool_bake_sums_free(&tu);
    return rc;
}

int qcli_cmd_merge(int argc, char **argv)
{
    const char *out = NULL, *sums_out = NULL, *manifest = NULL;
    long k = 0, lut = 32;
    int lsq = 0, nin = 0, r;
    uint32_t layout = QIBL_SHMAPS_PLANAR;
    char **in = malloc(sizeof(char *) * (size_t)argc);
    if (!in)
        return 1;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "-o") == 0 && i + 1 < argc)
            out = argv[++i];
        else if (strcmp(a, "--sums") == 0 && i + 1 < argc)
            sums_out = argv[++i];
        else if (strcmp(a, "--manifest") == 0 && i + 1 < argc)
            manifest = argv[++i];
        else if (strcmp(a, "--k") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 25, &k) != 0) {
                free(in);
                return qcli_usage_error("--k needs an integer in 1..25");
            }
        } else if ((r = qcli_lut_size_opt(argc, argv, &i, 0, &lut)) != 0) {
            if (r < 0) {
                free(in);
                return 2;
            }
        } else if (strcmp(a, "--layout") == 0 && i + 1 < argc) {
            if (qcli_parse_layout(argv[++i], &layout) != 0) {
                free(in);
                return qcli_usage_error("--layout is planar or interleaved");
            }
        } else if (strcmp(a, "--lsq") == 0)
            lsq = 1;
        else if (a[0] != '-')
            in[nin++] = argv[i];
        else {
            free(in);
            return qcli_usage_error("merge: unknown argument '%s' (see qibl help merge)", a);
        }
    }
    if ((nin == 0 && !manifest) || (!out && !sums_out)) {
        free(in);
        return qcli_usage_error("usage: qibl merge (-o ASSET | --sums OUT | both) [--k K] [--lut-size N] [--lsq] "
                                "(--manifest FILE | SUMS...)");
    }
    if (qcli_parse_only) { /* fuzz_cliopts: the options only */
        free(in);
        return 0;
    }
    /* the manifest's shards after the plain arguments, with their side files and I/N named */
    int cap = nin + (int)QTOOL_BAKE_MAX_SHARDS;
    char **all = malloc(sizeof(char *) * (size_t)cap), **side_u = calloc((size_t)cap, sizeof(char *)),
         **side_x = calloc((size_t)cap, sizeof(char *));
    long *want = malloc(sizeof(long) * (size_t)cap);
    uint8_t *mbuf = NULL;
    if (!all || !side_u || !side_x || !want) {
        fprintf(stderr, "qibl: merge: out of memory\n");
        free(all), free(side_u), free(side_x), free(want), free(in);
        return 1;
    }
    memcpy(all, in, sizeof(char *) * (size_t)nin);
    free(in);
    in = all;
    for (int i = 0; i < nin; ++i)
        want[i] = -1;
    if (manifest && read_manifest(manifest, &mbuf, in, side_u, side_x, want, &nin, cap) != 0) {
        free(in), free(side_u), free(side_x), free(want), free(mbuf);
        return 1;
    }
    qtool_bake_sums total = {0}, part;
    qtool_gen_maps mu = {0};
    qtool_extras xx;
    extras x;
    char err[1200];
    int rc = 1;
    memset(&xx, 0, sizeof xx), memset(&x, 0, sizeof x);
    int *seen = NULL; /* per shard index: 1 + the input it came from, 0 if none yet */
    for (int i = 0; i < nin; ++i) {
        /* every header is validated by the reader (shard < nshards <= QTOOL_BAKE_MAX_SHARDS) before use */
        if (qtool_bake_sums_read(in[i], &part, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            goto done;
        }
        if (want[i] >= 0 && (part.shard != (uint32_t)(want[i] / 65536) || part.nshards != (uint32_t)(want[i] % 65536))) {
            fprintf(stderr, "qibl: %s: the manifest names it shard %ld/%ld, the file is shard %u/%u\n", in[i],
                    want[i] / 65536, want[i] % 65536, part.shard, part.nshards);
            qtool_bake_sums_free(&part);
            goto done;
        }
        if (i == 0) {
            total = part;
            seen = calloc(part.nshards, sizeof *seen);
            if (!seen) {
                fprintf(stderr, "qibl: merge: out of memory\n");
                goto done;
            }
            seen[part.shard] = 1;
            continue;
        }
        /* same bake (and so the same shard count) first: only then is part.shard an index into seen */
        if (qtool_bake_sums_compatible(&total, &part, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s: %s (first input %s)\n", in[i], err, in[0]);
            qtool_bake_sums_free(&part);
            goto done;
        }
        if (seen[part.shard]) {
            fprintf(stderr, "qibl: %s: shard %u/%u given twice (also %s)\n", in[i], part.shard, part.nshards,
                    in[seen[part.shard] - 1]);
            qtool_bake_sums_free(&part);
            goto done;
        }
        if (qtool_bake_sums_add(&total, &part, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s: %s\n", in[i], err);
            qtool_bake_sums_free(&part);
            goto done;
        }
        seen[part.shard] = i + 1;
        qtool_bake_sums_free(&part);
    }
    uint32_t nsh = total.nshards, given = 0, first = nsh;
    for (uint32_t s = 0; s < nsh; ++s)
        if (seen[s])
            given++, first = first < s ? first : s;
    /* A partial set (tree merges): the shards I, I + M, I + 2M, ... of N (M dividing N) hold exactly the
     * direction blocks and rows of shard I of M, so their sum is written as that shard (--sums only). */
    uint32_t newn = 1, news = 0;
    if (given < nsh) {
        uint32_t m = nsh % given == 0 ? nsh / given : 0;
        for (uint32_t s = 0; m && s < nsh; ++s)
            if (!seen[s] != (s % m != first % m))
                m = 0;
        if (out || !sums_out) {
            for (uint32_t s = 0; s < nsh; ++s)
                if (!seen[s]) {
                    fprintf(stderr, "qibl: merge: shard %u/%u is missing (%s)\n", s, nsh,
                            out ? "an asset needs every shard; a partial merge writes --sums only"
                                : "a partial merge needs --sums OUT");
                    goto done;
                }
        }
        if (!m) {
            char list[200] = "";
            size_t at = 0;
            for (uint32_t s = 0; s < nsh && at < sizeof list - 16; ++s)
                if (seen[s])
                    at += (size_t)snprintf(list + at, sizeof list - at, "%s%u", at ? ", " : "", s);
            fprintf(stderr, "qibl: merge: shards %s%s of %u are not one shard of a coarser split: a partial merge takes "
                    "the shards I, I+M, I+2M, ... of N for an M dividing N (e.g. 0/4 and 2/4 make 0/2)\n", list,
                    at >= sizeof list - 16 ? ", ..." : "", nsh);
            goto done;
        }
        newn = m, news = first % m;
    }
    if (k > (long)total.k) {
        rc = qcli_usage_error("merge: --k %ld is above the shards' k = %u (bake with --k %ld or more)", k, total.k,
                                  k);
        goto done;
    }
    total.shard = news, total.nshards = newn;
    if (sums_out && qtool_bake_sums_write(&total, sums_out, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto done;
    }
    if (merge_extras(in, side_u, side_x, seen, nsh, &total, lsq, sums_out, out != NULL, &mu, &xx, &x) != 0) {
        if (sums_out)
            (void)unlink(sums_out); /* nothing half-done: the sums without their side files would merge wrongly */
        goto done;
    }
    if (sums_out && !out)
        printf(newn == 1 ? "wrote %s: the total sums (shard %u/%u, %u input%s)\n"
                         : "wrote %s: partial sums of shard %u/%u (%u input%s)\n", sums_out, news, newn, given,
               given == 1 ? "" : "s");
    rc = out ? finish_asset(&total, k ? (uint32_t)k : (total.k < 16 ? total.k : 16), (uint32_t)lut,
                            lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, layout, out, &x)
             : 0;
done:
    free(seen), free(in), free(side_u), free(side_x), free(want), free(mbuf);
    qtool_bake_sums_free(&total);
    qtool_gen_free(&mu);
    qtool_extras_free(&xx);
    return rc;
}

/* ---- qibl check ---------------------------------------------------------------------------------- */

int qcli_cmd_check(int argc, char **argv)
{
    if (argc < 2)
        return qcli_usage_error("usage: qibl check FILE...");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    int bad = 0;
    for (int i = 1; i < argc; ++i) {
        const char *p = argv[i], *ext = strrchr(p, '.');
        char err[512];
        if (ext && strcmp(ext, ".png") == 0) {
            int w, h, fr;
            uint8_t *rgb;
            if (qtool_png_read_rgb8(p, &w, &h, &fr, &rgb, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
                continue;
            }
            free(rgb);
            printf("%s: PNG %dx%d, %d frame%s, CRCs, zlib and Adler-32 good\n", p, w, h, fr, fr == 1 ? "" : "s");
        } else if (ext && strcmp(ext, ".pfm") == 0) {
            int w, h, ch;
            float *px;
            if (qtool_pfm_read(p, &w, &h, &ch, &px, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
                continue;
            }
            free(px);
            printf("%s: PFM %dx%d, %d channel%s\n", p, w, h, ch, ch == 1 ? "" : "s");
        } else if ((ext && strcmp(ext, ".exr") == 0) || qtool_exr_sniff(p)) {
            qtool_exr_info in;
            float *px;
            if (qtool_exr_read(p, &in, &px, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
                continue;
            }
            free(px);
            printf("%s: OpenEXR %dx%d (data window), %s, compression %d, every chunk decoded\n", p, in.w, in.h,
                   in.tiled ? "tiled" : "scanline", in.compression);
        } else if (ext && (strcmp(ext, ".hdr") == 0 || strcmp(ext, ".pic") == 0)) {
            /* the Radiance probes lights reads: header, resolution line and every scanline decoded */
            int w, h;
            float *px;
            if (qtool_hdr_read(p, &w, &h, &px, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
                continue;
            }
            double mx = 0;
            for (size_t j = 0; j < (size_t)w * (size_t)h * 3; ++j)
                mx = px[j] > mx ? px[j] : mx;
            free(px);
            printf("%s: Radiance HDR %dx%d, every scanline decoded, largest channel %.6g\n", p, w, h, mx);
        } else {
            size_t n;
            uint8_t *b = NULL;
            if (qtool_io_read_asset(p, &b, &n, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
                continue;
            }
            qibl_asset_t a;
            qibl_status_t st = qibl_asset_open(&a, b, n);
            if (st != QIBL_OK) {
                fprintf(stderr, "qibl: %s: %s\n", p, qibl_status_str(st));
                free(b);
                bad = 1;
                continue;
            }
            free(b);
            printf("%s: qibl asset, %u chunks, all CRCs good\n", p, a.chunk_count);
        }
    }
    return bad;
}
