#!/bin/sh
# pkg-files.sh OUTDIR PREFIX LIBDIR INCLUDEDIR VERSION SIZEOF_VOID_P [DEFINITION...] - writes the
# package files `make install` installs, from the same templates and with the same values as the
# CMake install (CMakeLists.txt): OUTDIR/qibl.pc, OUTDIR/qiblConfig.cmake,
# OUTDIR/qiblConfigVersion.cmake. Paths inside them are relative to the files' own places
# (LIBDIR/pkgconfig and LIBDIR/cmake/qibl), so the install can be moved.
set -eu
[ $# -ge 6 ] || { echo "usage: pkg-files.sh OUTDIR PREFIX LIBDIR INCLUDEDIR VERSION SIZEOF_VOID_P [DEF...]" >&2; exit 2; }
out=$1 prefix=$2 libdir=$3 incdir=$4 version=$5 ptr=$6
shift 6
here=$(cd "$(dirname "$0")/../pkgconfig" && pwd)
rel() { realpath -m --relative-to="$1" "$2"; }
pc_up=$(rel "$libdir/pkgconfig" "$prefix")
cm_up=$(rel "$libdir/cmake/qibl" "$prefix")
lib_rel=$(rel "$prefix" "$libdir")
inc_rel=$(rel "$prefix" "$incdir")
defs="" defs_cmake=""
for d in "$@"; do
    defs="$defs -D$d"
    defs_cmake="${defs_cmake:+$defs_cmake;}$d"
done
major=${version%%.*} rest=${version#*.}
minor=${rest%%.*}
mkdir -p "$out"
subst() {
    sed -e "s|@PC_UP@|$pc_up|g; s|@CMAKE_UP@|$cm_up|g; s|@LIBDIR_REL@|$lib_rel|g; s|@INCLUDEDIR_REL@|$inc_rel|g" \
        -e "s|@VERSION@|$version|g; s|@VERSION_MAJOR@|$major|g; s|@VERSION_MINOR@|$minor|g" \
        -e "s|@SIZEOF_VOID_P@|$ptr|g; s|@DEFS@|$defs|g; s|@DEFS_CMAKE@|$defs_cmake|g" "$here/$1" > "$out/$2"
}
subst qibl.pc.in qibl.pc
subst qiblConfig.cmake.in qiblConfig.cmake
subst qiblConfigVersion.cmake.in qiblConfigVersion.cmake
