/*
 * cmd_sh.c - `qibl sh eval`: the core's integer SH basis, printed as decimals.
 */
#include <stdio.h>
#include <string.h>

#include "qibl/cli.h"
#include "qibl/sh.h"

int qibl_cmd_sh(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "eval") != 0)
        return qibl_cli_usage_error("usage: qibl sh eval [--bands B] X Y Z");
    long bands = QIBL_SH_MAX_BANDS;
    const char *xyz[3];
    int n = 0;
    for (int i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "--bands") == 0) {
            if (i + 1 >= argc || qibl_cli_parse_int(argv[i + 1], 1, QIBL_SH_MAX_BANDS, &bands) != 0)
                return qibl_cli_usage_error("--bands needs an integer in 1..%d", QIBL_SH_MAX_BANDS);
            ++i;
        } else if (n < 3) {
            xyz[n++] = argv[i];
        } else {
            return qibl_cli_usage_error("sh eval takes exactly three coordinates X Y Z");
        }
    }
    if (n != 3)
        return qibl_cli_usage_error("sh eval takes exactly three coordinates X Y Z");
    qibl_q16_t dir[3];
    for (int k = 0; k < 3; ++k)
        if (qibl_cli_parse_q16(xyz[k], &dir[k]) != 0)
            return qibl_cli_usage_error("'%s' is not a number in the Q16.16 range [-32768, 32768)", xyz[k]);
    qibl_q30_t y[QIBL_SH_MAX_COUNT];
    qibl_status_t st = qibl_sh_eval(dir, (int)bands, y);
    if (st != QIBL_OK)
        return qibl_cli_usage_error("sh eval: %s", qibl_status_str(st));
    for (long i = 0; i < bands * bands; ++i)
        printf("%.9f\n", (double)y[i] / 1073741824.0);
    return 0;
}
