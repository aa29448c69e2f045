#!/usr/bin/env bash
# Small meshes with the default threads against OMP_NUM_THREADS=1 (BENCHMARKS.md, "Small meshes
# (issue 15, item 3)"), one fresh process per sample, the two settings alternating so that both
# see the same load: L + M and the heat precompute (`ifem_bench small`: the first call, the
# median of the later ones and their CPU time, all threads), and the whole
# `ifem distance MESH --source 0` process (wall clock). Prints medians over REPS processes, and
# the load average before and after (wall times on a shared machine are noisy: compare the two
# settings of one run, and repeat).
#   scripts/bench_small.sh [REPS] [BUILD]         (REPS: default 7; BUILD: default build)
set -u
reps=${1:-7}
build=${2:-build}
bench=$build/examples/ifem_bench
ifem=$build/examples/ifem
meshes=${MESHES:-"tests/data/spot.obj icosphere:23 ../shared/data/meshes/rocketship.ply"}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
with_threads() {  # with_threads default|1 CMD...
  local threads=$1; shift
  if [ "$threads" = 1 ]; then OMP_NUM_THREADS=1 "$@"; else "$@"; fi
}
cli_seconds() {  # cli_seconds THREADS MESH: wall seconds of one whole `ifem distance` process
  local t0=$(date +%s%N)
  with_threads "$1" "$ifem" distance "$2" --source 0 -o "$tmp/d.txt" --quiet >/dev/null
  awk -v a="$t0" -v b="$(date +%s%N)" 'BEGIN {printf "%.4f\n", (b - a) / 1e9}'
}
echo "load before: $(cat /proc/loadavg)"
echo "| mesh | what | default: first / median / CPU s | 1 thread: first / median / CPU s |"
echo "|---|---|---|---|"
for mesh in $meshes; do
  for what in lm precompute; do
    for _ in $(seq "$reps"); do
      for threads in default 1; do
        with_threads "$threads" "$bench" small --mesh "$mesh" --what "$what" >>"$tmp/$threads"
      done
    done
    row="| $(basename "$mesh") | $what"
    for threads in default 1; do
      row="$row | $(awk '{print $6}' "$tmp/$threads" | median) / $(awk '{print $8}' "$tmp/$threads" |
        median) / $(awk '{print $10}' "$tmp/$threads" | median)"
      rm "$tmp/$threads"
    done
    echo "$row |"
  done
  if [[ $mesh != icosphere:* ]]; then
    for _ in $(seq "$reps"); do
      for threads in default 1; do cli_seconds "$threads" "$mesh" >>"$tmp/cli$threads"; done
    done
    echo "| $(basename "$mesh") | ifem distance process | $(median <"$tmp/clidefault") | $(median <"$tmp/cli1") |"
    rm "$tmp/clidefault" "$tmp/cli1"
  fi
done
echo "load after: $(cat /proc/loadavg)"
