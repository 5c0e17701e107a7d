/*
 * io/json.c - bounded JSON parser: one pass, an explicit stack of open containers (no recursion),
 * tokens in a growing array capped before every growth.
 */
#include "io/json.h"
#include "qtool.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const char *s;
    size_t len, pos;
    qtool_json_tok *tok;
    size_t ntok, cap, max;
    char *err;
    size_t errlen;
} parser;

static int fail(parser *p, const char *fmt, ...)
{
    char at[48];
    snprintf(at, sizeof at, "json: byte %zu", p->pos);
    va_list ap;
    va_start(ap, fmt);
    qtool_verrf_at(p->err, p->errlen, at, 0, fmt, ap);
    va_end(ap);
    return -1;
}

static void ws(parser *p)
{
    while (p->pos < p->len) {
        char c = p->s[p->pos];
        if (c != ' ' && c != '\t' && c != '\n' && c != '\r')
            break;
        ++p->pos;
    }
}

static long push(parser *p, qtool_json_type type)
{
    if (p->ntok >= p->max)
        return fail(p, "more than %zu values (QTOOL_JSON_MAX_TOKENS, or one per byte of text)", p->max);
    if (p->ntok == p->cap) {
        size_t cap = p->cap ? p->cap * 2 : 64;
        if (cap > p->max)
            cap = p->max;
        qtool_json_tok *t = realloc(p->tok, cap * sizeof *t);
        if (!t)
            return fail(p, "out of memory");
        p->tok = t, p->cap = cap;
    }
    qtool_json_tok *t = &p->tok[p->ntok];
    memset(t, 0, sizeof *t);
    t->type = (uint8_t)type, t->start = p->pos;
    return (long)p->ntok++;
}

