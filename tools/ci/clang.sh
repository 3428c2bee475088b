#!/usr/bin/env bash
# CI: builds everything (library, CLI, tools, tests, benchmarks) with Debian's clang, warnings
# as errors, and runs the SIMD and ISA test cases of that build (the full suite runs with GCC).
# Usage: tools/ci/clang.sh   (installs clang with apt-get; run as root). Env: JOBS (default nproc).
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=${JOBS:-$(nproc)}
t0=$(date +%s)
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends clang
cmake --preset clang -DCMAKE_CXX_FLAGS=-Werror >/dev/null
cmake --build build-clang -j"$JOBS"
t1=$(date +%s)
./build-clang/tests/par2d_tests --test-case='*SIMD*,*simd*,*ISA*,*isa*,*thread*' --test-suite-exclude=long
echo "clang.sh: build $((t1 - t0)) s, tests $(( $(date +%s) - t1 )) s"
