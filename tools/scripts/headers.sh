#!/bin/bash
# headers.sh - prove every public header compiles on its own as C99 and C11 and as C++98/11/17,
# with gcc and clang, warning-free, and that a C++ program links against the C library.
#
# Engines include qibl from C++ and from C; each public header (core/include/qibl.h,
# core/include/qibl/*.h, platform/soft/include/qibl/*.h, platform/gles2/include/qibl/gles2.h) is compiled alone in a tiny TU in every
# language mode with each compiler (-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
# -Wundef -Werror), so a header that needs another first, uses `restrict` in C++ or a C-only
# construct fails here. Then the umbrella headers in C++ are compiled for a 32-bit target too
# (arm-none-eabi-g++, clang --target=armv6m-none-eabi -ffreestanding: long is 32 bits there and
# newlib's <stdint.h> hides INT32_MAX from C++98), and a C++ TU calling the core (extern "C") is
# linked with the core built by the C compiler and run.
# The C++ builds add what C++ engines turn on: -Wold-style-cast and -Wzero-as-null-pointer-constant
# (both compilers) and -Wuseless-cast (g++), for the inline functions and for the macros, which a
# second TU per header expands in C++ code outside any extern "C" block.
set -u
cd "$(dirname "$0")/../.." || exit 1
. tools/scripts/check-lib.sh
check_start headers "${BUILD:-build}/headers"

