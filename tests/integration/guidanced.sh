#!/bin/bash
# guidanced.sh — the real guidanced with the real uavsim, mtid and trackerd:
# idle until designated; a designation by point takes the track nearest it
# and the UAV leaves its orbit on the planned route (uavsim's `uav` shows
# the route); `intercept` carries waypoint, route and a four-corner
# footprint; a second designation pre-empts the first; killed with -9 and
# restarted, guidanced resumes the intercept; the intercept reaches its
# overflight; cancel leaves the UAV loitering; bad commands and bad
# parameters are refused with the reason. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
for b in "$UAVSIM" "$MTID" "$TRACKERD" "$GUIDANCED"; do [ -x "$b" ] || bail "no $b"; done

EX=$TMP/exercise.ini
{
    exercise_header 7 guidanced-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service trackerd
    exercise_service guidanced command params=guidance.ini
} >"$EX"
cp "$CGS_ROOT/deploy/params/guidance.ini" "$TMP/guidance.ini"
# Flat ground; the UAV circles the origin; two movers drive north, 4 km
# apart, 5 to 6 km from it.
{
    scenario_ground
    scenario_uav
    scenario_vehicle target hostile TARGET "5000 -4000" "5000 16000" 10 end=stop
    scenario_vehicle other unknown OTHER "-5000 -4000" "-5000 16000" 8 end=stop
} >"$TMP/scenario.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
# The latest intercept message as JSON.
icpt () { M echo intercept --json --count 1 --timeout 5 2>/dev/null | tail -1; }
# A field of a JSON line (first match): fieldof JSON KEY.
fieldof () { sed -n "s/.*\"$2\":\"\{0,1\}\([-A-Z_a-z0-9.]*\).*/\1/p" <<<"$1" | head -1; }
# Confirmed tracks of the latest batch: id east north.
tracks () { confirmed_tracks "$EX"; }

start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start T trackerd "$TRACKERD" --exercise "$EX"
start G1 guidanced-1 "$GUIDANCED" --exercise "$EX"
check "guidanced publishes an idle intercept" wait_for 30 bash -c \
    "'$MSCGS' echo intercept --json --count 1 --timeout 2 --exercise '$EX' | grep -q '\"uavId\":1\|\"uav_id\":1'"
first=$(icpt)
check "idle: no track, no footprint" bash -c "! grep -q 'track_id\|footprint' <<<'$first'"

# Wait for confirmed tracks of both movers (about 40 s of simulation).
tgt="" oth=""
for _ in $(seq 1 40); do
    tracks >"$TMP/tracks.txt"
    tgt=$(awk '$2 > 4500 && $2 < 5500 { print $1; exit }' "$TMP/tracks.txt")
    oth=$(awk '$2 > -5500 && $2 < -4500 { print $1; exit }' "$TMP/tracks.txt")
    [ -n "$tgt" ] && [ -n "$oth" ] && break
    sleep 0.5
done
diag "tracks: $(tr '\n' ';' <"$TMP/tracks.txt")"
check "both movers have confirmed tracks (target ${tgt:-none}, other ${oth:-none})" test -n "$tgt" -a -n "$oth"

M designate 99999 >"$TMP/nosuch.out" 2>&1
is "$?" 1 "designating a track that does not exist is refused"
check "with the reason" grep -q "no track 99999" "$TMP/nosuch.out"
M footprint-scale 3 >"$TMP/scale.out" 2>&1
is "$?" 2 "footprint scale 3 is refused by mscgs as bad usage"
M cancel >"$TMP/cancel0.out" 2>&1
is "$?" 1 "cancel with nothing designated is refused"

# Designate the other mover by id, then the target by a point near it: the
# second pre-empts the first.
M designate "$oth" >"$TMP/d1.out" 2>&1
is "$?" 0 "designate by track id is accepted"
d1=$(icpt)
n1=$(fieldof "$d1" designation_number)
p=$(awk -v id="$tgt" '$1 == id { printf "%.0f,%.0f", $2 + 100, $3 - 100 }' "$TMP/tracks.txt")
M designate --at "$p" >"$TMP/d2.out" 2>&1
is "$?" 0 "designate by a point near the target's newest hit is accepted"
diag "$(cat "$TMP/d2.out")"
check "the reply says it pre-empts the first" grep -q "pre-empts track $oth" "$TMP/d2.out"
sleep 0.5
d2=$(icpt)
n2=$(fieldof "$d2" designation_number)
is "$(fieldof "$d2" track_id)" "$tgt" "the intercept follows the target's track"
check "the designation number went up ($n1 -> $n2)" test "${n2:-0}" -gt "${n1:-0}"
check "the intercept has a waypoint, a route and t_pred" \
    bash -c "grep -q '\"waypoint\":{' <<<'$d2' && grep -q '\"route\":\[{' <<<'$d2' && grep -q 't_pred_s' <<<'$d2'"
