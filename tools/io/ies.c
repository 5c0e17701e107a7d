/*
 * io/ies.c - IES LM-63 reader, flux integral and candela lookup (see ies.h).
 *
 * The header is line-based up to TILT=; everything after it is a stream of numbers separated by
 * blanks, commas or line breaks (files wrap the lists anywhere). Every count is checked against
 * its cap and against what the rest of the file can hold before anything is allocated, so a short
 * hostile file never costs more than its own size.
 */
#include "io/ies.h"
#include "io/file.h"
#include "qibl/gonio.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "qtool.h"


/* ---- header lines ------------------------------------------------------------------------- */

/* [*pos, end of line) without its break (LF, CR LF, or a lone CR as old Mac files have); advances
 * *pos past the break */
static size_t next_line(const uint8_t *buf, size_t len, size_t *pos, size_t *start)
{
    size_t s = *pos, e = s;
    while (e < len && buf[e] != '\n' && buf[e] != '\r')
        ++e;
    *start = s;
    *pos = e;
    if (*pos < len && buf[*pos] == '\r')
        ++*pos;
    if (*pos < len && buf[*pos] == '\n')
        ++*pos;
    return e - s;
}

static int starts(const uint8_t *p, size_t n, const char *pre)
{
    size_t k = strlen(pre);
    return n >= k && memcmp(p, pre, k) == 0;
}

static void keep_text(char dst[QTOOL_IES_TEXT], const uint8_t *p, size_t n)
{
    while (n && (*p == ' ' || *p == '\t'))
        ++p, --n;
    while (n && (p[n - 1] == ' ' || p[n - 1] == '\t'))
        --n;
    if (n >= QTOOL_IES_TEXT)
        n = QTOOL_IES_TEXT - 1;
    for (size_t i = 0; i < n; ++i)
        dst[i] = (p[i] >= 0x20 && p[i] < 0x7F) ? (char)p[i] : '?';
    dst[n] = '\0';
}

