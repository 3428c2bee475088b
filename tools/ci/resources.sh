#!/usr/bin/env bash
# CI: the CLI under memory pressure (rendering and loading), past the contract's limits, and with special
# output files (FIFOs, stdout) and signals during writes: one clear line, no crash, no partial or lost file.
#
# Usage: tools/ci/resources.sh [BUILD_DIR]  (default: build; needs the par2d CLI built there, no sanitizer:
# ASan cannot start under ulimit -v).
set -euo pipefail
cd "$(dirname "$0")/../.."
CLI=${1:-build}/tools/par2d
[ -x "$CLI" ] || { echo "resources.sh: no CLI at $CLI" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
failures=0

# expect_clean_failure NAME PATTERN -- command...: non-zero exit below 128 (no signal), exactly one
# stderr line matching PATTERN, and no output file left behind.
expect_clean_failure() {
  local name=$1 pattern=$2; shift 3
  local rc=0
  "$@" 2>"$WORK/err" >/dev/null || rc=$?
  local lines; lines=$(wc -l <"$WORK/err")
  if [ "$rc" -eq 0 ] || [ "$rc" -ge 128 ] || [ "$lines" -ne 1 ] || ! grep -qE "$pattern" "$WORK/err" \
     || compgen -G "$WORK/out*" >/dev/null; then
    echo "resources.sh: FAIL $name: exit $rc, $lines stderr lines:" >&2
    cat "$WORK/err" >&2
    ls "$WORK" >&2
    failures=$((failures + 1))
  else
    echo "resources.sh: ok   $name (exit $rc): $(cat "$WORK/err")"
  fi
}

light='"lights": [{"circle": {"center": [100, 100], "radius": 10}}]'
echo "{\"width\": 16384, \"height\": 16384, $light}" >"$WORK/big.json"
echo "{\"width\": 16385, \"height\": 16, $light}" >"$WORK/too_wide.json"
echo "{\"width\": 16, \"height\": 1e9, $light}" >"$WORK/too_tall.json"

# 16384 x 16384 x 3 floats = 3 GiB; under a 1.5 GiB address-space limit the image cannot be had.
expect_clean_failure "image allocation fails under ulimit -v" "memory" -- \
  bash -c 'ulimit -v 1572864; exec "$0" render "$1" -o "$2/out.png" --pfm "$2/out.pfm" --threads 2' \
  "$CLI" "$WORK/big.json" "$WORK"
expect_clean_failure "bench allocation fails under ulimit -v" "memory" -- \
  bash -c 'ulimit -v 1572864; exec "$0" bench "$1" --frames 1 --threads 2' "$CLI" "$WORK/big.json"
# ~3.6 GiB: the image fits and renders, the PNG encoder's buffers do not: no partial file may remain.
expect_clean_failure "PNG encoding fails under ulimit -v, no torn file" "memory" -- \
  bash -c 'ulimit -v 3800000; exec "$0" render "$1" -o "$2/out.png" --threads 2' "$CLI" "$WORK/big.json" "$WORK"
expect_clean_failure "width beyond 16384" "too_wide.json: width" -- \
  "$CLI" render "$WORK/too_wide.json" -o "$WORK/out.png"
expect_clean_failure "height beyond 16384" "too_tall.json: height" -- \
  "$CLI" render "$WORK/too_tall.json" -o "$WORK/out.png"
expect_clean_failure "bench --width beyond 16384" "16384" -- \
  "$CLI" bench "$WORK/big.json" --width 100000 --height 4 --frames 1

# --- Memory limits while loading: the loader builds no JSON document (~2x the file at most),
# and every allocation failure is the one-line "out of memory", never an abort.
python3 - "$WORK/level.json" <<'PY'
import sys
parts = ['{"circle":{"center":[%d,%d],"radius":1}}' % (100 + k % 997, 100 + k % 991) for k in range(500000)]
open(sys.argv[1], "w").write('{"width": 4, "height": 4, "lights": [{"circle": {"center": [2, 2], "radius": 1}}], '
                             '"occluders": [' + ",".join(parts) + "]}")
PY
echo "resources.sh: level.json is $(( $(stat -c %s "$WORK/level.json") >> 20 )) MiB"
# The CLI maps ~29 MiB (its shared libraries, SDL2 for the viewer among them) before main
# runs, so the cap leaves it ~30 MiB of room: less than loading the scene needs.
expect_clean_failure "loading a 20 MB scene under ulimit -v 60000" "level.json: out of memory while loading" -- \
  bash -c 'ulimit -v 60000; exec "$0" render "$1" -o "$2/out.png" --threads 1' "$CLI" "$WORK/level.json" "$WORK"
# The issue's case: 300 MB is enough to load and render it (it aborted with SIGABRT before).
rc=0
bash -c 'ulimit -v 300000; exec "$0" render "$1" --pfm "$2/level.pfm" --threads 1' "$CLI" "$WORK/level.json" "$WORK" \
  2>"$WORK/err" || rc=$?
if [ "$rc" -ne 0 ] && { [ "$rc" -ge 128 ] || [ "$(wc -l <"$WORK/err")" -ne 1 ]; }; then
  echo "resources.sh: FAIL 20 MB scene under ulimit -v 300000: exit $rc" >&2; cat "$WORK/err" >&2; failures=$((failures + 1))
else
  echo "resources.sh: ok   20 MB scene under ulimit -v 300000 (exit $rc)"
fi
rm -f "$WORK/level.pfm"
# A FIFO with no writer as the scene: refused at once, not waited on.
mkfifo "$WORK/scene.fifo"
expect_clean_failure "a FIFO scene file with no writer" "not a regular file" -- \
  timeout 20 "$CLI" render "$WORK/scene.fifo" -o "$WORK/out.png"
rm -f "$WORK/scene.fifo"

# --- Huge emissions: refused at load time, naming the light.
echo "{\"width\": 8, \"height\": 8, \"lights\": [{\"circle\": {\"center\": [4, 4], \"radius\": 1}, \"intensity\": 2.2e39}]}" \
  >"$WORK/bright.json"
expect_clean_failure "emission beyond float output" "bright.json: lights\[0\]: emission too large" -- \
  "$CLI" render "$WORK/bright.json" -o "$WORK/out.png"

# --- Shapes far larger than the view (coordinates up to ~5.6e306), emissions near the 1e38 limit,
# and contacts (a light on an occluder's edge, equal circles): every backend renders under a
# 1 GiB address-space limit, exits 0 and writes a PFM that is finite and within [0, sum of e_L].
python3 - "$WORK/huge.json" <<'PY'
import json, sys
d, k = 2.0 ** 1016, 2.0 ** 1012  # lines 3x = 8y and circles (3K, -4K) of radius 5K through the origin
scene = {"width": 48, "height": 48, "view": [-4, -6, 12, 10],
         "lights": [{"polygon": [[-8 * d, -3 * d], [8 * d, -3 * d], [8 * d, 3 * d]], "intensity": 3e37},
                    {"segment": [[-2, 7], [4, 6]], "intensity": 2e37},
                    {"circle": {"center": [-2, 6], "radius": 0.5}, "intensity": 1e37}],
         "occluders": [{"segment": [[-8 * d, -3 * d], [8 * d, 3 * d]]},
                       {"polygon": [[-2, 7], [4, 6], [4, 9], [-2, 9]]},
                       {"circle": {"center": [-2, 6], "radius": 0.5}},
                       {"circle": {"center": [3 * k + 6, -4 * k], "radius": 5 * k}}]}
json.dump(scene, open(sys.argv[1], "w"))
PY
for backend in scalar simd raycast; do
  rc=0
  bash -c 'ulimit -v 1048576; exec "$0" render "$1" --pfm "$2" --backend "$3" --threads 2' \
    "$CLI" "$WORK/huge.json" "$WORK/huge_$backend.pfm" "$backend" 2>"$WORK/err" || rc=$?
  if [ "$rc" -eq 0 ] && python3 - "$WORK/huge_$backend.pfm" <<'PY'
import math, struct, sys
data = open(sys.argv[1], "rb").read()
header = data.split(b"\n", 3)
w, h = map(int, header[1].split())
values = struct.unpack("<%df" % (3 * w * h), header[3][:12 * w * h])
# sum of e_L per channel (white lights): 6e37; float rounding allowed
sys.exit(0 if all(math.isfinite(v) and 0.0 <= v <= 6e37 * (1 + 1e-5) for v in values) else 1)
PY
  then
    echo "resources.sh: ok   huge shapes, emissions and contacts render finite and bounded ($backend)"
  else
    echo "resources.sh: FAIL huge shapes ($backend): exit $rc" >&2; cat "$WORK/err" >&2; failures=$((failures + 1))
  fi
done
rm -f "$WORK"/huge_*.pfm

# --- Special output files and signals during writes.
echo '{"width": 256, "height": 256, "lights": [{"circle": {"center": [64, 64], "radius": 8}}]}' >"$WORK/s.json"
mkfifo "$WORK/pipe"
cat "$WORK/pipe" >"$WORK/from_pipe" &
reader=$!
if "$CLI" render "$WORK/s.json" --pfm "$WORK/pipe" && wait "$reader" && [ -p "$WORK/pipe" ] \
   && [ "$(stat -c %s "$WORK/from_pipe")" -eq $((16 + 256 * 256 * 12)) ]; then
  echo "resources.sh: ok   --pfm to a FIFO is written through, the FIFO stays"
else
  echo "resources.sh: FAIL --pfm to a FIFO" >&2; failures=$((failures + 1))
fi
if "$CLI" render "$WORK/s.json" -o - | cmp -s - <("$CLI" render "$WORK/s.json" -o "$WORK/o.png" && cat "$WORK/o.png"); then
  echo "resources.sh: ok   -o - writes the PNG to stdout"
else
  echo "resources.sh: FAIL -o -" >&2; failures=$((failures + 1))
fi
# SIGTERM while the PFM blocks on a full FIFO (opened, never read): no file may remain but
# the ones that were there, unchanged.
echo "old" >"$WORK/old.png"
exec 7<>"$WORK/pipe"  # a reader that never reads
"$CLI" render "$WORK/s.json" -o "$WORK/old.png" --pfm "$WORK/pipe" &
victim=$!
sleep 2
kill -TERM "$victim"; rc=0; wait "$victim" || rc=$?
exec 7<&-
leftover=$(find "$WORK" -name '*.tmp*' | wc -l)
if [ "$rc" -eq 143 ] && [ "$(cat "$WORK/old.png")" = "old" ] && [ "$leftover" -eq 0 ]; then
  echo "resources.sh: ok   SIGTERM mid-write leaves old.png as it was and no temporary"
else
  echo "resources.sh: FAIL SIGTERM mid-write: exit $rc, $leftover temporaries, old.png: $(head -c 8 "$WORK/old.png" | od -c | head -1)" >&2
  failures=$((failures + 1))
fi
rm -f "$WORK/pipe" "$WORK/from_pipe" "$WORK/o.png" "$WORK/old.png"

exit $((failures > 0))
