/*
 * cmd_bake.c - `qibl render` (ground truth), `qibl bake` (reference renders -> SH maps -> asset,
 * shards, --budget), `qibl merge` (shards -> asset), `qibl check` (validate PNG/APNG/PFM/HDR/asset
 * files): each parses its options into the library's struct (tools/bake/job.h, whose
 * QTOOL_*_OPTS_DEFAULT hold the defaults), calls the job and prints its reason on failure.
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/job.h"
#include "cli/cli.h"
#include "opt/opt.h"
#include "cli/scene_opts.h"
#include "qibl/asset.h"
#include "qibl/shmaps.h"

/* ---- shared options ------------------------------------------------------------------------------ */

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

/* --camera EYE TARGET UP (each X,Y,Z) or --camera gltf[:N] (the scene file's camera N) */
const char *qcli_camera_call(void *opts, char *const *v, int n, int *used)
{
    qcli_scene_cli *c = opts; /* the options struct starts with it */
    if (strncmp(v[0], "gltf", 4) == 0) {
        const char *g = v[0] + 4;
        long k = 0;
        if (*g && (*g != ':' || qcli_parse_int(g + 1, 0, 255, &k) != 0)) {
            snprintf(c->why, sizeof c->why, "gltf[:N]: N is the file's camera number 0..255, not '%s'", v[0]);
            return c->why;
        }
        c->camera = QTOOL_SCENE_GLTF_CAMERA, c->gltf_cam = (int)k, *used = 1;
        return NULL;
    }
    double e[3], t[3], u[3];
    if (n < 3 || parse_xyz(v[0], e) != 0 || parse_xyz(v[1], t) != 0 || parse_xyz(v[2], u) != 0)
        return "needs EYE TARGET UP, each X,Y,Z (or gltf[:N])";
    memcpy(c->eye, e, sizeof e), memcpy(c->target, t, sizeof t), memcpy(c->up, u, sizeof u);
    c->camera = QTOOL_SCENE_CAMERA, *used = 3;
    return NULL;
}

const char *qcli_fov_call(void *opts, const char *v)
{
    qcli_scene_cli *c = opts;
    char *end;
    double f = strtod(v, &end);
    if (*end || !(f > 0 && f < 180))
        return "is not the vertical field of view in degrees, in (0, 180)";
    c->fov = f, c->fov_given = 1;
    return NULL;
}

