/*
 * bake/merge.c - `qibl merge`'s work (bake/job.h): shards' partial sums (plain arguments and a
 * manifest's lines) checked against each other and added, a partial set written as one shard of a
 * coarser split, the unshadowed sums (SUMS.u) and the extras (SUMS.x) joined beside them, and the
 * asset projected and written.
 */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/bake.h"
#include "bake/extras.h"
#include "bake/job.h"
#include "bake/job_internal.h"
#include "bake/tile.h"
#include "io/file.h"
#include "qibl/asset.h"
#include "qibl/lightpath.h"
#include "qtool.h"

/* the inputs: the plain arguments, then the manifest's shards with their side files and I/N named */
typedef struct {
    char **in, **side_u, **side_x; /* side_*[i]: NULL: SUMS.u/.x beside in[i]; "": none */
    long *want;                    /* I * 65536 + N from the manifest, -1 for a plain argument */
    int nin, cap;
    uint8_t *mbuf;                 /* the manifest's text, which the names point into */
} inputs;

static int file_exists(const char *p)
{
    return *p && access(p, F_OK) == 0;
}

/* input i's side file: the one its manifest line names (side[i], "" for none), else SUMS.ext */
static void side_of(char *buf, size_t n, char *const *in, char *const *side, int i, const char *ext)
{
    if (side && side[i])
        snprintf(buf, n, "%s", side[i]);
    else
        qtool_bake_side_name(buf, n, in[i], ext);
}

/* A manifest (qibl merge --manifest): one line per shard, "shard I/N SUMS [SUMS.u [SUMS.x]]" ("-"
 * for a side file the shard does not have; blank lines and lines from '#' skipped; names without
 * blanks). At most QTOOL_MERGE_MANIFEST_MAX_BYTES and QTOOL_BAKE_MAX_SHARDS lines, checked before
 * use. The entries are appended to v. 0, or -1 with err naming the line. */
#define QTOOL_MERGE_MANIFEST_MAX_BYTES ((size_t)16 << 20)
static int read_manifest(const char *path, inputs *v, char *err, size_t errlen)
{
    static const qtool_io_kind kind = {"a shard manifest", 1, QTOOL_MERGE_MANIFEST_MAX_BYTES, 0, NULL};
    size_t n;
    if (qtool_io_load(path, &kind, &v->mbuf, &n, err, errlen) != 0)
        return -1;
    uint8_t *grown = realloc(v->mbuf, n + 1);
    if (!grown)
        return qtool_errf(err, errlen, "%s: out of memory", path);
    v->mbuf = grown;
    char *t = (char *)grown;
    t[n] = '\0';
    if (strlen(t) != n)
        return qtool_errf(err, errlen, "%s: a NUL byte: not a text manifest", path);
    int line = 0, shards = 0;
    for (char *l = t, *next; l; l = next) {
        next = strchr(l, '\n');
        if (next)
            *next++ = '\0';
        ++line;
        char *tok[6];
        int nt = 0;
        for (char *w = strtok(l, " \t\r"); w && nt < 6; w = strtok(NULL, " \t\r"))
            tok[nt++] = w;
        if (nt == 0 || tok[0][0] == '#')
            continue;
        long i, nn;
        char tail;
        if (nt < 3 || nt > 5 || strcmp(tok[0], "shard") != 0 || sscanf(tok[1], "%ld/%ld%c", &i, &nn, &tail) != 2 ||
            nn < 1 || nn > (long)QTOOL_BAKE_MAX_SHARDS || i < 0 || i >= nn)
            return qtool_errf(err, errlen, "%s:%d: not \"shard I/N SUMS [SUMS.u [SUMS.x]]\" with 0 <= I < N <= %u",
                              path, line, QTOOL_BAKE_MAX_SHARDS);
        if (++shards > (int)QTOOL_BAKE_MAX_SHARDS || v->nin >= v->cap)
            return qtool_errf(err, errlen, "%s:%d: more than %u shards", path, line, QTOOL_BAKE_MAX_SHARDS);
        v->in[v->nin] = tok[2];
        v->side_u[v->nin] = nt > 3 ? (strcmp(tok[3], "-") == 0 ? (char *)"" : tok[3]) : NULL;
        v->side_x[v->nin] = nt > 4 ? (strcmp(tok[4], "-") == 0 ? (char *)"" : tok[4]) : NULL;
        v->want[v->nin] = i * 65536 + nn;
        ++v->nin;
    }
    if (shards == 0)
        return qtool_errf(err, errlen, "%s: no shard line", path);
    return 0;
}

