#!/bin/bash
# trackerd.sh — the real trackerd fed by the real uavsim, mtid and bcisd: it
# publishes every track of the radar after each scan on `track`; the movers
# get confirmed tracks near where they are; the friendly's track turns
# friendly from its BCIS replies and the hostile's stays unknown; the
# vehicle that turns a corner gives a completed turn of about 90 degrees on
# `track.turn`; killed with -9 and restarted, trackerd keeps every track id
# (its checkpoint); malformed parameters are refused with file and line.
# TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
BCISD=$CGS_BUILD/bin/bcisd
TRACKERD=$CGS_BUILD/bin/trackerd
for b in "$UAVSIM" "$MTID" "$BCISD" "$TRACKERD"; do [ -x "$b" ] || bail "no $b"; done

EX=$TMP/exercise.ini
{
    exercise_header 6 trackerd-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service bcisd.uav1 uav=uav1
    exercise_service trackerd params=tracker.ini
} >"$EX"
cp "$CGS_ROOT/deploy/params/tracker.ini" "$TMP/tracker.ini"
# Flat open ground; the UAV circles the origin. Entity ids: uav1 1, blue 2,
# red 3, turner 4.
{
    scenario_ground size_m=32000
    scenario_uav altitude_agl_m=1500 airspeed_mps=30 loiter_radius_m=800
    scenario_vehicle blue friendly BLUE "4000 -3000" "4000 6000" 12 end=reverse
    scenario_vehicle red hostile RED "-5000 3000" "4000 3000" 12 end=reverse
    cat <<'EOF'

[vehicle turner]
force = hostile
marking = TURNER
point = -6000 -4000
point = -3000 -4000
point = -3000 3000
speed_mps = 15
end = stop
EOF
} >"$TMP/scenario.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }

start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start B bcisd "$BCISD" --exercise "$EX" --instance bcisd.uav1
start T1 trackerd-1 "$TRACKERD" --exercise "$EX"
check "trackerd publishes tracks" wait_for 30 bash -c \
    "'$MSCGS' echo track --count 1 --timeout 2 --exercise '$EX' >/dev/null 2>&1"
# The turner turns at t = 200 s (3 km at 15 m/s); 20 scans run to t = 250 s or so.
M echo track.turn --json --count 100 --timeout 25 >"$TMP/turns.json" 2>/dev/null &
turns_pid=$!
M echo track --json --count 20 --timeout 40 >"$TMP/track.json" 2>/dev/null
wait "$turns_pid"
last=$(tail -1 "$TMP/track.json")
check "each batch names the radar, the scan and its place among the batches" \
    grep -q '"uav_id":1,"scan_number":[0-9]*,"tracks":\[' <<<"$last"