int qcli_scene_from(const qtool_opt_cmd *t, const qcli_scene_cli *c, qtool_scene_opts *o)
{
    if (c->size[0] > 0) {
        if (c->size[0] * c->size[1] > (long)QIBL_ASSET_MAX_PIXELS)
            return qtool_opt_error(t, "--size %ldx%ld is above the asset's %u pixels", c->size[0], c->size[1],
                                  QIBL_ASSET_MAX_PIXELS);
        o->w = (uint32_t)c->size[0], o->h = (uint32_t)c->size[1];
    }
    if (c->scene)
        o->scene = c->scene;
    o->zup |= c->zup, o->raw |= c->raw;
    if (c->equirect)
        o->kind = QTOOL_PANO_EQUIRECT;
    if (c->threads > 0)
        o->threads = (int)c->threads;
    o->camera = c->camera, o->gltf_cam = c->gltf_cam, o->fov = c->fov;
    memcpy(o->eye, c->eye, sizeof o->eye), memcpy(o->target, c->target, sizeof o->target);
    memcpy(o->up, c->up, sizeof o->up);
    if (c->fov_given && o->camera == QTOOL_SCENE_PANORAMA)
        return qtool_opt_error(t, "--fov is the field of view of a --camera");
    if (o->camera != QTOOL_SCENE_PANORAMA && o->kind == QTOOL_PANO_EQUIRECT)
        return qtool_opt_error(t, "--camera makes a perspective frame: --equirect is for panoramas");
    if (o->camera == QTOOL_SCENE_GLTF_CAMERA && !c->fov_given)
        o->fov = 0; /* the file's own yfov */
    qtool_rt_camera cam;
    char err[256];
    if (o->camera == QTOOL_SCENE_CAMERA && qtool_rt_camera_init(&cam, o->eye, o->target, o->up, o->fov, err, sizeof err) != 0)
        return qtool_opt_error(t, "%s", err);
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

/* help's prose after the option list */
#define RENDER_PROSE \
    "  The reference renderer (BVH ray tracer, hard shadows, Lambert + glossy) from the viewpoint at the\n" \
    "  origin: what a light really produces, to compare relit frames with. --sun: directional light\n" \
    "  from (X, Y, Z) with irradiance --rgb (default 1 1 1); --point: a lamp at (X, Y, Z) with\n" \
    "  C0 = --rgb and falloff C0/|L| (or |L|^2); without --rgb, C0 = 2 d (or 2 d^2), d the median\n" \
    "  distance from the lamp to what the panorama sees (a note says so); every number within the Q16.16 range relight takes\n" \
    "  (|v| <= 32767.99998, --rgb >= 0). --png: sRGB 8-bit through the same framebuffer code\n" \
    "  as qibl relight; --pfm: linear RGB floats; --exr: the same floats as OpenEXR (scanline, ZIP, FLOAT\n" \
    "  channels, bit for bit); --depth: depth along each pixel's ray (0 for sky).\n" \
    "  Scenes: the built-in courtyard (default) or a glTF 2.0 (.gltf, .glb), OBJ or PLY mesh placed as a\n" \
    "  prop on a ground plane, 3.5 units along -x: the middle of the panorama, away from its seam at +x\n" \
    "  (Y-up turned to Z-up unless --zup; --raw: as given, nothing added). Materials colour the\n" \
    "  triangles: glTF baseColorFactor and PNG baseColorTexture, OBJ mtllib/usemtl with Kd and map_Kd\n" \
    "  (PNG) and vt. Default 1024x256 cylindrical. A frame whose mean is below 32 of 255 gets a note\n" \
    "  that it is almost black.\n" \
    "  --ies FILE.ies: the --point lamp is goniometric: C0 times I(direction) / I_peak from the IES\n" \
    "  profile in double precision (bilinear in its angle grid), oriented by --aim (default 0 0 -1)\n" \
    "  and --up (default 1 0 0) as relight --ies orients it: the truth of relight's tables.\n" \
    "  --camera EYE TARGET UP: a fixed perspective camera (a pre-rendered background) instead of the\n" \
    "  panorama: --size WxH pixels from EYE looking at TARGET, UP its approximate up, --fov DEG the\n" \
    "  vertical field of view (default 60, in (0, 180)); --camera gltf[:N]: the scene file's camera N\n" \
    "  (default 0, perspective, its yfov unless --fov), placed as the mesh is. A bad camera (EYE =\n" \
    "  TARGET, UP zero or along the view) is named.\n" \
    "  --probe PROBE.hdr [--yaw DEG]: the truth under the whole lat-long probe (as the demo's), turned\n" \
    "  and scaled as bake --probe does (a surface facing up receives 1.6), every direction shadowed:\n" \
    "  the mean of two importance-sampled renders of --spp samples per pixel (default 256) with seeds\n" \
    "  2 S + 1 and 2 S + 2 (--seed S, default 0).\n"


typedef struct render_cli {
    qcli_scene_cli sc; /* first: the scene options' callbacks find it here */
    qtool_render_opts o;
    long falloff;
    int have, have_aim;
    char why[256];
} render_cli;
static const render_cli render_defaults = {.sc = QCLI_SCENE_CLI_DEFAULT, .o = QTOOL_RENDER_OPTS_DEFAULT, .falloff = 1};

/* --sun X Y Z, --point X Y Z: the one light */
static const char *render_light(render_cli *c, int pt, char *const *v)
{
    qtool_rt_light *l = &c->o.light;
    double *d = pt ? l->pos : l->dir;
    if (qtool_relight_spec_xyz(v, -QTOOL_RELIGHT_Q16_MAX, d, c->why, sizeof c->why))
        return c->why;
    /* as relight sees it: a direction that rounds to 0 0 0 in Q16.16 has none */
    if (!pt && fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2]))) < 0.5 / 65536) {
        snprintf(c->why, sizeof c->why, "%s %s %s is 0 0 0 in Q16.16: --sun needs a non-zero direction", v[0], v[1],
                 v[2]);
        return c->why;
    }
    l->point = pt, c->have++;
    return NULL;
}

static const char *render_sun(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return render_light(o, 0, v);
}

static const char *render_point(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return render_light(o, 1, v);
}

static const char *render_rgb(void *o, char *const *v, int n, int *used)
{
    render_cli *c = o;
    (void)n, (void)used;
    if (qtool_relight_spec_xyz(v, 0, c->o.light.rgb, c->why, sizeof c->why))
        return c->why;
    c->o.have_rgb = 1;
    return NULL;
}

static const char *render_frame(void *o, char *const *v, double *out)
{
    render_cli *c = o;
    if (qtool_relight_spec_xyz(v, -QTOOL_RELIGHT_Q16_MAX, out, c->why, sizeof c->why))
        return c->why;
    c->have_aim = 1;
    return NULL;
}

