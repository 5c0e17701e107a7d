/*
 * cmd_bake.c - `qibl render` (ground truth), `qibl bake` (reference renders -> SH maps -> asset,
 * shards, --budget), `qibl merge` (shards -> asset), `qibl check` (validate PNG/APNG/PFM/HDR/asset
 * files): each parses its options into the library's struct (tools/bake/job.h, whose
 * QTOOL_*_OPTS_DEFAULT hold the defaults), calls the job and prints its reason on failure.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/job.h"
#include "cli/cli.h"
#include "qibl/asset.h"

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
    *o = (qtool_scene_opts)QTOOL_SCENE_OPTS_DEFAULT;
    o->threads = qcli_default_threads(); /* the job's CPUs (affinity, SLURM_CPUS_PER_TASK), not the machine's */
}

int qcli_scene_load(const qcli_scene *o, qtool_rt_scene *s)
{
    char err[1400];
    if (qtool_scene_load(o, s, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    return 0;
}

/* a library job's status as the CLI's exit status, its reason (when it gave one) on stderr */
static int job_status(int rc, const char *err)
{
    if (rc != 0 && err[0])
        fprintf(stderr, "qibl: %s\n", err);
    return rc == 0 ? 0 : rc == 2 ? 2 : 1;
}

/* "X,Y,Z" into v (finite numbers); 0 or -1 */
static int parse_xyz(const char *s, double v[3])
{
    char tail;
    return sscanf(s, "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) == 3 && isfinite(v[0]) && isfinite(v[1]) &&
                   isfinite(v[2])
               ? 0
               : -1;
}

/* The fixed-camera options of render and bake at argv[*i]: --camera EYE TARGET UP (each X,Y,Z),
 * --camera gltf[:N] (the scene file's camera N), --fov DEG. 1 if consumed, 0 if not ours, -1 after
 * a message. *fov_given: --fov was seen. */
static int camera_opt(int argc, char **argv, int *i, qcli_scene *o, int *fov_given)
{
    const char *a = argv[*i];
    if (strcmp(a, "--camera") == 0 && *i + 1 < argc && strncmp(argv[*i + 1], "gltf", 4) == 0) {
        const char *g = argv[++*i] + 4;
        long n = 0;
        if (*g && (*g != ':' || qcli_parse_int(g + 1, 0, 255, &n) != 0))
            return qcli_usage_error("--camera gltf[:N]: N is the file's camera number 0..255, not '%s'", argv[*i]), -1;
        o->camera = QTOOL_SCENE_GLTF_CAMERA, o->gltf_cam = (int)n;
    } else if (strcmp(a, "--camera") == 0) {
        if (*i + 3 >= argc || parse_xyz(argv[*i + 1], o->eye) != 0 || parse_xyz(argv[*i + 2], o->target) != 0 ||
            parse_xyz(argv[*i + 3], o->up) != 0)
            return qcli_usage_error("--camera needs EYE TARGET UP, each X,Y,Z (or gltf[:N])"), -1;
        o->camera = QTOOL_SCENE_CAMERA, *i += 3;
    } else if (strcmp(a, "--fov") == 0 && *i + 1 < argc) {
        char *end;
        o->fov = strtod(argv[++*i], &end);
        if (*end || !(o->fov > 0 && o->fov < 180))
            return qcli_usage_error("--fov needs the vertical field of view in degrees, in (0, 180): '%s'", argv[*i]),
                   -1;
        *fov_given = 1;
    } else {
        return 0;
    }
    return 1;
}

/* the scene, panorama and camera options of render and bake: as qcli_scene_opt */
static int frame_opt(int argc, char **argv, int *i, qcli_scene *o, int *fov_given)
{
    int r = qcli_scene_opt(argc, argv, i, o);
    return r != 0 ? r : camera_opt(argc, argv, i, o, fov_given);
}

/* the camera options together: 0, or 2 after a message */
static int camera_check(qcli_scene *o, int fov_given)
{
    if (fov_given && o->camera == QTOOL_SCENE_PANORAMA)
        return qcli_usage_error("--fov is the field of view of a --camera");
    if (o->camera != QTOOL_SCENE_PANORAMA && o->kind == QTOOL_PANO_EQUIRECT)
        return qcli_usage_error("--camera makes a perspective frame: --equirect is for panoramas");
    if (o->camera == QTOOL_SCENE_GLTF_CAMERA && !fov_given)
        o->fov = 0; /* the file's own yfov */
    qtool_rt_camera c;
    char err[256];
    if (o->camera == QTOOL_SCENE_CAMERA && qtool_rt_camera_init(&c, o->eye, o->target, o->up, o->fov, err, sizeof err) != 0)
        return qcli_usage_error("%s", err);
    return 0;
}

/* the frame's name in the reports */
static const char *frame_name(const qcli_scene *o)
{
    return o->camera != QTOOL_SCENE_PANORAMA ? "fixed-camera frame"
           : o->kind == QTOOL_PANO_CYLINDRICAL ? "cylindrical panorama"
                                                : "equirectangular panorama";
}

/* ---- qibl render --------------------------------------------------------------------------------- */

/* --point without --rgb: C0 from the distance to what the panorama sees, as relight does from the
 * asset's P map (the same points: the primary hits, sky QTOOL_CLI_SKY_DIST along the ray). 0, or 1
 * after a message. */
static int point_default(const qtool_rt_scene *s, const qcli_scene *so, qtool_rt_light *l)
{
    double *pts = NULL, c0, d;
    if (qtool_render_points(s, so, QTOOL_CLI_SKY_DIST, &pts) != 0 ||
        qcli_point_default(pts, (size_t)so->w * so->h, l->pos, l->falloff, &c0, &d) != 0) {
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

/* render's options into o; 0, or 2 after a message */
static int render_parse(int argc, char **argv, qtool_render_opts *o)
{
    qtool_rt_light *l = &o->light;
    int have = 0, have_aim = 0, fov_given = 0;
    long falloff = 1;
    for (int i = 1; i < argc; ++i) {
        int r = frame_opt(argc, argv, &i, &o->scene, &fov_given);
        if (r < 0)
            return 2;
        if (r)
            continue;
        const char *a = argv[i];
        if (strcmp(a, "--sun") == 0 || strcmp(a, "--point") == 0) {
            int pt = a[2] == 'p';
            double *v = pt ? l->pos : l->dir;
            if (parse_d3(argv, i, argc, -QTOOL_CLI_Q16_MAX, v) != 0)
                return 2;
            /* as relight sees it: a direction that rounds to 0 0 0 in Q16.16 has none */
            if (!pt && fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2]))) < 0.5 / 65536)
                return qcli_usage_error("--sun needs a non-zero direction: %s %s %s is 0 0 0 in Q16.16",
                                        argv[i + 1], argv[i + 2], argv[i + 3]);
            l->point = pt, have++, i += 3;
        } else if (strcmp(a, "--rgb") == 0) {
            if (parse_d3(argv, i, argc, 0, l->rgb) != 0)
                return 2;
            o->have_rgb = 1, i += 3;
        } else if (strcmp(a, "--falloff") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 2, &falloff) != 0)
                return qcli_usage_error("--falloff is 1 (C0/|L|) or 2 (C0/|L|^2)");
        } else if (strcmp(a, "--png") == 0 && i + 1 < argc) {
            o->png = argv[++i];
        } else if (strcmp(a, "--pfm") == 0 && i + 1 < argc) {
            o->pfm = argv[++i];
        } else if (strcmp(a, "--exr") == 0 && i + 1 < argc) {
            o->exr = argv[++i];
        } else if (strcmp(a, "--depth") == 0 && i + 1 < argc) {
            o->depth = argv[++i];
        } else if (strcmp(a, "--ies") == 0 && i + 1 < argc) {
            o->ies = argv[++i]; /* a goniometric lamp (io/ies.h), oriented as relight --ies orients it */
        } else if (strcmp(a, "--aim") == 0 || strcmp(a, "--up") == 0) {
            if (parse_d3(argv, i, argc, -QTOOL_CLI_Q16_MAX, a[2] == 'a' ? o->aim : o->up) != 0)
                return 2;
            have_aim = 1, i += 3;
        } else {
            return qcli_usage_error("render: unknown argument '%s' (see qibl help render)", a);
        }
    }
    if (have != 1 || (!o->png && !o->pfm && !o->exr && !o->depth))
        return qcli_usage_error("render needs exactly one of --sun/--point and at least one of --png/--pfm/--exr/--depth");
    if ((o->ies || have_aim) && !l->point)
        return qcli_usage_error("render: --ies, --aim and --up shape a --point lamp");
    if (have_aim && !o->ies)
        return qcli_usage_error("render: --aim and --up orient an --ies lamp: give --ies FILE.ies");
    l->falloff = (int)falloff;
    return camera_check(&o->scene, fov_given);
}

