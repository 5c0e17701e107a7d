/*
 * cmd_demo.c - `qibl demo`: bake -> assets for k = 9, 16, 25 -> relight by the core (sun sweep,
 * moving lamp) -> PNG frames, APNGs, contact sheet against ground truth, the results table.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake.h"
#include "io/atomic.h"
#include "io/png.h"
#include "io/text.h"
#include "cli/cli.h"
#include "ref/psnr.h"
#include "render/rt.h"

/* dir/name in a malloc'ed string (no fixed-size buffer: a long --out is never truncated); NULL if
 * out of memory */
static char *join(const char *dir, const char *name)
{
    size_t a = strlen(dir), b = strlen(name);
    char *p = malloc(a + b + 2);
    if (p) {
        memcpy(p, dir, a);
        p[a] = '/';
        memcpy(p + a + 1, name, b + 1);
    }
    return p;
}

static int save_png(const char *dir, const char *name, int w, int h, const uint8_t *rgb)
{
    char err[1200], *path = join(dir, name);
    if (!path || qtool_png_write_rgb8(path, w, h, rgb, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", path ? err : "demo: out of memory");
        free(path);
        return -1;
    }
    free(path);
    return 0;
}

/* qtool_bake_relight8 with its failure said: 0, or -1 after a message */
static int relight(const uint8_t *asset, size_t n, const qtool_rt_light *l, int use_lut, uint8_t *rgb8, double *ms)
{
    if (qtool_bake_relight8(asset, n, l, use_lut, rgb8, ms) == 0)
        return 0;
    fprintf(stderr, "qibl: demo: relighting the baked asset failed (%zu bytes)\n", n);
    return -1;
}

/* Makes sure every output can be written before the bake: the directory exists (created if
 * missing) and takes a new file, and no output name is a link, directory or other non-regular file.
 * 0, or 1 after a message. */
static int check_out_dir(const char *dir, long frames)
{
    struct stat st;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "qibl: %s: cannot create the output directory: %s\n", dir, strerror(errno));
        return 1;
    }
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "qibl: %s: not a directory\n", dir);
        return 1;
    }
    static const char *fixed[] = {"scene_k9.qibl", "scene_k16.qibl",    "scene_k25.qibl", "sun_sweep.png",
                                  "lamp_sweep.png", "contact_sheet.png", "relit_sun.png",  "truth_sun.png",
                                  "paths_sheet.png", "paths_readme.png", "probe_sheet.png"};
    enum { NFIXED = sizeof fixed / sizeof fixed[0] };
    char err[1200], name[64];
    int bad = 0;
    for (long i = 0; i < NFIXED + 2 * frames && !bad; ++i) {
        if (i < NFIXED)
            snprintf(name, sizeof name, "%s", fixed[i]);
        else /* the frames: sun_00.png .. then lamp_00.png .. */
            snprintf(name, sizeof name, "%s_%02ld.png", i - NFIXED < frames ? "sun" : "lamp", (i - NFIXED) % frames);
        char *path = join(dir, name);
        if (!path)
            return fprintf(stderr, "qibl: demo: out of memory\n"), 1;
        if (qtool_io_check_replaceable(path, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            bad = 1;
        } else if (i == 0) { /* one real temporary file: the directory takes new files */
            qtool_io_atomic a;
            if (qtool_io_atomic_open(&a, path, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                bad = 1;
            } else {
                qtool_io_atomic_abort(&a);
            }
        }
        free(path);
    }
    return bad;
}

/* error heat map: max channel difference, 0 black .. 8 blue .. 24 red .. 48+ yellow-white */
static void heat(const uint8_t *a, const uint8_t *b, const uint8_t *mask, size_t np, uint8_t *out)
{
    for (size_t i = 0; i < np; ++i) {
        int d = 0;
        for (int c = 0; c < 3; ++c) {
            int x = abs((int)a[3 * i + (size_t)c] - (int)b[3 * i + (size_t)c]);
            d = x > d ? x : d;
        }
        double t = mask[i] ? fmin(1.0, d / 48.0) : 0;
        double r = fmin(1, fmax(0, 3 * t - 1)), g = fmin(1, fmax(0, 3 * t - 2)), bl = t < 1.0 / 3 ? 3 * t : fmax(0, 2 - 3 * t);
        out[3 * i] = (uint8_t)lrint(255 * r), out[3 * i + 1] = (uint8_t)lrint(255 * g);
        out[3 * i + 2] = (uint8_t)lrint(255 * fmax(bl, 0.25 * g));
    }
}

/* The demo's three sizes (cli.h): small for CI, default for `make demo`, full for the README. */
static const qcli_demo_size demo_sizes[] = {
    {.name = "small", .w = 256, .h = 64, .ndirs = 128, .frames = 6, .path_steps = 32, .sky_dirs = 128, .probe_spp = 512},
    {.name = "default", .w = 512, .h = 128, .ndirs = 256, .frames = 12, .path_steps = 32, .sky_dirs = 128, .probe_spp = 256},
    {.name = "full", .w = 1024, .h = 256, .ndirs = 512, .frames = 24, .path_steps = 64, .sky_dirs = 256, .probe_spp = 256},
};

int qcli_cmd_demo(int argc, char **argv)
{
    /* the size first: --size WxH, --dirs and --frames given on the line override its values */
    const qcli_demo_size *sz = &demo_sizes[1];
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--small") == 0)
            sz = &demo_sizes[0];
        else if (strcmp(argv[i], "--full") == 0)
            sz = &demo_sizes[2];
    }
    qcli_scene so;
    qcli_scene_defaults(&so);
    so.w = sz->w, so.h = sz->h;
    const char *dir = NULL;
    long ndirs = sz->ndirs, frames = sz->frames;
    for (int i = 1; i < argc; ++i) {
        int r = qcli_scene_opt(argc, argv, &i, &so);
        if (r < 0)
            return 2;
        if (r)
            continue;
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            dir = argv[++i];
        else if (strcmp(argv[i], "--dirs") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 16, 65536, &ndirs) != 0)
                return qcli_usage_error("--dirs needs an integer in 16..65536");
        } else if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 2, 240, &frames) != 0)
                return qcli_usage_error("--frames needs an integer in 2..240");
        } else if (strcmp(argv[i], "--small") != 0 && strcmp(argv[i], "--full") != 0) {
            return qcli_usage_error("demo: unknown argument '%s' (see qibl help demo)", argv[i]);
        }
    }
    if (!dir)
        return qcli_usage_error("demo needs --out DIR");
    if (qcli_parse_only) /* fuzz_cliopts: the options only */
        return 0;
    if (check_out_dir(dir, frames) != 0)
        return 1;
    qtool_rt_scene s;
    if (qcli_scene_load(&so, &s) != 0)
        return 1;
    uint32_t w = so.w, h = so.h;
    size_t np = (size_t)w * h;
    const char *scene_name = so.scene ? so.scene : "the built-in courtyard";
    printf("== bake %s (demo size %s): %ux%u %s panorama, %ld light directions (spherical Fibonacci), %zu triangles, "
           "%d threads\n",
           scene_name, sz->name, w, h, so.kind ? "equirectangular" : "cylindrical", ndirs, s.ntri, so.threads);
    qtool_bake_sums sums;
    double t0 = qcli_now();
    if (qtool_bake_run(&s, w, h, (qtool_pano_kind)so.kind, (uint32_t)ndirs, 25, 0, 1, so.threads, 1, &sums) != 0) {
        fprintf(stderr, "qibl: demo: out of memory\n");
        qtool_rt_scene_free(&s);
        return 1;
    }
    double bake_s = qcli_now() - t0;
    printf("bake: %.1f s (reference renders and SH sums for k <= 25)\n", bake_s);

    /* the evaluation set: 8 novel suns, 4 lamps; ground truth once */
    enum { NDIR = 8, NPT = 4 };
    int prop = so.scene && !so.raw && strcmp(so.scene, "builtin") != 0;
    qtool_rt_light ev[NDIR + NPT];
    qcli_eval_lights(prop, NDIR, NPT, ev);
    uint8_t *truth[NDIR + NPT] = {0}, *mask = malloc(np), *tmp = malloc(np * 3), *heatb = malloc(np * 3);
    static const uint32_t ks[3] = {9, 16, 25};
    uint8_t *asset[3] = {0};
    size_t asize[3] = {0};
    int rc = 0;
    for (int i = 0; i < NDIR + NPT; ++i) {
        truth[i] = malloc(np * 3);
        if (!truth[i] || !mask || !tmp || !heatb ||
            qtool_bake_truth8(&s, w, h, (qtool_pano_kind)so.kind, &ev[i], so.threads, truth[i], mask) != 0) {
            fprintf(stderr, "qibl: demo: out of memory\n");
            rc = 1;
            goto done;
        }
    }
    double psnr_dir[3], psnr_pt[3], ms_dir[3], ms_pt[3];
    char name[64], err[1200];
    for (int q = 0; q < 3; ++q) {
        qtool_gen_maps m;
        if (qtool_bake_coeffs(&sums, ks[q], QTOOL_PROJ_QUADRATURE, &m) != 0 ||
            qtool_bake_asset(&m, 32, &asset[q], &asize[q]) != 0) {
            fprintf(stderr, "qibl: demo: out of memory\n");
            rc = 1;
            goto done;
        }
        qtool_gen_free(&m);
        snprintf(name, sizeof name, "scene_k%u.qibl", ks[q]);
        char *path = join(dir, name);
        if (!path || qtool_io_write_atomic(path, asset[q], asize[q], err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", path ? err : "demo: out of memory");
            free(path);
            rc = 1;
            goto done;
        }
        free(path);
        double mse_d = 0, mse_p = 0, tms[NDIR + NPT];
        for (int i = 0; i < NDIR + NPT; ++i) {
            if (relight(asset[q], asize[q], &ev[i], 1, tmp, &tms[i]) != 0) {
                rc = 1;
                goto done;
            }
            double e = qtool_bake_mse(tmp, truth[i], mask, np);
            if (i < NDIR)
                mse_d += e / NDIR;
            else
                mse_p += e / NPT;
        }
        psnr_dir[q] = qtool_ref_psnr8(mse_d);
        psnr_pt[q] = qtool_ref_psnr8(mse_p);
        ms_dir[q] = qcli_median(tms, NDIR);
        ms_pt[q] = qcli_median(tms + NDIR, NPT);
    }
    /* quadrature against least squares, k = 16 */
    double lsq_dir = 0, quad_dir = psnr_dir[1];
    {
        qtool_gen_maps m;
        uint8_t *b = NULL;
        size_t n = 0;
        if (qtool_bake_coeffs(&sums, 16, QTOOL_PROJ_LSQ, &m) == 0 && qtool_bake_asset(&m, 0, &b, &n) == 0) {
            double mse = 0;
            int ok = 1;
            for (int i = 0; i < NDIR && ok; ++i) {
                ok = relight(b, n, &ev[i], 0, tmp, NULL) == 0;
                mse += qtool_bake_mse(tmp, truth[i], mask, np) / NDIR;
            }
            lsq_dir = ok ? qtool_ref_psnr8(mse) : 0;
            rc = ok ? rc : 1;
            qtool_gen_free(&m);
        }
        free(b);
    }

    /* sun sweep and moving lamp, k = 16 */
    uint8_t *anim = malloc(np * 3 * (size_t)frames);
    if (!anim) {
        rc = 1;
        goto done;
    }
    for (int pass = 0; pass < 2 && rc == 0; ++pass) {
        for (long f = 0; f < frames; ++f) {
            double t = (double)f / frames, a = 2 * 3.14159265358979 * t;
            qtool_rt_light l;
            if (pass == 0) {
                double el = 0.35 + 0.45 * sin(3.14159265358979 * t);
                qtool_rt_light sl = {0, {cos(el) * cos(a), cos(el) * sin(a), sin(el)}, {0, 0, 0}, {2.6, 2.4, 2.1}, 1};
                l = sl;
            } else {
                double cx = prop ? QTOOL_RT_PROP_X : 0.0, r = prop ? 2.2 : 2.8;
                qtool_rt_light pl = {1, {0, 0, 1}, {cx + r * cos(a), r * sin(a), -0.5 + 0.4 * sin(2 * a)}, {5.0, 4.4, 3.6}, 1};
                l = pl;
            }
            uint8_t *fr = anim + np * 3 * (size_t)f;
            snprintf(name, sizeof name, "%s_%02ld.png", pass ? "lamp" : "sun", f);
            if (rc == 0 && (relight(asset[1], asize[1], &l, 1, fr, NULL) != 0 || save_png(dir, name, (int)w, (int)h, fr) != 0))
                rc = 1;
        }
        char *path = join(dir, pass ? "lamp_sweep.png" : "sun_sweep.png");
        if (rc == 0 && (!path || qtool_apng_write_rgb8(path, (int)w, (int)h, (int)frames, anim, 1, 8, err, sizeof err) != 0)) {
            fprintf(stderr, "qibl: %s\n", path ? err : "demo: out of memory");
            rc = 1;
        }
        free(path);
    }
    free(anim);
    /* contact sheet: relit (k = 16) | ground truth | error heat map, for 3 suns and 2 lamps, each column
     * and row under a label */
    if (rc == 0) {
        static const int rows[5] = {0, 3, 6, NDIR, NDIR + 2};
        static const char *cols[3] = {"relit by the core, k = 16", "truth: ray-traced", "error, 0 .. 48+ of 255"};
        static const uint8_t fg[3] = {235, 235, 235};
        int ts = w >= 512 ? 2 : 1, strip = (QTOOL_TEXT_HEIGHT + 3) * ts;
        size_t sw = (size_t)w * 3, shh = ((size_t)h + (size_t)strip) * 5;
        uint8_t *sheet = malloc(sw * 3 * shh);
        if (sheet)
            memset(sheet, 24, sw * 3 * shh);
        for (int r = 0; sheet && r < 5 && rc == 0; ++r) {
            int i = rows[r];
            size_t y0 = (size_t)r * (h + (size_t)strip);
            if (relight(asset[1], asize[1], &ev[i], 1, tmp, NULL) != 0) {
                rc = 1;
                break;
            }
            heat(tmp, truth[i], mask, np, heatb);
            const uint8_t *src[3] = {tmp, truth[i], heatb};
            char lab[120];
            for (int c = 0; c < 3; ++c) {
                if (c == 0)
                    snprintf(lab, sizeof lab, "%s %d: %s", i < NDIR ? "sun" : "lamp", i < NDIR ? i + 1 : i - NDIR + 1,
                             cols[0]);
                qtool_text_draw(sheet, (int)sw, (int)shh, c * (int)w + 4, (int)y0 + ts, c == 0 ? lab : cols[c], ts, fg);
            }
            for (uint32_t y = 0; y < h; ++y)
                for (int c = 0; c < 3; ++c)
                    memcpy(sheet + ((y0 + (size_t)strip + y) * sw + (size_t)c * w) * 3, src[c] + (size_t)y * w * 3,
                           (size_t)w * 3);
        }
        if (!sheet || rc != 0 || save_png(dir, "contact_sheet.png", (int)sw, (int)shh, sheet) != 0)
            rc = 1;
        free(sheet);
        if (rc == 0) { /* the picture for the README: one relit sun frame and its lamp frame */
            if (relight(asset[1], asize[1], &ev[0], 1, tmp, NULL) != 0 ||
                save_png(dir, "relit_sun.png", (int)w, (int)h, tmp) != 0 ||
                save_png(dir, "truth_sun.png", (int)w, (int)h, truth[0]) != 0)
                rc = 1;
        }
    }
    printf("\n%s, %ux%u, %ld directions, bake %.1f s on %d threads\n", scene_name, w, h, ndirs, bake_s, so.threads);
    printf("PSNR: the core's 8-bit relit frames against ray-traced ground truth (sRGB 8-bit, scene pixels),\n"
           "mean MSE over 8 novel suns / 4 lamps (cube-map LUT 32^2, falloff C0/|L|)\n\n");
    printf("|  k | bytes on disk | relight ms/frame (sun / lamp) | PSNR sun dB | PSNR lamp dB |\n");
    printf("|---:|--------------:|------------------------------:|------------:|-------------:|\n");
    for (int q = 0; q < 3; ++q)
        printf("| %2u | %13zu | %13.2f / %-13.2f | %11.2f | %12.2f |\n", ks[q], asize[q], ms_dir[q], ms_pt[q],
               psnr_dir[q], psnr_pt[q]);
    printf("\nprojection, k = 16, novel suns: quadrature %.2f dB, least squares %.2f dB\n", quad_dir, lsq_dir);
    for (int q = 0; q < 3; ++q)
        printf("RESULT demo.psnr_k%u_dir %.2f\nRESULT demo.psnr_k%u_point %.2f\nRESULT demo.bytes_k%u %zu\n"
               "RESULT demo.relight_ms_k%u %.3f\n",
               ks[q], psnr_dir[q], ks[q], psnr_pt[q], ks[q], asize[q], ks[q], ms_dir[q]);
    printf("RESULT demo.psnr_k16_dir_lsq %.2f\nRESULT demo.bake_s %.2f\n", lsq_dir, bake_s);
    if (rc == 0 && qtool_demo_paths(&s, &so, (uint32_t)ndirs, prop, sz, &sums, asset[1], asize[1], dir) != 0)
        rc = 1;
    if (rc == 0 && qcli_demo_probe(&s, &so, sz, &sums, (uint32_t)ndirs, dir) != 0)
        rc = 1;
    if (rc == 0)
        printf("\nwrote %s/: scene_k{9,16,25}.qibl, sun_NN.png and sun_sweep.png (APNG), lamp_NN.png and lamp_sweep.png "
               "(APNG), contact_sheet.png (relit | ground truth | error), relit_sun.png, truth_sun.png, paths_sheet.png, "
               "paths_readme.png, probe_sheet.png\n",
               dir);
done:
    for (int q = 0; q < 3; ++q)
        free(asset[q]);
    for (int i = 0; i < NDIR + NPT; ++i)
        free(truth[i]);
    free(mask), free(tmp), free(heatb);
    qtool_bake_sums_free(&sums);
    qtool_rt_scene_free(&s);
    return rc;
}
