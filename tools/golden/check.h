/*
 * golden/check.h - the golden cases (golden/cases.h) checked the way the CMocka suites check
 * goldens: each case through io/golden.h, so QIBL_ROOT and QIBL_UPDATE_GOLDEN=1 work as for every
 * other golden. Hosted (POSIX through io/golden.c); the plain runner does not use it.
 */
#ifndef QTOOL_GOLDEN_CHECK_H
#define QTOOL_GOLDEN_CHECK_H

/* Runs the group called name and checks every case. Returns the number of failed cases (each
 * named on stderr), or -1 if there is no such group. */
int qtool_goldens_check(const char *group);

#endif
