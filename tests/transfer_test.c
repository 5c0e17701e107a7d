/*
 * transfer_test.c - `qibl transfer`'s computation (tools/transfer/run.h, qtool_transfer_measure)
 * and its command (tools/cli/cmd_transfer.c): hemispherical-rasterization transfer of a mesh under
 * a probe against the ray-cast reference, on meshes and probes the test writes itself: a plane
 * (nothing blocks: qibl and the reference agree to the mask's resolution), an open box whose floor
 * is shadowed by its walls, the hierarchy and the PVS, the probe's median-cut lights as the
 * lighting (these through the library); a two-frame animation (an animated PNG of the documented
 * size), the report, and every refusal by name with nothing written (these through the binary).
 */
#include <math.h>

#include "cliutil.h"
#include "io/hdr_write.h"
#include "io/png.h"
#include "transfer/export.h"
#include "transfer/run.h"

CLI_FIXTURES("/tmp/qibl_transfer_test_XXXXXX")

static void path_of(char *out, size_t n, const char *name)
{
    snprintf(out, n, "%s/%s", dir, name);
}

/* a constant-radiance probe (1.0) or a sky with a sun: bright pixels near the zenith-ish */
static void write_probe(const char *path, int sun)
{
    enum { PW = 64, PH = 32 };
    static float rgb[PW * PH * 3];
    for (int y = 0; y < PH; ++y)
        for (int x = 0; x < PW; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[3 * (y * PW + x) + c] = sun && y == 6 && (x == 10 || x == 11) ? 400.0f : y < PH / 2 ? 1.0f : 0.2f;
    char err[256];
    assert_int_equal(qtool_hdr_write(path, PW, PH, rgb, err, sizeof err), 0);
}

static void write_text(const char *path, const char *s)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(s, f);
    fclose(f);
}

/* an open box (Y up): floor 2 x 2 at y = 0 split into 4 x 4 quads, walls of height h, plus dz */
static void write_box(const char *path, double h, double dz, int extra_tri)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i)
            fprintf(f, "v %g 0 %g\n", -1 + i * 0.5, -1 + j * 0.5 + dz);
    /* wall tops: 4 corners at height h */
    fprintf(f, "v -1 %g %g\nv 1 %g %g\nv 1 %g %g\nv -1 %g %g\n", h, -1 + dz, h, -1 + dz, h, 1 + dz, h, 1 + dz);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const int a = 1 + j * 5 + i, b = a + 1, c = a + 5, d = c + 1;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", a, c, d, a, d, b); /* up-facing (y) */
        }
    /* floor corners: 1 (-1,-1), 5 (1,-1), 25 (1,1), 21 (-1,1); tops 26..29 */
    fprintf(f, "f 1 5 27\nf 1 27 26\n");   /* wall z = -1 */
    fprintf(f, "f 5 25 28\nf 5 28 27\n");  /* wall x = 1 */
    fprintf(f, "f 25 21 29\nf 25 29 28\n"); /* wall z = 1 */
    fprintf(f, "f 21 1 26\nf 21 26 29\n");  /* wall x = -1 */
    if (extra_tri)
        fprintf(f, "f 26 27 28\n");
    fclose(f);
}

static double result(const char *out, const char *name)
{
    const char *p = strstr(out, name);
    assert_non_null(p);
    return strtod(p + strlen(name), NULL);
}

/* the defaults of `qibl transfer` with S x S reference rays */
static qtool_transfer_opts opts(int rays)
{
    qtool_transfer_opts o = QTOOL_TRANSFER_OPTS_DEFAULT;
    o.rays = rays;
    return o;
}

/* the library's run of one mesh (f2 NULL) or two frames under probe */
static qtool_transfer_result measure(const char *f1, const char *f2, const char *probe, qtool_transfer_opts o)
{
    char *files[2] = {(char *)f1, (char *)f2};
    o.files = files, o.nfiles = f2 ? 2 : 1, o.probe = probe;
    qtool_transfer_result r;
    char err[600];
    const int rc = qtool_transfer_measure(&o, &r, err, sizeof err);
    if (rc != 0)
        print_message("qtool_transfer_measure: %s\n", err);
    assert_int_equal(rc, 0);
    return r;
}

