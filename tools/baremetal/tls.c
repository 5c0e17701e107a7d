/*
 * baremetal/tls.c - the start-up check that picolibc's thread-local storage is set up (issue 24,
 * class 9): picolibc keeps errno in TLS, so a crt that never calls _set_tls leaves the thread
 * pointer at 0 and a failed allocation stores ENOMEM at address 0 + the TLS offset (8 on ARM: the
 * NMI vector of an MPS2 board, in writable RAM). The runner forces a failed malloc first thing and
 * refuses to go on unless errno was set, lives inside the TLS block the linker script reserves
 * (__tls_base .. __tls_end) and, on Cortex-M, the vector table is byte for byte what it was (the
 * Game Boy Advance, ARMv4T, has its vectors in the BIOS: no table to compare).
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "semi.h"
#include "tls.h"

extern char __tls_base[], __tls_end[], __heap_start[], __heap_end[];
#if defined(__ARM_ARCH_PROFILE) && __ARM_ARCH_PROFILE == 'M' /* crt_cm.c's vector table */
#define BM_VECTORS 1
extern char __vectors_start[];
enum { VECTOR_BYTES = 7 * 4 }; /* the entries crt_cm.c installs */
#else
#define BM_VECTORS 0
#endif

static int fail(const char *why)
{
    bm_puts("baremetal: FAIL: TLS: "), bm_puts(why), bm_puts("\n");
    return 1;
}

int bm_tls_check(void)
{
#if BM_VECTORS
    uint8_t vectors[VECTOR_BYTES];
    memcpy(vectors, __vectors_start, sizeof vectors);
#endif
    /* more than the whole heap: picolibc's malloc must fail and say ENOMEM through errno */
    volatile size_t huge = (size_t)(__heap_end - __heap_start) + 4096u;
    errno = 0;
    void *p = malloc(huge);
    const int e = errno;
    if (p != NULL) {
        free(p);
        return fail("an allocation larger than the heap succeeded");
    }
    if (e != ENOMEM)
        return fail("a failed malloc did not set errno to ENOMEM");
    const char *at = (const char *)&errno;
    if (at < __tls_base || at + sizeof errno > __tls_end)
        return fail("errno lies outside the TLS block (the thread pointer was never set: _set_tls)");
#if BM_VECTORS
    if (memcmp(vectors, __vectors_start, sizeof vectors) != 0)
        return fail("the failed malloc wrote into the vector table");
#endif
    errno = 0;
    bm_puts("tls ok: a failed malloc set errno inside the TLS block\n");
    return 0;
}
