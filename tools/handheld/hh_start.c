/*
 * handheld/hh_start.c - the end of the C reset the GBA and the DS share (gba_io.c, nds_io.c): each
 * port sets up its own hardware and copies its own sections first, then calls hh_start.
 */
#include <stdint.h>

#include "handheld/hh_start.h"
#include "semi.h"
#include "stack.h"

extern uint32_t __bss_start[], __bss_end[];
extern char __tls_base[];
void _init_tls(void *tls);
void _set_tls(void *tls);
int main(void);

void hh_start(void)
{
    for (uint32_t *d = __bss_start; d < __bss_end;)
        *d++ = 0;
    /* picolibc keeps errno in TLS; without a thread pointer it writes to address 8 (on the GBA, the
     * BIOS) */
    _init_tls(__tls_base);
    _set_tls(__tls_base);
    bm_stack_paint();
    bm_exit(main());
}