static const char *render_aim(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return render_frame(o, v, ((render_cli *)o)->o.aim);
}

static const char *render_up(void *o, char *const *v, int n, int *used)
{
    (void)n, (void)used;
    return render_frame(o, v, ((render_cli *)o)->o.up);
}

static const qtool_opt render_table[] = {
    {.name = "--sun", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = render_sun, .arg = "X Y Z",
     .help = "a directional light from (X, Y, Z) of irradiance --rgb (one --sun or --point)"},
    {.name = "--point", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = render_point, .arg = "X Y Z",
     .help = "a lamp at (X, Y, Z), C0 = --rgb, falloff C0/|L| (or |L|^2)"},
    {.name = "--rgb", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = render_rgb, .arg = "R G B",
     .def = "1 1 1; a --point: 2 d, or 2 d^2", .help = "the light's colour, each in 0..32767.99998"},
    {.name = "--falloff", .kind = QTOOL_OPT_INT, .off = offsetof(render_cli, falloff), .lo = 1, .hi = 2,
     .why = "1: C0/|L|, 2: C0/|L|^2", .help = "the lamp's falloff"},
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, o.png), .arg = "OUT",
     .help = "sRGB 8-bit through the same framebuffer code as qibl relight"},
    {.name = "--pfm", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, o.pfm), .arg = "OUT",
     .help = "linear RGB floats"},
    {.name = "--exr", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, o.exr), .arg = "OUT.exr",
     .help = "the same floats as OpenEXR (scanline, ZIP, FLOAT channels, bit for bit)"},
    {.name = "--depth", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, o.depth), .arg = "OUT.pfm",
     .help = "depth along each pixel's ray (0 for sky)"},
    {.name = "--ies", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, o.ies), .arg = "FILE.ies",
     .help = "the --point lamp is goniometric (its IES profile in double precision)"},
    {.name = "--aim", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = render_aim, .arg = "X Y Z", .def = "0 0 -1",
     .help = "the --ies lamp's axis, as relight --ies orients it"},
    {.name = "--up", .kind = QTOOL_OPT_CALL, .nargs = 3, .call_n = render_up, .arg = "X Y Z", .def = "1 0 0",
     .help = "the --ies lamp's horizontal angle 0"},
    {.name = "--probe", .kind = QTOOL_OPT_STR, .off = offsetof(render_cli, o.probe), .arg = "PROBE.hdr",
     .help = "the truth under the whole probe instead of --sun/--point"},
    {.name = "--yaw", .kind = QTOOL_OPT_NUM, .off = offsetof(render_cli, o.yaw), .arg = "DEG", .lo = -360, .hi = 360,
     .help = "turn the --probe (positive turns +x toward +y)"},
    {.name = "--spp", .kind = QTOOL_OPT_INT, .off = offsetof(render_cli, o.spp), .arg = "N", .lo = 4, .hi = 1 << 20,
     .help = "the --probe truth's samples per pixel in each of its two renders"},
    {.name = "--seed", .kind = QTOOL_OPT_INT, .off = offsetof(render_cli, o.seed), .arg = "S", .lo = 0, .hi = 1 << 30,
     .help = "the --probe truth's renders use seeds 2 S + 1 and 2 S + 2"},
    QCLI_SCENE_OPTS(NULL),
    QCLI_CAMERA_OPTS,
    {0},
};

static const qtool_opt_cmd render_spec = {
    .name = "render",
    QTOOL_OPT_TABLE(render_table, render_defaults),
    .prose = RENDER_PROSE,
};

/* render's options together in c->o; 0, or 2 after the one line */
static int render_check(void *opts)
{
    const qtool_opt_cmd *t = &render_spec;
    render_cli *c = opts;
    qtool_render_opts *o = &c->o;
    qcli_scene_defaults(&o->scene); /* the job's CPUs; the scene options are c->sc's */
    if (o->probe && (c->have || o->depth || o->ies))
        return qtool_opt_error(t, "--probe is the whole light: no --sun, --point, --ies or --depth with it");
    if (!o->probe && (o->yaw != 0 || o->spp != render_defaults.o.spp || o->seed))
        return qtool_opt_error(t, "--yaw, --spp and --seed shape a --probe truth: give --probe PROBE.hdr");
    if ((c->have != 1 && !o->probe) || (!o->png && !o->pfm && !o->exr && !o->depth))
        return qtool_opt_error(t, "render needs exactly one of --sun/--point/--probe and at least one of "
                              "--png/--pfm/--exr/--depth");
    if ((o->ies || c->have_aim) && !o->light.point)
        return qtool_opt_error(t, "--ies, --aim and --up shape a --point lamp");
    if (c->have_aim && !o->ies)
        return qtool_opt_error(t, "--aim and --up orient an --ies lamp: give --ies FILE.ies");
    o->light.falloff = (int)c->falloff;
    return qcli_scene_from(t, &c->sc, &o->scene);
}

