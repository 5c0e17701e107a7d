/*
 * fuzz_pfm.c - libFuzzer target: the PFM reader (tools/io/pfm.c, qtool_pfm_decode).
 *
 * Invariants: a failure leaves the outputs untouched and gives a one-line reason; a success gives
 * 1 <= w, h, channels 1 or 3 (from the magic PF / Pf), and channels w h samples that are the file's
 * own bit patterns, rows flipped to top first, in the byte order the scale's sign names.
 */
#include <string.h>

#include "fuzz.h"
#include "io/pfm.h"

static int is_ws(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    int w = -7, h = -7, ch = -7;
    float *px = (float *)&err;
    memset(err, 0, sizeof err);
    int rc = qtool_pfm_decode(data, size, &w, &h, &ch, &px, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && w == -7 && h == -7 && ch == -7 && px == (float *)&err);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(w >= 1 && h >= 1 && size >= 2 && ch == (data[1] == 'F' ? 3 : 1));
    size_t row = (size_t)w * (size_t)ch, n = row * (size_t)h;
    FUZZ_CHECK(size >= 4 * n);
    /* where the reader's header ends: magic, three tokens, one whitespace byte (pfm.c) */
    size_t pos = 2, tok[3] = {0, 0, 0};
    for (int t = 0; t < 3; ++t) {
        while (pos < size && is_ws(data[pos]))
            ++pos;
        tok[t] = pos;
        while (pos < size && !is_ws(data[pos]))
            ++pos;
    }
    ++pos;
    FUZZ_CHECK(pos <= size && size - pos >= 4 * n);
    /* the header is text: an accepted number holds no control byte (NUL, \v, \f ...) */
#ifndef FUZZ_LENIENT_TEXT
    for (size_t i = tok[0]; i < pos - 1; ++i)
        FUZZ_CHECK(is_ws(data[i]) || (data[i] >= 0x20 && data[i] < 0x7F));
#endif
    /* the reader's own reading of the scale's sign (strtod, which skips \v and \f) */
    char scale[64];
    size_t sl = 0;
    for (size_t i = tok[2]; i < pos - 1 && sl < 63; ++i)
        scale[sl++] = (char)data[i];
    scale[sl] = '\0';
    int little = strtod(scale, NULL) < 0;
    for (size_t y = 0; y < (size_t)h; ++y)
        for (size_t i = 0; i < row; ++i) {
            const uint8_t *b = data + pos + 4 * (y * row + i);
            uint32_t want = little ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24
                                   : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
            uint32_t got;
            memcpy(&got, &px[((size_t)h - 1 - y) * row + i], 4);
            FUZZ_CHECK(got == want);
        }
    free(px);
    return 0;
}
