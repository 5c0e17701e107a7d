/*
 * srgbe_exhaustive.c - `make check-exhaustive`: every one of the 2^32 sRGBE codes, decoded by the
 * core, against the double-precision reference (tools/ref/srgbe_ref.c). Plain C + pthreads (no
 * CMocka), split across all cores; CI runs it, `make test` only samples (tests/srgbe_test.c).
 *
 * For every code:
 *   - qibl_srgbe_decode_f32_n (in rows of 256 codes) and qibl_srgbe_decode_f32 give the reference's
 *     binary32 bits in every channel, and the saturation status exactly when the reference saturates;
 *   - qibl_srgbe_decode_q16_n gives the reference's Q16.16 (round half up, saturated);
 *   - a canonical code (largest |2X - 255| in 129..253) re-encodes to itself from its binary32
 *     decode (qibl_srgbe_encode_f32_n).
 * Usage: srgbe_exhaustive [threads]   (default: every online core). Exit status 1 on any mismatch.
 */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "qibl/srgbe.h"
#include "ref/srgbe_ref.h"

static uint32_t ref_f32[256][256]; /* [E][X] */
static unsigned char ref_f32_sat[256][256];
static int32_t ref_q16[256][256];
static unsigned char ref_q16_sat[256][256];
static unsigned char canon_m[256]; /* |2X - 255| */

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static unsigned next_unit;      /* units are (E, B) pairs: 65536 of them, 65536 codes each */
static unsigned long long n_bad, n_canon, n_sat_f32, n_sat_q16;

static void mismatch(const char *what, const uint8_t c[4], int ch, long long got, long long want)
{
    pthread_mutex_lock(&lock);
    if (n_bad < 20)
        fprintf(stderr, "srgbe_exhaustive: MISMATCH %s code %02x%02x%02x%02x channel %d: got %llx, reference %llx\n",
                what, c[0], c[1], c[2], c[3], ch, (unsigned long long)got, (unsigned long long)want);
    n_bad++;
    pthread_mutex_unlock(&lock);
}

