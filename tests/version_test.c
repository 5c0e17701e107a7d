/*
 * version_test.c - the library's version and configuration identity, and the check that turns a
 * config.h mismatch between caller and library into QIBL_E_CONFIG_MISMATCH.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "qibl.h"
#include "version_bands3.h"

static void test_version_string_matches_numbers(void **state)
{
    (void)state;
    char want[32];
    snprintf(want, sizeof want, "%d.%d.%d", QIBL_VERSION_MAJOR, QIBL_VERSION_MINOR, QIBL_VERSION_PATCH);
    assert_string_equal(QIBL_VERSION_STRING, want);
    assert_string_equal(qibl_version(), want);
    assert_int_equal(QIBL_VERSION_NUMBER,
                     QIBL_VERSION_MAJOR * 10000 + QIBL_VERSION_MINOR * 100 + QIBL_VERSION_PATCH);
}

static void test_same_config_passes(void **state)
{
    (void)state;
    assert_int_equal(qibl_config_id(), QIBL_CONFIG_ID);
    assert_int_equal(qibl_check_config(QIBL_CONFIG_ID), QIBL_OK);
    assert_int_equal(qibl_init_check(), QIBL_OK);
}

/* The fields of the identity as version.h documents them. */
static void test_config_id_fields(void **state)
{
    (void)state;
    uint32_t id = QIBL_CONFIG_ID;
    assert_int_equal(id >> 28, 0xAu);
    assert_int_equal((id >> 24) & 15u, (uint32_t)QIBL_VERSION_MAJOR & 15u);
    assert_int_equal((id >> 16) & 255u, (uint32_t)QIBL_VERSION_MINOR);
    assert_int_equal((id >> 8) & 15u, (uint32_t)QIBL_SH_MAX_BANDS);
    assert_int_equal(id & 255u, (uint32_t)(QIBL_USE_SH | QIBL_USE_SRGBE << 1 | QIBL_USE_ASSET << 2 |
                                          QIBL_USE_LIGHTPROBE << 3 | QIBL_USE_SHMAP << 4 |
                                          QIBL_USE_INTERLEAVED << 5 | QIBL_USE_PROBE << 6 |
                                          QIBL_USE_HEMI << 7));
    assert_int_equal((id >> 12) & 1u, (uint32_t)QIBL_USE_LIGHTPATH);
    assert_int_equal((id >> 13) & 1u, (uint32_t)QIBL_USE_GONIO);
    assert_int_equal(id & 0x0000C000u, 0u); /* reserved bits */
}

/* Any other identity is refused: every single-bit change, 0 and all ones. */
static void test_other_ids_refused(void **state)
{
    (void)state;
    for (unsigned b = 0; b < 32; ++b)
        assert_int_equal(qibl_check_config(QIBL_CONFIG_ID ^ (1u << b)), QIBL_E_CONFIG_MISMATCH);
    assert_int_equal(qibl_check_config(0u), QIBL_E_CONFIG_MISMATCH);
    assert_int_equal(qibl_check_config(0xFFFFFFFFu), QIBL_E_CONFIG_MISMATCH);
    assert_string_not_equal(qibl_status_str(QIBL_E_CONFIG_MISMATCH), "unknown status");
}

/* The case of issue 11: a TU compiled with -DQIBL_SH_MAX_BANDS=3, linked with the default library.
 * Its structs really are smaller (what made the library overflow its buffers), and its start-up
 * check gets the named status. */
static void test_bands3_caller_gets_mismatch(void **state)
{
    (void)state;
    if (QIBL_SH_MAX_BANDS == 3)
        skip(); /* a library built with 3 bands would match that TU */
    assert_true(version_bands3_shlight_size() < sizeof(qibl_shlight_t));
    assert_int_not_equal(version_bands3_config_id(), qibl_config_id());
    assert_int_equal((version_bands3_config_id() >> 8) & 15u, 3u);
    assert_int_equal(version_bands3_init_check(), QIBL_E_CONFIG_MISMATCH);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_version_string_matches_numbers),
        cmocka_unit_test(test_same_config_passes),
        cmocka_unit_test(test_config_id_fields),
        cmocka_unit_test(test_other_ids_refused),
        cmocka_unit_test(test_bands3_caller_gets_mismatch),
    };
    return cmocka_run_group_tests_name("version", tests, NULL, NULL);
}
