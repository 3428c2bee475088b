#!/usr/bin/env bash
# Installs a par2d build into a temporary prefix, then builds and runs examples/embed against it
# as a standalone project (find_package(par2d) + par2d::par2d), as a user of the package would.
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
read -r -a pc_flags <<<"$(PKG_CONFIG_PATH=$pc_dir pkg-config --cflags --libs par2d)"
"${PAR2D_CC:-cc}" -std=c99 $extra_flags "$example_dir/../embed_c/game_loop.c" "${pc_flags[@]}" -lm -o "$work/game_loop_c" \
  >"$work/c_build.log" 2>&1 || { cat "$work/c_build.log"; exit 1; }
LD_LIBRARY_PATH="$(dirname "$(find "$work/prefix" -name 'libpar2d.so' | head -1)")" ${PAR2D_EMULATOR:-} "$work/game_loop_c"