static void test_plane_matches_reference(void **state)
{
    (void)state;
    need_qibl();
    char probe[128], mesh[128], png[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(mesh, sizeof mesh, "plane.obj"), path_of(png, sizeof png, "p.png");
    write_probe(probe, 1);
    /* a duplicate vertex written as -0 welds with its +0 twin */
    write_text(mesh, "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv 1 -0 1\nf 1 4 3\nf 1 5 2\n");
    assert_int_equal(run("transfer", mesh, "--probe", probe, "--rays", "24", "--png", png, "--size", "64", NULL), 0);
    char *out = text(outlog);
    /* nothing blocks: both sides integrate the same unblocked hemisphere; what is left is the
     * 32x32 mask's sampling of the basis (under 1 %) and the reference's noise */
    assert_true(result(out, "RESULT transfer.l2err") < 0.03);
    assert_true(result(out, "RESULT transfer.shade_err") < 0.01);
    assert_non_null(strstr(out, "4 vertices, 2 triangles"));
    /* the LUT face by default: QIBL_HEMI_FACE_DEFAULT, the largest within 1 MiB (once a local 64) */
    char face[64];
    snprintf(face, sizeof face, "face %u (969.5 KiB of tables)", QIBL_HEMI_FACE_DEFAULT);
    assert_non_null(strstr(out, face));
    int w, h, frames;
    uint8_t *rgb;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(png, &w, &h, &frames, &rgb, err, sizeof err), 0);
    assert_int_equal(w, 3 * 64), assert_int_equal(h, 24 + 64 + 22), assert_int_equal(frames, 1);
    free(rgb), free(out);
}

