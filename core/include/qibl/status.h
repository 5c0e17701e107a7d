/*
 * qibl/status.h - the one error type of qibl.
 *
 * Every core function that can fail returns qibl_status_t: 0 is success and every other value names
 * one kind of bad input. A call that fails writes nothing to its outputs unless its header says
 * exactly what it writes.
 */
#ifndef QIBL_STATUS_H
#define QIBL_STATUS_H

typedef enum qibl_status {
    QIBL_OK = 0,
    QIBL_E_NULL_POINTER,   /* a required pointer argument was NULL */
    QIBL_E_ZERO_VECTOR,    /* a direction was (0, 0, 0): it has no direction */
    QIBL_E_BAD_BANDS,      /* SH band count outside 1..QIBL_SH_MAX_BANDS */
    QIBL_E_DIV_BY_ZERO,    /* a divisor (or the argument of a reciprocal) was zero */
    QIBL_E_RANGE,          /* the exact result does not fit the output format */
    QIBL_STATUS_COUNT      /* number of status values; not a status */
} qibl_status_t;

/* A short, constant, English description of s ("ok", "null pointer argument", ...). Never NULL:
 * values outside the enum give "unknown status". */
const char *qibl_status_str(qibl_status_t s);

#endif /* QIBL_STATUS_H */
