#!/bin/bash
# mtid.sh — the real mtid beside the real uavsim: it publishes a dwell at a
# time on `mti` (hits with measured positions near the movers), `mti.truth`
# naming their sources, and `mti.scan` at the end of each revolution; killed
# with -9 and restarted it scans on at the scan number simulation time gives;
# malformed parameters are refused with file and line; `mtid --monte-carlo`
# prints JSON with Pd and Pfa in agreement with theory. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
[ -x "$UAVSIM" ] || bail "no uavsim at $UAVSIM"
[ -x "$MTID" ] || bail "no mtid at $MTID"

EX=$TMP/exercise.ini
{
    exercise_header 4 mtid-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1 params=radar.ini
} >"$EX"
# Flat ground; movers 3-6 km from the UAV driving straight at or away from it
# (radial speed 8-10 m/s, well clear of the clutter) and one parked.
{
    scenario_ground size_m=16000
    scenario_uav altitude_agl_m=1500 airspeed_mps=30 loiter_radius_m=900
    cat <<'EOF'

[vehicle east]
force = unknown
point = 3000 0
point = 6000 0
speed_mps = 10
end = reverse

[vehicle north]
force = hostile
point = 0 6000
point = 0 3000
speed_mps = 10
end = reverse

[vehicle parked]
force = neutral
point = -4000 -1000
point = -4001 -1000
speed_mps = 1
end = stop
EOF
} >"$TMP/scenario.ini"
cp "$CGS_ROOT/deploy/params/radar.ini" "$TMP/radar.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
num () { sed -n "s/.*\"$2\":\"\{0,1\}\([-0-9.e]*\).*/\1/p" <<<"$1" | head -1; }

start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start R1 mtid-1 "$MTID" --exercise "$EX" --instance mtid.uav1
check "mtid publishes mti dwells" wait_for 20 bash -c \
    "'$MSCGS' echo mti --count 1 --timeout 2 --exercise '$EX' >/dev/null 2>&1"
M echo mti --json --count 240 --timeout 30 >"$TMP/mti.json" 2>/dev/null
M echo mti.truth --json --count 240 --timeout 30 >"$TMP/truth.json" 2>/dev/null
check "mti carries the UAV's id and the beam azimuth" \
    grep -q '"uav_id":1,.*"beam_azimuth_deg"' "$TMP/mti.json"
hits=$(grep -o '"hit_id"' "$TMP/mti.json" | wc -l)
diag "$hits hits in 240 dwells (two revolutions)"
check "hits arrive" test "$hits" -ge 2
# Every mover hit lies within 300 m of a mover's route (false alarms aside:
# those lie anywhere, so count only hits near the routes and want most).
near=$(grep -o '"position":{"east_m":[-0-9.e]*,"north_m":[-0-9.e]*' "$TMP/mti.json" |
    sed 's/.*east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\)/\1 \2/' |
    awk '($2 > -300 && $2 < 300 && $1 > 2700 && $1 < 6300) || ($1 > -300 && $1 < 300 && $2 > 2700 && $2 < 6300) { n++ } END { print n + 0 }')
diag "$near of them within 300 m of the two moving routes"
check "mti.truth names the sources of the hits" grep -q '"detected":true,"hit_id":' "$TMP/truth.json"
# Entity ids: uav1 1, east 2, north 3, parked 4.
for id in 2 3; do
    d=$(grep -o "{\"entity_id\":$id,[^}]*}" "$TMP/truth.json" | grep -c '"detected":true')
    check "mover $id is detected in two revolutions (mti.truth: $d)" test "$d" -ge 1
done
check "the hits near the moving routes are at least the movers' detections" test "$near" -ge 2
parked=$(grep -o '{"entity_id":4,[^}]*}' "$TMP/truth.json")
check "the parked vehicle is in the beam (mti.truth lists it)" test -n "$parked"
check "but, in the clutter, never detected" bash -c "! grep -q '\"detected\":true' <<<'$parked'"
check "mti.scan marks each revolution" bash -c \
    "'$MSCGS' echo mti.scan --json --count 1 --timeout 20 --exercise '$EX' | grep -q '\"full_revolution\":true'"
