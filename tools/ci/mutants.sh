#!/usr/bin/env bash
# Mutation check: plants one-line bugs that the suite has caught before, one at a time, in a
# copy of the tree, and shows that the README's test command (build + ctest) still fails on
# each. Run it after changing which tests run where (tiers, sweep sizes, sanitizer selection).
#
# Usage: tools/ci/mutants.sh [SOURCE_DIR]   (default: this checkout, with uncommitted changes)
# Env:   JOBS (default nproc), KEEP=1 keeps the copy for a look at a failure, TEST_CMD (default
#        the README's `ctest --test-dir build --output-on-failure -j$JOBS -LE long`) to check another
#        command instead (an older tree's suite, say), ONLY (an extended regex) to plant only the
#        mutants whose names match it, CHECK_ONLY=1 to check that every pattern still plants and
#        stop there (no build), CMAKE_ARGS for the copy's configure (a compiler launcher, say),
#        TMPDIR for where the copy goes.
# Exit:  0 when every mutant is caught and the unmutated copy passes, 1 otherwise. A pattern
#        that no longer matches its file exactly once fails the run before anything is built.
set -euo pipefail
SRC=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
JOBS=${JOBS:-$(nproc)}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/par2d_mutants_XXXXXX")
[ -n "${KEEP:-}" ] || trap 'rm -rf "$WORK"' EXIT
# The tracked and untracked (not ignored) files: what a commit of the working tree would hold.
(cd "$SRC" && git ls-files -co --exclude-standard -z | tar --null -T - -cf -) | (cd "$WORK" && tar -xf -)
cd "$WORK"

# name | file | perl substitution (must change exactly that file)
# name | file | perl substitution (must match exactly once, in that file)
MUTANTS=(
  "shortened reach|src/culling/light_reach.cpp|s/reach\.reach\[static_cast<std::size_t>\(k\)\] = radii\[found\];/reach.reach[static_cast<std::size_t>(k)] = 0.9 * radii[found];/"
  "removed fold check|src/scene/scene_validate.cpp|s/turn\.side == -winding \|\| \(turn\.fold && turn\.side == 0\)/turn.side == -winding/"
  "gamma 2.2 in the sRGB encoder|src/io/pixel_encoding.cpp|s/(thresholds\[static_cast<std::size_t>\(k - 1\)\] = s <= 0\.04045 \? s \/ 12\.92 : )std::pow\(\(s \+ 0\.055\) \/ 1\.055, 2\.4\)/\$1std::pow(s, 2.2)/"
  "flipped clipped-light sign|src/render/pair_setup.cpp|s/\(t \* along \+ r \* across\)/(t * along - r * across)/"
  "skipped overlap recompute in World::occluder_changed|src/world/world_occluders.cpp|s/^    describe_overlap\(light\.shape, occ, overlap\);\n//m"
  "lit interior blocks a light that overlaps it (SIMD)|src/simd/tile_kernel.hpp|s/occ_terms\.lit_interior \|\| j > 0 \? width/j > 0 ? width/"
  "moved occluder's old place not re-proved|src/world/world_occluders.cpp|s/^    if \(old_box\) observer_->region_changed\(\*old_box\);\n//m"
  "moved light's reach kept|src/culling/reach_cache.cpp|s/if \(!reset_pending_\) stale_\[p\] = 1;/(void)p;/"
  "range window through 1 / range|src/lighting/angular_profile.hpp|s/distance \/ profile_select\(within, range, T\(1\.0\)\)/distance * (T(1.0) \/ profile_select(within, range, T(1.0)))/"
  "light reach ignores the light's mask|src/culling/light_reach.cpp|s/return !\(t\.opaque\(\) && !t\.lit_interior && t\.acts_on\(mask\)\);/return !(t.opaque() && !t.lit_interior);/"
  "reach stale only when the changed box lies inside the proof's box|src/culling/reach_cache.cpp|s/boxes_meet\(depends_\[p\], box\)/(depends_[p].min_x <= box.min_x && box.max_x <= depends_[p].max_x && depends_[p].min_y <= box.min_y && box.max_y <= depends_[p].max_y)/"
  "reach cache's erase leaves the proof box behind|src/culling/reach_cache.cpp|s/^  depends_\.erase\(depends_\.begin\(\) \+ at\);\n//m"
  "reach cache's erase leaves the staleness behind|src/culling/reach_cache.cpp|s/^  stale_\.erase\(stale_\.begin\(\) \+ at\);\n//m"
  "moved light's old footprint not recomputed|src/render/change_tracker.cpp|s/^        mark_light\(scene, old_\[l\], nullptr, l\);\n//m"
  "moved light's layers kept|src/render/light_layers.cpp|s/for \(std::size_t b = 0; b < blocks_\.size\(\); \+\+b\) drop\(b, light\);/(void)light;/"
  "translucent boxes merged|src/world/occluder_merge.cpp|s/^    if \(o\.transmittance\[c\] != 0\.0 && o\.transmittance\[c\] != 1\.0\) return false;\n//m"
  "an update that changes only a light's mask counts as unchanged|src/scene/same_values.cpp|s/same_cookie\) && a\.mask == b\.mask &&/same_cookie) \&\&/"
  "validation fills holes|src/scene/scene_validate.cpp|s/^  if \(!polygon\.holes\.empty\(\)\) return true;\n//m"
  "concave partition merges across reflex angles|src/geometry/polygon_partition.cpp|s/return o > 0 \|\| \(o == 0 && !same_direction\(pa, px, py\)\);/return o < 0 || (o == 0 \&\& !same_direction(pa, px, py));/"
  "bounce radiance without its pi|src/scalar/bounce_reference.cpp|s/= kPi \* albedo\[c\] \* s\[c\];/= albedo[c] * s[c];/"
  "coarse bounce interpolates across occluders|src/render/bounce_tiles.cpp|s/if \(!segment_passes\(at, node_position\(gx, gy\)/if (false \&\& !segment_passes(at, node_position(gx, gy)/"
  "a scroll keeps the pixels of the old tile grid (blocks on the frame, not the grid)|src/render/frame_plan.hpp|s/return BlockGrid\(scene\.width, scene\.height, scene\.grid_x, scene\.grid_y\);/return BlockGrid(scene.width, scene.height, 0, 0);/"
  "a scroll moves the kept pixels the wrong way|src/render/frame_output.cpp|s/for \(int j = 0; j \+ dy < height; \+\+j\) move_row\(j\);/for (int j = height - 1; j + dy >= 0 \&\& j >= 0; --j) if (j + dy < height) move_row(j);/"
  "occlusion proofs join boxes a hairline apart|src/culling/occlusion_proof.cpp|s/      if \(y0 > y1\) continue;/      if (y0 > y1 + 0.5) continue;/"
  "C API swaps a shadow colour's green and blue|src/capi/par2d_c.cpp|s/\{terms->shadow_color\[0\], terms->shadow_color\[1\], terms->shadow_color\[2\]\}/{terms->shadow_color[0], terms->shadow_color[2], terms->shadow_color[1]}/"
)

