#!/bin/bash
# check-install.sh - prove the ways an engine takes qibl, as CI runs them (make check-install):
#   1. make install PREFIX=... (and DESTDIR=...), then the integration example built against the
#      installed headers and libraries through pkg-config alone, and through find_package(qibl 0.1);
#      the same after the install is moved elsewhere (the package files are relocatable);
#   2. CMake: tests/cmake_consumer takes the tree with add_subdirectory and links the example and a
#      C++17 file through the qibl::qibl target (also with QIBL_CONFIG_DEFINITIONS); the top-level
#      CMakeLists.txt (with the optional CLI and GLES2 backend) installs the same layout and package
#      files as make install, and the example builds from it through find_package and pkg-config.
# find_package refuses a version the install does not answer; no internal header is installed.
# Every example build must print the same frames as build/bin/console_port (the Makefile's build),
# a caller compiled with another config.h must be refused by the example's start-up check, and
# `qibl --version` must say the version of qibl/version.h.
set -u
cd "$(dirname "$0")/../.." || exit 1
build="${BUILD:-build}"
. tools/scripts/check-lib.sh
check_start check-install "$build/check-install"
out=$(cd "$out" && pwd)
for tool in pkg-config cmake; do
    command -v $tool >/dev/null 2>&1 || { echo "check-install: $tool not found (Debian: apt-get install $tool)" >&2; exit 1; }
done
cc="${CC:-cc}"
version=$(sed -n 's/^#define QIBL_VERSION_STRING "\(.*\)"/\1/p' core/include/qibl/version.h)

# the CLI says the version of the headers
v=$("$build/bin/qibl" --version) || err "qibl --version exits with $?"
case "$v" in "qibl $version "*) echo "check-install: $v";; *) err "qibl --version says '$v', version.h $version";; esac

# the reference: the Makefile's example on a small generated asset
"$build/bin/qibl" gen -o "$out/courtyard.qibl" --size 96x24 --k 9 >/dev/null || err "qibl gen failed"
"$build/bin/console_port" "$out/courtyard.qibl" 3 > "$out/ref.txt" || err "build/bin/console_port failed"
same() { # name file: the example's output must equal the reference
    if cmp -s "$out/ref.txt" "$2"; then echo "check-install: $1: same frames as build/bin/console_port"
    else err "$1 prints other frames than build/bin/console_port"; fi
}

# ---- 1. make install + pkg-config ----------------------------------------------------------------
prefix="$out/prefix"
make --no-print-directory BUILD="$build" install PREFIX="$prefix" > "$out/install.log" 2>&1 ||
    { err "make install failed"; tail -n 5 "$out/install.log" >&2; }
for f in include/qibl.h include/qibl/version.h include/qibl/soft.h lib/libqibl.a lib/libqibl-soft.a lib/pkgconfig/qibl.pc; do
    [ -f "$prefix/$f" ] || err "make install did not install $f"
done
make --no-print-directory BUILD="$build" install PREFIX=/opt/qibl DESTDIR="$out/stage" > "$out/install-destdir.log" 2>&1 ||
    err "make install DESTDIR=... failed"
# staged: the files land under DESTDIR, and the relocatable qibl.pc points at the staged tree
staged_lib=$(PKG_CONFIG_PATH="$out/stage/opt/qibl/lib/pkgconfig" pkg-config --variable=libdir qibl 2>/dev/null)
[ -f "$out/stage/opt/qibl/lib/libqibl.a" ] && [ -f "$staged_lib/libqibl-soft.a" ] ||
    err "make install DESTDIR=$out/stage PREFIX=/opt/qibl did not stage under DESTDIR (qibl.pc's libdir: '$staged_lib')"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
pv=$(pkg-config --modversion qibl) && [ "$pv" = "$version" ] || err "pkg-config --modversion qibl says '$pv', version.h $version"
# shellcheck disable=SC2046
if $cc -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Werror $(pkg-config --cflags qibl) tools/examples/console_port.c \
       $(pkg-config --libs qibl) -o "$out/console_port-pkgconfig"; then
    "$out/console_port-pkgconfig" "$out/courtyard.qibl" 3 > "$out/pkgconfig.txt" || err "console_port (pkg-config) failed"
    same "pkg-config build (make install PREFIX=$prefix)" "$out/pkgconfig.txt"
else
    err "tools/examples/console_port.c does not build through pkg-config"
