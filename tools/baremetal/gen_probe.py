#!/usr/bin/env python3
"""baremetal/gen_probe.py - writes the stack-measuring trampolines of probe.h for one target.

usage: gen_probe.py arm|armv4t|riscv BOUNDS OUT_DIR FUNCTION...
(armv4t: the ARM7TDMI of the GBA, whose Thumb has no blx, nor mov between low registers: the call
goes through bl to a bx r12, the move is an add of 0.)
BOUNDS: the output of stack.py ("<function> <bytes>"). For each FUNCTION (a core entry point the
golden cases call; run.sh renames the cases' references to it, with objcopy --redefine-sym, to
bm_probe_<function>) OUT_DIR/probe.S gets bm_probe_<function>, and
OUT_DIR/probe_table.c its name, bound and measured maximum. A trampoline paints 2 x bound + 256
bytes below its caller's stack pointer (not the whole stack: some functions run 10^5 times), calls
<function> with the registers and stack arguments untouched, then scans up from the deepest
painted word for the first one written. Single-threaded, no interrupts: the scratch area is static.
"""
import sys

PATTERN = 0xC5A5C5A5

ARM_COMMON = """
    .syntax unified
    .thumb
    .text
    .balign 4
    .thumb_func
    .type bm_probe_common, %%function
@ entry: r0-r3 the arguments as the caller passed them; bm_probe_tmp holds r0, r1, the real
@ function, its index, its paint depth and the return address (written by the stub)
bm_probe_common:
    ldr r0, =bm_probe_tmp
    ldr r1, [r0, #20]
    cmp r1, #0
    bne 9f
    movs r1, #1
    str r1, [r0, #20]
    str r2, [r0, #24]
    str r3, [r0, #28]
    mov r1, sp
    str r1, [r0, #32]          @ the caller's sp
    ldr r1, [r0, #12]
    str r1, [r0, #36]          @ the outer call's index and return address, kept from nested stubs
    ldr r1, [r0, #16]
    str r1, [r0, #40]
    mov r1, sp
    ldr r2, [r0, #44]          @ depth
    subs r2, r1, r2
    ldr r3, =__stack_limit
    cmp r2, r3
    bhs 1f
    mov r2, r3
1:  str r2, [r0, #48]          @ the deepest painted word
    ldr r3, =%(pattern)s
2:  subs r1, #4
    str r3, [r1]
    cmp r1, r2
    bhi 2b
    ldr r1, [r0, #8]
    mov r12, r1
    ldr r3, [r0, #28]
    ldr r2, [r0, #24]
    ldr r1, [r0, #4]
    ldr r0, [r0, #0]
    blx r12
    ldr r2, =bm_probe_tmp
    str r0, [r2, #0]
    str r1, [r2, #4]
    ldr r1, [r2, #48]
    ldr r3, =%(pattern)s
3:  ldr r0, [r2, #32]
    cmp r1, r0
    bhs 4f
    ldr r0, [r1]
    cmp r0, r3
    bne 4f
    adds r1, #4
    b 3b
4:  ldr r0, [r2, #32]
    subs r0, r0, r1            @ bytes used below the caller's sp
    adds r0, #1                @ (+1: 0 means never called)
    ldr r1, [r2, #36]
    lsls r1, r1, #2
    ldr r3, =bm_probe_used
    adds r3, r3, r1
    ldr r1, [r3]
    cmp r0, r1
    bls 5f
    str r0, [r3]
5:  movs r0, #0
    str r0, [r2, #20]
    ldr r0, [r2, #40]
    mov lr, r0
    ldr r0, [r2, #0]
    ldr r1, [r2, #4]
    bx lr
9:  ldr r1, [r0, #16]          @ nested: straight through, as if called directly
    mov lr, r1
    ldr r1, [r0, #8]
    mov r12, r1
    ldr r1, [r0, #4]
    ldr r0, [r0, #0]
    bx r12
    .ltorg
"""

ARM_STUB = """
    .balign 2
    .global bm_probe_%(f)s
    .thumb_func
    .type bm_probe_%(f)s, %%function
bm_probe_%(f)s:
    mov r12, r0
    ldr r0, =bm_probe_tmp
    str r1, [r0, #4]
    mov r1, r12
    str r1, [r0, #0]
    mov r1, lr
    str r1, [r0, #16]
    ldr r1, [r0, #20]
    cmp r1, #0
    bne 1f
    ldr r1, =%(depth)d
    str r1, [r0, #44]
    movs r1, #%(i)d
    str r1, [r0, #12]
1:  ldr r1, =%(f)s
    str r1, [r0, #8]
    bl bm_probe_common
    .ltorg
"""

