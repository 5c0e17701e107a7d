/*
 * cmd_transfer.c - `qibl transfer MESH... --probe PROBE.hdr --png OUT`: a mesh self-shadowed by
 * hemispherical rasterization (qibl/hemi.h) under a real probe's SH, beside the ray-cast reference
 * and the error. The computation is tools/transfer (transfer/run.h: qtool_transfer_measure); this
 * command parses the options by its option table (opt/opt.h) into its struct, calls it, prints the
 * report and writes the picture (an APNG when several MESH files are frames of one animation).
 * --export (a file) and --export-c (a C array) write a static mesh's per-vertex transfer vectors
 * for an engine to shade (transfer/export.h, qibl_hemi_xfer_*).
 */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli/cli.h"
#include "io/png.h"
#include "transfer/export.h"
#include "io/atomic.h"
#include "transfer/run.h"

/* the report of a finished run, as the command has always printed it */
/* where --export and --export-c go, and how many bands */
typedef struct exports {
    const char *qtr, *c;
    int bands;
} exports;

static void report(const qtool_transfer_opts *o, const qtool_transfer_result *r, const char *png, const exports *x)
{
    printf("transfer: %s%s: %u vertices, %u triangles, %u frame%s; %s%s; probe %s (%s)\n", o->files[0],
           o->nfiles > 1 ? " ..." : "", r->nv, r->nt, r->nframes, r->nframes > 1 ? "s" : "",
           o->zup ? "z up" : "y up turned to z up",
           o->flip ? ", normals turned (--flip)" : r->flipped ? ", closed and wound clockwise (normals turned)" : "",
           o->probe, r->probe_desc);
    printf("  hemi: %dx%d mask, face %d (%.1f KiB of tables), %s\n", o->mask, o->mask, o->face, r->hemi_bytes / 1024.0,
           o->skip_adjacent ? "adjacent faces skipped (--skip-adjacent)" : "the solid behind the faces around each vertex blocks");
    if (o->coarse > 0)
        printf("  hierarchy: coarse mesh of %u triangles (QEM half-edge collapses, vertices a subset of the mesh's) +\n"
               "  the full mesh within %d rings of each vertex: %.1f blockers per vertex (of %u, crease wedges included)\n",
               r->coarse_nt, o->ring, r->hier_blockers, r->nt);
    else
        printf("  every triangle a blocker of every vertex (--coarse T: a two-level hierarchy instead)\n");
    if (o->rays > 0)
        printf("  reference: %d x %d stratified cosine-weighted rays per vertex (tools/ref/hemi_ref.c)\n", o->rays, o->rays);
    for (uint32_t f = 0; f < r->nframes; ++f)
        if (r->no_normal[f])
            printf("  frame %u: %u vertices without a normal (isolated or degenerate): shaded black\n", f + 1,
                   r->no_normal[f]);
    const double n = (double)r->nv * r->nframes;
    printf("  hemi: %.2f ms per frame on one core (%.1f us per vertex, %u blockers each)\n", r->ms_per_frame,
           r->ms_per_frame * r->nframes / n * 1e3, r->nt);
    printf("RESULT transfer.ms_per_frame %.3f\n", r->ms_per_frame);
    if (o->pvs) {
        printf("  PVS over the %u frame%s: %.1f blockers per vertex (of %.1f), %.2f ms per frame (of %.2f); masks "
               "identical on %.0f of %.0f vertex-frames\n", r->nframes, r->nframes > 1 ? "s" : "", r->pvs_blockers,
               r->blockers, r->pvs_ms_per_frame, r->ms_per_frame, n - r->pvs_diff, n);
        printf("RESULT transfer.pvs_ms_per_frame %.3f\nRESULT transfer.pvs_blockers %.1f\n", r->pvs_ms_per_frame,
               r->pvs_blockers);
    }
    /* in the probe's units times 2^-k (the light's scaling): comparable between meshes under one probe */
    printf("RESULT transfer.mean_irradiance %.6f\n", r->mean_irradiance);
    if (o->rays > 0) {
        printf("  error of V* against the reference: mean relative L2 %.4f (reference noise %.4f, same measure)\n",
               r->l2err, r->ref_noise);
        printf("  shading error: mean |E - E_ref| / mean E_ref = %.4f\n", r->shade_err);
        printf("RESULT transfer.l2err %.5f\nRESULT transfer.ref_noise %.5f\nRESULT transfer.shade_err %.5f\n", r->l2err,
               r->ref_noise, r->shade_err);
    }
    if (png)
        printf("  wrote %s (%dx%d%s)\n", png, r->sheet_w, r->sheet_h, r->nframes > 1 ? ", animated" : "");
    for (int k = 0; k < 2; ++k)
        if (k ? x->c : x->qtr)
            printf("  exported %s: %u vertices x %d SH coefficients, Q2.30 world-space transfer (%u bytes%s)\n",
                   k ? x->c : x->qtr, r->nv, x->bands * x->bands,
                   QIBL_HEMI_XFER_HEADER_SIZE + r->nv * (uint32_t)(x->bands * x->bands) * 4u, k ? " as a C array" : "");
}

