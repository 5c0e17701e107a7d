/*
 * cmd_view.c - `qibl view`: the live viewer (tools/view). Parses the options into their struct,
 * reads the asset, has tools/view set it up (qtool_view_open_asset: maps, lamp, sun) and load the
 * truth (qtool_view_truths_load), adds the probes' SH (relight_light.c, as `qibl relight --probe`
 * makes it), then hands over to qtool_view_run and prints the bench's figures.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/relight_light.h"
#include "io/file.h"
#include "view/view.h"

#define VIEW_USAGE                                                                                    \
    "usage: qibl view FILE [--sun X Y Z] [--probe P.hdr]... [--lamp-rgb C0] [--exposure E]\n"          \
    "                 [--truth PNG|DIR] [--gles] [--bench [--frames N] [--headless] [--record OUT.png [--turn]]]"


/* the options of `qibl view` (the library's defaults: view/view.h) */
typedef struct vopts {
    const char *in, *truth, *record;
    const char *probes[QTOOL_VIEW_MAX_PROBES];
    uint32_t nprobes;
    int gles, bench, headless, turn;
    long frames;
    qibl_q16_t sun[3];
    qtool_view_asset_opts asset; /* exposure, lamp C0 (0: the lamp's default C0, as relight's --point), sun */
} vopts;

static const vopts vopts_default = {.frames = QTOOL_VIEW_BENCH_FRAMES_DEFAULT, .asset = QTOOL_VIEW_ASSET_OPTS_DEFAULT};

/* --sun X Y Z at argv[i]: 0, or the usage error's status */
static int parse_sun(char **argv, int i, vopts *o)
{
    for (int c = 0; c < 3; ++c)
        if (qcli_parse_q16(argv[i + 1 + c], &o->sun[c]) != 0)
            return qcli_usage_error("--sun: '%s' is not a number in the Q16.16 range", argv[i + 1 + c]);
    if (o->sun[0] == 0 && o->sun[1] == 0 && o->sun[2] == 0)
        return qcli_usage_error("--sun needs a non-zero direction");
    o->asset.sun = o->sun;
    return 0;
}

/* the options into o: -1, or the usage error's status */
static int parse(int argc, char **argv, vopts *o)
{
    *o = vopts_default;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--sun") == 0 && i + 3 < argc) {
            const int rc = parse_sun(argv, i, o);
            if (rc != 0)
                return rc;
            i += 3;
        } else if (strcmp(a, "--probe") == 0 && i + 1 < argc) {
            if (o->nprobes >= QTOOL_VIEW_MAX_PROBES)
                return qcli_usage_error("--probe: at most %u probes", QTOOL_VIEW_MAX_PROBES);
            o->probes[o->nprobes++] = argv[++i];
        } else if (strcmp(a, "--exposure") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], QTOOL_VIEW_EXPOSURE_MIN / 65536.0, QTOOL_VIEW_EXPOSURE_MAX / 65536.0,
                               "the viewer's exposure range", &o->asset.exposure) != 0)
                return 2;
        } else if (strcmp(a, "--lamp-rgb") == 0 && i + 1 < argc) {
            if (qcli_parse_num(a, argv[++i], 1.0 / 65536, QTOOL_CLI_Q16_MAX, QTOOL_CLI_Q16_WHY, &o->asset.lamp_c0) != 0)
                return 2;
        } else if (strcmp(a, "--truth") == 0 && i + 1 < argc)
            o->truth = argv[++i];
        else if (strcmp(a, "--gles") == 0)
            o->gles = 1;
        else if (strcmp(a, "--bench") == 0)
            o->bench = 1;
        else if (strcmp(a, "--headless") == 0)
            o->headless = 1;
        else if (strcmp(a, "--record") == 0 && i + 1 < argc)
            o->record = argv[++i];
        else if (strcmp(a, "--turn") == 0)
            o->turn = 1;
        else if (strcmp(a, "--frames") == 0 && i + 1 < argc) {
            if (qcli_parse_int(argv[++i], 1, QTOOL_VIEW_BENCH_FRAMES_MAX, &o->frames) != 0)
                return qcli_usage_error("--frames needs an integer in 1..%ld", QTOOL_VIEW_BENCH_FRAMES_MAX);
        } else if (a[0] != '-' && !o->in)
            o->in = a;
        else
            return qcli_usage_error(VIEW_USAGE);
    }
    if (!o->in)
        return qcli_usage_error("view needs an asset FILE (qibl gen or qibl bake makes one)");
    if (o->headless && !o->bench)
        return qcli_usage_error("--headless is for --bench (a window needs a display)");
    if (o->record && !o->bench)
        return qcli_usage_error("--record needs --bench (it records the frames the bench sweeps)");
    if (o->record && o->frames < 2)
        return qcli_usage_error("--record needs --frames of at least 2 (an animated PNG)");
    if (o->turn && !o->bench)
        return qcli_usage_error("--turn is for --bench (one turn of the sun over the frames)");
    return -1;
}

