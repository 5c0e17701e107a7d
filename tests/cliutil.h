/*
 * cliutil.h - running the qibl program from a CMocka suite (cli_test.c, cli_use_test.c): find the
 * binary, a scratch directory per test, posix_spawn with stdout and stderr captured to files.
 *
 * The binary is ../bin/qibl next to the running test's own directory (so build/asan/tests/cli_test
 * runs build/asan/bin/qibl), or $QIBL_BIN. Everything is static: each suite has its own copy.
 * Used by every suite that runs the program (cli_*, probe_cli, farm, transfer, exr_cli).
 */
#ifndef QTOOL_TESTS_CLIUTIL_H
#define QTOOL_TESTS_CLIUTIL_H

#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/file.h"

extern char **environ;

static char qibl[4096], dir[64], outlog[128], errlog[128];

static inline int find_qibl(void)
{
    const char *env = getenv("QIBL_BIN");
    if (env && *env) {
        snprintf(qibl, sizeof qibl, "%s", env);
    } else {
        char self[3000];
        ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        if (n <= 0)
            snprintf(self, sizeof self, "build/tests/cli_test");
        else
            self[n] = '\0';
        char *slash = strrchr(self, '/');
        if (slash)
            *slash = '\0';
        snprintf(qibl, sizeof qibl, "%s/../bin/qibl", self);
    }
    return access(qibl, X_OK) == 0 ? 0 : -1;
}

/* skip() the calling test when the binary is not built */
static inline void need_qibl(void)
{
    if (find_qibl() != 0) {
        fprintf(stderr, "SKIP: %s not built\n", qibl);
        skip();
    }
}

/* a fresh scratch directory from the mkdtemp template, with the two capture files' names */
static inline int cli_setup(const char *template_)
{
    snprintf(dir, sizeof dir, "%s", template_);
    if (!mkdtemp(dir))
        return -1;
    snprintf(outlog, sizeof outlog, "%s/stdout.txt", dir);
    snprintf(errlog, sizeof errlog, "%s/stderr.txt", dir);
    return 0;
}

static inline void rm_rf(const char *path)
{
    pid_t pid;
    char *argv[] = {"rm", "-rf", (char *)path, NULL};
    if (posix_spawnp(&pid, "rm", NULL, NULL, argv, environ) == 0)
        waitpid(pid, NULL, 0);
}

/* dir/name in one of 64 rotating buffers: the result stays valid for the next 63 calls */
static inline char *at(const char *name)
{
    static char buf[64][512];
    static int i;
    i = (i + 1) % 64;
    snprintf(buf[i], sizeof buf[i], "%s/%s", dir, name);
    return buf[i];
}

/* The suite's CMocka setup and teardown: a fresh scratch directory from the mkdtemp template per
 * test, removed after it. */
#define CLI_FIXTURES(template_)                                                                      \
    static int setup(void **state)                                                                   \
    {                                                                                                \
        (void)state;                                                                                 \
        return cli_setup(template_);                                                                 \
    }                                                                                                \
    static int teardown(void **state)                                                                \
    {                                                                                                \
        (void)state;                                                                                 \
        rm_rf(dir);                                                                                  \
        return 0;                                                                                    \
    }

/* Runs qibl with the NULL-terminated arguments, stdout to outlog, stderr to errlog. The exit
 * status, or 128 + the signal that killed it. */
static inline int run_v(const char *first, va_list ap)
{
    char *argv[64];
    int n = 0;
    argv[n++] = qibl;
    for (const char *a = first; a && n < 63; a = va_arg(ap, const char *))
        argv[n++] = (char *)a;
    argv[n] = NULL;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, outlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, errlog, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    /* A --gles run under ASan: Mesa keeps a few hundred bytes past eglTerminate (tests/gles2_test.c
     * says why no suppression can name them), so that process runs without leak checking; ASan and
     * UBSan still check every access. */
    int gles = 0;
    for (int i = 1; i < n; ++i)
        gles |= strcmp(argv[i], "--gles") == 0;
    const char *prev = getenv("ASAN_OPTIONS");
    char *saved = gles && prev ? strdup(prev) : NULL;
    if (gles) {
        char opts[512];
        snprintf(opts, sizeof opts, "%s%sdetect_leaks=0", prev ? prev : "", prev && *prev ? ":" : "");
        setenv("ASAN_OPTIONS", opts, 1);
    }
    pid_t pid;
    int rc = posix_spawn(&pid, qibl, &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (gles) {
        if (saved)
            setenv("ASAN_OPTIONS", saved, 1);
        else
            unsetenv("ASAN_OPTIONS");
        free(saved);
    }
    if (rc != 0)
        fail_msg("cannot run %s: %s", qibl, strerror(rc));
    int st;
    while (waitpid(pid, &st, 0) < 0)
        if (errno != EINTR)
            fail_msg("waitpid: %s", strerror(errno));
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

static inline int run(const char *first, ...)
{
    va_list ap;
    va_start(ap, first);
    int rc = run_v(first, ap);
    va_end(ap);
    return rc;
}

/* the whole of a captured stream as a string (the caller frees) */
static inline char *text(const char *path)
{
    size_t n;
    uint8_t *b = qtool_io_read_all(path, &n);
    char *s = malloc(n + 1);
    assert_non_null(s);
    if (b)
        memcpy(s, b, n);
    s[b ? n : 0] = '\0';
    free(b);
    return s;
}

#endif /* QTOOL_TESTS_CLIUTIL_H */
