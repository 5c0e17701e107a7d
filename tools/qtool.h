/*
 * tools/qtool.h - what every hosted tools library shares: one pi, one error formatter.
 * (The core has no floating point; these are for tools/ only.)
 */
#ifndef QTOOL_QTOOL_H
#define QTOOL_QTOOL_H

#include "qibl/status.h"

#include <stdarg.h>
#include <stddef.h>

#define QTOOL_PI 3.14159265358979323846

/* QTOOL_NODISCARD: on every tools-library function that returns a status enum (qibl_status_t,
 * qtool_transfer_status), as QIBL_NODISCARD (qibl/status.h) is on the core's: dropping the status is
 * a warning under GCC and Clang. */
#ifndef QTOOL_NODISCARD
#if defined(__GNUC__) || defined(__clang__)
#define QTOOL_NODISCARD __attribute__((warn_unused_result))
#else
#define QTOOL_NODISCARD
#endif
#endif

/* QTOOL_E_NOMEM: a tools library ran out of memory, where its callers take a qibl_status_t (the core
 * never allocates, so it has no such status). The last value of the backend range, which no
 * backend uses; qtool_status_str names it. */
#define QTOOL_E_NOMEM ((qibl_status_t)(QIBL_STATUS_BACKEND_END - 1))

/* A status's message: "out of memory" for QTOOL_E_NOMEM, else qibl_soft_status_str's (the core's
 * and platform/soft's messages). */
const char *qtool_status_str(qibl_status_t st);

/* Formats a message into err (errlen bytes, always terminated; err NULL or errlen 0: nothing is
 * written) and returns -1, so a reader's error path is one line: `return qtool_errf(err, n, ...)`. */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
int qtool_errf(char *err, size_t errlen, const char *fmt, ...);

/* As qtool_errf, prefixed by where the fault is: "name:line: message" (line > 0), "name: message"
 * (line <= 0) or the bare message (name NULL), so each reader names its input one way. */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 5, 6)))
#endif
int qtool_errf_at(char *err, size_t errlen, const char *name, long line, const char *fmt, ...);

/* qtool_errf_at taking a va_list, for a reader whose own formatter carries its state. */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 5, 0)))
#endif
int qtool_verrf_at(char *err, size_t errlen, const char *name, long line, const char *fmt, va_list ap);

#endif
