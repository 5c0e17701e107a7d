#!/bin/bash
# amalgamate.sh [OUTDIR] - the core as one qibl.h and one qibl.c (default OUTDIR build/amalgamated),
# as SQLite and the single-file libraries ship: copy two files into any build, no include paths.
#
# qibl.h: every header of core/include in dependency order (from the "qibl/...h" includes, starting
# at the umbrella qibl.h), with those includes removed; each keeps its own include guard, so code
# that also includes a single module header still compiles. qibl.c: #include "qibl.h", the core's
# internal headers (core/src/*.h, once each, dependencies first), then every core/src/*.c with its
# qibl and internal includes removed. One translation unit shares one scope, so the script
# (a) renames file-local names (statics, local typedefs, enum constants) that two source files
# define, in every file but the first (NAME -> NAME_<file>), and (b) #undefs each file's own macros
# at the end of its section. qibl.c compiles as C99 and as C++98/11/17 (the core's C99 `restrict`
# becomes QIBL_RESTRICT under C++, config.h). platform/soft, the software framebuffer backend,
# comes as a second pair made the same way: qibl_soft.h (platform/soft/include/qibl/*.h, including
# qibl.h) and qibl_soft.c (platform/soft/*.c), so a core-only build still copies two files.
# `make check-amalgamate` compiles the result with the core's strict flags as C and as C++,
# cross-compiles it for Cortex-M0, and runs the golden cases and the example on the C and C++ builds.
set -eu
cd "$(dirname "$0")/../.." || exit 1
out="${1:-${BUILD:-build}/amalgamated}"
mkdir -p "$out"
version=$(sed -n 's/^#define QIBL_VERSION_STRING "\(.*\)"/\1/p' core/include/qibl/version.h)
rev=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)

# ---- header order: depth-first over the quoted includes, dependencies first -------------------
# visit DIR RE STRICT H: appends H (a path relative to DIR) to $order after the headers it includes
# (RE: a sed pattern whose \1 is an included path), each once; an included header missing from DIR
# stops the script when STRICT is 1, else is passed over (the core's headers, seen from the others)
visit() {
    local dir=$1 re=$2 strict=$3 h=$4 dep seen
    for seen in "${order[@]+"${order[@]}"}"; do [ "$seen" = "$h" ] && return 0; done
    if [ ! -f "$dir/$h" ]; then
        [ "$strict" = 1 ] || return 0
        echo "amalgamate: $h is included but not in $dir" >&2; exit 1
    fi
    for dep in $(sed -n "s/$re/\1/p" "$dir/$h"); do visit "$dir" "$re" "$strict" "$dep"; done
    order+=("$h")
}
order=()
core_re='^[[:space:]]*#[[:space:]]*include[[:space:]]*"\(qibl[^"]*\.h\)".*'
for h in $(sed -n 's/^#include "\(qibl\/[^"]*\.h\)".*/\1/p' core/include/qibl.h); do visit core/include "$core_re" 1 "$h"; done
# any header qibl.h does not reach is still part of the core's API
for f in core/include/qibl/*.h; do visit core/include "$core_re" 1 "${f#core/include/}"; done
headers=("${order[@]}")

# (an inlined include becomes an empty line, so the #line numbers below stay those of the file)
strip_includes() { sed -E 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"qibl(\/[a-z0-9_]+)?\.h".*$//' "$1"; }

{
    echo "/*"
    echo " * qibl.h - amalgamated public header of the qibl core $version (git $rev), made by"
    echo " * tools/scripts/amalgamate.sh from core/include; do not edit, edit those files. Pair with qibl.c."
    echo " */"
    echo "#ifndef QIBL_AMALGAMATED_H"
    echo "#define QIBL_AMALGAMATED_H"
    echo "#define QIBL_H /* the umbrella header's guard: this file is the umbrella */"
    for h in "${headers[@]}"; do
        echo
        echo "/* ==== $h ==== */"
        strip_includes "core/include/$h"
    done
    echo
    echo "#endif /* QIBL_AMALGAMATED_H */"
} > "$out/qibl.h.tmp"

# ---- platform/soft's headers (raster.h includes soft.h), the core's replaced by qibl.h ----------
order=()
for f in platform/soft/include/qibl/*.h; do
    visit platform/soft/include '^[[:space:]]*#[[:space:]]*include[[:space:]]*"\(qibl\/[^"]*\.h\)".*' 0 "${f#platform/soft/include/}"
done
sorder=("${order[@]}")
{
    echo "/*"
    echo " * qibl_soft.h - amalgamated header of qibl's platform/soft backend $version (git $rev), made by"
    echo " * tools/scripts/amalgamate.sh from platform/soft/include; do not edit. Pair with qibl_soft.c; needs qibl.h."
    echo " */"
    echo "#ifndef QIBL_SOFT_AMALGAMATED_H"
    echo "#define QIBL_SOFT_AMALGAMATED_H"
    echo "#include \"qibl.h\""
    for h in "${sorder[@]}"; do
        echo
        echo "/* ==== platform/soft/include/$h ==== */"
        strip_includes "platform/soft/include/$h"
    done
    echo
    echo "#endif /* QIBL_SOFT_AMALGAMATED_H */"
} > "$out/qibl_soft.h.tmp"

