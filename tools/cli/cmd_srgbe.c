/*
 * cmd_srgbe.c - `qibl srgbe encode R G B` and `qibl srgbe decode HEX8`: one sRGBE code through the
 * core's integer codec (binary32 values go in and out as bit patterns).
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "opt/opt.h"
#include "qibl/srgbe.h"

static const qtool_opt_cmd encode_spec = {
    .name = "srgbe encode",
    .pos = {.names = "R G B", .min = 3, .max = 3, .numbers = 1},
    QTOOL_OPT_TABLE(NULL, qtool_opt_args),
    .prose =
        "  R G B are decimals rounded to binary32 (inf and nan accepted); prints the code as\n"
        "  8 hex digits, bytes R G B E in memory order (Granier et al. 4.2: e = floor(log2 max|c|) + 2,\n"
        "  X = round(255 (c 2^-e + 1/2)), E = e + 126). The code the codec wrote is always printed; a\n"
        "  status other than QIBL_OK is named on stderr (`qibl: srgbe encode: QIBL_E_SRGBE_INF: ...`):\n"
        "  an infinite channel saturates (exit 0); a NaN channel writes the zero code 80808000 (exit 1).\n",
};

static const qtool_opt_cmd decode_spec = {
    .name = "srgbe decode",
    .pos = {.names = "HEX8", .min = 1, .max = 1},
    QTOOL_OPT_TABLE(NULL, qtool_opt_args),
    .prose =
        "  HEX8 is 8 hex digits as printed by encode; prints the three channels\n"
        "  (X/255 - 1/2) 2^(E-126), correctly rounded to binary32, as %.9g (E = 255 with X = 0 or 255\n"
        "  saturates to +-FLT_MAX, printed, with QIBL_E_SRGBE_DECODE_SAT named on stderr; exit 0).\n",
};

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

static int srgbe_encode(void *opts)
{
    const qtool_opt_list *args = opts;
    uint32_t in[3];
    for (int i = 0; i < 3; ++i)
        if (parse_f32(args->v[i], &in[i]) != 0)
            return qtool_opt_error(&encode_spec, "'%s' is not a binary32 number", args->v[i]);
    uint8_t code[4];
    qibl_status_t st = qibl_srgbe_encode_f32(in, code);
    /* the codec writes a code for every status but a NULL pointer: print it, then name the status */
    printf("%02x%02x%02x%02x\n", code[0], code[1], code[2], code[3]);
    note_status("encode", st);
    return st == QIBL_E_SRGBE_NAN ? 1 : 0;
}

static int srgbe_decode(void *opts)
{
    const char *h = ((const qtool_opt_list *)opts)->v[0];
    uint8_t code[4];
    if (strlen(h) != 8)
        return qtool_opt_error(&decode_spec, "'%s' is not 8 hex digits", h);
    for (int i = 0; i < 4; ++i) {
        int hi = hexval(h[2 * i]), lo = hexval(h[2 * i + 1]);
        if (hi < 0 || lo < 0)
            return qtool_opt_error(&decode_spec, "'%s' is not 8 hex digits", h);
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

/* they read nothing and print a few numbers: fuzz_cliopts runs them whole */
const qcli_sub qcli_sub_srgbe_encode = {.opts = &encode_spec, .run = srgbe_encode, .whole = 1};
const qcli_sub qcli_sub_srgbe_decode = {.opts = &decode_spec, .run = srgbe_decode, .whole = 1};
