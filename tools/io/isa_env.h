/*
 * io/isa_env.h - QIBL_ISA=scalar|sse2|avx2|avx512|auto: the tools' choice of the core's kernel set.
 *
 * The core never reads the environment: it calls the application's qibl_isa_allowed() (qibl/isa.h)
 * on each dispatched call. The tools define it here: the mask qtool_isa_force() set, else the one
 * QIBL_ISA names (read once), else every set. A value that names no set, or a set this CPU or build
 * lacks, is refused by name: qtool_isa_env_check() returns the message, the hook exits with it
 * (status 2) rather than run the suites under a choice nobody asked for.
 */
#ifndef QTOOL_IO_ISA_ENV_H
#define QTOOL_IO_ISA_ENV_H

#include <stddef.h>
#include <stdint.h>

#include "qibl/isa.h"

/* Parses a QIBL_ISA value against `have` (qibl_isa_available()'s mask): NULL, "" and "auto" give
 * *mask = ~0 (every set); "scalar", "sse2", "avx2", "neon" give that set's bit. Returns 0, or -1
 * with a one-line message in err: "QIBL_ISA: unknown value 'x' (scalar, sse2, avx2, avx512, neon, auto)" or
 * "QIBL_ISA: avx2: not available here (this CPU and build run: scalar sse2)". */
int qtool_isa_parse(const char *value, uint32_t have, uint32_t *mask, char *err, size_t err_size);

/* qtool_isa_parse of getenv("QIBL_ISA") against this CPU: 0, or -1 and the message. */
int qtool_isa_env_check(char *err, size_t err_size);

/* Forces the mask the hook returns (a test looping over the sets); 0 returns to QIBL_ISA/auto.
 * Atomic: threads see either value. */
void qtool_isa_force(uint32_t mask);

/* "avx2 (available: scalar sse2 avx2; run-time dispatch)" or "... compile-time": for --version. */
void qtool_isa_describe(char *out, size_t out_size);

#endif /* QTOOL_IO_ISA_ENV_H */
