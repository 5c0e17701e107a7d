/*
 * farm_test.c - the bake on a render farm (issue 31), through the qibl program: shards of any split
 * merge to the single bake byte for byte with light paths and lamp occlusion baked by every shard
 * (its rows only), a shard baked without the others' --sun-path refused by name, version 1 extras
 * refused by name, tree merges of partial sets, the thread count from the CPU affinity and SLURM_CPUS_PER_TASK,
 * --progress=lines, and tile shards (both passes, the reduction and the merge of the parts byte for byte the
 * single bake for bands of 1, 2, 3 and 7 of 7 rows; every bad input refused by name).
 *
 * The binary is found as cliutil.h says; the tests skip when it is missing.
 */
#define _GNU_SOURCE /* sched_setaffinity for the affinity test */
#include <math.h>
#include <sched.h>
#include <dirent.h>
#include <sys/stat.h>

#include "cliutil.h"

#include "bake/extras.h"
#include "bake/tile.h"
#include "io/atomic.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"

CLI_FIXTURES("/tmp/qibl_farm_test_XXXXXX")

static int says(const char *log, const char *want)
{
    char *m = text(log);
    int ok = strstr(m, want) != NULL;
    if (!ok)
        fprintf(stderr, "%s says: %s\n(wanted '%s')\n", log, m, want);
    free(m);
    return ok;
}

/* 7 rows and 5 direction blocks: no split of 2..5 divides the rows evenly */
#define FARM_ARGS "--size", "20x7", "--k", "4", "--dirs", "80", "--unshadowed-k", "4", "--sun-path", "40,15,7,17", \
                  "--lamp-track", "1,1,-0.5;-1,1,-0.5", "--lamp-box", "-2,-2,-1,2,2,0", "--lamp-samples", "6", \
                  "--path-steps", "8", "--quiet", "--threads", "1"

static void file_eq(const char *a, const char *b)
{
    size_t na, nb;
    uint8_t *x = qtool_io_read_all(a, &na), *y = qtool_io_read_all(b, &nb);
    assert_non_null(x), assert_non_null(y);
    assert_int_equal(na, nb);
    assert_memory_equal(x, y, na);
    free(x), free(y);
}

static void shard(uint32_t i, uint32_t n, const char *name)
{
    char in[32];
    snprintf(in, sizeof in, "%u/%u", i, n);
    int rc = run("bake", FARM_ARGS, "--shard", in, "--sums", at(name), NULL);
    if (rc != 0) {
        char *m = text(errlog);
        fail_msg("bake --shard %s: exit %d: %s", in, rc, m);
    }
}

/* every split of 1..5 shards (merged in reverse order) is the single bake byte for byte, and each
 * shard's extras hold the light paths and occlusion of its own rows only (rows y % n == i): the
 * per-pixel work is spread over the shards instead of all on shard 0 */
