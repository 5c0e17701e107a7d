/* io/errf.c - qtool_errf and qtool_errf_at (tools/qtool.h): the tools' one error formatter; qtool_status_str. */
#include "qtool.h"
#include "qibl/soft.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

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

int qtool_verrf_at(char *err, size_t errlen, const char *name, long line, const char *fmt, va_list ap)
{
    if (!err || !errlen)
        return -1;
    size_t o = 0;
    if (name) {
        if (line > 0)
            snprintf(err, errlen, "%s:%ld: ", name, line);
        else
            snprintf(err, errlen, "%s: ", name);
        o = strlen(err);
    }
    if (o < errlen)
        vsnprintf(err + o, errlen - o, fmt, ap);
    return -1;
}

int qtool_errf_at(char *err, size_t errlen, const char *name, long line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    qtool_verrf_at(err, errlen, name, line, fmt, ap);
    va_end(ap);
    return -1;
}

const char *qtool_status_str(qibl_status_t st)
{
    return st == QTOOL_E_NOMEM ? "out of memory" : qibl_soft_status_str(st);
}
