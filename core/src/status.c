/*
 * status.c - names of qibl_status_t values.
 */
#include "qibl/status.h"

const char *qibl_status_str(qibl_status_t s)
{
    /* A switch rather than a table indexed by s: no out-of-range read for a forged value. */
    switch (s) {
    case QIBL_OK:             return "ok";
    case QIBL_E_NULL_POINTER: return "null pointer argument";
    case QIBL_E_ZERO_VECTOR:  return "zero vector has no direction";
    case QIBL_E_BAD_BANDS:    return "SH band count out of range";
    case QIBL_E_DIV_BY_ZERO:  return "division by zero";
    case QIBL_E_RANGE:        return "result out of range of the output format";
    case QIBL_STATUS_COUNT:   break;
    }
    return "unknown status";
}