static void test_every_split_identical_and_balanced(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", FARM_ARGS, "-o", at("whole.qibl"), NULL), 0);
    for (uint32_t n = 1; n <= 5; ++n) {
        char name[5][16];
        for (uint32_t i = 0; i < n; ++i) {
            snprintf(name[i], sizeof name[i], "n%u_%u", n, i);
            shard(i, n, name[i]);
            char xn[32];
            snprintf(xn, sizeof xn, "%s.x", name[i]);
            qtool_extras x;
            char err[1200];
            if (qtool_extras_read(at(xn), &x, err, sizeof err) != 0)
                fail_msg("%s", err);
            assert_int_equal(x.shard, i), assert_int_equal(x.nshards, n);
            assert_int_equal(x.count, 3); /* sun path, lamp track, occlusion */
            for (uint32_t c = 0; c < x.count; ++c) {
                if (x.type[c] == QIBL_CHUNK_LPTH) {
                    qibl_lightpath_t lp;
                    assert_int_equal(qibl_lightpath_parse(x.data[c], x.size[c], &lp), QIBL_OK);
                    for (uint32_t y = 0; y < lp.height; ++y) {
                        uint32_t a = qibl_load_u32le(lp.rows + 4 * y), b = qibl_load_u32le(lp.rows + 4 * y + 4);
                        if (y % n != i && b != a)
                            fail_msg("shard %u/%u: light path %u has edges in row %u", i, n, c, y);
                    }
                } else {
                    qibl_lampocc_t lo;
                    assert_int_equal(qibl_lightpath_occl_parse(x.data[c], x.size[c], &lo), QIBL_OK);
                    uint32_t set = 0;
                    for (uint32_t y = 0; y < lo.height; ++y)
                        for (uint32_t px = 0; px < lo.width; ++px) {
                            uint8_t v = lo.values[y * lo.width + px];
                            if (y % n != i && v != 0)
                                fail_msg("shard %u/%u: occlusion set in row %u", i, n, y);
                            set += y % n == i && v != 0;
                        }
                    if (set == 0)
                        fail_msg("shard %u/%u baked no occlusion in its rows", i, n);
                }
            }
            qtool_extras_free(&x);
        }
        char *m[5];
        for (uint32_t i = 0; i < n; ++i)
            m[i] = at(name[n - 1 - i]);
        char out[32];
        snprintf(out, sizeof out, "m%u.qibl", n);
        int rc = n == 1 ? run("merge", "-o", at(out), m[0], NULL)
               : n == 2 ? run("merge", "-o", at(out), m[0], m[1], NULL)
               : n == 3 ? run("merge", "-o", at(out), m[0], m[1], m[2], NULL)
               : n == 4 ? run("merge", "-o", at(out), m[0], m[1], m[2], m[3], NULL)
                        : run("merge", "-o", at(out), m[0], m[1], m[2], m[3], m[4], NULL);
        if (rc != 0) {
            char *e = text(errlog);
            fail_msg("merge of %u shards: exit %d: %s", n, rc, e);
        }
        file_eq(at("whole.qibl"), at(out));
    }
}

/* a shard baked without the others' --sun-path (or --lamp-box) is refused by name, nothing written;
 * it used to merge silently into an asset without the light path */
static void test_shard_without_path_refused(void **state)
{
    (void)state;
    need_qibl();
    shard(1, 2, "s1");
    assert_int_equal(run("bake", "--size", "20x7", "--k", "4", "--dirs", "80", "--unshadowed-k", "4", "--quiet",
                         "--threads", "1", "--shard", "0/2", "--sums", at("s0"), NULL), 0);
    assert_int_equal(run("merge", "-o", at("m.qibl"), at("s0"), at("s1"), NULL), 1);
    assert_true(says(errlog, "s1.x: 3 light path/occlusion chunks")), assert_true(says(errlog, "s0.x has 0"));
    assert_true(says(errlog, "shards of different bakes"));
    assert_int_equal(access(at("m.qibl"), F_OK), -1);
    /* another sun path on shard 0: named too */
    assert_int_equal(run("bake", "--size", "20x7", "--k", "4", "--dirs", "80", "--unshadowed-k", "4", "--sun-path",
                         "30,15,7,17", "--lamp-track", "1,1,-0.5;-1,1,-0.5", "--lamp-box", "-2,-2,-1,2,2,0",
                         "--lamp-samples", "6", "--path-steps", "8", "--quiet", "--threads", "1", "--shard", "0/2",
                         "--sums", at("s0"), NULL), 0);
    assert_int_equal(run("merge", "-o", at("m.qibl"), at("s0"), at("s1"), NULL), 1);
    assert_true(says(errlog, "light path 1 is not the one of"));
    assert_int_equal(access(at("m.qibl"), F_OK), -1);
    /* a missing side file of one shard: named */
    shard(0, 2, "s0");
    assert_int_equal(unlink(at("s1.x")), 0);
    assert_int_equal(run("merge", "-o", at("m.qibl"), at("s0"), at("s1"), NULL), 1);
    assert_true(says(errlog, "s1.x is missing"));
    assert_int_equal(access(at("m.qibl"), F_OK), -1);
}

