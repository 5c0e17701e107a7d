/*
 * gba/hemi_tables.c - qibl-hemi-tables: bakes the hemi tables blob of (n, face) into a file
 * (qibl_hemi_tables_build, the whole blob, words written little-endian), for a port to link into
 * ROM or flash and open in place (qibl_hemi_open). make gba bakes (32, 24) and (64, 8) for the
 * golden ROM (hemi_rom.S). Hosted C99; the words are the core's, the same on every machine.
 * Usage: qibl-hemi-tables N FACE OUT
 */
#include <stdio.h>
#include <stdlib.h>

#include "qibl/hemi.h"

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: qibl-hemi-tables N FACE OUT\n");
        return 2;
    }
    const int n = atoi(argv[1]), face = atoi(argv[2]);
    const size_t size = qibl_hemi_tables_size(n, face);
    uint32_t *w = size != 0u ? malloc(size) : NULL;
    if (w == NULL) {
        fprintf(stderr, "qibl-hemi-tables: %s\n", size == 0u ? qibl_status_str(QIBL_E_HEMI_SIZE) : "out of memory");
        return 1;
    }
    qibl_status_t st = qibl_hemi_tables_build(n, face, 0u, (uint32_t)(size / 4u), w);
    if (st != QIBL_OK) {
        fprintf(stderr, "qibl-hemi-tables: qibl_hemi_tables_build: %s\n", qibl_status_str(st));
        free(w);
        return 1;
    }
    FILE *f = fopen(argv[3], "wb");
    int bad = f == NULL;
    for (size_t i = 0; !bad && i < size / 4u; ++i) {
        const unsigned char b[4] = {(unsigned char)w[i], (unsigned char)(w[i] >> 8), (unsigned char)(w[i] >> 16),
                                    (unsigned char)(w[i] >> 24)};
        bad = fwrite(b, 1, 4, f) != 4;
    }
    if (f != NULL && fclose(f) != 0)
        bad = 1;
    free(w);
    if (bad) {
        fprintf(stderr, "qibl-hemi-tables: cannot write %s\n", argv[3]);
        return 1;
    }
    printf("qibl-hemi-tables: %s: n %d, face %d, %lu bytes\n", argv[3], n, face, (unsigned long)size);
    return 0;
}
