/* baremetal/crt_rv.S - reset for RV32 on qemu's virt machine (-bios none): the ELF is loaded into
 * RAM, so only the stack pointer, gp and .bss need setting up; then the stack is painted (stack.h),
 * main runs and semihosting exits. A trap prints a message and exits non-zero. */
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
2:  call bm_stack_paint
    call main
    call bm_exit

    .balign 4
bm_trap:
    la sp, __stack_top
    call bm_fault
