/*
 * io/golden.c - golden hash files: compare, or rewrite under QIBL_UPDATE_GOLDEN=1 (io/golden.h).
 * Files are written atomically (io/atomic.h), so an interrupted update leaves no partial file.
 */
#include "io/golden.h"
#include "io/atomic.h"
#include "io/sha256.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

static int valid_name(const char *name)
{
    size_t n = strlen(name);
    if (n == 0 || n > 200 || name[0] == '.')
        return 0;
    for (size_t i = 0; i < n; ++i)
        if (!isalnum((unsigned char)name[i]) && name[i] != '_' && name[i] != '-' && name[i] != '.')
            return 0;
    return 1;
}

static int valid_hex(const char *hex)
{
    if (strlen(hex) != 64)
        return 0;
    for (int i = 0; i < 64; ++i)
        if (!((hex[i] >= '0' && hex[i] <= '9') || (hex[i] >= 'a' && hex[i] <= 'f')))
            return 0;
    return 1;
}

static int make_dir(const char *path)
{
    return mkdir(path, 0777) == 0 || errno == EEXIST ? 0 : -1;
}

static int update(const char *name, const char *root, const char *path, const char *hex)
{
    char dir[4096], line[80], err[4400];
    snprintf(dir, sizeof dir, "%s/fixtures", root);
    int ok = make_dir(dir) == 0;
    snprintf(dir, sizeof dir, "%s/fixtures/golden", root);
    ok = ok && make_dir(dir) == 0;
    if (!ok) {
        fprintf(stderr, "golden %s: cannot write %s: %s\n", name, path, strerror(errno));
        return -1;
    }
    int n = snprintf(line, sizeof line, "%s\n", hex);
    if (qtool_io_write_atomic(path, line, (size_t)n, err, sizeof err) != 0) {
        fprintf(stderr, "golden %s: cannot write: %s\n", name, err);
        return -1;
    }
    fprintf(stderr, "golden %s: wrote %s (QIBL_UPDATE_GOLDEN=1)\n", name, path);
    return 0;
}

int qtool_golden_check(const char *name, const char *hex)
{
    if (name == NULL || hex == NULL || !valid_name(name) || !valid_hex(hex)) {
        fprintf(stderr, "golden %s: bad case name or hash \"%s\"\n", name ? name : "(null)", hex ? hex : "(null)");
        return -1;
    }
    const char *root = getenv("QIBL_ROOT");
    if (root == NULL || root[0] == '\0')
        root = ".";
    char path[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/fixtures/golden/%s.sha256", root, name) >= sizeof path) {
        fprintf(stderr, "golden %s: path too long\n", name);
        return -1;
    }
    const char *upd = getenv("QIBL_UPDATE_GOLDEN");
    if (upd != NULL && strcmp(upd, "1") == 0)
        return update(name, root, path, hex);

    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "golden %s: cannot read %s (%s); actual %s; QIBL_UPDATE_GOLDEN=1 creates it\n", name,
                path, strerror(errno), hex);
        return -1;
    }
    char line[256] = {0};
    if (fgets(line, sizeof line, f) == NULL)
        line[0] = '\0';
    fclose(f);
    size_t n = strlen(line);
    while (n > 0 && isspace((unsigned char)line[n - 1]))
        line[--n] = '\0';
    if (strcmp(line, hex) != 0) {
        fprintf(stderr, "golden %s: MISMATCH (%s)\n  expected %s\n  actual   %s\n", name, path, line, hex);
        return -1;
    }
    return 0;
}

int qtool_golden_check_bytes(const char *name, const void *data, size_t n)
{
    char hex[65];
    qtool_sha256_hex(data, n, hex);
    return qtool_golden_check(name, hex);
}