static int render_run(void *opts)
{
    qtool_render_opts o = ((const render_cli *)opts)->o;
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
               o.scene.scene ? o.scene.scene : "the built-in courtyard", j.s.ntri,
               o.probe ? "probe" : o.light.point ? "point" : "directional",
               j.ms, o.scene.threads);
    qtool_render_free(&j);
    return job_status(rc, err);
}

const qcli_sub qcli_sub_render = {.opts = &render_spec, .check = render_check, .run = render_run};

/* ---- qibl bake ----------------------------------------------------------------------------------- */

#define BAKE_PROSE \
    "  Renders the scene under N directional lights (spherical Fibonacci set, equal weights 4 pi / N,\n" \
    "  default 512) with hard shadows, projects every pixel's response onto SH (k <= 25, default 16;\n" \
    "  quadrature, or --lsq least squares), packs the maps to 8 bits (min/max per map and channel) and\n" \
    "  writes SHMP + PMAP (+ a cube-map YLUT of face --lut-size N, default 32; 0 = none). Sums are\n" \
    "  exact integers: the asset is bit-identical for any --threads and any sharding.\n" \
    "  --shard I/N --sums FILE (no -o): bake only the I-th of N shares of the directions (and of the\n" \
    "  rows of the light paths and lamp occlusion), write partial sums for qibl merge (a render farm:\n" \
    "  docs/farm.md). --budget DB: choose the smallest band-complete k whose PSNR against ground truth\n" \
    "  on 8 novel suns reaches DB, and the smallest LUT within 0.1 dB of direct SH evaluation on 4\n" \
    "  lamps, and say so. --progress: a bar on stderr (the default on a terminal), or lines (the\n" \
    "  default elsewhere: one flushed line per step, \"progress: stage=S done=D total=T fraction=F\"),\n" \
    "  or none (also --quiet). --threads defaults to the CPUs the process may run on (its affinity:\n" \
    "  taskset, a job's cgroup), lowered to SLURM_CPUS_PER_TASK where that is set.\n" \
    "  --layout interleaved: SH maps streamable by rows (see qibl help gen).\n" \
    "  --unshadowed-k K (default 9, 0 = none): also the unshadowed transfer (cosine x BRDF, no shadow\n" \
    "  test) as SHMU (planar); free point lights use it (visibility at infinity is wrong for a lamp\n" \
    "  inside the scene). --sun-path LAT,DECL,T0,T1 (degrees, degrees, solar hours; +x east, +y north)\n" \
    "  and --lamp-track \"x,y,z;x,y,z;...\" (a polyline, t by arc length; up to 8 paths): per pixel the\n" \
    "  light's visibility along the path (facing and shadow) as on/off edges of t in 0..65535, sampled\n" \
    "  at N + 1 points (--path-steps, default 64) and bisected to one 16-bit step (LPTH chunks; relit\n" \
    "  as unshadowed SH x visibility, qibl/lightpath.h). --lamp-box: the region free lamps move in;\n" \
    "  per pixel the expected visibility of a lamp there (N Halton positions, default 64), LOCC: free\n" \
    "  lamps through SHMU are scaled by it (their cast shadows on average). A shard also writes its\n" \
    "  share of the unshadowed sums (FILE.u) and its rows of the LPTH/LOCC chunks (FILE.x, also when\n" \
    "  there are none, so merge can refuse a shard baked without the others' paths).\n" \
    "  --tile I/N: a band of rows I h / N .. (I + 1) h / N - 1, every direction, output proportional to\n" \
    "  its rows, in two passes (the 8-bit maps' ranges are the whole image's): --ranges-out FILE writes\n" \
    "  the band's map ranges; qibl merge --ranges -o R FILE... reduces every tile's; --ranges R --part P\n" \
    "  bakes the band again and writes its final bytes; qibl merge -o ASSET P... joins the parts, byte\n" \
    "  for byte this bake's asset (same options in every pass; docs/farm.md). --cache DIR (a node-local\n" \
    "  directory): pass 1 keeps the band's exact sums there, pass 2 on the same node reuses them.\n" \
    "  --camera, --fov (as for render): the pixels are a fixed camera's rays instead of the panorama's,\n" \
    "  so the maps relight a pre-rendered background seen from one corner (qibl relight as any asset).\n" \
    "  --probe PROBE.hdr [--yaw DEG]: a probe-lit asset (the demo's sun + SH): the probe, turned and\n" \
    "  scaled so a surface facing up receives 1.6, gives its compact bright sources (each split into 8\n" \
    "  equal-energy parts), each part's visibility baked as a single-direction light path, shadowed maps\n" \
    "  k = 25 for the rest as SH, unshadowed k = 16 for the sources, and a PSUN chunk naming the probe;\n" \
    "  --k and --unshadowed-k do not apply. relight ASSET --probe PROBE.hdr uses it. A probe without a\n" \
    "  compact source is refused (relight it as SH).\n" \
    "  Exit status: 0 done, 1 failed (a file, memory; named on stderr, nothing half-written), 2 bad\n" \
    "  arguments.\n"