static int hex(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* at the opening quote; checks the string and leaves pos after the closing quote */
static int string(parser *p, int key)
{
    long i = push(p, QTOOL_JSON_STRING);
    if (i < 0)
        return -1;
    size_t b = ++p->pos;
    while (p->pos < p->len) {
        unsigned char c = (unsigned char)p->s[p->pos];
        if (c == '"')
            break;
        if (c < 0x20)
            return fail(p, "control character 0x%02x in a string", c);
        if (c == '\\') {
            if (p->pos + 1 >= p->len)
                break;
            char e = p->s[p->pos + 1];
            if (e == 'u') {
                if (p->pos + 6 > p->len)
                    break;
                for (int k = 2; k < 6; ++k)
                    if (hex(p->s[p->pos + (size_t)k]) < 0)
                        return fail(p, "bad \\u escape (four hex digits)");
                p->pos += 6;
                continue;
            }
            if (!strchr("\"\\/bfnrt", e) || !e)
                return fail(p, "bad escape '\\%c'", e >= 0x20 && e < 0x7f ? e : '?');
            p->pos += 2;
            continue;
        }
        ++p->pos;
    }
    if (p->pos >= p->len)
        return fail(p, "unterminated string");
    size_t n = p->pos - b;
    if (key && n > QTOOL_JSON_MAX_KEY)
        return fail(p, "object key of %zu bytes (at most %d, QTOOL_JSON_MAX_KEY)", n, QTOOL_JSON_MAX_KEY);
    if (n > UINT32_MAX)
        return fail(p, "string of %zu bytes", n);
    p->tok[i].start = b, p->tok[i].len = (uint32_t)n, p->tok[i].next = (uint32_t)p->ntok;
    ++p->pos;
    return 0;
}

static int number(parser *p)
{
    size_t b = p->pos, q = b;
    const char *s = p->s;
#define DIG(k) ((k) < p->len && s[k] >= '0' && s[k] <= '9')
    if (q < p->len && s[q] == '-')
        ++q;
    if (!DIG(q))
        return fail(p, "bad value");
    if (s[q] == '0')
        ++q;
    else
        while (DIG(q))
            ++q;
    if (q < p->len && s[q] == '.') {
        ++q;
        if (!DIG(q))
            return fail(p, "bad number: no digit after '.'");
        while (DIG(q))
            ++q;
    }
    if (q < p->len && (s[q] == 'e' || s[q] == 'E')) {
        ++q;
        if (q < p->len && (s[q] == '+' || s[q] == '-'))
            ++q;
        if (!DIG(q))
            return fail(p, "bad number: no digit in the exponent");
        while (DIG(q))
            ++q;
    }
#undef DIG
    char buf[65];
    if (q - b > 64)
        return fail(p, "number of %zu characters (at most 64)", q - b);
    memcpy(buf, s + b, q - b);
    buf[q - b] = '\0';
    double v = strtod(buf, NULL);
    if (!isfinite(v))
        return fail(p, "number %s out of range", buf);
    long i = push(p, QTOOL_JSON_NUMBER);
    if (i < 0)
        return -1;
    p->tok[i].num = v, p->tok[i].next = (uint32_t)p->ntok;
    p->pos = q;
    return 0;
}

static int literal(parser *p, const char *w, qtool_json_type type)
{
    size_t n = strlen(w);
    if (p->len - p->pos < n || memcmp(p->s + p->pos, w, n) != 0)
        return fail(p, "bad value");
    long i = push(p, type);
    if (i < 0)
        return -1;
    p->tok[i].next = (uint32_t)p->ntok;
    p->pos += n;
    return 0;
}

/* an object member's key and its ':' (the value follows) */
static int member_key(parser *p)
{
    ws(p);
    if (p->pos >= p->len || p->s[p->pos] != '"')
        return fail(p, "expected a string key");
    if (string(p, 1) != 0)
        return -1;
    ws(p);
    if (p->pos >= p->len || p->s[p->pos] != ':')
        return fail(p, "expected ':' after a key");
    ++p->pos;
    return 0;
}

int qtool_json_parse(const char *text, size_t len, qtool_json_doc *doc, char *err, size_t errlen)
{
    parser p = {.s = text, .len = len, .err = err, .errlen = errlen};
    p.max = len < QTOOL_JSON_MAX_TOKENS ? len : QTOOL_JSON_MAX_TOKENS;
    uint32_t stack[QTOOL_JSON_MAX_DEPTH]; /* open containers */
    int sp = 0;
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0)
        p.pos = 3;
    /* state: expecting a value (after '[', ',' in an array, ':' or at the start) */
    for (;;) {
        ws(&p);
        if (p.pos >= len) {
            if (sp)
                fail(&p, "unexpected end of text inside %s",
                     p.tok[stack[sp - 1]].type == QTOOL_JSON_OBJECT ? "an object" : "an array");
            else
                fail(&p, "no value");
            goto bad;
        }
        char c = text[p.pos];
        int opened = 0;
        if (c == '{' || c == '[') {
            if (sp == QTOOL_JSON_MAX_DEPTH) {
                fail(&p, "nesting deeper than %d (QTOOL_JSON_MAX_DEPTH)", QTOOL_JSON_MAX_DEPTH);
                goto bad;
            }
            long i = push(&p, c == '{' ? QTOOL_JSON_OBJECT : QTOOL_JSON_ARRAY);
            if (i < 0)
                goto bad;
            stack[sp++] = (uint32_t)i;
            ++p.pos;
            ws(&p);
            if (p.pos < len && text[p.pos] == (c == '{' ? '}' : ']')) {
                ++p.pos;
                p.tok[stack[--sp]].next = (uint32_t)p.ntok;
            } else
                opened = 1;
        } else if (c == '"') {
            if (string(&p, 0) != 0)
                goto bad;
        } else if (c == 't' || c == 'f' || c == 'n') {
            if (literal(&p, c == 't' ? "true" : c == 'f' ? "false" : "null",
                        c == 't' ? QTOOL_JSON_TRUE : c == 'f' ? QTOOL_JSON_FALSE : QTOOL_JSON_NULL) != 0)
                goto bad;
        } else if (number(&p) != 0) {
            goto bad;
        }
        /* an object member: key then ':' before its value */
        if (opened && p.tok[stack[sp - 1]].type == QTOOL_JSON_OBJECT) {
            if (member_key(&p) != 0)
                goto bad;
            ++p.tok[stack[sp - 1]].count;
            continue;
        }
        if (opened) {
            ++p.tok[stack[sp - 1]].count;
            continue;
        }
        /* a value is complete: close containers or take the separator */
        for (;;) {
            if (sp == 0) {
                ws(&p);
                if (p.pos != len) {
                    fail(&p, "text after the JSON value");
                    goto bad;
                }
                doc->text = text, doc->len = len, doc->tok = p.tok, doc->ntok = p.ntok;
                return 0;
            }
            qtool_json_tok *top = &p.tok[stack[sp - 1]];
            int obj = top->type == QTOOL_JSON_OBJECT;
            ws(&p);
            if (p.pos >= len) {
                fail(&p, "unexpected end of text inside %s", obj ? "an object" : "an array");
                goto bad;
            }
            c = text[p.pos];
            if (c == (obj ? '}' : ']')) {
                ++p.pos;
                top->next = (uint32_t)p.ntok;
                --sp;
                continue;
            }
            if (c != ',') {
                fail(&p, "expected ',' or '%c'", obj ? '}' : ']');
                goto bad;
            }
            ++p.pos;
            ++top->count;
            if (obj && member_key(&p) != 0)
                goto bad;
            break;
        }
    }
bad:
    free(p.tok);
    return -1;
}

