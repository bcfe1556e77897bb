#!/bin/bash
# bcisd.sh — the real bcisd beside the real uavsim: it publishes an
# interrogation a dwell on `bcis` and a marker at the end of each scan;
# friendly transponders in reach answer with their identity, the range and
# the beam's azimuth, placed where those meet the ground, near where they are, a friendly beyond the range where the link closes
# never does, nor a hostile carrying a transponder, nor an unknown without
# one; killed with -9 and restarted it scans on at the scan number simulation
# time gives; malformed parameters are refused with file and line. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
BCISD=$CGS_BUILD/bin/bcisd
[ -x "$UAVSIM" ] || bail "no uavsim at $UAVSIM"
[ -x "$BCISD" ] || bail "no bcisd at $BCISD"

EX=$TMP/exercise.ini
{
    exercise_header 5 bcisd-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service bcisd.uav1 uav=uav1 params=bcis.ini
} >"$EX"
# Flat open ground. The transmitters are 10 dB weaker than the defaults, so
# the link closes near 6 km: `near` (3-4 km) answers, `far` (13 km, inside
# max_range_m) does not; `foe` is hostile with a transponder, `stranger` an
# unknown without one, both 3 km out.
{
    scenario_ground size_m=32000
    scenario_uav airspeed_mps=30 loiter_radius_m=900
    scenario_vehicle near friendly NEAR "3000 0" "4000 0" 8 end=reverse
    cat <<'EOF'

[vehicle far]
force = friendly
point = 0 -13000
point = 0 -13500
speed_mps = 5
end = reverse

[vehicle foe]
force = hostile
bcis_transponder = yes
point = -3000 0
point = -3500 0
speed_mps = 5
end = reverse

[vehicle stranger]
force = unknown
point = 0 3000
point = 0 3500
speed_mps = 5
end = reverse
EOF
} >"$TMP/scenario.ini"
sed -e 's/^transmit_power_w = 1$/transmit_power_w = 0.1/' \
    -e 's/^transmit_power_w = 0.5$/transmit_power_w = 0.05/' \
    "$CGS_ROOT/deploy/params/bcis.ini" >"$TMP/bcis.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
num () { sed -n "s/.*\"$2\":\"\{0,1\}\([-0-9.e]*\).*/\1/p" <<<"$1" | head -1; }
replies () { grep -o "\"responder_id\":$1,[^}]*}" "$TMP/bcis.json"; }

start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start B1 bcisd-1 "$BCISD" --exercise "$EX" --instance bcisd.uav1
check "bcisd publishes interrogations" wait_for 20 bash -c \
    "'$MSCGS' echo bcis --count 1 --timeout 2 --exercise '$EX' >/dev/null 2>&1"
# 60 dwells a revolution: 300 messages are about five scans.
M echo bcis --json --count 300 --timeout 30 >"$TMP/bcis.json" 2>/dev/null
check "bcis carries the UAV's id, scan number and beam azimuth" \
    grep -q '"uav_id":1,"scan_number":[0-9]*,"scan_time_s":[-0-9.e]*,"beam_azimuth_deg"' \
    "$TMP/bcis.json"
markers=$(grep -c '"scan_end":true' "$TMP/bcis.json")
check "a marker ends each scan ($markers in 300 messages)" test "$markers" -ge 4
# Entity ids: uav1 1, near 2, far 3, foe 4, stranger 5.
n=$(replies 2 | wc -l)
check "the near friendly answers every scan ($n replies)" test "$n" -ge 4
check "its reply carries its marking" grep -q '"responder_id":2,"marking":"NEAR"' "$TMP/bcis.json"
# Its reply puts it on its route (3-4 km east, north 0), within the beam:
# 3 degrees either side of it (tan 3 deg = 0.052), and 60 m.
off=$(replies 2 | sed 's/.*"east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\).*/\1 \2/' |
    awk '{ w = 0.053 * $1 + 60; if ($1 < 2940 || $1 > 4060 || $2 < -w || $2 > w) n++ } END { print n + 0 }')
check "its replies place it on its route, within the beam ($off off it)" test "$off" -eq 0
check "a reply gives its range's and azimuth's sigma, not a position fix" bash -c \
    "grep -o '\"responder_id\":2,[^}]*}[^}]*}' '$TMP/bcis.json' | head -1 | grep -q '\"range_sigma_m\":5,\"azimuth_sigma_deg\":1.73' && ! grep -q '\"position_fix\":true' '$TMP/bcis.json'"
check "and the interrogator's position" grep -q '"interrogator":{"east_m"' "$TMP/bcis.json"
check "the friendly 13 km out, beyond where the link closes, never answers" \
    test "$(replies 3 | wc -l)" -eq 0
check "the hostile with a transponder never answers" test "$(replies 4 | wc -l)" -eq 0
check "the unknown without a transponder never answers" test "$(replies 5 | wc -l)" -eq 0
# The scan is a function of simulation time: scan = floor(t / 6 s) + 1.
scan_matches_time () {
    local m t s
    m=$(M echo bcis --json --count 1 --timeout 20 2>/dev/null)
    t=$(num "$m" scan_time_s); s=$(num "$m" scan_number)
    diag "interrogation at t=$t s in scan $s"
    awk -v t="$t" -v s="$s" 'BEGIN { exit !(t != "" && s == int(t / 6) + 1) }'
}
check "the interrogation's scan number follows simulation time" scan_matches_time

kill9 "$B1"
start B2 bcisd-2 "$BCISD" --exercise "$EX" --instance bcisd.uav1
check "the restarted bcisd scans on where simulation time says" scan_matches_time
check "and the near friendly answers again" wait_for 20 bash -c \
    "'$MSCGS' echo bcis --json --count 120 --timeout 10 --exercise '$EX' | grep -q '\"responder_id\":2'"
h=$(M echo health --json --count 20 --timeout 5 2>/dev/null | grep '"instance":"bcisd.uav1"' | head -1)
check "its health reports it running" grep -q 'SERVICE_STATE_RUNNING' <<<"$h"
stop "$B2"
is "$EXIT_CODE" 0 "bcisd stops on SIGTERM with exit code 0"
stop "$U"
check "no sanitizer report from the first bcisd" clean_log bcisd-1
check "no sanitizer report from the second bcisd" clean_log bcisd-2

# Malformed parameters: refused before the bus, with file, line and key.
sed 's/^modulation = bfsk$/modulation = morse/' "$TMP/bcis.ini" >"$TMP/bad.ini"
line=$(grep -n '^modulation' "$TMP/bad.ini" | cut -d: -f1)
"$BCISD" --exercise "$EX" --instance bcisd.uav1 --params "$TMP/bad.ini" --check >"$TMP/bad.log" 2>&1
is "$?" 1 "bcisd --check refuses modulation = morse"
check "naming the file, line and key" grep -q "bad.ini:$line: \[link\] modulation" "$TMP/bad.log"
sed 's/^correctable_bits = 0$/correctable_bits = 64/' "$TMP/bcis.ini" >"$TMP/bad2.ini"
"$BCISD" --exercise "$EX" --instance bcisd.uav1 --params "$TMP/bad2.ini" --check >"$TMP/bad2.log" 2>&1
is "$?" 1 "bcisd --check refuses a code that corrects a whole message"
check "saying why" grep -q "must be fewer than the bits of either message" "$TMP/bad2.log"
"$BCISD" --exercise "$EX" --instance bcisd.uav1 --check >"$TMP/good.log" 2>&1
is "$?" 0 "bcisd --check accepts the test's parameters"

finish
