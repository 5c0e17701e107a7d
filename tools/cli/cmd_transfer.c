/*
 * cmd_transfer.c - `qibl transfer MESH... --probe PROBE.hdr --png OUT`: a mesh self-shadowed by
 * hemispherical rasterization (qibl/hemi.h) under a real probe's SH, beside the ray-cast reference
 * and the error. The computation is tools/transfer (transfer/run.h: qtool_transfer_measure); this
 * command parses the options into its struct, calls it, prints the report and writes the picture
 * (an APNG when several MESH files are frames of one animation). --export (a file) and --export-c
 * (a C array) write a static mesh's per-vertex transfer vectors for an engine to shade
 * (transfer/export.h, qibl_hemi_xfer_*).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "io/png.h"
#include "transfer/export.h"
#include "io/atomic.h"
#include "transfer/run.h"

#define TRANSFER_USAGE                                                                                        \
    "usage: qibl transfer MESH [MESH...] --probe PROBE.hdr [--layout L] [--png OUT] [--size N] [--mask 16|32|64]\n" \
    "                     [--face F] [--rays S] [--coarse T [--ring K]] [--pvs] [--lights N] [--tween N] [--zup] [--flip] [--skip-adjacent] [--view AZ,EL] [--threads N]\n" \
    "                     [--export FILE.qtr] [--export-c FILE.h] [--export-bands 3|4|5]"

static int parse_view(const char *s, double *az, double *el)
{
    char *end;
    *az = strtod(s, &end);
    if (end == s || *end != ',' || !isfinite(*az))
        return -1;
    const char *t = end + 1;
    *el = strtod(t, &end);
    return end == t || *end || !isfinite(*el) || fabs(*el) > 89.9 ? -1 : 0;
}

static int bands_ok(long v)
{
    return v >= 3 && v <= 5;
}

static int any(long v)
{
    return (void)v, 1;
}

static int pow2(long v)
{
    return (v & (v - 1)) == 0;
}

static int mask_side(long v)
{
    return v == 16 || v == 32 || v == 64;
}

static int even(long v)
{
    return (v & 1) == 0;
}

/* the integer options: name, range and rule, where, what a bad value is told */
typedef struct int_opt {
    const char *name;
    long lo, hi;
    int (*ok)(long);
    int *dst;
    const char *why;
} int_opt;

#define STR_(x) #x
#define STR(x) STR_(x)

/* 1 if a is one of the integer options (parsed, or *rc the usage error), else 0 */
static int parse_int_opt(const int_opt *t, int n, int argc, char **argv, int *i, int *rc)
{
    for (int k = 0; k < n; ++k) {
        if (strcmp(argv[*i], t[k].name) != 0)
            continue;
        long v = 0;
        *rc = 0;
        if (*i + 1 >= argc || qcli_parse_int(argv[++*i], t[k].lo, t[k].hi, &v) != 0 || !t[k].ok(v))
            *rc = qcli_usage_error("%s", t[k].why);
        else
            *t[k].dst = (int)v;
        return 1;
    }
    return 0;
}

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

int qcli_cmd_transfer(int argc, char **argv)
{
    char *files[QTOOL_TRANSFER_MAX_FRAMES];
    const char *png = NULL, *layout = NULL;
    exports x = {.qtr = NULL, .c = NULL, .bands = QTOOL_TRANSFER_EXPORT_BANDS_DEFAULT};
    qtool_transfer_opts o = QTOOL_TRANSFER_OPTS_DEFAULT;
    o.threads = 0; /* 0 until given: the job's CPUs */
    const int_opt ints[] = {
        {"--coarse", 0, 1 << 20, any, &o.coarse, "--coarse needs a triangle count in 0..1048576 (0: no hierarchy)"},
        {"--lights", 1, 1024, pow2, &o.lights, "--lights needs a power of two in 1..1024 (median-cut lights of the probe)"},
        {"--tween", 1, QTOOL_TRANSFER_MAX_TWEEN, any, &o.tween, "--tween needs an integer in 1..16 (frames per key frame)"},
        {"--ring", 1, QTOOL_TRANSFER_MAX_RING, any, &o.ring, "--ring needs an integer in 1..16"},
        {"--size", 64, 2048, any, &o.size, "--size needs an integer in 64..2048 (pixels per panel)"},
        {"--mask", 16, 64, mask_side, &o.mask, "--mask needs 16, 32 or 64"},
        {"--face", 2, QIBL_HEMI_MAX_FACE, even, &o.face, "--face needs an even integer in 2.." STR(QIBL_HEMI_MAX_FACE)},
        {"--rays", 0, 256, any, &o.rays, "--rays needs S in 0..256 (S x S rays per vertex; 0: no reference)"},
        {"--threads", 1, 256, any, &o.threads, "--threads needs an integer in 1..256"},
        {"--export-bands", 3, 5, bands_ok, &x.bands, "--export-bands needs 3, 4 or 5 (9, 16 or 25 coefficients)"},
    };
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const int more = i + 1 < argc;
        int rc = 0;
        if (parse_int_opt(ints, (int)(sizeof ints / sizeof ints[0]), argc, argv, &i, &rc)) {
            if (rc != 0)
                return rc;
        } else if (strcmp(a, "--probe") == 0 && more)
            o.probe = argv[++i];
        else if (strcmp(a, "--png") == 0 && more)
            png = argv[++i];
        else if (strcmp(a, "--layout") == 0 && more)
            layout = argv[++i];
        else if (strcmp(a, "--export") == 0 && more)
            x.qtr = argv[++i];
        else if (strcmp(a, "--export-c") == 0 && more)
            x.c = argv[++i];
        else if (strcmp(a, "--zup") == 0)
            o.zup = 1;
        else if (strcmp(a, "--flip") == 0)
            o.flip = 1;
        else if (strcmp(a, "--skip-adjacent") == 0)
            o.skip_adjacent = 1;
        else if (strcmp(a, "--pvs") == 0)
            o.pvs = 1;
        else if (strcmp(a, "--view") == 0) {
            if (!more || parse_view(argv[++i], &o.az, &o.el) != 0)
                return qcli_usage_error("--view needs AZ,EL in degrees (|EL| < 90), e.g. 35,20");
        } else if (a[0] == '-') {
            return qcli_usage_error("transfer: unknown or incomplete option '%s' (%s)", a, TRANSFER_USAGE);
        } else if (o.nfiles == QTOOL_TRANSFER_MAX_FRAMES) {
            return qcli_usage_error("transfer: at most %d frames", QTOOL_TRANSFER_MAX_FRAMES);
        } else {
            files[o.nfiles++] = argv[i];
        }
    }
    if (o.nfiles == 0 || !o.probe)
        return qcli_usage_error(TRANSFER_USAGE);
    if ((x.qtr || x.c) && o.nfiles > 1)
        return qcli_usage_error("--export is for a static mesh: one MESH, not %d frames", o.nfiles);
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    o.files = files, o.sheet = png != NULL, o.keep_transfer = x.qtr || x.c;
    if (o.threads == 0)
        o.threads = qcli_default_threads();
    if (layout && qtool_probe_layout_parse(layout, &o.layout) != 0)
        return qcli_usage_error("--layout: unknown layout '%s'", layout), 1;
    return transfer_main(&o, png, &x);
}
