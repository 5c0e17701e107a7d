/*
 * opt/opt.c - the option tables' parser, help text and error lines (opt/opt.h).
 *
 * Invariants: every refusal is one line on stderr in one shape and returns 2; the parser writes
 * only into the caller's options struct; help walks the same table the parser does.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "opt/opt.h"

const char *qtool_opt_program = "qibl";

#define MAX_OPTS 64 /* entries per table the required-option check tracks */

const char qtool_opt_no_value[] = "is not a value";
const qtool_opt_list qtool_opt_args = {.n = 0};

static const char *help_name(const qtool_opt_cmd *c)
{
    return c->help_name ? c->help_name : c->name;
}

static int vfail(const char *name, const char *help, const char *fmt, va_list ap)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 0)))
#endif
    ;
static int vfail(const char *name, const char *help, const char *fmt, va_list ap)
{
    /* formatted first, so a value with a control character (a newline) cannot break the one line */
    char msg[1024];
    vsnprintf(msg, sizeof msg, fmt, ap);
    fprintf(stderr, "%s%s%s: ", qtool_opt_program, name[0] ? " " : "", name);
    for (const unsigned char *p = (const unsigned char *)msg; *p; ++p)
        if (*p < 0x20 || *p == 0x7f)
            fprintf(stderr, "\\x%02x", (unsigned)*p);
        else
            fputc(*p, stderr);
    if (help[0]) /* the command: "sh eval" is helped by `qibl help sh` */
        fprintf(stderr, "; see %s help %.*s\n", qtool_opt_program, (int)strcspn(help, " "), help);
    else /* qibl's own flags (main.c) */
        fprintf(stderr, "; see %s --help\n", qtool_opt_program);
    return 2;
}

int qtool_opt_error(const qtool_opt_cmd *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(c->name, help_name(c), fmt, ap);
    va_end(ap);
    return 2;
}

