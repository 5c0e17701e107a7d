/*
 * transfer/sheet.h - the pictures of `qibl transfer` (internal to tools/transfer): per frame a
 * sheet of panels (qibl's shading | the ray-cast reference | their error as a heat ramp), each a
 * mesh drawn by platform/soft's integer z-buffer rasterizer from per-vertex colours, with titles.
 */
#ifndef QTOOL_TRANSFER_SHEET_H
#define QTOOL_TRANSFER_SHEET_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/raster.h"
#include "transfer/transfer.h"

/* an orthographic view of the mesh fitted to a size x size panel */
typedef struct qtool_transfer_view {
    double right[3], up[3], fwd[3];
    double scale, cx, cy, zlo, zhi;
} qtool_transfer_view;

/* the scratch of one panel: nv raster vertices, size^2 pixels and depths */
typedef struct qtool_transfer_panel {
    qibl_raster_vertex_t *rv;
    uint8_t *px;
    uint32_t *depth;
    int size;
} qtool_transfer_panel;

/* The view from azimuth az, elevation el (degrees, z up) fitted to every frame of m (its
 * positions m->pos, nframes of them): the projection's box fills 92 % of the panel. */
void qtool_transfer_view_make(double az, double el, int size, const qtool_transfer_mesh *m, qtool_transfer_view *vw);

/* Draws the mesh at positions P (3 nv doubles) with linear colours rgb (3 per vertex) into the
 * RGB8 sheet (sw pixels wide) at column x0, row y0; 0, or -1 with the rasterizer's reason in err. */
int qtool_transfer_panel_draw(const qtool_transfer_mesh *m, const double *P, const qtool_transfer_view *vw,
                              const double *rgb, int srgb, qtool_transfer_panel *pn, uint8_t *sheet, int sw, int x0,
                              int y0, char *err, size_t errlen);

/* A title centred over the panel of width w at column x0, row y. */
void qtool_transfer_label(uint8_t *sheet, int sw, int sh, int x0, int w, int y, const char *s);

/* The heat ramp (black, red, yellow, white) of t in [0, 1], linear. */
void qtool_transfer_heat(double t, double out[3]);

/* The error panel's colour scale (0 .. QTOOL_TRANSFER_ERR_SCALE of the mean) under the panel at
 * column x0 of a panel size S. */
void qtool_transfer_legend(uint8_t *sheet, int sw, int sh, int x0, int S);

#endif
