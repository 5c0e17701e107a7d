/*
 * fuzz_ply.c - libFuzzer target for the PLY mesh reader (tools/io/ply.c: qtool_ply_parse).
 *
 * Input: a PLY file image. Invariants checked (abort on violation): a refusal leaves the mesh empty
 * with a message; an accepted mesh has 1..QTOOL_PLY_MAX_TRIANGLES triangles, finite corners within the
 * reader's coordinate bound and unit (or zero) normals; a triangle cap one below the count is refused
 * with the exact count and nothing allocated, a cap at the count gives the same triangles.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/ply.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    qtool_obj_mesh m;
    char err[512];
    err[0] = '\0';
    if (qtool_ply_parse("fuzz.ply", data, size, &m, err, sizeof err) != 0) {
        if (m.pos || m.nrm || m.ntri || err[0] == '\0')
            abort();
        return 0;
    }
    if (m.ntri == 0 || m.ntri > QTOOL_PLY_MAX_TRIANGLES)
        abort();
    for (size_t i = 0; i < m.ntri * 9; ++i) {
        if (!isfinite(m.pos[i]) || fabs(m.pos[i]) > 1e15)
            abort();
        if (i % 3 == 0) {
            const double *n = m.nrm + i;
            double l = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if (!(l == 0 || fabs(l - 1) < 1e-9))
                abort();
        }
    }
    /* a caller's cap: one below the count is refused with the exact count and nothing allocated,
     * the count itself gives the same mesh */
    const size_t ntri = m.ntri;
    qtool_obj_free(&m);
    char want[64];
    snprintf(want, sizeof want, "%zu triangles after fan triangulation", ntri);
    if (qtool_ply_parse_max("fuzz.ply", data, size, ntri - 1, &m, err, sizeof err) == 0 || m.pos || m.nrm || m.ntri ||
        !strstr(err, want))
        abort();
    if (qtool_ply_parse_max("fuzz.ply", data, size, ntri, &m, err, sizeof err) != 0 || m.ntri != ntri)
        abort();
    qtool_obj_free(&m);
    return 0;
}
