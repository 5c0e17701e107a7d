/*
 * cmd_bench.c - `qibl bench`: the options (its option table, opt/opt.h) into a qtool_bench_opts,
 * then the benchmarks library (tools/bench). Timing lives there, never in tests.
 */
#include <stddef.h>
#include <string.h>

#include "bench/bench.h"
#include "cli/cli.h"
#include "opt/opt.h"

typedef struct bench_cli_opts {
    qtool_opt_list what; /* the benchmark: the last one named counts, as it always did */
    const char *svg;
    int quick, csv, markdown;
} bench_cli_opts;
static const bench_cli_opts bench_defaults = {.svg = NULL, .quick = 0, .csv = 0, .markdown = 0};

static const qtool_opt bench_table[] = {
    {.name = "--quick", .kind = QTOOL_OPT_FLAG, .off = offsetof(bench_cli_opts, quick),
     .help = "smaller sizes and fewer repetitions"},
    {.name = "--csv", .kind = QTOOL_OPT_FLAG, .off = offsetof(bench_cli_opts, csv),
     .help = "relight: the table as CSV"},
    {.name = "--markdown", .kind = QTOOL_OPT_FLAG, .off = offsetof(bench_cli_opts, markdown),
     .help = "memory: the table as docs/porting.md has it"},
    {.name = "--svg", .kind = QTOOL_OPT_STR, .off = offsetof(bench_cli_opts, svg), .arg = "PATH",
     .help = "hemi: the cloth's error against frames per second, as an SVG plot"},
    {0},
};

static const qtool_opt_cmd bench_spec = {
    QTOOL_OPT_CMD("bench", bench_table, bench_defaults, "BENCH", 0, QTOOL_OPT_LIST_MAX, bench_cli_opts, what),
    .prose =
        "  BENCH: " QTOOL_BENCH_NAMES "\n"
        "  (default all; the last one named runs).\n"
        "  sh: integer SH basis against the double reference from Wong et al.'s appendix:\n"
        "      ns per evaluation (median of 7 runs) and max |error| over a fixed-seed sweep.\n"
        "  relight: the relighting kernels on the procedural courtyard, 1024x256, k = 4, 9, 16, 25:\n"
        "      directional and point lights (cube-map LUT 16^2/32^2/64^2, direct SH): ms/frame,\n"
        "      Mpixel/s, PSNR and max abs error in 8-bit units, a plain read of the same map bytes, the\n"
        "      two range-packing schemes; --csv prints the table as CSV.\n"
        "  baselines: the relight bench's plain-read and memcpy baselines alone.\n"
        "  srgbe: the sRGBE codec against Ward's RGBE (frexp/ldexp), RGB9E5 and binary32 on a real\n"
        "      probe from ../shared/fixtures/probes (QIBL_PROBE=FILE picks one; a procedural sky\n"
        "      when absent) and on signed SH data of it: max/mean relative error of the largest\n"
        "      channel, mean absolute error of the others, encode/decode Mpixel/s (medians).\n"
        "  lights: light-probe sampling on a 1024x512 probe (QIBL_PROBE=FILE, else quarry_01_1k.hdr from\n"
        "      ../shared/fixtures/probes, else a procedural sky) and on it upsampled to 4096x2048: SAT and\n"
        "      cut milliseconds for median cut 64/256, adaptive 64, varmin 64, and the ratio of median cut 64\n"
        "      (SAT included) to one plain read pass over the probe bytes (RESULT lights.sat64_over_read);\n"
        "      then the irradiance error of every method and priority on each real probe.\n"
        "  paths: path lights against today's SH-only relighting, 1024x256, thread CPU time: a sun as\n"
        "      unshadowed k = 9 or 16 x path visibility (hard, soft), sky + sun, lamps on a track and free.\n"
        "  asset: opening a 16 MB asset: nibble CRC, slicing-by-8 CRC, structure only, against a memcpy\n"
        "      of the same bytes (min and median of interleaved repetitions).\n"
        "  probe: SH projection of a 1024x512 probe (quarry_01_1k.hdr, else an integer-made one) against\n"
        "      one 64-bit read pass of its bytes (min and median of interleaved runs), the projection's\n"
        "      error against the double reference on every fixture probe, the rotation's error, and the\n"
        "      ringing of the irradiance with no window, Hann and Lanczos (RESULT probe.*).\n"
        "  hemi: hemispherical rasterization on an animated cloth (the paper's Tables 1 and 2): frames per\n"
        "      second on one core, error against a ray cast (--svg PATH: error against fps as an SVG plot).\n"
        "  memory: not a timing: the resident-memory table of docs/porting.md (--markdown: as there).\n"
        "  gles: frames per second of platform/gles2 on a headless EGL context (only when asked).\n"
        "  all: every timing benchmark (what `make bench` runs). --quick: fewer repetitions.\n",
};

/* the benchmark: the last one named counts, as it always did */
static const char *bench_what(const bench_cli_opts *c)
{
    return c->what.n ? c->what.v[c->what.n - 1] : "all";
}

static int bench_check(void *opts)
{
    const char *what = bench_what(opts);
    if (!qtool_bench_known(what))
        return qtool_opt_error(&bench_spec, "unknown benchmark '%s' (" QTOOL_BENCH_NAMES ")", what);
    return 0;
}

static int bench_run(void *opts)
{
    const bench_cli_opts *c = opts;
    const qtool_bench_opts o = {.what = bench_what(c), .quick = c->quick, .csv = c->csv, .markdown = c->markdown,
                                .svg = c->svg};
    return qtool_bench_run(&o);
}

const qcli_sub qcli_sub_bench = {.opts = &bench_spec, .check = bench_check, .run = bench_run};
