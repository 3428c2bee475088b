#!/usr/bin/env bash
# CI: runs a doctest binary's test cases one per process, JOBS processes at a time, so that a
# suite which is one long process (under a sanitizer or qemu) uses every core.
#
# Usage: tools/ci/sharded.sh BINARY [doctest filter options...]
# Env:   JOBS (default nproc); SHARD_WRAPPER, a command to run the binary under (e.g. qemu-aarch64).
# Each case runs as `BINARY FILTERS --first=i --last=i` (doctest's 1-based index among the cases
# passing the filters). A case passes only if its process exits 0 and reports exactly one test
# case run (one --duration line), so a selection that ran nothing fails instead of passing.
# A failing case's whole output is printed; the run fails if any case failed.
set -euo pipefail
JOBS=${JOBS:-$(nproc)}
[ $# -ge 1 ] || { echo "usage: tools/ci/sharded.sh BINARY [doctest options...]" >&2; exit 2; }
BIN=$1
shift
WRAP=()
[ -n "${SHARD_WRAPPER:-}" ] && read -r -a WRAP <<< "$SHARD_WRAPPER"

count=$("${WRAP[@]}" "$BIN" "$@" --count --no-intro=true | sed -n 's/.*passing the current filters: \([0-9][0-9]*\).*/\1/p')
if [ -z "$count" ] || [ "$count" -eq 0 ]; then
  echo "sharded.sh: no test case of $BIN passes the filters $*" >&2
  exit 1
fi
LOGS=$(mktemp -d)
trap 'rm -rf "$LOGS"' EXIT

run_case() {
  local i=$1
  shift
  local log="$LOGS/$i.log"
  if "${WRAP[@]}" "$BIN" "$@" --first="$i" --last="$i" --no-intro=true --duration=true >"$log" 2>&1 &&
     [ "$(grep -Ec '^[0-9.]+ s: ' "$log")" -eq 1 ]; then
    return 0
  fi
  echo "sharded.sh: case $i of $count FAILED ($BIN $* --first=$i --last=$i):" >&2
  cat "$log" >&2
  return 1
}

t0=$(date +%s)
status=0
running=0
for i in $(seq 1 "$count"); do
  if [ "$running" -ge "$JOBS" ]; then
    wait -n || status=1
    running=$((running - 1))
  fi
  run_case "$i" "$@" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || status=1
  running=$((running - 1))
done
asserts=$(cat "$LOGS"/*.log | sed -n 's/.*assertions: *\([0-9][0-9]*\) .*/\1/p' | awk '{s += $1} END {print s + 0}')
if [ "$status" -ne 0 ]; then
  echo "sharded.sh: $BIN: some of $count test cases FAILED" >&2
  exit 1
fi
echo "sharded.sh: $BIN: $count test cases passed ($asserts assertions), $JOBS at a time, $(( $(date +%s) - t0 )) s"
