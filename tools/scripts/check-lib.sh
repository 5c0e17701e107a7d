# check-lib.sh - sourced by the checking scripts (cross.sh, headers.sh, ports.sh, check-install.sh,
# check-amalgamate.sh) after their `cd` to the top of the tree: each starts in a fresh output folder
# and collects its failures before it exits, under its own name.
# shellcheck shell=bash disable=SC2034

# check_start TAG DIR: DIR emptied and made (out=DIR), fail=0; err then reports "TAG: FAIL: ..."
check_start() {
    check_tag=$1 out=$2
    rm -rf "$out"; mkdir -p "$out"
    fail=0
}
err() { echo "$check_tag: FAIL: $*" >&2; fail=1; }
