/*
 * nomem_test.c - the tools' relighting out of memory (QTOOL_E_NOMEM, tools/qtool.h): in a child
 * process whose address space is capped just above what it already maps, the frame buffers cannot
 * be allocated, and qtool_bake_relight8_ex and qtool_bake_relight_tiled8 fail with QTOOL_E_NOMEM
 * (they said QIBL_E_NULL_POINTER, a core status for a NULL argument) and qtool_status_str names it.
 * The same calls without the cap succeed, so the cap is what fails them. Skipped under sanitizers,
 * whose allocators reserve far more address space than they hand out.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bake/bake.h"
#include "bake/path.h"
#include "bake/tiled.h"
#include "gen/scene.h"
#include "qibl/shmtile.h"
#include "qtool.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define UNDER_SANITIZER 1
#endif
#endif

#ifndef UNDER_SANITIZER /* the helpers of the capped run, which the sanitizers' shadow memory cannot take */
enum { W = 512, H = 256, K = 4 }; /* a 512 KiB RGBA frame: well above the cap's margin */

/* the procedural scene's maps as an asset with SHMP and SHMT */
static void make_asset(uint8_t **out, size_t *n)
{
    qtool_gen_maps m;
    uint8_t *base, *pay;
    size_t bn, payn;
    uint32_t tiles[26];
    assert_int_equal(qtool_gen_scene(W, H, K, QTOOL_PANO_CYLINDRICAL, &m), 0);
    assert_int_equal(qtool_bake_shmt_payload(&m, 0, &pay, &payn, tiles), 0);
    assert_int_equal(qtool_bake_asset_ex(&m, &m, 0, NULL, NULL, &base, &bn), 0);
    assert_int_equal(qtool_bake_asset_add(base, bn, QIBL_CHUNK_SHMT, pay, payn, out, n), 0);
    free(base), free(pay);
    qtool_gen_free(&m);
}

/* bytes of address space the process maps now, or 0 when /proc does not say */
static size_t mapped_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    if (!f)
        return 0;
    if (fscanf(f, "%lu", &pages) != 1)
        pages = 0;
    fclose(f);
    return (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
}

static int relight(const uint8_t *asset, size_t n, int tiled, uint8_t *rgb8, qibl_status_t *st)
{
    qtool_rt_light l = {.dir = {0.3, 0.8, 0.5}, .rgb = {1, 1, 1}};
    if (tiled)
        return qtool_bake_relight_tiled8(asset, n, &l, -1, 0, 0, rgb8, NULL, st);
    return qtool_bake_relight8_ex(asset, n, &l, 0, 0, 1, rgb8, NULL, st);
}

/* exit code of a child that relights under the cap: 0 QTOOL_E_NOMEM as it should, 2 it succeeded,
 * 3 another status, 4 the cap could not be set */
static int capped_child(const uint8_t *asset, size_t n, int tiled, uint8_t *rgb8)
{
#ifdef __GLIBC__
    /* large blocks from fresh mappings, not from heap space freed earlier (glibc raises its mmap
     * threshold as large blocks are freed), so the cap binds */
    mallopt(M_MMAP_THRESHOLD, 64 * 1024);
    malloc_trim(0);
#endif
    size_t now = mapped_bytes();
    struct rlimit r = {.rlim_cur = now + 64 * 1024, .rlim_max = RLIM_INFINITY};
    if (now == 0 || setrlimit(RLIMIT_AS, &r) != 0)
        return 4;
    qibl_status_t st = QIBL_OK;
    if (relight(asset, n, tiled, rgb8, &st) == 0)
        return 2;
    return st == QTOOL_E_NOMEM && strcmp(qtool_status_str(st), "out of memory") == 0 ? 0 : 3;
}

#endif

static void test_nomem(void **state)
{
    (void)state;
#ifdef UNDER_SANITIZER
    skip();
#else
    uint8_t *asset;
    size_t n;
    make_asset(&asset, &n);
    uint8_t *rgb8 = malloc((size_t)W * H * 3);
    assert_non_null(rgb8);
    for (int tiled = 0; tiled < 2; ++tiled) {
        qibl_status_t st = QIBL_E_NULL_POINTER;
        assert_int_equal(relight(asset, n, tiled, rgb8, &st), 0); /* uncapped: it fits */
        fflush(NULL);
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0)
            _exit(capped_child(asset, n, tiled, rgb8));
        int ws = 0;
        assert_int_equal(waitpid(pid, &ws, 0), pid);
        assert_true(WIFEXITED(ws));
        if (WEXITSTATUS(ws) == 4) {
            free(rgb8), free(asset);
            skip(); /* no /proc or no RLIMIT_AS here */
        }
        printf("nomem: %s: capped child exit %d (0 = QTOOL_E_NOMEM)\n", tiled ? "tiled8" : "relight8_ex",
               WEXITSTATUS(ws));
        assert_int_equal(WEXITSTATUS(ws), 0);
    }
    free(rgb8);
    free(asset);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_nomem)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
