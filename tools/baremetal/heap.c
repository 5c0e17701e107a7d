/*
 * baremetal/heap.c - malloc, calloc, realloc and free of the golden cases (run.sh renames the
 * cases' references to bm_malloc..., with objcopy, so the C library's own calls stay as they are) to
 * count the bytes live and the peak since the last reset: what a case needed of caller-owned
 * memory (maps, workspaces, buffers). An 8-byte header holds each block's size.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "heap.h"

void *bm_malloc(size_t n);
void *bm_calloc(size_t a, size_t b);
void *bm_realloc(void *p, size_t n);
void bm_free(void *p);

enum { HDR = 8 };
static size_t live, peak;

static void *note(uint8_t *h, size_t n)
{
    if (h == NULL)
        return NULL;
    memcpy(h, &n, sizeof n);
    live += n;
    if (live > peak)
        peak = live;
    return h + HDR;
}

static size_t size_of(void *p)
{
    size_t n;
    memcpy(&n, (uint8_t *)p - HDR, sizeof n);
    return n;
}

void *bm_malloc(size_t n)
{
    return n > SIZE_MAX - HDR ? NULL : note(malloc(n + HDR), n);
}

void *bm_calloc(size_t a, size_t b)
{
    if (b != 0 && a > (SIZE_MAX - HDR) / b)
        return NULL;
    void *p = bm_malloc(a * b);
    if (p != NULL)
        memset(p, 0, a * b);
    return p;
}

void bm_free(void *p)
{
    if (p == NULL)
        return;
    live -= size_of(p);
    free((uint8_t *)p - HDR);
}

void *bm_realloc(void *p, size_t n)
{
    if (p == NULL)
        return bm_malloc(n);
    if (n > SIZE_MAX - HDR)
        return NULL;
    size_t old = size_of(p);
    uint8_t *h = realloc((uint8_t *)p - HDR, n + HDR);
    if (h == NULL)
        return NULL;
    live -= old;
    return note(h, n);
}

size_t bm_heap_live(void)
{
    return live;
}

size_t bm_heap_peak_reset(void)
{
    size_t p = peak;
    peak = live;
    return p;
}