/* frame 0's transfer into the export file and/or the C header; 0 or -1 with err */
static int write_exports(const qtool_transfer_result *r, const exports *x, char *err, size_t errlen)
{
    uint8_t *b;
    size_t n;
    if (qtool_transfer_export_bytes((const qibl_q30_t(*)[QIBL_HEMI_COEFFS])r->transfer, r->nv, x->bands, &b, &n, err,
                                    errlen) != 0)
        return -1;
    int rc = x->qtr ? qtool_io_write_atomic(x->qtr, b, n, err, errlen) : 0;
    if (rc == 0 && x->c)
        rc = qtool_transfer_export_write_c(x->c, b, n, NULL, err, errlen);
    free(b);
    return rc;
}

/* the run, the picture and the report; 0 or 1 */
static int transfer_main(const qtool_transfer_opts *o, const char *png, const exports *x)
{
    qtool_transfer_result r;
    char err[600];
    if (qtool_transfer_measure(o, &r, err, sizeof err) != 0)
        return fprintf(stderr, "qibl: transfer: %s\n", err), 1;
    int rc = 0;
    if (o->keep_transfer && write_exports(&r, x, err, sizeof err) != 0)
        fprintf(stderr, "qibl: transfer: %s\n", err), rc = 1;
    if (rc == 0 && png) {
        const int wr = r.nframes > 1 ? qtool_apng_write_rgb8(png, r.sheet_w, r.sheet_h, (int)r.nframes, r.sheet, 1, 8,
                                                             err, sizeof err)
                                     : qtool_png_write_rgb8(png, r.sheet_w, r.sheet_h, r.sheet, err, sizeof err);
        if (wr != 0)
            fprintf(stderr, "qibl: %s\n", err), rc = 1;
    }
    if (rc == 0)
        report(o, &r, png, x);
    qtool_transfer_result_free(&r);
    return rc;
}

/* What `qibl transfer` was asked: the library's options (transfer/run.h), with the integers as the
 * table's longs beside them (copied in once parsed), and what the command writes. */
typedef struct transfer_cli {
    qtool_opt_list mesh;
    qtool_transfer_opts o; /* probe, the switches, the view */
    long lights, size, face, rays, coarse, ring, tween, threads, bands;
    int layout;            /* index = value (qtool_relight_probe_layout_names) */
    int mask;              /* index into masks: the side 16 << mask */
    const char *png;
    exports x;
} transfer_cli;

static const transfer_cli transfer_defaults = {
    .o = QTOOL_TRANSFER_OPTS_DEFAULT, .size = QTOOL_TRANSFER_SIZE_DEFAULT,
    .mask = QTOOL_TRANSFER_MASK_DEFAULT / 32, /* 16, 32, 64: index 0, 1, 2 */
    .face = QIBL_HEMI_FACE_DEFAULT, .rays = QTOOL_TRANSFER_RAYS_DEFAULT, .ring = QTOOL_TRANSFER_RING_DEFAULT,
    .tween = QTOOL_TRANSFER_TWEEN_DEFAULT, .threads = 0 /* the job's CPUs */, .layout = QTOOL_PROBE_LAYOUT_AUTO,
    .bands = QTOOL_TRANSFER_EXPORT_BANDS_DEFAULT};

static const char *const masks[] = {"16", "32", "64", NULL};

static const char *view_call(void *opts, const char *v)
{
    qtool_transfer_opts *o = &((transfer_cli *)opts)->o;
    return qcli_parse_azel(v, 89.9, &o->az, &o->el) != 0 ? "is not AZ,EL in degrees (|EL| < 90), e.g. 35,20" : NULL;
}

