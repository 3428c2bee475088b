#!/usr/bin/env bash
# CI: the CLI under memory pressure and past SPEC limits must fail with one clear line, no crash, no output file.
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

exit $((failures > 0))