ncorners=$(grep -o '"corners":\[[^]]*\]' <<<"$d2" | grep -o 'east_m' | wc -l)
is "$ncorners" 4 "the footprint has four corners"
check "the UAV flies the route (uavsim's uav in ROUTE mode)" wait_for 10 bash -c \
    "'$MSCGS' echo uav --json --count 1 --timeout 3 --exercise '$EX' | grep -q 'UAV_MODE_ROUTE'"

# Kill -9 mid-intercept: the restarted guidanced resumes it.
check "guidanced saved its state" test -s "$TMP/state/guidanced.state"
kill9 "$G1"
start G2 guidanced-2 "$GUIDANCED" --exercise "$EX"
check "the restarted guidanced resumes the intercept" wait_for 20 \
    grep -q "resumed uav1: .*track $tgt" "$TMP/guidanced-2.log"
sleep 0.5
d3=$(icpt)
is "$(fieldof "$d3" designation_number)" "$n2" "same designation after the restart"
is "$(fieldof "$d3" track_id)" "$tgt" "same track after the restart"

# The intercept goes on to the overflight (a few minutes of simulation).
ok=0
for _ in $(seq 1 120); do
    s=$(fieldof "$(icpt)" state)
    case "$s" in INTERCEPT_STATE_OVERFLIGHT | INTERCEPT_STATE_DONE) ok=1; break ;; esac
    sleep 0.5
done
check "the target comes under the footprint (state ${s:-none})" test "$ok" = 1
grep 'uav1: ' "$TMP/guidanced-2.log" | tail -5 | while read -r l; do diag "$l"; done

M cancel >"$TMP/cancel.out" 2>&1
is "$?" 0 "cancel is accepted"
sleep 0.5
c=$(icpt)
is "$(fieldof "$c" state)" INTERCEPT_STATE_CANCELLED "the intercept is cancelled"
check "and shows no footprint" bash -c "! grep -q footprint <<<'$c'"
# proto3 JSON leaves out LOITER (0); TRANSIT is the way onto the new orbit.
check "the UAV leaves its route to loiter where it is" wait_for 10 bash -c \
    "'$MSCGS' echo uav --json --count 1 --timeout 3 --exercise '$EX' | grep -vq UAV_MODE_ROUTE"

stop "$G2"
is "$EXIT_CODE" 0 "guidanced stops on SIGTERM with exit code 0"
stop "$T"
stop "$R"
stop "$U"
check "no sanitizer report from the first guidanced" clean_log guidanced-1
check "no sanitizer report from the second guidanced" clean_log guidanced-2

"$GUIDANCED" --exercise "$EX" --check >"$TMP/check.log" 2>&1
is "$?" 0 "guidanced --check accepts the test's configuration"
sed 's/^threshold_deg = 20$/threshold_deg = 200/' "$TMP/guidance.ini" >"$TMP/bad.ini"
line=$(grep -n '^threshold_deg' "$TMP/bad.ini" | cut -d: -f1)
"$GUIDANCED" --exercise "$EX" --params "$TMP/bad.ini" --check >"$TMP/bad.log" 2>&1
is "$?" 1 "guidanced --check refuses a threshold of 200 degrees"
check "naming the file, line and key" grep -q "bad.ini:$line: \[replan\] threshold_deg" "$TMP/bad.log"

# The Monte Carlo of whole intercepts is `mscgs montecarlo` now (montecarlo.sh).
"$GUIDANCED" --monte-carlo >/dev/null 2>"$TMP/mc-bad.err"
check "guidanced has no --monte-carlo any more (refused, exit $?)" grep -q "monte-carlo" "$TMP/mc-bad.err"

finish
