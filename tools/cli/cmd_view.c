/*
 * cmd_view.c - `qibl view`: the live viewer (tools/view). Parses the options, loads the asset,
 * the probes' SH (relight_light.c, as `qibl relight --probe` makes it) and the truth, then hands
 * over to qtool_view_run.
 */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "io/file.h"
#include "io/png.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qibl/soft.h"
#include "view/view.h"

#define VIEW_USAGE                                                                                    \
    "usage: qibl view FILE [--sun X Y Z] [--probe P.hdr]... [--lamp-rgb C0] [--exposure E]\n"          \
    "                 [--truth PNG|DIR] [--gles] [--bench [--frames N] [--headless] [--record OUT.png [--turn]]]"

#define VIEW_BENCH_DEFAULT 600L
#define VIEW_BENCH_MAX 1000000L

/* --truth DIR: the `qibl render --sun X Y Z --png DIR/sun_X_Y_Z.png` frames of a directory */
typedef struct truth_set {
    uint32_t n;
    uint8_t *rgb[QTOOL_VIEW_MAX_TRUTHS];
    double dir[QTOOL_VIEW_MAX_TRUTHS][3];
    char *name[QTOOL_VIEW_MAX_TRUTHS];
} truth_set;

static void truth_set_free(truth_set *t)
{
    for (uint32_t i = 0; i < t->n; ++i)
        free(t->rgb[i]), free(t->name[i]);
    t->n = 0;
}

/* 0, or 1 after a one-line message (nothing kept) */
static int load_truths(const char *path, uint32_t w, uint32_t h, truth_set *t)
{
    DIR *d = opendir(path);
    if (!d)
        return fprintf(stderr, "qibl: --truth %s: %s\n", path, strerror(errno)), 1;
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d)) != NULL) {
        double v[3];
        int end = 0;
        size_t len = strlen(e->d_name);
        char stem[256];
        if (len < 8 || len >= sizeof stem || strcmp(e->d_name + len - 4, ".png") != 0)
            continue;
        memcpy(stem, e->d_name, len - 4), stem[len - 4] = '\0'; /* "sun_0_0_1.png": strtod would take "1." */
        if (sscanf(stem, "sun_%lf_%lf_%lf%n", &v[0], &v[1], &v[2], &end) != 3 || (size_t)end != len - 4)
            continue; /* not a truth frame's name */
        double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(l > 0) || !isfinite(l)) {
            fprintf(stderr, "qibl: --truth %s/%s: not a sun direction\n", path, e->d_name);
            rc = 1;
        } else if (t->n >= QTOOL_VIEW_MAX_TRUTHS ||
                   (size_t)(t->n + 1) * w * h * 3 > QTOOL_VIEW_TRUTH_MAX_BYTES) {
            fprintf(stderr, "qibl: --truth %s: more than %u sun_X_Y_Z.png frames of %ux%u (at most %u, %zu MiB)\n",
                    path, t->n, w, h, QTOOL_VIEW_MAX_TRUTHS, QTOOL_VIEW_TRUTH_MAX_BYTES >> 20);
            rc = 1;
        } else {
            char file[4096], err[600];
            int tw, th, tf;
            uint8_t *rgb = NULL;
            snprintf(file, sizeof file, "%s/%s", path, e->d_name);
            if (qtool_png_read_rgb8(file, &tw, &th, &tf, &rgb, err, sizeof err) != 0) {
                fprintf(stderr, "qibl: %s\n", err);
                rc = 1;
            } else if ((uint32_t)tw != w || (uint32_t)th != h) {
                fprintf(stderr, "qibl: --truth %s is %dx%d, the asset %ux%u: not the same frame\n", file, tw, th, w, h);
                free(rgb);
                rc = 1;
            } else {
                char *nm = strdup(e->d_name);
                if (!nm) {
                    free(rgb);
                    fprintf(stderr, "qibl: view: out of memory\n");
                    rc = 1;
                } else {
                    nm[len - 4] = '\0';
                    t->rgb[t->n] = rgb, t->name[t->n] = nm;
                    for (int c = 0; c < 3; ++c)
                        t->dir[t->n][c] = v[c] / l;
                    ++t->n;
                }
            }
        }
    }
    closedir(d);
    if (rc == 0 && t->n == 0) {
        fprintf(stderr, "qibl: --truth %s: no sun_X_Y_Z.png frames (qibl render --sun X Y Z --png DIR/sun_X_Y_Z.png)\n",
                path);
        rc = 1;
    }
    if (rc != 0)
        truth_set_free(t);
    return rc;
}