inc="-Icore/include -Iplatform/soft/include -Iplatform/gles2/include"
common="-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wundef -Werror"
cwarn="$common -Wdouble-promotion -Wmissing-prototypes -Wstrict-prototypes"
cxxwarn_clang="$common -Wold-style-cast -Wzero-as-null-pointer-constant"
cxxwarn_gcc="$cxxwarn_clang -Wuseless-cast"
# the public macros that expand to expressions, used from C++ (each from the header that defines it)
cat > "$out/macros.cpp" <<'CPP'
#include "qibl.h"
#include "qibl/soft.h"
#include "qibl/raster.h"
#include "qibl/gles2.h"
int macros_check(int i);
int macros_check(int i)
{
    const qibl_q16_t q[4] = {QIBL_Q16_ONE, QIBL_Q30_ONE, QIBL_Q29_ONE, QIBL_Q24_ONE};
    const uint32_t id = QIBL_CONFIG_ID, cc = QIBL_FOURCC('S', 'H', 'M', 'P'), mp = QIBL_LIGHTPROBE_MAX_PIXELS;
    const qibl_status_t st[6] = {QIBL_E_FB_FORMAT, QIBL_E_FB_SIZE, QIBL_E_FB_STRIDE, QIBL_E_FB_BOUNDS,
                                 QIBL_E_RASTER_RANGE, QIBL_E_GLES2_SIZE};
    return (q[i & 3] != 0 && id != cc && mp != 0u && st[i % 6] != QIBL_OK && qibl_init_check() == QIBL_OK) ? 1 : 0;
}
CPP
headers=$( (echo core/include/qibl.h; ls core/include/qibl/*.h platform/soft/include/qibl/*.h platform/gles2/include/qibl/*.h) )

# extern "C" in every header that declares something (config.h has macros only): a missing guard
# compiles as C++ and fails only at link time, for whichever function a program calls first.
for h in $headers; do
    if grep -qE '^(typedef|struct|enum|static|const|void|unsigned|int|uint|size_t|qibl_)' "$h" &&
       ! grep -q '^extern "C" {' "$h"; then
        err "$h declares types or functions but has no extern \"C\" block for C++"
    fi
done

for cc in gcc clang; do
    command -v $cc >/dev/null 2>&1 || { err "$cc not found"; continue; }
    cxx=g++; cxxwarn=$cxxwarn_gcc
    [ $cc = clang ] && cxx=clang++ && cxxwarn=$cxxwarn_clang
    command -v $cxx >/dev/null 2>&1 || { err "$cxx not found"; continue; }
    n=0
    for h in $headers; do
        name=${h#*/include/}; tag=$(echo "$name" | tr '/.' '__')
        # one declaration besides the include: ISO C forbids an empty translation unit
        printf '#include "%s"\ntypedef int headers_check_nonempty;\n' "$name" > "$out/$tag.c"
        printf '#include "%s"\n' "$name" > "$out/$tag.cpp"
        for std in c99 c11; do
            $cc -std=$std $cwarn $inc -fsyntax-only "$out/$tag.c" || err "$h as $std with $cc"
            n=$((n + 1))
        done
        for std in c++98 c++11 c++17; do
            $cxx -std=$std $cxxwarn $inc -fsyntax-only "$out/$tag.cpp" || err "$h as $std with $cxx"
            n=$((n + 1))
        done
    done
    for std in c++98 c++11 c++17; do
        $cxx -std=$std $cxxwarn $inc -fsyntax-only "$out/macros.cpp" || err "the public macros in C++ as $std with $cxx"
    done
    echo "headers: $(echo "$headers" | wc -l) public headers, each alone: $n compiles with $cc/$cxx (C99, C11, C++98/11/17; C++ also ${cxxwarn#"$common "}) clean, and the macros in C++"
done

# 32-bit targets: long has 32 bits (a 64-bit literal is a C++98 pedantic error there), and
# newlib's <stdint.h> defines INT32_MAX for C++98 only with __STDC_LIMIT_MACROS.
printf '#include "qibl.h"\n#include "qibl/soft.h"\n' > "$out/all32.cpp"
if command -v arm-none-eabi-g++ >/dev/null 2>&1; then
    for std in c++98 c++11 c++17; do
        arm-none-eabi-g++ -mcpu=cortex-m0 -mthumb -std=$std $cxxwarn_gcc $inc -fsyntax-only "$out/all32.cpp" ||
            err "qibl.h + qibl/soft.h as $std with arm-none-eabi-g++"
        arm-none-eabi-g++ -mcpu=cortex-m0 -mthumb -std=$std $cxxwarn_gcc $inc -fsyntax-only "$out/macros.cpp" ||
            err "the public macros in C++ as $std with arm-none-eabi-g++"
    done
    echo "headers: qibl.h + qibl/soft.h clean with arm-none-eabi-g++ -mcpu=cortex-m0 (C++98/11/17)"
else
    echo "headers: arm-none-eabi-g++ not found, 32-bit newlib C++ check skipped (Debian: libstdc++-arm-none-eabi-newlib)"
fi
for std in c++98 c++11 c++17; do
    clang++ --target=armv6m-none-eabi -ffreestanding -std=$std $cxxwarn_clang $inc -fsyntax-only "$out/all32.cpp" ||
        err "qibl.h + qibl/soft.h as $std with clang++ --target=armv6m-none-eabi -ffreestanding"
done
echo "headers: qibl.h + qibl/soft.h clean with clang++ --target=armv6m-none-eabi -ffreestanding (C++98/11/17)"

# Linkage: a C++ program calling the core through the headers, linked with the core compiled as C.
cat > "$out/link.cpp" <<'CPP'
#include <cstdio>
#include "qibl.h"
#include "qibl/soft.h"
int main()
{
    qibl_q30_t y[QIBL_SH_MAX_COUNT];
    const qibl_q16_t d[3] = {0, 0, QIBL_Q16_ONE};
    uint8_t code[4];
    const qibl_q16_t rgb[3] = {QIBL_Q16_ONE, QIBL_Q16_ONE / 2, 0};
    qibl_status_t st = qibl_init_check();
    if (st == QIBL_OK)
        st = qibl_sh_eval(d, QIBL_SH_MAX_BANDS, y);
    if (st == QIBL_OK)
        st = qibl_srgbe_encode_q16_n(rgb, 1, code);
    std::printf("qibl %s from C++: %s, Y_0 = %ld\n", qibl_version(), qibl_status_str(st), (long)y[0]);
    return st == QIBL_OK ? 0 : 1;
}
CPP
mkdir -p "$out/core"
for src in core/src/*.c platform/soft/*.c; do
    gcc -std=c99 -O1 $inc -c "$src" -o "$out/core/$(basename "$src" .c).o" || err "$src does not compile"
done
for cxx in g++ clang++; do
    if $cxx -std=c++98 $common $inc "$out/link.cpp" "$out"/core/*.o -o "$out/link-$cxx" && "$out/link-$cxx"; then :
    else err "a C++98 program built by $cxx does not link or run against the C core (extern \"C\")"; fi
done

if [ $fail = 0 ]; then echo "headers: OK"; else echo "headers: FAILED" >&2; fi
exit $fail