int qcli_cmd_render(int argc, char **argv)
{
    qtool_render_opts o = QTOOL_RENDER_OPTS_DEFAULT;
    qcli_scene_defaults(&o.scene);
    if (render_parse(argc, argv, &o) != 0)
        return 2;
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    qtool_render_job j;
    char err[1400] = "";
    int png_written = 0, rc = qtool_render_prepare(&o, &j, err, sizeof err);
    if (rc == 0 && o.light.point && !o.have_rgb && point_default(&j.s, &o.scene, &o.light) != 0)
        rc = -1, err[0] = '\0';
    if (rc == 0)
        rc = qtool_render_run(&o, &j, &png_written, err, sizeof err);
    if (png_written)
        qcli_warn_dark(o.png, j.rgb8, (size_t)o.scene.w * o.scene.h);
    if (rc == 0)
        printf("rendered %ux%u %s of %s, %zu triangles, %s light, %.0f ms on %d threads\n", o.scene.w, o.scene.h,
               frame_name(&o.scene),
               o.scene.scene ? o.scene.scene : "the built-in courtyard", j.s.ntri, o.light.point ? "point" : "directional",
               j.ms, o.scene.threads);
    qtool_render_free(&j);
    return job_status(rc, err);
}

/* ---- qibl bake ----------------------------------------------------------------------------------- */

