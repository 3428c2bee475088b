#!/usr/bin/env bash
# CI: builds the libFuzzer targets with clang (ASan+UBSan) and fuzzes each for a bounded time; any finding fails.
# Targets: the scene loader on arbitrary bytes, the renderer on decoded degenerate geometry,
# contact cases with huge emissions and extreme views (tests/fuzz/fuzz_contact_checks.hpp), and
# shapes 2^10..2^1010 pixels across through the view with emissions up to ~1e37
# (tests/fuzz/fuzz_huge_checks.hpp).
#
# Env: FUZZ_SECONDS (default 60: the time each of the first three targets had; the four targets now
# share 3 * FUZZ_SECONDS equally, so the run takes as long as before), JOBS (build, default nproc), CXX_CLANG (default clang++-14),
# FUZZ_SEED (default 1: the gate explores the same inputs on every run, so a finding reproduces
# from the log; set another seed, or a longer FUZZ_SECONDS, for a campaign that looks further).
# Findings land in build-fuzz/artifacts/; turn each into a file under tests/fuzz/corpus/ (it is then
# replayed by every build's test suite) and fix it.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
FUZZ_SEED=${FUZZ_SEED:-1}
PER_TARGET=$(( 3 * FUZZ_SECONDS / 4 ))
JOBS=${JOBS:-$(nproc)}
CXX_CLANG=${CXX_CLANG:-clang++-14}
BUILD=build-fuzz

t0=$(date +%s)
# The library itself is instrumented too (fuzzer-no-link: coverage without libFuzzer's main).
cmake -S . -B "$BUILD" -DCMAKE_CXX_COMPILER="$CXX_CLANG" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" \
      -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
      -DPAR2D_KERNEL_INLINE_HINTS=ON -DPAR2D_BUILD_TESTS=OFF -DPAR2D_BUILD_TOOLS=OFF -DPAR2D_BUILD_BENCH=OFF \
      -DPAR2D_BUILD_FUZZ=ON >/dev/null
cmake --build "$BUILD" -j"$JOBS" --target fuzz_scene_loader fuzz_render fuzz_contact fuzz_huge
t1=$(date +%s)
echo "fuzz.sh: build $((t1 - t0)) s"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p "$BUILD/artifacts"
status=0
run_target() {  # target, seed corpus dir, max input length
  local target=$1 seeds=$2 max_len=$3
  local work="$BUILD/corpus/$target"
  mkdir -p "$work"
  # The checked-in seeds are read, never written: new inputs go to the work corpus.
  # -timeout: an input that takes this long is reported as a hang; -rss_limit_mb: as a leak/blow-up.
  if ! "$BUILD/tests/fuzz/$target" "$work" "$seeds" -max_total_time="$PER_TARGET" -max_len="$max_len" -seed="$FUZZ_SEED" \
        -timeout=25 -rss_limit_mb=2560 -print_final_stats=1 \
        -artifact_prefix="$BUILD/artifacts/$target-" 2>"$BUILD/$target.log"; then
    echo "fuzz.sh: $target found a problem; last lines of $BUILD/$target.log:" >&2
    tail -n 60 "$BUILD/$target.log" >&2
    status=1
  else
    grep -E '^stat::(number_of_executed_units|peak_rss_mb)' "$BUILD/$target.log" | sed "s/^/fuzz.sh: $target /"
  fi
}
run_target fuzz_scene_loader "$ROOT/tests/fuzz/corpus/loader" 4096
run_target fuzz_render "$ROOT/tests/fuzz/corpus/render" 2048
# Lights on occluder edges, equal shapes, touching circles, emissions up to 1e37 each, views
# of 1e-300 to 1e300 units per pixel: 0 everywhere (docs/contract.md: t_occ == t_L hides).
run_target fuzz_contact "$ROOT/tests/fuzz/corpus/contact" 256
# Slanted lines, bands and circles far larger than the view, lights along occluders' huge
# edges, emissions up to ~1e37: bounded and finite everywhere; where lights and occluders are
# apart, SIMD within 1e-4 e_max of scalar and scalar within the ray caster's stratification bound.
run_target fuzz_huge "$ROOT/tests/fuzz/corpus/huge" 256
echo "fuzz.sh: total $(( $(date +%s) - t0 )) s"
exit $status
