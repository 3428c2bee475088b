#!/usr/bin/env bash
# Instructions per pixel of the tile kernel, SSE4.2 (x86-64) against NEON (aarch64), on the
# example scenes: counts every instruction executed inside the kernel's entry point and its
# callees while `par2d bench --frames 1` renders two frames (warm-up + 1) on one thread.
#   SSE4.2: valgrind callgrind, --toggle-collect on render_tile_sse4_2 (inclusive).
#   NEON:   qemu-aarch64 logs each translated block (-d in_asm) and each execution of one
#           (-d exec,nochain) whose address lies in the NEON kernel's code (-dfilter: the range
#           of the ISA file's functions, which call nothing outside it); the sum of block
#           lengths over executions is the count of executed instructions.
# Counts are of instructions, not time: they say nothing of a real core's cycles.
# Usage: tools/insn_per_pixel.sh X86_BUILD ARM64_BUILD [WIDTH HEIGHT]   (default 320 180)
set -euo pipefail
cd "$(dirname "$0")/.."
X86=${1:?x86 build dir}; ARM=${2:?arm64 build dir}; W=${3:-320}; H=${4:-180}
TMP=$(mktemp -d); trap 'rm -rf "$TMP"' EXIT
CLI_ARGS=(--backend simd --frames 1 --threads 1 --width "$W" --height "$H")
PIXELS=$((2 * W * H))

# The NEON kernel's code range in the aarch64 CLI (a PIE, so relative to its load address).
read -r LO HI < <(aarch64-linux-gnu-nm -S --defined-only "$ARM/tools/par2d" | python3 -c '
import sys
spans = [(int(a, 16), int(a, 16) + int(n, 16)) for a, n, t, name in (l.split()[:4] for l in sys.stdin if len(l.split()) >= 4)
         if t in "TtWw" and "neon64" in name]
print(min(s for s, e in spans), max(e for s, e in spans))')
BASE=$(qemu-aarch64 -d page "$ARM/tools/par2d" info 2>&1 >/dev/null | awk '$3 == "r-x" && b == "" { split($1, r, "-"); b = r[1] } END { print b }')
RANGE=$(printf '0x%x..0x%x' $((0x$BASE + LO)) $((0x$BASE + HI - 1)))
# Sums, over logged block executions ("Trace ... [flags/pc/...]"), the length of the block
# translated at that pc ("IN:" followed by one line per instruction). Addresses are compared
# as hex strings without leading zeros.
COUNT_BLOCKS='
function key(h) { sub(/^0x/, "", h); sub(/^0+/, "", h); return tolower(h) }
/^Trace / { split($4, f, "/"); total += len[key(f[2])]; next }
/^0x[0-9a-f]+:/ { if (start == "") start = key(substr($1, 1, length($1) - 1)); n++; next }
start != "" { len[start] = n; start = ""; n = 0 }
END { printf "%.0f\n", total }'

printf '%-16s %14s %14s %8s\n' scene sse4_insn/px neon64_insn/px ratio
for scene in paper colored_lights dungeon; do
  valgrind --tool=callgrind --callgrind-out-file="$TMP/cg.out" \
    --toggle-collect='par2d::simd::render_tile_sse4_2*' \
    "$X86/tools/par2d" bench "examples/$scene.json" --isa sse4 "${CLI_ARGS[@]}" >/dev/null 2>&1
  SSE=$(awk '/^totals:/ { print $2 }' "$TMP/cg.out")
  mkfifo "$TMP/qemu.log"
  awk "$COUNT_BLOCKS" "$TMP/qemu.log" > "$TMP/neon.txt" &
  qemu-aarch64 -d in_asm,exec,nochain -dfilter "$RANGE" -D "$TMP/qemu.log" \
    "$ARM/tools/par2d" bench "examples/$scene.json" "${CLI_ARGS[@]}" >/dev/null
  wait
  rm -f "$TMP/qemu.log"
  NEON=$(cat "$TMP/neon.txt")
  awk -v s="$scene" -v a="$SSE" -v b="$NEON" -v p="$PIXELS" \
    'BEGIN { printf "%-16s %14.1f %14.1f %8.3f\n", s, a / p, b / p, b / a }'
done
echo "($W x $H, 2 frames, 1 thread; x86 $(basename "$X86"), aarch64 $(basename "$ARM"))"