/* a keyword whose value states the luminaire's flux (manufacturers' underscore keywords included) */
static int is_flux_keyword(const char *k)
{
    static const char *const names[] = {"LUMINAIREOUTPUT", "_LUMINAIRELUMENS", "_ABSOLUTELUMENS", "_LUMENS",
                                        "_LUMINAIRE_LUMENS", "_TOTALLUMENS"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (strcmp(k, names[i]) == 0)
            return 1;
    return 0;
}

/* first number in a keyword's value ("9217", "9217 lm", "TOTAL 9217.5"), or -1 */
static double value_number(const char *s)
{
    for (; *s; ++s)
        if ((*s >= '0' && *s <= '9') || (*s == '.' && s[1] >= '0' && s[1] <= '9')) {
            char *end;
            double x = strtod(s, &end);
            return (isfinite(x) && x > 0) ? x : -1;
        }
    return -1;
}

/* ---- the number stream ---------------------------------------------------------------------- */

typedef struct numstream {
    const uint8_t *buf;
    size_t len, pos;
    uint32_t count; /* numbers read so far (for messages) */
} numstream;

static int is_sep(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',' || c == '\f' || c == '\v' || c == 0x1A;
}

/* the next number; 0, or -1 with err set (what names the field) */
static int num(numstream *s, double *x, const char *what, char *err, size_t errlen)
{
    while (s->pos < s->len && is_sep(s->buf[s->pos]))
        ++s->pos;
    if (s->pos >= s->len)
        return qtool_errf(err, errlen, "ends before %s (after %u numbers)", what, s->count);
    char tok[64];
    size_t n = 0, at = s->pos;
    while (s->pos < s->len && !is_sep(s->buf[s->pos])) {
        uint8_t c = s->buf[s->pos];
        if (n == sizeof tok - 1)
            return qtool_errf(err, errlen, "%s: a number longer than %zu characters at byte %zu", what, sizeof tok - 1, at);
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'))
            return qtool_errf(err, errlen, "%s: '%c' (byte 0x%02x) at byte %zu is not part of a number", what,
                        (c >= 0x20 && c < 0x7F) ? c : '?', c, s->pos);
        tok[n++] = (char)c;
        ++s->pos;
    }
    tok[n] = '\0';
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (*end != '\0' || end == tok)
        return qtool_errf(err, errlen, "%s: '%s' at byte %zu is not a number", what, tok, at);
    if (!isfinite(v) || fabs(v) >= 1e15)
        return qtool_errf(err, errlen, "%s: %s at byte %zu is out of range (|x| < 1e15)", what, tok, at);
    ++s->count;
    *x = v;
    return 0;
}

/* an integer field written as a number ("1", "1.000"), in lo..hi */
static int inum(numstream *s, int *out, long lo, long hi, const char *what, char *err, size_t errlen)
{
    double x = 0;
    if (num(s, &x, what, err, errlen) != 0)
        return -1;
    if (x != floor(x) || x < (double)lo || x > (double)hi)
        return qtool_errf(err, errlen, "%s %.15g is not an integer in %ld..%ld", what, x, lo, hi);
    *out = (int)x;
    return 0;
}

/* bytes left from the stream's position: n more numbers need at least 2 n - 1 of them */
static int room_for(const numstream *s, uint64_t n)
{
    return n == 0 || (uint64_t)(s->len - s->pos) >= 2 * n - 1;
}

static int read_angles(numstream *s, double *a, uint32_t n, double lo, double hi, const char *what, char *err,
                       size_t errlen)
{
    for (uint32_t i = 0; i < n; ++i) {
        if (num(s, &a[i], what, err, errlen) != 0)
            return -1;
        if (a[i] < lo || a[i] > hi)
            return qtool_errf(err, errlen, "%s angle %u is %g, outside %g..%g", what, i + 1, a[i], lo, hi);
        if (i && !(a[i] > a[i - 1]))
            return qtool_errf(err, errlen, "%s angles not increasing: %g after %g (angle %u)", what, a[i], a[i - 1], i + 1);
    }
    return 0;
}

/* ---- decode ----------------------------------------------------------------------------------- */

/* the first line's version label: 1 taken (a label), 0 not a label (1986 free text), -1 unknown */
static int header_version(const uint8_t *p, size_t n, qtool_ies *o, char *err, size_t errlen)
{
    if (starts(p, n, "IESNA:LM-63-1995"))
        o->version = 1995;
    else if (starts(p, n, "IESNA:LM-63-2002"))
        o->version = 2002;
    else if (starts(p, n, "IES:LM-63-2019") || starts(p, n, "IESNA:LM-63-2019") || starts(p, n, "IESNA:LM-63-2018"))
        o->version = 2019;
    else if (starts(p, n, "IESNA91") || starts(p, n, "IESNA:LM-63-1991"))
        o->version = 1991;
    else if (starts(p, n, "IESNA:LM-63-1986"))
        o->version = 1986;
    else if (starts(p, n, "IESNA") || starts(p, n, "IES:"))
        return qtool_errf(err, errlen, "unknown LM-63 version label '%.*s' (1991, 1995, 2002 or 2019 known)",
                          (int)(n > 40 ? 40 : n), (const char *)p);
    return o->version != 1986 || starts(p, n, "IESNA:LM-63-1986");
}

/* a [KEYWORD] value line: the four text fields kept, the flux noted */
static int header_keyword(const uint8_t *p, size_t n, uint32_t line, qtool_ies *o, char *err, size_t errlen)
{
    const uint8_t *q = memchr(p, ']', n);
    if (!q)
        return qtool_errf(err, errlen, "header line %u: keyword without its closing ']'", line);
    char kw[QTOOL_IES_TEXT], val[QTOOL_IES_TEXT];
    keep_text(kw, p + 1, (size_t)(q - p - 1));
    keep_text(val, q + 1, n - (size_t)(q + 1 - p));
    if (strcmp(kw, "MORE") == 0) {
        if (o->nkeywords == 0)
            return qtool_errf(err, errlen, "header line %u: [MORE] continues no keyword", line);
        return 0;
    }
    ++o->nkeywords;
    if (strcmp(kw, "TEST") == 0)
        memcpy(o->test, val, sizeof val);
    else if (strcmp(kw, "MANUFAC") == 0)
        memcpy(o->manufac, val, sizeof val);
    else if (strcmp(kw, "LUMINAIRE") == 0)
        memcpy(o->luminaire, val, sizeof val);
    else if (strcmp(kw, "LAMP") == 0)
        memcpy(o->lamp, val, sizeof val);
    else if (is_flux_keyword(kw) && o->stated_lumens < 0)
        o->stated_lumens = value_number(val);
    return 0;
}

/* the header lines up to TILT=: *pos ends past that line, [*tilt, *tilt + *tilt_n) is its value */
static int header(const uint8_t *buf, size_t len, size_t *pos, const uint8_t **tilt, size_t *tilt_n, qtool_ies *o,
                  char *err, size_t errlen)
{
    uint32_t lines = 0;
    size_t start, n;
    while (*pos < len) {
        n = next_line(buf, len, pos, &start);
        const uint8_t *p = buf + start;
        if (memchr(p, 0, n))
            return qtool_errf(err, errlen, "a NUL byte in header line %u (not a text file)", lines + 1);
        if (++lines > QTOOL_IES_MAX_HEADER_LINES)
            return qtool_errf(err, errlen, "no TILT= line in the first %u lines", QTOOL_IES_MAX_HEADER_LINES);
        /* leading blanks are tolerated before TILT= and keywords */
        while (n && (*p == ' ' || *p == '\t'))
            ++p, --n;
        if (lines == 1) {
            int r = header_version(p, n, o, err, errlen);
            if (r < 0)
                return -1;
            if (r)
                continue;
        }
        if (starts(p, n, "TILT=") || starts(p, n, "TILT =")) {
            const uint8_t *q = memchr(p, '=', n);
            *tilt = q + 1;
            *tilt_n = n - (size_t)(q + 1 - p);
            return 0;
        }
        if (n && p[0] == '[' && header_keyword(p, n, lines, o, err, errlen) != 0)
            return -1;
        /* other lines (1986 free text, stray comments) carry nothing the data need */
    }
    return qtool_errf(err, errlen, "no TILT= line (not an IES LM-63 file)");
}

/* TILT value: NONE, INCLUDE (the tilt block follows in the number stream) or a file name */
static int tilt_block(numstream *s, const uint8_t *t, size_t tilt_n, qtool_ies *o, char *err, size_t errlen)
{
    while (tilt_n && (*t == ' ' || *t == '\t'))
        ++t, --tilt_n;
    while (tilt_n && (t[tilt_n - 1] == ' ' || t[tilt_n - 1] == '\t'))
        --tilt_n;
    if (tilt_n == 4 && memcmp(t, "NONE", 4) == 0) {
        o->tilt = QTOOL_IES_TILT_NONE;
        return 0;
    }
    if (!(tilt_n == 7 && memcmp(t, "INCLUDE", 7) == 0))
        return qtool_errf(err, errlen, "TILT=%.*s: a tilt file beside the .ies is not read (inline it as TILT=INCLUDE)",
                          (int)(tilt_n > 60 ? 60 : tilt_n), (const char *)t);
    o->tilt = QTOOL_IES_TILT_INCLUDE;
    int ntilt;
    if (inum(s, &o->tilt_geometry, 1, 3, "the tilt block's lamp-to-luminaire geometry", err, errlen) != 0 ||
        inum(s, &ntilt, 1, QTOOL_IES_MAX_TILT, "the tilt angle count", err, errlen) != 0)
        return -1;
    if (!room_for(s, 2u * (uint64_t)ntilt))
        return qtool_errf(err, errlen, "the tilt block claims %d angles, more than the file holds", ntilt);
    o->ntilt = (uint32_t)ntilt;
    o->tilt_angle = malloc(sizeof(double) * o->ntilt);
    o->tilt_factor = malloc(sizeof(double) * o->ntilt);
    if (!o->tilt_angle || !o->tilt_factor)
        return qtool_errf(err, errlen, "out of memory for %u tilt angles", o->ntilt);
    if (read_angles(s, o->tilt_angle, o->ntilt, 0, 180, "tilt", err, errlen) != 0)
        return -1;
    for (uint32_t i = 0; i < o->ntilt; ++i) {
        if (num(s, &o->tilt_factor[i], "a tilt multiplying factor", err, errlen) != 0)
            return -1;
        if (o->tilt_factor[i] < 0)
            return qtool_errf(err, errlen, "tilt multiplying factor %u is negative (%g)", i + 1, o->tilt_factor[i]);
    }
    return 0;
}

/* the ten-number line and the three-number line; *nv, *nh the angle counts, checked */
static int photometry_lines(numstream *s, qtool_ies *o, int *nv, int *nh, char *err, size_t errlen)
{
    if (inum(s, &o->nlamps, 1, QTOOL_IES_MAX_LAMPS, "the number of lamps", err, errlen) != 0 ||
        num(s, &o->lumens_per_lamp, "the lumens per lamp", err, errlen) != 0 ||
        num(s, &o->multiplier, "the candela multiplier", err, errlen) != 0 ||
        inum(s, nv, 1, QTOOL_IES_MAX_ANGLES, "the number of vertical angles", err, errlen) != 0 ||
        inum(s, nh, 1, QTOOL_IES_MAX_ANGLES, "the number of horizontal angles", err, errlen) != 0 ||
        inum(s, &o->type, 1, 3, "the photometric type", err, errlen) != 0 ||
        inum(s, &o->units, 1, 2, "the units type", err, errlen) != 0 ||
        num(s, &o->width, "the luminous width", err, errlen) != 0 ||
        num(s, &o->length, "the luminous length", err, errlen) != 0 ||
        num(s, &o->height, "the luminous height", err, errlen) != 0 ||
        num(s, &o->ballast_factor, "the ballast factor", err, errlen) != 0 ||
        num(s, &o->factor2, "the ballast-lamp factor (future use / file generation type)", err, errlen) != 0 ||
        num(s, &o->watts, "the input watts", err, errlen) != 0)
        return -1;
    if (o->lumens_per_lamp < 0 && o->lumens_per_lamp != -1)
        return qtool_errf(err, errlen, "lumens per lamp %g is negative but not -1 (absolute photometry)", o->lumens_per_lamp);
    if (!(o->multiplier > 0))
        return qtool_errf(err, errlen, "candela multiplier %g is not positive", o->multiplier);
    if (!(o->ballast_factor > 0))
        return qtool_errf(err, errlen, "ballast factor %g is not positive", o->ballast_factor);
    if (o->version <= 1995 && !(o->factor2 > 0))
        return qtool_errf(err, errlen, "ballast-lamp photometric factor %g is not positive", o->factor2);
    if (*nv < 2)
        return qtool_errf(err, errlen, "1 vertical angle: an intensity distribution needs at least 2");
    if (o->type != QTOOL_IES_TYPE_C && *nh < 2)
        return qtool_errf(err, errlen, "1 horizontal angle: type %c photometry needs at least 2",
                          o->type == QTOOL_IES_TYPE_B ? 'B' : 'A');
    return 0;
}

/* the symmetry the horizontal angles' range states */
static int symmetry(qtool_ies *o, char *err, size_t errlen)
{
    double h0 = o->h[0], h1 = o->h[o->nh - 1];
    if (o->type == QTOOL_IES_TYPE_C) {
        if (o->nh == 1)
            o->sym = QTOOL_IES_SYM_AXIAL;
        else if (h0 == 0 && h1 == 90)
            o->sym = QTOOL_IES_SYM_QUAD;
        else if (h0 == 0 && h1 == 180)
            o->sym = QTOOL_IES_SYM_BILATERAL;
        else if (h0 == 90 && h1 == 270)
            o->sym = QTOOL_IES_SYM_BILATERAL90;
        else if (h0 == 0 && h1 > 180)
            o->sym = QTOOL_IES_SYM_FULL; /* up to 360 (a grid stopping short wraps to the 0 plane) */
        else
            return qtool_errf(err, errlen,
                              "horizontal angles %g..%g are none of type C's ranges (0, 0..90, 0..180, 90..270, 0..360)",
                              h0, h1);
    } else {
        if (h0 == 0 && h1 == 90)
            o->sym = QTOOL_IES_SYM_AB_HALF;
        else if (h0 == -90 && h1 == 90)
            o->sym = QTOOL_IES_SYM_AB_FULL;
        else
            return qtool_errf(err, errlen, "horizontal angles %g..%g are none of type %c's ranges (0..90, -90..90)", h0,
                              h1, o->type == QTOOL_IES_TYPE_B ? 'B' : 'A');
    }
    return 0;
}

/* the angles, the symmetry they state and the candela table (scaled by the multiplier) */
static int candela_table(numstream *s, qtool_ies *o, int nv, int nh, char *err, size_t errlen)
{
    uint64_t nvals = (uint64_t)nv * (uint64_t)nh;
    if (nvals > QTOOL_IES_MAX_VALUES)
        return qtool_errf(err, errlen, "%d x %d candela values, above the limit of %u", nv, nh, QTOOL_IES_MAX_VALUES);
    if (!room_for(s, (uint64_t)nv + (uint64_t)nh + nvals))
        return qtool_errf(err, errlen, "%d x %d angles claim more numbers than the file holds", nv, nh);
    o->nv = (uint32_t)nv;
    o->nh = (uint32_t)nh;
    o->v = malloc(sizeof(double) * o->nv);
    o->h = malloc(sizeof(double) * o->nh);
    o->cd = malloc(sizeof(double) * (size_t)nvals);
    if (!o->v || !o->h || !o->cd)
        return qtool_errf(err, errlen, "out of memory for %d x %d candela values", nv, nh);
    int c = o->type == QTOOL_IES_TYPE_C;
    if (read_angles(s, o->v, o->nv, c ? 0 : -90, c ? 180 : 90, "vertical", err, errlen) != 0 ||
        read_angles(s, o->h, o->nh, c ? 0 : -90, c ? 360 : 90, "horizontal", err, errlen) != 0 ||
        symmetry(o, err, errlen) != 0)
        return -1;
    o->cd_min = INFINITY;
    o->cd_max = 0;
    for (uint64_t k = 0; k < nvals; ++k) {
        double x;
        if (num(s, &x, "a candela value", err, errlen) != 0)
            return -1;
        if (x < 0)
            return qtool_errf(err, errlen, "candela value %g (horizontal angle %g, vertical %g) is negative", x,
                              o->h[k / o->nv], o->v[k % o->nv]);
        x *= o->multiplier;
        o->cd[k] = x;
        o->cd_min = x < o->cd_min ? x : o->cd_min;
        o->cd_max = x > o->cd_max ? x : o->cd_max;
    }
    /* what follows the table (an end marker, a DOS EOF, a signature) carries nothing: ignored */
    return 0;
}

static int decode_impl(const uint8_t *buf, size_t len, qtool_ies *o, char *err, size_t errlen)
{
    if (len == 0)
        return qtool_errf(err, errlen, "empty file");
    if (len > QTOOL_IES_MAX_FILE_BYTES)
        return qtool_errf(err, errlen, "file of %zu bytes is above the limit of %zu", len, QTOOL_IES_MAX_FILE_BYTES);
    o->version = 1986;
    o->stated_lumens = -1;
    size_t pos = 0, tilt_n = 0;
    const uint8_t *tilt = NULL;
    if (len >= 3 && buf[0] == 0xEF && buf[1] == 0xBB && buf[2] == 0xBF)
        pos = 3; /* a UTF-8 byte-order mark some editors write */
    if (header(buf, len, &pos, &tilt, &tilt_n, o, err, errlen) != 0)
        return -1;
    numstream s = {.buf = buf, .len = len, .pos = pos};
    int nv = 0, nh = 0;
    if (tilt_block(&s, tilt, tilt_n, o, err, errlen) != 0 || photometry_lines(&s, o, &nv, &nh, err, errlen) != 0)
        return -1;
    return candela_table(&s, o, nv, nh, err, errlen);
}

void qtool_ies_free(qtool_ies *ies)
{
    if (!ies)
        return;
    free(ies->tilt_angle);
    free(ies->tilt_factor);
    free(ies->v);
    free(ies->h);
    free(ies->cd);
    memset(ies, 0, sizeof *ies);
}

int qtool_ies_decode(const uint8_t *buf, size_t len, qtool_ies *out, char *err, size_t errlen)
{
    qtool_ies o;
    memset(&o, 0, sizeof o);
    if (!buf && len)
        return qtool_errf(err, errlen, "no data");
    if (decode_impl(buf, len, &o, err, errlen) != 0) {
        qtool_ies_free(&o);
        return -1;
    }
    *out = o;
    return 0;
}

/* IES files are text: a NUL among the first bytes marks something else */
static const char *ies_magic(const uint8_t *head, size_t n)
{
    return memchr(head, 0, n) ? "not an IES LM-63 file (binary data at its start)" : NULL;
}

int qtool_ies_read(const char *path, qtool_ies *out, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"an IES LM-63 file", 16, QTOOL_IES_MAX_FILE_BYTES, 64, ies_magic};
    uint8_t *buf = NULL;
    size_t n = 0;
    if (qtool_io_load(path, &kind, &buf, &n, err, errlen) != 0)
        return -1;
    char msg[256];
    int rc = qtool_ies_decode(buf, n, out, msg, sizeof msg);
    free(buf);
    if (rc != 0)
        return qtool_errf(err, errlen, "%s: %s", path, msg);
    return 0;
}

