#!/bin/bash
# check-install.sh - prove the two ways an engine takes qibl, as CI runs them (make check-install):
#   1. make install PREFIX=... (and DESTDIR=...), then the integration example built against the
#      installed headers and libqibl.a through pkg-config alone;
#   2. CMake: tests/cmake_consumer takes the tree with add_subdirectory and links the example and a
#      C++17 file through the qibl::qibl target (also with QIBL_CONFIG_DEFINITIONS); the top-level
#      CMakeLists.txt (with the optional CLI) installs a package that find_package(qibl) finds.
# Every example build must print the same frames as build/bin/console_port (the Makefile's build),
# a caller compiled with another config.h must be refused by the example's start-up check, and
# `qibl --version` must say the version of qibl/version.h.
set -u
cd "$(dirname "$0")/../.." || exit 1
build="${BUILD:-build}"
out="$build/check-install"
rm -rf "$out"; mkdir -p "$out"
out=$(cd "$out" && pwd)
fail=0
err() { echo "check-install: FAIL: $*" >&2; fail=1; }
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
[ -f "$out/stage/opt/qibl/lib/libqibl.a" ] && grep -qx 'prefix=/opt/qibl' "$out/stage/opt/qibl/lib/pkgconfig/qibl.pc" ||
    err "make install DESTDIR=$out/stage PREFIX=/opt/qibl did not stage under DESTDIR with prefix /opt/qibl"
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
if cmake -S . -B "$out/cmake-top" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$cprefix" -DQIBL_BUILD_TOOLS=ON \
         > "$out/cmake-top.log" 2>&1 && cmake --build "$out/cmake-top" -j 2 >> "$out/cmake-top.log" 2>&1 &&
   cmake --install "$out/cmake-top" >> "$out/cmake-top.log" 2>&1; then
    mkdir -p "$out/find-package"
    cat > "$out/find-package/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.13)
project(qibl_find_package LANGUAGES C)
find_package(qibl REQUIRED)
add_executable(console_port "$PWD/tools/examples/console_port.c")
target_link_libraries(console_port PRIVATE qibl::qibl)
CMAKE
    if cmake -S "$out/find-package" -B "$out/find-package/build" "${gen[@]}" -DCMAKE_PREFIX_PATH="$cprefix" \
             > "$out/find-package.log" 2>&1 && cmake --build "$out/find-package/build" >> "$out/find-package.log" 2>&1; then
        "$out/find-package/build/console_port" "$out/courtyard.qibl" 3 > "$out/find-package.txt" ||
            err "console_port (find_package) failed"
        same "CMake install + find_package(qibl)" "$out/find-package.txt"
    else
        err "find_package(qibl) consumer does not build:"; tail -n 15 "$out/find-package.log" >&2
    fi
    PKG_CONFIG_PATH="$cprefix/lib/pkgconfig" pkg-config --exists qibl || err "cmake --install did not install qibl.pc"
    v=$("$cprefix/bin/qibl" --version) && echo "check-install: CMake QIBL_BUILD_TOOLS=ON installs the CLI: $v" ||
        err "the CLI built by CMake (QIBL_BUILD_TOOLS=ON) does not run"
else
    err "the top-level CMakeLists.txt does not configure, build or install:"; tail -n 15 "$out/cmake-top.log" >&2
fi

if [ $fail = 0 ]; then echo "check-install: OK"; else echo "check-install: FAILED" >&2; fi
exit $fail
