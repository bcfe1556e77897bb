#!/bin/bash
# replay.sh — `mscgs replay` end to end. A short exercise of the default
# scenario (the real uavsim, mtid, bcisd, trackerd and guidanced; the
# scenario's operator designates at t = 120 s) is recorded with
# `mscgs record`. Then:
#  - refusals: a file that is not MCAP, the recorded exercise's own id, a
#    start past the end; a live uavsim answers `mscgs seek` as unsupported;
#  - exactness: the recording replayed (started paused, resumed by
#    `mscgs resume`) into a bus of its own and recorded again by a second
#    `mscgs record` is the same messages, field for field, but for the
#    header's exercise id (mcap_same.mjs: @mcap/core and protobufjs, nothing
#    of mscgs); an operator's command to the replay (`mscgs designate`) is
#    refused, saying it reaches nothing;
#  - the map: `mscgs replay --station PORT` starts a stationd on the replay,
#    and Debian's Chromium drives its timeline (replay.js: marks, pause,
#    speed, seek forward and back); a designation sent on the page's
#    WebSocket is refused by stationd.
# TAP on stdout. Screenshots to $CGS_BUILD/test-artifacts/browser-replay.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/../integration/lib.sh"

for p in uavsim mtid bcisd trackerd guidanced stationd mscgs; do
    [ -x "$CGS_BUILD/bin/$p" ] || bail "no $p"
done
[ -f "$CGS_BUILD/web/js/timeline.js" ] || bail "no page at $CGS_BUILD/web (make test-build)"
command -v node >/dev/null || bail "no node (scripts/install-deps installs it)"
INTEROP=$CGS_ROOT/tests/interop
[ -d "$INTEROP/node_modules/@mcap/core" ] || bail "no @mcap/core (npm ci in tests/interop)"
BROWSER_DIR=$(cd "$(dirname "$0")" && pwd)
[ -d "$BROWSER_DIR/node_modules/playwright-core" ] || bail "no playwright-core (npm ci in tests/browser)"
CHROMIUM=${CGS_CHROMIUM:-/usr/bin/chromium}
[ -x "$CHROMIUM" ] || bail "no Chromium at $CHROMIUM (scripts/install-deps installs it)"
ART=$CGS_BUILD/test-artifacts/browser-replay
mkdir -p "$ART" && rm -f "$ART"/[0-9][0-9]-*.png

EX=$TMP/exercise.ini
exercise_scene 19 replay-test "$CGS_ROOT/deploy/scenarios/default.ini" >"$EX"
MCAP=$TMP/run.mcap

# ---- the recording -------------------------------------------------------------------------
start REC record "$MSCGS" record --exercise "$EX" --out "$MCAP"
start E echo-intercept "$MSCGS" echo intercept --json --exercise "$EX"
sleep 1
start U uavsim "$CGS_BUILD/bin/uavsim" --exercise "$EX" --time-scale 10
start R mtid "$CGS_BUILD/bin/mtid" --exercise "$EX" --instance mtid.uav1
start B bcisd "$CGS_BUILD/bin/bcisd" --exercise "$EX" --instance bcisd.uav1
start T trackerd "$CGS_BUILD/bin/trackerd" --exercise "$EX"
start G guidanced "$CGS_BUILD/bin/guidanced" --exercise "$EX"
designated () { grep -q '"track_id":[1-9]' "$TMP/echo-intercept.log"; }
check "the scenario's operator designates a track (t = 120 s)" wait_for 90 designated
said=$("$MSCGS" seek 5 --exercise "$EX" --wait 2 2>&1)
is "$?" 1 "a live uavsim refuses \`mscgs seek\`"
check "as a command it does not take ($said)" grep -q "does not handle seek" <<<"$said"
sleep 10 # the intercept goes on a while after the designation
for p in $G $T $B $R $U $E; do stop "$p"; done
stop "$REC"
is "$EXIT_CODE" 0 "the recorder stops with exit code 0"
recorded=$(sed -n 's/.*mscgs record: \([0-9]*\) messages in .*/\1/p' "$TMP/record.log")
diag "recorded: $(grep 'messages in' "$TMP/record.log" | head -c 400)"

# ---- refusals ------------------------------------------------------------------------------
printf 'not an mcap file\n' >"$TMP/not.mcap"
said=$("$MSCGS" replay "$TMP/not.mcap" --exercise "$EX" 2>&1)
is "$?" 1 "a file that is not MCAP is refused (exit 1)"
check "saying so" grep -q "not an MCAP file" <<<"$said"
said=$("$MSCGS" replay "$MCAP" --exercise "$EX" --id 19 2>&1)
is "$?" 2 "a replay in the recorded exercise's own id is refused (exit 2)"
check "saying a replay has its own" grep -q "a replay has its own" <<<"$said"
said=$("$MSCGS" replay "$MCAP" --exercise "$EX" --from 100000 2>&1)
is "$?" 2 "a start past the end is refused (exit 2)"
check "giving the recording's length" grep -q "the recording is [0-9.]* s long" <<<"$said"