/* a version 1 extras file (whole chunks from shard 0 alone) is refused by name */
static void test_extras_v1_refused(void **state)
{
    (void)state;
    need_qibl();
    shard(0, 2, "s0");
    shard(1, 2, "s1");
    static const uint8_t v1[12] = {'Q', 'I', 'B', 'L', 'X', 'T', 'R', '1', 0, 0, 0, 0};
    char err[1200];
    assert_int_equal(qtool_io_write_atomic(at("s0.x"), v1, sizeof v1, err, sizeof err), 0);
    assert_int_equal(run("merge", "-o", at("m.qibl"), at("s0"), at("s1"), NULL), 1);
    assert_true(says(errlog, "a version 1 extras file"));
    assert_int_equal(access(at("m.qibl"), F_OK), -1);
}

/* tree merges: a partial set of shards I, I+M, ... of N merges (--sums only) into shard I of M with
 * its side files, and the tree's root is the single bake byte for byte; a set that is no shard of
 * a coarser split, or a partial set with -o, is refused by name and writes nothing */
static void test_tree_merge(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", FARM_ARGS, "-o", at("whole.qibl"), NULL), 0);
    for (uint32_t i = 0; i < 4; ++i) {
        char nm[8];
        snprintf(nm, sizeof nm, "s%u", i);
        shard(i, 4, nm);
    }
    assert_int_equal(run("merge", "--sums", at("a"), at("s2"), at("s0"), NULL), 0);
    assert_true(says(outlog, "partial sums of shard 0/2 (2 inputs)"));
    assert_int_equal(run("merge", "--sums", at("b"), at("s1"), at("s3"), NULL), 0);
    assert_true(says(outlog, "partial sums of shard 1/2 (2 inputs)"));
    assert_int_equal(access(at("a.u"), F_OK), 0), assert_int_equal(access(at("b.x"), F_OK), 0);
    assert_int_equal(run("merge", "-o", at("tree.qibl"), at("b"), at("a"), NULL), 0);
    file_eq(at("whole.qibl"), at("tree.qibl"));
    /* the total as sums, then the asset from it alone */
    assert_int_equal(run("merge", "--sums", at("t"), at("a"), at("b"), NULL), 0);
    assert_true(says(outlog, "the total sums"));
    assert_int_equal(run("merge", "-o", at("t.qibl"), at("t"), NULL), 0);
    file_eq(at("whole.qibl"), at("t.qibl"));
    /* -o and --sums at once: the total sums carry their side files too (a later merge of them alone
     * used to lose the unshadowed maps, light paths and occlusion) */
    assert_int_equal(run("merge", "-o", at("both.qibl"), "--sums", at("t2"), at("a"), at("b"), NULL), 0);
    file_eq(at("whole.qibl"), at("both.qibl"));
    assert_int_equal(run("merge", "-o", at("t2.qibl"), at("t2"), NULL), 0);
    file_eq(at("whole.qibl"), at("t2.qibl"));
    /* 0 and 1 of 4 are no shard of a split into 2 */
    assert_int_equal(run("merge", "--sums", at("bad"), at("s0"), at("s1"), NULL), 1);
    assert_true(says(errlog, "shards 0, 1 of 4 are not one shard of a coarser split"));
    assert_int_equal(access(at("bad"), F_OK), -1), assert_int_equal(access(at("bad.u"), F_OK), -1);
    /* an asset needs every shard */
    assert_int_equal(run("merge", "-o", at("bad.qibl"), at("s0"), at("s2"), NULL), 1);
    assert_true(says(errlog, "shard 1/4 is missing (an asset needs every shard"));
    assert_int_equal(access(at("bad.qibl"), F_OK), -1);
}

