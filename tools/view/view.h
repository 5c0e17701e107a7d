/*
 * view/view.h - the state and the frame of `qibl view`, a live relighting viewer: an asset's SH maps
 * relit by a sun the user drags, by a probe's SH (several probes, stepped), or both, with exposure,
 * the number of SH terms (k) and a yaw step; the frame drawn through platform/soft into a 32-bit
 * BGRX buffer (what an X11 TrueColor window takes), an overlay strip under it (io/text.h).
 *
 * What it does not do: open windows (view/x11.c does, when built with X11), read files or parse
 * options (the CLI does). The frame is the bytes `qibl relight --sun X Y Z` gives for the same sun
 * (qtool_view_sun_q16 names it): same core weights, same soft conversion (sRGB, exposure).
 */
#ifndef QTOOL_VIEW_VIEW_H
#define QTOOL_VIEW_VIEW_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/lightpath.h"
#include "qibl/shmap.h"
#include "qtool.h"

#define QTOOL_VIEW_MAX_PROBES 8u      /* --probe options (each an SH light, 3 x 25 Q16.16) */
#define QTOOL_VIEW_OVERLAY_SCALE 2    /* overlay font scale */
#define QTOOL_VIEW_LINE_H (7 * QTOOL_VIEW_OVERLAY_SCALE + 4) /* one overlay line, pixels */
#define QTOOL_VIEW_OVERLAY_H (2 * QTOOL_VIEW_LINE_H + 4)     /* the strip under the frame, pixels */
#define QTOOL_VIEW_EL_MAX 89.0        /* |elevation| of the dragged sun, degrees */
#define QTOOL_VIEW_YAW_STEP 15.0      /* degrees per yaw key */
#define QTOOL_VIEW_EXPOSURE_MIN 256u  /* UQ16.16 exposure range of the keys: 1/256 .. 256 */
#define QTOOL_VIEW_EXPOSURE_MAX (256u * 65536u)

/* The lighting schemes the keys switch through (S). SH needs a probe. */
typedef enum qtool_view_scheme {
    QTOOL_VIEW_SUN = 0, /* the dragged sun alone */
    QTOOL_VIEW_SH,      /* the probe's SH */
    QTOOL_VIEW_LIGHTS,  /* the probe's median-cut lights (in SH, as relight --probe-mode lights) */
    QTOOL_VIEW_SUN_SH,  /* the dragged sun plus the probe's SH */
    QTOOL_VIEW_LAMP,    /* a point lamp placed by picking the P map under the pointer (have_lamp) */
    QTOOL_VIEW_PATH,    /* a light on one of the asset's baked paths (LPTH) at path_t, as relight --path */
    QTOOL_VIEW_SCHEME_COUNT
} qtool_view_scheme;

typedef struct qtool_view {
    qibl_shmaps_t maps;                          /* the asset's shadowed maps (caller-owned bytes) */
    qibl_shlight_t probe[QTOOL_VIEW_MAX_PROBES]; /* each probe's radiance SH, k = maps.k */
    qibl_shlight_t probe_lights[QTOOL_VIEW_MAX_PROBES]; /* its median-cut lights as SH (have_lights) */
    int have_lights;
    const char *probe_name[QTOOL_VIEW_MAX_PROBES];
    uint32_t nprobes, cur_probe;
    qtool_view_scheme scheme;
    double az, el;          /* the sun, degrees: azimuth from +x toward +y, elevation above the z = 0 plane */
    double yaw;             /* degrees, the probe's rotation about +z (and the sun's azimuth offset) */
    qibl_q16_t sun_rgb[3];  /* Q16.16, default 1 1 1 as relight's --sun */
    uint32_t exposure;      /* UQ16.16, default 65536 */
    uint32_t k;             /* SH terms used (1, 4, 9, 16, 25 up to maps.k) */
    int linear;             /* 1: no sRGB curve */
    double ms;              /* the last frame's relight time */
    double psnr;            /* against the truth (< 0: none) */
    const char *truth_label; /* the truth frame compared (a --truth DIR's file name; NULL: the one file) */
    double truth_angle;      /* degrees between the sun and that frame's sun */
    /* the lamp (qtool_view_set_lamp): as `qibl relight --point X Y Z --rgb R G B` draws it (poly Y,
     * falloff 1/d, the asset's lamp occlusion when it has one) */
    int have_lamp;
    qibl_shmaps_t point_maps;   /* qibl_asset_point_shmaps */
    qibl_pmap_t pmap;
    qibl_lampocc_t occ;
    int have_occ;
    qibl_q16_t lamp_pos[3], lamp_rgb[3];
    /* the baked light paths (qibl_lightpath_count of the asset): relit by qtool_bake_relight_path8
     * (sRGB, exposure 1: the exposure, k and linear keys do not apply to this scheme) */
    const uint8_t *asset;       /* the asset's bytes (caller-owned), for the path scheme */
    size_t asset_n;
    uint32_t npaths, path_index;
    uint32_t path_t;            /* 0..QIBL_LIGHTPATH_T_MAX */
} qtool_view;

