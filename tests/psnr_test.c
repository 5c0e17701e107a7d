/*
 * psnr_test.c - the tools' one PSNR (tools/ref/psnr.c): 8-bit peak, dB, capped at 99 for equal data.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "ref/psnr.h"

/* against the amplitude form 20 log10(255 / rms), written the other way round */
static void test_psnr8_matches_amplitude_form(void **state)
{
    (void)state;
    static const double mse[] = {1e-9, 0.25, 1.0, 2.0, 6.5025, 100.0, 650.25, 1234.5, 65025.0, 1e6};
    for (size_t i = 0; i < sizeof mse / sizeof mse[0]; ++i)
        assert_true(fabs(qtool_ref_psnr8(mse[i]) - 20.0 * log10(255.0 / sqrt(mse[i]))) < 1e-9);
}

/* round figures: one 8-bit level of rms error is 48.13 dB, 10% of full scale 20 dB, full scale 0 dB */
static void test_psnr8_round_figures(void **state)
{
    (void)state;
    assert_true(fabs(qtool_ref_psnr8(1.0) - 48.1308036086791) < 1e-9);
    assert_true(fabs(qtool_ref_psnr8(650.25) - 20.0) < 1e-9);
    assert_true(fabs(qtool_ref_psnr8(65025.0)) < 1e-12);
    assert_true(qtool_ref_psnr8(65025.0 * 4) < 0); /* error above full scale: negative dB */
}

/* equal data: the cap every table uses, also for a (rounding) negative MSE */
static void test_psnr8_cap(void **state)
{
    (void)state;
    assert_true(qtool_ref_psnr8(0.0) == 99.0);
    assert_true(qtool_ref_psnr8(-0.0) == 99.0);
    assert_true(qtool_ref_psnr8(-1e-12) == 99.0);
    assert_true(qtool_ref_psnr8(1e-12) > 99.0); /* tiny but non-zero errors are not capped */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_psnr8_matches_amplitude_form),
        cmocka_unit_test(test_psnr8_round_figures),
        cmocka_unit_test(test_psnr8_cap),
    };
    return cmocka_run_group_tests_name("psnr", tests, NULL, NULL);
}
