#!/usr/bin/env bash
# The per-ISA units share no weak symbol with any other unit of the library
# (kernel/src/simd/isa_namespace.hpp): if two units compiled with different instruction-set
# flags emit the same inline function, the linker keeps one copy for every caller, possibly
# AVX-512 code for a caller on a CPU without it.
#   isa_symbols.sh OBJECT...   (the library's object files, per-ISA units named isa_*)
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: $0 OBJECT..." >&2; exit 2; }
isa_units=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for o in "$@"; do
  name=$(basename "$o")
  # W, V: weak symbols (inline functions, template instantiations); u: unique globals.
  nm --defined-only "$o" | awk '$2 ~ /^[WVu]$/ {print $3}' | sort -u >"$tmp/$name.weak"
  case "$name" in isa_*) isa_units=$((isa_units + 1)) ;; esac
done
[ "$isa_units" -gt 0 ] || { echo "no per-ISA unit among the objects" >&2; exit 1; }
# Allowed, because no instruction-set flag can change them: the personality routine's
# reference (data the unwinder reads), and, in unoptimised builds only, two accessors of
# std::initializer_list that xsimd's batch constants use and the conversion of xsimd's SSE2
# register wrapper to its __m128 member (plain loads and stores of a pointer and a size or of
# one register; the builder's 4-lane boxes share it with the SSE4.2 unit).
allowed='^(DW\.ref\.__gxx_personality_v0|_ZNKSt16initializer_listIjE(5begin|4size)Ev|_ZNK5xsimd5types13simd_registerIfNS_4sse2EEcvDv4_fEv)$'
status=0
for isa in "$tmp"/isa_*.weak; do
  for other in "$tmp"/*.weak; do
    [ "$other" = "$isa" ] && continue
    shared=$(comm -12 "$isa" "$other" | grep -Ev "$allowed" || true)
    if [ -n "$shared" ]; then
      echo "$(basename "$isa" .weak) and $(basename "$other" .weak) both define:" >&2
      echo "$shared" | c++filt | sed 's/^/  /' >&2
      status=1
    fi
  done
done
[ "$status" -eq 0 ] && echo "$isa_units per-ISA units checked against $# objects: no weak symbol shared"
exit "$status"