/* --manifest: every shard's files named (side files under other names), I/N checked per line */
static void test_manifest(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", FARM_ARGS, "-o", at("whole.qibl"), NULL), 0);
    shard(0, 2, "s0");
    shard(1, 2, "s1");
    assert_int_equal(rename(at("s1.u"), at("unshadowed1")), 0);
    assert_int_equal(rename(at("s1.x"), at("extras1")), 0);
    FILE *f = fopen(at("m.txt"), "w");
    assert_non_null(f);
    fprintf(f, "# the farm's shards\nshard 1/2 %s %s %s\n\nshard 0/2 %s\n", at("s1"), at("unshadowed1"),
            at("extras1"), at("s0"));
    fclose(f);
    assert_int_equal(run("merge", "-o", at("m.qibl"), "--manifest", at("m.txt"), NULL), 0);
    file_eq(at("whole.qibl"), at("m.qibl"));
    f = fopen(at("bad.txt"), "w");
    assert_non_null(f);
    fprintf(f, "shard 0/2 %s\nshard 0/2 %s\n", at("s1"), at("s0"));
    fclose(f);
    assert_int_equal(run("merge", "-o", at("b.qibl"), "--manifest", at("bad.txt"), NULL), 1);
    assert_true(says(errlog, "the manifest names it shard 0/2, the file is shard 1/2"));
    f = fopen(at("bad.txt"), "w");
    assert_non_null(f);
    fprintf(f, "shard 0/2\n");
    fclose(f);
    assert_int_equal(run("merge", "-o", at("b.qibl"), "--manifest", at("bad.txt"), NULL), 1);
    assert_true(says(errlog, "bad.txt:1: not \"shard I/N SUMS"));
    assert_int_equal(access(at("b.qibl"), F_OK), -1);
}

/* the thread count "on N threads" of a bake's summary line */
static int bake_threads(void)
{
    int rc = run("bake", "--size", "8x2", "--k", "1", "--dirs", "16", "--unshadowed-k", "0", "--progress=none",
                 "--sums", at("t.sums"), NULL);
    assert_int_equal(rc, 0);
    char *m = text(errlog), *p = strstr(m, " s on ");
    int n = p ? atoi(p + 6) : -1;
    free(m);
    return n;
}

/* threads from the job's allocation: the CPU affinity (taskset, cgroups) and SLURM_CPUS_PER_TASK;
 * both used to be ignored for the machine's CPU count */
static void test_threads_from_allocation(void **state)
{
    (void)state;
    need_qibl();
    cpu_set_t all, one;
    assert_int_equal(sched_getaffinity(0, sizeof all, &all), 0);
    int ncpu = CPU_COUNT(&all);
    unsetenv("SLURM_CPUS_PER_TASK");
    assert_int_equal(bake_threads(), ncpu > 256 ? 256 : ncpu);
    setenv("SLURM_CPUS_PER_TASK", "1", 1);
    assert_int_equal(bake_threads(), 1);
    setenv("SLURM_CPUS_PER_TASK", "junk", 1); /* ignored, not trusted */
    assert_int_equal(bake_threads(), ncpu > 256 ? 256 : ncpu);
    setenv("SLURM_CPUS_PER_TASK", "100000", 1); /* more than the mask: the mask wins */
    assert_int_equal(bake_threads(), ncpu > 256 ? 256 : ncpu);
    unsetenv("SLURM_CPUS_PER_TASK");
    if (ncpu < 2) {
        fprintf(stderr, "SKIP (part): one CPU in the affinity mask, no narrower mask to try\n");
        return;
    }
    CPU_ZERO(&one);
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &all)) {
            CPU_SET(c, &one);
            break;
        }
    assert_int_equal(sched_setaffinity(0, sizeof one, &one), 0); /* inherited by the spawned qibl */
    int n = bake_threads();
    assert_int_equal(sched_setaffinity(0, sizeof all, &all), 0);
    assert_int_equal(n, 1);
}

/* --progress=lines: one parseable line per step with the fraction done (the default off a
 * terminal, as here); none and --quiet print none; a bad mode is a usage error */
