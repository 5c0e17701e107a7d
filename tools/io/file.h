/*
 * io/file.h - whole-file reading shared by the readers (PFM, OBJ, PNG) and the CLI. Hosted.
 */
#ifndef QIBL_IO_FILE_H
#define QIBL_IO_FILE_H

#include <stddef.h>
#include <stdint.h>

/* The whole file at path in a malloc'ed buffer of *n bytes (the caller frees it); NULL with errno
 * set (from fopen, ENOMEM, or EIO for a read error) on failure. */
uint8_t *qibl_io_read_all(const char *path, size_t *n);

#endif
