/*
 * cmd_srgbe.c - `qibl srgbe encode R G B` and `qibl srgbe decode HEX8`: one sRGBE code through the
 * core's integer codec (binary32 values go in and out as bit patterns).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "qibl/srgbe.h"

#define SRGBE_USAGE "usage: qibl srgbe encode R G B | qibl srgbe decode HEX8"

/* a decimal (or inf/nan) rounded to binary32; 0, or -1 if not a number or beyond binary32 */
static int parse_f32(const char *s, uint32_t *bits)
{
    char *end;
    errno = 0;
    float f = strtof(s, &end);
    if (end == s || *end != '\0')
        return -1;
    if (errno == ERANGE && isinf(f))
        return -1; /* a finite decimal too large for binary32 (underflow to 0/subnormal is fine) */
    memcpy(bits, &f, sizeof *bits);
    return 0;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    return c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* The codec's non-OK statuses by their enum names, so a note names the status a program would get. */
static const char *status_name(qibl_status_t st)
{
    switch (st) {
    case QIBL_E_SRGBE_NAN:
        return "QIBL_E_SRGBE_NAN";
    case QIBL_E_SRGBE_INF:
        return "QIBL_E_SRGBE_INF";
    case QIBL_E_SRGBE_OVERFLOW:
        return "QIBL_E_SRGBE_OVERFLOW";
    case QIBL_E_SRGBE_DECODE_SAT:
        return "QIBL_E_SRGBE_DECODE_SAT";
    default:
        return "status";
    }
}

/* Every status that still wrote a result: the result on stdout, then one line on stderr naming the
 * status (what qibl_srgbe_* returned) and what it means. */
static void note_status(const char *what, qibl_status_t st)
{
    if (st != QIBL_OK)
        fprintf(stderr, "qibl: srgbe %s: %s: %s\n", what, status_name(st), qibl_status_str(st));
}

static int srgbe_encode(int argc, char **argv)
{
    if (argc != 5)
        return qcli_usage_error("srgbe encode needs three values R G B (" SRGBE_USAGE ")");
    uint32_t in[3];
    for (int i = 0; i < 3; ++i)
        if (parse_f32(argv[2 + i], &in[i]) != 0)
            return qcli_usage_error("srgbe encode: '%s' is not a binary32 number", argv[2 + i]);
    uint8_t code[4];
    qibl_status_t st = qibl_srgbe_encode_f32(in, code);
    /* the codec writes a code for every status but a NULL pointer: print it, then name the status */
    printf("%02x%02x%02x%02x\n", code[0], code[1], code[2], code[3]);
    note_status("encode", st);
    return st == QIBL_E_SRGBE_NAN ? 1 : 0;
}

static int srgbe_decode(int argc, char **argv)
{
    if (argc != 3)
        return qcli_usage_error("srgbe decode needs one code HEX8 (" SRGBE_USAGE ")");
    const char *h = argv[2];
    uint8_t code[4];
    if (strlen(h) != 8)
        return qcli_usage_error("srgbe decode: '%s' is not 8 hex digits", h);
    for (int i = 0; i < 4; ++i) {
        int hi = hexval(h[2 * i]), lo = hexval(h[2 * i + 1]);
        if (hi < 0 || lo < 0)
            return qcli_usage_error("srgbe decode: '%s' is not 8 hex digits", h);
        code[i] = (uint8_t)(hi << 4 | lo);
    }
    uint32_t out[3];
    qibl_status_t st = qibl_srgbe_decode_f32(code, out);
    float f[3];
    memcpy(f, out, sizeof f);
    printf("%.9g %.9g %.9g\n", (double)f[0], (double)f[1], (double)f[2]);
    note_status("decode", st);
    return 0;
}

int qcli_cmd_srgbe(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "encode") == 0)
        return srgbe_encode(argc, argv);
    if (argc >= 2 && strcmp(argv[1], "decode") == 0)
        return srgbe_decode(argc, argv);
    return qcli_usage_error(SRGBE_USAGE);
}