const char *qtool_ies_sym_name(qtool_ies_sym s)
{
    switch (s) {
#define QTOOL_IES_SYM_CASE_(name, value, label) case name: return label;
    QTOOL_IES_SYM_LIST(QTOOL_IES_SYM_CASE_)
#undef QTOOL_IES_SYM_CASE_
    }
    return "unknown";
}

/* ---- flux ----------------------------------------------------------------------------------- */

static double factors(const qtool_ies *e)
{
    return e->ballast_factor * (e->version <= 1995 ? e->factor2 : 1.0);
}

/* one zone [a, b] (radians) of the latitude-like angle with intensities ia at a and ib at b: the
 * zonal-lumen rule, the zone's mean intensity (ia + ib) / 2 times its solid angle per unit plane
 * angle, cos a - cos b (type C, angle from the nadir) or sin b - sin a (A, B, from the equator);
 * exact for an intensity linear in cos (sin) of the angle, so for isotropic and cosine lamps */
static double seg(double a, double b, double ia, double ib, int sin_w)
{
    return 0.5 * (ia + ib) * (sin_w ? cos(a) - cos(b) : sin(b) - sin(a));
}

double qtool_ies_lumens(const qtool_ies *e)
{
    const double r = QTOOL_PI / 180;
    uint32_t nv = e->nv, nh = e->nh;
    double total = 0;
    if (e->type == QTOOL_IES_TYPE_B) {
        /* latitude = horizontal angle (cos weight) within each plane; planes = vertical angles */
        double prev = 0;
        for (uint32_t i = 0; i < nv; ++i) {
            double l = 0;
            for (uint32_t j = 0; j + 1 < nh; ++j)
                l += seg(e->h[j] * r, e->h[j + 1] * r, e->cd[j * nv + i], e->cd[(j + 1) * nv + i], 0);
            if (e->sym == QTOOL_IES_SYM_AB_HALF)
                l *= 2;
            if (i)
                total += (e->v[i] - e->v[i - 1]) * r * 0.5 * (prev + l);
            prev = l;
        }
        return total * factors(e);
    }
    /* types C and A: latitude = vertical angle (sin weight from the nadir for C, cos from the
     * horizontal for A) within each horizontal plane */
    int sin_w = e->type == QTOOL_IES_TYPE_C;
    double prev = 0, first = 0;
    for (uint32_t j = 0; j < nh; ++j) {
        const double *row = e->cd + (size_t)j * nv;
        double l = 0;
        for (uint32_t i = 0; i + 1 < nv; ++i)
            l += seg(e->v[i] * r, e->v[i + 1] * r, row[i], row[i + 1], sin_w);
        if (j)
            total += (e->h[j] - e->h[j - 1]) * r * 0.5 * (prev + l);
        else
            first = l;
        prev = l;
    }
    switch (e->sym) {
    case QTOOL_IES_SYM_AXIAL: total = 2 * QTOOL_PI * first; break;
    case QTOOL_IES_SYM_QUAD: total *= 4; break;
    case QTOOL_IES_SYM_BILATERAL:
    case QTOOL_IES_SYM_BILATERAL90:
    case QTOOL_IES_SYM_AB_HALF: total *= 2; break;
    case QTOOL_IES_SYM_FULL: total += (360 - e->h[nh - 1]) * r * 0.5 * (prev + first); break;
    case QTOOL_IES_SYM_AB_FULL: break;
    }
    return total * factors(e);
}

