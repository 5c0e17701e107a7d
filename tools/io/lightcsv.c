/*
 * io/lightcsv.c - the `qibl lights --csv` light list, read back (see lightcsv.h). Every line is
 * copied into a bounded buffer before strtod sees it, so no read runs past the input.
 */
#include "io/lightcsv.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/file.h"

/* up to 40 bytes of s as printable text (a control byte becomes '?'), for a one-line message */
static const char *show(char *dst, size_t dn, const char *s, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; i < n && i < 40 && k + 1 < dn; ++i)
        dst[k++] = (unsigned char)s[i] < 0x20 || s[i] == 0x7f ? '?' : s[i];
    dst[k] = '\0';
    return dst;
}

/* one field ending at ',' (or at the end of the line for the last): 0, -1 not a number, -2 beyond
 * double range (an underflow reads as the tiny or zero value it is) */
static int csv_num(char **p, int last, double *out)
{
    char *s = *p, *end;
    if (*s == ',' || *s == '\0' || *s == ' ')
        return -1;
    errno = 0;
    *out = strtod(s, &end);
    if (end == s || (last ? *end != '\0' : *end != ','))
        return -1;
    if (errno == ERANGE && fabs(*out) > DBL_MIN)
        return -2;
    *p = last ? end : end + 1;
    return 0;
}