# Every pattern must still plant, and in one place only, before anything is built: code that
# moved leaves a pattern matching nothing, which must not pass as a mutant the suite missed.
stale=0
for entry in "${MUTANTS[@]}"; do
  IFS='|' read -r name file subst <<<"$entry"
  if [ ! -f "$file" ]; then
    echo "mutants.sh: MUTANT NOT PLANTED: $name: $file does not exist" >&2
    stale=$((stale + 1)); continue
  fi
  once=$(perl -0pe "$subst" "$file" | cksum)
  every=$(perl -0pe "${subst}g" "$file" | cksum)
  if [ "$once" = "$(cksum <"$file")" ]; then
    echo "mutants.sh: MUTANT NOT PLANTED: $name ($file): the pattern no longer matches" >&2
    stale=$((stale + 1))
  elif [ "$once" != "$every" ]; then
    echo "mutants.sh: MUTANT NOT PLANTED: $name ($file): the pattern matches more than once" >&2
    stale=$((stale + 1))
  fi
done
if [ "$stale" -ne 0 ]; then
  echo "mutants.sh: $stale of ${#MUTANTS[@]} patterns do not plant: fix them in tools/ci/mutants.sh" >&2
  exit 1
fi
echo "mutants.sh: all ${#MUTANTS[@]} patterns plant"
[ -z "${CHECK_ONLY:-}" ] || exit 0

test_command() {
  cmake --build build -j"$JOBS" >"$WORK/build.log" 2>&1 || { echo "build failed"; tail -20 "$WORK/build.log"; return 2; }
  eval "${TEST_CMD:-ctest --test-dir build --output-on-failure -j$JOBS -LE long}" >"$WORK/ctest.log" 2>&1
}

t0=$(date +%s)
cmake -S . -B build ${CMAKE_ARGS:-} >/dev/null
if ! test_command; then
  echo "mutants.sh: the unmutated tree fails its tests; see $WORK/ctest.log" >&2
  KEEP=1; trap - EXIT; exit 1
fi
echo "mutants.sh: unmutated: tests pass ($(( $(date +%s) - t0 )) s with the build)"
missed=0
planted=0
for entry in "${MUTANTS[@]}"; do
  IFS='|' read -r name file subst <<<"$entry"
  if [ -n "${ONLY:-}" ] && ! grep -Eq -- "$ONLY" <<<"$name"; then continue; fi
  planted=$((planted + 1))
  cp "$file" "$file.orig"
  perl -0pi -e "$subst" "$file"
  if cmp -s "$file" "$file.orig"; then
    echo "mutants.sh: MUTANT NOT PLANTED: $name ($file): the pattern no longer matches" >&2
    missed=$((missed + 1)); mv "$file.orig" "$file"; continue
  fi
  t1=$(date +%s)
  rc=0; test_command || rc=$?
  if [ "$rc" -eq 2 ]; then
    echo "mutants.sh: BUILD FAILED with $name: fix the substitution" >&2
    missed=$((missed + 1))
  elif [ "$rc" -ne 0 ]; then
    failed=$(sed -nE 's/^[[:space:]]*[0-9]+ - ([^ ]+) .*/\1/p' "$WORK/ctest.log" | tr '\n' ' ')
    echo "mutants.sh: caught  $name ($(( $(date +%s) - t1 )) s): failing ctest entries: $failed"
  else
    echo "mutants.sh: MISSED  $name: the test command passed" >&2
    missed=$((missed + 1))
  fi
  mv "$file.orig" "$file"
  touch "$file"
done
if [ "$planted" -eq 0 ]; then
  echo "mutants.sh: ONLY='${ONLY:-}' matches no mutant's name" >&2
  exit 1
fi
echo "mutants.sh: $planted mutants planted, $missed missed, $(( $(date +%s) - t0 )) s"
exit $((missed > 0))
