# tools/farm/args.sh - sourced by submit.sh and submit_tiles.sh: their first three arguments,
# N ASSET WORKDIR, checked the same way. farm_args SCRIPT WHAT MAX "$@" sets n, asset (absolute),
# work (made, absolute) and qibl (QIBL, else qibl on PATH); a bad argument or no binary exits 2 with
# one line naming SCRIPT. WHAT names the pieces (shards, tiles); MAX is their largest count, or a
# phrase such as "the rows" when the bake itself checks it. The caller then shifts 3.
farm_args() {
    local me=$1 what=$2 max=$3
    shift 3
    if [ $# -lt 3 ]; then
        echo "usage: $me N ASSET WORKDIR [qibl bake options...]" >&2
        exit 2
    fi
    n=$1 asset=$2 work=$3
    case $n in '' | *[!0-9]*) echo "$(basename "$me"): N must be a number of $what (1..$max): '$n'" >&2; exit 2 ;; esac
    case $max in
    *[!0-9]*) [ "$n" -ge 1 ] || { echo "$(basename "$me"): N must be at least 1: $n" >&2; exit 2; } ;;
    *) [ "$n" -ge 1 ] && [ "$n" -le "$max" ] || { echo "$(basename "$me"): N must be in 1..$max: $n" >&2; exit 2; } ;;
    esac
    qibl=${QIBL:-$(command -v qibl || true)}
    [ -x "$qibl" ] || { echo "$(basename "$me"): no qibl binary (set QIBL=/path/to/qibl)" >&2; exit 2; }
    mkdir -p "$work"
    work=$(cd "$work" && pwd)
    case $asset in /*) ;; *) asset=$(pwd)/$asset ;; esac
}
