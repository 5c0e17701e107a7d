/*
 * handheld/hh_start.h - what the two handheld ports (tools/gba, tools/nds) share in their C reset.
 */
#ifndef QTOOL_HANDHELD_HH_START_H
#define QTOOL_HANDHELD_HH_START_H

/* The end of a handheld's reset, called once its own hardware set-up and copies are done: .bss
 * zeroed, picolibc's TLS set up, the stack painted (baremetal/stack.h), then bm_exit(main()). */
void hh_start(void) __attribute__((noreturn));

#endif
