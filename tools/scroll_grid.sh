#!/usr/bin/env bash
# A scrolling camera's frames against full frames, over levels built differently (tilemaps and
# free-form walls, 16 to 256 lights, ranged and unranged) and the bundled dungeon, 1920 x 1080.
# Each column is par2d_incremental_frames' median frame time in one run of this script, as a
# share of the full frame's (p: every pixel computed while the camera pans): h, v, g (the
# camera panning 4 px a frame right, down, diagonally, nothing else changing), m (g while the
# level's first N/32 lights move, at least one), b (those lights moving, no pan: what the
# motion alone costs), g with the light-layer cache (64 MiB) over g without it, and G and M:
# g and m into a ring buffer (BufferLayout::ring: the kept pixels do not move), and M with the
# light-layer cache (the lights that do not move are recombined from their layers). The buffer
# is float RGB (12 bytes a pixel), the benchmark's.
#
# Usage: tools/scroll_grid.sh BUILD_DIR [OUT_DIR]     (THREADS=2, ISA=best by default)
# Prints a markdown table (docs/performance.md, "Scrolling").
set -euo pipefail
build=${1:?usage: tools/scroll_grid.sh BUILD_DIR [OUT_DIR]}
out=${2:-$(mktemp -d)}
threads=${THREADS:-2}
mkdir -p "$out"
make_grid="$build/tools/par2d_make_grid"
frames="$build/bench/par2d_incremental_frames"
here=$(cd "$(dirname "$0")/.." && pwd)

# Median milliseconds of SCENARIO over FRAMES frames with LAYER_MIB of cache on LEVEL.
median() {
  "$frames" "$1" "$2" "$threads" "$3" "$4" | sed -n 's/.*median \([0-9.]*\) ms.*/\1/p'
}
share() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f %%", 100 * a / b }'; }

echo "| level (1920 x 1080, $threads threads) | lights, occluders | full (ms) | h | v | g | m | b (no pan) | g cached / g | G (ring) | M (ring) | M (ring, cached) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
while IFS='|' read -r name args; do
  [[ -z $name ]] && continue
  if [[ $args == examples/* ]]; then
    level="$here/$args"
  else
    level="$out/$(tr -c 'A-Za-z0-9_\n-' '_' <<<"$name").json"
    # shellcheck disable=SC2086
    "$make_grid" $args --width 1920 --height 1080 > "$level"
  fi
  counts=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(len(d['lights']), len(d['occluders']))" "$level")
  full=$(median p 6 0 "$level")
  h=$(median h 40 0 "$level")
  v=$(median v 40 0 "$level")
  g=$(median g 40 0 "$level")
  m=$(median m 20 0 "$level")
  b=$(median b 20 0 "$level")
  gc=$(median g 40 64 "$level")
  gr=$(median G 40 0 "$level")
  mr=$(median M 20 0 "$level")
  mc=$(median M 20 64 "$level")
  echo "| $name | ${counts/ /, } | $full | $(share "$h" "$full") | $(share "$v" "$full") | $(share "$g" "$full") | $(share "$m" "$full") | $(share "$b" "$full") | $(awk -v a="$gc" -v b="$g" 'BEGIN { printf "%.2f", a / b }') | $(share "$gr" "$full") | $(share "$mr" "$full") | $(share "$mc" "$full") |"
done <<'LEVELS'
dungeon (examples)|examples/dungeon.json
tilemap, 32 px cells, 64 torches, range 96|walls --tile 32 --style tilemap --torches 64 --range 96
free-form walls, 64 px cells, 64 torches, range 128|walls --tile 64 --style free --torches 64 --range 128 --seed 11
tilemap, 24 px cells, 16 torches, no range|walls --tile 24 --style tilemap --torches 16 --seed 5
merged runs, 16 px cells, 256 torches, range 64|walls --tile 16 --style merged --density 0.15 --torches 256 --range 64 --seed 7
free-form walls, 48 px cells, 128 torches, no range|walls --tile 48 --style free --torches 128 --seed 3
field, 64 lights, 1024 occluders, no range|field --lights 64 --occluders 1024
LEVELS
