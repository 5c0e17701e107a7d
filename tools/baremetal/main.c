/*
 * baremetal/main.c - the golden runner on bare metal: every group of tools/golden/cases.h, one
 * line per case with its SHA-256 and the heap the case held at its peak, then the stack high-water
 * mark, the stack each wrapped core entry point used (probe.S) and the digest of tools/golden/
 * runner.c. No file system here: tools/baremetal/run.sh compares the hashes with fixtures/golden.
 *
 * Output:
 *   tls ok: ...                            (tls.c: a failed malloc set errno inside the TLS block)
 *   case <name> <64 hex> heap <bytes>      |  case <name> - ERROR <why>
 *   group <name>: <n> cases, <ms> ms emulated
 *   stack <entry point> <bytes>            (deepest use of one call, measured by painting)
 *   stack high-water <bytes> of <bytes>
 *   golden: <config>: <n> cases, <m> errors; digest <64 hex>
 */
#include <string.h>

#include "golden/cases.h"
#include "io/sha256.h"
#include "heap.h"
#include "probe.h"
#include "semi.h"
#include "stack.h"
#include "tls.h"

#ifndef BM_CONFIG
#define BM_CONFIG "baremetal"
#endif

/* A port with prebuilt hemi tables (BM_HEMI_TABLES: tools/gba/hemi_rom.c, blobs in cartridge ROM)
 * hands them to the cases; the others build the tables in the heap. */
#ifdef BM_HEMI_TABLES
const void *bm_hemi_tables(void *user, int n, int face, size_t *size);
#define BM_HEMI_TABLES_HOOK bm_hemi_tables
#else
#define BM_HEMI_TABLES_HOOK NULL
#endif

typedef struct {
    int cases, errors;
    qtool_sha256_t all;
} run;

static void digest_line(run *r, const char *name, const char *rest, size_t n)
{
    qtool_sha256_update(&r->all, name, strlen(name));
    qtool_sha256_update(&r->all, rest, n);
}

static int emit(void *user, const char *name, const char *hex, uint64_t n)
{
    run *r = (run *)user;
    (void)n;
    ++r->cases;
    digest_line(r, name, " ", 1);
    qtool_sha256_update(&r->all, hex, 64);
    qtool_sha256_update(&r->all, "\n", 1);
    bm_puts("case "), bm_puts(name), bm_puts(" "), bm_puts(hex), bm_puts(" heap ");
    bm_putu((uint32_t)bm_heap_peak_reset());
    bm_puts("\n");
    return 0; /* the host compares */
}

static void error(void *user, const char *name, const char *what)
{
    run *r = (run *)user;
    ++r->cases, ++r->errors;
    digest_line(r, name, " ERROR\n", 7);
    bm_puts("case "), bm_puts(name), bm_puts(" - ERROR "), bm_puts(what), bm_puts("\n");
}

int main(void)
{
    static run r;
    if (bm_tls_check() != 0) /* errno must land in TLS, not in low memory */
        return 1;
    qtool_sha256_init(&r.all);
    qtool_goldens_sink_t sink = {.emit = emit, .error = error, .user = &r, .hemi_tables = BM_HEMI_TABLES_HOOK};
    bm_clock_start();
    for (size_t g = 0; g < qtool_goldens_group_count; ++g) {
        int before = r.cases;
        uint64_t t0 = bm_clock_ns();
        (void)bm_heap_peak_reset();
        qtool_goldens_groups[g].run(&sink);
        uint64_t ns = bm_clock_ns() - t0;
        bm_puts("group "), bm_puts(qtool_goldens_groups[g].name), bm_puts(": ");
        bm_putu((uint32_t)(r.cases - before)), bm_puts(" cases, ");
        bm_putu((uint32_t)(ns / 1000000u)), bm_puts(" ms emulated\n");
    }
    bm_probe_report();
    bm_puts("stack high-water "), bm_putu((uint32_t)bm_stack_high_water());
    bm_puts(" of "), bm_putu((uint32_t)bm_stack_size()), bm_puts("\n");
    uint8_t d[32];
    char hex[65];
    qtool_sha256_final(&r.all, d);
    qtool_sha256_to_hex(d, hex);
    bm_puts("golden: " BM_CONFIG ": "), bm_putu((uint32_t)r.cases), bm_puts(" cases, ");
    bm_putu((uint32_t)r.errors), bm_puts(" errors; digest "), bm_puts(hex), bm_puts("\n");
    return r.errors != 0;
}