static void inputs_free(inputs *v)
{
    free(v->in), free(v->side_u), free(v->side_x), free(v->want), free(v->mbuf);
}

static int inputs_init(const qtool_merge_opts *o, inputs *v, char *err, size_t errlen)
{
    memset(v, 0, sizeof *v);
    v->cap = o->nin + (int)QTOOL_BAKE_MAX_SHARDS;
    v->in = malloc(sizeof(char *) * (size_t)v->cap);
    v->side_u = calloc((size_t)v->cap, sizeof(char *)), v->side_x = calloc((size_t)v->cap, sizeof(char *));
    v->want = malloc(sizeof(long) * (size_t)v->cap);
    if (!v->in || !v->side_u || !v->side_x || !v->want)
        return qtool_errf(err, errlen, "merge: out of memory");
    for (int i = 0; i < o->nin; ++i)
        v->in[i] = o->in[i], v->want[i] = -1;
    v->nin = o->nin;
    return o->manifest ? read_manifest(o->manifest, v, err, errlen) : 0;
}

/* ---- the shadowed sums --------------------------------------------------------------------------- */

/* Reads and adds every input into *total; (*seen)[s] is 1 + the input of shard s, 0 if none. Every
 * header is validated by the reader (shard < nshards <= QTOOL_BAKE_MAX_SHARDS) before use. 0 or -1. */
static int add_sums(const inputs *v, qtool_bake_sums *total, int **seen, char *err, size_t errlen)
{
    char e[1200];
    qtool_bake_sums part;
    for (int i = 0; i < v->nin; ++i) {
        const char *name = v->in[i];
        if (qtool_bake_sums_read(name, &part, err, errlen) != 0)
            return -1;
        int bad = 0;
        if (v->want[i] >= 0 &&
            (part.shard != (uint32_t)(v->want[i] / 65536) || part.nshards != (uint32_t)(v->want[i] % 65536)))
            bad = qtool_errf(err, errlen, "%s: the manifest names it shard %ld/%ld, the file is shard %u/%u", name,
                             v->want[i] / 65536, v->want[i] % 65536, part.shard, part.nshards);
        else if (i == 0) {
            *total = part;
            *seen = calloc(part.nshards, sizeof **seen);
            if (!*seen)
                return qtool_errf(err, errlen, "merge: out of memory");
            (*seen)[part.shard] = 1;
            continue;
        }
        /* same bake (and so the same shard count) first: only then is part.shard an index into seen */
        else if (qtool_bake_sums_compatible(total, &part, e, sizeof e) != 0)
            bad = qtool_errf(err, errlen, "%s: %s (first input %s)", name, e, v->in[0]);
        else if ((*seen)[part.shard])
            bad = qtool_errf(err, errlen, "%s: shard %u/%u given twice (also %s)", name, part.shard, part.nshards,
                             v->in[(*seen)[part.shard] - 1]);
        else if (qtool_bake_sums_add(total, &part, e, sizeof e) != 0)
            bad = qtool_errf(err, errlen, "%s: %s", name, e);
        else
            (*seen)[part.shard] = i + 1;
        qtool_bake_sums_free(&part);
        if (bad)
            return -1;
    }
    return 0;
}

/* A partial set (tree merges): the shards I, I + M, I + 2M, ... of N (M dividing N) hold exactly the
 * direction blocks and rows of shard I of M, so their sum is written as that shard (--sums only).
 * *newn, *news: that shard (1 and 0 for every shard); *given the shards present. 0 or -1. */
