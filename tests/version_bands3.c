/*
 * version_bands3.c - a translation unit the Makefile compiles with -DQIBL_SH_MAX_BANDS=3 and links
 * into version_test against the default library: the application of issue 11 that overflowed a
 * stack buffer, reduced to what it sees of qibl.
 */
#include "qibl.h"
#include "version_bands3.h"

#if QIBL_SH_MAX_BANDS != 3
#error "version_bands3.c must be compiled with -DQIBL_SH_MAX_BANDS=3 (see the Makefile)"
#endif

qibl_status_t version_bands3_init_check(void)
{
    return qibl_init_check();
}

uint32_t version_bands3_config_id(void)
{
    return QIBL_CONFIG_ID;
}

size_t version_bands3_shlight_size(void)
{
    return sizeof(qibl_shlight_t);
}
