/*
 * golden/runner.c - qibl-golden: runs every golden case of the core (golden/cases.h), prints one
 * SHA-256 per case and compares it with fixtures/golden/<case>.sha256.
 *
 * A plain C99 program: it links the core, platform/soft, io/sha256.c and the cases, and uses only
 * the C library (no POSIX, no libm, no test framework), so it cross-compiles for any port that has
 * a libc and runs under qemu-user. `make ports` builds it for every compiler, optimisation level
 * and architecture and checks that all of them print the same hashes.
 *
 * Output, one line per case and a summary:
 *   case <name> <64 hex> ok | MISMATCH (expected <hex>) | MISSING (no <file>) | ERROR <why> | updated
 *   golden: <config>: <n> cases, <m> failed; digest <64 hex>
 * The digest is the SHA-256 of all "<name> <hash>\n" lines in order: one value to compare between
 * configurations. Exit status 0 if every case matched, 1 otherwise (each failure names its case),
 * 2 on a usage error.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "golden/cases.h"
#include "io/sha256.h"
#include "qibl/isa.h"

typedef struct {
    const char *root;
    int update;
    int cases, failed;
    qtool_sha256_t all; /* of every "<name> <hash>\n" */
    char **names;      /* seen so far, to reject a duplicate case name */
    size_t nnames, capnames;
} run;

static int seen_before(run *r, const char *name)
{
    for (size_t i = 0; i < r->nnames; ++i)
        if (strcmp(r->names[i], name) == 0)
            return 1;
    if (r->nnames == r->capnames) {
        size_t cap = r->capnames ? 2 * r->capnames : 256;
        char **p = realloc(r->names, cap * sizeof *p);
        if (p == NULL)
            return 0;
        r->names = p, r->capnames = cap;
    }
    size_t n = strlen(name) + 1;
    char *c = malloc(n);
    if (c != NULL) {
        memcpy(c, name, n);
        r->names[r->nnames++] = c;
    }
    return 0;
}

static int valid_name(const char *name)
{
    size_t n = strlen(name);
    if (n == 0 || n > 200)
        return 0;
    for (size_t i = 0; i < n; ++i) {
        char c = name[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-'))
            return 0;
    }
    return 1;
}

/* reads the first line of path into hex (64 chars + NUL); 0 on success */
static int read_expected(const char *path, char hex[65])
{
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return -1;
    char line[256];
    int ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    if (!ok)
        return -1;
    size_t n = strlen(line);
    while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r' || line[n - 1] == ' ' || line[n - 1] == '\t'))
        line[--n] = '\0';
    if (n != 64)
        return -1;
    memcpy(hex, line, 65);
    return 0;
}

static int write_expected(const char *path, const char *hex)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (f == NULL)
        return -1;
    int ok = fprintf(f, "%s\n", hex) > 0;
    ok = fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0) {
        remove(tmp);
        return -1;
    }
    return 0;
}

/* A failed case's line, "case NAME HEX " then what went wrong (pre, arg, post), counted; returns 1. */
static int failed(run *r, const char *name, const char *hex, const char *pre, const char *arg, const char *post)
{
    printf("case %s %s %s%s%s\n", name, hex, pre, arg, post);
    ++r->failed;
    return 1;
}

static int emit(void *user, const char *name, const char *hex, uint64_t n)
{
    run *r = (run *)user;
    char path[4096], want[65];
    (void)n;
    ++r->cases;
    qtool_sha256_update(&r->all, name, strlen(name));
    qtool_sha256_update(&r->all, " ", 1);
    qtool_sha256_update(&r->all, hex, 64);
    qtool_sha256_update(&r->all, "\n", 1);
    if (!valid_name(name) || seen_before(r, name))
        return failed(r, name, hex, "ERROR bad or duplicate case name", "", "");
    if ((size_t)snprintf(path, sizeof path, "%s/fixtures/golden/%s.sha256", r->root, name) >= sizeof path)
        return failed(r, name, hex, "ERROR path too long", "", "");
    if (r->update) {
        if (read_expected(path, want) == 0 && strcmp(want, hex) == 0) {
            printf("case %s %s ok\n", name, hex);
            return 0;
        }
        if (write_expected(path, hex) != 0)
            return failed(r, name, hex, "ERROR cannot write ", path, "");
        printf("case %s %s updated\n", name, hex);
        return 0;
    }
    if (read_expected(path, want) != 0)
        return failed(r, name, hex, "MISSING (no readable ", path, "; --update writes it)");
    if (strcmp(want, hex) != 0)
        return failed(r, name, hex, "MISMATCH (expected ", want, ")");
    printf("case %s %s ok\n", name, hex);
    return 0;
}

