#!/usr/bin/env bash
# CI: the LÖVE 11 example (examples/love: par2d through LuaJIT's FFI) under Xvfb with Mesa's
# software GL for 30 frames, its last frame as shown compared with `par2d render` of the
# world it saved, multiplied over its sprite layer on the CPU (examples/love/check_love.py),
# and its FFI declarations held to par2d.h. See docs/embedding.md.
#
# Usage: tools/ci/love.sh            (installs what it needs with apt-get; run as root)
# Env:   JOBS (default 2), NATIVE (default build: the native build whose libpar2d.so and
#        par2d CLI are used; configured and built here when it has none), PYTHON (default
#        /usr/bin/python3, the one Debian's python3-numpy and python3-pil belong to).
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=${JOBS:-2}
NATIVE=${NATIVE:-build}
PYTHON=${PYTHON:-/usr/bin/python3}

stamp() { date +%s; }
t0=$(stamp)
apt-get update
# love 11.4 (LuaJIT); xauth for xvfb-run. Without recommends: love's would add systemd.
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends love xvfb xauth python3-numpy python3-pil \
  build-essential cmake pkg-config libxsimd-dev libtbb-dev libstb-dev nlohmann-json3-dev libcli11-dev
t1=$(stamp)

if [[ ! -f $NATIVE/CMakeCache.txt ]]; then
  cmake -S . -B "$NATIVE" -DPAR2D_BUILD_TESTS=OFF -DPAR2D_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$NATIVE" -j"$JOBS" --target par2d_shared par2d_cli
t2=$(stamp)

echo "+ love $(love --version)"
xvfb-run -a -s "-screen 0 800x600x24" \
  "$PYTHON" examples/love/check_love.py love "$NATIVE/tools/par2d" "$NATIVE/src/libpar2d.so"
echo "love.sh: install $((t1 - t0)) s, native build $((t2 - t1)) s, example and check $(($(stamp) - t2)) s, total $(($(stamp) - t0)) s"
