/*
 * bake/extras.h - the chunks a sharded bake carries beside its partial sums: light paths (LPTH) and
 * lamp occlusion (LOCC), made whole by shard 0 (they are per pixel, not per direction block) and
 * copied into the asset by `qibl merge`. The unshadowed maps travel as a second partial-sums file
 * (SUMS.u, same format), split into direction blocks like the shadowed ones.
 *
 * Extras file (SUMS.x), little-endian:
 *     0  "QIBLXTR1"
 *     8  u32 count (0..QTOOL_EXTRAS_MAX)
 *    12  count records: u32 type (LPTH or LOCC), u32 size, u32 CRC-32 of the payload, payload
 *    the file ends exactly after the last record
 * The reader refuses anything else with a one-line reason naming the file.
 */
#ifndef QTOOL_BAKE_EXTRAS_H
#define QTOOL_BAKE_EXTRAS_H

#include <stddef.h>
#include <stdint.h>

#define QTOOL_EXTRAS_MAX 16

typedef struct qtool_extras {
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

#endif
