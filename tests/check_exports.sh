#!/usr/bin/env bash
# The shared library exports the public API and nothing of the internals, under a versioned SONAME.
# Usage: check_exports.sh LIBPAR2D_SO
set -euo pipefail
lib=$1
symbols=$(nm -D --defined-only "$lib" | c++filt)
fail=0
for wanted in 'par2d_render' 'par2d_renderer_create' 'par2d_version' 'par2d::Renderer::render(' \
              'par2d::render(par2d::Scene const&' 'par2d::load_scene_file(' 'par2d::Status'; do
  grep -qF -- "$wanted" <<<"$symbols" || { echo "not exported: $wanted" >&2; fail=1; }
done
# Every function the public headers declare is exported (one declared but not exported would
# only fail when a program first links or calls it): C functions by name, C++ ones by qualified
# name and overload count, read from the headers themselves.
include_dir=$(dirname "$0")/../include/par2d
python3 "$(dirname "$0")/public_functions.py" "$include_dir" <(printf '%s\n' "$symbols") || fail=1
if leaked=$(grep -E 'par2d::(detail|simd|bench|test)::' <<<"$symbols"); then
  echo "internal symbols exported:" >&2
  head -20 <<<"$leaked" >&2
  fail=1
fi
# The SONAME names the ABI par2d.h declares (its PAR2D_ABI_MAJOR.PAR2D_ABI_MINOR).
soname=$(objdump -p "$lib" | awk '/SONAME/ {print $2}')
abi=$(awk '$1 == "#define" && $2 == "PAR2D_ABI_MAJOR" {major = $3} $1 == "#define" && $2 == "PAR2D_ABI_MINOR" {minor = $3}
           END {if (major != "" && minor != "") print major "." minor}' "$include_dir/par2d.h")
[[ -n $abi && $soname == "libpar2d.so.$abi" ]] ||
  { echo "SONAME '$soname' is not par2d.h's ABI: libpar2d.so.${abi:-?}" >&2; fail=1; }
echo "exported symbols: $(wc -l <<<"$symbols"), SONAME $soname"
exit $fail
