/*
 * fuzz_ply.c - libFuzzer target for the PLY mesh reader (tools/io/ply.c: qtool_ply_parse).
 *
 * Input: a PLY file image. Invariants checked (abort on violation): a refusal leaves the mesh empty
 * with a message; an accepted mesh has 1..QTOOL_PLY_MAX_TRIANGLES triangles, finite corners within the
 * reader's coordinate bound and unit (or zero) normals.
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
    qtool_obj_free(&m);
    return 0;
}
