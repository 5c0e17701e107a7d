/*
 * golden_test.c - the golden groups of modules whose own suites check exactness against
 * references rather than hashes: fixed-point primitives, the SH basis, the sRGBE codec and the
 * asset parser (tools/golden/cases_*.c). Their hashes pin the exact bits, so that every compiler,
 * optimisation level and port (`make ports`) and both core flavours (this suite is built native and
 * portable like every suite) give the same ones. The relight, soft and lightprobe groups are
 * checked by shmap_test, soft_test and lightprobe_test. QIBL_UPDATE_GOLDEN=1 rewrites the files.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "golden/check.h"
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixed),
        cmocka_unit_test(test_sh),
        cmocka_unit_test(test_srgbe),
        cmocka_unit_test(test_asset),
    };
    return cmocka_run_group_tests_name(QIBL_CONFIG_NATIVE_MUL64 ? "golden (native paths)" : "golden (portable M0 paths)",
                                       tests, NULL, NULL);
}
