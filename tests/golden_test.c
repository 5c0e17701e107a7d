/*
 * golden_test.c - the golden groups of modules whose own suites check exactness against
 * references rather than hashes: fixed-point primitives, the SH basis, the sRGBE codec and the
 * asset parser (tools/golden/cases_*.c). Their hashes pin the exact bits, so that every compiler,
 * optimisation level and port (`make ports`) and both core flavours (this suite is built native and
 * portable like every suite) give the same ones. The relight, soft and lightprobe groups are
 * checked by shmap_test, soft_test and lightprobe_test. QIBL_UPDATE_GOLDEN=1 rewrites the files.
 * Also the cases' plumbing (golden/casesi.h): output hashed as produced, and the out-of-memory
 * report with the bytes a case needed (tools/gba/run.sh reads it).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "golden/casesi.h"
#include "golden/check.h"
#include "io/sha256.h"
#include "qibl/config.h"

static void test_fixed(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("fixed"), 0);
}

static void test_sh(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("sh"), 0);
}

static void test_srgbe(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("srgbe"), 0);
}

static void test_asset(void **state)
{
    (void)state;
    assert_int_equal(qtool_goldens_check("asset"), 0);
}

typedef struct {
    char name[64], hex[65], what[128];
    uint64_t n;
    int emits, errors;
} seen;

static int seen_emit(void *user, const char *name, const char *hex, uint64_t n)
{
    seen *r = (seen *)user;
    snprintf(r->name, sizeof r->name, "%s", name);
    snprintf(r->hex, sizeof r->hex, "%s", hex);
    r->n = n, ++r->emits;
    return 0;
}

static void seen_error(void *user, const char *name, const char *what)
{
    seen *r = (seen *)user;
    snprintf(r->name, sizeof r->name, "%s", name);
    snprintf(r->what, sizeof r->what, "%s", what);
    ++r->errors;
}

/* A case's bytes through every qtool_gbuf writer, longer than a handheld's RAM (1 MiB + 7): the hash
 * and count it emits are those of the same bytes laid out in memory, and the qtool_gbuf is reusable
 * after qtool_gbuf_emit (the next case starts empty). */
static void test_gbuf_streams(void **state)
{
    (void)state;
    enum { ROUNDS = 1 << 16 };
    const size_t total = (size_t)ROUNDS * 16u + 7u;
    uint8_t *want = malloc(total), *p = want;
    assert_non_null(want);
    seen r;
    memset(&r, 0, sizeof r);
    qtool_goldens_sink_t sink = {.emit = seen_emit, .error = seen_error, .user = &r};
    qtool_gbuf b = {0};
    qtool_grng g = {42};
    for (int i = 0; i < ROUNDS; ++i) {
        uint64_t v = qtool_grng_next(&g);
        qtool_gbuf_u8(&b, (uint32_t)v), *p++ = (uint8_t)v;
        qtool_gbuf_u16(&b, (uint32_t)(v >> 8)), *p++ = (uint8_t)(v >> 8), *p++ = (uint8_t)(v >> 16);
        qtool_gbuf_s32(&b, qtool_gs32((uint32_t)(v >> 24))), qtool_gput_u32(p, (uint32_t)(v >> 24)), p += 4;
        qtool_gbuf_u64(&b, v);
        for (int k = 0; k < 8; ++k)
            *p++ = (uint8_t)(v >> (8 * k));
        qtool_gbuf_bytes(&b, p - 15, 1), *p = p[-15], ++p;
    }
    qtool_gbuf_bytes(&b, "golden!", 7), memcpy(p, "golden!", 7), p += 7;
    assert_int_equal((size_t)(p - want), total);
    assert_int_equal(qtool_gbuf_emit(&sink, "streamed", &b), 0);
    char hex[65];
    qtool_sha256_hex(want, total, hex);
    assert_string_equal(r.name, "streamed");
    assert_string_equal(r.hex, hex);
    assert_true(r.n == (uint64_t)total);
    /* reused: an empty case is the hash of no bytes */
    assert_int_equal(qtool_gbuf_emit(&sink, "empty", &b), 0);
    qtool_sha256_hex(want, 0, hex);
    assert_string_equal(r.hex, hex);
    assert_true(r.n == 0);
    assert_int_equal(r.emits, 2);
    assert_int_equal(r.errors, 0);
    free(want);
}

/* The out-of-memory report names the bytes (run.sh tells a case that cannot fit from one that
 * should have by them); 0 stands for a size beyond size_t. */
static void test_oom_size(void **state)
{
    (void)state;
    seen r;
    memset(&r, 0, sizeof r);
    qtool_goldens_sink_t sink = {.emit = seen_emit, .error = seen_error, .user = &r};
    assert_int_equal(qtool_gcase_oom_size(&sink, "big", 329240u), 1);
    assert_string_equal(r.name, "big");
    assert_string_equal(r.what, "out of memory: needs 329240 bytes");
    assert_int_equal(qtool_gcase_oom_size(&sink, "huge", 0u), 1);
    assert_string_equal(r.what, "out of memory: needs more bytes than size_t holds");
    assert_int_equal(r.errors, 2);
    assert_int_equal(r.emits, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixed),
        cmocka_unit_test(test_sh),
        cmocka_unit_test(test_srgbe),
        cmocka_unit_test(test_asset),
        cmocka_unit_test(test_gbuf_streams),
        cmocka_unit_test(test_oom_size),
    };
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "golden (native paths)" : "golden (portable M0 paths)",
                                       tests, NULL, NULL);
}
