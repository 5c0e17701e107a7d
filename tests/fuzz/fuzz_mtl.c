/*
 * fuzz_mtl.c - libFuzzer target: OBJ materials (tools/io/obj.c, qtool_obj_read_materials): the
 * input is written as m.mtl beside a fixed OBJ (mtllib m.mtl, usemtl of the material named "a",
 * faces with vt), in a private folder made once; map_Kd names resolve inside that folder (where
 * only the two files exist, so a texture is a missing file or the .obj or .mtl read as a PNG).
 *
 * Invariants: a failure leaves the mesh untouched, allocates nothing (the leak checker sees it)
 * and gives a one-line reason; a success gives 2 triangles whose albedo is in 0..1 and whose
 * texture indices are -1 or inside the textures.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz.h"
#include "io/obj.h"

static char dir[64], obj[96], mtl[96];

/* the private folder goes when the fuzzer exits */
static void cleanup(void)
{
    remove(obj), remove(mtl), rmdir(dir);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/qibl_fuzz_mtl_XXXXXX");
        if (!mkdtemp(dir))
            abort();
        snprintf(obj, sizeof obj, "%s/a.obj", dir);
        snprintf(mtl, sizeof mtl, "%s/m.mtl", dir);
        FILE *f = fopen(obj, "w");
        if (!f)
            abort();
        fputs("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1 2 3\nusemtl a\nf 1/1 2/2 3/3\n", f);
        fclose(f);
        atexit(cleanup);
    }
    FILE *f = fopen(mtl, "wb");
    if (!f)
        abort();
    if (size && fwrite(data, 1, size, f) != size)
        abort();
    fclose(f);
    char err[256];
    qtool_obj_mesh m, before;
    memset(&m, 0xA5, sizeof m);
    memcpy(&before, &m, sizeof m);
    memset(err, 0, sizeof err);
    int rc = qtool_obj_read_materials(obj, 100, &m, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && memcmp(&m, &before, sizeof m) == 0);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(m.ntri == 2 && m.albedo);
    for (size_t i = 0; i < 6; ++i)
        FUZZ_CHECK(m.albedo[i] >= 0 && m.albedo[i] <= 1);
    for (size_t t = 0; m.tex && t < 2; ++t)
        FUZZ_CHECK(m.tex[t] == -1 || (m.tex[t] >= 0 && (size_t)m.tex[t] < m.ntex));
    qtool_obj_free(&m);
    return 0;
}
