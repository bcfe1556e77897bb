#!/bin/bash
# uavsim.sh — the real uavsim with the mscgs tool: it publishes clock,
# entity and uav; a route task is accepted, flown and survives kill -9 (the
# restarted uavsim resumes from its checkpoint: time and task, not the
# scenario's start); pause and time scale work; a malformed scenario is
# refused with file and line. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
[ -x "$UAVSIM" ] || bail "no uavsim at $UAVSIM"
[ -x "$MSCGS" ] || bail "no mscgs at $MSCGS"

EX=$TMP/exercise.ini
{
    exercise_header 3 uavsim-test
    cat <<EOF
scenario = scenario.ini

[service uavsim]
publish = ipc://$TMP/uavsim.pub
command = ipc://$TMP/uavsim.cmd
EOF
} >"$EX"
cat >"$TMP/scenario.ini" <<'EOF'
[terrain]
size_m = 8000
resolution_m = 50
relief_m = 120

[uav uav1]
position = -2500 -2500
altitude_agl_m = 800
airspeed_mps = 30
loiter_radius_m = 900

[vehicle t1]
force = unknown
point = 0 0
point = 2000 0
point = 2000 2000
end = loop

[vehicle f1]
force = friendly
point = -1000 1000
point = 1000 1000
end = reverse

[uavsim]
checkpoint_interval_s = 0.5
EOF

M () { "$MSCGS" "$@" --exercise "$EX"; }
# json TOPIC: one message of TOPIC as JSON (within 10 s).
json () { M echo "$1" --json --count 1 --timeout 10 2>/dev/null; }
# num TEXT KEY: the number after "KEY": in JSON text.
num () { sed -n "s/.*\"$2\":\"\{0,1\}\([-0-9.e]*\).*/\1/p" <<<"$1" | head -1; }
# gt A B: A > B as numbers.
gt () { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 > b + 0) }'; }

start U1 uavsim-1 "$UAVSIM" --exercise "$EX" --time-scale 10
check "uavsim publishes clock" wait_for 15 bash -c "'$MSCGS' echo clock --count 1 --timeout 2 --exercise '$EX' >/dev/null 2>&1"
e=$(json entity)
is "$(grep -o '"entity_id"' <<<"$e" | wc -l)" 3 "entity batches carry the UAV and both vehicles"
u=$(json uav)
check "the UAV starts on its task 1 (the scenario's orbit)" grep -q '"task_number":"1"' <<<"$u"

out=$(M route 0,0 1500,-500 2>&1)
rc=$?
is "$rc" 0 "mscgs route is accepted"
check "and the reply names the new task" grep -q "task 2 accepted" <<<"$out"
route_flown () {
    M echo uav --json --count 1 --timeout 5 2>/dev/null | grep '"mode":"UAV_MODE_ROUTE"' |
        grep -q '"task_number":"2"'
}
check "the UAV flies the route (mode ROUTE, task 2)" wait_for 10 route_flown

out=$(M speed 500 2>&1)
is "$?" 1 "an airspeed outside the UAV's limits is refused (exit 1)"
check "with the reason" grep -q "airspeed outside the UAV's limits" <<<"$out"

# Let a checkpoint pass, then crash it.
t1=$(num "$(json clock)" sim_time_s)
check "simulation time runs at the time scale (t=$t1 s)" gt "$t1" 5
sleep 1.2
kill9 "$U1"
start U2 uavsim-2 "$UAVSIM" --exercise "$EX" --time-scale 10
t2=$(num "$(json clock)" sim_time_s)
diag "before the kill: t=$t1 s; first clock after the restart: t=$t2 s"
check "the restarted uavsim resumes near where it was, not at 0" gt "$t2" "$(awk -v a="$t1" 'BEGIN{print a - 1}')"
check "it says it resumed from its saved state" grep -q "resumed from the saved state" "$TMP/uavsim-2.log"
u=$(json uav)
check "the route task survived the crash (task 2)" grep -q '"task_number":"2"' <<<"$u"

M pause >/dev/null 2>&1
is "$?" 0 "mscgs pause"
c3=$(json clock)
sleep 0.5
c4=$(json clock)
check "paused: the clock says so" grep -q '"paused":true' <<<"$c4"
is "$(num "$c4" sim_time_s)" "$(num "$c3" sim_time_s)" "paused: simulation time stands still"
M resume >/dev/null 2>&1
is "$?" 0 "mscgs resume"
M time-scale 2000 >/dev/null 2>&1
is "$?" 1 "a time scale over 1000 is refused"

stop "$U2"
is "$EXIT_CODE" 0 "uavsim stops on SIGTERM with exit code 0"
check "no sanitizer report from the first run" clean_log uavsim-1
check "no sanitizer report from the second run" clean_log uavsim-2

# A malformed scenario: refused before touching the bus, with file and line.
sed 's/^force = unknown$/force = sideways/' "$TMP/scenario.ini" >"$TMP/bad.ini"
"$UAVSIM" --exercise "$EX" --scenario "$TMP/bad.ini" --check >"$TMP/bad.log" 2>&1
is "$?" 1 "uavsim --check refuses a scenario with an unknown force"
check "naming the file and line" grep -q "bad.ini:13: \[vehicle t1\] force" "$TMP/bad.log"

finish