# ---- internal headers of core/src, dependencies first --------------------------------------------
order=()
for f in core/src/*.h; do
    [ -f "$f" ] && visit core/src '^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([a-z0-9_]*\.h\)".*' 0 "$(basename "$f")"
done
internal=("${order[@]+"${order[@]}"}")
# qibl includes and includes of the internal headers, both inlined above
strip_all() {
    if [ ${#internal[@]} -gt 0 ]; then
        local alt; alt=$(printf '%s|' "${internal[@]}" | sed 's/\./\\./g; s/|$//')
        strip_includes "$1" | sed -E "s/^[[:space:]]*#[[:space:]]*include[[:space:]]*\"($alt)\".*\$//"
    else
        strip_includes "$1"
    fi
}

# ---- sources: file-local names defined in more than one file ------------------------------------
srcs=(core/src/*.c)
# names a file defines at file scope: static functions/objects, "} name;" of a typedef'd struct,
# one-line typedefs, constants of one-line enums
locals() {
    perl -ne '
        if (/^static\b([^(=\[;]*)/) { my $d = $1; $d =~ s/\s+$//; print "$1\n" if $d =~ /(\w+)$/; }
        elsif (/^\}\s*(\w+)\s*;/) { print "$1\n"; }
        elsif (/^typedef\b[^{]*?(\w+)\s*;/) { print "$1\n"; }
        elsif (/^enum\s*\{([^}]*)\}/) { print "$1\n" for ($1 =~ /\b([A-Za-z_]\w*)\s*(?:=|,|$)/g); }
    ' "$1" | sort -u
}
declare -A owner renames
for f in "${srcs[@]}"; do
    for n in $(locals "$f"); do
        if [ -n "${owner[$n]:-}" ]; then renames[$f]+=" $n"; else owner[$n]=$f; fi
    done
done
# platform/soft's sources: one translation unit of their own (qibl_soft.c), renamed among themselves
ssrcs=(platform/soft/*.c)
declare -A sowner
for f in "${ssrcs[@]}"; do
    for n in $(locals "$f"); do
        if [ -n "${sowner[$n]:-}" ]; then renames[$f]+=" $n"; else sowner[$n]=$f; fi
    done
done

# one source file: its section, file-local names renamed where needed, its macros undefined after it
emit_source() {
    local f=$1 m pat d
    m=$(basename "$f" .c)
    echo
    echo "/* ==== $f ==== */"
    echo "#line 1 \"$f\""
    if [ -n "${renames[$f]:-}" ]; then
        pat=$(echo ${renames[$f]} | tr ' ' '|')
        strip_all "$f" | perl -pe "s/(?<![.\\w])(?<!->)($pat)(?!\\w)/\${1}_$m/g"
        echo "amalgamate: $f: file-local names another source also defines, renamed:$(for n in ${renames[$f]}; do printf ' %s -> %s_%s' "$n" "$n" "$m"; done)" >&2
    else
        strip_all "$f"
    fi
    for d in $(sed -n 's/^[[:space:]]*#[[:space:]]*define[[:space:]]\+\([A-Za-z_][A-Za-z_0-9]*\).*/\1/p' "$f" | sort -u); do
        echo "#undef $d"
    done
}

{
    echo "/*"
    echo " * qibl.c - amalgamated source of the qibl core $version (git $rev), made by"
    echo " * tools/scripts/amalgamate.sh from core/src; do not edit, edit those files. Compile it as C99"
    echo " * (freestanding is fine: see docs/porting.md for the flags) or as C++98/11/17, with qibl.h beside it."
    echo " */"
    echo "#include \"qibl.h\""
    echo "/* C++ has no restrict: the compiler's own spelling (config.h's QIBL_RESTRICT) */"
    echo "#if defined(__cplusplus) && !defined(restrict)"
    echo "#define restrict QIBL_RESTRICT"
    echo "#define QIBL_AMALGAMATED_RESTRICT_"
    echo "#endif"
    for h in "${internal[@]+"${internal[@]}"}"; do
        echo
        echo "/* ==== core/src/$h (internal) ==== */"
        echo "#line 1 \"core/src/$h\""
        strip_all "core/src/$h"
    done
    for f in "${srcs[@]}"; do emit_source "$f"; done
    echo
    echo "#ifdef QIBL_AMALGAMATED_RESTRICT_"
    echo "#undef restrict"
    echo "#undef QIBL_AMALGAMATED_RESTRICT_"
    echo "#endif"
} > "$out/qibl.c.tmp"

{
    echo "/*"
    echo " * qibl_soft.c - amalgamated source of qibl's platform/soft backend $version (git $rev), made by"
    echo " * tools/scripts/amalgamate.sh from platform/soft; do not edit. Compile it as C99 or C++ with"
    echo " * qibl.h and qibl_soft.h beside it; link it with qibl.c."
    echo " */"
    echo "#include \"qibl_soft.h\""
    for f in "${ssrcs[@]}"; do emit_source "$f"; done
} > "$out/qibl_soft.c.tmp"

mv "$out/qibl.h.tmp" "$out/qibl.h"
mv "$out/qibl.c.tmp" "$out/qibl.c"
mv "$out/qibl_soft.h.tmp" "$out/qibl_soft.h"
mv "$out/qibl_soft.c.tmp" "$out/qibl_soft.c"
echo "amalgamate: $out/qibl.h ($(wc -l < "$out/qibl.h") lines, ${#headers[@]} headers), $out/qibl.c ($(wc -l < "$out/qibl.c") lines, ${#internal[@]} internal headers, ${#srcs[@]} sources)"
echo "amalgamate: $out/qibl_soft.h ($(wc -l < "$out/qibl_soft.h") lines, ${#sorder[@]} headers), $out/qibl_soft.c ($(wc -l < "$out/qibl_soft.c") lines, ${#ssrcs[@]} sources)"
