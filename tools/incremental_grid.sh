#!/usr/bin/env bash
# The flicker frame (a light-layer recombination) on levels built differently from the torch hall, in callgrind
# instructions per frame (1 thread): a full frame, and (c) without and with the light-layer
# cache (64 MiB), each level written by par2d_make_grid. Of a level's N lights the first N/32
# move and the next N/8 flicker (the hall's 2 and 8 of 64); occluder 0 slides.
#
# Usage: tools/incremental_grid.sh BUILD_DIR [OUT_DIR]     (ISA=avx2 by default)
# Prints a markdown table (docs/performance.md, "Levels built differently").
set -euo pipefail
build=${1:?usage: tools/incremental_grid.sh BUILD_DIR [OUT_DIR]}
out=${2:-$(mktemp -d)}
isa=${ISA:-avx2}
mkdir -p "$out"
make_grid="$build/tools/par2d_make_grid"
frames="$build/bench/par2d_incremental_frames"

# Instructions per frame of par2d_incremental_frames SCENARIO FRAMES 1 MIB LEVEL.
per_frame() {
  local cg="$out/cg.$$"
  PAR2D_ISA=$isa valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*timed_frames*' \
    --callgrind-out-file="$cg" "$frames" "$1" "$2" 1 "$3" "$4" > /dev/null 2>&1
  local total
  total=$(callgrind_annotate "$cg" 2>/dev/null | grep -m1 'PROGRAM TOTALS' | awk '{print $1}' | tr -d ,)
  rm -f "$cg"
  echo $(( total / $2 ))
}

echo "| level | lights, occluders | full | (c) without cache | (c) with cache |"
echo "|---|---|---|---|---|"
while IFS='|' read -r name args; do
  "$make_grid" $args > "$out/$name.json"
  counts=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(len(d['lights']), len(d['occluders']))" "$out/$name.json")
  full=$(per_frame full 2 0 "$out/$name.json")
  plain=$(per_frame c 10 0 "$out/$name.json")
  cached=$(per_frame c 10 64 "$out/$name.json")
  awk -v n="$name" -v c="$counts" -v f="$full" -v p="$plain" -v k="$cached" 'BEGIN {
    split(c, a, " ");
    printf "| %s | %s, %s | %.1f M | %.1f M (%.1f %%) | %.2f M (**%.1f %%**) |\n", n, a[1], a[2], f / 1e6, p / 1e6, 100 * p / f, k / 1e6, 100 * k / f }'
done <<'LEVELS'
L1 tilemap, 32 px cells, range 96|walls --width 1280 --height 720 --tile 32 --style tilemap --torches 64 --range 96
L2 merged runs, 16 px cells, pillars 15 %, range 64|walls --width 1280 --height 720 --tile 16 --style merged --density 0.15 --torches 64 --range 64 --seed 7
L3 free-form walls, 64 px cells, range 128, torches 2 px off|walls --width 1280 --height 720 --tile 64 --style free --torches 64 --range 128 --overlap -2 --seed 11
L4 tilemap, 24 px cells, no range|walls --width 1280 --height 720 --tile 24 --style tilemap --torches 40 --seed 5
L5 tilemap, 48 px cells, pillars 10 %, range 96, torches 3 px deep|walls --width 1280 --height 720 --tile 48 --style tilemap --density 0.1 --torches 64 --range 96 --overlap 3 --seed 13
F1 field crop, 256 lights and 4096 occluders (640 x 360 of 1920 x 1080), no range|field --lights 256 --occluders 4096 --width 640 --height 360
LEVELS
