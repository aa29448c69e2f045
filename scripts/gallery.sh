#!/usr/bin/env bash
# Remakes the gallery: runs ifem commands on bundled meshes (and on ../shared/data/meshes when
# present), draws each result headless with `ifem render` into docs/gallery/*.png (640×480) and
# writes docs/gallery.md with every picture and the exact commands that made it.
#   scripts/gallery.sh [IFEM]     IFEM: the ifem executable (default build/examples/ifem)
#   IFEM_GALLERY_MESHES=DIR       where thingi10k_90225.obj and block.off are (default
#                                 ../shared/data/meshes; absent: a generated sliver band)
# Runs in a temporary directory; 3-6 s wall on 2 shared cores. Same bytes every run.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
ifem=$(realpath "${1:-$repo/build/examples/ifem}")
shared="${IFEM_GALLERY_MESHES:-$repo/../shared/data/meshes}"  # the CAD part and sliver mesh
out="$repo/docs/gallery"
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
ln -s "$repo/tests/data/spot.obj" spot.obj
ln -s "$repo/tests/data/bunny_npm_lowres.obj" bunny.obj

md="$work/gallery.md"
log=""
# run CMD...: runs `ifem CMD...` (or a shell line for non-ifem steps) and records it
run() {
  log+="ifem $*"$'\n'
  "$ifem" "$@" --quiet >/dev/null
}
note() { log+="$1"$'\n'; }
# picture NAME TITLE TEXT: copies NAME.png into docs/gallery and writes its section
picture() {
  cp "$1.png" "$out/$1.png"
  {
    printf '## %s\n\n%s\n\n![%s](gallery/%s.png)\n\n```sh\n%s```\n\n' "$2" "$3" "$2" "$1" "$log"
  } >>"$md"
  log=""
}
size=(--size 640x480)

cat >"$md" <<'EOF'
# Gallery

Every picture here is made headless by `scripts/gallery.sh` (which writes this page too, in
about 10 s): the commands under a picture make it, run in a directory holding spot.obj and
bunny.obj (`tests/data/bunny_npm_lowres.obj`) and, from `../shared/data/meshes`, part.obj
(`thingi10k_90225.obj`) and sliver.off (`block.off`); without `../shared` the script makes a
band of sliver triangles for those two. `ifem render` is the software rasterizer of
docs/decisions.md D-156; `ifem view` with the same inputs (`--field`, `--curves`,
`--triangulation`, `--symmetry`) opens the same scene in a browser.

EOF

# a CAD part with slivers (shared), or a generated sliver mesh without ../shared
if [ -f "$shared/thingi10k_90225.obj" ] && [ -f "$shared/block.off" ]; then
  ln -s "$shared/thingi10k_90225.obj" part.obj
  ln -s "$shared/block.off" sliver.off
  cad_note="(part.obj: 88 vertices, corner angles down to 3e-15°; sliver.off: down to 0.06°.)"
else
  /usr/bin/env python3 - <<'EOF'
import math
# a ring-shaped band, 3 rings of 80 long thin triangles (slivers) each, and a cap fan
n, rings = 80, 4
with open("part.obj", "w") as f, open("sliver.off", "w") as g:
    V = [(math.cos(2 * math.pi * j / n) * (1 + 0.3 * i), 0.4 * i * i / rings,
          math.sin(2 * math.pi * j / n) * (1 + 0.3 * i)) for i in range(rings) for j in range(n)]
    F = []
    for i in range(rings - 1):
        for j in range(n):
            a, b = i * n + j, i * n + (j + 1) % n
            F += [(a, b, b + n), (a, b + n, a + n)]
    for v in V: f.write("v %.17g %.17g %.17g\n" % v)
    for t in F: f.write("f %d %d %d\n" % tuple(k + 1 for k in t))
    g.write("OFF\n%d %d 0\n" % (len(V), len(F)))
    for v in V: g.write("%.17g %.17g %.17g\n" % v)
    for t in F: g.write("3 %d %d %d\n" % t)