void qtool_json_free(qtool_json_doc *doc)
{
    free(doc->tok);
    memset(doc, 0, sizeof *doc);
}

const qtool_json_tok *qtool_json_first(const qtool_json_doc *doc, const qtool_json_tok *t)
{
    if (!t || (t->type != QTOOL_JSON_ARRAY && t->type != QTOOL_JSON_OBJECT) || t->count == 0)
        return NULL;
    return t + 1 < doc->tok + doc->ntok ? t + 1 : NULL;
}

const qtool_json_tok *qtool_json_skip(const qtool_json_doc *doc, const qtool_json_tok *t)
{
    return t->next < doc->ntok ? doc->tok + t->next : NULL;
}

const qtool_json_tok *qtool_json_get(const qtool_json_doc *doc, const qtool_json_tok *obj, const char *key)
{
    if (!obj || obj->type != QTOOL_JSON_OBJECT)
        return NULL;
    const qtool_json_tok *k = qtool_json_first(doc, obj);
    for (uint32_t i = 0; k && i < obj->count; ++i) {
        const qtool_json_tok *v = k + 1;
        if (qtool_json_str_eq(doc, k, key))
            return v;
        k = qtool_json_skip(doc, v);
    }
    return NULL;
}

long qtool_json_str(const qtool_json_doc *doc, const qtool_json_tok *t, char *buf, size_t cap)
{
    if (!t || t->type != QTOOL_JSON_STRING || cap == 0)
        return -1;
    const char *s = doc->text + t->start;
    size_t o = 0;
    for (size_t i = 0; i < t->len;) {
        char c = s[i];
        unsigned long u;
        unsigned char enc[4];
        int n = 1;
        if (c != '\\') {
            enc[0] = (unsigned char)c, ++i;
        } else {
            char e = s[i + 1];
            i += 2;
            switch (e) {
            case 'b': enc[0] = '\b'; break;
            case 'f': enc[0] = '\f'; break;
            case 'n': enc[0] = '\n'; break;
            case 'r': enc[0] = '\r'; break;
            case 't': enc[0] = '\t'; break;
            case 'u':
                u = (unsigned long)(hex(s[i]) << 12 | hex(s[i + 1]) << 8 | hex(s[i + 2]) << 4 | hex(s[i + 3]));
                i += 4;
                /* a surrogate pair as one code point; a lone surrogate is kept as its 3 bytes */
                if (u >= 0xD800 && u < 0xDC00 && i + 6 <= t->len && s[i] == '\\' && s[i + 1] == 'u') {
                    unsigned long lo = (unsigned long)(hex(s[i + 2]) << 12 | hex(s[i + 3]) << 8 | hex(s[i + 4]) << 4 |
                                                       hex(s[i + 5]));
                    if (lo >= 0xDC00 && lo < 0xE000) {
                        u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00);
                        i += 6;
                    }
                }
                if (u == 0)
                    return -1;
                if (u < 0x80)
                    enc[0] = (unsigned char)u;
                else if (u < 0x800)
                    enc[0] = (unsigned char)(0xC0 | u >> 6), enc[1] = (unsigned char)(0x80 | (u & 63)), n = 2;
                else if (u < 0x10000)
                    enc[0] = (unsigned char)(0xE0 | u >> 12), enc[1] = (unsigned char)(0x80 | (u >> 6 & 63)),
                    enc[2] = (unsigned char)(0x80 | (u & 63)), n = 3;
                else
                    enc[0] = (unsigned char)(0xF0 | u >> 18), enc[1] = (unsigned char)(0x80 | (u >> 12 & 63)),
                    enc[2] = (unsigned char)(0x80 | (u >> 6 & 63)), enc[3] = (unsigned char)(0x80 | (u & 63)), n = 4;
                break;
            default: enc[0] = (unsigned char)e; break; /* " \ / */
            }
        }
        if (o + (size_t)n >= cap)
            return -1;
        for (int k = 0; k < n; ++k) {
            if (enc[k] == 0)
                return -1;
            buf[o++] = (char)enc[k];
        }
    }
    buf[o] = '\0';
    return (long)o;
}

int qtool_json_str_eq(const qtool_json_doc *doc, const qtool_json_tok *t, const char *s)
{
    if (!t || t->type != QTOOL_JSON_STRING)
        return 0;
    size_t n = strlen(s);
    /* fast path: no escapes */
    if (t->len == n && memcmp(doc->text + t->start, s, n) == 0)
        return 1;
    if (!memchr(doc->text + t->start, '\\', t->len) || t->len > QTOOL_JSON_MAX_KEY)
        return 0;
    char buf[QTOOL_JSON_MAX_KEY + 1];
    long m = qtool_json_str(doc, t, buf, sizeof buf);
    return m >= 0 && (size_t)m == n && memcmp(buf, s, n) == 0;
}
