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
    };
    return cmocka_run_group_tests_name("status", tests, NULL, NULL);
}
