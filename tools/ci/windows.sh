#!/usr/bin/env bash
# CI: cross-builds par2d for 64-bit Windows with Debian's MinGW-w64 (the DLL with the C API,
# tiles on std::threads since there is no TBB for it) and the C example against that DLL, runs
# the example under wine, and compares its image with the same example built natively (TBB),
# within the contract's accuracy bounds (docs/contract.md section 5). See docs/platforms.md.
#
# Usage: tools/ci/windows.sh            (installs what it needs with apt-get; run as root)
# Env:   JOBS (default 2), BUILD (default build-mingw, the preset's directory), NATIVE (default
#        build: the native build whose libpar2d.so and par2d_image_diff are used; configured
#        and built here when it has none).
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=${JOBS:-2}
BUILD=${BUILD:-build-mingw}
NATIVE=${NATIVE:-build}

stamp() { date +%s; }
t0=$(stamp)
apt-get update
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
  g++-mingw-w64-x86-64-posix wine64 cmake pkg-config libxsimd-dev nlohmann-json3-dev libstb-dev \
  build-essential libtbb-dev libcli11-dev
t1=$(stamp)

# The DLL only (no tools, tests or benchmarks: the preset), then the C example against its
# import library, the DLL copied beside the .exe where Windows looks for it.
cmake --preset x86_64-w64-mingw32 -B "$BUILD" >/dev/null
cmake --build "$BUILD" -j"$JOBS" --target par2d_shared
out=$BUILD/example
mkdir -p "$out"
cp "$BUILD/src/libpar2d.dll" "$out/"
x86_64-w64-mingw32-gcc-posix -std=c99 -O2 -Iinclude examples/embed_c/game_loop.c "$BUILD/src/libpar2d.dll.a" \
  -o "$out/game_loop.exe"
t2=$(stamp)

fail() { echo "windows.sh: $*" >&2; exit 1; }
# The DLL exports every function par2d.h declares (dllexport), and it and the program need
# only Windows' own DLLs (the GCC runtime is linked in statically: the toolchain file).
dump=$(x86_64-w64-mingw32-objdump -p "$out/libpar2d.dll")
declared=$(grep -oE '^PAR2D_C_API [^(]*\(' include/par2d/par2d.h | grep -oE 'par2d_[a-z0-9_]+\($' | tr -d '(' | sort)
exported=$(sed -n '/\[Ordinal\/Name Pointer\] Table/,/^$/p' <<<"$dump" | awk '/^[[:space:]]*\[ *[0-9]+\]/ {print $NF}' | sort)
[[ -n $declared && $declared == "$exported" ]] ||
  fail "libpar2d.dll exports $(wc -w <<<"$exported") functions, par2d.h declares $(wc -w <<<"$declared"): $(comm -3 <(echo "$declared") <(echo "$exported") | tr '\n' ' ')"
for binary in "$out/libpar2d.dll" "$out/game_loop.exe"; do
  imports=$(x86_64-w64-mingw32-objdump -p "$binary" | awk '/DLL Name:/ {print $3}' | grep -vixE 'kernel32.dll|msvcrt.dll|libpar2d.dll' || true)
  [[ -z $imports ]] || fail "$binary needs DLLs Windows does not have: $imports"
done
echo "windows.sh: libpar2d.dll exports the $(wc -w <<<"$exported") functions of par2d.h"

# The same example natively, against the native shared library (TBB scheduler).
if [[ ! -f $NATIVE/CMakeCache.txt ]]; then
  cmake -S . -B "$NATIVE" -DPAR2D_BUILD_TESTS=OFF -DPAR2D_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$NATIVE" -j"$JOBS" --target par2d_shared par2d_image_diff
cc -std=c99 -O2 -Iinclude examples/embed_c/game_loop.c -L"$NATIVE/src" -lpar2d -Wl,-rpath,"$(cd "$NATIVE/src" && pwd)" -lm \
  -o "$out/game_loop_native"

# wine: a fresh prefix in a temporary folder, its messages off. A console program needs no X server.
# wineserver -k at the end stops this prefix's server, which would linger for a few seconds.
WINE=$(command -v wine || command -v wine64 || echo /usr/lib/wine/wine64)
WINESERVER=$(command -v wineserver || echo /usr/lib/wine/wineserver64)
WINEPREFIX=$(mktemp -d)
export WINEPREFIX WINEDEBUG=-all
trap '"$WINESERVER" -k 2>/dev/null || true; rm -rf "$WINEPREFIX"' EXIT
run_windows() { echo "+ PAR2D_ISA=${PAR2D_ISA:-} wine game_loop.exe $*"; (cd "$out" && "$WINE" game_loop.exe "$@"); }
run_native() { echo "+ PAR2D_ISA=${PAR2D_ISA:-} game_loop_native $*"; "$out/game_loop_native" "$@"; }
run_windows windows.pfm
for isa in scalar sse4 avx2; do PAR2D_ISA=$isa run_windows "windows_$isa.pfm"; done
run_native "$out/native.pfm"
PAR2D_ISA=scalar run_native "$out/native_scalar.pfm"
t3=$(stamp)

# The image: one light of intensity 4 whose largest channel is 1, so e_max = 4 (section 5).
# Windows' SIMD images (the ISA this CPU has, and SSE4.2 and AVX2 forced by PAR2D_ISA) against
# the native scalar one: the SIMD bound, 1e-4 * e_max. The two scalar images: each within 1e-6 * e_max of the exact value, so within
# 2e-6 * e_max of each other. Then the scheduler: the same kernels on the same CPU, tiles on
# std::threads against TBB, must give the same bytes (docs/architecture.md), which holds
# across the two C runtimes here because nothing in the frame rounds differently in them.
diff_tool=$NATIVE/tools/par2d_image_diff
echo "+ windows (default ISA) vs native scalar, tolerance 4e-4"
"$diff_tool" "$out/windows.pfm" "$out/native_scalar.pfm" --tolerance 4e-4
for isa in sse4 avx2; do
  echo "+ windows $isa vs native scalar, tolerance 4e-4"
  "$diff_tool" "$out/windows_$isa.pfm" "$out/native_scalar.pfm" --tolerance 4e-4
done
echo "+ windows scalar vs native scalar, tolerance 8e-6"
"$diff_tool" "$out/windows_scalar.pfm" "$out/native_scalar.pfm" --tolerance 8e-6
echo "+ windows (default ISA, std::threads) vs native (default ISA, TBB): identical"
"$diff_tool" "$out/windows.pfm" "$out/native.pfm" --tolerance 0
cmp "$out/windows.pfm" "$out/native.pfm" || fail "the std::thread and TBB images differ"
echo "windows.sh: install $((t1 - t0)) s, cross build $((t2 - t1)) s, native example and runs $((t3 - t2)) s, total $(($(stamp) - t0)) s"
