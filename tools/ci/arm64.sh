#!/usr/bin/env bash
# CI: cross-builds par2d for ARM64 (aarch64) with Debian's cross toolchain and :arm64 packages,
# then runs the test suite's numeric core under qemu-user: the NEON kernel against the scalar
# reference, closed forms, thread identity, culling exactness, and ISA selection.
#
# Usage: tools/ci/arm64.sh            (installs what it needs with apt-get; run as root)
# Env:   JOBS (default nproc), BUILD (default build-arm64, the preset's directory).
#
# Under emulation the tests run about 10-15x slower than natively (see docs/arm64.md, "Building for
# ARM64"), so the run is an explicit selection of doctest test cases (FILTER and SLOW below),
# never a test that skips itself; the native x86 suite covers the rest (scene parsing, proofs).
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=${JOBS:-$(nproc)}
BUILD=${BUILD:-build-arm64}

stamp() { date +%s; }
t0=$(stamp)
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  dpkg --add-architecture arm64
fi
apt-get update
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
  crossbuild-essential-arm64 qemu-user cmake pkg-config file \
  libxsimd-dev:arm64 libtbb-dev:arm64 libstb-dev:arm64 libbenchmark-dev:arm64 \
  doctest-dev nlohmann-json3-dev libcli11-dev
t1=$(stamp)

# Library, CLI, tests and benchmarks, all for aarch64 (the preset's toolchain file).
cmake --preset aarch64-linux-gnu -B "$BUILD" >/dev/null
# What runs emulated below: the suite and the CLI (the benchmarks and other tools are not run here).
cmake --build "$BUILD" -j"$JOBS" --target par2d_tests par2d_cli
t2=$(stamp)

# A target binary must really be aarch64, not a host binary from a misconfigured build.
file -L "$BUILD/tests/par2d_tests" | grep -q "ARM aarch64" || {
  echo "arm64.sh: $BUILD/tests/par2d_tests is not an aarch64 executable" >&2
  exit 1
}
# No -L: the loader must be libc6:arm64's (see cmake/toolchains/aarch64-linux-gnu.cmake).
QEMU=(qemu-aarch64)
run() { echo "+ PAR2D_ISA=${PAR2D_ISA:-} ${QEMU[*]} $*"; "${QEMU[@]}" "$@"; }

# The numeric core, with the default ISA (NEON): every SIMD test compares each ISA this CPU
# has (here neon64) against the scalar reference within the contract's bounds (docs/contract.md section 5).
# Left out (named, not skipped): the two culling tests over 1000-occluder fields, ~270 s
# emulated; culling's SIMD exactness is still checked here by "culling never changes the SIMD
# image beyond docs/contract.md bounds", and those two run in the native x86 suite.
FILTER='*SIMD*,*simd*,*ISA*,*isa*,*culling*,*closed*,*circle light*,*segment light*,*thread*,*identical*,*edge*,*kernel*,*atan2*,*union*'
# The lighting-model examples at full size (scalar renders of 7 scenes, ~200 s emulated) run
# natively too; the model kernel's NEON exactness is checked here by the "model SIMD" cases.
# So do the small-shape field (15 s natively) and the huge-shape sweeps over 13 extents (13 s):
# each ten minutes or more emulated; NEON's exactness on them is the same kernel's, checked on
# the random-scene and far-shape cases here.
# The light-layer cache's 500 random frames (a fresh full render per frame: past 400 s
# emulated) run natively; its 60-frame budget-limited case runs here.
# The closed-stdout case spawns the CLI with descriptor 1 closed; under qemu-user the emulator,
# not the CLI, owns the process's descriptors at start-up, so it does not test the CLI there
# (it runs natively in every x86-64 build).
# The comb lights against the ray caster (171 s emulated, mostly the ray caster in double) and
# the huge shapes 2^6 to 2^40 pixels away (90 s) run natively; NEON meets comb-like and far
# shapes in the random-scene, concave-light and far-shape cases here.
SLOW='with standard output closed*,culling is exact with up to 1000 occluders*,culling is exact in a dense field*,the lighting-model examples*,small occluders and small lights*,huge slanted segments*,huge circles through the view*,light-layer cache: 500 random*,comb lights along either axis*,huge shapes whose boundary passes*'
unset PAR2D_ISA
# One case per emulated process, on every core (sharded.sh).
echo "+ sharded: ${QEMU[*]} $BUILD/tests/par2d_tests --test-case=... --test-case-exclude=..."
SHARD_WRAPPER="${QEMU[*]}" JOBS="$JOBS" tools/ci/sharded.sh "$BUILD/tests/par2d_tests" \
  --test-case="$FILTER" --test-case-exclude="$SLOW" --test-suite-exclude=long
# ISA selection with PAR2D_ISA forced to each level (as ctest does natively): scalar must be
# honoured, neon64 kept, and x86 names fall back to the best level the CPU has.
for isa in scalar neon64 avx2; do
  PAR2D_ISA=$isa run "$BUILD/tests/par2d_tests" --test-case='PAR2D_ISA*'
done
# The CLI end to end on an example scene.
run "$BUILD/tools/par2d" info
run "$BUILD/tools/par2d" bench examples/dungeon.json --frames 1 --threads 2 --width 320 --height 180
echo "arm64.sh: install $((t1 - t0)) s, cross build $((t2 - t1)) s, emulated tests $(( $(stamp) - t2 )) s"
