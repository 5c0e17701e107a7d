/* baremetal/crt_rv.S - reset for RV32 on qemu's virt machine (-bios none): the ELF is loaded into
 * RAM, so only the stack pointer, gp, .bss and the TLS block need setting up (.tbss zeroed, tp set
 * with picolibc's _set_tls: errno lives there, and with tp left at 0 it would be stored at address
 * 0); then the stack is painted (stack.h), main runs and semihosting exits. A trap prints a message
 * and exits non-zero. */
    .section .text.start, "ax"
    .globl _start
_start:
    .option push
    .option norelax
    la gp, __global_pointer$
    .option pop
    la sp, __stack_top
    la t0, bm_trap
    .insn i SYSTEM, 1, x0, t0, 0x305   /* csrw mtvec, t0 (without needing the zicsr spelling) */
    la t0, __bss_start
    la t1, __bss_end
1:  bgeu t0, t1, 2f
    sw zero, 0(t0)
    addi t0, t0, 4
    j 1b
2:  la t0, __tbss_start
    la t1, __tbss_end
3:  bgeu t0, t1, 4f
    sw zero, 0(t0)
    addi t0, t0, 4
    j 3b
4:  la a0, __tls_base
    call _set_tls
    call bm_stack_paint
    call main
    call bm_exit

    .balign 4
bm_trap:
    la sp, __stack_top
    call bm_fault