# One line per track of a batch: id status identity east north friendly_id.
# proto3 JSON leaves out fields at their defaults (TENTATIVE, UNKNOWN, 0).
tracks () {
    sed 's/{"track_id":/\n&/g' <<<"$1" | grep '^{"track_id":' | awk '
        function field(k, d,   m) {
            if (match($0, "\"" k "\":\"?[-A-Z_0-9.e]*")) {
                m = substr($0, RSTART + length(k) + 3, RLENGTH - length(k) - 3)
                gsub(/"/, "", m); return m
            }
            return d
        }
        {
            st = field("status", "TRACK_STATUS_TENTATIVE"); sub(/TRACK_STATUS_/, "", st)
            id = field("identity", "TRACK_IDENTITY_UNKNOWN"); sub(/TRACK_IDENTITY_/, "", id)
            print field("track_id", 0), st, id, field("east_m", 0), field("north_m", 0), field("friendly_id", 0)
        }'
}
tracks "$last" >"$TMP/tracks.txt"
diag "$(cat "$TMP/tracks.txt" | tr '\n' ';')"
# blue runs north along east 4000; red east along north 3000.
blue=$(awk '($2 == "CONFIRMED" || $2 == "COASTING") && $4 > 3800 && $4 < 4200 && $5 < 2800 { print $1 }' "$TMP/tracks.txt" | head -1)
red=$(awk '($2 == "CONFIRMED" || $2 == "COASTING") && $5 > 2800 && $5 < 3200 && $4 < 3700 { print $1 }' "$TMP/tracks.txt" | head -1)
check "the friendly has a track on its road (id ${blue:-none})" test -n "$blue"
check "the hostile has a track on its road (id ${red:-none})" test -n "$red"
check "the friendly's track is confirmed (or coasting) and friendly, with its BCIS id" \
    grep -Eq "^$blue (CONFIRMED|COASTING) FRIENDLY [-0-9.e]+ [-0-9.e]+ 2$" "$TMP/tracks.txt"
check "the hostile's track is confirmed (or coasting) and unknown" \
    grep -Eq "^$red (CONFIRMED|COASTING) UNKNOWN " "$TMP/tracks.txt"
check "tracks carry their hit history" grep -q '"history":\[{"position"' <<<"$last"
# The completed turn near the turner's corner at (-3000, -4000).
complete=$(grep '"complete":true' "$TMP/turns.json" | awk '
    match($0, /"east_m":[-0-9.e]+,"north_m":[-0-9.e]+/) {
        split(substr($0, RSTART, RLENGTH), a, /[:,]/)
        if ((a[2] + 3000) ^ 2 + (a[4] + 4000) ^ 2 < 1500 ^ 2) { print; exit }
    }')
diag "turn: $complete"
angle=$(sed -n 's/.*"turn_angle_deg":\([-0-9.e]*\).*/\1/p' <<<"$complete")
# East then north is a left turn: -90 degrees, clockwise positive.
check "the turner's corner gives a completed turn of about -90 degrees (${angle:-none})" \
    awk -v a="${angle:-x}" 'BEGIN { exit !(a != "x" && a < -60 && a > -120) }'

# Restart: every track id survives.
ids_before=$(tracks "$(M echo track --json --count 1 --timeout 10 2>/dev/null)" |
    awk '$2 == "CONFIRMED" { print $1 }' | sort -n | tr '\n' ' ')
kill9 "$T1"
start T2 trackerd-2 "$TRACKERD" --exercise "$EX"
check "the restarted trackerd resumes from its checkpoint" wait_for 20 grep -q "resumed" "$TMP/trackerd-2.log"
sleep 1
after=$(M echo track --json --count 2 --timeout 20 2>/dev/null | tail -1)
ids_after=$(tracks "$after" | awk '{ print $1 }' | sort -n | tr '\n' ' ')
diag "confirmed before: $ids_before; after: $ids_after"
missing=0
for id in $ids_before; do grep -qw "$id" <<<"$ids_after" || missing=$((missing + 1)); done
check "every confirmed track keeps its id across the restart ($missing missing)" \
    test -n "$ids_before" -a "$missing" -eq 0
h=$(M echo health --json --count 40 --timeout 5 2>/dev/null | grep '"instance":"trackerd"' | head -1)
check "its health reports it running" grep -q 'SERVICE_STATE_RUNNING' <<<"$h"
stop "$T2"
is "$EXIT_CODE" 0 "trackerd stops on SIGTERM with exit code 0"
stop "$B"
stop "$R"
stop "$U"
check "no sanitizer report from the first trackerd" clean_log trackerd-1
check "no sanitizer report from the second trackerd" clean_log trackerd-2

# A damaged checkpoint (here one of the format before cgs_ckpt, cut short) is
# refused with a reason naming what it found; trackerd starts empty and runs.
check "the stopped trackerd left its checkpoint" test -s "$TMP/state/trackerd.tracks"
printf 'MSCGSTRK\001\000\000\000garbage' >"$TMP/state/trackerd.tracks"
start T3 trackerd-3 "$TRACKERD" --exercise "$EX"
check "a damaged checkpoint is ignored with the reason" wait_for 20 \
    grep -q "checkpoint .*trackerd.tracks ignored: " "$TMP/trackerd-3.log"
check "the reason names what the old file begins with" \
    grep -q 'not a trackerd checkpoint: it begins "MSCG"' "$TMP/trackerd-3.log"
check "and trackerd runs on with no tracks" wait_for 20 bash -c \
    "'$MSCGS' echo health --json --count 20 --timeout 5 --exercise '$EX' | grep -q '\"instance\":\"trackerd\".*RUNNING'"
stop "$T3"
check "no sanitizer report from the third trackerd" clean_log trackerd-3
"$TRACKERD" --exercise "$EX" --check >"$TMP/check.log" 2>&1
is "$?" 0 "trackerd --check accepts the test's parameters"
# Malformed parameters: refused before the bus, with file, line and key.
sed 's/^confirm_m = 3$/confirm_m = 9/' "$TMP/tracker.ini" >"$TMP/bad.ini"
line=$(grep -n '^confirm_m' "$TMP/bad.ini" | cut -d: -f1)
"$TRACKERD" --exercise "$EX" --params "$TMP/bad.ini" --check >"$TMP/bad.log" 2>&1
is "$?" 1 "trackerd --check refuses confirm_m above confirm_n"
check "naming the file, line and key" grep -q "bad.ini:$line: \[association\] confirm_m" "$TMP/bad.log"
sed 's/^mode = imm$/mode = fast/' "$TMP/tracker.ini" >"$TMP/bad2.ini"
"$TRACKERD" --exercise "$EX" --params "$TMP/bad2.ini" --check >"$TMP/bad2.log" 2>&1
is "$?" 1 "trackerd --check refuses mode = fast"
line=$(grep -n '^mode' "$TMP/bad2.ini" | cut -d: -f1)
check "naming the file, line and what it expected" \
    grep -q "bad2.ini:$line: \[filter\] mode: expected one of 'paper', 'kalman', 'imm', got 'fast'" "$TMP/bad2.log"

finish
