/*
 * fuzz_obj.c - libFuzzer target: the Wavefront OBJ reader (tools/io/obj.c, qtool_obj_parse).
 *
 * Invariants: a failure leaves the mesh untouched, allocates nothing (the leak checker sees it) and
 * gives a one-line reason; a success gives at least one triangle, finite corner positions and, per
 * corner, a normal that is finite and unit length (or zero, for a degenerate triangle), as obj.h
 * promises.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "io/obj.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    qtool_obj_mesh m, before;
    memset(&m, 0xA5, sizeof m);
    memcpy(&before, &m, sizeof m);
    memset(err, 0, sizeof err);
    int rc = qtool_obj_parse("fuzz.obj", (const char *)data, size, &m, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && memcmp(&m, &before, sizeof m) == 0);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(m.ntri >= 1 && m.pos && m.nrm);
    for (size_t i = 0; i < 9 * m.ntri; ++i)
        FUZZ_CHECK(isfinite(m.pos[i]));
    for (size_t c = 0; c < 3 * m.ntri; ++c) {
        const double *n = m.nrm + 3 * c;
        double len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        FUZZ_CHECK(isfinite(len2) && (len2 == 0.0 || fabs(len2 - 1.0) < 1e-6));
    }
    qtool_obj_free(&m);
    return 0;
}