fi
# find_package(qibl VERSION) consumer of an install prefix: builds the example and compares its frames
fp_consumer() { # name prefix version-request [expect-fail]
    local d="$out/fp-$1"
    mkdir -p "$d"
    cat > "$d/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.13)
project(qibl_find_package LANGUAGES C)
find_package(qibl $3 REQUIRED)
add_executable(console_port "$PWD/tools/examples/console_port.c")
target_link_libraries(console_port PRIVATE qibl::qibl)
foreach(_t qibl::core qibl::soft)
  if(NOT TARGET \${_t})
    message(FATAL_ERROR "find_package(qibl) did not define \${_t}")
  endif()
endforeach()
if(EXISTS "$2/lib/libqibl-gles2.a" AND NOT TARGET qibl::gles2)
  message(FATAL_ERROR "libqibl-gles2.a is installed but find_package(qibl) did not define qibl::gles2")
endif()
CMAKE
    if cmake -S "$d" -B "$d/build" "${gen[@]}" -DCMAKE_PREFIX_PATH="$2" > "$d.log" 2>&1 &&
       cmake --build "$d/build" >> "$d.log" 2>&1; then
        if [ "${4:-}" = fail ]; then err "$1: find_package(qibl $3) accepted an install of version $version"; return; fi
        "$d/build/console_port" "$out/courtyard.qibl" 3 > "$d.txt" || err "console_port ($1) failed"
        same "$1: find_package(qibl $3)" "$d.txt"
    elif [ "${4:-}" = fail ]; then
        echo "check-install: $1: find_package(qibl $3) refused, as it must be for version $version"
    else
        err "$1: find_package(qibl $3) consumer does not build:"; tail -n 15 "$d.log" >&2
    fi
}
pc_consumer() { # name prefix: the example through the install's qibl.pc alone
    local pcdir="$2/lib/pkgconfig"
    # shellcheck disable=SC2046
    if $cc -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Werror $(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags qibl) \
           tools/examples/console_port.c $(PKG_CONFIG_PATH="$pcdir" pkg-config --libs qibl) -o "$out/console_port-$1"; then
        "$out/console_port-$1" "$out/courtyard.qibl" 3 > "$out/$1.txt" || err "console_port ($1) failed"
        same "$1: pkg-config" "$out/$1.txt"
    else
        err "$1: the example does not build through the installed qibl.pc"
    fi
}
no_internal() { # prefix: the installed headers are the public ones only
    local bad
    bad=$(grep -rl 'qibli_\|_internal' "$1/include" 2>/dev/null)
    [ -z "$bad" ] || err "internal headers installed: $bad"
}
no_internal "$prefix"
fp_consumer make-install "$prefix" 0.1
fp_consumer make-install-newer "$prefix" 0.2 fail
[ -x "$prefix/bin/qibl" ] && "$prefix/bin/qibl" --version > /dev/null || err "make install did not install a working CLI"
# relocated: the whole prefix moved; qibl.pc and qiblConfig.cmake find it from their own places
moved="$out/moved/elsewhere"
mkdir -p "$out/moved" && cp -a "$prefix" "$moved" && rm -rf "$out/moved-from" && mv "$prefix" "$out/moved-from"
pc_consumer make-install-moved "$moved"
fp_consumer make-install-moved "$moved" 0.1
mv "$out/moved-from" "$prefix"

# a caller compiled with another config.h against the installed default library: refused at start-up
# shellcheck disable=SC2046
$cc -std=c99 -DQIBL_SH_MAX_BANDS=3 $(pkg-config --cflags qibl) tools/examples/console_port.c $(pkg-config --libs qibl) \
    -o "$out/console_port-bands3" || err "console_port with -DQIBL_SH_MAX_BANDS=3 does not build"
if "$out/console_port-bands3" "$out/courtyard.qibl" 1 > /dev/null 2> "$out/bands3.err"; then
    err "console_port built with -DQIBL_SH_MAX_BANDS=3 ran against the default library"
elif grep -q 'config' "$out/bands3.err"; then
    echo "check-install: -DQIBL_SH_MAX_BANDS=3 caller refused: $(cat "$out/bands3.err")"
else
    err "console_port built with -DQIBL_SH_MAX_BANDS=3 failed for another reason: $(cat "$out/bands3.err")"
fi

