# qibl - top-level build (GNU make). `make help` lists the targets.

# A parallel build by default, one job per core, unless the caller chose -j (or JOBS=1).
NPROC := $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
JOBS  ?= $(NPROC)
ifeq ($(filter -j%,$(MAKEFLAGS)),)
MAKEFLAGS += -j$(JOBS)
endif

CC      ?= cc
AR      ?= ar
BUILD   ?= build
OPT     ?= -O3
# -O3 by default: the kernels (and the benchmarks' plain read loops) are written to be auto-vectorised.
CORE_OPT ?= $(OPT)

# core/: strict C99, integer-only, freestanding-clean (proven by `make cross`).
CORE_WARN   := -std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion \
               -Wmissing-prototypes -Werror
# SAN: extra compile and link flags for every object and program (make test-asan sets sanitizers).
SAN     ?=
CORE_CFLAGS := $(CORE_WARN) $(CORE_OPT) -g -Icore/include $(SAN)
# tools/ and tests/: hosted C99 + POSIX.
HOST_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -Wall -Wextra -Werror $(OPT) -g -Icore/include -Iplatform/soft/include -Itools $(SAN)
HOST_LIBS   := -lm -lpthread

CORE_SRC := $(wildcard core/src/*.c)
# platform/<backend>/: each backend its own directory and library on top of the core (the backend
# contract is in docs/ARCHITECTURE.md). platform/soft is freestanding like core/ and built with the
# core flags (native and portable) into libqibl-soft.a; platform/gles2 is hosted (`make gles`).
PLATFORM_SRC := $(wildcard platform/soft/*.c)
PLATFORM_INC := -Iplatform/soft/include
TOOL_LIB_SRC := $(wildcard tools/ref/*.c) $(wildcard tools/io/*.c) $(wildcard tools/gles/*.c) $(wildcard tools/gen/*.c) $(wildcard tools/render/*.c) $(wildcard tools/bake/*.c) $(wildcard tools/transfer/*.c)
TOOL_LIB_SRC += $(wildcard tools/study/*.c) $(wildcard tools/engine/*.c) $(wildcard tools/view/*.c) $(wildcard tools/relight/*.c)
# the demo behind `qibl demo` (tools/demo: bake, relight, light paths, probe-lit rows)
TOOL_LIB_SRC += $(wildcard tools/demo/*.c)
TOOL_LIB_SRC += $(wildcard tools/probe/*.c)
# near-field light sources (tools/luminaire: the .qnf file, simulated capture, textured spotlights)
TOOL_LIB_SRC += $(wildcard tools/luminaire/*.c)
# the option tables under the CLI's commands (tools/opt: parser, help and error lines from one table)
TOOL_LIB_SRC += $(wildcard tools/opt/*.c)
# the golden cases (plain C, shared by the suites and the golden runner) and their CMocka-side check
GOLDEN_CASES_SRC := $(wildcard tools/golden/cases*.c)
TOOL_LIB_SRC += $(GOLDEN_CASES_SRC) tools/golden/check.c
QIBL_SRC := $(wildcard tools/cli/*.c)
# tools/bench: the benchmarks library (libqibl-bench.a) `qibl bench` calls; its twin_*.c compare a
# kernel with its scalar twin (tools/twin) and are built into their own program, qibl-bench
BENCH_TWIN_SRC := $(wildcard tools/bench/twin_*.c)
BENCH_SRC := $(filter-out $(BENCH_TWIN_SRC),$(wildcard tools/bench/*.c))
# tests/gles2_test.c links the GLES backend and EGL: built by its own rule below
TEST_SRC := $(filter-out tests/gles2_test.c,$(wildcard tests/*_test.c))

# platform/gles2: hosted (GL headers and libraries), its own library and target (`make gles`).
# HAVE_GLES: the EGL and GLES2 headers compile here; without them the CLI says so and
# tests/gles2_test skips (fails with QIBL_REQUIRE_GLES=1).
HAVE_GLES := $(shell printf '\043include <EGL/egl.h>\n\043include <GLES2/gl2.h>\n' | $(CC) -fsyntax-only -x c - 2>/dev/null && echo 1)
GLES_SRC := $(wildcard platform/gles2/*.c)
GLES_INC := -Iplatform/gles2/include
GLES_CFLAGS := $(CORE_WARN) $(OPT) -g -Icore/include $(GLES_INC) $(SAN)
GLES_LIBS := $(shell pkg-config --libs glesv2 egl 2>/dev/null || echo -lGLESv2 -lEGL)
GLES_OBJ := $(GLES_SRC:%.c=$(BUILD)/gles/%.o)
LIBGLES := $(BUILD)/libqibl-gles2.a
HOST_CFLAGS += $(GLES_INC) $(if $(HAVE_GLES),-DQIBL_HAVE_GLES2=1)
GLES_LINK := $(if $(HAVE_GLES),$(LIBGLES) $(GLES_LIBS))

# tools/view (`qibl view`): the window is X11 (Xlib). HAVE_X11: its headers compile here; without
# them the qibl binary still builds and `qibl view` says so (tests/view_test skips; QIBL_REQUIRE_VIEW=1
# fails instead). Only the programs that show a window link -lX11.
HAVE_X11 := $(shell printf '\043include <X11/Xlib.h>\n' | $(CC) -fsyntax-only -x c - 2>/dev/null && echo 1)
X11_LIBS := $(if $(HAVE_X11),$(shell pkg-config --libs x11 2>/dev/null || echo -lX11))
HOST_CFLAGS += $(if $(HAVE_X11),-DQIBL_HAVE_X11=1)

# Two flavours of the core: the native one and the "portable" one that takes the Cortex-M0 paths
# (16x16 products, shift-subtract division) on the host, so both are tested on every run.
# It also takes the scalar C kernels (QIBL_CONFIG_SIMD=0), the reference the SIMD paths must equal.
PORTABLE_DEFS := -DQIBL_CONFIG_NATIVE_MUL64=0 -DQIBL_CONFIG_NATIVE_DIV64=0 -DQIBL_CONFIG_NATIVE_SHIFT64=0 \
                 -DQIBL_CONFIG_SIMD=0

PLATFORM_OBJ := $(PLATFORM_SRC:%.c=$(BUILD)/native/%.o)
PLATFORM_POBJ := $(PLATFORM_SRC:%.c=$(BUILD)/portable/%.o)
CORE_OBJ := $(CORE_SRC:%.c=$(BUILD)/native/%.o)
CORE_POBJ := $(CORE_SRC:%.c=$(BUILD)/portable/%.o)
# only platform/ sees its own headers: core/ cannot include them
$(PLATFORM_OBJ) $(PLATFORM_POBJ): CORE_CFLAGS += $(PLATFORM_INC)
TOOL_LIB_OBJ := $(TOOL_LIB_SRC:%.c=$(BUILD)/host/%.o)
QIBL_OBJ := $(QIBL_SRC:%.c=$(BUILD)/host/%.o)
BENCH_OBJ := $(BENCH_SRC:%.c=$(BUILD)/host/%.o)
BENCH_TWIN_OBJ := $(BENCH_TWIN_SRC:%.c=$(BUILD)/host/%.o)
# the benchmarks name the compiler and the core's flags in their output
$(BENCH_OBJ) $(BENCH_TWIN_OBJ): HOST_CFLAGS += -DQIBL_BENCH_CORE_FLAGS='"$(CORE_OPT)"'
TESTS := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%) $(TEST_SRC:tests/%.c=$(BUILD)/tests/%-portable)

# A third flavour where the CPU has AVX2: the core built with -mavx2 (config.h then picks the AVX2
# kernels; the native flavour has SSE2), every suite linked against it; skipped with a message elsewhere.
AVX2_OK := $(shell grep -qw avx2 /proc/cpuinfo 2>/dev/null && echo 1)
CORE_AOBJ := $(CORE_SRC:%.c=$(BUILD)/avx2/%.o) $(PLATFORM_SRC:%.c=$(BUILD)/avx2/%.o)
$(PLATFORM_SRC:%.c=$(BUILD)/avx2/%.o): CORE_CFLAGS += $(PLATFORM_INC)
LIBQIBL_AVX2 := $(BUILD)/libqibl-avx2.a
AVX2_TESTS := $(if $(AVX2_OK),$(TEST_SRC:tests/%.c=$(BUILD)/tests/%-avx2))

# Run-time dispatch on hosted x86-64 (qibl/isa.h, config.h's QIBL_CONFIG_DISPATCH): the native
# library carries the scalar and AVX2 copies of the SIMD modules (core/src/x86/, the AVX2 ones built
# with -mavx2) beside their SSE2 build, and each kernel call picks one from the CPU; QIBL_ISA
# (tools/io/isa_env.h) restricts the choice for the suites and benches. DISPATCH=0: compile-time
# selection, as on every other target. Modules that gain from AVX-512 (DISPATCH_512) add a copy
# built with AVX512_FLAGS, which the CPU must have all of (isa.c checks each).
DISPATCH ?= $(shell $(CC) -dumpmachine 2>/dev/null | grep -q '^x86_64' && echo 1)
DISPATCH_MODS := shmap srgbe probe lightprobe hemi
DISPATCH_512 := shmap probe srgbe
AVX512_FLAGS := -mavx2 -mavx512f -mavx512bw -mavx512vl -mavx512cd -mavx512vnni
ifeq ($(DISPATCH),1)
DISPATCH_SRC := $(foreach m,$(DISPATCH_MODS),core/src/x86/$(m)_scalar.c core/src/x86/$(m)_avx2.c) \
                $(DISPATCH_512:%=core/src/x86/%_avx512.c)
DISPATCH_OBJ := $(DISPATCH_SRC:%.c=$(BUILD)/native/%.o)
$(CORE_OBJ) $(DISPATCH_OBJ): CORE_CFLAGS += -DQIBL_CONFIG_DISPATCH=1
$(filter %_avx2.o,$(DISPATCH_OBJ)): CORE_CFLAGS += -mavx2
$(filter %_avx512.o,$(DISPATCH_OBJ)): CORE_CFLAGS += $(AVX512_FLAGS)
CORE_OBJ += $(DISPATCH_OBJ)
endif
# the tools' qibl_isa_allowed (io/isa_env.c) is linked into every host program, referenced or not
HOST_LDFLAGS := -Wl,-u,qibl_isa_allowed
# the suites whose kernels dispatch: `make test` runs them again under each QIBL_ISA the CPU has
ISA_SUITES := shmap shmtile srgbe probe lightprobe hemi golden lightpath transfer isa

LIBQIBL := $(BUILD)/libqibl.a
LIBQIBL_PORTABLE := $(BUILD)/libqibl-portable.a
LIBSOFT := $(BUILD)/libqibl-soft.a
LIBSOFT_PORTABLE := $(BUILD)/libqibl-soft-portable.a
LIBTOOLS := $(BUILD)/libqibl-tools.a
LIBBENCH := $(BUILD)/libqibl-bench.a
QIBL := $(BUILD)/bin/qibl
QIBL_BENCH := $(BUILD)/bin/qibl-bench

.PHONY: study gles all lib qibl test test-deps cross warnings bench demo clean help check-exhaustive golden ports test-asan examples \
        install check-install check-farm amalgamate check-amalgamate docs-memory
.PHONY: baremetal baremetal-tables docs-size gba gba-tables nds nds-tables
.PHONY: docs docs-check docs-check-test docs-bench docs-probe bench-repeat
.DEFAULT_GOAL := all

all: $(LIBQIBL) $(LIBSOFT) $(QIBL) $(QIBL_BENCH)
lib: $(LIBQIBL) $(LIBSOFT)
qibl: $(QIBL)

help:
	@echo "make            build the core library and the qibl CLI ($(QIBL))"
	@echo "make demo       run the main demo (SCENE=path.obj for a mesh, DEMO_SIZE=small for the CI size, FULL=1 for the README size)"
	@echo "make test       build and run the CMocka suites (installs libcmocka-dev if it can)"
	@echo "make docs-memory  regenerate the resident-memory table of docs/porting.md (make test checks it)"
	@echo "make docs-size  rewrite docs/porting.md's size tables from a make cross run (make cross checks them)"
	@echo "make docs       rewrite every generated block of README.md and docs/ (docs/api.md too: tools/scripts/docs.sh)"
	@echo "make docs-check fail when a generated block is stale or a measured figure is typed outside one (CI runs it)"
	@echo "make docs-check-test  show that docs-check fails on a stale block (a copy of the tree, corrupted)"
	@echo "make docs-bench run the benchmarks the README quotes into docs/results/bench.txt, then make docs"
	@echo "make cross      freestanding builds for Cortex-M0/M4 and RV64, checks and size table"
	@echo "make warnings   compile core/, platform/soft/ and platform/gles2/ with gcc and clang under the strict warning set;"
	@echo "                every public header alone as C99/C11/C++98/11/17 (tools/scripts/headers.sh)"
	@echo "make gles       build platform/gles2 (libqibl-gles2.a) and run its suite on EGL (Mesa llvmpipe here)"
	@echo "make bench      benchmarks (speed against error), RESULT lines"
	@echo "make bench-repeat  make bench twice back to back: each RESULT ratio of both runs and their difference"
	@echo "make check-exhaustive  sweeps too long for make test (all 2^32 sRGBE codes; CI runs it)"
	@echo "make golden     run the golden runner natively: one hash per golden case, compared with fixtures/golden"
	@echo "make ports      the golden runner on every compiler, -O level and architecture (qemu); hashes must agree"
	@echo "make baremetal  the golden runner on Cortex-M0/M4 and RV32 under qemu-system (semihosting): hashes, stack, insn/px"
	@echo "make baremetal-tables  regenerate the stack and memory tables of docs/porting.md"
	@echo "make gba        the golden runner and the relight demo on the Game Boy Advance (ROMs run headless over"
	@echo "                libmgba): hashes, stack, cycles per pixel; gba-tables rewrites docs/porting.md's GBA block"
	@echo "make nds        the golden runner on the Nintendo DS (a ROM under desmume-cli): hashes, stack;"
	@echo "                nds-tables rewrites docs/porting.md's DS block"
	@echo "make test-asan  the suites and the CLI under AddressSanitizer + UndefinedBehaviorSanitizer (in $(BUILD)/asan)"
	@echo "make fuzz       every libFuzzer target for FUZZ_SECONDS (default 60) each; fuzz-smoke: CI's short run"
	@echo "make examples   build and run tools/examples/console_port, the integration example (docs/porting.md)"
	@echo "make install    headers, the libraries, the CLI, qibl.pc and the CMake package into PREFIX (default /usr/local; DESTDIR honoured)"
	@echo "make check-install  install to a temporary prefix and build the example through pkg-config and CMake"
	@echo "make check-farm     a one-node Slurm cluster here: a bake as 4 shards, and as 4 tiles, + merge == one bake"
	@echo "make amalgamate the core as one qibl.h + one qibl.c in $(BUILD)/amalgamated, platform/soft as qibl_soft.h + qibl_soft.c (tools/scripts/amalgamate.sh)"
	@echo "make check-amalgamate  those pairs under the strict flags as C and C++, freestanding for Cortex-M0/M4, with the goldens and the example on the C and C++ builds"
	@echo "make clean      remove $(BUILD)/ and out/"

$(BUILD)/native/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CORE_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/portable/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CORE_CFLAGS) $(PORTABLE_DEFS) -MMD -MP -c $< -o $@

$(BUILD)/host/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

# every static library below: its prerequisites archived afresh (no stale members)
define archive
@mkdir -p $(dir $@)
rm -f $@ && $(AR) rcs $@ $^
endef

$(BUILD)/avx2/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CORE_CFLAGS) -mavx2 -MMD -MP -c $< -o $@

$(LIBQIBL): $(CORE_OBJ)
$(LIBQIBL_AVX2): $(CORE_AOBJ)
$(LIBQIBL_PORTABLE): $(CORE_POBJ)
$(LIBSOFT): $(PLATFORM_OBJ)
$(LIBSOFT_PORTABLE): $(PLATFORM_POBJ)
$(LIBTOOLS): $(TOOL_LIB_OBJ)
$(LIBBENCH): $(BENCH_OBJ)
$(LIBQIBL) $(LIBQIBL_AVX2) $(LIBQIBL_PORTABLE) $(LIBSOFT) $(LIBSOFT_PORTABLE) $(LIBTOOLS) $(LIBBENCH):
	$(archive)

# tools/twin: core modules compiled again as their scalar twins (QIBL_CONFIG_SIMD=0, names renamed,
# the core's flags), so qibl-bench and the suites run the SIMD path and its reference in one process
TWIN_SRC := $(wildcard tools/twin/*.c)
TWIN_OBJ := $(TWIN_SRC:%.c=$(BUILD)/twin/%.o)
LIBTWIN := $(BUILD)/libqibl-twin.a
$(BUILD)/twin/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CORE_CFLAGS) -Itools -MMD -MP -c $< -o $@

$(LIBTWIN): $(TWIN_OBJ)
	$(archive)

$(QIBL): $(QIBL_OBJ) $(LIBBENCH) $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL) $(if $(HAVE_GLES),$(LIBGLES))
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $(QIBL_OBJ) $(LIBBENCH) $(LIBTOOLS) $(GLES_LINK) $(LIBSOFT) $(LIBQIBL) $(X11_LIBS) $(HOST_LIBS)

# the benches against the scalar twins (tools/bench/twin_*.c): not in the shipped qibl
$(QIBL_BENCH): $(BENCH_TWIN_OBJ) $(LIBBENCH) $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL) $(LIBTWIN)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $(BENCH_TWIN_OBJ) $(LIBBENCH) $(LIBTOOLS) $(LIBSOFT) $(LIBTWIN) $(LIBQIBL) $(HOST_LIBS)

# ---- platform/gles2 -------------------------------------------------------------------------
$(BUILD)/gles/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(GLES_CFLAGS) -MMD -MP -c $< -o $@

$(LIBGLES): $(GLES_OBJ)
	$(archive)

GLES_TEST := $(BUILD)/tests/gles2_test
$(GLES_TEST): $(BUILD)/host/tests/gles2_test.o $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL) $(if $(HAVE_GLES),$(LIBGLES)) | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $< $(LIBTOOLS) $(GLES_LINK) $(LIBSOFT) $(LIBQIBL) $(CMOCKA_LIBS) $(HOST_LIBS)

# the backend, its suite (EGL on Mesa: llvmpipe here) and nothing else
gles: test-deps
	@$(if $(HAVE_GLES),,echo "gles: EGL/GLES2 headers not found (Debian: apt-get install libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri)" >&2; exit 1)
	@$(MAKE) --no-print-directory $(LIBGLES) $(GLES_TEST)
	@sh tools/scripts/run-tests.sh $(GLES_TEST)

# ---- tests ----------------------------------------------------------------------------------
CMOCKA_CFLAGS = $(shell pkg-config --cflags cmocka 2>/dev/null)
CMOCKA_LIBS = $(shell pkg-config --libs cmocka 2>/dev/null || echo -lcmocka)

test-deps:
	@sh tools/scripts/need-cmocka.sh

$(BUILD)/tests/%_test: $(BUILD)/host/tests/%_test.o $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL) | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $< $(TEST_EXTRA) $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL) $(CMOCKA_LIBS) $(HOST_LIBS)

$(BUILD)/tests/%_test-portable: $(BUILD)/host-portable/tests/%_test.o $(LIBTOOLS) $(LIBSOFT_PORTABLE) $(LIBQIBL_PORTABLE) | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $< $(TEST_EXTRA) $(LIBTOOLS) $(LIBSOFT_PORTABLE) $(LIBQIBL_PORTABLE) $(CMOCKA_LIBS) $(HOST_LIBS)

$(BUILD)/tests/%_test-avx2: $(BUILD)/host/tests/%_test.o $(LIBTOOLS) $(LIBQIBL_AVX2) | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $< $(TEST_EXTRA) $(LIBTOOLS) $(LIBQIBL_AVX2) $(CMOCKA_LIBS) $(HOST_LIBS)

# lightprobe_test, shmap_test and hemi_test compare the library's path with the scalar twin (tools/twin)
LP_TESTS := $(BUILD)/tests/lightprobe_test $(BUILD)/tests/lightprobe_test-portable $(BUILD)/tests/lightprobe_test-avx2 \
            $(BUILD)/tests/shmap_test $(BUILD)/tests/shmap_test-portable $(BUILD)/tests/shmap_test-avx2 \
            $(BUILD)/tests/hemi_test $(BUILD)/tests/hemi_test-portable $(BUILD)/tests/hemi_test-avx2
$(LP_TESTS): $(LIBTWIN)
$(LP_TESTS): TEST_EXTRA = $(LIBTWIN)

# bench_test checks the benchmarks library's helpers and the hemi benches' cloth (tools/bench)
BENCH_TESTS := $(BUILD)/tests/bench_test $(BUILD)/tests/bench_test-portable $(BUILD)/tests/bench_test-avx2
$(BENCH_TESTS): $(LIBBENCH)
$(BENCH_TESTS): TEST_EXTRA = $(LIBBENCH)

# view_test grabs the viewer's window with Xlib
$(BUILD)/tests/view_test $(BUILD)/tests/view_test-portable $(BUILD)/tests/view_test-avx2: TEST_EXTRA = $(X11_LIBS)

# version_test also links a TU compiled with -DQIBL_SH_MAX_BANDS=3: a caller whose config.h differs
# from the library's must get QIBL_E_CONFIG_MISMATCH from its start-up check.
VERSION_BANDS3 := $(BUILD)/host/tests/version_bands3.o
$(VERSION_BANDS3): tests/version_bands3.c
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -DQIBL_SH_MAX_BANDS=3 -MMD -MP -c $< -o $@
$(BUILD)/tests/version_test $(BUILD)/tests/version_test-portable $(BUILD)/tests/version_test-avx2: $(VERSION_BANDS3)
$(BUILD)/tests/version_test $(BUILD)/tests/version_test-portable $(BUILD)/tests/version_test-avx2: TEST_EXTRA = $(VERSION_BANDS3)

# cli_opts_test also tests the option-table parser itself (tools/opt, in the tools library: libc only)

$(BUILD)/host/tests/%.o: tests/%.c | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(CMOCKA_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/host-portable/tests/%.o: tests/%.c | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(PORTABLE_DEFS) $(CMOCKA_CFLAGS) -MMD -MP -c $< -o $@

test: test-deps
	@$(MAKE) --no-print-directory $(TESTS) $(GLES_TEST) $(QIBL)
	@QIBL=$(QIBL) sh tools/scripts/memory-table.sh --check
	@sh tools/scripts/run-tests.sh $(TESTS) $(GLES_TEST)
	@for isa in $$($(QIBL) --isa-list); do [ "$$isa" = "$$($(QIBL) --isa-list | tail -n 1)" ] && continue; \
	    echo "== QIBL_ISA=$$isa: the suites whose kernels dispatch"; \
	    QIBL_ISA=$$isa sh tools/scripts/run-tests.sh $(ISA_SUITES:%=$(BUILD)/tests/%_test) || exit 1; done

# docs/porting.md's resident-memory table is generated (make test checks that it matches)
docs-memory: $(QIBL)
	@QIBL=$(QIBL) sh tools/scripts/memory-table.sh --update

# Exhaustive sweeps: plain C + pthreads, no CMocka, too long for `make test` (CI runs them).
EXHAUSTIVE := $(BUILD)/tests/srgbe_exhaustive

$(BUILD)/host/tests/srgbe_exhaustive.o: tests/srgbe_exhaustive.c
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/tests/srgbe_exhaustive: $(BUILD)/host/tests/srgbe_exhaustive.o $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(HOST_LDFLAGS) -o $@ $< $(LIBTOOLS) $(LIBSOFT) $(LIBQIBL) $(HOST_LIBS)

check-exhaustive: $(EXHAUSTIVE)
	@for t in $(EXHAUSTIVE); do ./$$t || exit 1; done

# ---- proofs and measurements ----------------------------------------------------------------
cross:
	@BUILD=$(BUILD) bash tools/scripts/cross.sh

# rewrites the size tables of docs/porting.md from a `make cross` run (make cross checks them)
docs-size:
	@QIBL_SIZE_DOC=write BUILD=$(BUILD) bash tools/scripts/cross.sh

# The golden runner: plain C99 + libc (core, platform/soft, the cases, SHA-256), no CMocka, so it
# cross-compiles anywhere. `make golden` runs it here; `make ports` builds and runs it for every
# configuration (tools/scripts/ports.sh, builds under $(BUILD)/ports/).
GOLDEN := $(BUILD)/bin/qibl-golden
GOLDEN_OBJ := $(GOLDEN_CASES_SRC:%.c=$(BUILD)/host/%.o) $(BUILD)/host/tools/golden/runner.o $(BUILD)/host/tools/io/sha256.o \
              $(BUILD)/host/tools/io/isa_env.o

$(GOLDEN): $(GOLDEN_OBJ) $(LIBSOFT) $(LIBQIBL)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -o $@ $(GOLDEN_OBJ) $(LIBSOFT) $(LIBQIBL)

# under every kernel set this CPU runs (QIBL_ISA): the same hashes each time
golden: $(GOLDEN) $(QIBL)
	@for isa in $$($(QIBL) --isa-list); do echo "golden: QIBL_ISA=$$isa"; QIBL_ISA=$$isa $(GOLDEN) || exit 1; done

# (the CLI makes the asset the integration example runs on in every configuration)
ports: $(QIBL)
	@BUILD=$(BUILD) bash tools/scripts/ports.sh

# ---- docs whose figures come from commands (tools/scripts/docs.sh) ---------------------------
# docs rewrites the generated blocks, docs-check compares them and counts typed figures (fast:
# no benchmark or bake; it reuses the binaries); docs-bench re-measures the timings the README
# keeps into the committed log docs/results/bench.txt (machine, compiler, flags, date named).
docs: $(QIBL) $(GOLDEN)
	@BUILD=$(BUILD) QIBL=$(QIBL) GOLDEN=$(GOLDEN) bash tools/scripts/docs.sh --write

docs-check: $(QIBL) $(GOLDEN)
	@BUILD=$(BUILD) QIBL=$(QIBL) GOLDEN=$(GOLDEN) bash tools/scripts/docs.sh --check

docs-check-test: $(QIBL) $(GOLDEN)
	@BUILD=$(BUILD) QIBL=$(QIBL) GOLDEN=$(GOLDEN) bash tests/docs_check_test.sh

docs-bench: $(QIBL) $(GOLDEN)
	@QIBL=$(QIBL) CC="$(CC)" HOST_CFLAGS="$(HOST_CFLAGS)" bash tools/scripts/docs-bench.sh docs/results/bench.txt
	@BUILD=$(BUILD) QIBL=$(QIBL) GOLDEN=$(GOLDEN) bash tools/scripts/docs.sh --write

# the README's probe table of a user's probe (demo --probe and the bake/relight/render --probe chain)
docs-probe: $(QIBL) $(GOLDEN)
	@QIBL=$(QIBL) bash tools/scripts/docs-probe.sh docs/results/probe.txt
	@$(MAKE) --no-print-directory docs

# Bare metal (tools/baremetal/run.sh): the golden runner for Cortex-M0 code on qemu's mps2-an385,
# Cortex-M4 code on mps2-an386 and RV32IMAC on virt (picolibc, semihosting); every case must print
# the hash of fixtures/golden, every wrapped entry point stay under its static stack bound; then the
# instruction counts per relit pixel on the M4 (RESULT lines). baremetal-tables rewrites the
# generated tables of docs/porting.md from the same builds.
baremetal: $(GOLDEN)
	@BUILD=$(BUILD) bash tools/baremetal/run.sh

baremetal-tables: $(GOLDEN)
	@BUILD=$(BUILD) BM_TABLES=docs/porting.md bash tools/baremetal/run.sh

# Game Boy Advance (tools/gba/run.sh): the golden runner as a cartridge ROM for the ARM7TDMI
# (Thumb, ROM / IWRAM / EWRAM, crt_gba.S, gba.ld), run headless over libmgba (tools/gba/host.c,
# the qibl-gba-run program); every case that fits the 256 KiB EWRAM must print the hash of
# fixtures/golden, the rest must say how much they need; stack bounds as on the MCU boards; then
# the relighting demo ROM (courtyard, moving sun, mode 3) in two placements, cycles per pixel.
gba: $(GOLDEN) $(QIBL) $(LIBQIBL) $(LIBSOFT)
	@BUILD=$(BUILD) bash tools/gba/run.sh

gba-tables: $(GOLDEN) $(QIBL) $(LIBQIBL) $(LIBSOFT)
	@BUILD=$(BUILD) GBA_TABLES=docs/porting.md bash tools/gba/run.sh

# The golden runner as a Nintendo DS ROM under desmume-cli (tools/nds/run.sh; Debian's desmume)
nds: $(GOLDEN)
	@BUILD=$(BUILD) bash tools/nds/run.sh

nds-tables: $(GOLDEN)
	@BUILD=$(BUILD) NDS_TABLES=docs/porting.md bash tools/nds/run.sh

# The integration example for engines (docs/porting.md): core + platform/soft + libc only, plain
# C99, built with the core's strictness; run on a small courtyard asset made by `qibl gen`.
EXAMPLES := $(BUILD)/bin/console_port $(BUILD)/bin/transfer_port
EXAMPLE_CFLAGS := -std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Werror $(OPT) -g -Icore/include \
                  -Iplatform/soft/include $(SAN)

$(BUILD)/bin/console_port: tools/examples/console_port.c $(LIBSOFT) $(LIBQIBL)
	@mkdir -p $(dir $@)
	$(CC) $(EXAMPLE_CFLAGS) -o $@ $< $(LIBSOFT) $(LIBQIBL)

# the transfer export at run time (issue 25): core only
$(BUILD)/bin/transfer_port: tools/examples/transfer_port.c $(LIBQIBL)
	@mkdir -p $(dir $@)
	$(CC) $(EXAMPLE_CFLAGS) -o $@ $< $(LIBQIBL)

examples: $(EXAMPLES) $(QIBL)
	@mkdir -p $(BUILD)/examples
	$(QIBL) gen -o $(BUILD)/examples/courtyard.qibl --size 256x64 --k 9
	$(BUILD)/bin/console_port $(BUILD)/examples/courtyard.qibl 4 $(BUILD)/examples/console_port.ppm
	@if [ -f ../shared/fixtures/meshes/teapot.obj ]; then \
	  $(QIBL) transfer ../shared/fixtures/meshes/teapot.obj --probe ../shared/fixtures/probes/quarry_01_1k.hdr --rays 0 \
	    --coarse 800 --export $(BUILD)/examples/teapot.qtr && $(BUILD)/bin/transfer_port $(BUILD)/examples/teapot.qtr 8; \
	else echo "examples: transfer_port built, not run (no ../shared/fixtures/meshes/teapot.obj)"; fi

# The suites (native and portable core paths), the golden runner and the qibl CLI (a smoke run of
# every subcommand on good and bad inputs; tests/cli_test runs it too) under ASan + UBSan, in their own
# build dir ($(BUILD)/asan); any finding is an error. All of it takes well under a minute at -O1.
# (GCC's flow warnings give false positives on instrumented code, so they stay warnings there; the
# plain builds and `make warnings` keep them errors.)
ASAN_FLAGS := -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer \
              -Wno-error=maybe-uninitialized -Wno-error=stringop-overflow \
              -Wno-error=array-bounds
test-asan: test-deps
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/asan OPT=-O1 SAN="$(ASAN_FLAGS)" $(BUILD)/asan/bin/qibl-golden
	@printf '#include <limits.h>\nint main(int argc, char **argv) { int x = INT_MAX - 1 + argc; (void)argv; return x + argc > 0; }\n' \
	  > $(BUILD)/asan/canary.c && $(CC) $(ASAN_FLAGS) $(BUILD)/asan/canary.c -o $(BUILD)/asan/canary
	@if $(BUILD)/asan/canary 2>/dev/null; then echo "test-asan: UBSan let a signed overflow pass" >&2; exit 1; \
	  else echo "test-asan: sanitizers live (a signed overflow stops a canary program)"; fi
	@echo "== golden runner under ASan + UBSan"
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  $(BUILD)/asan/bin/qibl-golden --config asan-ubsan > $(BUILD)/asan/golden.txt 2>&1; \
	  rc=$$?; grep -E ' (MISMATCH|MISSING|ERROR)|^golden: ' $(BUILD)/asan/golden.txt; \
	  [ $$rc = 0 ] || { tail -n 30 $(BUILD)/asan/golden.txt; exit 1; }
	@echo "== the qibl CLI under ASan + UBSan (tools/scripts/cli-smoke.sh)"
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/asan OPT=-O1 SAN="$(ASAN_FLAGS)" $(BUILD)/asan/bin/qibl
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  sh tools/scripts/cli-smoke.sh $(BUILD)/asan/bin/qibl $(BUILD)/asan/cli-smoke
	@echo "== suites under ASan + UBSan"
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  $(MAKE) --no-print-directory BUILD=$(BUILD)/asan OPT=-O1 SAN="$(ASAN_FLAGS)" test

# ---- fuzzing (docs/robustness.md) ----------------------------------------------------------
# libFuzzer targets: every tests/fuzz/fuzz_*.c, built with clang, ASan and UBSan (any finding aborts)
# against an instrumented copy of the core, platform/soft and the tool code, in $(BUILD)/fuzz.
# `make fuzz` runs each target for FUZZ_SECONDS on the seeds the project's writers make
# ($(FUZZ_DIR)/seeds, by tests/fuzz/seeds.c) plus tests/fuzz/corpus/<target>, and fails on any
# crash, leak, timeout or allocation above FUZZ_MALLOC_MB; `make fuzz-smoke` is CI's short run;
# `make fuzz-crashes` replays tests/fuzz/crashes-found/<target>/* (inputs that once failed).
# FUZZ_CORE=portable builds everything with the Cortex-M0 arithmetic paths, in $(BUILD)/fuzz-portable.
FUZZ_CC ?= clang
FUZZ_SECONDS ?= 60
FUZZ_SMOKE_SECONDS ?= 10
FUZZ_RSS_MB ?= 2048
# per allocation: well above what any fuzz-sized input (FUZZ_MAX_LEN) legitimately decodes to
FUZZ_MALLOC_MB ?= 512
FUZZ_MAX_LEN ?= 4096
FUZZ_TIMEOUT ?= 10
FUZZ_CORE ?= native
FUZZ_DIR := $(BUILD)/fuzz$(if $(filter portable,$(FUZZ_CORE)),-portable)
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
FUZZ_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -O1 -g $(FUZZ_SAN) -fsanitize=fuzzer-no-link \
               -Icore/include -Iplatform/soft/include -Itools $(if $(filter portable,$(FUZZ_CORE)),$(PORTABLE_DEFS))
FUZZ_SRC := $(sort $(wildcard tests/fuzz/fuzz_*.c))
FUZZ_BIN := $(FUZZ_SRC:tests/fuzz/%.c=$(FUZZ_DIR)/bin/%)
# everything a target may call: core, platform/soft, tools (not the CMocka-side golden check) and
# the CLI's commands, whose main() is renamed so libFuzzer's main is the only one, and the benchmarks
# library (fuzz_cliopts reaches the command table, and so cmd_bench.o)
FUZZ_LIB_SRC := $(CORE_SRC) $(PLATFORM_SRC) $(filter-out tools/golden/%,$(TOOL_LIB_SRC)) $(QIBL_SRC) $(BENCH_SRC)
FUZZ_LIB_OBJ := $(FUZZ_LIB_SRC:%.c=$(FUZZ_DIR)/obj/%.o)
FUZZ_LIB := $(FUZZ_DIR)/libqibl-fuzz.a
FUZZ_SEEDS := $(FUZZ_DIR)/bin/fuzz-seeds

$(FUZZ_DIR)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -Wall -Wextra -MMD -MP -c $< -o $@
$(FUZZ_DIR)/obj/tools/cli/main.o: FUZZ_CFLAGS += -Dmain=qibl_cli_main_unused

$(FUZZ_LIB): $(FUZZ_LIB_OBJ)
	rm -f $@ && $(AR) rcs $@ $^

$(FUZZ_DIR)/bin/fuzz_%: tests/fuzz/fuzz_%.c $(wildcard tests/fuzz/*.h) $(FUZZ_LIB)
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -Wall -Wextra -Werror -fsanitize=fuzzer -o $@ $< $(FUZZ_LIB) -lm -lpthread

$(FUZZ_SEEDS): tests/fuzz/seeds.c $(FUZZ_LIB)
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -Wall -Wextra -Werror -o $@ $< $(FUZZ_LIB) -lm -lpthread

.PHONY: fuzz fuzz-smoke fuzz-build fuzz-crashes
fuzz-build: $(FUZZ_BIN) $(FUZZ_SEEDS)

fuzz: fuzz-build
	@rm -rf $(FUZZ_DIR)/seeds && $(FUZZ_SEEDS) $(FUZZ_DIR)/seeds
	@FUZZ_DIR=$(FUZZ_DIR) FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_RSS_MB=$(FUZZ_RSS_MB) FUZZ_MALLOC_MB=$(FUZZ_MALLOC_MB) \
	  FUZZ_MAX_LEN=$(FUZZ_MAX_LEN) FUZZ_TIMEOUT=$(FUZZ_TIMEOUT) sh tools/scripts/fuzz.sh $(FUZZ_BIN)

# the smoke run is seeded (reproducible: a CI finding replays with the same seed); `make fuzz` is random
fuzz-smoke:
	@FUZZ_SEED=$${FUZZ_SEED:-1} $(MAKE) --no-print-directory fuzz FUZZ_SECONDS=$(FUZZ_SMOKE_SECONDS)

fuzz-crashes: fuzz-build
	@FUZZ_DIR=$(FUZZ_DIR) FUZZ_RSS_MB=$(FUZZ_RSS_MB) FUZZ_MALLOC_MB=$(FUZZ_MALLOC_MB) FUZZ_TIMEOUT=$(FUZZ_TIMEOUT) \
	  sh tools/scripts/fuzz.sh --replay $(FUZZ_BIN)

warnings:
	@for cc in gcc clang; do \
	  if ! command -v $$cc >/dev/null 2>&1; then echo "warnings: $$cc not found" >&2; exit 1; fi; \
	  for o in -O0 -O2 -O3; do for f in $(CORE_SRC) $(PLATFORM_SRC); do \
	    $$cc $(CORE_WARN) $$o -Icore/include $(PLATFORM_INC) -fsyntax-only $$f || exit 1; \
	    $$cc $(CORE_WARN) $(PORTABLE_DEFS) $$o -Icore/include $(PLATFORM_INC) -fsyntax-only $$f || exit 1; \
	  done; done; echo "warnings: core/ and platform/soft/ clean with $$cc (-O0/-O2/-O3, native and portable paths)"; \
	  $(if $(filter 1,$(DISPATCH)),for o in -O0 -O2 -O3; do for f in $(CORE_SRC) $(DISPATCH_SRC); do \
	    $$cc $(CORE_WARN) $$o -Icore/include -DQIBL_CONFIG_DISPATCH=1 $$(case $$f in (*_avx2.c) echo -mavx2;; (*_avx512.c) echo $(AVX512_FLAGS);; esac) \
	      -fsyntax-only $$f || exit 1; \
	  done; done; echo "warnings: core/ with run-time dispatch (core/src/x86/) clean with $$cc (-O0/-O2/-O3)";,) \
	  $(if $(HAVE_GLES),for o in -O0 -O2 -O3; do for f in $(GLES_SRC); do \
	    $$cc $(CORE_WARN) $$o -Icore/include $(GLES_INC) -fsyntax-only $$f || exit 1; \
	  done; done; echo "warnings: platform/gles2/ clean with $$cc (-O0/-O2/-O3)";, \
	  echo "warnings: platform/gles2/ skipped: no EGL/GLES2 headers";) \
	done
	@BUILD=$(BUILD) bash tools/scripts/headers.sh
	@python3 tools/scripts/long-functions.py 150 > /dev/null || { python3 tools/scripts/long-functions.py 150 >&2; \
	  echo "warnings: a function outside tests/ is longer than 150 lines (issue 29): split it" >&2; exit 1; }

# Every status-returning public function documented in one skeleton (Formats/Bound/Errors/On failure);
# every public header of core/ and platform/ is checked (no pending list); make docs-check runs it.
.PHONY: check-header-docs
check-header-docs:
	@python3 tools/scripts/check-header-docs.py

# ---- install: the core and platform/soft as engines link them (see also CMakeLists.txt) -------
PREFIX ?= /usr/local
LIBDIR ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
BINDIR ?= $(PREFIX)/bin
QIBL_VERSION := $(shell sed -n 's/^\#define QIBL_VERSION_STRING "\(.*\)"/\1/p' core/include/qibl/version.h)

# One layout with the CMake install (CMakeLists.txt): headers, libqibl.a, libqibl-soft.a, the CLI,
# libqibl-gles2.a and its header where EGL/GLES2 exist, and the package files (qibl.pc,
# qiblConfig.cmake, qiblConfigVersion.cmake) from tools/pkgconfig's templates, relocatable.
# Internal headers (core/src) are never installed.
SIZEOF_VOID_P := $(shell printf '__SIZEOF_POINTER__\n' | $(CC) -E -P -x c - 2>/dev/null | tail -n 1)
install: $(LIBQIBL) $(LIBSOFT) $(QIBL) $(if $(HAVE_GLES),$(LIBGLES))
	install -d $(DESTDIR)$(INCLUDEDIR)/qibl $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(LIBDIR)/cmake/qibl $(DESTDIR)$(BINDIR)
	install -m 644 core/include/qibl.h $(DESTDIR)$(INCLUDEDIR)/qibl.h
	install -m 644 core/include/qibl/*.h platform/soft/include/qibl/*.h $(DESTDIR)$(INCLUDEDIR)/qibl/
	install -m 644 $(LIBQIBL) $(DESTDIR)$(LIBDIR)/libqibl.a
	install -m 644 $(LIBSOFT) $(DESTDIR)$(LIBDIR)/libqibl-soft.a
	$(if $(HAVE_GLES),install -m 644 $(LIBGLES) $(DESTDIR)$(LIBDIR)/libqibl-gles2.a)
	$(if $(HAVE_GLES),install -m 644 platform/gles2/include/qibl/*.h $(DESTDIR)$(INCLUDEDIR)/qibl/)
	install -m 755 $(QIBL) $(DESTDIR)$(BINDIR)/qibl
	sh tools/scripts/pkg-files.sh $(BUILD)/pkg "$(PREFIX)" "$(LIBDIR)" "$(INCLUDEDIR)" $(QIBL_VERSION) "$(SIZEOF_VOID_P)"
	install -m 644 $(BUILD)/pkg/qibl.pc $(DESTDIR)$(LIBDIR)/pkgconfig/qibl.pc
	install -m 644 $(BUILD)/pkg/qiblConfig.cmake $(BUILD)/pkg/qiblConfigVersion.cmake $(DESTDIR)$(LIBDIR)/cmake/qibl/

# What CI runs: make install into a temporary prefix (and a DESTDIR), the example built through
# pkg-config and through CMake (add_subdirectory), qibl --version against version.h.
check-install: $(QIBL) $(EXAMPLES)
	@BUILD=$(BUILD) bash tools/scripts/check-install.sh

# What CI runs: a one-node Slurm cluster on this machine (slurm-wlm + munge, configured in a temporary
# directory), a bake as a job array of 4 shards plus the afterok merge, then as 4 tile shards (two
# arrays, reduce and merge), each asset byte for byte the single-machine bake's; RESULT
# farm.shard_balance, farm.tile_output_over_share. Bounded waits (FARM_TIMEOUT, default 240 s).
check-farm: $(QIBL)
	@BUILD=$(BUILD) bash tools/farm/check.sh

# The core as one qibl.h + one qibl.c (as SQLite ships), platform/soft as qibl_soft.h + qibl_soft.c,
# and their proof as C and as C++ (CI runs check-amalgamate).
amalgamate:
	@BUILD=$(BUILD) bash tools/scripts/amalgamate.sh

check-amalgamate: amalgamate $(QIBL) $(EXAMPLES)
	@BUILD=$(BUILD) bash tools/scripts/check-amalgamate.sh

# `qibl bench all`, then the kernels against their scalar twins (qibl-bench: the twins stay out of qibl)
bench: $(QIBL) $(QIBL_BENCH)
	$(QIBL) bench all
	$(QIBL_BENCH) all

# make bench twice back to back, every RESULT ratio of the two runs side by side (a report: does a
# ratio reproduce within 15 %?), the runs' output in out/bench-repeat/
bench-repeat: $(QIBL) $(QIBL_BENCH)
	@QIBL=$(QIBL) QIBL_BENCH=$(QIBL_BENCH) sh tools/scripts/bench-repeat.sh out/bench-repeat

# The light-probe approximation study (tools/study, `qibl study`): every method on every fixture
# probe (procedural skies when ../shared is absent); CSV, plots, overlays, summary in out/study/.
study: $(QIBL)
	$(QIBL) study $(wildcard ../shared/fixtures/probes/*.hdr) --out out/study

# The main demo: bake the built-in courtyard (or SCENE=path.obj) with the ray tracer, relight it with
# the core (sun sweep, moving lamp), compare with ground truth; PNGs, APNGs, contact sheet, table and
# RESULT lines in out/demo/. Sizes (tools/demo/demo.c): the default 512x128 fits a newcomer's 90 s;
# DEMO_SIZE=small is the CI version (256x64, 128 directions); FULL=1 (or DEMO_SIZE=full) the README's
# pictures at 1024x256 with the full probe-lit truths (minutes of CPU).
SCENE ?= builtin
DEMO_SIZE ?= $(if $(FULL),full,default)
DEMO_THREADS ?= $(shell n=$$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2); echo $$n)
demo: $(QIBL)
	@mkdir -p out/demo
	$(QIBL) demo --out out/demo --scene $(SCENE) --threads $(DEMO_THREADS) $(if $(filter small,$(DEMO_SIZE)),--small)$(if $(filter full,$(DEMO_SIZE)),--full)
	$(QIBL) check out/demo/scene_k16.qibl out/demo/sun_sweep.png out/demo/lamp_sweep.png out/demo/contact_sheet.png out/demo/probe_sheet.png out/demo/camera_sheet.png

clean:
	rm -rf $(BUILD) out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
