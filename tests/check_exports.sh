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
# Every function par2d.h declares is exported (a declared but undefined one would only fail
# when a C program first calls it).
header=$(dirname "$0")/../include/par2d/par2d.h
declared=$(tr '\n' ' ' <"$header" | grep -oE 'PAR2D_C_API[^;(]*\bpar2d_[a-z0-9_]+\(' | grep -oE 'par2d_[a-z0-9_]+\($' | tr -d '(' | sort -u)
[[ $(wc -l <<<"$declared") -ge 40 ]] || { echo "could not read the C declarations of $header" >&2; fail=1; }
for name in $declared; do
  grep -qx -- "$name" <<<"$(awk '{print $NF}' <<<"$symbols")" || { echo "declared in par2d.h, not exported: $name" >&2; fail=1; }
done
if leaked=$(grep -E 'par2d::(detail|simd|bench|test)::' <<<"$symbols"); then
  echo "internal symbols exported:" >&2
  head -20 <<<"$leaked" >&2
  fail=1
fi
soname=$(objdump -p "$lib" | awk '/SONAME/ {print $2}')
[[ $soname =~ ^libpar2d\.so\.[0-9]+\.[0-9]+$ ]] || { echo "unexpected SONAME: '$soname'" >&2; fail=1; }
echo "exported symbols: $(wc -l <<<"$symbols"), SONAME $soname"
exit $fail