# ARMv4T Thumb has no blx: bl here sets lr (with the Thumb bit), bx r12 enters the function in its
# own state (Thumb or ARM)
V4T_CALL = """
    .thumb_func
bm_probe_call_r12:
    bx r12
"""

RV_COMMON = """
    .text
    .balign 4
# entry: a0-a7 and the stack as the caller passed them; t0 the real function, t1 its index,
# t2 the paint depth, ra the caller's return address
bm_probe_common:
    la t3, bm_probe_tmp
    lw t4, 0(t3)
    bnez t4, 9f
    li t4, 1
    sw t4, 0(t3)
    sw ra, 4(t3)
    sw t1, 8(t3)
    sw sp, 12(t3)
    sub t5, sp, t2
    la t6, __stack_limit
    bgeu t5, t6, 1f
    mv t5, t6
1:  sw t5, 16(t3)
    li t4, %(pattern)s
    mv t6, sp
2:  addi t6, t6, -4
    sw t4, 0(t6)
    bgtu t6, t5, 2b
    jalr t0
    la t3, bm_probe_tmp
    lw t5, 16(t3)
    lw t2, 12(t3)
    li t4, %(pattern)s
3:  bgeu t5, t2, 4f
    lw t6, 0(t5)
    bne t6, t4, 4f
    addi t5, t5, 4
    j 3b
4:  sub t6, t2, t5
    addi t6, t6, 1             # (+1: 0 means never called)
    lw t1, 8(t3)
    slli t1, t1, 2
    la t2, bm_probe_used
    add t2, t2, t1
    lw t1, 0(t2)
    bleu t6, t1, 5f
    sw t6, 0(t2)
5:  sw zero, 0(t3)
    lw ra, 4(t3)
    ret
9:  jr t0
"""

RV_STUB = """
    .balign 2
    .global bm_probe_%(f)s
bm_probe_%(f)s:
    la t0, %(f)s
    li t1, %(i)d
    li t2, %(depth)d
    j bm_probe_common
"""


def main(argv):
    arch, bounds_path, out = argv[1], argv[2], argv[3]
    funcs = sorted(set(argv[4:]))
    bounds = {}
    with open(bounds_path) as f:
        for line in f:
            p = line.split()
            if len(p) == 2:
                bounds[p[0]] = int(p[1])
    funcs = [f for f in funcs if f in bounds]
    if len(funcs) > 255:
        sys.exit("gen_probe: more than 255 functions")
    if arch not in ("arm", "armv4t", "riscv"):
        sys.exit("gen_probe: unknown arch %s" % arch)
    common = RV_COMMON if arch == "riscv" else ARM_COMMON
    if arch == "armv4t":
        common = common.replace("    blx r12\n", "    bl bm_probe_call_r12\n") + V4T_CALL
        common = common.replace("    mov r2, r3\n", "    adds r2, r3, #0\n")  # (no low-to-low mov)
    asm = [common % {"pattern": hex(PATTERN)}]
    for i, f in enumerate(funcs):
        stub = RV_STUB if arch == "riscv" else ARM_STUB
        asm.append(stub % {"f": f, "i": i, "depth": (2 * bounds[f] + 256) & ~3})
    with open(out + "/probe.S", "w") as f:
        f.write("/* generated by tools/baremetal/gen_probe.py: do not edit */\n")
        f.write("".join(asm))
    n = max(len(funcs), 1)
    with open(out + "/probe_table.c", "w") as f:
        f.write("/* generated by tools/baremetal/gen_probe.py: do not edit */\n")
        f.write('#include <stdint.h>\n#include "probe.h"\n#include "semi.h"\n')
        f.write("uint32_t bm_probe_tmp[16];\n")
        f.write("uint32_t bm_probe_used[%d];\n" % n)
        f.write("static const char *const names[%d] = {%s};\n" % (n, ", ".join('"%s"' % x for x in funcs) or "0"))
        f.write("static const uint32_t bounds[%d] = {%s};\n" % (n, ", ".join(str(bounds[x]) for x in funcs) or "0"))
        f.write("void bm_probe_report(void)\n{\n")
        f.write("    for (unsigned i = 0; i < %d; ++i)\n" % len(funcs))
        f.write("        if (bm_probe_used[i] != 0) {\n")
        f.write('            bm_puts("stack "), bm_puts(names[i]), bm_puts(" "), bm_putu(bm_probe_used[i] - 1u);\n')
        f.write('            bm_puts(" bound "), bm_putu(bounds[i]), bm_puts("\\n");\n')
        f.write("        }\n}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