typedef struct bake_cli {
    qcli_scene_cli sc; /* first: the scene options' callbacks find it here */
    qtool_bake_opts o;
    int layout;        /* index into layouts */
    int progress;      /* o.progress; -1: not given (a bar on a terminal, lines elsewhere) */
    char why[400];
} bake_cli;

static const char *const layouts[] = {"planar", "interleaved", NULL};
static const uint32_t layout_values[] = {QIBL_SHMAPS_PLANAR, QIBL_SHMAPS_INTERLEAVED};
static const char *const progress_names[] = {"none", "bar", "lines", NULL}; /* o.progress 0, 1, 2 */

static const char *bake_shard(void *opts, const char *v)
{
    qtool_bake_opts *o = &((bake_cli *)opts)->o;
    long i, n;
    char tail;
    if (sscanf(v, "%ld/%ld%c", &i, &n, &tail) != 2 || n < 1 || n > 4096 || i < 0 || i >= n)
        return "is not I/N with 0 <= I < N <= 4096";
    o->shard = i, o->nshards = n;
    return NULL;
}

static const char *bake_tile(void *opts, const char *v)
{
    qtool_bake_opts *o = &((bake_cli *)opts)->o;
    long i, n;
    char tail;
    if (sscanf(v, "%ld/%ld%c", &i, &n, &tail) != 2 || n < 1 || n > QIBL_ASSET_MAX_DIM || i < 0 || i >= n)
        return "is not I/N with 0 <= I < N (at most the rows)";
    o->tile = i, o->ntiles = n;
    return NULL;
}

static const char *bake_budget(void *opts, const char *v)
{
    char *end;
    double b = strtod(v, &end);
    if (*end || !(b > 0 && b < 99))
        return "is not a PSNR in dB (0..99)";
    ((bake_cli *)opts)->o.budget = b;
    return NULL;
}

/* --sun-path LAT,DECL,T0,T1 or --lamp-track X,Y,Z;X,Y,Z;...: one light path more */
static const char *bake_path(bake_cli *c, int sun, const char *v)
{
    qtool_bake_opts *o = &c->o;
    if (o->npaths == QTOOL_BAKE_JOB_MAX_PATHS)
        return "is one light path too many: at most 8 per asset";
    qtool_bake_path *pp = &o->paths[o->npaths];
    memset(pp, 0, sizeof *pp);
    int bad = sun ? qtool_bake_path_parse_sun(v, pp, c->why, sizeof c->why)
                  : qtool_bake_path_parse_track(v, pp, c->why, sizeof c->why);
    if (bad)
        return c->why;
    o->npaths++;
    return NULL;
}

static const char *bake_sun_path(void *opts, const char *v)
{
    return bake_path(opts, 1, v);
}

static const char *bake_lamp_track(void *opts, const char *v)
{
    return bake_path(opts, 0, v);
}

static const char *bake_lamp_box(void *opts, const char *v)
{
    qtool_bake_opts *o = &((bake_cli *)opts)->o;
    char tail;
    double b[6];
    if (sscanf(v, "%lf,%lf,%lf,%lf,%lf,%lf%c", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &tail) != 6 ||
        !(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5]) ||
        !(fabs(b[0]) < 1e6 && fabs(b[1]) < 1e6 && fabs(b[2]) < 1e6 && fabs(b[3]) < 1e6 && fabs(b[4]) < 1e6 &&
          fabs(b[5]) < 1e6))
        return "is not X0,Y0,Z0,X1,Y1,Z1 with X0 <= X1, Y0 <= Y1, Z0 <= Z1 (|v| < 1e6)";
    memcpy(o->lamp_box, b, sizeof b), o->has_box = 1;
    return NULL;
}

