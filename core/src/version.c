/*
 * version.c - the library's version and configuration identity, as this build compiled them.
 */
#include "qibl/version.h"

const char *qibl_version(void)
{
    return QIBL_VERSION_STRING;
}

uint32_t qibl_config_id(void)
{
    return QIBL_CONFIG_ID;
}

qibl_status_t qibl_check_config(uint32_t caller_id)
{
    return caller_id == QIBL_CONFIG_ID ? QIBL_OK : QIBL_E_CONFIG_MISMATCH;
}
