#!/usr/bin/env bash
# Fails if a library includes from a library above it. Allowed: fem → intrinsic,
# solvers → fem → intrinsic, pointcloud → intrinsic, solvers → pointcloud (the pipeline chooses
# the point-cloud path).
cd "$(dirname "$0")/.."
bad=0
check() {  # folder, forbidden include prefixes...
  local dir=$1; shift
  for p in "$@"; do
    if grep -rn "#include \"$p/" "$dir" --include='*.h' --include='*.cpp'; then bad=1; fi
  done
}
check intrinsic fem solvers pointcloud examples
check fem solvers pointcloud examples
check solvers examples
check pointcloud fem solvers examples
if [ $bad = 1 ]; then echo "layering violated (see above)"; exit 1; fi
echo "layering ok"