static const bake_cli bake_defaults = {.sc = QCLI_SCENE_CLI_DEFAULT, .o = QTOOL_BAKE_OPTS_DEFAULT, .progress = -1};

static const qtool_opt bake_table[] = {
    {.name = "-o", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.out), .arg = "ASSET", .help = "the asset"},
    {.name = "--shard", .kind = QTOOL_OPT_CALL, .call = bake_shard, .arg = "I/N",
     .help = "bake only the I-th of N shares (with --sums, no -o; qibl merge joins them)"},
    {.name = "--sums", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.sums_out), .arg = "FILE",
     .help = "the shard's partial sums"},
    {.name = "--tile", .kind = QTOOL_OPT_CALL, .call = bake_tile, .arg = "I/N",
     .help = "bake only the I-th of N bands of rows, every direction (--ranges-out, or --ranges and --part)"},
    {.name = "--ranges-out", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.ranges_out), .arg = "FILE",
     .help = "tile pass 1: the band's map ranges (qibl merge --ranges reduces them)"},
    {.name = "--ranges", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.ranges_in), .arg = "FILE",
     .help = "tile pass 2: every tile's map ranges, reduced"},
    {.name = "--part", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.part_out), .arg = "FILE",
     .help = "tile pass 2: the band's final bytes (qibl merge -o ASSET PART... joins them)"},
    {.name = "--cache", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.cache), .arg = "DIR",
     .help = "tile passes: pass 1 keeps the band's exact sums in DIR, pass 2 reuses them (no second bake)"},
    {.name = "--k", .kind = QTOOL_OPT_INT, .off = offsetof(bake_cli, o.k), .arg = "K", .lo = 1, .hi = 25,
     .help = "the number of SH maps"},
    QCLI_LUT_SIZE_OPTS(bake_cli, o.lut),
    {.name = "--dirs", .kind = QTOOL_OPT_INT, .off = offsetof(bake_cli, o.ndirs), .arg = "N", .lo = 16, .hi = 65536,
     .help = "light directions (spherical Fibonacci, equal weights 4 pi / N)"},
    {.name = "--lsq", .kind = QTOOL_OPT_FLAG, .off = offsetof(bake_cli, o.lsq),
     .help = "least-squares projection instead of quadrature"},
    {.name = "--budget", .kind = QTOOL_OPT_CALL, .call = bake_budget, .arg = "DB",
     .help = "the smallest k (and LUT) whose PSNR on held-out lights reaches DB"},
    {.name = "--quiet", .kind = QTOOL_OPT_FLAG, .off = offsetof(bake_cli, o.quiet), .help = "--progress none"},
    {.name = "--progress", .kind = QTOOL_OPT_ENUM, .eq = 1, .off = offsetof(bake_cli, progress),
     .names = progress_names, .def = "bar on a terminal, else lines",
     .help = "progress on stderr (also --progress=MODE)"},
    {.name = "--layout", .kind = QTOOL_OPT_ENUM, .off = offsetof(bake_cli, layout), .names = layouts,
     .help = "the maps' byte order in the asset (see qibl help gen)"},
    {.name = "--unshadowed-k", .kind = QTOOL_OPT_INT, .off = offsetof(bake_cli, o.uk), .arg = "K", .lo = 0,
     .hi = 25, .why = "0: no unshadowed maps", .help = "the unshadowed transfer's maps (SHMU), for free lamps"},
    {.name = "--sun-path", .kind = QTOOL_OPT_CALL, .call = bake_sun_path, .arg = "LAT,DECL,T0,T1",
     .help = "a sun's path (degrees, degrees, solar hours; +x east, +y north) baked as visibility edges"},
    {.name = "--lamp-track", .kind = QTOOL_OPT_CALL, .call = bake_lamp_track, .arg = "X,Y,Z;X,Y,Z;...",
     .help = "a lamp's polyline track (t by arc length) baked as visibility edges"},
    {.name = "--path-steps", .kind = QTOOL_OPT_INT, .off = offsetof(bake_cli, o.steps), .arg = "N", .lo = 2,
     .hi = 4096, .help = "samples along each path before bisection"},
    {.name = "--lamp-box", .kind = QTOOL_OPT_CALL, .call = bake_lamp_box, .arg = "X0,Y0,Z0,X1,Y1,Z1",
     .help = "the region free lamps move in (LOCC: their expected visibility)"},
    {.name = "--lamp-samples", .kind = QTOOL_OPT_INT, .off = offsetof(bake_cli, o.lamp_samples), .arg = "N",
     .lo = 1, .hi = 4096, .help = "Halton lamp positions in the box"},
    {.name = "--probe", .kind = QTOOL_OPT_STR, .off = offsetof(bake_cli, o.probe), .arg = "PROBE.hdr",
     .help = "a probe-lit asset: the probe's compact sources as light paths, the rest as SH"},
    {.name = "--yaw", .kind = QTOOL_OPT_NUM, .off = offsetof(bake_cli, o.yaw), .arg = "DEG", .lo = -360, .hi = 360,
     .help = "turn the --probe (positive turns +x toward +y)"},
    QCLI_SCENE_OPTS(NULL),
    QCLI_CAMERA_OPTS,
    {0},
};

