/*
 * io/golden.h - golden hashes for tests: a case's output bytes are hashed (io/sha256.h) and the
 * digest compared with fixtures/golden/<name>.sha256 (one line: 64 lowercase hex digits).
 *
 * Environment:
 *   QIBL_ROOT            the repository root the fixtures path is relative to (default ".";
 *                        `make test` runs the suites from the root).
 *   QIBL_UPDATE_GOLDEN=1 (re)write each checked file with the actual digest instead of comparing,
 *                        and pass. Use once when a case is added or its output changes on
 *                        purpose; review and commit the changed .sha256 files with the change.
 *                        Example: QIBL_UPDATE_GOLDEN=1 build/tests/soft_test
 */
#ifndef QTOOL_IO_GOLDEN_H
#define QTOOL_IO_GOLDEN_H

#include <stddef.h>

/* Compares hex (64 lowercase hex digits) with fixtures/golden/<name>.sha256. name is made of
 * letters, digits, '_', '-' and '.', and does not start with '.'. Returns 0 when equal (or after
 * rewriting the file under QIBL_UPDATE_GOLDEN=1); -1 otherwise, after printing one line to stderr
 * naming the case, the file, the expected and the actual hash (or why the file could not be read
 * or written). */
int qtool_golden_check(const char *name, const char *hex);

/* The same for n bytes at data: hashes them and checks the digest. */
int qtool_golden_check_bytes(const char *name, const void *data, size_t n);

#endif
