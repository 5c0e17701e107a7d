/*
 * transfer/run.h - everything `qibl transfer` computes, short of parsing its options and printing:
 * the frames of a mesh (welded, normalised, z up, tweened), each vertex's transfer vector from the
 * hemispherical rasterization of its blockers (every triangle, the two-level hierarchy or its PVS,
 * transfer/transfer.h) shaded under a probe's radiance SH (or its median-cut lights as SH), the
 * ray-cast reference and its error, the CPU time of each phase, and optionally the sheet of pictures
 * (qibl | reference | error per frame, drawn by platform/soft's rasterizer).
 *
 * Contract: options in one designated-initialised struct whose defaults live here
 * (QTOOL_TRANSFER_OPTS_DEFAULT); qtool_transfer_measure returns 0 with every figure in the result,
 * or -1 with a one-line reason in err and the result zeroed (nothing allocated). It prints nothing
 * and writes no file: the command prints the figures and writes the sheet.
 */
#ifndef QTOOL_TRANSFER_RUN_H
#define QTOOL_TRANSFER_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "io/probe_layout.h"
#include "qibl/fixed.h"
#include "qibl/hemi.h"
#include "transfer/transfer.h"

#define QTOOL_TRANSFER_MAX_FRAMES 64 /* MESH files (key frames) of one run */
#define QTOOL_TRANSFER_MAX_TWEEN 16  /* frames per key frame */
/* what a run may hold for its frames: the sheet of every frame (the APNG writer takes them all at
 * once) and --pvs's integer positions of every frame; refused up front beyond it */
#define QTOOL_TRANSFER_MAX_HELD ((uint64_t)256 << 20)
#define QTOOL_TRANSFER_LABEL_H 24     /* the sheet's title bar, pixels */
#define QTOOL_TRANSFER_LEGEND_H 22    /* colour-scale bar under the error panel */
#define QTOOL_TRANSFER_ERR_SCALE 0.10 /* the error panel's full scale: 10 % of the mean shading */

typedef struct qtool_transfer_opts {
    char *const *files;          /* nfiles meshes (.obj, .ply, glTF): the key frames of one animation */
    int nfiles;
    const char *probe;           /* the lighting: a probe image (.hdr) */
    qtool_probe_layout_t layout; /* its layout (AUTO: detected) */
    int lights;                  /* > 0 (a power of two): its median-cut lights projected to SH instead */
    int zup;                     /* the meshes are z up (else y up, turned) */
    int flip;                    /* turn the normals (a mesh wound clockwise that is not closed) */
    int skip_adjacent;           /* the faces around each vertex do not block (no crease wedges) */
    int pvs;                     /* also each vertex from its PVS over the frames, timed, masks compared */
    int mask, face;              /* the hemicube mask (16, 32, 64) and its LUT face (even, 2..128) */
    int rays;                    /* S: S x S reference rays per vertex (0: no reference) */
    int coarse, ring;            /* coarse > 0: the two-level hierarchy, coarse triangles + ring rings */
    int tween;                   /* frames per key frame (1: the key frames alone) */
    int threads;                 /* >= 1 */
    int sheet;                   /* 1: draw the sheet of pictures (result.sheet) */
    int size;                    /* pixels per panel of the sheet */
    double az, el;               /* the sheet's view, degrees */
    int keep_transfer;           /* 1: keep frame 0's world transfer vectors (result.transfer) */
    int time_reps;               /* 0: the frame times are the pass's per-vertex clocks; N > 0 (benchmarks):
                                    after each frame's pass its hemi work again N times as whole-frame
                                    blocks on one thread (every-blocker and PVS passes alternated), the
                                    frame's times their minima (0..QTOOL_TRANSFER_MAX_TIME_REPS) */
} qtool_transfer_opts;

#define QTOOL_TRANSFER_MAX_TIME_REPS 64

/* the defaults of `qibl transfer`, in one place (the integers named: the command's table reads them) */
#define QTOOL_TRANSFER_MASK_DEFAULT 32
#define QTOOL_TRANSFER_RAYS_DEFAULT 32
#define QTOOL_TRANSFER_RING_DEFAULT 3
#define QTOOL_TRANSFER_TWEEN_DEFAULT 1
#define QTOOL_TRANSFER_SIZE_DEFAULT 320
#define QTOOL_TRANSFER_OPTS_DEFAULT                                                                         \
    {                                                                                                       \
        .layout = QTOOL_PROBE_LAYOUT_AUTO, .mask = QTOOL_TRANSFER_MASK_DEFAULT,                             \
        .face = (int)QIBL_HEMI_FACE_DEFAULT, .rays = QTOOL_TRANSFER_RAYS_DEFAULT, .coarse = 0,              \
        .ring = QTOOL_TRANSFER_RING_DEFAULT, .tween = QTOOL_TRANSFER_TWEEN_DEFAULT, .threads = 1,           \
        .size = QTOOL_TRANSFER_SIZE_DEFAULT, .az = 35, .el = 20                                             \
    }

typedef struct qtool_transfer_result {
    uint32_t nv, nt, nframes;     /* nframes: every frame computed (key frames x tween) */
    int flipped;                  /* normals turned: flip, or a closed mesh wound clockwise */
    char probe_desc[160];         /* the probe's size and layout (and the lights' distance from it) */
    size_t hemi_bytes;            /* the hemi tables */
    uint32_t coarse_nt;           /* the hierarchy's coarse triangles */
    double hier_blockers;         /* the hierarchy's blockers per vertex */
    double ms_per_frame;          /* hemi CPU ms per frame, one core */
    double l2err, ref_noise, shade_err; /* against the reference (rays > 0) */
    double mean_irradiance;       /* luminance in the probe's units times the light's scaling */
    double share[4];              /* of the hemi time: transform, rasterization, integration, other */
    double ref_ms_per_frame;      /* the ray cast's CPU time (0 without one) */
    double blockers, rasterized;  /* per vertex: triangles tested, rasterized (above the horizon) */
    double pvs_blockers, pvs_ms_per_frame, pvs_diff; /* with pvs: per vertex, hemi time, masks that differed */
    uint32_t no_normal[QTOOL_TRANSFER_MAX_FRAMES * QTOOL_TRANSFER_MAX_TWEEN]; /* per frame: vertices without one */
    int32_t light[3][QIBL_HEMI_COEFFS]; /* the SH light the vertices were shaded with (Q16.16) */
    uint8_t *sheet;               /* sheet: nframes RGB8 pictures of sheet_w x sheet_h (malloc'd) */
    int sheet_w, sheet_h;
    qibl_q30_t (*transfer)[QIBL_HEMI_COEFFS]; /* keep_transfer: frame 0's, per vertex (malloc'd) */
    qibl_q16_t (*shade)[3];       /* keep_transfer: frame 0's qibl_hemi_shade of it (malloc'd) */
} qtool_transfer_result;

/* The run: 0, or -1 with a one-line reason in err (errlen bytes) and *r zeroed. */
int qtool_transfer_measure(const qtool_transfer_opts *o, qtool_transfer_result *r, char *err, size_t errlen);
/* Frees what the result holds (sheet, transfer, shade); its figures stay. */
void qtool_transfer_result_free(qtool_transfer_result *r);

/* Area-weighted vertex normals of positions P (3 nv doubles) into N (3 nv); flip < 0 turns them. */
void qtool_transfer_normals(uint32_t nv, uint32_t nt, const uint32_t (*tri)[3], const double *P, double flip,
                            double *N);

#endif
