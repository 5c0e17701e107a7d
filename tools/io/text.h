/*
 * io/text.h - labels on the tools' RGB8 pictures: a 5 x 7 bitmap font (upper case, digits and
 * common punctuation; lower case is drawn as upper case, anything else as a box), scaled by an
 * integer, so contact sheets and READMEs carry their titles without an image tool.
 */
#ifndef QTOOL_IO_TEXT_H
#define QTOOL_IO_TEXT_H

#include <stdint.h>

#define QTOOL_TEXT_ADVANCE 6 /* glyph cell width, font pixels (5 + 1 of spacing) */
#define QTOOL_TEXT_HEIGHT 7  /* font pixels */

/* Width in image pixels of s at scale (>= 1). */
int qtool_text_width(const char *s, int scale);

/* Draws s with its top-left corner at (x, y) into a w x h RGB8 image in colour rgb; pixels outside
 * the image are skipped (clipped). */
void qtool_text_draw(uint8_t *img, int w, int h, int x, int y, const char *s, int scale, const uint8_t rgb[3]);

#endif
