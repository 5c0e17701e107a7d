#!/bin/sh
# need-cmocka.sh - make sure CMocka is visible to pkg-config; install it with apt-get when we may.
# Exit 0 when usable, 1 with one line naming the package otherwise.
if pkg-config --exists cmocka 2>/dev/null; then exit 0; fi
if command -v apt-get >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ]; then sudo=""; elif sudo -n true 2>/dev/null; then sudo="sudo -n"; else sudo=no; fi
    if [ "$sudo" != no ]; then
        echo "qibl: CMocka not found; installing libcmocka-dev with apt-get" >&2
        $sudo apt-get update -qq >&2 &&
            DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq libcmocka-dev pkg-config >&2
        if pkg-config --exists cmocka 2>/dev/null; then exit 0; fi
    fi
fi
echo "qibl: CMocka is missing: install libcmocka-dev (Debian/Ubuntu: apt-get install libcmocka-dev), libcmocka-devel (Fedora: dnf install libcmocka-devel) or cmocka (Homebrew: brew install cmocka)" >&2
exit 1
