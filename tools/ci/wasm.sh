#!/usr/bin/env bash
# CI: builds par2d for WebAssembly with Debian's emscripten (the SSE4.2 kernel on SIMD128, and a
# scalar-only module with WASM_BENCH=1), then runs under node: every example against the native
# build's renders (web/test/examples.mjs), the playground in headless Chromium
# (web/test/playground.mjs), and with WASM_BENCH=1 the paper.json frame-time targets
# (web/test/bench.mjs). See docs/platforms.md, "WebAssembly and the playground".
#
# Usage: tools/ci/wasm.sh            (installs what it needs with apt-get; run as root)
# Env:   WASM_BENCH=1: also the scalar-only module and the frame-time targets (bench.mjs),
#        JOBS (default 2), NATIVE (default build: the native build whose par2d CLI and
#        par2d_image_diff are used; configured and built here when it has none),
#        BENCH_JSON (optional: where bench.mjs writes its numbers).
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=${JOBS:-2}
NATIVE=${NATIVE:-build}

stamp() { date +%s; }
t0=$(stamp)
apt-get update
# emscripten (3.1.6) and its JavaScript optimizer's parser (node-acorn); chromium for the
# playground; the native build's packages for the CLI the images are compared with.
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
  emscripten node-acorn chromium cmake pkg-config libxsimd-dev nlohmann-json3-dev libstb-dev \
  build-essential libtbb-dev libcli11-dev
t1=$(stamp)

# Debian's emscripten needs node; a node from elsewhere (NodeSource's) does not search Debian's
# /usr/share/nodejs, where acorn is: the toolchain file passes NODE_PATH to emcc's link step.
command -v node >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends nodejs

cmake --preset wasm >/dev/null
cmake --build --preset wasm -j"$JOBS"
if [[ ${WASM_BENCH:-0} == 1 ]]; then
  cmake --preset wasm-scalar >/dev/null
  cmake --build --preset wasm-scalar -j"$JOBS"
fi
if [[ ! -f $NATIVE/CMakeCache.txt ]]; then
  cmake -S . -B "$NATIVE" -DPAR2D_BUILD_TESTS=OFF -DPAR2D_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$NATIVE" -j"$JOBS" --target par2d_cli par2d_image_diff
t2=$(stamp)

# The module must not need threads (no SharedArrayBuffer, so no cross-origin isolation headers).
if grep -q 'SharedArrayBuffer' build-wasm/web/par2d_core.mjs; then
  echo "wasm.sh: the module uses SharedArrayBuffer (a pthreads build)" >&2
  exit 1
fi

node web/test/examples.mjs build-wasm/web/site "$NATIVE"
t3=$(stamp)
# The frame-time targets need the scalar-only module, a second build of the library (about as
# long as the first): WASM_BENCH=1 builds it and runs them.
if [[ ${WASM_BENCH:-0} == 1 ]]; then
  node web/test/bench.mjs build-wasm/web/site build-wasm-scalar/web/site "$NATIVE" --frames 20 ${BENCH_JSON:+--json "$BENCH_JSON"}
fi
t4=$(stamp)
node web/test/playground.mjs build-wasm/web/site "$NATIVE"
t5=$(stamp)
echo "wasm.sh: apt $((t1 - t0)) s, builds $((t2 - t1)) s, examples $((t3 - t2)) s, bench $((t4 - t3)) s, playground $((t5 - t4)) s"
