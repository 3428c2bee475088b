#!/usr/bin/env bash
# The grid's three target ratios (torch in a wall against off it, merged against unmerged walls, dense
# fields against small levels) over its levels, in callgrind instructions (1 thread).
#
# Usage: tools/grid_bench.sh BUILD_DIR [OUT_DIR]     (ISA=avx2 by default; PARTS="walls merge field")
#
# Each level is written by par2d_make_grid and rendered once by `par2d render --threads 1`;
# the count is par2d::render's inclusive one (world, light reach, frame; not loading or
# writing files). Prints one markdown table per target:
#  walls: a torch reaching OVERLAP px into its wall over the same torch 2 px off (goal <= 1.3),
#         one parameter at a time around tile 32, tilemap, radius 5, overlap 1, no range,
#         density 0.04 (640 x 360);
#  merge: the tilemap over the same walls with each row's runs merged (goal >= 1.3);
#  field: 256 lights + 4096 occluders over 16 + 256 in the same 1920 x 1080 field, seen through
#         a 320 x 180 window at its center (goal <= 16), with `par2d bench --stats`'s kernel
#         pairs per sample against the exact pairs per pixel (goal <= 8 on 1.5-4 px).
set -euo pipefail
build=${1:?usage: tools/grid_bench.sh BUILD_DIR [OUT_DIR]}
out=${2:-$(mktemp -d)}
isa=${ISA:-avx2}
parts=${PARTS:-walls merge field}
mkdir -p "$out"
make_grid="$build/tools/par2d_make_grid"
par2d="$build/tools/par2d"

# Instructions of par2d::render for one level (written to $out/NAME.json first).
count() {
  local name
  name=$(tr -c 'A-Za-z0-9_.\n-' '_' <<<"$1")
  shift
  "$make_grid" "$@" > "$out/$name.json"
  valgrind --tool=callgrind --callgrind-out-file="$out/$name.cg" --toggle-collect='par2d::render(*' \
    "$par2d" render "$out/$name.json" --isa "$isa" --threads 1 --pfm "$out/$name.pfm" 2>&1 |
    sed -n 's/.*Collected : *\([0-9]*\).*/\1/p'
}
mi() { awk -v n="$1" 'BEGIN { printf "%.1f", n / 1e6 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }'; }

if [[ $parts == *walls* ]]; then
  echo "| level (640x360, $isa) | overlapping (M) | 2 px off (M) | ratio |"
  echo "|---|---|---|---|"
  # name|arguments besides --overlap (the center: tile 32, tilemap, r 5, no range, density 0.04)|overlap
  while IFS='|' read -r name args overlap; do
    [[ -z $name ]] && continue
    # shellcheck disable=SC2086
    a=$(count "walls_${name}_in" walls $args --overlap "$overlap")
    # shellcheck disable=SC2086
    b=$(count "walls_${name}_off" walls $args --overlap -2)
    echo "| $name | $(mi "$a") | $(mi "$b") | $(ratio "$a" "$b") |"
  done <<'EOF'
center (tile 32, tilemap, r 5, overlap 1)|--tile 32|1
tile 16|--tile 16|1
tile 64|--tile 64|1
free-form walls|--style free|1
overlap 0.1|--tile 32|0.1
overlap 2.5 (half the radius)|--tile 32|2.5
radius 2.5|--torch-radius 2.5|1
radius 6, overlap 3|--torch-radius 6|3
range 100|--range 100|1
range 100, free-form|--range 100 --style free|1
density 0.15|--density 0.15|1
tile 16, 24 torches, range 60|--tile 16 --torches 24 --range 60|1
EOF
  echo
fi

if [[ $parts == *merge* ]]; then
  echo "| tilemap level (640x360, $isa) | boxes | merged | unmerged (M) | merged (M) | ratio |"
  echo "|---|---|---|---|---|---|"
  while IFS='|' read -r name args; do
    [[ -z $name ]] && continue
    # shellcheck disable=SC2086
    a=$(count "merge_${name}_cells" walls --style tilemap $args)
    # shellcheck disable=SC2086
    b=$(count "merge_${name}_runs" walls --style merged $args)
    slug=$(tr -c 'A-Za-z0-9_.\n-' '_' <<<"$name")
    na=$(grep -o '"polygon"' "$out/merge_${slug}_cells.json" | wc -l)
    nb=$(grep -o '"polygon"' "$out/merge_${slug}_runs.json" | wc -l)
    echo "| $name | $na | $nb | $(mi "$a") | $(mi "$b") | $(ratio "$a" "$b") |"
  done <<'EOF'
tile 16|--tile 16
tile 32|--tile 32
tile 64|--tile 64
tile 16, density 0.15|--tile 16 --density 0.15
tile 32, torches 2 px off|--tile 32 --overlap -2
tile 16, 24 torches, range 60|--tile 16 --torches 24 --range 60
EOF
  echo
fi

if [[ $parts == *field* ]]; then
  echo "| occluders (px) | lights (px) | 16 + 256 (M) | 256 + 4096 (M) | ratio | kernel pairs/sample | exact pairs/pixel | pairs ratio |"
  echo "|---|---|---|---|---|---|---|---|"
  while read -r omin omax lmin lmax; do
    [[ -z $omin ]] && continue
    tag="${omin}-${omax}_${lmin}-${lmax}"
    sizes=(--occluder-size "$omin" "$omax" --light-size "$lmin" "$lmax" --width 320 --height 180)
    a=$(count "field_${tag}_16" field --lights 16 --occluders 256 "${sizes[@]}")
    b=$(count "field_${tag}_256" field --lights 256 --occluders 4096 "${sizes[@]}")
    stats=$("$par2d" bench "$out/field_${tag}_256.json" --isa "$isa" --threads 1 --frames 1 --stats)
    kernel=$(sed -n 's/.*per sample (kernel): [0-9.]* light arcs, \([0-9.]*\) pairs.*/\1/p' <<<"$stats")
    exact=$(sed -n 's/.*lights visible, \([0-9.]*\) occluders cutting.*/\1/p' <<<"$stats")
    echo "| $omin-$omax | $lmin-$lmax | $(mi "$a") | $(mi "$b") | $(ratio "$b" "$a") | $kernel | $exact | $(ratio "$kernel" "$exact") |"
  done <<'EOF'
1.5 4 3 5
1.5 4 6 12
4 12 3 5
4 12 6 12
12 40 3 5
12 40 6 12
EOF
fi