#define QTOOL_VIEW_PATH_STEP 2048u /* t per t / T key (1/32 of a path) */

/* The lamp set 1/10 of the way from the P map's point under pixel (x, y) toward the viewpoint (the
 * origin), so it hangs in front of what was picked. 1 if moved; 0 outside the frame, without a
 * lamp, or on the sky (a point QTOOL_VIEW_SKY_DIST or more away). */
#define QTOOL_VIEW_SKY_DIST 1000
int qtool_view_pick(qtool_view *v, int x, int y);

/* Fills v for the maps m (checked with qibl_shmap_check): sun at 45 deg azimuth, 30 deg up, k = m's
 * k, exposure 1, scheme sun. 0, or -1 (bad maps). */
int qtool_view_init(qtool_view *v, const qibl_shmaps_t *m);

/* The sun's direction in Q16.16 as the frame uses it (after the yaw). */
void qtool_view_sun_q16(const qtool_view *v, qibl_q16_t dir[3]);

/* A pointer drag of (dx, dy) window pixels over a frame w pixels wide, h high: a full width turns
 * the sun once around (azimuth grows to the left, as the panorama's), a full height sweeps 180
 * degrees of elevation (up is up); the elevation is clamped to +-QTOOL_VIEW_EL_MAX. */
void qtool_view_drag(qtool_view *v, int dx, int dy, uint32_t w, uint32_t h);

/* A pointer drag in the path scheme: a full window width scrubs t over the whole path (clamped). */
void qtool_view_scrub(qtool_view *v, int dx, uint32_t w);

/* A key (an X11 keysym's Latin-1 value): s scheme (sun, SH, lights, sun + SH, lamp, path; those
 * needing a probe, its lights, a P map or a baked path skipped without one), t / T the path's t
 * +/- QTOOL_VIEW_PATH_STEP (wrapping), P the next path, p probe, y / Y yaw -/+, + / - exposure x2 / /2,
 * k fewer SH terms (cycling back to all), l linear/sRGB. 1 if the state changed, 0 if the key means
 * nothing here (including S with no probe for SH). */
int qtool_view_key(qtool_view *v, int key);

/* The SH light of the current scheme (sun, the probe turned by the yaw, or both), its terms past
 * v->k zeroed: what the frame is relit by. QIBL_OK or the core's status. */
QTOOL_NODISCARD qibl_status_t qtool_view_light(const qtool_view *v, qibl_shlight_t *l);

/* Relights the frame into bgrx (w x h 4-byte pixels B, G, R, 255 at row stride `stride` bytes;
 * w, h the maps'), times it into v->ms. ws: qtool_view_workspace_size bytes. 0, or -1 with *st. */
size_t qtool_view_workspace_size(const qtool_view *v);
int qtool_view_render(qtool_view *v, uint8_t *bgrx, size_t stride, void *ws, qibl_status_t *st);

/* The overlay text (scheme, light, k, exposure, ms, PSNR when a truth is set) drawn into a w x
 * QTOOL_VIEW_OVERLAY_H strip of 4-byte pixels at stride bytes; fps: frames per second measured by the caller. */
void qtool_view_overlay(const qtool_view *v, double fps, uint8_t *bgrx, uint32_t w, size_t stride);
/* The two overlay lines as text (for logs and tests); each buffer n bytes. */
void qtool_view_describe(const qtool_view *v, double fps, char *line1, char *line2, size_t n);

/* PSNR in dB of the 8-bit RGB of the frame (bgrx, w x h at stride) against truth (w x h RGB8); 99
 * when equal. */
double qtool_view_psnr(const uint8_t *bgrx, size_t stride, uint32_t w, uint32_t h, const uint8_t *truth);

/* ---- the window (view/x11.c; built with X11 when the Makefile finds Xlib, else it says so) ---- */

/* A frame drawer other than the core + platform/soft one (`--gles`): fills bgrx (the maps' w x h at
 * stride) for v's state; 0, or -1 after a one-line message on stderr. */
typedef int (*qtool_view_frame_fn)(void *user, qtool_view *v, uint8_t *bgrx, size_t stride);

typedef struct qtool_view_run_opts {
    const char *title;         /* window title; NULL: "qibl view" */
    qtool_view_frame_fn frame; /* NULL: qtool_view_render */
    void *user;
    const uint8_t *truth;      /* w x h RGB8 (NULL: no PSNR) */
    /* or a set of truth frames, each of a sun direction (--truth DIR): in the sun scheme the PSNR is
     * against the frame whose sun is nearest the dragged one */
    uint32_t ntruths;
    const uint8_t *const *truths;
    const double (*truth_dirs)[3]; /* unit vectors */
    const char *const *truth_names;
    long bench_frames;         /* > 0: --bench, that many frames with the sun dragged, then return */
    double *bench_fps;         /* out: the bench's frames per second */
    int headless;              /* bench without a window (the framebuffer and overlay only) */
    void *log;                 /* FILE *: one "view: ..." line per settled change (NULL: none) */
    int drag_dx;               /* the bench's drag per frame, pixels (0: 4) */
    const char *record;        /* with bench_frames: every frame shown (overlay included) into this APNG */
} qtool_view_run_opts;

