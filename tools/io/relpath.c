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
