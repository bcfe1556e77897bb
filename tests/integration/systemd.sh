#!/bin/bash
# systemd.sh — the units of deploy/systemd/ as `make install` writes them:
# `systemd-analyze verify` prints nothing on stderr for an instance of every
# unit (and does print for a unit whose program is missing, so the check can
# fail), `systemd-analyze security` scores every service 2.5 or better, the
# installed lab exercise names the installed parameter files and passes
# --check, its gateway's parameters (/etc/mscgs/gateway.ini) broadcast DIS on
# the interface they name, and an existing exercise file or gateway
# parameter file is never overwritten. (A real
# systemd running the units is a separate, opt-in target.) TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

command -v systemd-analyze >/dev/null || bail "no systemd-analyze"
ROOT=$TMP/root
# The build under test, installed as built (install-built builds nothing).
SAN=0
ldd "$CGS_BUILD/bin/mtid" 2>/dev/null | grep -q libasan && SAN=1
make -s -C "$CGS_ROOT" install-built O="$CGS_BUILD" SAN=$SAN PREFIX="$ROOT/usr/local" SYSCONFDIR="$ROOT/etc" \
    >"$TMP/install.out" 2>&1 || { cat "$TMP/install.out"; bail "make install failed"; }
UNITS=$ROOT/usr/local/lib/systemd/system
check "make install puts the units, the binaries, the page and the exercise in place" bash -c \
    "[ -f '$UNITS/mscgs.target' ] && [ -x '$ROOT/usr/local/bin/mtid' ] && [ -f '$ROOT/usr/local/share/mscgs/web/vendor/ol.js' ] && [ -f '$ROOT/usr/local/share/mscgs/web/js/main.js' ] && [ -f '$ROOT/etc/mscgs/exercise.ini' ]"

V=$TMP/verify
mkdir -p "$V"
cp "$UNITS/mscgs.target" "$V/"
for p in uavsim mtid bcisd trackerd guidanced imagerd gateway stationd; do
    check "$p@.service is installed" test -f "$UNITS/$p@.service"
    cp "$UNITS/$p@.service" "$V/$p@$p.test.service"
    (cd "$V" && systemd-analyze verify "./$p@$p.test.service" ./mscgs.target) >"$TMP/$p.verify.out" 2>"$TMP/$p.verify.err"
    check "systemd-analyze verify prints nothing on stderr for $p@$p.test.service" test ! -s "$TMP/$p.verify.err"
    score=$(cd "$V" && systemd-analyze security --offline=yes "./$p@$p.test.service" 2>&1 |
        sed -n 's/.*Overall exposure level for [^:]*: \([0-9.]*\).*/\1/p')
    check "systemd-analyze security scores $p ${score:-?} (2.5 or better)" \
        awk -v s="${score:-99}" 'BEGIN { exit !(s <= 2.5) }'
done
sed "s|$ROOT/usr/local/bin|$TMP/nowhere|" "$UNITS/mtid@.service" >"$V/mtid@missing.service"
(cd "$V" && systemd-analyze verify ./mtid@missing.service) >/dev/null 2>"$TMP/missing.err"
check "verify does report a unit whose program is missing" grep -q 'is not executable' "$TMP/missing.err"
check "the units start the installed programs with the installed exercise" \
    grep -q "^ExecStart=$ROOT/usr/local/bin/mtid --exercise $ROOT/etc/mscgs/exercise.ini --instance %i" "$UNITS/mtid@.service"

EX=$ROOT/etc/mscgs/exercise.ini
check "the installed exercise uses tcp endpoints only" bash -c "! grep -qE '^(publish|command) = ipc://' '$EX' && grep -qE '^publish = tcp://' '$EX'"
check "and names the installed parameter files" grep -q "params = $ROOT/usr/local/share/mscgs/params/guidance.ini" "$EX"
"$CGS_BUILD/bin/guidanced" --exercise "$EX" --check >"$TMP/check.out" 2>&1
is "$?" 0 "guidanced --check passes with it"
GWP=$ROOT/etc/mscgs/gateway.ini
check "the lab's gateway parameters are installed in $ROOT/etc/mscgs" cmp -s "$GWP" "$CGS_ROOT/deploy/params/gateway-lab.ini"
check "and the lab exercise's gateway uses them" grep -q "^params = $ROOT/etc/mscgs/gateway.ini$" "$EX"
check "they broadcast on an interface named explicitly" bash -c \
    "grep -q '^mode = broadcast' '$GWP' && grep -qE '^interface = [a-z]' '$GWP'"
echo "; the admin's own" >>"$EX"
echo "; the admin's own" >>"$GWP"
make -s -C "$CGS_ROOT" install-built O="$CGS_BUILD" SAN=$SAN PREFIX="$ROOT/usr/local" SYSCONFDIR="$ROOT/etc" >"$TMP/install2.out" 2>&1
check "a second make install leaves an existing exercise file alone" bash -c \
    "tail -1 '$EX' | grep -q \"the admin's own\" && grep -q 'exercise.ini exists: left as it is' '$TMP/install2.out'"
check "and an existing gateway parameter file" bash -c \
    "tail -1 '$GWP' | grep -q \"the admin's own\" && grep -q 'gateway.ini exists: left as it is' '$TMP/install2.out'"
finish