static int partial_set(const qtool_merge_opts *o, const int *seen, uint32_t nsh, uint32_t *newn, uint32_t *news,
                       uint32_t *given, char *err, size_t errlen)
{
    uint32_t first = nsh;
    *given = 0, *newn = 1, *news = 0;
    for (uint32_t s = 0; s < nsh; ++s)
        if (seen[s])
            ++*given, first = first < s ? first : s;
    if (*given == nsh)
        return 0;
    uint32_t m = nsh % *given == 0 ? nsh / *given : 0;
    for (uint32_t s = 0; m && s < nsh; ++s)
        if (!seen[s] != (s % m != first % m))
            m = 0;
    if (o->out || !o->sums_out) {
        for (uint32_t s = 0; s < nsh; ++s)
            if (!seen[s])
                return qtool_errf(err, errlen, "merge: shard %u/%u is missing (%s)", s, nsh,
                                  o->out ? "an asset needs every shard; a partial merge writes --sums only"
                                         : "a partial merge needs --sums OUT");
    }
    if (!m) {
        char list[200] = "";
        size_t at = 0;
        for (uint32_t s = 0; s < nsh && at < sizeof list - 16; ++s)
            if (seen[s])
                at += (size_t)snprintf(list + at, sizeof list - at, "%s%u", at ? ", " : "", s);
        return qtool_errf(err, errlen, "merge: shards %s%s of %u are not one shard of a coarser split: a partial merge "
                          "takes the shards I, I+M, I+2M, ... of N for an M dividing N (e.g. 0/4 and 2/4 make 0/2)",
                          list, at >= sizeof list - 16 ? ", ..." : "", nsh);
    }
    *newn = m, *news = first % m;
    return 0;
}

/* ---- the side files: unshadowed sums (.u) and extras (.x) ---------------------------------------- */

/* How many given shards have their side file ext (*given: how many shards are given). */
static uint32_t count_sides(const inputs *v, char *const *side, const int *seen, uint32_t nsh, const char *ext,
                            uint32_t *given)
{
    char name[4200];
    uint32_t have = 0;
    *given = 0;
    for (uint32_t s = 0; s < nsh; ++s) {
        if (!seen[s])
            continue;
        ++*given;
        side_of(name, sizeof name, v->in, side, seen[s] - 1, ext);
        have += file_exists(name) ? 1u : 0u;
    }
    return have;
}

/* When have of the given shards have their side file ext but not all: -1 with err naming the first
 * missing one (what: what it holds); else 0. */
static int side_missing(const inputs *v, char *const *side, const int *seen, uint32_t nsh, const char *ext,
                        const char *what, uint32_t have, uint32_t given, char *err, size_t errlen)
{
    char name[4200];
    for (uint32_t s = 0; have != 0 && have != given && s < nsh; ++s) {
        if (!seen[s])
            continue;
        side_of(name, sizeof name, v->in, side, seen[s] - 1, ext);
        if (!file_exists(name))
            return qtool_errf(err, errlen, "merge: %s is missing (%s of shard %u/%u; %u other shard%s have theirs)",
                              name, what, s, nsh, have, have == 1 ? "" : "s");
    }
    return 0;
}

/* The unshadowed sums of every given shard (SUMS.u), added into *tu. 0 or -1. */
static int add_unshadowed(const inputs *v, const int *seen, uint32_t nsh, const qtool_bake_sums *total,
                          qtool_bake_sums *tu, char *err, size_t errlen)
{
    char name[4200], e[1200];
    qtool_bake_sums part;
    int started = 0;
    for (uint32_t s = 0; s < nsh; ++s) {
        if (!seen[s])
            continue;
        side_of(name, sizeof name, v->in, v->side_u, seen[s] - 1, "u");
        if (qtool_bake_sums_read(name, &part, err, errlen) != 0)
            return -1;
        int bad = 0;
        if (part.shard != s || part.nshards != nsh || part.w != total->w || part.h != total->h ||
            part.ndirs != total->ndirs || part.kind != total->kind ||
            memcmp(part.pmap, total->pmap, (size_t)part.w * part.h * 12) != 0)
            bad = qtool_errf(err, errlen, "%s: not the unshadowed sums of %s (shard %u/%u of another bake)", name,
                             v->in[seen[s] - 1], part.shard, part.nshards);
        else if (!started) {
            *tu = part, started = 1;
            continue;
        } else if (qtool_bake_sums_add(tu, &part, e, sizeof e) != 0)
            bad = qtool_errf(err, errlen, "%s: %s", name, e);
        qtool_bake_sums_free(&part);
        if (bad)
            return -1;
    }
    return 0;
}

