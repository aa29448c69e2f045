#!/usr/bin/env bash
# Performance gate: two builds of ifem side by side in one run, fresh processes taking turns
# (old, new, old, new, ...), so both see the same load. Prints one row per operation × mesh:
# the median of each build and the ratio new/old (< 1: new is faster).
#
#   scripts/bench_gate.sh OLD_BUILD NEW_BUILD [REPS]        (REPS: default 5)
#
# Operations (ifem_bench): the heat precompute in a fresh process (`small --what precompute`,
# its first call), one query and a block of 32 sources (`query --sources 1|32`, median of 5
# calls after the precompute). Meshes: MESHES (default: rocketship, igea, icosphere(224) =
# 1,003,520 faces). Gate of issue 28: ratio ≤ 1.10 (rocketship precompute ≤ 1.3).
set -u
old=$1/examples/ifem_bench
new=$2/examples/ifem_bench
reps=${3:-5}
data=${IFEM_SHARED_DATA:-$(dirname "$0")/../../shared/data}
meshes=${MESHES:-"$data/meshes/rocketship.ply $data/meshes/igea_268k.ply icosphere:224"}
for b in "$old" "$new"; do [ -x "$b" ] || { echo "bench_gate: no $b" >&2; exit 2; }; done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {if (NR) print a[int((NR + 1) / 2)]; else print "nan"}'; }
precompute() {  # BIN MESH -> seconds of the first precompute in a fresh process
  "$1" small --mesh "$2" --what precompute --repeat 1 2>/dev/null | awk '/ first /{for(i=1;i<=NF;i++) if($i=="first") print $(i+1)}'
}
query() {  # BIN MESH K -> seconds per call (K sources at once), median of 5 calls
  local args=(--mesh "$2")
  case $2 in icosphere:*) args=(--n "${2#icosphere:}") ;; esac
  "$1" query "${args[@]}" --sources "$3" --repeat 5 2>/dev/null |
    awk -v k="$3" '/source\(s\)/{for(i=1;i<=NF;i++) if($i=="source(s)") {v=$(i+1); print v}}'
}
echo "load before: $(cat /proc/loadavg)"
echo "| operation | mesh | old s (median of $reps) | new s | new/old |"
echo "|---|---|---:|---:|---:|"
for mesh in $meshes; do
  name=$(basename "$mesh")
  for op in precompute q1 q32; do
    : >"$tmp/old"; : >"$tmp/new"
    for _ in $(seq "$reps"); do
      for side in old new; do
        bin=$old; [ $side = new ] && bin=$new
        case $op in
          precompute) precompute "$bin" "$mesh" >>"$tmp/$side" ;;
          q1) query "$bin" "$mesh" 1 >>"$tmp/$side" ;;
          q32) query "$bin" "$mesh" 32 >>"$tmp/$side" ;;
        esac
      done
    done
    mo=$(median <"$tmp/old"); mn=$(median <"$tmp/new")
    ratio=$(awk -v a="$mo" -v b="$mn" 'BEGIN {if (a > 0) printf "%.3f", b / a; else print "nan"}')
    label=$op; [ $op = q1 ] && label="one query"; [ $op = q32 ] && label="32 sources at once"
    [ $op = precompute ] && label="heat precompute (fresh process)"
    echo "| $label | $name | $mo | $mn | $ratio |"
  done
done
echo "load after: $(cat /proc/loadavg)"