int qcli_cmd_view(int argc, char **argv)
{
    const char *in = NULL, *truth = NULL, *record = NULL;
    const char *probes[QTOOL_VIEW_MAX_PROBES];
    uint32_t nprobes = 0;
    int gles = 0, bench = 0, headless = 0, have_sun = 0, turn = 0;
    long frames = VIEW_BENCH_DEFAULT;
    int32_t sun[3] = {0, 0, 0};
    double exposure = 1.0, lamp_c0 = 0; /* 0: the lamp's default C0 (as relight's --point) */
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--sun") == 0 && i + 3 < argc) {
            for (int c = 0; c < 3; ++c)
                if (qcli_parse_q16(argv[i + 1 + c], &sun[c]) != 0)
                    return qcli_usage_error("--sun: '%s' is not a number in the Q16.16 range", argv[i + 1 + c]);
            if (sun[0] == 0 && sun[1] == 0 && sun[2] == 0)
                return qcli_usage_error("--sun needs a non-zero direction");
            have_sun = 1, i += 3;
        } else if (strcmp(a, "--probe") == 0 && i + 1 < argc) {
            if (nprobes >= QTOOL_VIEW_MAX_PROBES)
                return qcli_usage_error("--probe: at most %u probes", QTOOL_VIEW_MAX_PROBES);
            probes[nprobes++] = argv[++i];
        } else if (strcmp(a, "--exposure") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], QTOOL_VIEW_EXPOSURE_MIN / 65536.0, QTOOL_VIEW_EXPOSURE_MAX / 65536.0,
                               "the viewer's exposure range", &exposure) != 0)
                return 2;
        } else if (strcmp(a, "--lamp-rgb") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], 1.0 / 65536, QTOOL_CLI_Q16_MAX, QTOOL_CLI_Q16_WHY, &lamp_c0) != 0)
                return 2;
        } else if (strcmp(a, "--truth") == 0 && i + 1 < argc)
            truth = argv[++i];
        else if (strcmp(a, "--gles") == 0)
            gles = 1;
        else if (strcmp(a, "--bench") == 0)
            bench = 1;
        else if (strcmp(a, "--headless") == 0)
            headless = 1;
        else if (strcmp(a, "--record") == 0 && i + 1 < argc)
            record = argv[++i];
        else if (strcmp(a, "--turn") == 0)
            turn = 1;
        else if (strcmp(a, "--frames") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, VIEW_BENCH_MAX, &frames) != 0)
                return qcli_usage_error("--frames needs an integer in 1..%ld", VIEW_BENCH_MAX);
        } else if (a[0] != '-' && !in)
            in = a;
        else
            return qcli_usage_error(VIEW_USAGE);
    }
    if (!in)
        return qcli_usage_error("view needs an asset FILE (qibl gen or qibl bake makes one)");
    if (headless && !bench)
        return qcli_usage_error("--headless is for --bench (a window needs a display)");
    if (record && !bench)
        return qcli_usage_error("--record needs --bench (it records the frames the bench sweeps)");
    if (record && frames < 2)
        return qcli_usage_error("--record needs --frames of at least 2 (an animated PNG)");
    if (turn && !bench)
        return qcli_usage_error("--turn is for --bench (one turn of the sun over the frames)");
    if (qcli_parse_only)
        return 0;
    if (!bench && !qtool_view_have_window()) {
        fprintf(stderr, "qibl: view: this qibl was built without X11 (Debian: apt-get install libx11-dev, then "
                        "rebuild); --bench --headless still runs\n");
        return 1;
    }
    uint8_t *bytes = NULL, *truth_rgb = NULL;
    truth_set tset = {0};
    qtool_view_gles *vg = NULL;
    size_t n;
    char err[600];
    if (qtool_io_read_asset(in, &bytes, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    int rc = 1;
    qibl_asset_t as;
    qibl_shmaps_t m;
    qtool_view v;
    qibl_status_t st = qibl_asset_open(&as, bytes, n);
    if (st == QIBL_OK)
        st = qibl_asset_shmaps(&as, &m);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl: %s: %s\n", in, qibl_soft_status_str(st));
        goto out;
    }
    if (qtool_view_init(&v, &m) != 0) {
        fprintf(stderr, "qibl: %s: its maps are not usable\n", in);
        goto out;
    }
    v.exposure = (uint32_t)lrint(exposure * 65536.0);
    v.asset = bytes, v.asset_n = n, v.npaths = qibl_lightpath_count(&as); /* the path scheme (LPTH) */
    /* the lamp scheme where the asset has a P map: relight --point's maps, P map and lamp occlusion */
    if (qibl_asset_pmap(&as, &v.pmap) == QIBL_OK && qibl_asset_point_shmaps(&as, &v.point_maps) == QIBL_OK &&
        v.pmap.width == m.width && v.pmap.height == m.height) {
        qibl_chunk_t shmu, locc;
        v.have_lamp = 1;
        if (qibl_asset_find_nth(&as, QIBL_CHUNK_SHMU, 0, &shmu) == QIBL_OK &&
            qibl_asset_find_nth(&as, QIBL_CHUNK_LOCC, 0, &locc) == QIBL_OK) {
            qibl_status_t ost = qibl_lightpath_occl_from_asset(&as, &v.occ);
            v.have_occ = ost == QIBL_OK;
            if (ost != QIBL_OK)
                fprintf(stderr, "qibl: note: %s: its LOCC chunk is not usable (%s): the lamp is drawn without lamp "
                                "occlusion\n", in, qibl_soft_status_str(ost));
        }
        /* the lamp starts over the middle of the frame's lower half (the ground), else anywhere not sky */
        int placed = qtool_view_pick(&v, (int)m.width / 2, (int)(m.height * 3 / 4));
        for (uint32_t y = m.height; !placed && y-- > 0;)
            for (uint32_t x = 0; x < m.width && !placed; x += 7)
                placed = qtool_view_pick(&v, (int)x, (int)y);
        if (!placed)
            v.have_lamp = 0; /* all sky: nowhere to put it */
    }
    if (v.have_lamp) {
        double c0 = lamp_c0, d = 1;
        if (c0 == 0) { /* relight --point's default C0 for the starting position (point_default.c) */
            size_t np = (size_t)m.width * m.height;
            double *pts = malloc(np * 3 * sizeof *pts), lp[3];
            for (int c = 0; c < 3; ++c)
                lp[c] = v.lamp_pos[c] / 65536.0;
            for (uint32_t y = 0; pts && y < m.height; ++y)
                for (uint32_t x = 0; x < m.width; ++x) {
                    qibl_q16_t q[3];
                    qibl_pmap_point(&v.pmap, x, y, q);
                    for (int c = 0; c < 3; ++c)
                        pts[3 * ((size_t)y * m.width + x) + (size_t)c] = q[c] / 65536.0;
                }
            int prc = pts ? qcli_point_default(pts, np, lp, 1, &c0, &d) : -1;
            free(pts);
            if (prc != 0) {
                fprintf(stderr, "qibl: view: out of memory\n");
                goto out;
            }
        }
        v.lamp_rgb[0] = v.lamp_rgb[1] = v.lamp_rgb[2] = (qibl_q16_t)nearbyint(c0 * 65536.0);
    } else if (lamp_c0 != 0) {
        fprintf(stderr, "qibl: note: %s has no P map to place a lamp in: --lamp-rgb is ignored\n", in);
    }
    if (have_sun) {
        double x = sun[0], y = sun[1], z = sun[2], r = sqrt(x * x + y * y);
        v.az = fmod(atan2(y, x) * 180.0 / 3.14159265358979323846 + 360.0, 360.0);
        v.el = atan2(z, r) * 180.0 / 3.14159265358979323846;
        v.el = v.el > QTOOL_VIEW_EL_MAX ? QTOOL_VIEW_EL_MAX : v.el < -QTOOL_VIEW_EL_MAX ? -QTOOL_VIEW_EL_MAX : v.el;
    }
    for (uint32_t j = 0; j < nprobes; ++j) { /* each probe's SH as `qibl relight --probe P` makes it */
        qcli_light_list ll;
        qcli_light_list_init(&ll);
        ll.probe = probes[j];
        if (qcli_light_list_sh(&ll, m.k, stdout, &v.probe[j]) != 0)
            goto out;
        ll.mode = QCLI_PROBE_LIGHTS; /* and its median-cut lights, as relight --probe-mode lights */
        if (qcli_light_list_sh(&ll, m.k, stdout, &v.probe_lights[j]) != 0)
            goto out;
        const char *slash = strrchr(probes[j], '/');
        v.probe_name[j] = slash ? slash + 1 : probes[j]; /* the overlay shows the file's name */
    }
    v.nprobes = nprobes, v.have_lights = nprobes > 0;
    if (nprobes)
        v.scheme = QTOOL_VIEW_SUN_SH;
    struct stat tst;
    if (truth && stat(truth, &tst) == 0 && S_ISDIR(tst.st_mode)) { /* a directory of sun_X_Y_Z.png frames */
        if (load_truths(truth, m.width, m.height, &tset) != 0)
            goto out;
    } else if (truth) {
        int tw, th, tf;
        if (qtool_png_read_rgb8(truth, &tw, &th, &tf, &truth_rgb, err, sizeof err) != 0) {
            fprintf(stderr, "qibl: %s\n", err);
            goto out;
        }
        if ((uint32_t)tw != m.width || (uint32_t)th != m.height) {
            fprintf(stderr, "qibl: --truth %s is %dx%d, the asset %ux%u: not the same frame\n", truth, tw, th, m.width,
                    m.height);
            goto out;
        }
    }
    if (gles && !(vg = qtool_view_gles_open(&v, err, sizeof err))) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    double fps = 0;
    qtool_view_run_opts o = {.title = "qibl view", .frame = gles ? qtool_view_gles_frame : NULL, .user = vg,
                             .truth = truth_rgb, .ntruths = tset.n, .truths = (const uint8_t *const *)tset.rgb,
                             .truth_dirs = (const double(*)[3])tset.dir, .truth_names = (const char *const *)tset.name,
                             .bench_frames = bench ? frames : 0, .bench_fps = &fps,
                             .headless = headless, .log = bench ? NULL : stdout, .record = record,
                             .drag_dx = turn ? (int)((m.width + (uint32_t)frames - 1) / (uint32_t)frames) : 0};
    if (qtool_view_run(&v, &o, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    if (bench) {
        printf("view bench: %ux%u, k = %u, %s, %ld frames with the sun dragged, %s: %.2f ms per frame (last)\n",
               m.width, m.height, m.k, gles ? "platform/gles2" : "core + platform/soft", frames,
               headless ? "headless (framebuffer and overlay)" : "shown in an X11 window", v.ms);
        printf("RESULT view.fps %.1f\n", fps);
        if (record)
            printf("wrote %s (%ld frames, %ux%u, the viewer's window with its overlay)\n", record, frames, m.width,
                   m.height + QTOOL_VIEW_OVERLAY_H);
    }
    rc = 0;
out:
    qtool_view_gles_close(vg);
    truth_set_free(&tset);
    free(bytes), free(truth_rgb);
    return rc;
}