static const qtool_opt_cmd bake_spec = {
    .name = "bake",
    QTOOL_OPT_TABLE(bake_table, bake_defaults),
    .synopsis = "(-o ASSET | --shard I/N --sums FILE | --tile I/N (--ranges-out FILE | --ranges FILE --part FILE))",
    .prose = BAKE_PROSE,
};

/* bake's options together in c->o (progress -1: not given, a bar on a terminal, lines elsewhere); 0, or 2
 * after the one line */
static int bake_check(void *opts)
{
    bake_cli *c = opts;
    qtool_bake_opts *o = &c->o;
    qcli_scene_defaults(&o->scene); /* the job's CPUs; the scene options are c->sc's */
    o->layout = layout_values[c->layout], o->progress = c->progress;
    if (qcli_scene_from(&bake_spec, &c->sc, &o->scene) != 0)
        return 2;
    if (o->quiet)
        o->progress = 0;
    else if (o->progress < 0)
        o->progress = isatty(2) ? 1 : 2;
    char err[1400] = "";
    if (qtool_bake_opts_check(o, err, sizeof err) != 0)
        return qtool_opt_error(&bake_spec, "%s", err);
    return 0;
}

static int bake_run(void *opts)
{
    char err[1400] = "";
    return job_status(qtool_bake_job(&((bake_cli *)opts)->o, stdout, stderr, err, sizeof err), err);
}

const qcli_sub qcli_sub_bake = {.opts = &bake_spec, .check = bake_check, .run = bake_run};

/* ---- qibl merge ---------------------------------------------------------------------------------- */

typedef struct merge_cli {
    qtool_merge_opts o; /* QTOOL_MERGE_OPTS_DEFAULT; o.in grows as SUMS come (the command frees it) */
    int layout;         /* index into layouts */
    size_t room;
} merge_cli;
static const merge_cli merge_defaults = {.o = QTOOL_MERGE_OPTS_DEFAULT, .layout = 0};

/* one SUMS file more: any number of them (a farm's shards) */
static const char *merge_file(void *opts, const char *v)
{
    merge_cli *c = opts;
    if ((size_t)c->o.nin == c->room) {
        size_t n = c->room ? 2 * c->room : 16;
        char **in = realloc(c->o.in, n * sizeof *in);
        if (!in)
            return "is one file too many: out of memory";
        c->o.in = in, c->room = n;
    }
    c->o.in[c->o.nin++] = (char *)(uintptr_t)v; /* qtool_merge_opts holds argv's own strings */
    return NULL;
}

static const qtool_opt merge_table[] = {
    {.name = "-o", .kind = QTOOL_OPT_STR, .off = offsetof(merge_cli, o.out), .arg = "ASSET",
     .help = "the merged asset"},
    {.name = "--sums", .kind = QTOOL_OPT_STR, .off = offsetof(merge_cli, o.sums_out), .arg = "OUT",
     .help = "the total sums (merged again later, or baked into an asset)"},
    {.name = "--manifest", .kind = QTOOL_OPT_STR, .off = offsetof(merge_cli, o.manifest), .arg = "FILE",
     .help = "the SUMS files, one per line (docs/farm.md)"},
    {.name = "--k", .kind = QTOOL_OPT_INT, .off = offsetof(merge_cli, o.k), .arg = "K", .lo = 1, .hi = 25,
     .def = "the shards' k, at most 16", .help = "the number of SH maps"},
    QCLI_LUT_SIZE_OPTS(merge_cli, o.lut),
    {.name = "--layout", .kind = QTOOL_OPT_ENUM, .off = offsetof(merge_cli, layout), .names = layouts,
     .help = "the maps' byte order in the asset (see qibl help gen)"},
    {.name = "--lsq", .kind = QTOOL_OPT_FLAG, .off = offsetof(merge_cli, o.lsq),
     .help = "least-squares projection instead of quadrature"},
    {.name = "--ranges", .kind = QTOOL_OPT_FLAG, .off = offsetof(merge_cli, o.ranges),
     .help = "reduce tiles' ranges files (bake --tile --ranges-out) into -o RANGES"},
    {0},
};