static void test_box_floor_shadowed(void **state)
{
    (void)state;
    char probe[128], mesh[128], flat[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(mesh, sizeof mesh, "box.obj"), path_of(flat, sizeof flat, "flat.obj");
    write_probe(probe, 0);
    write_box(mesh, 1.0, 0, 0);
    /* the same box with walls of height ~0: the floor sees the whole sky */
    write_box(flat, 1e-6, 0, 0);
    qtool_transfer_opts o = opts(24);
    o.skip_adjacent = 1;
    const double l2_skip = measure(mesh, NULL, probe, o).l2err;
    /* The box is all creases (floor meets walls at 90 degrees, corners averaged): skipping the
     * faces around a vertex (the paper) lets it see through them; the wedges between those faces
     * and the nadir bring it to the ray cast's answer, up to the T-junctions where the floor's
     * edge vertices sit on a wall they are not part of. */
    qtool_transfer_result r = measure(mesh, NULL, probe, opts(24));
    const double l2 = r.l2err, noise = r.ref_noise;
    assert_true(l2 < 0.10 + noise);
    assert_true(l2 < 0.5 * l2_skip);
    assert_true(r.shade_err < 0.08);
    assert_int_equal(r.nt, 40);
    const double boxed = r.mean_irradiance;
    /* walls as high as the box is wide hide much of the sky from the floor */
    assert_true(boxed < 0.8 * measure(flat, NULL, probe, opts(0)).mean_irradiance);
    /* the two-level hierarchy: a coarse box (its vertices the mesh's) + 4 rings of the full one (fewer
     * rings leave out the walls near a floor vertex, see docs/ARCHITECTURE.md) */
    o = opts(24);
    o.coarse = 20, o.ring = 4;
    r = measure(mesh, NULL, probe, o);
    assert_true(r.coarse_nt > 0 && r.coarse_nt <= 20 && r.hier_blockers > 0);
    assert_true(r.l2err < 0.10 + noise);
    /* with the whole mesh as its own coarse mesh the hierarchy holds every triangle exactly once
     * (near field or far field, no hole between them), so it shades like every triangle, ring 1
     * to 3 (the near field once missed the triangles whose three vertices lie on the ring's edge) */
    const double all = measure(mesh, NULL, probe, opts(0)).mean_irradiance;
    for (int ring = 1; ring <= 3; ++ring) {
        o = opts(0);
        o.coarse = 1000, o.ring = ring;
        assert_true(fabs(measure(mesh, NULL, probe, o).mean_irradiance - all) <= 1e-6 * all);
    }
}

/* the library's refusals: a one-line reason, the result zeroed, nothing held */
static void test_measure_refusals(void **state)
{
    (void)state;
    char probe[128], mesh[128], missing[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(mesh, sizeof mesh, "rbox.obj");
    path_of(missing, sizeof missing, "missing.obj");
    write_probe(probe, 0);
    write_box(mesh, 1.0, 0, 0);
    char *files[1] = {mesh};
    const char *why[] = {"tween", "lights", "ring", "no probe", "missing mesh", "time_reps"};
    for (int k = 0; k < 6; ++k) {
        qtool_transfer_opts o = opts(0);
        o.files = files, o.nfiles = 1, o.probe = probe;
        if (k == 0)
            o.tween = 0;
        else if (k == 1)
            o.lights = 3;
        else if (k == 2)
            o.ring = 0;
        else if (k == 3)
            o.probe = NULL;
        else if (k == 5)
            o.time_reps = QTOOL_TRANSFER_MAX_TIME_REPS + 1;
        else
            files[0] = missing;
        qtool_transfer_result r;
        memset(&r, 0x5A, sizeof r);
        char err[600] = "";
        print_message("refusal: %s\n", why[k]);
        assert_int_equal(qtool_transfer_measure(&o, &r, err, sizeof err), -1);
        assert_true(err[0] != '\0');
        assert_null(r.sheet), assert_null(r.transfer), assert_int_equal(r.nv, 0);
    }
}

/* --export: frame 0's transfer, which the core shades (qibl_hemi_xfer_shade_span under the run's
 * light) to the very values the run's own shading gave, bit for bit; the command writes the bytes
 * the library makes; refusals write nothing. */
static void test_export_round_trip(void **state)
{
    (void)state;
    char probe[128], mesh[128], xp[128], f2[128];
    path_of(probe, sizeof probe, "sun.hdr"), path_of(mesh, sizeof mesh, "xbox.obj"), path_of(xp, sizeof xp, "b.qtr");
    path_of(f2, sizeof f2, "xbox2.obj");
    write_probe(probe, 1);
    write_box(mesh, 1.0, 0, 0), write_box(f2, 0.5, 0.25, 0);
    qtool_transfer_opts o = opts(0);
    o.keep_transfer = 1;
    qtool_transfer_result r = measure(mesh, NULL, probe, o);
    assert_non_null(r.transfer), assert_non_null(r.shade);
    uint8_t *b;
    size_t n;
    char err[600];
    assert_int_equal(qtool_transfer_export_bytes((const qibl_q30_t(*)[25])r.transfer, r.nv, 5, &b, &n, err, sizeof err), 0);
    qibl_hemi_xfer_t x;
    assert_int_equal(qibl_hemi_xfer_open(&x, b, n), QIBL_OK);
    assert_int_equal(x.count, r.nv);
    qibl_q16_t(*out)[3] = malloc(sizeof *out * r.nv);
    assert_non_null(out);
    assert_int_equal(qibl_hemi_xfer_shade_span(&x, (const int32_t(*)[25])r.light, 0, r.nv, out), QIBL_OK);
    assert_memory_equal(out, r.shade, sizeof *out * r.nv);
    int lit = 0;
    for (uint32_t v = 0; v < r.nv; ++v)
        lit += out[v][1] > 0;
    assert_true(lit > 0); /* not an all-black comparison */
    if (find_qibl() == 0) { /* the command too, when it is built */
        assert_int_equal(run("transfer", mesh, "--probe", probe, "--rays", "0", "--export", xp, NULL), 0);
        uint8_t *fb;
        size_t fn;
        assert_int_equal(qtool_transfer_export_read(xp, &fb, &fn, err, sizeof err), 0);
        assert_int_equal(fn, n);
        assert_memory_equal(fb, b, n);
        free(fb);
        char *log = text(outlog);
        assert_non_null(strstr(log, "x 25 SH coefficients"));
        free(log);
        /* --export-c: the same bytes as a C array named after the file */
        char hp[128];
        path_of(hp, sizeof hp, "9box.h");
        assert_int_equal(run("transfer", mesh, "--probe", probe, "--rays", "0", "--export-c", hp, NULL), 0);
        char *h = text(hp);
        char def[64];
        snprintf(def, sizeof def, "#define qtr_9box_SIZE %zuu", n);
        assert_non_null(strstr(h, def));
        const char *q = strstr(h, "static const unsigned char qtr_9box[qtr_9box_SIZE] = {");
        assert_non_null(q);
        q = strchr(q, '{') + 1;
        for (size_t k = 0; k < n; ++k) {
            char *end;
            const unsigned long byte = strtoul(q, &end, 16);
            assert_true(end != q && byte == b[k]);
            q = end + (*end == ',');
        }
        assert_non_null(strstr(q, "};"));
        free(h);
        assert_int_equal(run("transfer", mesh, "--probe", probe, "--rays", "0", "--export", xp, "--export-bands", "3",
                             NULL), 0);
        assert_int_equal(qtool_transfer_export_read(xp, &fb, &fn, err, sizeof err), 0);
        assert_int_equal(qibl_hemi_xfer_open(&x, fb, fn), QIBL_OK);
        assert_int_equal(x.ncoef, 9);
        free(fb);
        remove(xp);
        assert_int_equal(run("transfer", mesh, "--probe", probe, "--export", xp, "--export-bands", "6", NULL), 2);
        assert_int_equal(run("transfer", mesh, f2, "--probe", probe, "--export", xp, NULL), 2);
        assert_int_not_equal(access(xp, F_OK), 0);
    }
    /* the tools' reader refuses a file that is not an export, by name */
    uint8_t *fb = NULL;
    size_t fn = 0;
    assert_int_equal(qtool_transfer_export_read(probe, &fb, &fn, err, sizeof err), -1);
    assert_non_null(strstr(err, "QTRX"));
    free(out), free(b);
    qtool_transfer_result_free(&r);
}

static void test_animation_is_apng(void **state)
{
    (void)state;
    need_qibl();
    char probe[128], f1[128], f2[128], png[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(f1, sizeof f1, "f1.obj"), path_of(f2, sizeof f2, "f2.obj");
    path_of(png, sizeof png, "anim.png");
    write_probe(probe, 1);
    write_box(f1, 1.0, 0, 0), write_box(f2, 0.5, 0.25, 0);
    assert_int_equal(run("transfer", f1, f2, "--probe", probe, "--rays", "0", "--png", png, "--size", "64", NULL), 0);
    int w, h, frames;
    uint8_t *rgb;
    char err[256];
    assert_int_equal(qtool_png_read_rgb8(png, &w, &h, &frames, &rgb, err, sizeof err), 0);
    assert_int_equal(frames, 2);
    free(rgb);
    /* --tween 3: two key frames, two in between each (the last back to the first): 6 frames */
    assert_int_equal(run("transfer", f1, f2, "--probe", probe, "--rays", "0", "--png", png, "--size", "64", "--tween", "3",
                         NULL), 0);
    assert_int_equal(qtool_png_read_rgb8(png, &w, &h, &frames, &rgb, err, sizeof err), 0);
    assert_int_equal(frames, 6);
    assert_int_equal(w, 64), assert_int_equal(h, 24 + 64); /* no reference: one panel, no legend */
    free(rgb);
    char *out = text(outlog);
    assert_null(strstr(out, "RESULT transfer.l2err"));
    assert_non_null(strstr(out, "RESULT transfer.ms_per_frame"));
    free(out);
}

/* pvs: each vertex's blockers over the frames, which must give the very same masks (the run
 * compares every one and fails otherwise) with fewer blockers; with and without the hierarchy. */
static void test_pvs(void **state)
{
    (void)state;
    char probe[128], f1[128], f2[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(f1, sizeof f1, "p1.obj"), path_of(f2, sizeof f2, "p2.obj");
    write_probe(probe, 1);
    write_box(f1, 1.0, 0, 0), write_box(f2, 0.5, 0.25, 0);
    for (int hier = 0; hier < 2; ++hier) {
        qtool_transfer_opts o = opts(0);
        o.pvs = 1;
        if (hier)
            o.coarse = 20, o.ring = 4;
        const qtool_transfer_result r = measure(f1, f2, probe, o);
        /* 29 vertices, 2 frames, every mask the same */
        assert_int_equal(r.nv, 29), assert_int_equal(r.nframes, 2);
        assert_true(r.pvs_diff == 0);
        assert_true(r.pvs_blockers > 0 && r.pvs_blockers < 0.8 * r.blockers);
        assert_true(r.pvs_ms_per_frame > 0);
        /* the benchmarks' block timing: the same masks and figures, only the clocks differ */
        o.time_reps = 2;
        const qtool_transfer_result b = measure(f1, f2, probe, o);
        assert_true(b.pvs_diff == 0);
        assert_true(b.blockers == r.blockers && b.pvs_blockers == r.pvs_blockers && b.rasterized == r.rasterized);
        assert_true(b.mean_irradiance == r.mean_irradiance);
        assert_true(b.ms_per_frame > 0 && b.pvs_ms_per_frame > 0);
    }
}

/* --lights N: the probe's median-cut lights projected to SH light the mesh instead of the probe's
 * own projection. The shading follows the ray cast as closely, and how much the box's walls hide
 * (a ratio, free of the lighting's scale) matches the probe's SH within a few per cent. */
static double irradiance_of(const char *mesh, const char *probe, int lights)
{
    qtool_transfer_opts o = opts(0);
    o.lights = lights;
    const qtool_transfer_result r = measure(mesh, NULL, probe, o);
    if (lights)
        assert_non_null(strstr(r.probe_desc, "median-cut lights as SH"));
    return r.mean_irradiance;
}

/* the lights' SH against the probe's own projection (relative L2, each scaled by its DC) */
static double lights_sh_err(const char *mesh, const char *probe, int lights)
{
    qtool_transfer_opts o = opts(0);
    o.lights = lights;
    const qtool_transfer_result r = measure(mesh, NULL, probe, o);
    return result(r.probe_desc, "median-cut lights as SH: relative L2 ");
}

static void test_lights(void **state)
{
    (void)state;
    need_qibl();
    char probe[128], mesh[128], flat[128];
    path_of(probe, sizeof probe, "sun.hdr"), path_of(mesh, sizeof mesh, "box.obj"), path_of(flat, sizeof flat, "flat.obj");
    write_probe(probe, 1);
    write_box(mesh, 1.0, 0, 0);
    write_box(flat, 1e-6, 0, 0);
    qtool_transfer_opts o = opts(24);
    o.lights = 64;
    assert_true(measure(mesh, NULL, probe, o).shade_err < 0.08);
    const double sh = irradiance_of(mesh, probe, 0) / irradiance_of(flat, probe, 0);
    const double l64 = irradiance_of(mesh, probe, 64) / irradiance_of(flat, probe, 64);
    assert_true(sh > 0.1 && sh < 0.9);
    assert_true(fabs(l64 - sh) < 0.05 * sh);
    /* more lights come closer to the projection: on this 64 x 32 sky 0.2 or more with 4 lights */
    const double e4 = lights_sh_err(mesh, probe, 4), e64 = lights_sh_err(mesh, probe, 64);
    assert_true(e64 < 0.1);
    assert_true(e4 > 2 * e64);
    char png[128];
    path_of(png, sizeof png, "never.png");
    assert_int_equal(run("transfer", mesh, "--probe", probe, "--lights", "3", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", mesh, "--probe", probe, "--lights", "0", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", mesh, "--probe", probe, "--lights", "2048", "--png", png, NULL), 2);
    assert_int_not_equal(access(png, F_OK), 0);
}

/* a binary PLY of one 256-vertex disc and nf faces fanning 255 of them: 253 triangles a face, about
 * one triangle per byte of file */
static void write_fan_ply(const char *path, int nf)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex 256\nproperty float x\nproperty float y\n"
               "property float z\nelement face %d\nproperty list uchar uint8 vertex_indices\nend_header\n", nf);
    for (int i = 0; i < 256; ++i) {
        const float p[3] = {(float)cos(i * 0.0245436926), (float)sin(i * 0.0245436926), i ? 0.0f : 0.5f};
        assert_int_equal(fwrite(p, sizeof p, 1, f), 1); /* little-endian host (x86, ARM) */
    }
    uint8_t face[256];
    face[0] = 255;
    for (int i = 0; i < 255; ++i)
        face[1 + i] = (uint8_t)i;
    for (int i = 0; i < nf; ++i)
        assert_int_equal(fwrite(face, sizeof face, 1, f), 1);
    fclose(f);
}

/* issue 24, class 4: a PLY of fans is checked against the triangle cap from its exact fan count
 * before the mesh is allocated, and the message gives that count (it said 0); render --scene gets
 * the same cap (it read and rendered 4 million triangles, 1.3 GB) */
static void test_mesh_caps(void **state)
{
    (void)state;
    need_qibl();
    char probe[128], fan[128], png[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(fan, sizeof fan, "fan.ply"), path_of(png, sizeof png, "never.png");
    write_probe(probe, 0);
    write_fan_ply(fan, 4145); /* 4145 * 253 = 1048685 triangles, 109 past 2^20 */
    assert_int_equal(run("transfer", fan, "--probe", probe, "--rays", "0", "--png", png, NULL), 1);
    char *err = text(errlog);
    assert_non_null(strstr(err, "1048685 triangles after fan triangulation of 4145 faces (at most 1048576)"));
    free(err);
    assert_int_equal(run("render", "--scene", fan, "--sun", "0.3", "0.8", "0.5", "--size", "64x32", "--png", png, NULL), 1);
    err = text(errlog);
    assert_non_null(strstr(err, "1048685 triangles after fan triangulation of 4145 faces (at most 1048576)"));
    free(err);
    assert_int_not_equal(access(png, F_OK), 0);
}

/* issue 24, class 4: --tween held every frame raw. The frames' sheet for --png is computed from the
 * request and refused past 256 MiB before anything is read; --pvs's integer positions of every
 * frame likewise; tweened positions are made one frame at a time. */
static void test_tween_caps(void **state)
{
    (void)state;
    need_qibl();
    char probe[128], f1[128], f2[128], png[128], grid[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(f1, sizeof f1, "t1.obj"), path_of(f2, sizeof f2, "t2.obj");
    path_of(png, sizeof png, "never.png"), path_of(grid, sizeof grid, "grid.obj");
    write_probe(probe, 0);
    write_box(f1, 1.0, 0, 0), write_box(f2, 0.5, 0.25, 0);
    /* 2 key frames x 16 = 32 frames of 2048 x 2072 (one panel): 388.5 MiB */
    assert_int_equal(run("transfer", f1, f2, "--probe", probe, "--rays", "0", "--tween", "16", "--size", "2048", "--png",
                         png, NULL), 1);
    char *err = text(errlog);
    assert_non_null(strstr(err, "--png of 32 frames of 2048x2072 is 388 MiB of frames held for the APNG (at most 256 MiB)"));
    free(err);
    /* three panels (the reference) at 128: 16 frames of 384 x 174, well under the cap: drawn */
    assert_int_equal(run("transfer", f1, f2, "--probe", probe, "--rays", "1", "--tween", "8", "--size", "128", "--png",
                         png, "--mask", "16", "--face", "2", NULL), 0);
    int w, h, frames;
    uint8_t *rgb;
    char perr[256];
    assert_int_equal(qtool_png_read_rgb8(png, &w, &h, &frames, &rgb, perr, sizeof perr), 0);
    assert_int_equal(frames, 16), assert_int_equal(w, 384), assert_int_equal(h, 24 + 128 + 22);
    free(rgb);
    remove(png);
    /* --pvs over 16 key frames x 16 of a 210 x 210 grid: 44100 vertices x 256 frames x 24 bytes */
    FILE *f = fopen(grid, "w");
    assert_non_null(f);
    for (int j = 0; j < 210; ++j)
        for (int i = 0; i < 210; ++i)
            fprintf(f, "v %d %d %d\n", i, (i * j) % 3, j);
    for (int j = 0; j < 209; ++j)
        for (int i = 0; i < 209; ++i) {
            const int a = 1 + j * 210 + i;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", a, a + 210, a + 211, a, a + 211, a + 1);
        }
    fclose(f);
    const char *g = grid;
    assert_int_equal(run("transfer", g, g, g, g, g, g, g, g, g, g, g, g, g, g, g, g, "--probe", probe, "--rays", "0",
                         "--pvs", "--tween", "16", NULL),
                     1);
    err = text(errlog);
    assert_non_null(strstr(err, "--pvs over 256 frames of 44100 vertices needs 258 MiB"));
    free(err);
}

static void test_refusals_write_nothing(void **state)
{
    (void)state;
    need_qibl();
    char probe[128], box[128], other[128], dot[128], png[128], missing[128];
    path_of(probe, sizeof probe, "sky.hdr"), path_of(box, sizeof box, "box.obj"), path_of(other, sizeof other, "o.obj");
    path_of(dot, sizeof dot, "dot.obj"), path_of(png, sizeof png, "never.png");
    path_of(missing, sizeof missing, "missing.obj");
    write_probe(probe, 0);
    write_box(box, 1.0, 0, 0), write_box(other, 1.0, 0, 1);
    write_text(dot, "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n");
    assert_int_equal(run("transfer", box, NULL), 2); /* no probe */
    assert_int_equal(run("transfer", box, "--probe", probe, "--mask", "48", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", box, "--probe", probe, "--face", "7", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", box, "--probe", probe, "--view", "0,95", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", box, "--probe", probe, "--bogus", NULL), 2);
    assert_int_equal(run("transfer", box, "--probe", probe, "--coarse", "10", "--ring", "0", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", box, "--probe", probe, "--coarse", "-1", "--png", png, NULL), 2);
    assert_int_equal(run("transfer", missing, "--probe", probe, "--png", png, NULL), 1);
    char *err = text(errlog);
    assert_non_null(strstr(err, "missing.obj"));
    free(err);
    assert_int_equal(run("transfer", box, "--probe", missing, "--png", png, NULL), 1);
    assert_int_equal(run("transfer", box, other, "--probe", probe, "--png", png, NULL), 1);
    err = text(errlog);
    assert_non_null(strstr(err, "frames must share triangles"));
    free(err);
    assert_int_equal(run("transfer", dot, "--probe", probe, "--png", png, NULL), 1);
    err = text(errlog);
    assert_non_null(strstr(err, "no extent"));
    free(err);
    assert_int_not_equal(access(png, F_OK), 0); /* nothing written by any refusal */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_plane_matches_reference, setup, teardown),
        cmocka_unit_test_setup_teardown(test_box_floor_shadowed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pvs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_measure_refusals, setup, teardown),
        cmocka_unit_test_setup_teardown(test_export_round_trip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_animation_is_apng, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lights, setup, teardown),
        cmocka_unit_test_setup_teardown(test_refusals_write_nothing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mesh_caps, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tween_caps, setup, teardown),
    };
    return cmocka_run_group_tests_name("transfer", tests, NULL, NULL);
}