static void error(void *user, const char *name, const char *what)
{
    run *r = (run *)user;
    ++r->cases;
    ++r->failed;
    qtool_sha256_update(&r->all, name, strlen(name));
    qtool_sha256_update(&r->all, " ERROR\n", 7);
    printf("case %s - ERROR %s\n", name, what);
}

static void usage(FILE *f)
{
    fprintf(f, "usage: qibl-golden [--root DIR] [--config NAME] [--update] [--list] [GROUP...]\n"
               "  runs the golden cases of the core (all groups, or the ones named) and compares each\n"
               "  hash with DIR/fixtures/golden/<case>.sha256 (DIR: --root, else $QIBL_ROOT, else .)\n"
               "  --update   rewrite the expected hash of every case that differs or is missing\n"
               "  --config   a label for the summary line (make ports passes the configuration)\n"
               "  --list     list the groups and exit\n");
}

int main(int argc, char **argv)
{
    run r;
    memset(&r, 0, sizeof r);
    const char *config = "native";
    r.root = getenv("QIBL_ROOT");
    if (r.root == NULL || r.root[0] == '\0')
        r.root = ".";
    const char *only[64];
    int nonly = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--update") == 0) {
            r.update = 1;
        } else if (strcmp(argv[i], "--root") == 0 && i + 1 < argc) {
            r.root = argv[++i];
        } else if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
            config = argv[++i];
        } else if (strcmp(argv[i], "--list") == 0) {
            for (size_t g = 0; g < qtool_goldens_group_count; ++g)
                printf("%-12s %s\n", qtool_goldens_groups[g].name, qtool_goldens_groups[g].about);
            return 0;
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (argv[i][0] != '-' && nonly < 64) {
            int found = 0;
            for (size_t g = 0; g < qtool_goldens_group_count; ++g)
                found |= strcmp(qtool_goldens_groups[g].name, argv[i]) == 0;
            if (!found) {
                fprintf(stderr, "qibl-golden: no group \"%s\" (--list names them)\n", argv[i]);
                return 2;
            }
            only[nonly++] = argv[i];
        } else {
            usage(stderr);
            return 2;
        }
    }
    qtool_sha256_init(&r.all);
    qtool_goldens_sink_t sink = {.emit = emit, .error = error, .user = &r};
    for (size_t g = 0; g < qtool_goldens_group_count; ++g) {
        int wanted = nonly == 0;
        for (int i = 0; i < nonly; ++i)
            wanted |= strcmp(only[i], qtool_goldens_groups[g].name) == 0;
        if (!wanted)
            continue;
        int before = r.cases;
        clock_t t0 = clock();
        qtool_goldens_groups[g].run(&sink);
        double ms = 1000.0 * (double)(clock() - t0) / CLOCKS_PER_SEC;
        printf("group %s: %d cases, %.0f ms CPU\n", qtool_goldens_groups[g].name, r.cases - before, ms);
    }
    uint8_t d[32];
    char hex[65];
    qtool_sha256_final(&r.all, d);
    qtool_sha256_to_hex(d, hex);
    printf("golden: kernels %s (%s)\n", qibl_isa_name(qibl_isa_active()),
           qibl_isa_dispatches() ? "run-time dispatch, QIBL_ISA" : "compile-time");
    printf("golden: %s: %d cases, %d failed%s; digest %s\n", config, r.cases, r.failed,
           r.update ? " (--update)" : "", hex);
    for (size_t i = 0; i < r.nnames; ++i)
        free(r.names[i]);
    free(r.names);
    return r.failed ? 1 : 0;
}
