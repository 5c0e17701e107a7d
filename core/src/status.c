/*
 * status.c - names of qibl_status_t values, made from status.h's QIBL_STATUS_LIST.
 */
#include "qibl/status.h"

const char *qibl_status_str(qibl_status_t s)
{
    /* A switch rather than a table indexed by s: no out-of-range read for a forged value. */
    switch (s) {
#define QIBL_STATUS_CASE_(name, message) case name: return message;
    QIBL_STATUS_LIST(QIBL_STATUS_CASE_)
#undef QIBL_STATUS_CASE_
    case QIBL_STATUS_COUNT:   break;
    case QIBL_STATUS_SOFT_BASE: case QIBL_STATUS_GLES2_BASE: case QIBL_STATUS_BACKEND_END: break;
    }
    /* unsigned compare: no assumption about the enum's signedness */
    if ((unsigned)s >= (unsigned)QIBL_STATUS_SOFT_BASE && (unsigned)s < (unsigned)QIBL_STATUS_BACKEND_END)
        return "platform backend status";
    return "unknown status";
}
