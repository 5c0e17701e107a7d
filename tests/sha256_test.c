/*
 * sha256_test.c - tools/io/sha256: the FIPS 180-2 / NIST example vectors ("abc", "", the 448- and
 * 896-bit messages, one million 'a' fed in odd chunk sizes), messages around the 55/56/64-byte
 * padding boundaries (expected digests from an independent implementation), and incremental
 * updates split at every point agreeing with the one-shot digest. Also the golden helper's
 * comparison (tools/io/golden) in a temporary QIBL_ROOT.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "io/golden.h"
#include "io/sha256.h"

static void check_hex(const char *msg, const char *want)
{
    char got[65];
    qtool_sha256_hex(msg, strlen(msg), got);
    assert_string_equal(got, want);
}

static void test_nist_vectors(void **state)
{
    (void)state;
    check_hex("abc", "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    check_hex("", "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    check_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq",
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    check_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrs"
              "mnopqrstnopqrstu",
              "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
    char got[65];
    qtool_sha256_hex(NULL, 0, got); /* NULL with n == 0 is allowed */
    assert_string_equal(got, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

static void test_million_a_in_odd_chunks(void **state)
{
    (void)state;
    static char a[1000];
    memset(a, 'a', sizeof a);
    const size_t chunks[] = {1, 3, 7, 13, 55, 56, 63, 64, 65, 127, 129, 997};
    qtool_sha256_t s;
    qtool_sha256_init(&s);
    size_t done = 0;
    for (unsigned k = 0; done < 1000000; ++k) {
        size_t n = chunks[k % (sizeof chunks / sizeof chunks[0])];
        if (n > 1000000 - done)
            n = 1000000 - done;
        qtool_sha256_update(&s, a, n);
        qtool_sha256_update(&s, a, 0);
        done += n;
    }
    uint8_t d[32];
    char got[65];
    qtool_sha256_final(&s, d);
    qtool_sha256_to_hex(d, got);
    assert_string_equal(got, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

static void test_padding_boundaries(void **state)
{
    (void)state;
    /* message bytes (7i + 3) mod 256; digests from Python's hashlib */
    static const struct { size_t n; const char *hex; } v[] = {
        {55, "e7313d333c272e639f790978283f9eb392e843d0f29b7016828bb1daa4aac70b"},
        {56, "4324d65f3c103567f5589c710bc08f8523f929a9272e3af36fc968e52abc6c27"},
        {57, "35df609437dcfea3279283ab79fd554e2bf78f8f7ae2de532d8ee300b09e8f73"},
        {63, "81c80242132f230c3bd41b3e63bbcff16107339549214a99614ff26664625055"},
        {64, "39e3d7b6b5d075d37d053ad89b24b41bef4f3c29760c84447cab3f3be1882241"},
        {65, "aacca6ff74fdbb296d165a45cecfa04e5127bc008770fbbdd48006f2d2fae95e"},
        {119, "9ce7368e4daf32341631b492e80359dc9f594b48453cd0dd5bf0b19279cc177e"},
        {120, "7836b787757e95e58b3ca5aec90b1b004e8deba1e50e9675af9cabf1a13a04b5"},
        {128, "d2742f1f4ac6bb7ca2b239ee18402ba8b3f9f8e652d2a72973c2b9ba11c08cf6"},
    };
    uint8_t m[200];
    for (int i = 0; i < 200; ++i)
        m[i] = (uint8_t)(i * 7 + 3);
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) {
        char got[65];
        qtool_sha256_hex(m, v[k].n, got);
        assert_string_equal(got, v[k].hex);
    }
    /* every split point of every length up to 200 gives the one-shot digest */
    for (size_t n = 0; n <= 200; ++n) {
        char want[65];
        qtool_sha256_hex(m, n, want);
        for (size_t cut = 0; cut <= n; ++cut) {
            qtool_sha256_t s;
            uint8_t d[32];
            char got[65];
            qtool_sha256_init(&s);
            qtool_sha256_update(&s, m, cut);
            qtool_sha256_update(&s, m + cut, n - cut);
            qtool_sha256_final(&s, d);
            qtool_sha256_to_hex(d, got);
            assert_string_equal(got, want);
        }
    }
}

/* the golden helper against files in a temporary root */
static void test_golden_helper(void **state)
{
    (void)state;
    char root[] = "/tmp/qibl-golden-XXXXXX";
    assert_non_null(mkdtemp(root));
    const char *old_root = getenv("QIBL_ROOT"), *old_upd = getenv("QIBL_UPDATE_GOLDEN");
    char *saved_root = old_root ? strdup(old_root) : NULL, *saved_upd = old_upd ? strdup(old_upd) : NULL;
    setenv("QIBL_ROOT", root, 1);
    const char *h1 = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
    const char *h2 = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";

    unsetenv("QIBL_UPDATE_GOLDEN");
    assert_int_equal(qtool_golden_check("case_a", h1), -1); /* no file yet */
    setenv("QIBL_UPDATE_GOLDEN", "1", 1);
    assert_int_equal(qtool_golden_check("case_a", h1), 0); /* creates fixtures/golden/case_a.sha256 */
    unsetenv("QIBL_UPDATE_GOLDEN");
    assert_int_equal(qtool_golden_check("case_a", h1), 0);
    assert_int_equal(qtool_golden_check("case_a", h2), -1);
    assert_int_equal(qtool_golden_check_bytes("case_a", "abc", 3), 0);
    /* file content: the digest and a newline */
    char path[256], line[128] = {0};
    snprintf(path, sizeof path, "%s/fixtures/golden/case_a.sha256", root);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    assert_non_null(fgets(line, sizeof line, f));
    fclose(f);
    assert_int_equal(strlen(line), 65);
    assert_int_equal(line[64], '\n');
    /* bad names and hashes are refused, nothing written */
    setenv("QIBL_UPDATE_GOLDEN", "1", 1);
    assert_int_equal(qtool_golden_check("../evil", h1), -1);
    assert_int_equal(qtool_golden_check(".hidden", h1), -1);
    assert_int_equal(qtool_golden_check("", h1), -1);
    assert_int_equal(qtool_golden_check("case_b", "BA7816BF"), -1);
    unsetenv("QIBL_UPDATE_GOLDEN");

    remove(path);
    snprintf(path, sizeof path, "%s/fixtures/golden", root);
    assert_int_equal(rmdir(path), 0); /* empty: nothing else was written */
    snprintf(path, sizeof path, "%s/fixtures", root);
    assert_int_equal(rmdir(path), 0);
    assert_int_equal(rmdir(root), 0);
    if (saved_root) setenv("QIBL_ROOT", saved_root, 1); else unsetenv("QIBL_ROOT");
    if (saved_upd) setenv("QIBL_UPDATE_GOLDEN", saved_upd, 1);
    free(saved_root);
    free(saved_upd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nist_vectors),
        cmocka_unit_test(test_million_a_in_odd_chunks),
        cmocka_unit_test(test_padding_boundaries),
        cmocka_unit_test(test_golden_helper),
    };
    return cmocka_run_group_tests_name("sha256", tests, NULL, NULL);
}
