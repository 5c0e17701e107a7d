/*
 * transfer/frames.h - the frames of `qibl transfer` (internal to tools/transfer): the meshes of an
 * animation loaded as one indexed mesh with a frame of positions each, tweened frames, and each
 * frame's integer inputs to the hemi core.
 */
#ifndef QTOOL_TRANSFER_FRAMES_H
#define QTOOL_TRANSFER_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/fixed.h"
#include "transfer/transfer.h"

/* Loads every frame, welds on frame 0, checks the others share its topology, normalises all frames
 * with frame 0's box (centre, largest half-extent 1) and turns Y-up to Z-up unless zup. 0, or -1
 * with a one-line reason in err and *out zeroed. */
int qtool_transfer_frames_load(char *const *paths, int n, int zup, qtool_transfer_mesh *out, char *err, size_t errlen);

/* Frame f's positions: with t > 1, t - 1 frames between each pair of the nkeys key frames, linear
 * per vertex, the last blending back into the first (an animation cycle, like the paper's
 * interpolated keyframes), made one at a time into buf (3 nv doubles): only the key frames are
 * held, so tweening costs one frame of memory, not t times the animation. */
const double *qtool_transfer_frame_pos(const qtool_transfer_mesh *m, uint32_t nkeys, uint32_t t, uint32_t f,
                                       double *buf);

/* One frame's integer inputs: positions Q16.16, unit normals Q2.30 (zero where a vertex has none);
 * returns how many vertices have no normal. N: 3 nv doubles of scratch. */
uint32_t qtool_transfer_frame_ints(const qtool_transfer_mesh *m, const double *P, double flip, double *N,
                                   qibl_q16_t (*pos)[3], int32_t (*nrm)[3]);

#endif
