/*
 * io/file.h - whole-file reading shared by the readers (HDR, PFM, OBJ, PNG) and the CLI. Hosted.
 *
 * Every read follows the same order, so a hostile path costs nothing before it is recognised:
 *   1. stat the path: a directory is "is a directory", a fifo, socket or device is refused by name
 *      ("is a fifo, not a regular file") - nothing is opened that could block or never end;
 *   2. open it without blocking (O_NONBLOCK) and fstat the open file: still a regular file, the
 *      same one;
 *   3. an empty file, a file shorter than the kind's minimum, and a file larger than the kind's
 *      limit are refused from the size alone;
 *   4. the first bytes are read and the kind's magic check runs on them (1 GiB of zeros costs one
 *      small read, not 1 GB);
 *   5. only then is the whole file read, into one buffer of exactly its size.
 */
#ifndef QTOOL_IO_FILE_H
#define QTOOL_IO_FILE_H

#include <stddef.h>
#include <stdint.h>

/* Largest file qtool_io_read_all reads: the asset container's 32-bit file size (qibl/asset.h). */
#define QTOOL_IO_MAX_FILE_BYTES ((size_t)UINT32_MAX)
/* Largest first-bytes prefix a magic check may ask for. */
#define QTOOL_IO_MAX_HEAD_BYTES 64u

/* What one reader accepts. */
typedef struct qtool_io_kind {
    const char *what;  /* for messages: "a Radiance .hdr file" */
    size_t min_bytes;  /* shorter files are refused ("too short"), >= 1 */
    size_t max_bytes;  /* larger files are refused before anything is read */
    size_t head_bytes; /* bytes the magic check sees (<= QTOOL_IO_MAX_HEAD_BYTES; fewer if the file is shorter) */
    /* NULL if head[0 .. n) may start a file of this kind, else the reason it cannot; may be NULL */
    const char *(*magic)(const uint8_t *head, size_t n);
} qtool_io_kind;

/* Reads the regular file at path as kind allows (the steps above). 0 with *buf (malloc'ed, *n bytes,
 * the caller frees) set; or -1 with a one-line reason naming the file in err and nothing set. */
int qtool_io_load(const char *path, const qtool_io_kind *kind, uint8_t **buf, size_t *n, char *err, size_t errlen);

/* A qibl asset file (magic QIBL\r\n\x1A\n, at most QTOOL_IO_MAX_FILE_BYTES): as qtool_io_load. */
int qtool_io_read_asset(const char *path, uint8_t **buf, size_t *n, char *err, size_t errlen);

/* The whole regular file (at most QTOOL_IO_MAX_FILE_BYTES, no magic check) in a malloc'ed buffer of
 * *n bytes (the caller frees it); NULL with errno set on failure: from stat/open, EISDIR for a
 * directory, EINVAL for any other non-regular file, EFBIG above the limit, ENOMEM, EIO for a read
 * error. Prefer qtool_io_load, whose messages say more. */
uint8_t *qtool_io_read_all(const char *path, size_t *n);

#endif
