/*
 * golden/cases.h - every golden case of the core: fixed inputs -> output bytes, one name each.
 *
 * The one place golden fixtures are generated. Two consumers include it:
 *   - tools/golden/runner.c, the plain C runner that `make ports` cross-compiles and runs on every
 *     configuration (it links this code, the core, platform/soft and io/sha256.c, nothing else);
 *   - the CMocka suites, through golden/check.h (qtool_goldens_check), which compare against the
 *     same fixtures/golden/<name>.sha256 files.
 *
 * Rules for cases (what makes a golden worth something on every port):
 *   - Inputs are made with integer arithmetic only (splitmix64, ramps, hashes): no libm, no float,
 *     so the input bytes cannot depend on a platform's math library or FPU.
 *   - Outputs are serialised byte by byte, little-endian, never by copying structs or host words,
 *     so the bytes do not depend on the host's byte order, padding or sizeof.
 *   - Cases are small: the runner must take seconds under qemu.
 * Code here is plain C99 + the C library (stdio, stdlib, string): no POSIX, no libm.
 *
 * Adding a module: write cases_<module>.c with one `int qibl_goldens_<module>(const
 * qtool_goldens_sink_t *s)`, list it in qtool_goldens_groups (cases.c), run the runner once with
 * --update and commit the new fixtures/golden/<case>.sha256 files.
 */
#ifndef QTOOL_GOLDEN_CASES_H
#define QTOOL_GOLDEN_CASES_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/lightprobe.h"

/* Where a group's cases go. */
typedef struct qtool_goldens_sink {
    /* One finished case: its name (letters, digits, '_'; the fixtures file name without
     * ".sha256"), the SHA-256 of its output bytes as 64 lowercase hex digits and their count.
     * Returns 0 when the case passed (hash as expected). The bytes themselves are not handed over:
     * a case's output is hashed as it is produced (casesi.h: qtool_gbuf), so it needs no memory of its
     * size; some outputs exceed a handheld's whole RAM (the GBA's 256 KiB). */
    int (*emit)(void *user, const char *name, const char *hex, uint64_t n);
    /* A case that could not be produced: a core call returned an unexpected status, or memory ran
     * out. what says which call and why. The case counts as failed. */
    void (*error)(void *user, const char *name, const char *what);
    void *user;
    /* Optional (NULL on hosts): the port's prebuilt hemi tables for (n, face), the blob of
     * qibl_hemi_tables_build (e.g. in cartridge ROM), its bytes in *size; NULL when it has none.
     * The hemi cases that use the tables open it in place (qibl_hemi_open) instead of building the
     * tables in the heap, so a machine with less RAM than the tables runs them (tools/gba). */
    const void *(*hemi_tables)(void *user, int n, int face, size_t *size);
} qtool_goldens_sink_t;

/* A group runs all cases of one module and returns the number that failed (emit returned
 * non-zero, or error was called). */
typedef int (*qtool_goldens_fn)(const qtool_goldens_sink_t *s);

typedef struct qtool_goldens_group {
    const char *name;   /* "relight", "soft", ... (the case names start with it or its module) */
    const char *about;  /* one line */
    qtool_goldens_fn run;
} qtool_goldens_group_t;

/* Every group, in the order the runner runs them. */
extern const qtool_goldens_group_t qtool_goldens_groups[];
extern const size_t qtool_goldens_group_count;

/* Runs the group called name. Returns its failure count, or -1 if there is no such group. */
int qtool_goldens_run(const char *name, const qtool_goldens_sink_t *s);

/* The groups (cases_<module>.c). */
int qtool_goldens_fixed(const qtool_goldens_sink_t *s);
int qtool_goldens_sh(const qtool_goldens_sink_t *s);
int qtool_goldens_srgbe(const qtool_goldens_sink_t *s);
int qtool_goldens_asset(const qtool_goldens_sink_t *s);
int qtool_goldens_relight(const qtool_goldens_sink_t *s);
int qtool_goldens_soft(const qtool_goldens_sink_t *s);
int qtool_goldens_raster(const qtool_goldens_sink_t *s);
int qtool_goldens_lightprobe(const qtool_goldens_sink_t *s);
int qtool_goldens_lightpath(const qtool_goldens_sink_t *s);
int qtool_goldens_probe(const qtool_goldens_sink_t *s);
int qtool_goldens_hemi(const qtool_goldens_sink_t *s);
int qtool_goldens_gonio(const qtool_goldens_sink_t *s);

/* The serialisation of a light list that the lightprobe_* goldens hash (also used by
 * tests/lightprobe_test.c for the real probes): count, rgb_exp, then per light dir[3], rgb[3],
 * u0, v0, u1, v1, each a little-endian 32-bit word. out needs 8 + 40 * res->count bytes; returns
 * the bytes written. */
size_t qtool_goldens_light_bytes(const qibl_lightprobe_light_t *lights, const qibl_lightprobe_result_t *res,
                                uint8_t *out);

#endif
