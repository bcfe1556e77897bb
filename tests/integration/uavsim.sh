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
    exercise_header 3 uavsim-test scenario=scenario.ini
    exercise_service uavsim command
} >"$EX"
{
    scenario_ground size_m=8000 resolution_m=50 relief_m=120
    scenario_uav "position=-2500 -2500" altitude_agl_m=800 airspeed_mps=30 loiter_radius_m=900
    cat <<'EOF'

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
} >"$TMP/scenario.ini"

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
M route --speed 500 --altitude 900 0,0 >/dev/null 2>&1
is "$?" 1 "a route with an impossible speed is refused"
u=$(json uav)
check "and changes nothing: still task 2, still 30 m/s, still 800 m" bash -c \
    "grep -q '\"task_number\":\"2\"' <<<'$u' && grep -q '\"commanded_airspeed_mps\":30,' <<<'$u' && grep -q '\"commanded_altitude_agl_m\":800,' <<<'$u'"
out=$(M loiter --at 0,0 --radius 50 2>&1)
is "$?" 1 "an orbit tighter than the UAV can turn is refused"
check "saying how tight it can turn" grep -q "tighter than the UAV can turn" <<<"$out"

# The clock runs at the time scale: about 10 s of simulation per second.
ta=$(num "$(json clock)" sim_time_s)
sleep 1
tb=$(num "$(json clock)" sim_time_s)
rate=$(awk -v a="$ta" -v b="$tb" 'BEGIN { print b - a }')
diag "simulated $rate s in a little over 1 s of wall time at time scale 10"
check "simulation time advances at about the time scale" \
    awk -v r="$rate" 'BEGIN { exit !(r > 8 && r < 14) }'

# Let a checkpoint pass, then crash it; restart without --time-scale.
t1=$tb
sleep 1.2
kill9 "$U1"
start U2 uavsim-2 "$UAVSIM" --exercise "$EX"
c2=$(json clock)
t2=$(num "$c2" sim_time_s)
diag "before the kill: t=$t1 s; first clock after the restart: t=$t2 s"
check "the restarted uavsim resumes where it was (t=$t2 s), not at 0" gt "$t2" "$t1"
check "it says it resumed from its saved state" grep -q "resumed from the saved state" "$TMP/uavsim-2.log"
check "the time scale came back with the world (10, not the exercise's 1)" \
    grep -q '"time_scale":10' <<<"$c2"
u=$(json uav)
check "the route task survived the crash (task 2)" grep -q '"task_number":"2"' <<<"$u"

out=$(M goto 500,500 --radius 600 2>&1)
is "$?" 0 "mscgs goto is accepted"
check "the UAV heads for the point (task 3, mode TRANSIT)" wait_for 10 bash -c \
    "'$MSCGS' echo uav --json --count 1 --timeout 5 --exercise '$EX' 2>/dev/null | grep '\"task_number\":\"3\"' | grep -q UAV_MODE_TRANSIT"

M pause >/dev/null 2>&1
is "$?" 0 "mscgs pause"
c3=$(json clock)
sleep 0.5
c4=$(json clock)
check "paused: the clock says so" grep -q '"paused":true' <<<"$c4"
is "$(num "$c4" sim_time_s)" "$(num "$c3" sim_time_s)" "paused: simulation time stands still"
M resume >/dev/null 2>&1
is "$?" 0 "mscgs resume"
sleep 0.5
check "resumed: simulation time advances again" gt "$(num "$(json clock)" sim_time_s)" "$(num "$c4" sim_time_s)"
M time-scale 20 >/dev/null 2>&1
is "$?" 0 "mscgs time-scale 20 is accepted"
check "the clock reports it" wait_for 5 bash -c "'$MSCGS' echo clock --json --count 1 --timeout 3 --exercise '$EX' | grep -q '\"time_scale\":20'"
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
