/*
 * ref/hemi_ref.h - the ray-cast reference for hemispherical rasterization (qibl/hemi.h): the
 * transfer vector V*_i = integral of Y_i(s) V(s) max(0, n.s) ds of one receiver, by S x S
 * stratified cosine-weighted rays through the BVH of tools/render/rt.c, in double.
 */
#ifndef QTOOL_REF_HEMI_REF_H
#define QTOOL_REF_HEMI_REF_H

#include <stdint.h>

#include "render/rt.h"

/* V* (25 coefficients, bands 0..4) at p with frame axes ax (rows t, b, n; n the normal), from
 * side x side rays with jitter from seed. world = 0: the basis in the frame's coordinates (what
 * qibl_hemi_transfer returns); world = 1: in world coordinates (what qibl_hemi_to_world returns).
 * *noise (may be NULL) gets the estimate |A - B| / 2 / |V*| from the two interleaved halves of the
 * strata (each estimates the whole). */
void qtool_hemi_ref(const qtool_rt_scene *rt, const double p[3], const double ax[3][3], int side, int world,
                    uint64_t seed, double out[25], double *noise);

/* The glossy transfer of qibl_hemi_transfer_phong: the integral of Y_i(s) V(s) max(0, n.s)
 * max(0, r.s)^e ds, the basis in the frame's coordinates, refl = r in the frame (any length). Each
 * cosine-weighted ray weighted by the lobe; the noise as above. */
void qtool_hemi_ref_phong(const qtool_rt_scene *rt, const double p[3], const double ax[3][3], int side,
                          const double refl[3], double e, uint64_t seed, double out[25], double *noise);

#endif
