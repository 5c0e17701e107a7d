/*
 * bench_test.c - the helpers of the benchmarks library (tools/bench) that its figures rest on:
 * the median (odd and even counts, sorted in place), the paired ratio (a load change between
 * repetitions cancels; at most 64 pairs), the minimum, the u64 read baseline (whole words only),
 * and the hemi benches' cloth (cloth.c): its counts, the blocker lists of the full-mesh window and
 * of the two-ring, and the integer frame. Timing itself is never asserted.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "bench/bench.h"
#include "bench/cloth.h"

static void test_median_min(void **state)
{
    (void)state;
    double odd[5] = {5, 1, 4, 2, 3}, even[4] = {10, 2, 8, 4};
    assert_true(qtool_bench_median(odd, 5) == 3.0);
    assert_true(odd[0] == 1.0 && odd[4] == 5.0); /* sorted in place, as documented */
    assert_true(qtool_bench_median(even, 4) == 6.0);
    const double m[3] = {2.5, -1.0, 7.0};
    assert_true(qtool_bench_min(m, 3) == -1.0);
    assert_true(qtool_bench_min(m, 1) == 2.5);
}

static void test_paired_ratio(void **state)
{
    (void)state;
    /* the load doubles every other repetition: the times swing, each pair's ratio does not */
    double num[7], den[7];
    for (int i = 0; i < 7; ++i) {
        const double load = i % 2 ? 2.0 : 1.0;
        num[i] = 3.0 * load, den[i] = 1.5 * load;
    }
    num[6] = 100.0; /* one outlier falls out of the median */
    assert_true(qtool_bench_paired_ratio(num, den, 7) == 2.0);
    assert_true(qtool_bench_paired_ratio(num, den, 0) == 0.0);
    /* more than 64 pairs: the first 64 count */
    double a[70], b[70];
    for (int i = 0; i < 70; ++i)
        a[i] = i < 64 ? 1.0 : 9.0, b[i] = 1.0;
    assert_true(qtool_bench_paired_ratio(a, b, 70) == 1.0);
}

static void test_read_u64(void **state)
{
    (void)state;
    uint8_t buf[21];
    for (size_t i = 0; i < sizeof buf; ++i)
        buf[i] = (uint8_t)(i + 1);
    uint64_t w0, w1;
    memcpy(&w0, buf, 8), memcpy(&w1, buf + 8, 8);
    /* two whole words; the 5 bytes after them are not read */
    assert_true(qtool_bench_read_u64(buf, sizeof buf) == w0 + w1);
    assert_true(qtool_bench_read_u64(buf, 7) == 0);
    assert_true(qtool_bench_read_u64(buf, 8) == w0);
}

static void test_cloth(void **state)
{
    (void)state;
    qtool_bench_cloth s;
    memset(&s, 0, sizeof s);
    assert_int_equal(qtool_bench_cloth_make(&s, 2), 0);
    assert_int_equal(s.nv, CLOTH_G * CLOTH_G);
    assert_int_equal(s.ntri, 2 * (CLOTH_G - 1) * (CLOTH_G - 1));
    assert_int_equal(s.ncv, CLOTH_CG * CLOTH_CG);
    assert_int_equal(s.nct, 2 * (CLOTH_CG - 1) * (CLOTH_CG - 1));
    static qibl_q16_t pos[CLOTH_G * CLOTH_G][3], gp[CLOTH_LOCAL_MAX][3];
    static int32_t nrm[CLOTH_G * CLOTH_G][3];
    assert_int_equal(qtool_bench_cloth_frame(&s, 1, pos, nrm), 0);
    for (int v = 0; v < s.nv; ++v) { /* unit normals in Q2.30, scaled by 0.999 */
        const double l = ((double)nrm[v][0] * nrm[v][0] + (double)nrm[v][1] * nrm[v][1] +
                          (double)nrm[v][2] * nrm[v][2]) / (1073741824.0 * 1073741824.0);
        assert_true(l > 0.997 && l < 0.999);
    }
    /* the whole grid as the window: no coarse triangle left, every full one, every vertex */
    assert_int_equal(qtool_bench_cloth_rings(&s, CLOTH_G), 0);
    for (int v = 0; v < s.nv; v += 97) {
        assert_int_equal(s.nring[v], s.ntri);
        assert_int_equal(s.nrv[v], s.nv);
    }
    /* the two-ring: indices within what gather hands the rasterizer, which is the receiver's own */
    assert_int_equal(qtool_bench_cloth_rings(&s, 2), 0);
    for (int v = 0; v < s.nv; ++v) {
        const uint32_t nl = qtool_bench_cloth_gather(&s, (const qibl_q16_t(*)[3])pos, v, 1, gp);
        assert_int_equal(nl, (uint32_t)(s.ncv + s.nrv[v]));
        assert_true(nl <= CLOTH_LOCAL_MAX);
        int own = 0;
        for (uint32_t k = (uint32_t)s.ncv; k < nl; ++k)
            own |= memcmp(gp[k], pos[v], sizeof pos[v]) == 0;
        assert_true(own);
        const uint32_t(*ring)[3] = s.ringf + s.ring_off[v];
        for (int t = 0; t < s.nring[v]; ++t)
            assert_true(ring[t][0] < nl && ring[t][1] < nl && ring[t][2] < nl);
    }
    qtool_bench_cloth_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_median_min),
        cmocka_unit_test(test_paired_ratio),
        cmocka_unit_test(test_read_u64),
        cmocka_unit_test(test_cloth),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
