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
# at the end of its section. `make check-amalgamate` compiles the result with the core's strict
# flags, cross-compiles it for Cortex-M0, and runs the golden cases and the example on it.
set -eu
cd "$(dirname "$0")/../.." || exit 1
out="${1:-${BUILD:-build}/amalgamated}"
mkdir -p "$out"
version=$(sed -n 's/^#define QIBL_VERSION_STRING "\(.*\)"/\1/p' core/include/qibl/version.h)
rev=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)

# ---- header order: depth-first over the quoted qibl includes, dependencies first -------------
order=()
visit() { # header path relative to core/include
    local h=$1 dep seen
    for seen in "${order[@]+"${order[@]}"}"; do [ "$seen" = "$h" ] && return 0; done
    [ -f "core/include/$h" ] || { echo "amalgamate: $h is included but not in core/include" >&2; exit 1; }
    for dep in $(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\(qibl[^"]*\.h\)".*/\1/p' "core/include/$h"); do
        visit "$dep"
    done
    order+=("$h")
}
for h in $(sed -n 's/^#include "\(qibl\/[^"]*\.h\)".*/\1/p' core/include/qibl.h); do visit "$h"; done
# any header qibl.h does not reach is still part of the core's API
for f in core/include/qibl/*.h; do visit "${f#core/include/}"; done

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
    for h in "${order[@]}"; do
        echo
        echo "/* ==== $h ==== */"
        strip_includes "core/include/$h"
    done
    echo
    echo "#endif /* QIBL_AMALGAMATED_H */"
} > "$out/qibl.h.tmp"

# ---- internal headers of core/src, dependencies first --------------------------------------------
internal=()
ivisit() { # file name in core/src
    local h=$1 dep seen
    for seen in "${internal[@]+"${internal[@]}"}"; do [ "$seen" = "$h" ] && return 0; done
    for dep in $(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([a-z0-9_]*\.h\)".*/\1/p' "core/src/$h"); do
        [ -f "core/src/$dep" ] && ivisit "$dep"
    done
    internal+=("$h")
}
for f in core/src/*.h; do [ -f "$f" ] && ivisit "$(basename "$f")"; done
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

{
    echo "/*"
    echo " * qibl.c - amalgamated source of the qibl core $version (git $rev), made by"
    echo " * tools/scripts/amalgamate.sh from core/src; do not edit, edit those files. Compile it as C99"
    echo " * (freestanding is fine: see docs/porting.md for the flags) with qibl.h beside it."
    echo " */"
    echo "#include \"qibl.h\""
    for h in "${internal[@]+"${internal[@]}"}"; do
        echo
        echo "/* ==== core/src/$h (internal) ==== */"
        echo "#line 1 \"core/src/$h\""
        strip_all "core/src/$h"
    done
    for f in "${srcs[@]}"; do
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
        # the file's own macros end with it
        for d in $(sed -n 's/^[[:space:]]*#[[:space:]]*define[[:space:]]\+\([A-Za-z_][A-Za-z_0-9]*\).*/\1/p' "$f" | sort -u); do
            echo "#undef $d"
        done
    done
} > "$out/qibl.c.tmp"

mv "$out/qibl.h.tmp" "$out/qibl.h"
mv "$out/qibl.c.tmp" "$out/qibl.c"
echo "amalgamate: $out/qibl.h ($(wc -l < "$out/qibl.h") lines, ${#order[@]} headers), $out/qibl.c ($(wc -l < "$out/qibl.c") lines, ${#internal[@]} internal headers, ${#srcs[@]} sources)"