# ---- exactness: replayed and recorded again ------------------------------------------------
REX=$TMP/replay.ini
start P replay "$MSCGS" replay "$MCAP" --exercise "$EX" --live none --paused --once --speed 20 \
    --dir "$TMP/rdir" --replay-exercise "$REX"
check "the replay writes its exercise" wait_for 20 grep -q "standing in for 5 services" "$TMP/replay.log"
check "its own id (19 + 100)" grep -q "^id = 119$" "$REX"
start Q record-again "$MSCGS" record --exercise "$REX" --out "$TMP/again.mcap"
check "a recorder listens to the replay" wait_for 10 grep -q "topics from 6 services" "$TMP/record-again.log"
sleep 1
said=$("$MSCGS" designate 1 --exercise "$REX" --wait 2 2>&1)
is "$?" 1 "an operator's command to a replay is refused"
check "it reaches nothing ($said)" grep -q "reaches nothing" <<<"$said"
said=$("$MSCGS" resume --exercise "$REX" 2>&1)
is "$?" 0 "\`mscgs resume\` starts the paused replay ($said)"
wait_exit "$P" 120
is "$EXIT_CODE" 0 "the replay ends (--once) with exit code 0"
check "having sent every recorded message ($recorded)" \
    grep -q "mscgs replay: $recorded messages sent" "$TMP/replay.log"
sleep 0.5
stop "$Q"
node "$INTEROP/mcap_same.mjs" "$MCAP" "$TMP/again.mcap" --ignore replay >"$TMP/same.json" 2>"$TMP/same.err"
same_rc=$?
diag "$(head -c 600 "$TMP/same.json") $(head -c 300 "$TMP/same.err")"
is "$same_rc" 0 "the replay recorded again is the same messages, field for field, but for the exercise id"
q () { node -e 'const o = JSON.parse(require("fs").readFileSync(process.argv[1])); console.log(eval(process.argv[2]))' "$TMP/same.json" "$1"; }
is "$(q 'o.same')" "$recorded" "all $recorded of them"
check "and the \`replay\` topic was heard" grep -q "replay [1-9]" "$TMP/record-again.log"

# ---- the map, its timeline in Chromium -----------------------------------------------------
free_port () {
    local p
    for _ in $(seq 1 50); do
        p=$((20000 + RANDOM % 20000))
        (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null || { echo "$p"; return 0; }
    done
    return 1
}
PORT=$(free_port) || bail "no free TCP port"
# Slow (0.5x), so that the seeks land before the end.
start M replay-map "$MSCGS" replay "$MCAP" --exercise "$EX" --station "$PORT" --speed 0.5 \
    --dir "$TMP/rdir2" --replay-exercise "$TMP/replay-map.ini" --id 121
page_up () { curl -sf -o /dev/null "http://127.0.0.1:$PORT/"; }
check "the replay's stationd serves the map on port $PORT" wait_for 30 page_up
check "it is a stationd of the replay exercise" grep -q "exercise replay-test-replay (id 121)" \
    "$TMP/rdir2/stationd.log"
node "$BROWSER_DIR/ws_probe.js" "ws://127.0.0.1:$PORT/ws" --origin "http://127.0.0.1:$PORT" \
    --send '{"op":"designate","req":7,"track_id":1}' --replies 1 --seconds 10 >"$TMP/probe.out" 2>&1
check "a designation on the page's WebSocket is refused by stationd in a replay" \
    grep -q '"ok":false.*reaches nothing' "$TMP/probe.out"
start N browser node "$BROWSER_DIR/replay.js" --url "http://127.0.0.1:$PORT/" --chromium "$CHROMIUM" \
    --artifacts "$ART"
wait_exit "$N" 180 || stop "$N"
browser_rc=$EXIT_CODE
relay "$TMP/browser.log"
is "$browser_rc" 0 "the browser script ran to its end"
stop "$M"
is "$EXIT_CODE" 0 "the replay stops on SIGTERM with exit code 0 (its stationd with it)"
check "no sanitizer report in the replays' logs" clean_log replay
check "no sanitizer report in the map's replay" clean_log replay-map
check "no sanitizer report in the replay's stationd" \
    bash -c "! grep -qE 'ERROR: AddressSanitizer|runtime error|LeakSanitizer' '$TMP/rdir2/stationd.log'"
finish