# ---- 2. CMake: add_subdirectory, and the installed package -------------------------------------
gen=(); command -v ninja >/dev/null 2>&1 && gen=(-G Ninja)
if cmake -S tests/cmake_consumer -B "$out/cmake-consumer" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release \
         -DQIBL_WARNINGS_AS_ERRORS=ON > "$out/cmake-consumer.log" 2>&1 &&
   cmake --build "$out/cmake-consumer" -j 2 >> "$out/cmake-consumer.log" 2>&1; then
    "$out/cmake-consumer/console_port" "$out/courtyard.qibl" 3 > "$out/cmake.txt" || err "console_port (CMake) failed"
    same "CMake add_subdirectory build (qibl::qibl)" "$out/cmake.txt"
    "$out/cmake-consumer/cxx_consumer" || err "the C++17 consumer failed"
else
    err "tests/cmake_consumer does not configure or build:"; tail -n 15 "$out/cmake-consumer.log" >&2
fi
# QIBL_CONFIG_DEFINITIONS reach the library and its users alike (PUBLIC): the start-up check passes
if cmake -S tests/cmake_consumer -B "$out/cmake-bands3" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release \
         -DQIBL_CONFIG_DEFINITIONS="QIBL_SH_MAX_BANDS=3;QIBL_USE_LIGHTPROBE=0" > "$out/cmake-bands3.log" 2>&1 &&
   cmake --build "$out/cmake-bands3" -j 2 >> "$out/cmake-bands3.log" 2>&1 &&
   "$out/cmake-bands3/cxx_consumer" > "$out/cmake-bands3.txt" &&
   id=$(sed -n 's/.*config id \([0-9a-f]*\).*/\1/p' "$out/cmake-bands3.txt") && [ -n "$id" ] &&
   [ $(( (0x$id >> 8) & 15 )) = 3 ] && [ $(( (0x$id >> 3) & 1 )) = 0 ]; then
    echo "check-install: CMake with QIBL_CONFIG_DEFINITIONS=QIBL_SH_MAX_BANDS=3;QIBL_USE_LIGHTPROBE=0: $(cat "$out/cmake-bands3.txt")"
else
    err "CMake with QIBL_CONFIG_DEFINITIONS: library and users do not agree:"; tail -n 5 "$out/cmake-bands3.log" "$out/cmake-bands3.txt" >&2
fi
cprefix="$out/cmake-prefix"
gles=OFF
printf '#include <EGL/egl.h>\n#include <GLES2/gl2.h>\n' | $cc -fsyntax-only -x c - 2>/dev/null && gles=ON
if cmake -S . -B "$out/cmake-top" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$cprefix" -DQIBL_BUILD_TOOLS=ON \
         -DQIBL_BUILD_GLES2=$gles > "$out/cmake-top.log" 2>&1 && cmake --build "$out/cmake-top" -j 2 >> "$out/cmake-top.log" 2>&1 &&
   cmake --install "$out/cmake-top" >> "$out/cmake-top.log" 2>&1; then
    no_internal "$cprefix"
    fp_consumer cmake-install "$cprefix" 0.1
    pc_consumer cmake-install "$cprefix"
    # one layout: the same files, and the same package files, as make install's
    a=$(cd "$prefix" && find . -type f | sort) b=$(cd "$cprefix" && find . -type f | sort)
    [ "$a" = "$b" ] || err "make install and cmake --install lay out different files: $(diff <(echo "$a") <(echo "$b") | tr '\n' ' ')"
    for f in lib/pkgconfig/qibl.pc lib/cmake/qibl/qiblConfig.cmake lib/cmake/qibl/qiblConfigVersion.cmake; do
        cmp -s "$prefix/$f" "$cprefix/$f" || err "make install and cmake --install write different $f"
    done
    [ "$a" = "$b" ] && echo "check-install: make install and cmake --install (GLES2 $gles) give the same $(echo "$a" | wc -l) files"
    v=$("$cprefix/bin/qibl" --version) && echo "check-install: CMake QIBL_BUILD_TOOLS=ON installs the CLI: $v" ||
        err "the CLI built by CMake (QIBL_BUILD_TOOLS=ON) does not run"
else
    err "the top-level CMakeLists.txt does not configure, build or install:"; tail -n 15 "$out/cmake-top.log" >&2
fi

if [ $fail = 0 ]; then echo "check-install: OK"; else echo "check-install: FAILED" >&2; fi
exit $fail