/* The asset options bake and merge share (--k, --lut-size, --layout, --lsq) at argv[*i]: 1 if
 * consumed, 0 if not ours, -1 after a message on a bad value. */
static int asset_opt(int argc, char **argv, int *i, long *k, long *lut, uint32_t *layout, int *lsq)
{
    const char *a = argv[*i];
    int r;
    if (strcmp(a, "--k") == 0 && *i + 1 < argc) {
        if (qcli_parse_int(argv[++*i], 1, 25, k) != 0)
            return qcli_usage_error("--k needs an integer in 1..25"), -1;
    } else if ((r = qcli_lut_size_opt(argc, argv, i, 0, lut)) != 0) {
        return r < 0 ? -1 : 1;
    } else if (strcmp(a, "--layout") == 0 && *i + 1 < argc) {
        if (qcli_parse_layout(argv[++*i], layout) != 0)
            return qcli_usage_error("--layout is planar or interleaved"), -1;
    } else if (strcmp(a, "--lsq") == 0) {
        *lsq = 1;
    } else {
        return 0;
    }
    return 1;
}

/* bake's options into o (progress -1: a bar on a terminal, lines elsewhere); 0, or 2 after a message */
static int bake_parse(int argc, char **argv, qtool_bake_opts *o)
{
    char perr[400];
    int fov_given = 0;
    for (int i = 1; i < argc; ++i) {
        int r = frame_opt(argc, argv, &i, &o->scene, &fov_given);
        if (r == 0)
            r = asset_opt(argc, argv, &i, &o->k, &o->lut, &o->layout, &o->lsq);
        if (r < 0)
            return 2;
        if (r)
            continue;
        const char *a = argv[i];
        if (strcmp(a, "-o") == 0 && i + 1 < argc)
            o->out = argv[++i];
        else if (strcmp(a, "--dirs") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 16, 65536, &o->ndirs) != 0)
                return qcli_usage_error("--dirs needs an integer in 16..65536");
        } else if (strcmp(a, "--shard") == 0 && i + 1 < argc) {
            char tail;
            if (sscanf(argv[++i], "%ld/%ld%c", &o->shard, &o->nshards, &tail) != 2 || o->nshards < 1 ||
                o->nshards > 4096 || o->shard < 0 || o->shard >= o->nshards)
                return qcli_usage_error("--shard needs I/N with 0 <= I < N <= 4096");
        } else if (strcmp(a, "--sums") == 0 && i + 1 < argc)
            o->sums_out = argv[++i];
        else if (strcmp(a, "--budget") == 0 && i + 1 < argc) {
            char *end;
            o->budget = strtod(argv[++i], &end);
            if (*end || !(o->budget > 0 && o->budget < 99))
                return qcli_usage_error("--budget needs a PSNR in dB (0..99)");
        } else if (strcmp(a, "--unshadowed-k") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 0, 25, &o->uk) != 0)
                return qcli_usage_error("--unshadowed-k needs an integer in 0..25 (0: no unshadowed maps)");
        } else if (strcmp(a, "--path-steps") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 2, 4096, &o->steps) != 0)
                return qcli_usage_error("--path-steps needs an integer in 2..4096");
        } else if ((strcmp(a, "--sun-path") == 0 || strcmp(a, "--lamp-track") == 0) && i + 1 < argc) {
            if (o->npaths == QTOOL_BAKE_JOB_MAX_PATHS)
                return qcli_usage_error("%s: at most 8 light paths per asset", a);
            qtool_bake_path *pp = &o->paths[o->npaths];
            memset(pp, 0, sizeof *pp);
            int bad = a[2] == 's' ? qtool_bake_path_parse_sun(argv[++i], pp, perr, sizeof perr)
                                  : qtool_bake_path_parse_track(argv[++i], pp, perr, sizeof perr);
            if (bad)
                return qcli_usage_error("%s", perr);
            o->npaths++;
        } else if (strcmp(a, "--lamp-box") == 0 && i + 1 < argc) {
            char tail;
            double *b = o->lamp_box;
            if (sscanf(argv[++i], "%lf,%lf,%lf,%lf,%lf,%lf%c", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &tail) != 6 ||
                !(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5]) || !(fabs(b[0]) < 1e6 && fabs(b[1]) < 1e6 &&
                fabs(b[2]) < 1e6 && fabs(b[3]) < 1e6 && fabs(b[4]) < 1e6 && fabs(b[5]) < 1e6))
                return qcli_usage_error("--lamp-box needs X0,Y0,Z0,X1,Y1,Z1 with X0 <= X1, Y0 <= Y1, Z0 <= Z1 (|v| < 1e6): "
                                        "'%s'", argv[i]);
            o->has_box = 1;
        } else if (strcmp(a, "--lamp-samples") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, 4096, &o->lamp_samples) != 0)
                return qcli_usage_error("--lamp-samples needs an integer in 1..4096");
        } else if (strcmp(a, "--quiet") == 0)
            o->quiet = 1;
        else if (strncmp(a, "--progress=", 11) == 0 || (strcmp(a, "--progress") == 0 && i + 1 < argc)) {
            const char *m = a[10] == '=' ? a + 11 : argv[++i];
            o->progress = strcmp(m, "none") == 0 ? 0 : strcmp(m, "bar") == 0 ? 1 : strcmp(m, "lines") == 0 ? 2 : -2;
            if (o->progress == -2)
                return qcli_usage_error("--progress is bar, lines or none: '%s'", m);
        } else
            return qcli_usage_error("bake: unknown argument '%s' (see qibl help bake)", a);
    }
    return camera_check(&o->scene, fov_given);
}

