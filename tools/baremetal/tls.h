/*
 * baremetal/tls.h - the start-up check of picolibc's thread-local storage (tls.c).
 */
#ifndef QTOOL_BM_TLS_H
#define QTOOL_BM_TLS_H

/* Forces a failed malloc; 0 when errno came back ENOMEM from inside the TLS block (and, on
 * Cortex-M, the vector table is unchanged), else 1 after a "baremetal: FAIL: TLS: ..." line. */
int bm_tls_check(void);

#endif
