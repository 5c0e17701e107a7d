/*
 * io/isa_env.c - QIBL_ISA for the tools: the qibl_isa_allowed() hook of qibl/isa.h (io/isa_env.h).
 */
#include "io/isa_env.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const names[] = {"scalar", "sse2", "avx2", "neon", "avx512"};

static void list(uint32_t have, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i)
        if (have & QIBL_ISA_BIT(i)) {
            int r = snprintf(out + used, size - used, "%s%s", used ? " " : "", names[i]);
            if (r < 0 || (size_t)r >= size - used)
                return;
            used += (size_t)r;
        }
}

int qtool_isa_parse(const char *value, uint32_t have, uint32_t *mask, char *err, size_t err_size)
{
    if (value == NULL || value[0] == '\0' || strcmp(value, "auto") == 0) {
        *mask = ~0u;
        return 0;
    }
    for (unsigned i = 0; i < QIBL_ISA_COUNT; ++i)
        if (strcmp(value, names[i]) == 0) {
            if (!(have & QIBL_ISA_BIT(i))) {
                char l[64];
                list(have, l, sizeof l);
                snprintf(err, err_size, "QIBL_ISA: %s: not available here (this CPU and build run: %s)", names[i], l);
                return -1;
            }
            *mask = QIBL_ISA_BIT(i);
            return 0;
        }
    snprintf(err, err_size, "QIBL_ISA: unknown value '%.32s' (scalar, sse2, avx2, avx512, neon, auto)", value);
    return -1;
}

int qtool_isa_env_check(char *err, size_t err_size)
{
    uint32_t mask;
    return qtool_isa_parse(getenv("QIBL_ISA"), qibl_isa_available(), &mask, err, err_size);
}

/* 0: not read yet; else the mask (bit 31 marks "read", so an env mask is never 0) */
static uint32_t env_mask, forced;

uint32_t qibl_isa_allowed(void)
{
    const uint32_t f = __atomic_load_n(&forced, __ATOMIC_RELAXED);
    if (f != 0u)
        return f;
    uint32_t m = __atomic_load_n(&env_mask, __ATOMIC_RELAXED);
    if (m == 0u) {
        char err[160];
        if (qtool_isa_parse(getenv("QIBL_ISA"), qibl_isa_available(), &m, err, sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            exit(2);
        }
        m |= 0x80000000u;
        __atomic_store_n(&env_mask, m, __ATOMIC_RELAXED);
    }
    return m;
}

void qtool_isa_force(uint32_t mask)
{
    __atomic_store_n(&forced, mask, __ATOMIC_RELAXED);
}

void qtool_isa_describe(char *out, size_t out_size)
{
    char l[64];
    list(qibl_isa_available(), l, sizeof l);
    snprintf(out, out_size, "%s (available: %s; %s)", qibl_isa_name(qibl_isa_active()), l,
             qibl_isa_dispatches() ? "run-time dispatch" : "compile-time selection");
}
