/*
 * fuzz_gltf.c - libFuzzer target: the glTF 2.0 reader (tools/io/gltf.c, qtool_gltf_parse), on both
 * .gltf JSON and .glb bytes, with no folder (external uris are refused, never opened); inputs of
 * even length are read at an animation time taken from their last byte (0 .. 7.97 s: sampling,
 * skinning), odd ones in the rest pose.
 *
 * Invariants: a failure leaves the output untouched, allocates nothing (the leak checker sees it)
 * and gives a one-line reason; a success gives at least one triangle and at most the cap, finite
 * positions within QIBL_OBJ_MAX_COORD, unit (or zero) normals, albedo in 0..1, texture indices in
 * range with finite uv and texture sizes that match their pixels, finite cameras with unit axes.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/gltf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    qtool_gltf_scene s, before;
    memset(&s, 0xA5, sizeof s);
    memcpy(&before, &s, sizeof s);
    memset(err, 0, sizeof err);
    const size_t cap = 1 << 16;
    double t = size && !(size & 1) ? data[size - 1] / 32.0 : -1.0;
    int rc = qtool_gltf_parse_at("fuzz.gltf", NULL, data, size, cap, t, &s, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && memcmp(&s, &before, sizeof s) == 0);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    const qtool_obj_mesh *m = &s.mesh;
    FUZZ_CHECK(m->ntri >= 1 && m->ntri <= cap && m->pos && m->nrm);
    for (size_t i = 0; i < 9 * m->ntri; ++i)
        FUZZ_CHECK(fabs(m->pos[i]) <= QIBL_OBJ_MAX_COORD);
    for (size_t c = 0; c < 3 * m->ntri; ++c) {
        const double *n = m->nrm + 3 * c;
        double len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        FUZZ_CHECK(isfinite(len2) && (len2 == 0.0 || fabs(len2 - 1.0) < 1e-6));
    }
    for (size_t i = 0; m->albedo && i < 3 * m->ntri; ++i)
        FUZZ_CHECK(m->albedo[i] >= 0 && m->albedo[i] <= 1);
    FUZZ_CHECK(!m->tex == !m->uv);
    for (size_t t = 0; m->tex && t < m->ntri; ++t) {
        FUZZ_CHECK(m->tex[t] >= -1 && (m->tex[t] < 0 || (size_t)m->tex[t] < m->ntex));
        for (int k = 0; k < 6; ++k)
            FUZZ_CHECK(isfinite(m->uv[6 * t + k]));
    }
    for (size_t i = 0; i < m->ntex; ++i) {
        FUZZ_CHECK(m->texs[i].w >= 1 && m->texs[i].h >= 1 && m->texs[i].rgb);
        volatile uint8_t last = m->texs[i].rgb[3 * (size_t)m->texs[i].w * (size_t)m->texs[i].h - 1];
        (void)last; /* ASan: the pixels are really there */
    }
    FUZZ_CHECK(!s.has_anim || (isfinite(s.anim_start) && isfinite(s.anim_end) && s.anim_start <= s.anim_end));
    for (size_t c = 0; c < s.ncam; ++c)
        for (int j = 0; j < 3; ++j)
            FUZZ_CHECK(isfinite(s.cams[c].eye[j]) && isfinite(s.cams[c].fwd[j]) && isfinite(s.cams[c].up[j]));
    qtool_gltf_free(&s);
    return 0;
}
