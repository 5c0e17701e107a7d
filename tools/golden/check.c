/*
 * golden/check.c - golden groups checked through io/golden.h (golden/check.h).
 */
#include "golden/check.h"

#include <stdio.h>

#include "golden/cases.h"
#include "io/golden.h"

static int emit(void *user, const char *name, const char *hex, uint64_t n)
{
    (void)user, (void)n;
    return qtool_golden_check(name, hex);
}

static void error(void *user, const char *name, const char *what)
{
    (void)user;
    fprintf(stderr, "golden %s: ERROR %s\n", name, what);
}

int qtool_goldens_check(const char *group)
{
    qtool_goldens_sink_t s = {.emit = emit, .error = error, .user = NULL};
    int bad = qtool_goldens_run(group, &s);
    if (bad < 0)
        fprintf(stderr, "golden: no group \"%s\"\n", group);
    return bad;
}
