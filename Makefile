# qibl - top-level build (GNU make). `make help` lists the targets.

CC      ?= cc
AR      ?= ar
BUILD   ?= build
OPT     ?= -O3
# -O3 by default: the kernels (and the benchmarks' plain read loops) are written to be auto-vectorised.
CORE_OPT ?= $(OPT)

# core/: strict C99, integer-only, freestanding-clean (proven by `make cross`).
CORE_WARN   := -std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wundef -Wdouble-promotion \
               -Wmissing-prototypes -Werror
CORE_CFLAGS := $(CORE_WARN) $(CORE_OPT) -g -Icore/include
# tools/ and tests/: hosted C99 + POSIX.
HOST_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -Wall -Wextra -Werror $(OPT) -g -Icore/include -Iplatform/soft/include -Itools
HOST_LIBS   := -lm -lpthread

CORE_SRC := $(wildcard core/src/*.c)
# platform/soft: freestanding like core/, built with the core flags into the same two libraries.
PLATFORM_SRC := $(wildcard platform/soft/*.c)
PLATFORM_INC := -Iplatform/soft/include
TOOL_LIB_SRC := $(wildcard tools/ref/*.c) $(wildcard tools/io/*.c) $(wildcard tools/gen/*.c)
QIBL_SRC := $(wildcard tools/qibl/*.c)
TEST_SRC := $(wildcard tests/*_test.c)

# Two flavours of the core: the native one and the "portable" one that takes the Cortex-M0 paths
# (16x16 products, shift-subtract division) on the host, so both are tested on every run.
PORTABLE_DEFS := -DQIBL_CONFIG_NATIVE_MUL64=0 -DQIBL_CONFIG_NATIVE_DIV64=0 -DQIBL_CONFIG_NATIVE_SHIFT64=0

PLATFORM_OBJ := $(PLATFORM_SRC:%.c=$(BUILD)/native/%.o)
PLATFORM_POBJ := $(PLATFORM_SRC:%.c=$(BUILD)/portable/%.o)
CORE_OBJ := $(CORE_SRC:%.c=$(BUILD)/native/%.o) $(PLATFORM_OBJ)
CORE_POBJ := $(CORE_SRC:%.c=$(BUILD)/portable/%.o) $(PLATFORM_POBJ)
# only platform/ sees its own headers: core/ cannot include them
$(PLATFORM_OBJ) $(PLATFORM_POBJ): CORE_CFLAGS += $(PLATFORM_INC)
TOOL_LIB_OBJ := $(TOOL_LIB_SRC:%.c=$(BUILD)/host/%.o)
QIBL_OBJ := $(QIBL_SRC:%.c=$(BUILD)/host/%.o)
TESTS := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%) $(TEST_SRC:tests/%.c=$(BUILD)/tests/%-portable)

LIBQIBL := $(BUILD)/libqibl.a
LIBQIBL_PORTABLE := $(BUILD)/libqibl-portable.a
LIBTOOLS := $(BUILD)/libqibl-tools.a
QIBL := $(BUILD)/bin/qibl

.PHONY: all lib qibl test test-deps cross warnings bench demo clean help check-exhaustive
.DEFAULT_GOAL := all

all: $(LIBQIBL) $(QIBL)
lib: $(LIBQIBL)
qibl: $(QIBL)

help:
	@echo "make            build the core library and the qibl CLI ($(QIBL))"
	@echo "make demo       run the main demo"
	@echo "make test       build and run the CMocka suites (installs libcmocka-dev if it can)"
	@echo "make cross      freestanding builds for Cortex-M0/M4 and RV64, checks and size table"
	@echo "make warnings   compile core/ and platform/soft/ with gcc and clang under the strict warning set"
	@echo "make bench      benchmarks (speed against error), RESULT lines"
	@echo "make check-exhaustive  sweeps too long for make test (all 2^32 sRGBE codes; CI runs it)"
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

$(LIBQIBL): $(CORE_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^

$(LIBQIBL_PORTABLE): $(CORE_POBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^

$(LIBTOOLS): $(TOOL_LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^

$(QIBL): $(QIBL_OBJ) $(LIBTOOLS) $(LIBQIBL)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -o $@ $(QIBL_OBJ) $(LIBTOOLS) $(LIBQIBL) $(HOST_LIBS)

# ---- tests ----------------------------------------------------------------------------------
CMOCKA_CFLAGS = $(shell pkg-config --cflags cmocka 2>/dev/null)
CMOCKA_LIBS = $(shell pkg-config --libs cmocka 2>/dev/null || echo -lcmocka)

test-deps:
	@sh tools/scripts/need-cmocka.sh

$(BUILD)/tests/%_test: $(BUILD)/host/tests/%_test.o $(LIBTOOLS) $(LIBQIBL) | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -o $@ $< $(LIBTOOLS) $(LIBQIBL) $(CMOCKA_LIBS) $(HOST_LIBS)

$(BUILD)/tests/%_test-portable: $(BUILD)/host-portable/tests/%_test.o $(LIBTOOLS) $(LIBQIBL_PORTABLE) | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -o $@ $< $(LIBTOOLS) $(LIBQIBL_PORTABLE) $(CMOCKA_LIBS) $(HOST_LIBS)

$(BUILD)/host/tests/%.o: tests/%.c | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(CMOCKA_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/host-portable/tests/%.o: tests/%.c | test-deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(PORTABLE_DEFS) $(CMOCKA_CFLAGS) -MMD -MP -c $< -o $@

test: test-deps
	@$(MAKE) --no-print-directory $(TESTS) $(QIBL)
	@sh tools/scripts/run-tests.sh $(TESTS)

# Exhaustive sweeps: plain C + pthreads, no CMocka, too long for `make test` (CI runs them).
EXHAUSTIVE := $(BUILD)/tests/srgbe_exhaustive

$(BUILD)/host/tests/srgbe_exhaustive.o: tests/srgbe_exhaustive.c
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/tests/srgbe_exhaustive: $(BUILD)/host/tests/srgbe_exhaustive.o $(LIBTOOLS) $(LIBQIBL)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -o $@ $< $(LIBTOOLS) $(LIBQIBL) $(HOST_LIBS)

check-exhaustive: $(EXHAUSTIVE)
	@for t in $(EXHAUSTIVE); do ./$$t || exit 1; done

# ---- proofs and measurements ----------------------------------------------------------------
cross:
	@BUILD=$(BUILD) bash tools/scripts/cross.sh

warnings:
	@for cc in gcc clang; do \
	  if ! command -v $$cc >/dev/null 2>&1; then echo "warnings: $$cc not found" >&2; exit 1; fi; \
	  for o in -O0 -O2 -O3; do for f in $(CORE_SRC) $(PLATFORM_SRC); do \
	    $$cc $(CORE_WARN) $$o -Icore/include $(PLATFORM_INC) -fsyntax-only $$f || exit 1; \
	    $$cc $(CORE_WARN) $(PORTABLE_DEFS) $$o -Icore/include $(PLATFORM_INC) -fsyntax-only $$f || exit 1; \
	  done; done; echo "warnings: core/ and platform/soft/ clean with $$cc (-O0/-O2/-O3, native and portable paths)"; \
	done

bench: $(QIBL)
	$(QIBL) bench all

# Until the bake-and-relight demo lands (issue "Bake pipeline"), the demo relights the procedural
# courtyard (analytic SH maps) with the core kernels and writes PNGs to out/demo/.
demo: $(QIBL)
	@mkdir -p out/demo
	@echo "== qibl demo: SH basis (bands 0..2) of the sun direction (1, 1, 2), computed in integers"
	$(QIBL) sh eval --bands 3 1 1 2
	@echo "== bake the procedural courtyard to 8-bit SH maps (k = 16) with a P map and a 32^2 cube-map Y LUT"
	$(QIBL) gen -o out/demo/courtyard.qibl --k 16 --lut 32
	$(QIBL) info out/demo/courtyard.qibl | head -8
	@echo "== relight it: a low sun, then a lamp in the courtyard (integer kernels, software framebuffer)"
	$(QIBL) relight out/demo/courtyard.qibl --sun 0.5 0.3 0.8 --rgb 1.6 1.45 1.2 --png out/demo/sun.png
	$(QIBL) relight out/demo/courtyard.qibl --point 1.5 -2 0.8 --rgb 4 3.4 2.6 --lut --png out/demo/lamp.png
	$(QIBL) sh plot --png out/demo/sh_basis.png
	@echo "== demo images are in out/demo/"

clean:
	rm -rf $(BUILD) out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