static const qtool_opt_cmd merge_spec = {
    .name = "merge",
    QTOOL_OPT_TABLE(merge_table, merge_defaults),
    .pos = {.names = "SUMS...", .min = 0, .max = QTOOL_OPT_LIST_MAX, .call = merge_file},
    .synopsis = "(-o ASSET | --sums OUT | both) (--manifest FILE | SUMS...)",
    .prose =
        "  Adds the partial sums written by `qibl bake --shard I/N --sums FILE` (every shard exactly once,\n"
        "  same bake) and writes the asset as qibl bake would (byte-identical, with the unshadowed maps,\n"
        "  light paths and lamp occlusion joined from every SUMS.u / SUMS.x when the shards wrote them), and/or the\n"
        "  total sums.\n"
        "  Every file is checked before use (version, CRC-32s, counts within the bake's limits, exact size),\n"
        "  then against the first (split, size, k, directions, P map); sums that would overflow 64 bits, a\n"
        "  shard given twice or missing, and --k above the shards' k are refused by name; so are shards whose\n"
        "  light paths or lamp occlusion (SUMS.x) differ (one baked without the others' --sun-path).\n"
        "  --manifest FILE: the shards named one per line, \"shard I/N SUMS [SUMS.u [SUMS.x]]\" ('-' for a\n"
        "  side file the shard has not; '#' comments), each file's I/N checked against the line.\n"
        "  A partial set (tree merges, --sums OUT without -o): shards I, I+M, I+2M, ... of N (M dividing N)\n"
        "  are written as shard I/M with OUT.u and OUT.x, for a later merge; any other partial set is refused.\n"
        "  Tile shards (bake --tile, docs/farm.md): --ranges -o R FILE... reduces every tile's ranges (each\n"
        "  tile once, one bake); -o ASSET PART... joins every tile's part (bake --tile --ranges --part) into\n"
        "  the asset, its LUT and layout the parts'; another bake, other ranges, a tile missing, given twice\n"
        "  or of another split are refused by name.\n"
        "  Exit status: 0 written, 1 refused or failed (named on stderr, nothing written), 2 bad arguments.\n",
};

static int merge_check(void *opts)
{
    merge_cli *c = opts;
    if ((c->o.nin == 0 && !c->o.manifest) || (!c->o.out && !c->o.sums_out))
        return qtool_opt_error(&merge_spec, "needs -o ASSET or --sums OUT (or both), and --manifest FILE or SUMS...");
    c->o.layout = layout_values[c->layout];
    return 0;
}

static int merge_run(void *opts)
{
    char err[4400] = "";
    return job_status(qtool_bake_merge(&((merge_cli *)opts)->o, stdout, err, sizeof err), err);
}

static void merge_drop(void *opts)
{
    free(((merge_cli *)opts)->o.in);
}

const qcli_sub qcli_sub_merge = {.opts = &merge_spec, .check = merge_check, .run = merge_run, .drop = merge_drop};

/* ---- qibl check ---------------------------------------------------------------------------------- */

/* the files are argv's own: the table only refuses flags (there are none) */
typedef struct check_cli {
    int n;
    int argc;
    char **argv;
} check_cli;

static const char *check_file(void *opts, const char *v)
{
    (void)v;
    ++((check_cli *)opts)->n;
    return NULL;
}

static const qtool_opt_cmd check_spec = {
    .name = "check",
    .pos = {.names = "FILE...", .min = 1, .max = QTOOL_OPT_LIST_MAX, .call = check_file},
    .size = sizeof(check_cli),
    .prose =
        "  .png: signature, every chunk CRC, the zlib stream (inflated), Adler-32, APNG frame sequence;\n"
        "  .pfm: header and size; .hdr/.pic: Radiance header, resolution line and every scanline (RLE or\n"
        "  flat) decoded, as qibl lights reads it; .exr (or the EXR magic): header and every chunk decoded;\n"
        "  anything else as a qibl asset (qibl_asset_open).\n"
        "  Exit 1 if any is bad.\n",
};

static int check_check(void *opts, int argc, char **argv)
{
    check_cli *c = opts;
    if (c->n == 0)
        return qtool_opt_error(&check_spec, "needs FILE...");
    c->argc = argc, c->argv = argv;
    return 0;
}

static int check_run(void *opts)
{
    const check_cli *c = opts;
    int argc = c->argc;
    char **argv = c->argv;
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

const qcli_sub qcli_sub_check = {.opts = &check_spec, .check_line = check_check, .run = check_run};
