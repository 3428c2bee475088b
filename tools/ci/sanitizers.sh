#!/usr/bin/env bash
# CI: builds the test suite under ASan+UBSan (all tests) and TSan (threaded tests), and fails on any report.
#
# Only what the tests need is built (no benchmarks); the CLI is built because tests run it.
# Usage: tools/ci/sanitizers.sh [asan|tsan]...   (default: asan tsan). Env: JOBS (default nproc).
# Debian's libtbb is not built with -fsanitize=thread, so TSan could not see TBB's own
# synchronization; the TSan build therefore schedules tiles on std::threads
# (PAR2D_STD_THREADS, switched on by PAR2D_SANITIZE=thread), and runs with no suppressions.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
JOBS=${JOBS:-$(nproc)}
STEPS=("$@")
[ ${#STEPS[@]} -eq 0 ] && STEPS=(asan tsan)

stamp() { date +%s; }
# -g1 (line tables, no variables): enough for the sanitizers' stack traces, and GCC skips its
# variable tracking, which on the always-inlined tile kernels runs out of its limit and starts
# over (it made the ASan build 17 minutes).
DEBUG_FLAGS=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")

run_asan() {
  local t0; t0=$(stamp)
  # Built with Debian's clang, warnings as errors: this is also the gate that everything
  # (library, CLI, tools, tests, benchmarks) compiles cleanly with clang, and clang builds
  # this configuration in about a third of GCC's time (measured: ~270 s against 749 s on
  # 2 cores). The user's test command and the long tier run the GCC build.
  # Kernel files at -O2 like the rest: a sanitizer build leaves their inlining to the compiler
  # (PAR2D_KERNEL_INLINE_HINTS, see CMakeLists.txt), which is what made them take minutes here.
  CC=${CC_CLANG:-clang-14} CXX=${CXX_CLANG:-clang++-14} \
    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "${DEBUG_FLAGS[@]}" -DPAR2D_SANITIZE=address,undefined \
          -DCMAKE_CXX_FLAGS=-Werror -DPAR2D_KERNEL_OPTIMIZATION=-O2 -DPAR2D_BUILD_BENCH=ON -DPAR2D_BUILD_FUZZ=OFF >/dev/null
  cmake --build build-asan -j"$JOBS"
  local t1; t1=$(stamp)
  # The suite's default tier once (its SIMD tests compare every ISA with the scalar reference
  # themselves, so each kernel instantiation runs in every ISA); the per-ISA re-runs of the
  # automatic backend and the long tier add nothing under a sanitizer but time.
  # par2d_tests, most of the time, runs one case per process on every core (sharded.sh), from
  # its ctest working directory; ctest runs the other entries (C API, install, embedding).
  # detect_leaks: LeakSanitizer must be clean too (it is on by default on x86-64 Linux; say so).
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # Left out here: the heaviest numeric sweeps of the default tier (the largest random scenes
  # and example levels, compared per ISA with the scalar reference and unculled renders). They
  # run the kernel, culling and cell-list code that smaller cases of the same files run under
  # the sanitizers too, only on more pixels; under ASan they took over half of this step (the
  # model-kernel sweep alone over 10 minutes on 2 cores; without the first six below the
  # tests took 551 s, the next five are the largest native sweeps after them; the light-layer
  # cache's 500 frames, minutes here, have a 60-frame twin that runs). The last four (measured
  # 80 to 124 s each under ASan, a third of what was left) render large views of dense fields
  # through culling paths the other culling, reach and fill cases here run on fewer pixels.
  # They still run natively in the user's test command (and their larger versions in the long tier).
  local heavy='render writes every pixel of its view: NaN-filled*,rubble (1.5-4 px occluders*,light reach: points beyond a sector*,culled renders equal unculled ones and the scalar reference inside rings*,cell lists: game-model scenes with every term on small occluders*,rubble with many lights per block*,the lighting-model examples*,culling is exact in a dense field*,small occluders and small lights*,huge slanted segments*,culling is exact with up to 1000 occluders*,scalar matches ray casting on random scenes with every lighting-model term,cell lists: small occluders and lights (1.5-5 px)*,huge shapes whose boundary passes*,huge circles through the view*,light-layer cache: 500 random*'
  (cd build-asan/tests && JOBS="$JOBS" "$ROOT/tools/ci/sharded.sh" ./par2d_tests --test-suite-exclude=long \
     --test-case-exclude="$heavy")
  ctest --test-dir build-asan --output-on-failure -j"$JOBS" -E '^par2d_test'
  unset ASAN_OPTIONS UBSAN_OPTIONS
  echo "sanitizers.sh: asan+ubsan build $((t1 - t0)) s, tests $(( $(stamp) - t1 )) s"
}

run_tsan() {
  local t0; t0=$(stamp)
  # The CLI and the embed example are not threaded beyond what the library does: skip the tools.
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo "${DEBUG_FLAGS[@]}" -DPAR2D_SANITIZE=thread \
        -DPAR2D_BUILD_BENCH=OFF -DPAR2D_BUILD_TOOLS=OFF -DPAR2D_BUILD_FUZZ=OFF >/dev/null
  cmake --build build-tsan -j"$JOBS" --target par2d_tests
  local t1; t1=$(stamp)
  # Races live in what threads share: the scheduler, per-thread scratch, the Renderer's world
  # and caches. The selection renders through every kernel shape (shape-major, cells, the
  # lighting model, culling proofs, stores, raycast and scalar) with several threads, and every
  # threading mode; the numeric sweeps beyond it run the same threaded code on more scenes
  # (under ASan and natively), which TSan would only repeat at ~8x the cost.
  TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" JOBS="$JOBS" \
    tools/ci/sharded.sh ./build-tsan/tests/par2d_tests --test-suite-exclude=long \
      -tc='*thread*,*Renderer*,*SIMD matches scalar*,*raycast backend*,*culled renders equal*,*every pixel format*,*model SIMD*,*cell lists: small*,*culling is exact in a dense*,*contact*' \
      --test-case-exclude='light-layer cache: 500 random*'
  echo "sanitizers.sh: tsan build $((t1 - t0)) s, tests $(( $(stamp) - t1 )) s"
}

for step in "${STEPS[@]}"; do
  case "$step" in
    asan) run_asan ;;
    tsan) run_tsan ;;
    *) echo "sanitizers.sh: unknown step '$step' (asan|tsan)" >&2; exit 2 ;;
  esac
done
