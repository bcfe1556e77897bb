#!/bin/bash
# layering.sh — the boundaries the architecture names: no service includes
# or links another service's code (scripts/check-layering over the tree, and
# the same check seeing an offence planted in a copy of a service), and no
# service binary carries another service's symbols (nm: no mti_, bcis_,
# trk_, gd_, uavsim_, im_, gw_ or st_ function of another service). TAP.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

"$CGS_ROOT/scripts/check-layering" "$CGS_ROOT" >"$TMP/check.out" 2>&1
rc=$?
[ "$rc" -eq 0 ] || sed 's/^/#   /' "$TMP/check.out"
is "$rc" 0 "scripts/check-layering: no service includes another service's header"

# The check can fail: a copy of the tree's services with one cross include.
mkdir -p "$TMP/tree"
cp -r "$CGS_ROOT/common" "$CGS_ROOT/services" "$TMP/tree/"
sed -i '1i #include "trk_tracker.h"' "$TMP/tree/services/guidanced/gd_adapter.c"
"$CGS_ROOT/scripts/check-layering" "$TMP/tree" >"$TMP/planted.out" 2>&1
is "$?" 1 "and it refuses a cross-service include planted in a copy"
check "naming the file, the line and the owner" \
    grep -q '^services/guidanced/gd_adapter.c:1: includes "trk_tracker.h" of services/trackerd' "$TMP/planted.out"

# Every service binary links its own code and common/ only.
declare -A PREFIX=([mtid]=mti_ [bcisd]=bcis_ [trackerd]=trk_ [guidanced]=gd_ [uavsim]=uavsim_
                   [imagerd]=im_ [gateway]=gw_ [stationd]=st_)
for svc in "${!PREFIX[@]}"; do
    bin=$CGS_BUILD/bin/$svc
    [ -x "$bin" ] || { check "$svc is built" false; continue; }
    others=()
    for o in "${!PREFIX[@]}"; do [ "$o" = "$svc" ] || others+=("${PREFIX[$o]}"); done
    pattern=$(IFS='|'; echo "${others[*]}")
    nm --defined-only "$bin" | awk '$2 ~ /^[Tt]$/ { print $3 }' | grep -E "^($pattern)" >"$TMP/$svc.foreign"
    check "$svc carries no other service's functions" test ! -s "$TMP/$svc.foreign"
    [ -s "$TMP/$svc.foreign" ] && head -5 "$TMP/$svc.foreign" | sed 's/^/#   /'
done
finish