static int fail_named(const char *name, const char *help, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static int fail_named(const char *name, const char *help, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(name, help, fmt, ap);
    va_end(ap);
    return 2;
}

static size_t count(const qtool_opt *t)
{
    size_t n = 0;
    while (t && t[n].kind != QTOOL_OPT_END)
        ++n;
    return n;
}

static const qtool_opt *find(const qtool_opt *t, const char *a)
{
    for (size_t i = 0; t && t[i].kind != QTOOL_OPT_END; ++i)
        if (strcmp(t[i].name, a) == 0 || (t[i].alias && strcmp(t[i].alias, a) == 0))
            return &t[i];
    return NULL;
}

/* the option with .eq named by the first n bytes of a ("--progress" of "--progress=bar") */
static const qtool_opt *find_eq(const qtool_opt *t, const char *a, size_t n)
{
    for (size_t i = 0; t && t[i].kind != QTOOL_OPT_END; ++i)
        if (t[i].eq && strlen(t[i].name) == n && strncmp(t[i].name, a, n) == 0)
            return &t[i];
    return NULL;
}

/* the whole string is a number strtod reads (negative, inf and nan included) */
static int is_number(const char *s)
{
    char *end;
    (void)strtod(s, &end);
    return end != s && *end == '\0';
}

/* "a, b or c" of a NULL-terminated list into buf */
static const char *alternatives(const char *const *names, const char *last, char *buf, size_t n)
{
    size_t k = 0, len = 0;
    while (names && names[k])
        ++k;
    buf[0] = '\0';
    size_t total = k + (last ? 1 : 0);
    for (size_t i = 0; i < total && len < n; ++i) {
        const char *w = i < k ? names[i] : last;
        const char *sep = i == 0 ? "" : i + 1 == total ? " or " : ", ";
        int m = snprintf(buf + len, n - len, "%s%s", sep, w);
        len += m > 0 ? (size_t)m : 0;
    }
    return buf;
}

/* the value's name in usage and errors */
static const char *arg_name(const qtool_opt *o, char *buf, size_t n)
{
    if (o->arg)
        return o->arg;
    switch (o->kind) {
    case QTOOL_OPT_ENUM: {
        size_t len = 0;
        buf[0] = '\0';
        for (size_t i = 0; o->names[i] && len < n; ++i) {
            int m = snprintf(buf + len, n - len, "%s%s", i ? "|" : "", o->names[i]);
            len += m > 0 ? (size_t)m : 0;
        }
        return buf;
    }
    case QTOOL_OPT_SIZE:
        return "WxH";
    case QTOOL_OPT_TRIPLE:
        return "X Y Z";
    case QTOOL_OPT_INT:
        return "N";
    case QTOOL_OPT_NUM:
        return "X";
    default:
        return "VALUE";
    }
}

int qtool_opt_num_value(const char *s, double lo, double hi, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0')
        return 1;
    if (!isfinite(v)) /* an overflow is HUGE_VAL; an underflow (ERANGE near 0) is taken as the tiny value */
        return 2;
    if (!(v >= lo && v <= hi))
        return 3;
    *out = v;
    return 0;
}

static int parse_num(const char *name, const char *help, const qtool_opt *o, const char *s, double *out)
{
    switch (qtool_opt_num_value(s, o->lo, o->hi, out)) {
    case 0:
        return 0;
    case 1:
        return fail_named(name, help, "%s: '%s' is not a number", o->name, s);
    case 2:
        return fail_named(name, help, "%s: '%s' is not a finite number", o->name, s);
    default:
        return fail_named(name, help, "%s: %s is outside %.10g..%.10g%s%s%s", o->name, s, o->lo, o->hi,
                          o->why ? " (" : "", o->why ? o->why : "", o->why ? ")" : "");
    }
}

int qtool_opt_int_value(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

static int parse_int(const char *name, const char *help, const qtool_opt *o, const char *s, long *out)
{
    if (qtool_opt_int_value(s, (long)o->lo, (long)o->hi, out) != 0)
        return fail_named(name, help, "%s: '%s' is not %s in %ld..%ld%s%s%s", o->name, s,
                          o->what ? o->what : "an integer", (long)o->lo, (long)o->hi, o->why ? " (" : "",
                          o->why ? o->why : "", o->why ? ")" : "");
    return 0;
}

int qtool_opt_size_value(const char *s, long max, long wh[2])
{
    const char *p = s;
    long v[2];
    for (int i = 0; i < 2; ++i) {
        long x = 0;
        if (*p < '0' || *p > '9')
            return -1;
        while (*p >= '0' && *p <= '9') {
            x = x > max ? x : x * 10 + (*p - '0'); /* stops growing past max: no overflow */
            ++p;
        }
        if (x < 1 || x > max || *p != (i == 0 ? 'x' : '\0'))
            return -1;
        v[i] = x;
        ++p;
    }
    wh[0] = v[0], wh[1] = v[1];
    return 0;
}

static int parse_size(const char *name, const char *help, const qtool_opt *o, const char *s, long *wh)
{
    if (qtool_opt_size_value(s, (long)o->hi, wh) != 0)
        return fail_named(name, help, "%s needs WxH with both in 1..%ld, got '%s'", o->name, (long)o->hi, s);
    return 0;
}

/* one option's value(s) at argv[*i + 1 ...] into its field; *i advanced past them. The errors name
 * the flag as it was spelled (an alias too). */
static int take(const qtool_opt_cmd *c, const qtool_opt *table_o, int argc, char **argv, int *i, char *opts)
{
    qtool_opt spelled = *table_o;
    spelled.name = argv[*i];
    const qtool_opt *o = &spelled;
    const char *name = c->name, *help = help_name(c);
    char buf[256];
    void *dst = opts + o->off;
    void *self = o->field ? dst : opts; /* what a CALL's call gets */
    if (o->kind == QTOOL_OPT_FLAG) {
        *(int *)dst = 1;
        const char *bad = o->call ? o->call(self, NULL) : NULL;
        return bad ? fail_named(name, help, "%s %s", o->name, bad) : 0;
    }
    if (o->kind == QTOOL_OPT_CALL && o->optional) { /* the next argument, if it is a value; else none */
        const char *v = *i + 1 < argc ? argv[*i + 1] : NULL, *bad = v ? o->call(self, v) : qtool_opt_no_value;
        if (bad == qtool_opt_no_value)
            v = NULL, bad = o->call(self, NULL);
        if (bad)
            return v ? fail_named(name, help, "%s: '%s' %s", o->name, v, bad)
                     : fail_named(name, help, "%s %s", o->name, bad);
        *i += v ? 1 : 0;
        return 0;
    }
    int nv = o->kind == QTOOL_OPT_TRIPLE ? 3 : o->kind == QTOOL_OPT_CALL && o->nargs > 1 ? o->nargs : 1;
    int least = o->kind == QTOOL_OPT_CALL && o->nargs > 1 && o->nargs_min > 0 ? o->nargs_min : nv;
    if (argc - *i - 1 < least)
        return fail_named(name, help, "%s needs %s", o->name, arg_name(o, buf, sizeof buf));
    if (nv > 1 && o->kind == QTOOL_OPT_CALL) {
        int n = argc - *i - 1 < nv ? argc - *i - 1 : nv, used = n;
        const char *bad = o->call_n(self, argv + *i + 1, n, &used);
        if (bad)
            return fail_named(name, help, "%s: %s", o->name, bad);
        *i += used >= least && used <= n ? used : n;
        return 0;
    }
    const char *v = argv[*i + 1];
    int rc = 0;
    switch (o->kind) {
    case QTOOL_OPT_INT:
        rc = parse_int(name, help, o, v, (long *)dst);
        break;
    case QTOOL_OPT_NUM:
        rc = parse_num(name, help, o, v, (double *)dst);
        break;
    case QTOOL_OPT_STR:
        *(const char **)dst = v;
        break;
    case QTOOL_OPT_ENUM: {
        int k = 0;
        while (o->names[k] && strcmp(o->names[k], v) != 0)
            ++k;
        if (!o->names[k])
            return fail_named(name, help, "%s: '%s' is not %s", o->name, v,
                              alternatives(o->names, NULL, buf, sizeof buf));
        *(int *)dst = k;
        break;
    }
    case QTOOL_OPT_SIZE:
        rc = parse_size(name, help, o, v, (long *)dst);
        break;
    case QTOOL_OPT_TRIPLE: {
        double t[3];
        for (int k = 0; k < 3 && rc == 0; ++k)
            rc = parse_num(name, help, o, argv[*i + 1 + k], &t[k]);
        if (rc == 0)
            memcpy(dst, t, sizeof t);
        break;
    }
    case QTOOL_OPT_LIST: {
        qtool_opt_list *l = dst;
        int max = o->hi > 0 && o->hi < QTOOL_OPT_LIST_MAX ? (int)o->hi : QTOOL_OPT_LIST_MAX;
        if (l->n >= max)
            return fail_named(name, help, "%s: at most %d, and '%s' is one more", o->name, max, v);
        l->v[l->n++] = v;
        break;
    }
    case QTOOL_OPT_CALL: {
        const char *bad = o->call(self, v);
        if (bad)
            return fail_named(name, help, "%s: '%s' %s", o->name, v, bad);
        break;
    }
    default:
        break;
    }
    if (rc != 0)
        return rc;
    if (o->renamed)
        fprintf(stderr, "%s: note: %s %s is deprecated here; say %s %s%s%s%s\n", qtool_opt_program, o->name,
                arg_name(o, buf, sizeof buf), o->renamed, v, o->note ? " (" : "", o->note ? o->note : "",
                o->note ? ")" : "");
    *i += nv;
    return 0;
}

int qtool_opt_parse(const qtool_opt_cmd *c, int argc, char **argv, int first, void *opts)
{
    const char *name = c->name, *help = help_name(c);
    char *base = opts;
    unsigned char seen[MAX_OPTS] = {0};
    if (c->defaults)
        memcpy(opts, c->defaults, c->size);
    else
        memset(opts, 0, c->size);
    qtool_opt_list *pos = c->pos.max > 0 && !c->pos.call ? (qtool_opt_list *)(void *)(base + c->pos.off) : NULL;
    if (pos)
        pos->n = 0;
    for (int i = first; i < argc; ++i) {
        const char *a = argv[i];
        const qtool_opt *o = find(c->opts, a);
        const char *eq = a[0] == '-' ? strchr(a, '=') : NULL;
        const qtool_opt *oe = !o && eq ? find_eq(c->opts, a, (size_t)(eq - a)) : NULL;
        if (oe) { /* --name=VALUE: as --name VALUE */
            char *two[2] = {(char *)(uintptr_t)oe->name, (char *)(uintptr_t)(eq + 1)};
            int at = 0, rc = take(c, oe, 2, two, &at, base);
            size_t k = (size_t)(oe - c->opts);
            if (k < MAX_OPTS)
                seen[k] = 1;
            if (rc != 0)
                return rc;
            continue;
        }
        if (o) {
            size_t k = (size_t)(o - c->opts);
            if (k < MAX_OPTS)
                seen[k] = 1;
            int rc = take(c, o, argc, argv, &i, base);
            if (rc != 0)
                return rc;
            continue;
        }
        /* "-" alone is a value (standard input's name); so is "-1" where values may be numbers */
        if (a[0] == '-' && a[1] != '\0' && !(c->pos.numbers && is_number(a)))
            return fail_named(name, help, "unknown option '%s'", a);
        if (c->pos.call) {
            const char *bad = c->pos.call(opts, a);
            if (bad)
                return fail_named(name, help, "'%s' %s", a, bad);
            continue;
        }
        if (!pos)
            return fail_named(name, help, "takes no arguments but options, and '%s' is not one", a);
        if (pos->n >= c->pos.max)
            return fail_named(name, help, "takes %s%s: '%s' is one too many", c->pos.max > 1 ? "at most " : "",
                              c->pos.names, a);
        pos->v[pos->n++] = a;
    }
    size_t n = count(c->opts);
    for (size_t k = 0; k < n && k < MAX_OPTS; ++k)
        if (c->opts[k].required && !seen[k]) {
            char buf[256];
            return fail_named(name, help, "%s %s is required", c->opts[k].name, arg_name(&c->opts[k], buf, sizeof buf));
        }
    if (pos && pos->n < c->pos.min)
        return fail_named(name, help, "needs %s, got %d argument%s", c->pos.names, pos->n, pos->n == 1 ? "" : "s");
    return 0;
}

const qtool_opt_cmd *qtool_opt_sub(const char *cmd, const qtool_opt_cmd *const *subs, const char *others, int argc,
                                 char **argv)
{
    const char *words[16];
    size_t k = 0;
    for (; subs[k] && k < 15; ++k) {
        const char *sp = strrchr(subs[k]->name, ' ');
        words[k] = sp ? sp + 1 : subs[k]->name;
        if (argc >= 2 && strcmp(argv[1], words[k]) == 0)
            return subs[k];
    }
    words[k] = NULL;
    char buf[256];
    alternatives(words, others, buf, sizeof buf);
    if (argc < 2)
        fail_named(cmd, cmd, "needs a subcommand: %s", buf);
    else if (argv[1][0] == '-')
        fail_named(cmd, cmd, "unknown option '%s' (a subcommand comes first: %s)", argv[1], buf);
    else
        fail_named(cmd, cmd, "'%s' is not a subcommand (%s)", argv[1], buf);
    return NULL;
}

/* the default as help shows it, read from the defaults struct; "" when there is none to show */
static const char *default_text(const qtool_opt_cmd *c, const qtool_opt *o, char *buf, size_t n)
{
    buf[0] = '\0';
    if (o->def)
        return o->def;
    if (!c->defaults)
        return buf;
    const char *p = (const char *)c->defaults + o->off;
    switch (o->kind) {
    case QTOOL_OPT_INT:
        snprintf(buf, n, "%ld", *(const long *)(const void *)p);
        break;
    case QTOOL_OPT_NUM:
        snprintf(buf, n, "%g", *(const double *)(const void *)p);
        break;
    case QTOOL_OPT_STR:
        if (*(const char *const *)(const void *)p)
            snprintf(buf, n, "%s", *(const char *const *)(const void *)p);
        break;
    case QTOOL_OPT_ENUM:
        snprintf(buf, n, "%s", o->names[*(const int *)(const void *)p]);
        break;
    case QTOOL_OPT_SIZE: {
        const long *wh = (const long *)(const void *)p;
        snprintf(buf, n, "%ldx%ld", wh[0], wh[1]);
        break;
    }
    case QTOOL_OPT_TRIPLE: {
        const double *t = (const double *)(const void *)p;
        snprintf(buf, n, "%g %g %g", t[0], t[1], t[2]);
        break;
    }
    default:
        break;
    }
    return buf;
}

/* text from column `indent` on, broken at spaces before column WIDTH, continued at `indent` */
#define WIDTH 100
static void wrap(FILE *f, const char *text, int indent)
{
    int col = indent;
    const char *p = text;
    while (*p) {
        const char *sp = strchr(p, ' ');
        int len = sp ? (int)(sp - p) : (int)strlen(p);
        if (col > indent && col + 1 + len > WIDTH) {
            fprintf(f, "\n%*s", indent, "");
            col = indent;
        }
        fprintf(f, "%s%.*s", col > indent ? " " : "", len, p);
        col += (col > indent ? 1 : 0) + len;
        p += len;
        while (*p == ' ')
            ++p;
    }
    fputc('\n', f);
}

/* "[--k K]", "-o FILE" into buf */
static void usage_item(const qtool_opt *o, char *buf, size_t n)
{
    char a[256];
    const char *an = o->kind == QTOOL_OPT_FLAG ? NULL : arg_name(o, a, sizeof a);
    snprintf(buf, n, "%s%s%s%s%s%s%s%s", o->required ? "" : "[", o->name, an ? " " : "", o->optional ? "[" : "",
             an ? an : "", o->optional ? "]" : "", o->kind == QTOOL_OPT_LIST ? "..." : "", o->required ? "" : "]");
}

/* whether the synopsis names the option (as a whole word: "--sums" is not "--sums-x") */
static int in_synopsis(const char *syn, const char *name)
{
    const size_t l = strlen(name);
    for (const char *p = syn ? strstr(syn, name) : NULL; p; p = strstr(p + 1, name))
        if ((p == syn || p[-1] == ' ' || p[-1] == '(' || p[-1] == '[' || p[-1] == '|') &&
            (p[l] == '\0' || p[l] == ' ' || p[l] == ')' || p[l] == ']' || p[l] == '|'))
            return 1;
    return 0;
}

void qtool_opt_help(FILE *f, const qtool_opt_cmd *c)
{
    char lead[96], item[384];
    int col = snprintf(lead, sizeof lead, "usage: %s %s", qtool_opt_program, c->name);
    const int indent = col, width = WIDTH;
    fputs(lead, f);
    if (c->synopsis) {
        fprintf(f, " %s", c->synopsis);
        col += 1 + (int)strlen(c->synopsis);
    }
    size_t n = count(c->opts);
    for (size_t k = 0; k <= n; ++k) {
        if (k < n && (c->opts[k].renamed || in_synopsis(c->synopsis, c->opts[k].name)))
            continue; /* an old spelling, or said by the synopsis: in the list below, not the usage line */
        if (k < n)
            usage_item(&c->opts[k], item, sizeof item);
        else if (c->pos.max > 0 && !in_synopsis(c->synopsis, c->pos.names))
            snprintf(item, sizeof item, "%s%s%s", c->pos.min == 0 ? "[" : "", c->pos.names, c->pos.min == 0 ? "]" : "");
        else
            break;
        int len = (int)strlen(item);
        if (col + 1 + len > width && col > indent) {
            fprintf(f, "\n%*s", indent, "");
            col = indent;
        }
        fprintf(f, " %s", item);
        col += 1 + len;
    }
    fputc('\n', f);
    qtool_opt_help_list(f, c);
    if (c->prose)
        fputs(c->prose, f);
}

/* "--k, -k K" (an optional value: "--k [K]") into buf; its length */
static int list_item(const qtool_opt *o, char *buf, size_t n)
{
    char a[256];
    const char *an = o->kind == QTOOL_OPT_FLAG ? "" : arg_name(o, a, sizeof a);
    return snprintf(buf, n, "%s%s%s%s%s%s%s", o->name, o->alias ? ", " : "", o->alias ? o->alias : "",
                    o->kind == QTOOL_OPT_FLAG ? "" : " ", o->optional ? "[" : "", an, o->optional ? "]" : "");
}

void qtool_opt_help_list(FILE *f, const qtool_opt_cmd *c)
{
    char item[384];
    size_t n = count(c->opts);
    if (n > 0) {
        int w = 0;
        for (size_t k = 0; k < n; ++k) {
            const qtool_opt *o = &c->opts[k];
            int len = list_item(o, item, sizeof item);
            w = len > w && len <= 28 ? len : w;
        }
        fputs("options:\n", f);
        for (size_t k = 0; k < n; ++k) {
            const qtool_opt *o = &c->opts[k];
            char d[128], range[160] = "";
            list_item(o, item, sizeof item);
            if (o->kind == QTOOL_OPT_INT)
                snprintf(range, sizeof range, "%ld..%ld", (long)o->lo, (long)o->hi);
            else if (o->kind == QTOOL_OPT_NUM || o->kind == QTOOL_OPT_TRIPLE)
                snprintf(range, sizeof range, "%.10g..%.10g", o->lo, o->hi);
            else if (o->kind == QTOOL_OPT_SIZE)
                snprintf(range, sizeof range, "sides 1..%ld", (long)o->hi);
            else if (o->kind == QTOOL_OPT_LIST)
                snprintf(range, sizeof range, "repeatable, at most %d",
                         o->hi > 0 && o->hi < QTOOL_OPT_LIST_MAX ? (int)o->hi : QTOOL_OPT_LIST_MAX);
            const char *def = default_text(c, o, d, sizeof d);
            char text[1024];
            size_t len = 0;
            if (o->renamed)
                len = (size_t)snprintf(text, sizeof text, "the old spelling of %s%s%s", o->renamed, o->note ? ": " : "",
                                       o->note ? o->note : "");
            else
                len = (size_t)snprintf(text, sizeof text, "%s", o->help ? o->help : "");
            if (len < sizeof text && (range[0] || o->why || def[0] || o->required))
                snprintf(text + len, sizeof text - len, " (%s%s%s%s%s%s%s)", range, range[0] && o->why ? ", " : "",
                         o->why ? o->why : "", (range[0] || o->why) && (def[0] || o->required) ? "; " : "",
                         def[0] && !o->required ? "default " : "", o->required ? "" : def, o->required ? "required" : "");
            fprintf(f, "  %-*s  ", w, item);
            wrap(f, text, 2 + w + 2);
        }
    }
}

void qtool_opt_flags(FILE *f, const qtool_opt_cmd *c)
{
    fprintf(f, "%s\n", c->name);
    for (size_t k = 0; c->opts && c->opts[k].kind != QTOOL_OPT_END; ++k) {
        /* an optional value: the flag alone is whole */
        const char *kind = c->opts[k].kind == QTOOL_OPT_FLAG || c->opts[k].optional ? "flag" : "value";
        fprintf(f, "%s\t%s\t%s\n", c->name, c->opts[k].name, kind);
        if (c->opts[k].alias)
            fprintf(f, "%s\t%s\t%s\n", c->name, c->opts[k].alias, kind);
    }
}
