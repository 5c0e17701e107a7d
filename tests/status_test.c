/*
 * status_test.c - every qibl_status_t value has its own description.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "qibl/status.h"

static void test_every_status_named_and_distinct(void **state)
{
    (void)state;
    const char *unknown = qibl_status_str(QIBL_STATUS_COUNT);
    assert_string_equal(unknown, "unknown status");
    assert_string_equal(qibl_status_str(QIBL_OK), "ok");
    for (int i = 0; i < QIBL_STATUS_COUNT; ++i) {
        const char *a = qibl_status_str((qibl_status_t)i);
        assert_non_null(a);
        assert_true(strlen(a) > 0);
        assert_string_not_equal(a, unknown);
        for (int j = 0; j < i; ++j)
            assert_string_not_equal(a, qibl_status_str((qibl_status_t)j));
    }
}

/* The values are ABI (callers, assets and goldens store them): the one list in status.h may only
 * grow at its end. A few values pinned from each group, and the count. */
static void test_status_values_pinned(void **state)
{
    (void)state;
    assert_int_equal(QIBL_OK, 0);
    assert_int_equal(QIBL_E_NULL_POINTER, 1);
    assert_int_equal(QIBL_E_RANGE, 5);
    assert_int_equal(QIBL_E_ASSET_TRUNCATED_HEADER, 6);
    assert_int_equal(QIBL_E_ASSET_MISMATCH, 25);
    assert_int_equal(QIBL_E_RESERVED_26, 26);
    assert_int_equal(QIBL_E_WORKSPACE, 30);
    assert_int_equal(QIBL_E_SRGBE_NAN, 39);
    assert_int_equal(QIBL_E_PROBE_SIZE, 43);
    assert_int_equal(QIBL_E_CONFIG_MISMATCH, 53);
    assert_int_equal(QIBL_E_LIGHTPATH_SIZE, 61);
    assert_int_equal(QIBL_E_HEMI_SIZE, 69);
    assert_int_equal(QIBL_E_GONIO_SIZE, 74);
    assert_int_equal(QIBL_E_WORKSPACE_ALIGN, 79);
    assert_int_equal(QIBL_E_HEMI_XFER_SHORT, 80);
    assert_int_equal(QIBL_E_HEMI_XFER_BOUNDS, 85);
    assert_int_equal(QIBL_E_HEMI_TABLES_BOUNDS, 86);
    assert_int_equal(QIBL_E_HEMI_TABLES_CRC, 93);
    assert_int_equal(QIBL_STATUS_COUNT, 94);
    assert_int_equal(QIBL_STATUS_SOFT_BASE, 0x100);
    assert_int_equal(QIBL_STATUS_GLES2_BASE, 0x200);
    assert_int_equal(QIBL_STATUS_BACKEND_END, 0x1000);
}

/* The list gives each status its message: the message of every entry is the one
 * qibl_status_str returns for that entry's value (no case can drift out of step). */
static void test_status_list_matches_str(void **state)
{
    (void)state;
    int n = 0;
#define CHECK_(name, message) assert_string_equal(qibl_status_str(name), message); \
                              assert_int_equal((int)(name), n); ++n;
    QIBL_STATUS_LIST(CHECK_)
#undef CHECK_
    assert_int_equal(n, QIBL_STATUS_COUNT);
}

static void test_out_of_range_status_is_unknown(void **state)
{
    (void)state;
    assert_string_equal(qibl_status_str((qibl_status_t)-1), "unknown status");
    assert_string_equal(qibl_status_str((qibl_status_t)(QIBL_STATUS_COUNT + 7)), "unknown status");
    /* backend ranges: the core only says whose they are; the backend's *_status_str names them */
    assert_string_equal(qibl_status_str((qibl_status_t)(QIBL_STATUS_SOFT_BASE + 1)), "platform backend status");
    assert_string_equal(qibl_status_str((qibl_status_t)(QIBL_STATUS_BACKEND_END - 1)), "platform backend status");
    assert_string_equal(qibl_status_str(QIBL_STATUS_BACKEND_END), "unknown status");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_status_named_and_distinct),
        cmocka_unit_test(test_out_of_range_status_is_unknown),
        cmocka_unit_test(test_status_values_pinned),
        cmocka_unit_test(test_status_list_matches_str),
    };
    return cmocka_run_group_tests_name("status", tests, NULL, NULL);
}