static void test_progress_lines(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", "--size", "8x5", "--k", "1", "--dirs", "16", "--unshadowed-k", "1", "--sun-path",
                         "40,15,7,17", "--threads", "1", "--shard", "0/1", "--sums", at("p.sums"), NULL), 0);
    char *m = text(errlog);
    int rows = 0, last = 0;
    for (char *l = m; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        unsigned d, t;
        char stage[32];
        double f;
        if (sscanf(l, "progress: stage=%31s done=%u total=%u fraction=%lf", stage, &d, &t, &f) == 4) {
            assert_true(d <= t && t > 0);
            assert_true(f >= 0 && f <= 1 && fabs(f - (double)d / t) < 1e-4);
            if (strcmp(stage, "shadowed") == 0)
                rows++, last = d == t;
        }
    }
    free(m);
    assert_int_equal(rows, 5), assert_true(last);
    assert_true(says(errlog, "progress: stage=unshadowed done=5 total=5 fraction=1.0000"));
    assert_true(says(errlog, "progress: stage=path done=1 total=1 fraction=1.0000"));
    assert_int_equal(run("bake", "--size", "8x5", "--k", "1", "--dirs", "16", "--threads", "1", "--progress=none",
                         "--sums", at("p.sums"), NULL), 0);
    m = text(errlog);
    assert_null(strstr(m, "progress:"));
    free(m);
    assert_int_equal(run("bake", "--progress=loud", "--sums", at("p.sums"), NULL), 2);
    assert_true(says(errlog, "qibl bake: --progress: 'loud' is not none, bar or lines; see qibl help bake"));
}

/* ---- tile shards (bake/tile.h) ------------------------------------------------------------------ */

/* pass 1 of tile i/n (extra: one more option pair, or NULL) into name */
static void tile1(uint32_t i, uint32_t n, const char *name, const char *o1, const char *v1)
{
    char in[32];
    snprintf(in, sizeof in, "%u/%u", i, n);
    int rc = run("bake", FARM_ARGS, "--tile", in, "--ranges-out", at(name), o1, v1, NULL);
    if (rc != 0) {
        char *m = text(errlog);
        fail_msg("bake --tile %s --ranges-out: exit %d: %s", in, rc, m);
    }
}

/* pass 2 of tile i/n against ranges into part; the exit status */
static int tile2(uint32_t i, uint32_t n, const char *ranges, const char *part, const char *o1, const char *v1)
{
    char in[32];
    snprintf(in, sizeof in, "%u/%u", i, n);
    return run("bake", FARM_ARGS, "--tile", in, "--ranges", at(ranges), "--part", at(part), o1, v1, NULL);
}

/* qibl merge [--ranges] -o out of up to 8 files (f NULL-padded); the exit status */
static int merge_files(int ranges, const char *out, char **f)
{
    return ranges ? run("merge", "--ranges", "-o", at(out), f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], NULL)
                  : run("merge", "-o", at(out), f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], NULL);
}

/* both passes of every tile of n and the reduction (tag names the files: TAGr_I, TAGR, TAGp_I); the
 * files given in reverse order. o1 v1: one more bake option pair (or NULL). */
static void tiles(uint32_t n, const char *tag, const char *o1, const char *v1)
{
    char rn[8][32], pn[8][32], red[32], *f[9] = {0};
    snprintf(red, sizeof red, "%sR", tag);
    for (uint32_t i = 0; i < n; ++i) {
        snprintf(rn[i], sizeof rn[i], "%sr_%u", tag, i), snprintf(pn[i], sizeof pn[i], "%sp_%u", tag, i);
        tile1(i, n, rn[i], o1, v1);
    }
    for (uint32_t i = 0; i < n; ++i)
        f[i] = at(rn[n - 1 - i]);
    if (merge_files(1, red, f) != 0) {
        char *m = text(errlog);
        fail_msg("merge --ranges of %u tiles: %s", n, m);
    }
    for (uint32_t i = 0; i < n; ++i)
        if (tile2(i, n, red, pn[i], o1, v1) != 0) {
            char *m = text(errlog);
            fail_msg("bake --tile %u/%u --part: %s", i, n, m);
        }
}

