#!/usr/bin/env bash
# FlipOut shortening, µs per flip, of several commits in one run: for each COMMIT its intrinsic/
# tree (git archive) is compiled with the project's Release flags into one small driver (the
# logic of `ifem_bench geodesic --mesh M --ssad 0`: the Dijkstra path from vertex 0 to the vertex
# farthest from it in space, then shorten(), thread CPU seconds), and the drivers take turns,
# ROUNDS fresh processes each per mesh. Prints per mesh the flips (and DIFFERENT if the commits'
# flips or final lengths, %.17g, differ), each commit's median µs/flip and each one's ratio to
# the first. For the issue-time comparisons of docs/decisions.md D-385 (BENCHMARKS.md I30p).
#
#   scripts/bench_flipout_history.sh ROUNDS COMMIT... -- MESH...
#   e.g. scripts/bench_flipout_history.sh 9 2df7c6c main HEAD -- icosphere:71 ../shared/data/meshes/igea_268k.ply
#
# Needs g++ and Eigen (/usr/include/eigen3); compiles ~25–45 files per commit (about a minute each
# on two cores), in a temporary directory removed at the end.
set -eu
rounds=$1
shift
commits=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do commits+=("$1"); shift; done
[ $# -gt 0 ] && shift
[ ${#commits[@]} -gt 0 ] && [ $# -gt 0 ] || { sed -n 2,14p "$0" >&2; exit 2; }
repo=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/drive.cpp" <<'EOF'
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/io/mesh_io.h"
using namespace ifem::intrinsic;
using ifem::Index;
int main(int, char** argv) {
  const std::string spec = argv[1], ico = "icosphere:";
  TriangleMesh m;
  if (spec.rfind(ico, 0) == 0) {
    m = icosphere(std::stoi(spec.substr(ico.size())));
  } else {
    const ifem::io::SurfaceInput in = ifem::io::read_mesh(spec);
    m.faces = in.triangles;
    m.positions = in.positions;
  }
  Index far = 1;
  for (Index v = 1; v < m.positions.rows(); ++v) {
    const auto d = [&](Index u) { return (m.positions.row(u) - m.positions.row(0)).norm(); };
    if (d(v) > d(far)) far = v;
  }
  SignpostTriangulation st(m.faces, m.positions);
  EdgePath path = shortest_edge_path(st, 0, far);
  timespec a{}, b{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
  const FlipOutReport rep = shorten(st, path);
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
  const double s = double(b.tv_sec - a.tv_sec) + 1e-9 * double(b.tv_nsec - a.tv_nsec);
  std::printf("%d %.17g %.6f\n", int(rep.flips), rep.final_length,
              1e6 * s / std::max(1, int(rep.flips)));
}
EOF
flags="-O3 -DNDEBUG -fPIC -fopenmp -std=gnu++17 -DEIGEN_DONT_PARALLELIZE -isystem /usr/include/eigen3"
for k in "${!commits[@]}"; do
  d="$tmp/c$k"
  mkdir -p "$d/src" "$d/obj"
  git -C "$repo" archive "${commits[$k]}" intrinsic | tar -x -C "$d/src"
  find "$d/src/intrinsic" -name '*.cpp' | xargs -P 2 -I{} sh -c \
    "g++ $flags -I$d/src -c {} -o $d/obj/\$(echo {} | md5sum | cut -c1-12).o"
  ar rcs "$d/lib.a" "$d"/obj/*.o
  g++ $flags -I"$d/src" "$tmp/drive.cpp" "$d/lib.a" -o "$d/drive"
done
echo "load before: $(cat /proc/loadavg)"
printf '| mesh | flips |'
for c in "${commits[@]}"; do printf ' µs/flip %s |' "$c"; done
for c in "${commits[@]:1}"; do printf ' %s / %s |' "$c" "${commits[0]}"; done
printf '\n|---|---:|'
for _ in "${commits[@]}" "${commits[@]:1}"; do printf -- '---:|'; done
echo
for mesh in "$@"; do
  for k in "${!commits[@]}"; do : >"$tmp/out$k"; done
  for _ in $(seq "$rounds"); do
    for k in "${!commits[@]}"; do "$tmp/c$k/drive" "$mesh" >>"$tmp/out$k"; done
  done
  same=$(cut -d' ' -f1,2 "$tmp"/out* | sort -u | wc -l)
  line="| $(basename "$mesh") | $(cut -d' ' -f1 "$tmp/out0" | head -1)$([ "$same" = 1 ] || echo ' DIFFERENT') |"
  meds=()
  for k in "${!commits[@]}"; do
    meds+=("$(cut -d' ' -f3 "$tmp/out$k" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')")
    line="$line ${meds[$k]} |"
  done
  for k in "${!commits[@]}"; do
    [ "$k" = 0 ] || line="$line $(awk -v a="${meds[0]}" -v b="${meds[$k]}" 'BEGIN {printf "%.3f", b / a}') |"
  done
  echo "$line"
done
echo "load after: $(cat /proc/loadavg)"
