/*
 * io/atomic.h - the one way the tools write an output file: a temporary file created exclusively
 * next to the destination, written, flushed, fsync'ed and renamed over it. Hosted (POSIX 2008).
 *
 * Guarantees:
 *  - the temporary file is new: open(O_CREAT | O_EXCL | O_NOFOLLOW) with a random name in the
 *    destination's directory, so a symbolic link or file planted at a predictable name is never
 *    written through, and two writers to the same path never share a temporary file (each renames
 *    a complete file; the last rename wins);
 *  - permissions are those of any newly created file (0666 less the umask);
 *  - a destination that exists and is not a regular file (symbolic link, directory, FIFO, device,
 *    socket) is refused with a message naming what it is, before anything is written and again
 *    just before the rename; the destination is never followed or replaced;
 *  - on any failure the temporary file is removed and the destination is left as it was.
 * A process killed mid-write can leave its temporary file (".NAME.XXXXXXXXXXXXXXXX.tmp") behind,
 * never a truncated destination.
 *
 * Usage (streaming):
 *   qtool_io_atomic a;
 *   if (qtool_io_atomic_open(&a, path, err, errlen) != 0) return -1;
 *   fwrite(..., a.f);                        // any stdio writes
 *   if (bad) { qtool_io_atomic_abort(&a); return -1; }
 *   return qtool_io_atomic_commit(&a, err, errlen);
 */
#ifndef QTOOL_IO_ATOMIC_H
#define QTOOL_IO_ATOMIC_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct qtool_io_atomic {
    FILE *f;      /* the temporary file, open for writing between open and commit/abort */
    char *path;   /* copy of the destination */
    char *tmp;    /* the temporary file's name */
    int no_fsync; /* set to 1 after open to skip the fsyncs (scratch output only) */
} qtool_io_atomic;

/* Checks that path does not exist or is a regular file (lstat: never follows a link). 0, or -1
 * with "PATH: refusing to replace a symbolic link" (directory, FIFO, device, socket, ...) or the
 * lstat error in err. */
int qtool_io_check_replaceable(const char *path, char *err, size_t errlen);

/* Checks the destination and creates the temporary file. 0, or -1 with a one-line reason naming
 * path in err; nothing is created and *a needs no cleanup on failure. */
int qtool_io_atomic_open(qtool_io_atomic *a, const char *path, char *err, size_t errlen);

/* Flushes, fsyncs, closes and renames the temporary file over the destination (then fsyncs the
 * directory, best effort). Fails if any earlier write on a->f failed. 0, or -1 with a one-line
 * reason naming the destination; on failure the temporary file is removed and the destination is
 * untouched. Releases *a either way. */
int qtool_io_atomic_commit(qtool_io_atomic *a, char *err, size_t errlen);

/* Closes and removes the temporary file (the destination is untouched); releases *a. */
void qtool_io_atomic_abort(qtool_io_atomic *a);

/* open + one write of n bytes + commit. */
int qtool_io_write_atomic(const char *path, const void *data, size_t n, char *err, size_t errlen);

/* The last step of a *_write over an encoder that mallocs its bytes and fails only when out of
 * memory: enc is what the encoder returned (0, or -1 with b unset); on 0 the n bytes at b are
 * written atomically and b is freed. 0, or -1 with err naming path. */
int qtool_io_write_encoded(const char *path, int enc, uint8_t *b, size_t n, char *err, size_t errlen);

#endif