int qtool_lightcsv_parse(const char *name, const char *buf, size_t n, qibl_lightprobe_light_t **lights,
                         uint32_t *count, int32_t *rgb_exp, char *err, size_t errlen)
{
    static const char *names[10] = {"x", "y", "z", "r", "g", "b", "u0", "v0", "u1", "v1"};
    char line[QTOOL_LIGHTCSV_LINE_MAX + 2], shown[48];
    size_t cap = 0, nl = 0, pos = 0;
    double *v = NULL; /* 10 per row */
    unsigned long ln = 0;
    int rc = -1;
    if (n == 0) {
        snprintf(err, errlen, "%s: empty: want the header line '%s' (qibl lights --csv)", name, QTOOL_LIGHTCSV_HEADER);
        return -1;
    }
    while (pos < n) {
        const char *s = buf + pos, *e = memchr(s, '\n', n - pos);
        size_t len = e ? (size_t)(e - s) : n - pos;
        pos += len + (e != NULL);
        ++ln;
        if (len > 0 && s[len - 1] == '\r')
            --len;
        const char *nul = memchr(s, '\0', len);
        if (nul) { /* before the length: a NUL is what is wrong, however long the line */
            snprintf(err, errlen, "%s:%lu: a NUL byte at column %zu: not a text line", name, ln, (size_t)(nul - s) + 1);
            goto out;
        }
        if (len > QTOOL_LIGHTCSV_LINE_MAX) {
            snprintf(err, errlen, "%s:%lu: line longer than %u bytes", name, ln, QTOOL_LIGHTCSV_LINE_MAX);
            goto out;
        }
        memcpy(line, s, len);
        line[len] = '\0';
        if (ln == 1) {
            if (strcmp(line, QTOOL_LIGHTCSV_HEADER) != 0) {
                snprintf(err, errlen, "%s:1: header '%s' is not '%s' (qibl lights --csv)", name,
                         show(shown, sizeof shown, line, len), QTOOL_LIGHTCSV_HEADER);
                goto out;
            }
            continue;
        }
        if (len == 0)
            continue; /* an empty line */
        if (nl >= QTOOL_LIGHTCSV_MAX) {
            snprintf(err, errlen, "%s:%lu: more than %u lights", name, ln, QTOOL_LIGHTCSV_MAX);
            goto out;
        }
        if (nl == cap) {
            size_t nc = cap ? 2 * cap : 64;
            double *nv = realloc(v, sizeof *v * 10 * nc);
            if (!nv) {
                snprintf(err, errlen, "%s: out of memory", name);
                goto out;
            }
            v = nv, cap = nc;
        }
        double *r = v + 10 * nl;
        char *p = line;
        for (int k = 0; k < 10; ++k) {
            char *f = p;
            if (k > 0 && *f == '\0') {
                snprintf(err, errlen, "%s:%lu: %d columns, want 10 (" QTOOL_LIGHTCSV_HEADER ")", name, ln, k);
                goto out;
            }
            int c = csv_num(&p, k == 9, &r[k]);
            size_t fl = strcspn(f, ",");
            if (c == -2) {
                snprintf(err, errlen, "%s:%lu: %s '%s' is beyond double range", name, ln, names[k],
                         show(shown, sizeof shown, f, fl));
                goto out;
            }
            if (c != 0) {
                if (k < 9 && f[fl] == '\0') {
                    snprintf(err, errlen, "%s:%lu: %d columns, want 10 (" QTOOL_LIGHTCSV_HEADER ")", name, ln, k + 1);
                    goto out;
                }
                snprintf(err, errlen, "%s:%lu: %s '%s' is not a number%s", name, ln, names[k],
                         show(shown, sizeof shown, f, fl), k == 9 && f[fl] == ',' ? " (more than 10 columns)" : "");
                goto out;
            }
            if (!isfinite(r[k])) {
                snprintf(err, errlen, "%s:%lu: %s is %g: not finite", name, ln, names[k], r[k]);
                goto out;
            }
            if (k >= 3 && r[k] < 0) {
                snprintf(err, errlen, "%s:%lu: %s is %g: negative", name, ln, names[k], r[k]);
                goto out;
            }
            if (k >= 6 && (r[k] != floor(r[k]) || r[k] > 4294967295.0)) {
                snprintf(err, errlen, "%s:%lu: %s is %g: not a pixel index", name, ln, names[k], r[k]);
                goto out;
            }
            if (k >= 3 && k < 6 && r[k] > 1e30) {
                snprintf(err, errlen, "%s:%lu: %s is %g: above 1e30", name, ln, names[k], r[k]);
                goto out;
            }
        }
        if (r[0] == 0 && r[1] == 0 && r[2] == 0) {
            snprintf(err, errlen, "%s:%lu: direction 0,0,0 is not a direction", name, ln);
            goto out;
        }
        ++nl;
    }
    double mx = 0;
    for (size_t i = 0; i < nl; ++i)
        for (int c = 3; c < 6; ++c)
            mx = fmax(mx, v[10 * i + (size_t)c]);
    int e = 0;
    if (mx > 0)
        (void)frexp(mx, &e), e -= 30; /* the largest channel below 2^30 */
    qibl_lightprobe_light_t *L = malloc(sizeof *L * (nl ? nl : 1));
    if (!L) {
        snprintf(err, errlen, "%s: out of memory", name);
        goto out;
    }
    for (size_t i = 0; i < nl; ++i) {
        const double *r = v + 10 * i;
        /* scaled by the largest component before squaring: 1e-300 squared underflows to 0 and
         * 1e200 squared overflows to inf, either of which made a zero direction */
        double m = fmax(fabs(r[0]), fmax(fabs(r[1]), fabs(r[2]))), d[3], len;
        for (int c = 0; c < 3; ++c)
            d[c] = r[c] / m; /* in [-1, 1], the largest exactly +-1 */
        len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); /* in [1, sqrt 3] */
        for (int c = 0; c < 3; ++c) {
            L[i].dir[c] = (int32_t)lrint(d[c] / len * 1073741824.0);
            L[i].rgb[c] = (int32_t)lrint(ldexp(r[3 + c], -e));
        }
        L[i].u0 = (uint32_t)r[6], L[i].v0 = (uint32_t)r[7], L[i].u1 = (uint32_t)r[8], L[i].v1 = (uint32_t)r[9];
    }
    *lights = L, *count = (uint32_t)nl, *rgb_exp = e;
    rc = 0;
out:
    free(v);
    return rc;
}

int qtool_lightcsv_read(const char *path, qibl_lightprobe_light_t **lights, uint32_t *count, int32_t *rgb_exp,
                        char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a light list (qibl lights --csv)", 1, QTOOL_LIGHTCSV_MAX_BYTES, 0, NULL};
    uint8_t *b;
    size_t n;
    struct stat st;
    if (stat(path, &st) != 0) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    if (S_ISREG(st.st_mode) && st.st_size == 0) /* the parser's own message */
        return qtool_lightcsv_parse(path, "", 0, lights, count, rgb_exp, err, errlen);
    if (qtool_io_load(path, &kind, &b, &n, err, errlen) != 0)
        return -1;
    int rc = qtool_lightcsv_parse(path, (const char *)b, n, lights, count, rgb_exp, err, errlen);
    free(b);
    return rc;
}
