/*
 * bake/extras.h - the chunks a sharded bake carries beside its partial sums: light paths (LPTH) and
 * lamp occlusion (LOCC). They are per pixel, so each shard bakes the rows y with y % nshards ==
 * shard (interleaved rows: sky and scene rows spread evenly, so the shards cost the same) and
 * leaves the others empty (0 edges, occlusion 0); `qibl merge` takes every row from its shard
 * (qtool_extras_join) and copies the whole chunks into the asset. Every shard writes its extras
 * file, also with no chunk, so a shard baked without --sun-path is refused by name at the merge
 * instead of dropping the path. The unshadowed maps travel as a second partial-sums file (SUMS.u,
 * same format), split into direction blocks like the shadowed ones.
 *
 * Extras file (SUMS.x), version 2, little-endian:
 *     0  "QIBLXTR2"
 *     8  u32 shard, u32 nshards (shard < nshards <= QTOOL_EXTRAS_MAX_SHARDS)
 *    16  u32 count (0..QTOOL_EXTRAS_MAX)
 *    20  count records: u32 type (LPTH or LOCC), u32 size, u32 CRC-32 of the payload, payload
 *    the file ends exactly after the last record
 * The reader refuses anything else with a one-line reason naming the file; version 1 ("QIBLXTR1",
 * whole chunks from shard 0) by name.
 */
#ifndef QTOOL_BAKE_EXTRAS_H
#define QTOOL_BAKE_EXTRAS_H

#include <stddef.h>
#include <stdint.h>

#define QTOOL_EXTRAS_MAX 16
#define QTOOL_EXTRAS_MAX_SHARDS 4096u /* = QTOOL_BAKE_MAX_SHARDS */

typedef struct qtool_extras {
    uint32_t shard, nshards; /* 0 and 1: a whole bake's chunks */
    uint32_t count;
    uint32_t type[QTOOL_EXTRAS_MAX];
    uint8_t *data[QTOOL_EXTRAS_MAX]; /* malloc'ed */
    size_t size[QTOOL_EXTRAS_MAX];
} qtool_extras;

/* The file's bytes (*out malloc'ed). 0 or -1 (no memory, too many chunks). */
int qtool_extras_encode(const qtool_extras *x, uint8_t **out, size_t *n);
/* Parses bytes into x (payloads copied); name is for messages. 0, or -1 with the reason in err. */
int qtool_extras_decode(const uint8_t *b, size_t n, const char *name, qtool_extras *x, char *err, size_t errlen);
int qtool_extras_write(const qtool_extras *x, const char *path, char *err, size_t errlen);
int qtool_extras_read(const char *path, qtool_extras *x, char *err, size_t errlen);
void qtool_extras_free(qtool_extras *x);

/* Joins the shards' chunks: parts[s] is shard s of nshards, or NULL when that shard is absent (a
 * partial merge); every given part has the same count, chunk i of each of the same type and header
 * (LPTH: size, kind, keys; LOCC: size). Row y comes from part y % nshards, empty (no edges,
 * occlusion 0) when that part is absent. w x h (0 x 0: the first part's) is the bake's size every
 * chunk must have. out gets the joined chunks with shard 0 of 1 (the caller sets the shard of a
 * partial join); names[s] name the files in messages ("b.x: 3 light path/occlusion chunks, a.x has
 * 0: shards of different bakes ..."). 0, or -1 with the reason in err and out untouched. */
int qtool_extras_join(const qtool_extras *const *parts, const char *const *names, uint32_t nshards, uint32_t w,
                      uint32_t h, qtool_extras *out, char *err, size_t errlen);

#endif
