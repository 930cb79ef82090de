#!/usr/bin/env bash
# Build step of pt_add_isa_objects (cmake/isa_levels.cmake):
#   localize_isa_objects.sh LD OBJCOPY NM NAMESPACE OUT OBJECT...
# Links the objects of one instruction-set level into one relocatable object
# OUT whose only global symbols are those of namespace pt::NAMESPACE (the
# level's entry tables). Every other symbol, inline functions and template
# instances included, becomes local, and COMDAT groups are dissolved, so that
# the final link keeps this level's copies for this level's code alone.
# Fails when the objects define writable data with external linkage outside
# the namespace (function-local statics of inline functions, template static
# members): localizing would give each level its own copy of shared state.
# (DW.ref.* are the exception tables' pointers to the personality routine,
# constants after relocation; __odr_asan.* are AddressSanitizer's one-byte
# indicators for its ODR check.)
set -euo pipefail
ld=$1 objcopy=$2 nm=$3 namespace=$4 out=$5
shift 5
keep="_ZN2pt${#namespace}${namespace}"  # mangled prefix of pt::NAMESPACE::
partial="$out.partial.o"
"$ld" -r -o "$partial" "$@"

shared_state=$("$nm" --defined-only -f sysv "$partial" | awk -F'|' -v keep="$keep" '
  { name = $1; cls = $3; section = $7; gsub(/ /, "", name); gsub(/ /, "", cls); gsub(/ /, "", section) }
  cls ~ /^[BDGSVu]$/ && section ~ /^\.(data|bss|tdata|tbss)/ && section !~ /^\.data\.rel\.ro/ &&
  index(name, keep) != 1 && name !~ /^(DW\.ref|__odr_asan)\./ { print name }')
if [ -n "$shared_state" ]; then
  echo "localize_isa_objects: $namespace defines writable data shared with other levels:" >&2
  echo "$shared_state" >&2
  exit 1
fi

"$objcopy" --wildcard --keep-global-symbol="${keep}*" --remove-section=.group "$partial" "$out"
rm -f "$partial"