/* --record's cap: frames x width x (height + overlay) x 3 bytes held until the APNG is written */
#define QTOOL_VIEW_RECORD_MAX_BYTES ((size_t)256 << 20)
/* --truth DIR: at most this many sun_X_Y_Z.png frames, and their RGB8 bytes at most this many */
#define QTOOL_VIEW_MAX_TRUTHS 64u
#define QTOOL_VIEW_TRUTH_MAX_BYTES ((size_t)256 << 20)

/* ---- before the window (view/setup.c) ---------------------------------------------------------- */

/* The sun from a direction (Q16.16, not zero): azimuth and elevation, clamped to +-QTOOL_VIEW_EL_MAX. */
void qtool_view_set_sun(qtool_view *v, const qibl_q16_t sun[3]);

/* What qtool_view_open_asset sets besides the maps. lamp_default: the lamp's default C0 for its
 * position from the scene's points (as the CLI's `--point` without `--rgb`: qcli_point_default's
 * signature; 0, or -1 out of memory), used when lamp_c0 is 0. */
typedef struct qtool_view_asset_opts {
    double exposure;          /* linear, QTOOL_VIEW_EXPOSURE_MIN..MAX / 65536 */
    double lamp_c0;           /* the lamp's C0 (0: lamp_default) */
    const qibl_q16_t *sun;    /* 3 values, not all zero (NULL: qtool_view_init's sun) */
    int (*lamp_default)(const double *pts, size_t n, const double pos[3], int falloff, double *c0, double *dist);
} qtool_view_asset_opts;

/* the defaults of `qibl view`, in one place: exposure 1, the lamp's C0 from lamp_default, the
 * initial sun; --bench's frame count and its cap */
#define QTOOL_VIEW_ASSET_OPTS_DEFAULT {.exposure = 1.0, .lamp_c0 = 0, .sun = NULL, .lamp_default = NULL}
#define QTOOL_VIEW_BENCH_FRAMES_DEFAULT 600L
#define QTOOL_VIEW_BENCH_FRAMES_MAX 1000000L

/* Fills v (qtool_view_init) for the asset's bytes (caller-owned, kept for the path scheme), name
 * naming it in messages: its maps, exposure, sun, the path scheme, and where it has a P map the lamp
 * (its maps, its occlusion when the LOCC chunk is usable, placed by qtool_view_pick, its C0). A
 * one-line note (the LOCC chunk unusable, --lamp-rgb without a P map) goes into note ("" if none).
 * 0, or -1 with a one-line reason in err. */
int qtool_view_open_asset(qtool_view *v, const uint8_t *bytes, size_t n, const char *name,
                          const qtool_view_asset_opts *o, char *note, size_t notelen, char *err, size_t errlen);

/* The truth frames of --truth PATH: one PNG of the maps' w x h (one), or a directory of
 * sun_X_Y_Z.png frames (n of them, each of the unit sun direction dir and the name stem; at most
 * QTOOL_VIEW_MAX_TRUTHS and QTOOL_VIEW_TRUTH_MAX_BYTES). 0, or -1 with a one-line reason in err and
 * nothing kept. */
typedef struct qtool_view_truths {
    uint8_t *one;
    uint32_t n;
    uint8_t *rgb[QTOOL_VIEW_MAX_TRUTHS];
    double dir[QTOOL_VIEW_MAX_TRUTHS][3];
    char *name[QTOOL_VIEW_MAX_TRUTHS];
} qtool_view_truths;
int qtool_view_truths_load(const char *path, uint32_t w, uint32_t h, qtool_view_truths *t, char *err, size_t errlen);
void qtool_view_truths_free(qtool_view_truths *t);

/* Checks a recording's size against QTOOL_VIEW_RECORD_MAX_BYTES: 0, or -1 with a one-line reason. */
int qtool_view_record_check(const qtool_view *v, long frames, char *err, size_t errlen);

/* --gles (view/gles.c): platform/gles2 on a headless EGL context kept for the whole run, the frame
 * read back into the window's buffer. open: 0, or -1 with a one-line reason (no EGL in this build,
 * no context, the upload failed); frame: a qtool_view_frame_fn with user = the qtool_view_gles. */
typedef struct qtool_view_gles qtool_view_gles;
qtool_view_gles *qtool_view_gles_open(const qtool_view *v, char *err, size_t errlen);
int qtool_view_gles_frame(void *user, qtool_view *v, uint8_t *bgrx, size_t stride);
void qtool_view_gles_close(qtool_view_gles *g);

/* 1 if this build can open a window (X11 found at build time). */
int qtool_view_have_window(void);

/* Opens a window of the maps' width x (height + QTOOL_VIEW_OVERLAY_H) and runs until q, Escape or
 * the window is closed; or the bench (headless: no window at all). 0, or -1 with a one-line reason
 * in err (no display, no X11 in this build, out of memory, a core error). */
int qtool_view_run(qtool_view *v, const qtool_view_run_opts *o, char *err, size_t errlen);

#endif
