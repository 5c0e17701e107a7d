/*
 * fuzz_json.c - libFuzzer target: the bounded JSON parser (tools/io/json.c).
 *
 * Invariants: a failure leaves the document untouched, allocates nothing and gives a one-line
 * reason; a success gives at most one token per input byte, every token's subtree end after it and
 * within the document, containers whose children (counted by walking the skips) match their
 * counts, object keys that are strings, and strings that decode or are refused without overrun.
 */
#include <string.h>

#include "fuzz.h"
#include "io/json.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256];
    qtool_json_doc d, before;
    memset(&d, 0xA5, sizeof d);
    memcpy(&before, &d, sizeof d);
    memset(err, 0, sizeof err);
    int rc = qtool_json_parse((const char *)data, size, &d, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1 && memcmp(&d, &before, sizeof d) == 0);
        FUZZ_CHECK(fuzz_one_line(err, sizeof err));
        return 0;
    }
    FUZZ_CHECK(d.ntok >= 1 && d.ntok <= size && d.tok[0].next == d.ntok);
    for (size_t i = 0; i < d.ntok; ++i) {
        const qtool_json_tok *t = &d.tok[i];
        FUZZ_CHECK(t->next > i && t->next <= d.ntok);
        if (t->type == QTOOL_JSON_ARRAY || t->type == QTOOL_JSON_OBJECT) {
            const qtool_json_tok *c = qtool_json_first(&d, t);
            uint32_t n = 0;
            while (c && c < d.tok + t->next) {
                if (t->type == QTOOL_JSON_OBJECT) {
                    FUZZ_CHECK(c->type == QTOOL_JSON_STRING);
                    c = c + 1;
                    FUZZ_CHECK(c < d.tok + t->next);
                }
                ++n;
                c = c->next < d.ntok ? d.tok + c->next : NULL;
            }
            FUZZ_CHECK(n == t->count);
        } else {
            FUZZ_CHECK(t->next == i + 1);
        }
        if (t->type == QTOOL_JSON_STRING) {
            FUZZ_CHECK(t->start + t->len < size);
            char buf[64];
            long l = qtool_json_str(&d, t, buf, sizeof buf);
            FUZZ_CHECK(l < (long)sizeof buf && (l < 0 || buf[l] == '\0'));
        }
    }
    qtool_json_free(&d);
    return 0;
}