/* a copy of file a as b, cut to n bytes (n < 0: whole) and byte at flip (if >= 0) changed */
static void copy_bad(const char *a, const char *b, long n, long flip)
{
    size_t len;
    uint8_t *x = qtool_io_read_all(at(a), &len);
    char err[1200];
    assert_non_null(x);
    if (flip >= 0)
        x[flip] ^= 0x40;
    if (qtool_io_write_atomic(at(b), x, n >= 0 ? (size_t)n : len, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(x);
}

static long file_size(const char *a)
{
    size_t len;
    uint8_t *x = qtool_io_read_all(at(a), &len);
    assert_non_null(x);
    free(x);
    return (long)len;
}

/* the exit status 1, the message naming want, and out not written */
static void refused(int rc, const char *want, const char *out)
{
    assert_int_equal(rc, 1);
    assert_true(says(errlog, want));
    assert_int_equal(access(at(out), F_OK), -1);
}

/* every tile split the test names (1, 2, 3 of 7 rows: not divisible; 7: one row a band) merges to the
 * single bake byte for byte, light paths and lamp occlusion included; so does a least-squares,
 * interleaved bake without unshadowed maps */
static void test_tiles_identical(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("bake", FARM_ARGS, "-o", at("whole.qibl"), NULL), 0);
    static const uint32_t splits[] = {1, 2, 3, 7};
    for (size_t s = 0; s < sizeof splits / sizeof splits[0]; ++s) {
        uint32_t n = splits[s];
        char tag[8], out[32], pn[8][32], *f[9] = {0};
        snprintf(tag, sizeof tag, "t%u", n), snprintf(out, sizeof out, "t%u.qibl", n);
        tiles(n, tag, NULL, NULL);
        for (uint32_t i = 0; i < n; ++i)
            snprintf(pn[i], sizeof pn[i], "%sp_%u", tag, n - 1 - i), f[i] = at(pn[i]);
        if (merge_files(0, out, f) != 0) {
            char *m = text(errlog);
            fail_msg("merge of %u tile parts: %s", n, m);
        }
        file_eq(at("whole.qibl"), at(out));
    }
    assert_int_equal(run("bake", FARM_ARGS, "--lsq", "--layout", "interleaved", "-o", at("lsq.qibl"), NULL), 0);
    assert_int_equal(run("bake", FARM_ARGS, "--lsq", "--tile", "0/2", "--ranges-out", at("l0"), "--layout",
                         "interleaved", NULL), 0);
    assert_int_equal(run("bake", FARM_ARGS, "--lsq", "--tile", "1/2", "--ranges-out", at("l1"), "--layout",
                         "interleaved", NULL), 0);
    assert_int_equal(run("merge", "--ranges", "-o", at("lR"), at("l0"), at("l1"), NULL), 0);
    for (int i = 0; i < 2; ++i) {
        char in[32], part[32];
        snprintf(in, sizeof in, "%d/2", i), snprintf(part, sizeof part, "lp%d", i);
        assert_int_equal(run("bake", FARM_ARGS, "--lsq", "--tile", in, "--ranges", at("lR"), "--part", at(part),
                             "--layout", "interleaved", NULL), 0);
    }
    assert_int_equal(run("merge", "-o", at("lt.qibl"), at("lp1"), at("lp0"), NULL), 0);
    file_eq(at("lsq.qibl"), at("lt.qibl"));
    /* --cache: pass 2 takes pass 1's exact sums instead of baking again; the same bytes */
    char cache[600];
    snprintf(cache, sizeof cache, "%s", at("cache"));
    assert_int_equal(mkdir(cache, 0755), 0);
    tiles(2, "c", "--cache", cache);
    assert_true(says(outlog, "wrote ")), assert_true(says(outlog, "cp_1: tile 1/2, rows 3..6"));
    assert_true(says(outlog, "(sums from the cache)"));
    assert_int_equal(run("merge", "-o", at("c.qibl"), at("cp_0"), at("cp_1"), NULL), 0);
    file_eq(at("whole.qibl"), at("c.qibl"));
    /* a damaged cached file is not trusted: that set is baked again, the bytes the same */
    DIR *d = opendir(cache);
    assert_non_null(d);
    int damaged = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        static const char tail[] = "-0-of-2.sums"; /* tile 0's shadowed sums, not its .u */
        size_t l = strlen(e->d_name);
        if (l > sizeof tail - 1 && strcmp(e->d_name + l - (sizeof tail - 1), tail) == 0) {
            char name[700];
            snprintf(name, sizeof name, "cache/%s", e->d_name);
            copy_bad(name, name, -1, 100);
            damaged++;
        }
    }
    closedir(d);
    assert_int_equal(damaged, 1);
    assert_int_equal(tile2(0, 2, "cR", "cp_0", "--cache", cache), 0);
    assert_true(says(outlog, "(some sums from the cache)"));
    assert_int_equal(run("merge", "-o", at("c2.qibl"), at("cp_0"), at("cp_1"), NULL), 0);
    file_eq(at("whole.qibl"), at("c2.qibl"));
}

