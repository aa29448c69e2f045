#!/usr/bin/env bash
# FlipOut speed, two builds side by side in one run: fresh processes take turns (old, new, old,
# new, ...) so both see the same load. Per mesh: the shortening of one long path (median time,
# flips, µs per flip) and single-source geodesics from vertex 0 (median time), each build's
# median over REPS processes (each process: the median of --repeat 1 run), and new/old.
#
#   scripts/bench_flipout.sh OLD_BUILD NEW_BUILD [REPS]        (REPS: default 3)
#
# Meshes: MESHES (default: icospheres of 10,580 / 100,820 / 269,120 / 1,003,520 faces and igea);
# single-source only up to SSAD_MAX_FACES faces (default 300000: the old build's single source is
# quadratic-ish, 20 s on igea).
set -u
old=$1/examples/ifem_bench
new=$2/examples/ifem_bench
reps=${3:-3}
data=${IFEM_SHARED_DATA:-$(dirname "$0")/../../shared/data}
meshes=${MESHES:-"icosphere:23 icosphere:71 icosphere:116 icosphere:224 $data/meshes/igea_268k.ply"}
ssad_max=${SSAD_MAX_FACES:-300000}
for b in "$old" "$new"; do [ -x "$b" ] || { echo "bench_flipout: no $b" >&2; exit 2; }; done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {if (NR) print a[int((NR + 1) / 2)]; else print "nan"}'; }
field() { awk -v k="$1" '{for (i = 1; i < NF; i++) if ($i == k) print $(i + 1)}'; }
echo "load before: $(cat /proc/loadavg)"
echo "| mesh | faces | flips old/new | shorten old s | new s | µs/flip old | new | new/old | single-source old s | new s | new/old |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for mesh in $meshes; do
  case $mesh in icosphere:*) faces=$((20 * ${mesh#icosphere:} ** 2)) ;; *) faces=268686 ;; esac
  ssad=1
  [ "$faces" -gt "$ssad_max" ] && ssad=0
  for side in old new; do : >"$tmp/$side"; done
  for _ in $(seq "$reps"); do
    for side in old new; do
      bin=$old; [ $side = new ] && bin=$new
      "$bin" geodesic --mesh "$mesh" --repeat 1 --ssad $ssad 2>/dev/null >>"$tmp/$side"
    done
  done
  for side in old new; do
    eval "${side}_s=\$(field shorten_s <\"$tmp/$side\" | median)"
    eval "${side}_f=\$(field flips <\"$tmp/$side\" | head -1)"
    eval "${side}_u=\$(field us_per_flip <\"$tmp/$side\" | median)"
    eval "${side}_ss=\$(field ssad_s <\"$tmp/$side\" | median)"
    eval "${side}_faces=\$(field faces <\"$tmp/$side\" | head -1)"
  done
  r1=$(awk -v a="$old_u" -v b="$new_u" 'BEGIN {printf "%.3f", b / a}')
  r2=$(awk -v a="$old_ss" -v b="$new_ss" 'BEGIN {if (a > 0) printf "%.3f", b / a; else print "-"}')
  echo "| $(basename "$mesh") | $new_faces | $old_f / $new_f | $old_s | $new_s | $old_u | $new_u | $r1 | $old_ss | $new_ss | $r2 |"
done
echo "load after: $(cat /proc/loadavg)"
