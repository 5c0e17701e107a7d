/*
 * json_test.c - tools/io/json.c: the token layout (subtree skips, counts), escapes decoded, numbers,
 * and every malformed or hostile text refused with its named one-line error and nothing allocated.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "io/json.h"

static void test_structure(void **state)
{
    (void)state;
    const char *t = "\xEF\xBB\xBF { \"a\" : [1, -2.5e3, true, false, null, {\"x\": []}], \"b\\u0041\": \"s\\n\\u00e9\\ud83d\\ude00\","
                    " \"a\": 7 }\n";
    qtool_json_doc d;
    char err[256];
    if (qtool_json_parse(t, strlen(t), &d, err, sizeof err) != 0)
        fail_msg("%s", err);
    const qtool_json_tok *r = d.tok;
    assert_int_equal(r->type, QTOOL_JSON_OBJECT);
    assert_int_equal(r->count, 3);
    assert_int_equal(r->next, d.ntok);
    const qtool_json_tok *a = qtool_json_get(&d, r, "a"); /* the first of two "a" */
    assert_int_equal(a->type, QTOOL_JSON_ARRAY);
    assert_int_equal(a->count, 6);
    const qtool_json_tok *e = qtool_json_first(&d, a);
    assert_true(e->type == QTOOL_JSON_NUMBER && e->num == 1);
    e = qtool_json_skip(&d, e);
    assert_true(e->num == -2500);
    e = qtool_json_skip(&d, e);
    assert_int_equal(e->type, QTOOL_JSON_TRUE);
    e = qtool_json_skip(&d, qtool_json_skip(&d, qtool_json_skip(&d, e)));
    assert_int_equal(e->type, QTOOL_JSON_OBJECT);
    const qtool_json_tok *x = qtool_json_get(&d, e, "x");
    assert_true(x->type == QTOOL_JSON_ARRAY && x->count == 0 && qtool_json_first(&d, x) == NULL);
    /* the escaped key "b\u0041" is "bA"; its value decodes \n, e-acute and an astral pair */
    const qtool_json_tok *s = qtool_json_get(&d, r, "bA");
    assert_non_null(s);
    char buf[32];
    assert_int_equal(qtool_json_str(&d, s, buf, sizeof buf), 8);
    assert_string_equal(buf, "s\n\xC3\xA9\xF0\x9F\x98\x80");
    assert_int_equal(qtool_json_str(&d, s, buf, 8), -1); /* does not fit */
    assert_null(qtool_json_get(&d, r, "c"));
    assert_null(qtool_json_get(&d, a, "a")); /* not an object */
    qtool_json_free(&d);
}

static void refused(const char *t, size_t n, const char *needle)
{
    qtool_json_doc d;
    char err[256];
    memset(&d, 0x5A, sizeof d);
    qtool_json_doc before = d;
    if (qtool_json_parse(t, n, &d, err, sizeof err) != -1)
        fail_msg("'%.40s' accepted; '%s' expected", t, needle);
    if (!strstr(err, needle))
        fail_msg("'%.40s': error '%s' does not mention '%s'", t, err, needle);
    assert_null(strchr(err, '\n'));
    assert_memory_equal(&d, &before, sizeof d);
}

static void test_refused(void **state)
{
    (void)state;
    static const char *const bad[][2] = {
        {"", "byte 0: no value"},
        {"   ", "no value"},
        {"[1,]", "byte 3: bad value"},
        {"[1 2]", "expected ',' or ']'"},
        {"{\"a\" 1}", "expected ':' after a key"},
        {"{1:2}", "expected a string key"},
        {"{\"a\":1,}", "expected a string key"},
        {"[01]", "expected ',' or ']'"},
        {"[1.]", "no digit after '.'"},
        {"[1e+]", "no digit in the exponent"},
        {"[-]", "bad value"},
        {"[1e999]", "out of range"},
        {"[tru]", "bad value"},
        {"\"abc", "unterminated string"},
        {"\"a\\x\"", "bad escape '\\x'"},
        {"\"\\u12G4\"", "bad \\u escape"},
        {"\"a\tb\"", "control character 0x09"},
        {"[1] x", "text after the JSON value"},
        {"{\"a\":[1,2", "unexpected end of text inside an array"},
        {"{\"a\":1", "unexpected end of text inside an object"},
        {"[12345678901234567890123456789012345678901234567890123456789012345]", "number of 65 characters"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i)
        refused(bad[i][0], strlen(bad[i][0]), bad[i][1]);
    /* a NUL inside the text is a control character in a string, else not a value */
    refused("\"a\0b\"", 5, "control character 0x00");
    /* depth: 64 levels parse, 65 do not */
    char deep[256];
    memset(deep, '[', 64);
    memset(deep + 64, ']', 64);
    qtool_json_doc d;
    char err[256];
    assert_int_equal(qtool_json_parse(deep, 128, &d, err, sizeof err), 0);
    assert_int_equal(d.ntok, 64);
    qtool_json_free(&d);
    memset(deep, '[', 65);
    memset(deep + 65, ']', 65);
    refused(deep, 130, "nesting deeper than 64 (QTOOL_JSON_MAX_DEPTH)");
    /* a key longer than QTOOL_JSON_MAX_KEY */
    char key[400];
    int o = snprintf(key, sizeof key, "{\"");
    memset(key + o, 'k', QTOOL_JSON_MAX_KEY + 1);
    snprintf(key + o + QTOOL_JSON_MAX_KEY + 1, sizeof key - (size_t)o - QTOOL_JSON_MAX_KEY - 1, "\":1}");
    refused(key, strlen(key), "object key of 257 bytes (at most 256, QTOOL_JSON_MAX_KEY)");
}

/* values never outnumber the text's bytes: the token array stays within 32 bytes per input byte */
static void test_tokens_bounded(void **state)
{
    (void)state;
    size_t n = (1 << 16) - 1; /* "[0,0,...,0]" */
    char *t = malloc(n);
    assert_non_null(t);
    t[0] = '[';
    for (size_t i = 1; i + 1 < n; i += 2)
        t[i] = '0', t[i + 1] = ',';
    t[n - 1] = ']';
    t[n - 2] = '0';
    qtool_json_doc d;
    char err[256];
    assert_int_equal(qtool_json_parse(t, n, &d, err, sizeof err), 0);
    assert_true(d.ntok <= n);
    assert_int_equal(d.tok[0].count, d.ntok - 1);
    qtool_json_free(&d);
    free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_structure),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_tokens_bounded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