/* Every given shard's extras (its rows of the light paths and lamp occlusion) joined into xx. 0 or -1. */
static int join_extras(const inputs *v, const int *seen, uint32_t nsh, const qtool_bake_sums *total, qtool_extras *xx,
                       char *err, size_t errlen)
{
    char name[4200];
    qtool_extras *parts = calloc(nsh, sizeof *parts);
    const qtool_extras **byshard = calloc(nsh, sizeof *byshard);
    char **names = calloc(nsh, sizeof *names);
    int bad = !parts || !names || !byshard ? qtool_errf(err, errlen, "merge: out of memory") : 0;
    for (uint32_t s = 0; !bad && s < nsh; ++s) {
        if (!seen[s])
            continue;
        side_of(name, sizeof name, v->in, v->side_x, seen[s] - 1, "x");
        names[s] = malloc(strlen(name) + 1);
        if (!names[s])
            bad = qtool_errf(err, errlen, "merge: out of memory");
        else if (strcpy(names[s], name), qtool_extras_read(name, &parts[s], err, errlen) != 0)
            bad = -1;
        else
            byshard[s] = &parts[s];
    }
    if (!bad &&
        qtool_extras_join(byshard, (const char *const *)names, nsh, total->w, total->h, xx, err, errlen) != 0)
        bad = -1;
    for (uint32_t s = 0; parts && names && s < nsh; ++s)
        qtool_extras_free(&parts[s]), free(names[s]);
    free(parts), free(names), free(byshard);
    return bad;
}

/* The joined chunks into the asset's extras x. 0 or -1. */
static int extras_chunks(const qtool_extras *xx, qtool_bake_asset_extras *x, char *err, size_t errlen)
{
    for (uint32_t i = 0; i < xx->count; ++i) {
        if (xx->type[i] == QIBL_CHUNK_LOCC && !x->locc)
            x->locc = xx->data[i], x->locc_n = xx->size[i];
        else if (xx->type[i] == QIBL_CHUNK_LPTH && x->npaths < 8)
            x->paths[x->npaths] = xx->data[i], x->sizes[x->npaths++] = xx->size[i];
        else
            return qtool_errf(err, errlen, "merge: more than 8 light paths or two lamp occlusions");
    }
    return 0;
}

/* partial_out's side file with that suffix, named into side; when this merge has none (have 0) a
 * stale one is removed, so that it cannot reach the next merge. Returns have: 1 to write it. */
static int side_to_write(char *side, size_t n, const char *partial_out, const char *suffix, int have)
{
    qtool_bake_side_name(side, n, partial_out, suffix);
    if (!have)
        (void)unlink(side);
    return have;
}

/* A partial sum's side files as one shard of the coarser split. 0 or -1. */
static int write_partial_sides(const char *partial_out, const qtool_bake_sums *total, qtool_bake_sums *tu, int have,
                               qtool_extras *xx, int hx, char *err, size_t errlen)
{
    char side[4200];
    if (side_to_write(side, sizeof side, partial_out, "u", have)) {
        tu->shard = total->shard, tu->nshards = total->nshards;
        if (qtool_bake_sums_write(tu, side, err, errlen) != 0)
            return -1;
    }
    if (side_to_write(side, sizeof side, partial_out, "x", hx)) {
        xx->shard = total->shard, xx->nshards = total->nshards;
        if (qtool_extras_write(xx, side, err, errlen) != 0)
            return -1;
    }
    return 0;
}

/* The unshadowed maps from the given shards' SUMS.u (all or none: a bake writes them for every
 * shard) and their light paths and lamp occlusion joined from every SUMS.x, into x. partial_out
 * (the merge's --sums, may be NULL): the unshadowed sums and the joined extras are also written
 * beside it (.u, .x) as shard total->shard of total->nshards, so a later merge of it alone loses
 * nothing; project: the unshadowed maps into mu (for an asset). 0, or -1 with err naming the file. */