#define T_(field) offsetof(transfer_cli, field)
static const qtool_opt transfer_table[] = {
    {.name = "--probe", .kind = QTOOL_OPT_STR, .off = T_(o.probe), .arg = "PROBE.hdr", .required = 1,
     .help = "the light probe whose radiance SH shades the mesh"},
    {.name = "--layout", .kind = QTOOL_OPT_ENUM, .off = T_(layout), .names = qtool_relight_probe_layout_names,
     .arg = "L", .help = "the probe's layout: auto (detected), latlong, angular, ball, vcross or hcross"},
    {.name = "--lights", .kind = QTOOL_OPT_INT, .off = T_(lights), .lo = 1, .hi = 1024, .why = "a power of two",
     .def = "none: the probe's own SH", .help = "the probe's N median-cut lights projected to SH instead"},
    {.name = "--png", .kind = QTOOL_OPT_STR, .off = T_(png), .arg = "OUT",
     .help = "qibl | ray cast | error, side by side (an animated PNG for several MESH)"},
    {.name = "--size", .kind = QTOOL_OPT_INT, .off = T_(size), .lo = 64, .hi = 2048, .why = "pixels per panel",
     .help = "the pictures' panels"},
    {.name = "--view", .kind = QTOOL_OPT_CALL, .call = view_call, .arg = "AZ,EL", .def = "35,20",
     .help = "the pictures' orthographic view: azimuth and elevation in degrees"},
    {.name = "--mask", .kind = QTOOL_OPT_ENUM, .off = T_(mask), .names = masks,
     .help = "the hemicube mask's side"},
    {.name = "--face", .kind = QTOOL_OPT_INT, .off = T_(face), .arg = "F", .lo = 2, .hi = QIBL_HEMI_MAX_FACE,
     .why = "even", .help = "the hemi LUT's cube-map face"},
    {.name = "--rays", .kind = QTOOL_OPT_INT, .off = T_(rays), .arg = "S", .lo = 0, .hi = 256,
     .why = "0: no reference", .help = "S x S reference rays per vertex"},
    {.name = "--coarse", .kind = QTOOL_OPT_INT, .off = T_(coarse), .arg = "T", .lo = 0, .hi = 1 << 20,
     .what = "a triangle count", .why = "0: no hierarchy", .help = "the two-level hierarchy's coarse triangles"},
    {.name = "--ring", .kind = QTOOL_OPT_INT, .off = T_(ring), .arg = "K", .lo = 1, .hi = QTOOL_TRANSFER_MAX_RING,
     .help = "with --coarse: the full mesh within K edges of each vertex"},
    {.name = "--pvs", .kind = QTOOL_OPT_FLAG, .off = T_(o.pvs),
     .help = "also each vertex from its PVS over the frames: timed, masks compared"},
    {.name = "--tween", .kind = QTOOL_OPT_INT, .off = T_(tween), .lo = 1, .hi = QTOOL_TRANSFER_MAX_TWEEN,
     .why = "frames per key frame", .help = "N - 1 frames interpolated between key frames"},
    {.name = "--zup", .kind = QTOOL_OPT_FLAG, .off = T_(o.zup), .help = "the meshes are Z-up (not turned from Y-up)"},
    {.name = "--flip", .kind = QTOOL_OPT_FLAG, .off = T_(o.flip), .help = "turn the normals"},
    {.name = "--skip-adjacent", .kind = QTOOL_OPT_FLAG, .off = T_(o.skip_adjacent),
     .help = "the paper's rule alone: the faces around a vertex skipped, the solid behind them not"},
    {.name = "--threads", .kind = QTOOL_OPT_INT, .off = T_(threads), .lo = 1, .hi = 256,
     .def = "the CPUs of the process's affinity, or SLURM_CPUS_PER_TASK", .help = "worker threads"},
    {.name = "--export", .kind = QTOOL_OPT_STR, .off = T_(x.qtr), .arg = "FILE.qtr",
     .help = "a static mesh's per-vertex transfer vectors (qibl_hemi_xfer_*), for an engine to shade"},
    {.name = "--export-c", .kind = QTOOL_OPT_STR, .off = T_(x.c), .arg = "FILE.h", .help = "the same as a C array"},
    {.name = "--export-bands", .kind = QTOOL_OPT_INT, .off = T_(bands), .arg = "3|4|5", .lo = 3, .hi = 5,
     .why = "9, 16 or 25 coefficients", .help = "the SH bands exported"},
    {0},
};

