/*
 * fuzz/fuzz.h - what the libFuzzer targets share: a reader that takes parameters from the front of
 * the fuzz input (zeros once it runs out, so every input is usable) and FUZZ_CHECK, which reports a
 * broken invariant and aborts (libFuzzer then keeps the input as a crash).
 */
#ifndef QTOOL_FUZZ_H
#define QTOOL_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_CHECK(cond)                                                                   \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: invariant broken: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                       \
        }                                                                                  \
    } while (0)

typedef struct fuzz_in {
    const uint8_t *p;
    size_t n;
} fuzz_in;

static inline uint8_t fuzz_u8(fuzz_in *in)
{
    if (in->n == 0)
        return 0;
    in->n--;
    return *in->p++;
}

static inline uint32_t fuzz_u32(fuzz_in *in)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
        v |= (uint32_t)fuzz_u8(in) << (8 * i);
    return v;
}

static inline uint16_t fuzz_u16(fuzz_in *in)
{
    uint16_t lo = fuzz_u8(in);
    return (uint16_t)(lo | (uint16_t)(fuzz_u8(in) << 8));
}

/* one-line error text: non-empty, terminated, no newline (what every reader promises).
 * Built with -DFUZZ_LENIENT_TEXT the text checks pass, to look past a known text finding. */
static inline int fuzz_one_line(const char *err, size_t cap)
{
#ifdef FUZZ_LENIENT_TEXT
    (void)err, (void)cap;
    return 1;
#endif
    size_t i = 0;
    while (i < cap && err[i] && err[i] != '\n')
        ++i;
    return i > 0 && i < cap && err[i] == '\0';
}

#endif
