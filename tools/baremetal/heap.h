/* baremetal/heap.h - what the golden cases hold of the heap (heap.c). */
#ifndef QTOOL_BAREMETAL_HEAP_H
#define QTOOL_BAREMETAL_HEAP_H

#include <stddef.h>

size_t bm_heap_live(void);
/* the peak of live bytes since the last call; starts the next period at what is live now */
size_t bm_heap_peak_reset(void);

#endif
