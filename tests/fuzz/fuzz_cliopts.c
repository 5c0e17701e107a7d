/*
 * fuzz_cliopts.c - libFuzzer target: the qibl CLI's option parsing. The input is an argv (arguments
 * separated by NUL bytes; the first byte picks the command), handed to qcli_run with
 * qcli_parse_only set, so every command returns once its options are parsed and checked and
 * never reads a file, bakes or writes (cli.h); `sh eval` and `srgbe`, which only print a few
 * numbers, run whole (their qcli_sub's .whole). When the first argument is a command's name (as the seeds write it) that
 * command runs; otherwise the first byte picks one and every argument goes to it.
 *
 * Invariants: no crash, leak or undefined behaviour; the exit status is 0, 1 or 2; a refusal
 * (non-zero) says why on stderr in a first line that starts "qibl: " and is not empty, or (a
 * command on option tables, cli/opt.h) "qibl CMD[ SUB]: " and ends "; see qibl help CMD"; the
 * parsers' work is bounded (libFuzzer's timeout).
 */
#include <stdio.h>
#include <string.h>

#include "fuzz.h"
#include "cli/cli.h"

#define NCMDS qcli_ncommands
#define MAX_ARGS 48
#define MAX_ARG 256

/* the refusal's first line: "qibl: why", or an option table's "qibl CMD[ SUB]: why; see qibl help CMD" */
static int refusal_ok(const char *e, const char *cmd)
{
    if (strncmp(e, "qibl: ", 6) == 0)
        return e[6] != '\0' && e[6] != '\n';
    size_t n = strlen(cmd);
    if (strncmp(e, "qibl ", 5) != 0 || strncmp(e + 5, cmd, n) != 0)
        return 0;
    const char *p = e + 5 + n, *nl = strchr(e, '\n');
    if (*p == ' ') /* a subcommand */
        for (++p; *p >= 'a' && *p <= 'z'; ++p)
            ;
    /* the first line ends "; see qibl help CMD" (a value may hold that text too: the end is what counts) */
    char tail[64];
    int tn = snprintf(tail, sizeof tail, "; see qibl help %s", cmd);
    size_t len = nl ? (size_t)(nl - e) : strlen(e);
    return p[0] == ':' && p[1] == ' ' && p[2] != '\0' && p[2] != '\n' && tn > 0 && len >= (size_t)tn &&
           memcmp(e + len - (size_t)tn, tail, (size_t)tn) == 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char args[MAX_ARGS][MAX_ARG + 1];
    static char errbuf[4096], outbuf[4096];
    char *argv[MAX_ARGS + 1];
    if (size == 0)
        return 0;
    qcli_parse_only = 1;
    size_t c = data[0] % NCMDS, pos = 0;
    int argc = 1;
    while (pos < size && argc < MAX_ARGS) { /* NUL-separated arguments, each cut at MAX_ARG bytes */
        const uint8_t *e = memchr(data + pos, 0, size - pos);
        size_t len = e ? (size_t)(e - (data + pos)) : size - pos;
        size_t k = len < MAX_ARG ? len : MAX_ARG;
        memcpy(args[argc], data + pos, k);
        args[argc][k] = '\0';
        argv[argc] = args[argc];
        ++argc;
        pos += len + 1;
    }
    int named = 0;
    for (size_t j = 0; argc > 1 && j < NCMDS && !named; ++j)
        if (strcmp(args[1], qcli_commands[j].name) == 0)
            c = j, named = 1;
    if (named) { /* the name is argv[0] */
        for (int j = 1; j < argc; ++j)
            argv[j - 1] = argv[j];
        --argc;
    } else {
        snprintf(args[0], sizeof args[0], "%s", qcli_commands[c].name);
        argv[0] = args[0];
    }
    argv[argc] = NULL;
    /* the command's stdout and stderr into bounded buffers (writes past the end are dropped) */
    memset(errbuf, 0, sizeof errbuf);
    FILE *err = fmemopen(errbuf, sizeof errbuf - 1, "w"), *out = fmemopen(outbuf, sizeof outbuf - 1, "w");
    FUZZ_CHECK(err && out);
    FILE *saved_err = stderr, *saved_out = stdout;
    stderr = err, stdout = out;
    int rc = qcli_run(&qcli_commands[c], argc, argv);
    fflush(err), fflush(out);
    stderr = saved_err, stdout = saved_out;
    fclose(err), fclose(out);
    FUZZ_CHECK(rc == 0 || rc == 1 || rc == 2);
    if (rc != 0) {
        if (!refusal_ok(errbuf, qcli_commands[c].name))
            fprintf(stderr, "%s: exit %d with stderr '%.200s'\n", qcli_commands[c].name, rc, errbuf);
        FUZZ_CHECK(refusal_ok(errbuf, qcli_commands[c].name));
    }
    return 0;
}
