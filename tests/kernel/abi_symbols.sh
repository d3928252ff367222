#!/usr/bin/env bash
# libsphray.so exports its public API and nothing else: the sphray_ functions sphray.h declares
# (all of them) and C++ symbols of namespace sphray outside its internal namespaces. Anything
# else (the standard library's, xsimd's or oneTBB's template instantiations, the per-ISA
# kernels, the C API's helpers) would become part of the ABI by accident. And the other way
# round: no function of the public namespace is left hidden in the library's objects (a public
# declaration without SPHRAY_API, which static users would never notice).
#   abi_symbols.sh LIBRARY HEADER OBJECT...   (libsphray.so, kernel/include/sphray/sphray.h,
#                                              the library's object files)
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 LIBRARY HEADER OBJECT..." >&2; exit 2; }
lib=$1
header=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

nm -D --defined-only "$lib" | awk '{print $NF}' | sort -u >"$tmp/all"
[ -s "$tmp/all" ] || { echo "no exported symbol in $lib" >&2; exit 1; }
grep -v '^_Z' "$tmp/all" >"$tmp/c" || true
grep '^_Z' "$tmp/all" | c++filt >"$tmp/cpp" || true
# The functions the header declares: "SPHRAY_API <type> sphray_name(".
grep -o 'SPHRAY_API[^(]*\bsphray_[a-z0-9_]*(' "$header" | grep -o 'sphray_[a-z0-9_]*' | sort -u \
  >"$tmp/declared"
[ -s "$tmp/declared" ] || { echo "no SPHRAY_API function found in $header" >&2; exit 1; }

status=0
report() {
  echo "$1" >&2
  sed 's/^/  /' "$2" >&2
  status=1
}
comm -23 "$tmp/c" "$tmp/declared" >"$tmp/c_extra"
[ -s "$tmp/c_extra" ] && report "exported, but not a function of $(basename "$header"):" "$tmp/c_extra"
comm -13 "$tmp/c" "$tmp/declared" >"$tmp/c_missing"
[ -s "$tmp/c_missing" ] && report "declared in $(basename "$header") but not exported:" "$tmp/c_missing"
internal='^sphray::(detail|c_api|sse4_2|avx2|avx512|neon)::'
{ grep -Ev '^sphray::' "$tmp/cpp" || true; grep -E "$internal" "$tmp/cpp" || true; } >"$tmp/cpp_extra"
[ -s "$tmp/cpp_extra" ] && report "C++ symbols outside the public sphray:: API:" "$tmp/cpp_extra"
for o in "$@"; do
  readelf -sW "$o" | awk '$5 == "GLOBAL" && $6 == "HIDDEN" && $7 != "UND" {print $8}'
done | sort -u | c++filt | { grep -E '^sphray::' || true; } | { grep -Ev "$internal" || true; } \
  >"$tmp/hidden_public"
[ -s "$tmp/hidden_public" ] &&
  report "public sphray:: functions not exported (SPHRAY_API missing):" "$tmp/hidden_public"

echo "$(wc -l <"$tmp/all") exported symbols: $(wc -l <"$tmp/c") sphray_ C functions" \
     "($(wc -l <"$tmp/declared") declared in $(basename "$header")), $(wc -l <"$tmp/cpp") sphray:: C++"
exit "$status"