/* every bad input of the tile steps refused by name, nothing written: ranges and parts truncated or
 * damaged, of another bake, of another split (overlapping tiles), missing, given twice; pass 2 with
 * unreduced ranges, another bake's ranges or ranges that do not cover its maps; parts packed against
 * other ranges */
static void test_tile_refusals(void **state)
{
    (void)state;
    need_qibl();
    tiles(2, "a", NULL, NULL);
    char *f[9] = {0};
    /* reduce */
    f[0] = at("ar_0");
    refused(merge_files(1, "X", f), "merge: tile 1/2 is missing", "X");
    f[1] = at("ar_0");
    refused(merge_files(1, "X", f), "ar_0: tile 0/2 given twice (also", "X");
    tile1(1, 2, "k3r_1", "--k", "3");
    f[1] = at("k3r_1");
    refused(merge_files(1, "X", f), "k3r_1: the ranges of another bake than", "X");
    assert_true(says(errlog, "(k 3 against 4)"));
    tile1(1, 3, "n3r_1", NULL, NULL);
    f[1] = at("n3r_1");
    refused(merge_files(1, "X", f), "n3r_1: tile 1/3, ", "X");
    assert_true(says(errlog, "is of 2 tiles: overlapping tiles of another split"));
    f[0] = at("aR"), f[1] = at("ar_1");
    refused(merge_files(1, "X", f), "aR: already reduced", "X");
    copy_bad("ar_1", "cut", file_size("ar_1") - 1, -1);
    f[0] = at("ar_0"), f[1] = at("cut");
    refused(merge_files(1, "X", f), "cut: ", "X");
    assert_true(says(errlog, "truncated"));
    copy_bad("ar_1", "flip", -1, 60);
    f[1] = at("flip");
    refused(merge_files(1, "X", f), "flip: checksum mismatch in the ranges", "X");
    copy_bad("ar_1", "flip", -1, 8);
    refused(merge_files(1, "X", f), "flip: unsupported ranges version", "X");
    /* pass 2 */
    refused(tile2(1, 2, "ar_0", "P", NULL, NULL), "ar_0: the ranges of tile 0/2 alone", "P");
    tile1(0, 2, "k3r_0", "--k", "3");
    f[0] = at("k3r_0"), f[1] = at("k3r_1");
    assert_int_equal(merge_files(1, "k3R", f), 0);
    refused(tile2(1, 2, "k3R", "P", NULL, NULL), "k3R: the ranges of another bake (k 3 against 4)", "P");
    refused(tile2(1, 2, "cut", "P", NULL, NULL), "truncated", "P");
    qtool_tile_ranges r;
    char err[1200];
    if (qtool_tile_ranges_read(at("aR"), &r, err, sizeof err) != 0)
        fail_msg("%s", err);
    double hi0 = r.hi[0];
    r.hi[0] = r.lo[0]; /* narrower than the maps: refused */
    assert_int_equal(qtool_tile_ranges_write(&r, at("narrow"), err, sizeof err), 0);
    r.hi[0] = hi0 + 1; /* wider: a valid pass 2 whose bytes are not the others' */
    assert_int_equal(qtool_tile_ranges_write(&r, at("wide"), err, sizeof err), 0);
    qtool_tile_ranges_free(&r);
    refused(tile2(1, 2, "narrow", "P", NULL, NULL), "outside the ranges", "P");
    /* merge of parts */
    f[0] = at("ap_0"), f[1] = NULL;
    refused(merge_files(0, "X.qibl", f), "merge: tile 1/2 is missing", "X.qibl");
    f[1] = at("ap_0");
    refused(merge_files(0, "X.qibl", f), "ap_0: tile 0/2 given twice", "X.qibl");
    assert_int_equal(tile2(1, 2, "k3R", "k3p_1", "--k", "3"), 0);
    f[1] = at("k3p_1");
    refused(merge_files(0, "X.qibl", f), "k3p_1: a part of another bake than", "X.qibl");
    assert_int_equal(tile2(1, 2, "wide", "wp_1", NULL, NULL), 0);
    f[1] = at("wp_1");
    refused(merge_files(0, "X.qibl", f), "wp_1: packed against other ranges than", "X.qibl");
    tile1(0, 3, "n3r_0", NULL, NULL), tile1(2, 3, "n3r_2", NULL, NULL);
    f[0] = at("n3r_0"), f[1] = at("n3r_1"), f[2] = at("n3r_2");
    assert_int_equal(merge_files(1, "n3R", f), 0);
    assert_int_equal(tile2(1, 3, "n3R", "n3p_1", NULL, NULL), 0);
    f[0] = at("ap_0"), f[1] = at("n3p_1"), f[2] = NULL;
    refused(merge_files(0, "X.qibl", f), "n3p_1: tile 1/3, ", "X.qibl");
    assert_true(says(errlog, "overlapping tiles of another split"));
    copy_bad("ap_1", "pcut", file_size("ap_1") - 1, -1);
    f[1] = at("pcut");
    refused(merge_files(0, "X.qibl", f), "pcut: ", "X.qibl");
    assert_true(says(errlog, "(truncated)"));
    copy_bad("ap_1", "pflip", -1, 100);
    f[1] = at("pflip");
    refused(merge_files(0, "X.qibl", f), "pflip: checksum mismatch in the body", "X.qibl");
    copy_bad("ap_1", "pflip", -1, 20);
    refused(merge_files(0, "X.qibl", f), "pflip: header checksum mismatch", "X.qibl");
    /* the good set still merges */
    f[1] = at("ap_1");
    assert_int_equal(merge_files(0, "X.qibl", f), 0);
    /* option combinations */
    assert_int_equal(run("bake", FARM_ARGS, "--tile", "0/2", NULL), 2);
    assert_true(says(errlog, "--tile needs either --ranges-out FILE (pass 1) or --ranges FILE and --part FILE"));
    assert_int_equal(run("bake", FARM_ARGS, "--tile", "0/2", "--ranges-out", at("Y"), "-o", at("Y.qibl"), NULL), 2);
    assert_true(says(errlog, "no -o, --sums, --shard, --budget or --probe with it"));
    assert_int_equal(run("bake", FARM_ARGS, "--tile", "0/8", "--ranges-out", at("Y"), NULL), 2);
    assert_true(says(errlog, "--tile: 8 tiles but only 7 rows"));
    assert_int_equal(run("bake", FARM_ARGS, "--ranges-out", at("Y"), NULL), 2);
    assert_true(says(errlog, "the passes of a tile shard: give --tile I/N"));
    assert_int_equal(run("merge", "--ranges", "--sums", at("Y"), at("ar_0"), NULL), 2);
    assert_int_equal(access(at("Y"), F_OK), -1);
}

/* the usage lines: a shard refuses -o, so -o is not marked as required */
static void test_usage_lines(void **state)
{
    (void)state;
    need_qibl();
    assert_int_equal(run("merge", NULL), 2);
    assert_true(says(errlog, "qibl merge: needs -o ASSET or --sums OUT (or both)"));
    assert_int_equal(run("help", "bake", NULL), 0);
    assert_true(says(outlog, "usage: qibl bake (-o ASSET | --shard I/N --sums FILE | --tile I/N"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_every_split_identical_and_balanced, setup, teardown),
        cmocka_unit_test_setup_teardown(test_shard_without_path_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_extras_v1_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tree_merge, setup, teardown),
        cmocka_unit_test_setup_teardown(test_manifest, setup, teardown),
        cmocka_unit_test_setup_teardown(test_threads_from_allocation, setup, teardown),
        cmocka_unit_test_setup_teardown(test_progress_lines, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tiles_identical, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tile_refusals, setup, teardown),
        cmocka_unit_test_setup_teardown(test_usage_lines, setup, teardown),
    };
    return cmocka_run_group_tests_name("farm", tests, NULL, NULL);
}