static const qtool_opt_cmd transfer_spec = {
    QTOOL_OPT_CMD("transfer", transfer_table, transfer_defaults, "MESH [MESH...]", 1, QTOOL_TRANSFER_MAX_FRAMES,
                  transfer_cli, mesh),
    .synopsis = "MESH [MESH...] --probe PROBE.hdr",
    .prose =
        "  Per vertex of a glTF (.gltf, .glb: the scene's meshes in world space, skinned; FILE.gltf@T: its\n"
        "  animation at T seconds, so FILE.gltf@0 FILE.gltf@0.5 ... are frames), OBJ or PLY mesh\n"
        "  (welded by position, centred, largest half-extent 1, Y-up turned\n"
        "  to Z-up unless --zup; normals point out of counter-clockwise faces, turned by --flip or when a\n"
        "  mesh with under 2 % open edges has a negative volume), the transfer vector V*\n"
        "  (bands 0..4) from hemispherical rasterization with every triangle a blocker (qibl/hemi.h: mask\n"
        "  --mask, LUT face --face), turned to world space and shaded with the\n"
        "  probe's radiance SH (irradiance; pictures at an automatic exposure). --skip-adjacent: the paper's\n"
        "  rule alone (faces around a vertex skipped) instead of also blocking the solid behind them at\n"
        "  creases. Reference: S x S stratified cosine-weighted\n"
        "  rays per vertex (--rays; 0: none) through a BVH, shaded with the same coefficients.\n"
        "  --coarse T: the paper's two-level hierarchy instead of every triangle: a coarse mesh of about T\n"
        "  triangles (quadric-error half-edge collapses, so its vertices are the mesh's and it animates with\n"
        "  it) plus the full mesh within K edges of each vertex (--ring).\n"
        "  --png: qibl | ray cast | error (|E - E_ref| / mean E_ref, 0..10 %), drawn by platform/soft's\n"
        "  integer z-buffer rasterizer, orthographic from azimuth / elevation --view (default 35,20);\n"
        "  several MESH files are frames of one animation (same triangles, at most 64): an animated PNG\n"
        "  (--tween N: N - 1 frames interpolated between key frames, the last back into the first). Prints\n"
        "  ms per frame on one core (thread CPU time of the hemi calls) and RESULT transfer.* lines.\n"
        "  --pvs: each vertex also rasterized against its potentially visible set over all the frames.\n"
        "  --export FILE.qtr / --export-c FILE.h: frame 0's world-space transfer of a static mesh (one MESH)\n"
        "  in Q2.30, --export-bands of them (transfer/export.h), for `qibl view MESH --transfer` or an engine.\n",
};

/* what a range cannot say */
static int transfer_check(void *opts)
{
    const qtool_opt_cmd *t = &transfer_spec;
    const transfer_cli *c = opts;
    if (c->lights & (c->lights - 1))
        return qtool_opt_error(t, "--lights: %ld is not a power of two (median-cut lights of the probe)", c->lights);
    if (c->face & 1)
        return qtool_opt_error(t, "--face: %ld is not even", c->face);
    if ((c->x.qtr || c->x.c) && c->mesh.n > 1)
        return qtool_opt_error(t, "--export is for a static mesh: one MESH, not %d frames", c->mesh.n);
    return 0;
}

static int transfer_run(void *opts)
{
    transfer_cli *c = opts;
    qtool_transfer_opts o = c->o;
    o.files = (char *const *)c->mesh.v, o.nfiles = c->mesh.n; /* argv's strings */
    o.layout = (qtool_probe_layout_t)c->layout, o.lights = (int)c->lights, o.size = (int)c->size,
    o.mask = 16 << c->mask;
    o.face = (int)c->face, o.rays = (int)c->rays, o.coarse = (int)c->coarse, o.ring = (int)c->ring;
    o.tween = (int)c->tween, o.threads = c->threads ? (int)c->threads : qcli_default_threads();
    o.sheet = c->png != NULL, o.keep_transfer = c->x.qtr || c->x.c;
    c->x.bands = (int)c->bands;
    return transfer_main(&o, c->png, &c->x);
}

const qcli_sub qcli_sub_transfer = {.opts = &transfer_spec, .check = transfer_check, .run = transfer_run};
