#!/usr/bin/env bash
# Runs `ifem poisson --curves` (plain and --refine) and `ifem distance --curves` on every mesh of
# ../shared/data/meshes (or the folder given) and prints one line per mesh: each run "ok" (with
# its time; for Poisson also the range of u, which the maximum principle keeps in [0, 1]) or the
# first line of its error. The curves are chosen from a heat distance from a source so that they
# lie in its component: a geodesic held at 0, a Bézier curve from 0 to 1 and a slit with 0.25 on
# its left and 0.75 on its right, through vertices at distance quantiles.
#   scripts/curves_corpus.sh [MESH_DIR] [IFEM]       (IFEM: default build/examples/ifem)
set -u
dir=${1:-../shared/data/meshes}
ifem=${2:-build/examples/ifem}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() {  # run LABEL OUT CMD...: prints "LABEL ok (s) [range]" or "LABEL FAILED(first error line)"
  local label=$1 out=$2; shift 2
  local t0=$(date +%s.%N)
  if timeout 600 "$@" --quiet >"$tmp/out" 2>"$tmp/err"; then
    printf ' %s ok %.2fs' "$label" "$(echo "$(date +%s.%N) - $t0" | bc)"
    case "$label" in poisson*)
      awk 'NR == 1 { lo = $1; hi = $1 } { if ($1 < lo) lo = $1; if ($1 > hi) hi = $1 }
           END { printf " [%.3g, %.3g]", lo, hi }' "$out" ;;
    esac
  else
    printf ' %s FAILED(%s)' "$label" "$(head -c 200 "$tmp/err" | head -1)"
  fi
}
for mesh in "$dir"/*; do
  case "$mesh" in *.obj|*.off|*.ply|*.stl) ;; *) continue ;; esac
  name=$(basename "$mesh")
  status= q=
  for src in 0 1 2 3 10 100 1000; do
    if ! timeout 300 "$ifem" distance "$mesh" --source "$src" -o "$tmp/d.txt" --quiet >"$tmp/out" 2>"$tmp/err"; then
      status="distance from $src refused: $(head -1 "$tmp/err" | head -c 200)"
      continue
    fi
    # vertices at distance quantiles 10 20 35 50 60 70 80 95 % of the reachable ones
    q=$(awk '$1 != "inf" && $1 + 0 > 0 { print $1, NR - 1 }' "$tmp/d.txt" | sort -g |
        awk '{ v[NR] = $2 } END { if (NR < 20) exit; n = split("10 20 35 50 60 70 80 95", p, " ");
             for (i = 1; i <= n; ++i) printf "%s ", v[int(NR * p[i] / 100)] }')
    [ -n "$q" ] && status=ok && break
  done
  printf '%s (src %s):' "$name" "$src"
  if [ "$status" != ok ]; then echo " ${status:-too few reachable vertices}"; continue; fi
  read -r a b c d e f g h <<<"$q"
  printf '0 %s %s\nbezier=3 0 1 : %s %s %s %s\nslit 0.25 0.75 %s %s\n' "$a" "$d" "$e" "$f" "$g" "$h" "$b" "$c" >"$tmp/curves.txt"
  run poisson "$tmp/u.txt" "$ifem" poisson "$mesh" --curves "$tmp/curves.txt" -o "$tmp/u.txt"
  run poisson-refined "$tmp/ur.txt" "$ifem" poisson "$mesh" --curves "$tmp/curves.txt" --refine -o "$tmp/ur.txt"
  run distance "$tmp/dc.txt" "$ifem" distance "$mesh" --curves "$tmp/curves.txt" -o "$tmp/dc.txt"
  echo
done