int qcli_cmd_bake(int argc, char **argv)
{
    qtool_bake_opts o = QTOOL_BAKE_OPTS_DEFAULT;
    qcli_scene_defaults(&o.scene);
    o.progress = -1; /* not given: a bar on a terminal, lines elsewhere */
    if (bake_parse(argc, argv, &o) != 0)
        return 2;
    if (o.quiet)
        o.progress = 0;
    else if (o.progress < 0)
        o.progress = isatty(2) ? 1 : 2;
    char err[1400] = "";
    if (qtool_bake_opts_check(&o, err, sizeof err) != 0)
        return qcli_usage_error("%s", err);
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    return job_status(qtool_bake_job(&o, stdout, stderr, err, sizeof err), err);
}

/* ---- qibl merge ---------------------------------------------------------------------------------- */

static int merge_parse(int argc, char **argv, qtool_merge_opts *o)
{
    for (int i = 1; i < argc; ++i) {
        int r = asset_opt(argc, argv, &i, &o->k, &o->lut, &o->layout, &o->lsq);
        if (r < 0)
            return 2;
        if (r)
            continue;
        const char *a = argv[i];
        if (strcmp(a, "-o") == 0 && i + 1 < argc)
            o->out = argv[++i];
        else if (strcmp(a, "--sums") == 0 && i + 1 < argc)
            o->sums_out = argv[++i];
        else if (strcmp(a, "--manifest") == 0 && i + 1 < argc)
            o->manifest = argv[++i];
        else if (a[0] != '-')
            o->in[o->nin++] = argv[i];
        else
            return qcli_usage_error("merge: unknown argument '%s' (see qibl help merge)", a);
    }
    if ((o->nin == 0 && !o->manifest) || (!o->out && !o->sums_out))
        return qcli_usage_error("usage: qibl merge (-o ASSET | --sums OUT | both) [--k K] [--lut-size N] [--lsq] "
                                "(--manifest FILE | SUMS...)");
    return 0;
}

int qcli_cmd_merge(int argc, char **argv)
{
    qtool_merge_opts o = QTOOL_MERGE_OPTS_DEFAULT;
    o.in = malloc(sizeof(char *) * (size_t)argc);
    if (!o.in)
        return 1;
    int rc = merge_parse(argc, argv, &o);
    char err[4400] = "";
    if (rc == 0 && !qcli_parse_only) /* fuzz_cliopts: the options only */
        rc = job_status(qtool_bake_merge(&o, stdout, err, sizeof err), err);
    free(o.in);
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
        char line[512], err[512];
        if (qtool_bake_check_file(argv[i], line, sizeof line, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            bad = 1;
        } else {
            printf("%s: %s\n", argv[i], line);
        }
    }
    return bad;
}
