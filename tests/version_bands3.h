/*
 * version_bands3.h - what tests/version_bands3.c (built with -DQIBL_SH_MAX_BANDS=3) exports to
 * tests/version_test.c; plain types only, so both configurations agree on these declarations.
 */
#ifndef QTOOL_TESTS_VERSION_BANDS3_H
#define QTOOL_TESTS_VERSION_BANDS3_H

#include <stddef.h>
#include <stdint.h>
#include "qibl/status.h"

qibl_status_t version_bands3_init_check(void); /* qibl_init_check() as that TU sees it */
uint32_t version_bands3_config_id(void);       /* its QIBL_CONFIG_ID */
size_t version_bands3_shlight_size(void);      /* its sizeof(qibl_shlight_t) */

#endif
