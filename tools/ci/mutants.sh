#!/usr/bin/env bash
# Mutation check: plants one-line bugs that the suite has caught before, one at a time, in a
# copy of the tree, and shows that the README's test command (build + ctest) still fails on
# each. Run it after changing which tests run where (tiers, sweep sizes, sanitizer selection).
#
# Usage: tools/ci/mutants.sh [SOURCE_DIR]   (default: this checkout, with uncommitted changes)
# Env:   JOBS (default nproc), KEEP=1 keeps the copy for a look at a failure, TEST_CMD (default
#        the README's `ctest --test-dir build --output-on-failure -j$JOBS -LE long`) to check another
#        command instead (an older tree's suite, say).
# Exit:  0 when every mutant is caught and the unmutated copy passes, 1 otherwise.
set -euo pipefail
SRC=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
JOBS=${JOBS:-$(nproc)}
WORK=$(mktemp -d /tmp/par2d_mutants_XXXXXX)
[ -n "${KEEP:-}" ] || trap 'rm -rf "$WORK"' EXIT
# The tracked and untracked (not ignored) files: what a commit of the working tree would hold.
(cd "$SRC" && git ls-files -co --exclude-standard -z | tar --null -T - -cf -) | (cd "$WORK" && tar -xf -)
cd "$WORK"

# name | file | perl substitution (must change exactly that file)
MUTANTS=(
  "shortened reach|src/culling/light_reach.cpp|s/reach\.reach\[static_cast<std::size_t>\(k\)\] = radii\[found\];/reach.reach[static_cast<std::size_t>(k)] = 0.9 * radii[found];/"
  "removed fold check|src/scene/scene_validate.cpp|s/turn\.side == -winding \|\| \(turn\.fold && turn\.side == 0\)/turn.side == -winding/"
  "gamma 2.2 in the sRGB encoder|src/io/image_files.cpp|s/std::pow\(\(s \+ 0\.055\) \/ 1\.055, 2\.4\)/std::pow(s, 2.2)/"
  "flipped clipped-light sign|src/render/pair_setup.cpp|s/\(t \* along \+ r \* across\)/(t * along - r * across)/"
  "skipped overlap recompute in World::occluder_changed|src/world/world.cpp|s/^    describe_overlap\(light\.shape, occ, overlap\);\n//m"
  "lit interior blocks a light that overlaps it (SIMD)|src/simd/tile_kernel.hpp|s/if \(occ_terms\.lit_interior \|\| j > 0\) \{/if (j > 0) {/"
  "moved occluder's old place not re-proved|src/world/world.cpp|s/^  if \(old_box\) touch_reach\(\*old_box\);\n//m"
  "moved light's reach kept|src/world/world.cpp|s/^  reach_stale_\[p\] = 1;\n\}/}/m"
  "range window through 1 / range|src/lighting/angular_profile.hpp|s/distance \/ profile_select\(within, range, T\(1\.0\)\)/distance * (T(1.0) \/ profile_select(within, range, T(1.0)))/"
)

test_command() {
  cmake --build build -j"$JOBS" >"$WORK/build.log" 2>&1 || { echo "build failed"; tail -20 "$WORK/build.log"; return 2; }
  eval "${TEST_CMD:-ctest --test-dir build --output-on-failure -j$JOBS -LE long}" >"$WORK/ctest.log" 2>&1
}

t0=$(date +%s)
cmake -S . -B build >/dev/null
if ! test_command; then
  echo "mutants.sh: the unmutated tree fails its tests; see $WORK/ctest.log" >&2
  KEEP=1; trap - EXIT; exit 1
fi
echo "mutants.sh: unmutated: tests pass ($(( $(date +%s) - t0 )) s with the build)"
missed=0
for entry in "${MUTANTS[@]}"; do
  IFS='|' read -r name file subst <<<"$entry"
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
echo "mutants.sh: ${#MUTANTS[@]} mutants, $missed missed, $(( $(date +%s) - t0 )) s"
exit $((missed > 0))
