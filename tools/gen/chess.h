/*
 * gen/chess.h - a procedural chess set with moving pieces, the paper's third scene (Kautz et al.,
 * "Chess"), for `qibl bench hemi` and `qibl transfer`: a board (a 16 x 16 grid of quads, 8 x 8
 * squares of 1 unit) and the 32 pieces as closed surfaces of revolution (a profile per kind; the
 * knight's head leans), z up. In the frames a white pawn opens two squares, a knight hops and a
 * black pawn answers; every frame has the same triangles. With the default 8 segments around:
 * 1889 vertices, 3584 triangles (the paper's set: 1897 and 3704). Hosted, double precision.
 */
#ifndef QTOOL_GEN_CHESS_H
#define QTOOL_GEN_CHESS_H

#include <stddef.h>
#include <stdint.h>

typedef struct qtool_chess {
    uint32_t nv, nt, nframes;
    uint32_t (*tri)[3]; /* counter-clockwise seen from outside */
    double *pos;        /* nframes * nv * 3 */
} qtool_chess;

/* Builds nframes (1..64) frames with `segments` (3..64) vertices around each piece. 0, or -1 on a
 * bad argument or no memory (*out then empty). */
int qtool_chess_make(int nframes, int segments, qtool_chess *out);
void qtool_chess_free(qtool_chess *c);

/* Writes frame f as a Wavefront OBJ (v and f lines, z up) through io/atomic.h. 0, or -1 with a
 * one-line message in err. */
int qtool_chess_write_obj(const qtool_chess *c, uint32_t f, const char *path, char *err, size_t errlen);

#endif /* QTOOL_GEN_CHESS_H */