static void *worker(void *arg)
{
    (void)arg;
    uint8_t codes[256 * 4], back[256 * 4];
    uint32_t f32[256 * 3];
    int32_t q16[256 * 3];
    unsigned long long canon = 0, satf = 0, satq = 0;
    for (;;) {
        pthread_mutex_lock(&lock);
        unsigned unit = next_unit < 65536u ? next_unit++ : 65536u;
        pthread_mutex_unlock(&lock);
        if (unit >= 65536u)
            break;
        unsigned E = unit >> 8, B = unit & 255u;
        for (unsigned G = 0; G < 256; ++G) {
            for (unsigned R = 0; R < 256; ++R) {
                codes[4 * R + 0] = (uint8_t)R;
                codes[4 * R + 1] = (uint8_t)G;
                codes[4 * R + 2] = (uint8_t)B;
                codes[4 * R + 3] = (uint8_t)E;
            }
            int want_satf_row = 0, want_satq_row = 0;
            qibl_status_t sf = qibl_srgbe_decode_f32_n(codes, 256, f32);
            qibl_status_t sq = qibl_srgbe_decode_q16_n(codes, 256, q16);
            for (unsigned R = 0; R < 256; ++R) {
                const uint8_t *c = codes + 4 * R;
                uint32_t one[3];
                qibl_status_t s1 = qibl_srgbe_decode_f32(c, one);
                int want_sat = 0, want_qsat = 0;
                for (int ch = 0; ch < 3; ++ch) {
                    uint32_t w = ref_f32[E][c[ch]];
                    want_sat |= ref_f32_sat[E][c[ch]];
                    want_qsat |= ref_q16_sat[E][c[ch]];
                    if (f32[3 * R + ch] != w)
                        mismatch("decode_f32_n", c, ch, f32[3 * R + ch], w);
                    if (one[ch] != w)
                        mismatch("decode_f32", c, ch, one[ch], w);
                    if (q16[3 * R + ch] != ref_q16[E][c[ch]])
                        mismatch("decode_q16_n", c, ch, q16[3 * R + ch], ref_q16[E][c[ch]]);
                }
                if (s1 != (want_sat ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK))
                    mismatch("decode_f32 status", c, -1, s1, want_sat);
                want_satf_row |= want_sat;
                want_satq_row |= want_qsat;
                satf += (unsigned long long)want_sat;
                satq += (unsigned long long)want_qsat;
            }
            if (sf != (want_satf_row ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK))
                mismatch("decode_f32_n status", codes, -1, sf, want_satf_row);
            if (sq != (want_satq_row ? QIBL_E_SRGBE_DECODE_SAT : QIBL_OK))
                mismatch("decode_q16_n status", codes, -1, sq, want_satq_row);
            /* canonical codes come back from their binary32 decode */
            QIBL_DROP_STATUS(qibl_srgbe_encode_f32_n(f32, 256, back));
            for (unsigned R = 0; R < 256; ++R) {
                const uint8_t *c = codes + 4 * R;
                unsigned m = canon_m[c[0]];
                if (canon_m[c[1]] > m)
                    m = canon_m[c[1]];
                if (canon_m[c[2]] > m)
                    m = canon_m[c[2]];
                if (m < 129 || m > 253)
                    continue;
                ++canon;
                if (memcmp(back + 4 * R, c, 4) != 0)
                    mismatch("re-encode of canonical", c, -1,
                             (long long)((uint32_t)back[4 * R] << 24 | (uint32_t)back[4 * R + 1] << 16 |
                                         (uint32_t)back[4 * R + 2] << 8 | back[4 * R + 3]),
                             0);
            }
        }
    }
    pthread_mutex_lock(&lock);
    n_canon += canon;
    n_sat_f32 += satf;
    n_sat_q16 += satq;
    pthread_mutex_unlock(&lock);
    return NULL;
}

int main(int argc, char **argv)
{
    long nt = sysconf(_SC_NPROCESSORS_ONLN);
    if (argc > 1)
        nt = strtol(argv[1], NULL, 10);
    if (nt < 1 || nt > 256) {
        fprintf(stderr, "usage: srgbe_exhaustive [threads 1..256]\n");
        return 2;
    }
    for (unsigned E = 0; E < 256; ++E)
        for (unsigned X = 0; X < 256; ++X) {
            int s = 0, q = 0;
            ref_f32[E][X] = qtool_ref_srgbe_channel_f32(X, E, &s);
            ref_f32_sat[E][X] = (unsigned char)s;
            ref_q16[E][X] = qtool_ref_srgbe_channel_s32(X, E, 16, &q);
            ref_q16_sat[E][X] = (unsigned char)q;
        }
    for (unsigned X = 0; X < 256; ++X)
        canon_m[X] = (unsigned char)(X >= 128 ? 2 * X - 255 : 255 - 2 * X);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    pthread_t th[256];
    for (long i = 0; i < nt; ++i)
        if (pthread_create(&th[i], NULL, worker, NULL) != 0) {
            fprintf(stderr, "srgbe_exhaustive: cannot start thread %ld\n", i);
            return 1;
        }
    for (long i = 0; i < nt; ++i)
        pthread_join(th[i], NULL);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    printf("srgbe_exhaustive: 4294967296 codes on %ld threads in %.1f s: decode_f32 (bulk and one-pixel) and "
           "decode_q16 match the double reference bit for bit; %llu canonical codes re-encode to themselves; "
           "%llu codes saturate binary32, %llu saturate Q16.16; %llu mismatches\n",
           nt, secs, n_canon, n_sat_f32, n_sat_q16, n_bad);
    printf("RESULT srgbe.exhaustive_mismatches %llu\n", n_bad);
    return n_bad ? 1 : 0;
}