/* ---- lookup --------------------------------------------------------------------------------- */

/* index i and weight t with x between a[i] and a[i + 1] (n >= 2), or -1 outside a[0]..a[n-1] */
static long locate(const double *a, uint32_t n, double x, double *t)
{
    if (n == 1) {
        *t = 0;
        return 0;
    }
    if (x < a[0] || x > a[n - 1])
        return -1;
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (a[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    *t = (x - a[lo]) / (a[lo + 1] - a[lo]);
    return (long)lo;
}

static double clamp1(double x)
{
    return x < -1 ? -1 : x > 1 ? 1 : x;
}

double qtool_ies_candela(const qtool_ies *e, const double d[3])
{
    const double g = 180 / QTOOL_PI;
    double va, ha; /* the grid's vertical and horizontal angles of d */
    if (e->type == QTOOL_IES_TYPE_C) {
        va = acos(clamp1(d[2])) * g;
        ha = atan2(d[0], d[1]) * g;
        if (ha < 0)
            ha += 360;
        switch (e->sym) {
        case QTOOL_IES_SYM_AXIAL: ha = e->h[0]; break;
        case QTOOL_IES_SYM_QUAD:
            if (ha > 180)
                ha = 360 - ha;
            if (ha > 90)
                ha = 180 - ha;
            break;
        case QTOOL_IES_SYM_BILATERAL:
            if (ha > 180)
                ha = 360 - ha;
            break;
        case QTOOL_IES_SYM_BILATERAL90:
            if (ha < 90)
                ha = 180 - ha;
            else if (ha > 270)
                ha = 540 - ha;
            break;
        default: break;
        }
    } else if (e->type == QTOOL_IES_TYPE_B) {
        ha = asin(clamp1(d[0])) * g;
        va = atan2(d[1], d[2]) * g;
    } else {
        va = asin(clamp1(d[1])) * g;
        ha = atan2(d[0], d[2]) * g;
    }
    if (e->sym == QTOOL_IES_SYM_AB_HALF)
        ha = fabs(ha);
    double tv, th;
    long i = locate(e->v, e->nv, va, &tv);
    if (i < 0)
        return 0;
    long j0, j1;
    if (e->sym == QTOOL_IES_SYM_FULL && ha > e->h[e->nh - 1]) {
        /* the wrap from the last plane back to the 0 plane at 360 */
        j0 = (long)e->nh - 1;
        j1 = 0;
        th = (ha - e->h[j0]) / (360 - e->h[j0]);
    } else {
        j0 = locate(e->h, e->nh, ha, &th);
        if (j0 < 0)
            return 0;
        j1 = e->nh > 1 ? j0 + 1 : j0;
    }
    const double *r0 = e->cd + (size_t)j0 * e->nv, *r1 = e->cd + (size_t)j1 * e->nv;
    double a = r0[i] + (r0[i + 1] - r0[i]) * tv, b = r1[i] + (r1[i + 1] - r1[i]) * tv;
    return (a + (b - a) * th) * factors(e);
}

/* ---- the core's table ----------------------------------------------------------------------- */

int qtool_ies_gonio_table(const qtool_ies *e, uint32_t n, uint16_t *table, double *peak_cd)
{
    double peak = e->cd_max * factors(e);
    if (n < QIBL_GONIO_MIN_N || n > QIBL_GONIO_MAX_N || !(peak > 0))
        return -1;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            /* the texel centre's direction: the octahedral map of gonio.h, inverted */
            double u = (2.0 * i + 1) / n - 1, v = (2.0 * j + 1) / n - 1, z = 1 - fabs(u) - fabs(v);
            if (z < 0) {
                double uu = (1 - fabs(v)) * (u < 0 ? -1 : 1), vv = (1 - fabs(u)) * (v < 0 ? -1 : 1);
                u = uu, v = vv;
            }
            double l = sqrt(u * u + v * v + z * z), d[3] = {u / l, v / l, z / l};
            double q = qtool_ies_candela(e, d) / peak * QIBL_GONIO_ONE;
            q = q < 0 ? 0 : q > QIBL_GONIO_ONE ? QIBL_GONIO_ONE : q;
            table[(size_t)j * n + i] = (uint16_t)lround(q);
        }
    if (peak_cd)
        *peak_cd = peak;
    return 0;
}

/* ---- a profile in the world (double) -------------------------------------------------------- */

int qtool_ies_lamp_init(qtool_ies_lamp *l, const qtool_ies *ies, const double aim[3], const double up[3])
{
    double za = sqrt(aim[0] * aim[0] + aim[1] * aim[1] + aim[2] * aim[2]);
    double peak = ies->cd_max * factors(ies);
    if (!(za > 0) || !(peak > 0))
        return -1;
    double z[3] = {aim[0] / za, aim[1] / za, aim[2] / za};
    double d = up[0] * z[0] + up[1] * z[1] + up[2] * z[2];
    double y[3] = {up[0] - d * z[0], up[1] - d * z[1], up[2] - d * z[2]};
    double ul = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    double yl = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    if (!(ul > 0) || yl < ul * ldexp(1, -10))
        return -1;
    for (int k = 0; k < 3; ++k)
        y[k] /= yl;
    l->ies = ies;
    l->peak = peak;
    for (int k = 0; k < 3; ++k)
        l->z[k] = z[k], l->y[k] = y[k];
    l->x[0] = y[1] * z[2] - y[2] * z[1];
    l->x[1] = y[2] * z[0] - y[0] * z[2];
    l->x[2] = y[0] * z[1] - y[1] * z[0];
    return 0;
}

double qtool_ies_lamp_scale(const void *ctx, const double d[3])
{
    const qtool_ies_lamp *l = ctx;
    double loc[3] = {d[0] * l->x[0] + d[1] * l->x[1] + d[2] * l->x[2], d[0] * l->y[0] + d[1] * l->y[1] + d[2] * l->y[2],
                     d[0] * l->z[0] + d[1] * l->z[1] + d[2] * l->z[2]};
    return qtool_ies_candela(l->ies, loc) / l->peak;
}