/* each probe's SH as `qibl relight --probe P` makes it, and its median-cut lights; 0 or -1 */
static int load_probes(const vopts *o, qtool_view *v)
{
    for (uint32_t j = 0; j < o->nprobes; ++j) {
        qcli_light_list ll;
        qcli_light_list_init(&ll);
        ll.probe = o->probes[j];
        if (qcli_light_list_sh(&ll, v->maps.k, stdout, &v->probe[j]) != 0)
            return -1;
        ll.mode = QCLI_PROBE_LIGHTS; /* and its median-cut lights, as relight --probe-mode lights */
        if (qcli_light_list_sh(&ll, v->maps.k, stdout, &v->probe_lights[j]) != 0)
            return -1;
        const char *slash = strrchr(o->probes[j], '/');
        v->probe_name[j] = slash ? slash + 1 : o->probes[j]; /* the overlay shows the file's name */
    }
    v->nprobes = o->nprobes, v->have_lights = o->nprobes > 0;
    if (o->nprobes)
        v->scheme = QTOOL_VIEW_SUN_SH;
    return 0;
}

int qcli_cmd_view(int argc, char **argv)
{
    vopts o;
    const int prc = parse(argc, argv, &o);
    if (prc >= 0)
        return prc;
    if (qcli_parse_only)
        return 0;
    if (!o.bench && !qtool_view_have_window()) {
        fprintf(stderr, "qibl: view: this qibl was built without X11 (Debian: apt-get install libx11-dev, then "
                        "rebuild); --bench --headless still runs\n");
        return 1;
    }
    uint8_t *bytes = NULL;
    qtool_view_truths tset = {0};
    qtool_view_gles *vg = NULL;
    size_t n;
    char err[600], note[600];
    if (qtool_io_read_asset(o.in, &bytes, &n, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        return 1;
    }
    int rc = 1;
    qtool_view v;
    o.asset.lamp_default = qcli_point_default;
    const int orc = qtool_view_open_asset(&v, bytes, n, o.in, &o.asset, note, sizeof note, err, sizeof err);
    if (note[0])
        fprintf(stderr, "qibl: note: %s\n", note);
    if (orc != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    const qibl_shmaps_t m = v.maps;
    if (load_probes(&o, &v) != 0)
        goto out;
    if (o.truth && qtool_view_truths_load(o.truth, m.width, m.height, &tset, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    if (o.gles && !(vg = qtool_view_gles_open(&v, err, sizeof err))) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    double fps = 0;
    qtool_view_run_opts ro = {.title = "qibl view", .frame = o.gles ? qtool_view_gles_frame : NULL, .user = vg,
                              .truth = tset.one, .ntruths = tset.n, .truths = (const uint8_t *const *)tset.rgb,
                             .truth_dirs = (const double(*)[3])tset.dir, .truth_names = (const char *const *)tset.name,
                             .bench_frames = o.bench ? o.frames : 0, .bench_fps = &fps,
                             .headless = o.headless, .log = o.bench ? NULL : stdout, .record = o.record,
                             .drag_dx = o.turn ? (int)((m.width + (uint32_t)o.frames - 1) / (uint32_t)o.frames) : 0};
    if (qtool_view_run(&v, &ro, err, sizeof err) != 0) {
        fprintf(stderr, "qibl: %s\n", err);
        goto out;
    }
    if (o.bench) {
        printf("view bench: %ux%u, k = %u, %s, %ld frames with the sun dragged, %s: %.2f ms per frame (last)\n",
               m.width, m.height, m.k, o.gles ? "platform/gles2" : "core + platform/soft", o.frames,
               o.headless ? "headless (framebuffer and overlay)" : "shown in an X11 window", v.ms);
        printf("RESULT view.fps %.1f\n", fps);
        if (o.record)
            printf("wrote %s (%ld frames, %ux%u, the viewer's window with its overlay)\n", o.record, o.frames, m.width,
                   m.height + QTOOL_VIEW_OVERLAY_H);
    }
    rc = 0;
out:
    qtool_view_gles_close(vg);
    qtool_view_truths_free(&tset);
    free(bytes);
    return rc;
}
