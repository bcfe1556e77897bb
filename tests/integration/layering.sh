#!/bin/bash
# layering.sh — the boundaries the architecture names: no service includes
# or links another service's code (scripts/check-layering over the tree, and
# the same check seeing an offence planted in a copy of a service), and no
# service binary carries another service's symbols (the same script given
# the build: nm, no mti_, bcis_, trk_, gd_, uavsim_, im_, gw_ or st_
# function of another service; and seeing one planted). TAP.
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

# A service may not include a header private to a module of common/.
mkdir -p "$TMP/tree2"
cp -r "$CGS_ROOT/common" "$CGS_ROOT/services" "$TMP/tree2/"
sed -i '1i #include "cgs_terrain_impl.h"' "$TMP/tree2/services/mtid/mti_radar.c"
"$CGS_ROOT/scripts/check-layering" "$TMP/tree2" >"$TMP/planted2.out" 2>&1
is "$?" 1 "and it refuses a service including common/'s private cgs_terrain_impl.h"
check "naming the file and the header" \
    grep -q '^services/mtid/mti_radar.c:1: includes "cgs_terrain_impl.h", private' "$TMP/planted2.out"

# Every service binary links its own code and common/ only.
"$CGS_ROOT/scripts/check-layering" "$CGS_ROOT" "$CGS_BUILD" >"$TMP/links.out" 2>&1
rc=$?
[ "$rc" -eq 0 ] || sed 's/^/#   /' "$TMP/links.out"
is "$rc" 0 "no service binary carries another service's functions"
# And that check can fail: a service binary built with another's function.
mkdir -p "$TMP/bad/bin"
for b in "$CGS_BUILD"/bin/*; do ln -s "$b" "$TMP/bad/bin/"; done
rm "$TMP/bad/bin/mtid"
printf 'int trk_planted (void) { return 1; }\nint main (void) { return trk_planted (); }\n' >"$TMP/planted.c"
cc -o "$TMP/bad/bin/mtid" "$TMP/planted.c"
"$CGS_ROOT/scripts/check-layering" "$CGS_ROOT" "$TMP/bad" >"$TMP/links-bad.out" 2>&1
is "$?" 1 "and it refuses a service binary holding another's function"
check "naming the binary and the function" grep -q "bin/mtid: defines trk_planted" "$TMP/links-bad.out"
finish
