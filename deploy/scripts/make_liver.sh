#!/usr/bin/env bash
# Writes deploy/meshes/liver.obj, the default scene's organ (001 Fig 9):
# a liver-like closed surface of 7,500 triangles, outward-facing, in
# metres (22 cm long). A cube of 25 x 25 squares per face is pushed onto
# the unit sphere, stretched into an ellipsoid, tapered from a thick right
# lobe (-x) to a thin left lobe (+x), notched on its front edge between
# the lobes, and cut flat underneath so that it rests on its underside.
# Every step keeps each vertical line through the body crossing its
# surface twice, so the result stays closed and free of folds.
# Usage: deploy/scripts/make_liver.sh [OUT.obj]   (default: deploy/meshes/liver.obj)
#        deploy/scripts/make_liver.sh --check     (the tree's file is what this writes)
set -euo pipefail
tree=$(cd "$(dirname "$0")/.." && pwd)/meshes/liver.obj
if [[ ${1:-} == --check ]]; then
  fresh=$(mktemp)
  trap 'rm -f "$fresh"' EXIT
  "$0" "$fresh" >/dev/null
  cmp -s "$fresh" "$tree" || { echo "make_liver: $tree differs from what this script writes; run it" >&2; exit 1; }
  echo "make_liver: $tree is what this script writes"
  exit 0
fi
out=${1:-$tree}
awk -v s=25 'BEGIN {
  print "# Liver-like organ for hcosim (deploy/scripts/make_liver.sh); metres; CCW outward"
  n = 0
  for (a = 0; a < 3; ++a)
    for (side = 0; side < 2; ++side) {
      b = (a + 1) % 3; c = (a + 2) % 3
      if (side == 0) { t = b; b = c; c = t }
      for (v = 0; v < s; ++v)
        for (u = 0; u < s; ++u) {
          for (q = 0; q < 4; ++q) {
            p[a] = side ? s : 0
            p[b] = u + (q == 1 || q == 2)
            p[c] = v + (q >= 2)
            key = p[0] "," p[1] "," p[2]
            if (!(key in id)) { id[key] = ++n; vertex(p[0], p[1], p[2]) }
            w[q] = id[key]
          }
          faces[++f] = w[0] " " w[1] " " w[2]
          faces[++f] = w[0] " " w[2] " " w[3]
        }
    }
  for (k = 1; k <= f; ++k) print "f " faces[k]
}
# The point of the sphere above cube grid node (i, j, k), shaped.
function vertex(i, j, k,    x, y, z, r, t, notch) {
  x = 2 * i / s - 1; y = 2 * j / s - 1; z = 2 * k / s - 1
  r = sqrt(x * x + y * y + z * z); x /= r; y /= r; z /= r
  y *= 0.65; z *= 0.55
  t = (x + 1) / 2                              # 0 at the right lobe, 1 at the left
  z *= 1.0 - 0.55 * t; y *= 1.0 - 0.25 * t     # tapering
  notch = (x - 0.25) / 0.12
  if (y < 0) y *= 1 - 0.3 * exp(-notch * notch)  # the notch between the lobes, in front
  z += 0.1 * (1 - x * x)                       # a domed top
  if (z < -0.15) z = -0.15                     # the flat underside
  printf "v %.6f %.6f %.6f\n", 0.11 * x, 0.11 * y, 0.11 * z
}' >"$out"
echo "make_liver: wrote $out"
