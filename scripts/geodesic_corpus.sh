#!/usr/bin/env bash
# Runs every mode of `ifem geodesic` on every mesh of ../shared/data/meshes (or the folder given)
# and prints one line per mesh: single-source, path, loop, Bézier and network, each "ok" (with
# the figure it printed) or the first line of its error. Points are chosen from the single-source
# lengths so that they lie in the source's component: the source (the first vertex with a finite
# length to itself), the farthest reachable vertex and one about halfway.
#   scripts/geodesic_corpus.sh [MESH_DIR] [IFEM]       (IFEM: default build/examples/ifem)
set -u
dir=${1:-../shared/data/meshes}
ifem=${2:-build/examples/ifem}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() {  # run LABEL CMD...: prints "LABEL ok (s)" or "LABEL FAILED: first error line"
  local label=$1; shift
  local t0=$(date +%s.%N)
  if timeout 300 "$@" --quiet >"$tmp/out" 2>"$tmp/err"; then
    printf ' %s ok %.2fs' "$label" "$(echo "$(date +%s.%N) - $t0" | bc)"
  else
    printf ' %s FAILED(%s)' "$label" "$(head -c 160 "$tmp/err" | head -1)"
  fi
}
for mesh in "$dir"/*; do
  case "$mesh" in *.obj|*.off|*.ply|*.stl) ;; *) continue ;; esac
  name=$(basename "$mesh")
  # source: the first of a few vertices from which some other vertex is reachable
  far= mid= status=
  for src in 0 1 2 3 10 100 1000; do
    t0=$(date +%s.%N)
    if ! timeout 300 "$ifem" geodesic "$mesh" --all-from "$src" -o "$tmp/all.txt" --quiet >"$tmp/out" 2>"$tmp/err"; then
      status="refused: $(head -1 "$tmp/err" | head -c 200)"
      break
    fi
    status=$(printf 'all-from ok %.2fs' "$(echo "$(date +%s.%N) - $t0" | bc)")
    read -r far mid < <(awk 'BEGIN { m = -1 } $1 != "inf" && $1 + 0 > 0 { v[NR - 1] = $1; if ($1 + 0 > m) { m = $1; far = NR - 1 } }
      END { if (m < 0) exit; best = -1; for (k in v) { d = v[k] - m / 2; if (d < 0) d = -d; if (best < 0 || d < best) { best = d; mid = k } } print far, mid }' "$tmp/all.txt")
    [ -n "${far:-}" ] && break
  done
  printf '%s (src %s): %s' "$name" "$src" "$status"
  case "$status" in refused*) echo; continue ;; esac
  if [ -z "${far:-}" ] || [ -z "${mid:-}" ]; then printf ' (no second vertex reachable)\n'; continue; fi
  run path "$ifem" geodesic "$mesh" --path "$src,$far" -o "$tmp/p.obj"
  run loop "$ifem" geodesic "$mesh" --path "$src,$mid,$far" --loop --pin -o "$tmp/l.obj"
  run bezier "$ifem" geodesic "$mesh" --path "$src,$mid,$far" --bezier 3 -o "$tmp/b.obj"
  printf 'path %s %s\npath %s %s\n' "$src" "$far" "$src" "$mid" >"$tmp/net.txt"
  run network "$ifem" geodesic "$mesh" --network "$tmp/net.txt" -o "$tmp/n.obj"
  echo
done