# The scan is a function of simulation time: scan = floor(t / 10 s) + 1.
scan_matches_time () {
    local m t s
    m=$(M echo mti --json --count 1 --timeout 20 2>/dev/null)
    t=$(num "$m" sim_time_s); s=$(num "$m" scan_number)
    diag "dwell at t=$t s in scan $s"
    awk -v t="$t" -v s="$s" 'BEGIN { exit !(t != "" && s == int(t / 10) + 1) }'
}
check "the dwell's scan number follows simulation time" scan_matches_time

kill9 "$R1"
start R2 mtid-2 "$MTID" --exercise "$EX" --instance mtid.uav1
check "the restarted mtid scans on where simulation time says" scan_matches_time
check "and publishes hits again" wait_for 20 bash -c \
    "'$MSCGS' echo mti --json --count 20 --timeout 5 --exercise '$EX' | grep -q hit_id"
h=$(M echo health --json --count 20 --timeout 5 2>/dev/null | grep '"instance":"mtid.uav1"' | head -1)
check "its health reports it running" grep -q 'SERVICE_STATE_RUNNING' <<<"$h"
stop "$R2"
is "$EXIT_CODE" 0 "mtid stops on SIGTERM with exit code 0"
stop "$U"
check "no sanitizer report from the first mtid" clean_log mtid-1
check "no sanitizer report from the second mtid" clean_log mtid-2

# Malformed parameters: refused before the bus, with file, line and key.
sed 's/^fft_size = 64$/fft_size = 48/' "$TMP/radar.ini" >"$TMP/bad.ini"
line=$(grep -n '^fft_size' "$TMP/bad.ini" | cut -d: -f1)
"$MTID" --exercise "$EX" --instance mtid.uav1 --params "$TMP/bad.ini" --check >"$TMP/bad.log" 2>&1
is "$?" 1 "mtid --check refuses fft_size = 48"
check "naming the file, line and key" grep -q "bad.ini:$line: \[processing\] fft_size" "$TMP/bad.log"
sed 's/^n = 4$/n = 7/' "$TMP/radar.ini" >"$TMP/bad2.ini"
"$MTID" --exercise "$EX" --instance mtid.uav1 --params "$TMP/bad2.ini" --check >"$TMP/bad2.log" 2>&1
is "$?" 1 "mtid --check refuses more coherent intervals than a dwell holds"
check "saying how many pulses a dwell has" grep -q "a dwell has only 416" "$TMP/bad2.log"
"$MTID" --exercise "$EX" --instance mtid.uav1 --check >"$TMP/good.log" 2>&1
is "$?" 0 "mtid --check accepts the shipped parameters"

# The Monte Carlo mode: Pd and Pfa against theory, as JSON.
mc=$("$MTID" --monte-carlo --swerling 1 --snr-db 12 --trials 10000 --pfa 1e-3 2>&1)
diag "$mc"
pd=$(num "$mc" pd_measured); th=$(num "$mc" pd_theory)
check "--monte-carlo prints the measured and theoretical Pd ($pd, $th)" test -n "$pd" -a -n "$th"
lo=$(sed -n 's/.*"pd_interval_99":\[\([0-9.e-]*\),.*/\1/p' <<<"$mc")
check "and the 99% interval of the measured Pd ($lo...)" test -n "$lo"
check "which agree within 0.02" awk -v a="$pd" -v b="$th" 'BEGIN { d = a - b; exit !(d < 0.02 && d > -0.02) }'
"$MTID" --monte-carlo --swerling 4 >/dev/null 2>"$TMP/mc.err"
is "$?" 2 "--monte-carlo refuses a Swerling model it does not know"
check "saying which it knows" grep -q "expected 0 (constant), 1, 2 or 2-pulse" "$TMP/mc.err"

finish