EOF
  cad_note="../shared was absent: part.obj and sliver.off are a generated band of sliver triangles."
fi
# 1-2. the intrinsic triangulation over the input: flips only, then flips + refinement
run refine part.obj --max-insertions 0 --save flips.ifem
run render part.obj --triangulation flips.ifem --wireframe "${size[@]}" --azimuth 35 \
  --elevation 25 -o idt_flips.png
picture idt_flips "Intrinsic Delaunay triangulation over a CAD part (flips only)" \
  "The input's edges thin and dark, the intrinsic Delaunay triangulation's edges in blue, each traced over the input surface through its signposts: the same vertices, the flipped edges bend across input triangles. $cad_note"
run refine part.obj --min-angle 25 --save refined.ifem
run render part.obj --triangulation refined.ifem --wireframe "${size[@]}" --azimuth 35 \
  --elevation 25 -o idt_refined.png
picture idt_refined "Intrinsic Delaunay refinement of the same part (flips + inserted vertices)" \
  "Refined until every intrinsic angle is at least 25° (Chew's second algorithm): the inserted vertices sit on the input's triangles, the surface is unchanged."

# 3-4. heat distance before / after intrinsic refinement on a sliver mesh
run distance sliver.off --source 0 -o dist_input.ply
run render dist_input.ply --isolines 16 "${size[@]}" --azimuth 35 --elevation 25 --legend \
  -o dist_input.png
picture dist_input "Heat distance on a sliver mesh, input triangulation" \
  "The heat method's distance from vertex 0 on the intrinsic Delaunay triangulation of the input's vertices alone: slivers make the isolines ragged."
run distance sliver.off --source 0 --refine -o dist_refined.ply
run render dist_refined.ply --isolines 16 "${size[@]}" --azimuth 35 --elevation 25 --legend \
  -o dist_refined.png
picture dist_refined "Heat distance on the same mesh after intrinsic refinement" \
  "The same source with --refine: solved on the refined intrinsic triangulation (angles ≥ 25°) and read back on the input's vertices, drawn linearly over the input's triangles (so its slivers still show in the isolines' corners)."

# 5. a PDE with Dirichlet data on curves and a slit
curves='closed 0 1235 402 673 2363 2161 1033\nslit 0 1 1013 974 1009\n'
printf "$curves" >curves.txt
note "printf '$curves' > curves.txt"
run poisson spot.obj --curves curves.txt --curves-out curves.obj -o u.ply
run render u.ply --curves curves.obj --isolines 12 --legend "${size[@]}" --view right \
  --azimuth 60 -o poisson_curves.png
picture poisson_curves "Laplace's equation with data on curves and a slit" \
  "u = 0 on a closed geodesic loop; a slit (a cut) with 0 on its left and 1 on its right: u jumps across it. Curves in red, as inserted into the triangulation."

# 6. a smooth direction field with its singularities
run field bunny.obj --symmetry 4 -o cross.ply
run render cross.ply --property singularity --colormap diverging --symmetry 4 "${size[@]}" \
  --azimuth 20 --fill 1.3 -o field_cross.png
picture field_cross "The smoothest cross field and its singularities" \
  "A 4-direction field (dark crosses at every vertex); the surface coloured by the singularity index (red +1/4, blue −1/4): the indices sum to the Euler characteristic, 2."

# 7. a point-cloud eigenfunction
awk '/^v /{print $2, $3, $4}' spot.obj >spot.xyz
note "awk '/^v /{print \$2, \$3, \$4}' spot.obj > spot.xyz"
run eigen spot.xyz -k 8 -o modes.ply
run render modes.ply --property phi3 --colormap diverging "${size[@]}" \
  --view right --azimuth 60 --legend -o eigen_points.png
picture eigen_points "A Laplace eigenfunction of a point cloud" \
  "spot's vertices alone, as an .xyz point cloud: the fourth eigenfunction of the point-cloud Laplacian (intrinsic Delaunay on the tufted cover of local triangulations), blue negative, red positive."

cp "$md" "$repo/docs/gallery.md"
du -ch "$out"/*.png | tail -1
