/*
 * io/relpath.c - names inside a scene file resolved against its folder (io/relpath.h).
 */
#include "io/relpath.h"

#include <stdio.h>
#include <string.h>

int qtool_io_relpath(const char *dir, const char *rel, char *out, size_t cap, const char **why)
{
    const char *colon = strchr(rel, ':'), *slash = strchr(rel, '/');
    if (!rel[0])
        *why = "empty";
    else if (colon && (!slash || colon < slash))
        *why = "a URI scheme";
    else if (rel[0] == '/')
        *why = "an absolute path";
    else if (strchr(rel, '\\'))
        *why = "a backslash";
    else if (strpbrk(rel, "\x01\x02\x03\x04\x05\x06\x07\x08\x09\x0a\x0b\x0c\x0d\x0e\x0f\x10\x11\x12\x13\x14\x15\x16"
                          "\x17\x18\x19\x1a\x1b\x1c\x1d\x1e\x1f\x7f"))
        *why = "a control character";
    else
        *why = NULL;
    for (const char *p = rel; !*why && *p;) {
        size_t l = strcspn(p, "/");
        if (l == 2 && p[0] == '.' && p[1] == '.')
            *why = "a '..'";
        p += l;
        if (*p)
            ++p;
    }
    if (*why)
        return -1;
    int w = snprintf(out, cap, "%s/%s", dir, rel);
    if (w < 0 || (size_t)w >= cap) {
        *why = "too long";
        return -1;
    }
    return 0;
}

int qtool_io_dirname(const char *path, char *out, size_t cap)
{
    const char *sl = strrchr(path, '/');
    int w;
    if (!sl)
        w = snprintf(out, cap, ".");
    else if (sl == path)
        w = snprintf(out, cap, "/");
    else
        w = snprintf(out, cap, "%.*s", (int)(sl - path), path);
    return w < 0 || (size_t)w >= cap ? -1 : 0;
}
