/*
 * isa_test.c - run-time kernel choice (qibl/isa.h) and QIBL_ISA (io/isa_env.h): the values the
 * tools refuse by name, forcing each set this CPU runs, and every golden group bit-identical under
 * each of them (the kernels of shmap, srgbe, probe, lightprobe and hemi under every dispatch choice).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "golden/cases.h"
#include "golden/check.h"
#include "io/isa_env.h"
#include "qibl/isa.h"

static void test_parse(void **state)
{
    (void)state;
    const uint32_t all = QIBL_ISA_BIT(QIBL_ISA_SCALAR) | QIBL_ISA_BIT(QIBL_ISA_SSE2) | QIBL_ISA_BIT(QIBL_ISA_AVX2);
    const uint32_t no_avx2 = QIBL_ISA_BIT(QIBL_ISA_SCALAR) | QIBL_ISA_BIT(QIBL_ISA_SSE2);
    uint32_t m = 0;
    char err[160] = "";
    assert_int_equal(qtool_isa_parse(NULL, all, &m, err, sizeof err), 0);
    assert_int_equal(m, ~0u);
    assert_int_equal(qtool_isa_parse("", all, &m, err, sizeof err), 0);
    assert_int_equal(m, ~0u);
    assert_int_equal(qtool_isa_parse("auto", all, &m, err, sizeof err), 0);
    assert_int_equal(m, ~0u);
    assert_int_equal(qtool_isa_parse("scalar", all, &m, err, sizeof err), 0);
    assert_int_equal(m, QIBL_ISA_BIT(QIBL_ISA_SCALAR));
    assert_int_equal(qtool_isa_parse("sse2", no_avx2, &m, err, sizeof err), 0);
    assert_int_equal(m, QIBL_ISA_BIT(QIBL_ISA_SSE2));
    assert_int_equal(qtool_isa_parse("avx2", all, &m, err, sizeof err), 0);
    assert_int_equal(m, QIBL_ISA_BIT(QIBL_ISA_AVX2));
    assert_int_equal(qtool_isa_parse("avx512", all | QIBL_ISA_BIT(QIBL_ISA_AVX512), &m, err, sizeof err), 0);
    assert_int_equal(m, QIBL_ISA_BIT(QIBL_ISA_AVX512));
    assert_int_equal(qtool_isa_parse("avx512", all, &m, err, sizeof err), -1);
    assert_string_equal(err, "QIBL_ISA: avx512: not available here (this CPU and build run: scalar sse2 avx2)");
    /* a CPU without AVX2: refused by name, the mask untouched */
    m = 7u;
    assert_int_equal(qtool_isa_parse("avx2", no_avx2, &m, err, sizeof err), -1);
    assert_int_equal(m, 7u);
    assert_string_equal(err, "QIBL_ISA: avx2: not available here (this CPU and build run: scalar sse2)");
    assert_int_equal(qtool_isa_parse("neon", all, &m, err, sizeof err), -1);
    assert_non_null(strstr(err, "neon: not available"));
    /* unknown values, including near misses */
    assert_int_equal(qtool_isa_parse("avx1024", all, &m, err, sizeof err), -1);
    assert_string_equal(err, "QIBL_ISA: unknown value 'avx1024' (scalar, sse2, avx2, avx512, neon, auto)");
    assert_int_equal(qtool_isa_parse("SSE2", all, &m, err, sizeof err), -1);
    assert_int_equal(qtool_isa_parse("sse2 ", all, &m, err, sizeof err), -1);
    assert_int_equal(m, 7u);
}

static void test_core_api(void **state)
{
    (void)state;
    const uint32_t have = qibl_isa_available();
    assert_int_not_equal(have, 0u);
    assert_true(have & QIBL_ISA_BIT(qibl_isa_active()));
    assert_string_equal(qibl_isa_name(QIBL_ISA_SCALAR), "scalar");
    assert_string_equal(qibl_isa_name(QIBL_ISA_SSE2), "sse2");
    assert_string_equal(qibl_isa_name(QIBL_ISA_AVX2), "avx2");
    assert_string_equal(qibl_isa_name(QIBL_ISA_NEON), "neon");
    assert_string_equal(qibl_isa_name(QIBL_ISA_AVX512), "avx512");
    assert_string_equal(qibl_isa_name((qibl_isa_t)9), "?");
    if (qibl_isa_dispatches()) {
        /* hosted x86-64: the scalar twin and SSE2 always, AVX2 where the CPU has it */
        assert_true(have & QIBL_ISA_BIT(QIBL_ISA_SCALAR));
        assert_true(have & QIBL_ISA_BIT(QIBL_ISA_SSE2));
        assert_false(have & QIBL_ISA_BIT(QIBL_ISA_NEON));
        /* the AVX-512 choice runs AVX2 copies too */
        if (have & QIBL_ISA_BIT(QIBL_ISA_AVX512))
            assert_true(have & QIBL_ISA_BIT(QIBL_ISA_AVX2));
    } else {
        assert_int_equal(have & (have - 1u), 0u); /* one compile-time path */
    }
}

/* each set forced in turn is the one calls use; a mask the CPU cannot run is ignored (never
 * unsupported code); 0 returns to QIBL_ISA/auto */
static void test_force(void **state)
{
    (void)state;
    const uint32_t have = qibl_isa_available();
    const qibl_isa_t before = qibl_isa_active();
    for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i) {
        if (!(have & QIBL_ISA_BIT(i)))
            continue;
        qtool_isa_force(QIBL_ISA_BIT(i));
        if (qibl_isa_dispatches())
            assert_int_equal(qibl_isa_active(), (qibl_isa_t)i);
        else
            assert_int_equal(qibl_isa_active(), before);
    }
    qtool_isa_force(~have & 0xffu); /* nothing this CPU runs: the best it has */
    assert_true(have & QIBL_ISA_BIT(qibl_isa_active()));
    qtool_isa_force(0u);
    assert_int_equal(qibl_isa_active(), before);
}

/* every golden group (the fixtures' hashes) under every set this CPU runs */
static void test_goldens_every_isa(void **state)
{
    (void)state;
    const uint32_t have = qibl_isa_available();
    int runs = 0;
    for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i) {
        if (!(have & QIBL_ISA_BIT(i)))
            continue;
        qtool_isa_force(QIBL_ISA_BIT(i));
        for (size_t g = 0; g < qtool_goldens_group_count; ++g) {
            const int bad = qtool_goldens_check(qtool_goldens_groups[g].name);
            if (bad != 0)
                fprintf(stderr, "isa %s: golden group %s: %d failed\n", qibl_isa_name((qibl_isa_t)i),
                        qtool_goldens_groups[g].name, bad);
            assert_int_equal(bad, 0);
        }
        ++runs;
    }
    qtool_isa_force(0u);
    assert_true(runs >= 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse),
        cmocka_unit_test(test_core_api),
        cmocka_unit_test(test_force),
        cmocka_unit_test(test_goldens_every_isa),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
