/*
 * io/file.c - whole-file reading shared by the readers and the CLI.
 */
#include "io/file.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* Whole file into a malloc'ed buffer; NULL with errno set on failure. */
uint8_t *qibl_io_read_all(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, len = 0;
    uint8_t *buf = malloc(cap);
    while (buf) {
        len += fread(buf + len, 1, cap - len, f);
        if (len < cap)
            break;
        uint8_t *bigger = cap > SIZE_MAX / 2 ? NULL : realloc(buf, cap * 2);
        if (!bigger) {
            free(buf);
            buf = NULL;
            errno = ENOMEM;
            break;
        }
        buf = bigger;
        cap *= 2;
    }
    int e = errno;
    if (buf && ferror(f)) {
        free(buf);
        buf = NULL;
        e = EIO;
    }
    fclose(f);
    errno = e;
    *n = len;
    return buf;
}
