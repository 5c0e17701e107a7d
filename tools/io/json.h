/*
 * io/json.h - a small bounded JSON (RFC 8259) parser for the glTF reader. Hosted, libc only.
 *
 * The text is parsed once, without recursion, into a flat array of tokens in document order: a
 * container is followed by its children (an object's as key, value, key, value ...), and every
 * token knows the index just past its subtree, so skipping a value costs O(1). Strings stay as
 * spans of the caller's text (escapes are checked while parsing and decoded on request); numbers
 * are parsed with strtod after the JSON grammar has been checked.
 *
 * Limits (each a named one-line error giving the byte offset; nothing is allocated on failure):
 *   - nesting at most QTOOL_JSON_MAX_DEPTH arrays/objects;
 *   - at most QTOOL_JSON_MAX_TOKENS values (and never more than the text's bytes: every value takes
 *     at least one), so memory is at most sizeof(qtool_json_tok) = 32 bytes per input byte;
 *   - an object key at most QTOOL_JSON_MAX_KEY bytes; a number at most 64 characters and finite;
 *   - strings: no raw control characters, only the JSON escapes, \u with four hex digits; bytes
 *     above 0x7F are passed through (not checked as UTF-8).
 * Duplicate keys are kept; qtool_json_get returns the first. Trailing text after the value, a
 * leading UTF-8 byte order mark excepted, is refused.
 */
#ifndef QTOOL_IO_JSON_H
#define QTOOL_IO_JSON_H

#include <stddef.h>
#include <stdint.h>

#define QTOOL_JSON_MAX_DEPTH 64
#define QTOOL_JSON_MAX_TOKENS ((size_t)1 << 24)
#define QTOOL_JSON_MAX_KEY 256

typedef enum {
    QTOOL_JSON_NULL = 0,
    QTOOL_JSON_FALSE,
    QTOOL_JSON_TRUE,
    QTOOL_JSON_NUMBER,
    QTOOL_JSON_STRING,
    QTOOL_JSON_ARRAY,
    QTOOL_JSON_OBJECT
} qtool_json_type;

typedef struct qtool_json_tok {
    double num;      /* NUMBER: the value */
    size_t start;    /* STRING: offset of the first byte after the opening quote; else of the value */
    uint32_t len;    /* STRING: raw (escaped) length in bytes */
    uint32_t count;  /* ARRAY: elements; OBJECT: members (key/value pairs) */
    uint32_t next;   /* index of the first token after this value's subtree */
    uint8_t type;    /* qtool_json_type */
} qtool_json_tok;

typedef struct qtool_json_doc {
    const char *text;
    size_t len;
    qtool_json_tok *tok; /* tok[0] is the root value */
    size_t ntok;
} qtool_json_doc;

/* Parses len bytes of text (not copied: it must outlive doc). 0, or -1 with a one-line reason
 * ("json: byte N: ...") in err and nothing allocated. */
int qtool_json_parse(const char *text, size_t len, qtool_json_doc *doc, char *err, size_t errlen);
void qtool_json_free(qtool_json_doc *doc);

/* The value of key in object obj (first match), or NULL (obj NULL or not an object: NULL). */
const qtool_json_tok *qtool_json_get(const qtool_json_doc *doc, const qtool_json_tok *obj, const char *key);
/* The first child of an array or object (for an object, its first key), or NULL if empty. */
const qtool_json_tok *qtool_json_first(const qtool_json_doc *doc, const qtool_json_tok *t);
/* The token after t's subtree, for walking siblings; the caller counts them (parent's count). */
const qtool_json_tok *qtool_json_skip(const qtool_json_doc *doc, const qtool_json_tok *t);
/* Decodes a string into buf (cap bytes, NUL-terminated; \u escapes as UTF-8, \u0000 refused).
 * Returns its decoded length, or -1 if t is not a string, it does not fit or holds a NUL. */
long qtool_json_str(const qtool_json_doc *doc, const qtool_json_tok *t, char *buf, size_t cap);
/* 1 if t is a string equal to s after decoding. */
int qtool_json_str_eq(const qtool_json_doc *doc, const qtool_json_tok *t, const char *s);

#endif
