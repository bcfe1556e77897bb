#!/bin/bash
# run.sh — `mscgs run` with real processes: the test peer, copied beside a
# copy of mscgs under a service's name (uavsim, publishing clock), is started
# with the exercise, reports health, is restarted after kill -9 (a restart
# counted in the summary), and everything stops at --duration with logs and
# a summary in the output folder; `mscgs status` sees the service up while it
# runs. Then the real stationd with `port = 0`: mscgs run says the system
# chooses the map's port and prints the address once stationd reports it,
# and the page is served there; with --record the run's topics go to
# OUT/recording.mcap, which @mcap/core reads. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

[ -x "$MSCGS" ] || bail "no mscgs at $MSCGS"
[ -x "$PEER" ] || bail "no test peer at $PEER"
BIN=$TMP/bin
mkdir -p "$BIN"
cp "$MSCGS" "$BIN/mscgs"
cp "$PEER" "$BIN/uavsim"

EX=$TMP/exercise.ini
{
    cat <<INI
[exercise]
id = 7
origin = geo 35.96 -121.23 0
state_dir = $TMP/state
INI
    exercise_service uavsim command
    # Listed but not built in this folder: mscgs run leaves it out.
    exercise_service trackerd
} >"$EX"

OUT=$TMP/out
start RUN run "$BIN/mscgs" run --exercise "$EX" --duration 25 --out "$OUT"
check "mscgs run starts the built service and it reports health" \
    wait_for 15 grep -q "1/1 running, 1 reporting" "$TMP/run.log"
grep -q "1 of 2 services built here" "$TMP/run.log"
check "mscgs run says which services are built" [ $? -eq 0 ]

"$BIN/mscgs" status --exercise "$EX" --wait 5 >"$TMP/status.out" 2>&1
rc=$?
is "$rc" 3 "mscgs status exits 3 while an enabled instance (trackerd) is down"
check "mscgs status shows uavsim up" grep -qE '^uavsim +up ' "$TMP/status.out"
check "mscgs status shows trackerd down" grep -qE '^trackerd +down' "$TMP/status.out"
# The peer, started as mscgs run starts a service, serves no commands: the
# tool must say so clearly rather than hang.
"$BIN/mscgs" ping uavsim --exercise "$EX" >"$TMP/ping.out" 2>&1
rc=$?
is "$rc" 1 "mscgs ping exits 1 when the service does not answer"
check "and says where it got no reply from" grep -q "no reply from ipc://$TMP/uavsim.cmd after 3 attempts" "$TMP/ping.out"

# A second copy of the same instance with the same state folder refuses to
# start (it would take over the first one's endpoints and state).
timeout 20 "$BIN/uavsim" --exercise "$EX" --instance uavsim --state-dir "$OUT/state" \
    >"$TMP/second.log" 2>&1
rc=$?
is "$rc" 1 "a second copy of the instance exits 1"
check "and says it is already running" grep -q "uavsim is already running" "$TMP/second.log"

pid=$(pgrep -f "^$BIN/uavsim " | head -1)
check "the service runs as a child of mscgs run" [ -n "$pid" ]
[ -n "$pid" ] && kill -9 "$pid"
check "mscgs run reports the death and restarts it" \
    wait_for 10 grep -q "uavsim was killed by Killed; restarting in 1 s (restart 1" "$TMP/run.log"
check "the restarted service is running again" \
    wait_for 15 bash -c "pgrep -f '^$BIN/uavsim ' | grep -vqx '$pid'"
# A progress line after the restart message that shows it running and reporting.
reporting_after_restart () {
    awk '/restarting in/ {seen = 1} seen && /1\/1 running, 1 reporting/ {found = 1} END {exit !found}' \
        "$TMP/run.log"
}
check "and reports health again" wait_for 20 reporting_after_restart

check "mscgs run stops by itself at --duration" wait_exit "$RUN" 40
is "$EXIT_CODE" 0 "mscgs run exits 0"
check "no service process is left" bash -c "! pgrep -f '^$BIN/uavsim '"
check "the summary counts one restart" grep -qE 'uavsim +.*1 restart' "$OUT/summary.txt"
check "the service's log is in the output folder" grep -q "exercise" "$OUT/logs/uavsim.log"
check "its state folder is in the output folder" [ -d "$OUT/state" ]
check "the service stopped cleanly on SIGTERM (no sanitizer report)" clean_log out/logs/uavsim

# The map on a port the system chooses.
STATIOND=$CGS_BUILD/bin/stationd
[ -x "$STATIOND" ] || bail "no stationd at $STATIOND"
command -v curl >/dev/null || bail "no curl"
EX2=$TMP/exercise-map.ini
{
    cat <<INI
[exercise]
id = 8
origin = geo 35.96 -121.23 0
state_dir = $TMP/state-map
INI
    exercise_service stationd params="$TMP/station-any.ini"
} >"$EX2"
printf '[http]\nlisten = 127.0.0.1\nport = 0\n' >"$TMP/station-any.ini"
start RUN2 run-map "$MSCGS" run --exercise "$EX2" --duration 12 --out "$TMP/out-map" --record
check "mscgs run says the system chooses the map's port" \
    wait_for 10 grep -q "tactical map (stationd) on a free port the system chooses" "$TMP/run-map.log"
map_url () { sed -n 's|^mscgs run: tactical map (stationd) at \(http://127\.0\.0\.1:[1-9][0-9]*/\)$|\1|p' "$TMP/run-map.log" | head -1; }
has_map_url () { [ -n "$(map_url)" ]; }
check "and then the address with the port stationd was given" wait_for 10 has_map_url
URL=$(map_url)
diag "the map: ${URL:-none}"
check "the page is served at that address" bash -c "curl -sf '${URL:-http://127.0.0.1:1/}' | grep -qi '<html'"
check "mscgs run stops at --duration" wait_exit "$RUN2" 40
is "$EXIT_CODE" 0 "mscgs run exits 0"
# --record: every topic into the output folder, closed after the services stop.
check "mscgs run --record says where it records" \
    grep -q "^mscgs run: recording every topic into $TMP/out-map/recording.mcap$" "$TMP/run-map.log"
check "and that the recording is closed" \
    grep -q "^mscgs run: recording in $TMP/out-map/recording.mcap$" "$TMP/run-map.log"
if [ -d "$CGS_ROOT/tests/interop/node_modules/@mcap/core" ]; then
    rec=$(node "$CGS_ROOT/tests/interop/mcap_check.mjs" "$TMP/out-map/recording.mcap" 2>&1)
    check "@mcap/core reads it, with stationd's health in it" \
        node -e 'const o = JSON.parse(process.argv[1]); process.exit(o.complete && o.topics.health.sources.stationd > 0 ? 0 : 1)' "$rec"
else
    check "@mcap/core is installed (npm ci in tests/interop)" false
fi

finish
