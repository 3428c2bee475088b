#!/usr/bin/env bash
# Installs a par2d build into a temporary prefix, then builds and runs examples/embed against it
# as a standalone project (find_package(par2d) + par2d::par2d), as a user of the package would;
# builds the C example with the README's pkg-config line (with its rpath) and runs it without
# LD_LIBRARY_PATH; imports the installed Python module from the prefix.
# Usage: install_test.sh CMAKE BUILD_DIR EXAMPLE_DIR [EXTRA_CXX_FLAGS]
# Env (cross builds): PAR2D_TOOLCHAIN_FILE for the consumer's configure, PAR2D_CC for the C
# example, PAR2D_EMULATOR to run them.
set -euo pipefail
cmake_cmd=$1 build_dir=$2 example_dir=$3 extra_flags=${4:-}
work=$(mktemp -d "${TMPDIR:-/tmp}/par2d-install-test.XXXXXX")
trap 'rm -rf "$work"' EXIT

"$cmake_cmd" --install "$build_dir" --prefix "$work/prefix" >"$work/install.log" ||
  { cat "$work/install.log"; exit 1; }
# The package must be usable without the source tree: nothing may point back into it.
if grep -rqs -- "$(cd "$example_dir/../.." && pwd)" "$work/prefix/lib"*/cmake/par2d; then
  echo "installed CMake package refers to the source tree" >&2
  exit 1
fi
"$cmake_cmd" -S "$example_dir" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="$extra_flags" \
  ${PAR2D_TOOLCHAIN_FILE:+-DCMAKE_TOOLCHAIN_FILE="$PAR2D_TOOLCHAIN_FILE"} \
  -DCMAKE_EXE_LINKER_FLAGS="$extra_flags" >"$work/configure.log" ||
  { cat "$work/configure.log"; exit 1; }
"$cmake_cmd" --build "$work/build" >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
${PAR2D_EMULATOR:-} "$work/build/par2d_embed"
${PAR2D_EMULATOR:-} "$work/build/par2d_game_loop"

# The C example through pkg-config, against the installed shared library (PAR2D_CC: the cross
# C compiler in cross builds).
pc_dir=$(dirname "$(find "$work/prefix" -name par2d.pc | head -1)")
[[ -f $pc_dir/par2d.pc ]] || { echo "par2d.pc was not installed" >&2; exit 1; }
[[ $(dirname "$(find "$work/prefix" -path '*/cmake/par2d/par2dConfig.cmake' | head -1)") == "$(dirname "$pc_dir")/cmake/par2d" ]] ||
  { echo "par2d.pc is not next to the CMake package" >&2; exit 1; }
# Built with the README's line, which records the library's folder in the binary (-Wl,-rpath):
# it must run from this non-system prefix with no LD_LIBRARY_PATH.
export PKG_CONFIG_PATH=$pc_dir
read -r -a pc_flags <<<"$(pkg-config --cflags --libs par2d)"
"${PAR2D_CC:-cc}" -std=c99 $extra_flags "$example_dir/../embed_c/game_loop.c" "${pc_flags[@]}" \
  -Wl,-rpath,"$(pkg-config --variable=libdir par2d)" -lm -o "$work/game_loop_c" \
  >"$work/c_build.log" 2>&1 || { cat "$work/c_build.log"; exit 1; }
env -u LD_LIBRARY_PATH ${PAR2D_EMULATOR:-} "$work/game_loop_c"

# The Python module, when this build has one: installed under the prefix (lib/python3.X/
# dist-packages or site-packages), importable from there alone and rendering.
cache=$build_dir/CMakeCache.txt
if grep -q '^PAR2D_BUILD_PYTHON:BOOL=ON' "$cache" 2>/dev/null; then
  # Python3_EXECUTABLE when the user set it, else what FindPython3 chose (its internal entry).
  python=$(sed -n 's/^_\{0,1\}Python3_EXECUTABLE:[A-Z]*=//p' "$cache" | head -n 1)
  [[ -n $python ]] || { echo "no Python3_EXECUTABLE in $cache" >&2; exit 1; }
  site=$(sed -n 's/^PAR2D_PYTHON_INSTALL_DIR:[A-Z]*=//p' "$cache")
  [[ $site == /* ]] || site=$work/prefix/$site
  compgen -G "$site/par2d*.so" >/dev/null || { echo "the Python module was not installed in $site" >&2; exit 1; }
  (cd "$work" && PYTHONPATH=$site "$python" -s -c '
import os, sys
import par2d
assert os.path.dirname(par2d.__file__) == sys.argv[1], par2d.__file__
image = par2d.render({"width": 8, "height": 4, "lights": [{"circle": {"center": [2, 2], "radius": 1}}]})
assert image.shape == (4, 8, 3) and image.max() > 0
print("installed Python module:", par2d.__file__)
' "$site")
fi
