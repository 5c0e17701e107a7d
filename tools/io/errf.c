/* io/errf.c - qtool_errf (tools/qtool.h): the tools' one error formatter. */
#include "qtool.h"

#include <stdarg.h>
#include <stdio.h>

int qtool_errf(char *err, size_t errlen, const char *fmt, ...)
{
    if (err && errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return -1;
}