static int merge_extras(const inputs *v, const int *seen, uint32_t nsh, const qtool_bake_sums *total, int lsq,
                        const char *partial_out, int project, qtool_gen_maps *mu, qtool_extras *xx,
                        qtool_bake_asset_extras *x, char *err, size_t errlen)
{
    uint32_t given, have = count_sides(v, v->side_u, seen, nsh, "u", &given), hx = 0;
    if (side_missing(v, v->side_u, seen, nsh, "u", "the unshadowed sums", have, given, err, errlen) != 0)
        return -1;
    qtool_bake_sums tu = {0};
    int rc = have ? add_unshadowed(v, seen, nsh, total, &tu, err, errlen) : 0;
    if (rc == 0 && have && project) {
        if (qtool_bake_coeffs(&tu, tu.k, lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, mu) != 0)
            rc = qtool_errf(err, errlen, "merge: cannot project the unshadowed sums (too few directions or no memory)");
        else
            x->mu = mu;
    }
    if (rc == 0)
        hx = count_sides(v, v->side_x, seen, nsh, "x", &given);
    if (rc == 0 && hx != 0 && !have)
        rc = qtool_errf(err, errlen, "merge: light paths (.x files) without the unshadowed sums (.u files)");
    if (rc == 0)
        rc = side_missing(v, v->side_x, seen, nsh, "x", "the light paths and lamp occlusion", hx, given, err, errlen);
    if (rc == 0 && hx)
        rc = join_extras(v, seen, nsh, total, xx, err, errlen) != 0 || extras_chunks(xx, x, err, errlen) != 0 ? -1 : 0;
    if (rc == 0 && partial_out)
        rc = write_partial_sides(partial_out, total, &tu, have != 0, xx, hx != 0, err, errlen);
    qtool_bake_sums_free(&tu);
    return rc;
}

/* ---- the job ------------------------------------------------------------------------------------- */

int qtool_bake_merge(const qtool_merge_opts *o, FILE *out, char *err, size_t errlen)
{
    inputs v;
    qtool_bake_sums total = {0};
    qtool_gen_maps mu = {0};
    qtool_extras xx;
    qtool_bake_asset_extras x;
    memset(&xx, 0, sizeof xx), memset(&x, 0, sizeof x);
    int *seen = NULL; /* per shard index: 1 + the input it came from, 0 if none yet */
    uint32_t newn, news, given;
    int rc = -1;
    int part = !o->ranges && o->nin > 0 && qtool_tile_is_part(o->in[0]);
    if (o->ranges || part) { /* the tile steps (bake/tile.h): the inputs are ranges files or parts */
        if (!o->out || o->sums_out || o->manifest || o->nin < 1)
            return qtool_errf(err, errlen, "merge %s: -o %s and the files only (no --sums or --manifest)",
                              o->ranges ? "--ranges" : "of tile parts", o->ranges ? "RANGES" : "ASSET"),
                   2;
        return o->ranges ? qtool_tile_reduce(o->out, o->in, o->nin, out, err, errlen)
                         : qtool_tile_merge(o->out, o->in, o->nin, out, err, errlen);
    }
    if (inputs_init(o, &v, err, errlen) != 0 || add_sums(&v, &total, &seen, err, errlen) != 0 ||
        partial_set(o, seen, total.nshards, &newn, &news, &given, err, errlen) != 0)
        goto done;
    uint32_t nsh = total.nshards;
    if (o->k > (long)total.k) {
        rc = 2;
        qtool_errf(err, errlen, "merge: --k %ld is above the shards' k = %u (bake with --k %ld or more)", o->k, total.k,
                   o->k);
        goto done;
    }
    total.shard = news, total.nshards = newn;
    if (o->sums_out && qtool_bake_sums_write(&total, o->sums_out, err, errlen) != 0)
        goto done;
    if (merge_extras(&v, seen, nsh, &total, o->lsq, o->sums_out, o->out != NULL, &mu, &xx, &x, err, errlen) != 0) {
        if (o->sums_out)
            (void)unlink(o->sums_out); /* nothing half-done: the sums without their side files would merge wrongly */
        goto done;
    }
    if (o->sums_out && !o->out)
        fprintf(out, newn == 1 ? "wrote %s: the total sums (shard %u/%u, %u input%s)\n"
                               : "wrote %s: partial sums of shard %u/%u (%u input%s)\n", o->sums_out, news, newn, given,
                given == 1 ? "" : "s");
    rc = o->out ? qtool_bake_finish_asset(&total, o->k ? (uint32_t)o->k : (total.k < 16 ? total.k : 16),
                                           (uint32_t)o->lut, o->lsq ? QTOOL_PROJ_LSQ : QTOOL_PROJ_QUADRATURE, o->layout,
                                           o->out, &x, out, err, errlen)
                : 0;
done:
    free(seen);
    inputs_free(&v);
    qtool_bake_sums_free(&total);
    qtool_gen_free(&mu);
    qtool_extras_free(&xx);
    return rc;
}
