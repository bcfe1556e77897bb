#!/bin/bash
# stationd.sh — stationd's protocol without a browser, beside the real
# uavsim, mtid, trackerd and guidanced: the page's files, the relief and the
# vendored OpenLayers, milsymbol and mpegts.js are served from the build;
# pictures are pushed at push_hz with the exercise's UAV, hits and tracks; a
# WebSocket from another site's Origin is refused and counted; with a token
# configured, a page without it watches but its commands are refused with
# the reason, and one with it commands; malformed JSON, unknown ops and bad
# values get an error with the reason, are counted, and stationd keeps
# serving; the camera command reaches uavsim (its settings and a stare at a
# point come back on the picture's UAV, one outside the scenario's limits
# comes back refused with uavsim's reason), malformed camera and
# sensor-mode commands are refused by stationd, and a sensor mode for a UAV
# with no imagerd taking commands is refused saying so; a Host that is another name for a loopback server (DNS
# rebinding), messages over 4 KiB and pages beyond threads - 2 (pages and
# live-video WebSockets together) are refused and counted, and /video
# refuses another site's Origin too; the cursor's MGRS equals GeographicLib's own tools'; a command
# while guidanced is down is reported unanswered, and answered again once it
# is back; a stationd on a non-loopback address without a token, or with bad
# parameters, refuses to start naming the key; SIGTERM stops it cleanly.
# The browser itself is tests/browser/stationd.sh. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
STATIOND=$CGS_BUILD/bin/stationd
for b in "$UAVSIM" "$MTID" "$TRACKERD" "$GUIDANCED" "$STATIOND"; do [ -x "$b" ] || bail "no $b"; done
command -v node >/dev/null || bail "no node"
command -v curl >/dev/null || bail "no curl"
command -v GeoConvert >/dev/null || bail "no GeoConvert (geographiclib-tools)"
PROBE=$CGS_ROOT/tests/browser/ws_probe.js
[ -d "$CGS_ROOT/tests/browser/node_modules/ws" ] || bail "no ws package (npm ci in tests/browser)"

ORIGIN="35.96 -121.23 0"
PORT=$((20000 + RANDOM % 20000))
TOKEN=s3cret-token-1
EX=$TMP/exercise.ini
{
    exercise_header 12 station-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service trackerd
    exercise_service guidanced command
    exercise_service stationd params=station.ini
} >"$EX"
cat >"$TMP/station.ini" <<EOF
[http]
port = $PORT
token = $TOKEN
; at most 4 pages at once
threads = 6
EOF
{
    scenario_ground relief_m=300
    scenario_uav
    scenario_vehicle target hostile TARGET "5000 -4000" "5000 16000" 10
} >"$TMP/scenario.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
URL=http://127.0.0.1:$PORT
WS=ws://127.0.0.1:$PORT/ws
probe () { node "$PROBE" "$@"; }
counter () { M status 2>/dev/null | grep -o "$1=[0-9]*" | head -1 | cut -d= -f2; }
counter_ge () { local v; v=$(counter "$1"); [ "${v:-0}" -ge "$2" ]; }

# ---- refusals at start --------------------------------------------------------------
printf '[http]\nlisten = 0.0.0.0\nport = %s\n' "$PORT" >"$TMP/open.ini"
timeout 20 "$STATIOND" --exercise "$EX" --params "$TMP/open.ini" >"$TMP/open.out" 2>&1
rc=$?
check "on 0.0.0.0 without a token stationd refuses to start (exit $rc)" test "$rc" -ne 0
check "naming the file, line and key" grep -q "open.ini:2: \[http\] listen: .*needs an operators' access token" "$TMP/open.out"
: >"$TMP/empty.ini"
timeout 20 "$STATIOND" --exercise "$EX" --params "$TMP/empty.ini" --listen 0.0.0.0 --port "$PORT" \
    >"$TMP/open2.out" 2>&1
check "--listen 0.0.0.0 without a token too" bash -c "[ $? -ne 0 ] && grep -q 'needs an operators' '$TMP/open2.out'"
printf '[display]\npush_hz = 0\n' >"$TMP/bad.ini"
timeout 20 "$STATIOND" --exercise "$EX" --params "$TMP/bad.ini" --check >"$TMP/bad.out" 2>&1
check "a bad value is refused by --check with file, line and key" bash -c \
    "[ $? -ne 0 ] && grep -q 'bad.ini:2: \[display\] push_hz' '$TMP/bad.out'"
timeout 20 "$STATIOND" --exercise "$EX" --check >"$TMP/check.out" 2>&1
check "the test's own parameters pass --check" bash -c "[ $? -eq 0 ] && grep -q 'parameters are good' '$TMP/check.out'"

# ---- serving ------------------------------------------------------------------------
start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start T trackerd "$TRACKERD" --exercise "$EX"
start G guidanced "$GUIDANCED" --exercise "$EX"
start S stationd "$STATIOND" --exercise "$EX"
check "stationd serves the page" wait_for 20 curl -sf -o "$TMP/index.html" "$URL/"
check "which loads OpenLayers and milsymbol from this server only" bash -c \
    "grep -q 'vendor/ol.js' '$TMP/index.html' && grep -q 'vendor/milsymbol.js' '$TMP/index.html' && ! grep -qiE 'src=\"(https?:)?//' '$TMP/index.html'"
for f in style.css vendor/ol.js vendor/ol.css vendor/milsymbol.js vendor/mpegts.js; do
    check "/$f is served" curl -sf -o /dev/null "$URL/$f"
done
check "which loads its script as an ES module" grep -q '<script type="module" src="/js/main.js">' "$TMP/index.html"
# Every module of the page, as a browser loads a module: text/javascript.
for m in "$CGS_ROOT"/services/stationd/web/js/*.js; do
    f=js/$(basename "$m")
    check "/$f is served as text/javascript" bash -c \
        "curl -sf -o /dev/null -w '%{content_type}' '$URL/$f' | grep -q '^text/javascript'"
done
curl -sf -o "$TMP/relief.png" "$URL/relief.png"
check "/relief.png is a PNG of the terrain" bash -c "file '$TMP/relief.png' | grep -q 'PNG image data, 401 x 401'"
check "no folder listing" bash -c "[ \"\$(curl -s -o /dev/null -w '%{http_code}' '$URL/vendor/')\" != 200 ]"

probe "$WS" --seconds 3 >"$TMP/view.jsonl"
hello=$(grep -m1 '"type":"hello"' "$TMP/view.jsonl")
check "a page without the token gets a hello that says it only watches" bash -c \
    "grep -q '\"operator\":false' <<<'$hello' && grep -q '\"token_required\":true' <<<'$hello'"
check "and the relief's extent (the grid's outer pixel edges)" \
    grep -q '"extent":\[-20050,-20050,20050,20050\]' <<<"$hello"
# (The push rate itself is measured by bench_stationd, not timed here.)
check "pictures keep coming, numbered in order" node -e '
    const seqs = require("fs").readFileSync(process.argv[1], "utf8").split("\n").filter((l) => l.includes("\"type\":\"state\""))
        .map((l) => JSON.parse(l).seq);
    process.exit(seqs.length >= 3 && seqs.every((s, i) => i === 0 || s > seqs[i - 1]) ? 0 : 1);' "$TMP/view.jsonl"
check "with the UAV and the target's hits" wait_for 30 bash -c \
    "node '$PROBE' '$WS' --seconds 1 | grep '\"type\":\"state\"' | tail -1 | grep -q '\"uavs\":1,.*' &&
     node '$PROBE' '$WS' --seconds 1 | grep '\"type\":\"state\"' | tail -1 | grep -qv '\"hits\":0,'"

# ---- access -------------------------------------------------------------------------
probe "$WS" --send '{"op":"cancel","req":1}' --replies 1 >"$TMP/noauth.jsonl"
check "a command without the token is refused with the reason" \
    grep -q '"req":1,"op":"cancel","ok":false,"error":"commands need the operators'"'"' access token' "$TMP/noauth.jsonl"
probe "$WS" --origin "http://evil.example" --seconds 2 >"$TMP/evil.jsonl"
check "a WebSocket from another site's Origin is refused" grep -q '"type":"connect-error"' "$TMP/evil.jsonl"
probe "$WS" --host "evil.example:$PORT" --origin "http://evil.example:$PORT" --seconds 2 >"$TMP/rebind.jsonl"
check "and one whose Host is another name for this loopback server (DNS rebinding)" \
    grep -q '"type":"connect-error"' "$TMP/rebind.jsonl"
probe "$WS" --host "localhost:$PORT" --origin "http://localhost:$PORT" --seconds 1 >"$TMP/localhost.jsonl"
check "while localhost:PORT is this server" grep -q '"type":"hello"' "$TMP/localhost.jsonl"
held=()
for i in 1 2 3 4; do
    node "$PROBE" "$WS" --seconds 6 >"$TMP/held$i.jsonl" &
    held+=($!)
done
wait_for 5 bash -c "[ \$(cat '$TMP'/held?.jsonl | grep -c '\"type\":\"hello\"') -eq 4 ]"
probe "$WS" --seconds 2 >"$TMP/fifth.jsonl"
check "a fifth page is refused while 4 (threads - 2) are open" grep -q '"type":"connect-error"' "$TMP/fifth.jsonl"
check "and counted" wait_for 10 counter_ge pages_refused_full 1
wait "${held[@]}"
# The live video's WebSocket: the same Origin check, and the same limit
# (each holds a thread): two pages and two video pages fill it.
VIDEO=ws://127.0.0.1:$PORT/video
probe "$VIDEO" --origin "http://evil.example" --seconds 2 >"$TMP/video-evil.jsonl"
check "a /video WebSocket from another site's Origin is refused" grep -q '"type":"connect-error"' "$TMP/video-evil.jsonl"
held=()
for i in 1 2; do
    node "$PROBE" "$WS" --seconds 6 >"$TMP/mixed-ws$i.jsonl" &
    held+=($!)
    node "$PROBE" "$VIDEO" --origin "http://127.0.0.1:$PORT" --seconds 6 >"$TMP/mixed-video$i.jsonl" &
    held+=($!)
done
wait_for 5 counter_ge video_pages 2
probe "$VIDEO" --seconds 2 >"$TMP/video-fifth.jsonl"
check "a /video WebSocket is refused while 2 pages and 2 video pages are open" \
    grep -q '"type":"connect-error"' "$TMP/video-fifth.jsonl"
probe "$WS" --seconds 2 >"$TMP/ws-fifth.jsonl"
check "and so is a page" grep -q '"type":"connect-error"' "$TMP/ws-fifth.jsonl"
wait "${held[@]}"
check "the video pages were open (no connect error), and counted" bash -c \
    "! grep -q connect-error '$TMP'/mixed-video?.jsonl && ! grep -q connect-error '$TMP'/mixed-ws?.jsonl"
check "in health: video_pages_total" counter_ge video_pages_total 2
probe "$WS?token=$TOKEN" --origin "http://127.0.0.1:$PORT" \
    --send '{"op":"footprint_scale","req":2,"value":5}' --replies 1 >"$TMP/auth.jsonl"
check "with the token (and this server's Origin) the page is an operator's" grep -q '"operator":true' "$TMP/auth.jsonl"
check "and its footprint scale reaches guidanced, which takes it" \
    grep -q '"req":2,"op":"footprint_scale","ok":true,"server":"guidanced"' "$TMP/auth.jsonl"
probe "$WS?token=wrong-token-9" --send '{"op":"cancel","req":3}' --replies 1 >"$TMP/wrong.jsonl"
check "a wrong token is no token" grep -q '"req":3,.*"ok":false' "$TMP/wrong.jsonl"

# ---- bad requests -------------------------------------------------------------------
probe "$WS?token=$TOKEN" --send 'not json' --send '[1,2]' --send '{"op":"fly-away","req":4}' \
    --send '{"op":"designate","req":5,"e":"x","n":1}' --send '{"op":"footprint_scale","req":6,"value":2.5}' \
    --send '{"op":"intercept_mode","req":7,"value":"sideways"}' --send '{"op":"altitude","req":8,"value":-50}' \
    --send '{"op":"designate","req":9,"uav_id":-1,"e":0,"n":0}' --send '{"op":"cancel","req":10,"uav_id":"1"}' \
    --send '{"op":"designate","req":11,"hit":2.5,"radar":1}' \
    --send '{"op":"designate","req":12,"hit":5,"radar":"uav1"}' \
    --send '{"op":"camera","req":13,"fov":"wide"}' --send '{"op":"camera","req":14,"uav_id":1}' \
    --send '{"op":"camera","req":15,"stare":{"e":1}}' --send '{"op":"camera","req":16,"depression":95}' \
    --send '{"op":"sensor_mode","req":17,"mode":"x-ray"}' \
    --send-size 5000 --replies 17 >"$TMP/bad.jsonl"
check "malformed JSON gets an error" bash -c "[ \$(grep -c '\"type\":\"error\",\"error\":\"expected a JSON object' '$TMP/bad.jsonl') -eq 2 ]"
check "an unknown op gets an error naming it" grep -q 'unknown op \\"fly-away\\"' "$TMP/bad.jsonl"
check "designate without numbers is refused with the reason" grep -q '"req":5,.*"error":"designate needs the clicked hit (hit, radar) or a point (e, n)' "$TMP/bad.jsonl"
check "designate of a hit id that is not whole is refused" grep -q '"req":11,.*"error":"designate: hit and radar must be whole numbers' "$TMP/bad.jsonl"
check "so is a radar that is not a number (never taken as any radar)" grep -q '"req":12,.*"error":"designate: hit and radar must be whole numbers' "$TMP/bad.jsonl"
check "a footprint scale that is not whole is refused" grep -q '"req":6,.*"ok":false' "$TMP/bad.jsonl"
check "an unknown intercept method is refused" grep -q '"req":7,.*"error":"intercept_mode needs the value' "$TMP/bad.jsonl"
check "uavsim's own reason comes back for a bad altitude" \
    grep -q '"req":8,"op":"altitude","ok":false,"server":"uavsim","error":"altitude must be' "$TMP/bad.jsonl"
check "a negative UAV id is refused" grep -q '"req":9,.*"error":"uav_id must be' "$TMP/bad.jsonl"
check "so is one that is not a number, never taken as the only UAV" grep -q '"req":10,.*"error":"uav_id must be' "$TMP/bad.jsonl"
check "a camera command with a field of view that is not a number is refused, saying which" \
    grep -q '"req":13,"op":"camera","ok":false,"error":"camera: fov' "$TMP/bad.jsonl"
check "so is one that sets nothing" grep -q '"req":14,.*"error":"camera needs at least one of depression, fov, stabilized, stare' "$TMP/bad.jsonl"
check "and a stare point without its north" grep -q '"req":15,.*"error":"camera: stare must be' "$TMP/bad.jsonl"
check "and a depression beyond 90 degrees" grep -q '"req":16,.*"error":"camera: depression must be' "$TMP/bad.jsonl"
check "an unknown sensor mode is refused" grep -q '"req":17,"op":"sensor_mode","ok":false,"error":"sensor_mode needs the mode' "$TMP/bad.jsonl"
check "a message over 4096 bytes is refused unread" grep -q '"error":"a message must be one text frame of at most 4096 bytes"' "$TMP/bad.jsonl"
check "stationd counts them in health" wait_for 10 counter_ge bad_requests 13
check "the oversized one apart" counter_ge oversized_requests 1
check "and the unauthorised command" counter_ge unauthorised 2
check "and the refused Origin" counter_ge origin_refused 1
check "and keeps serving" bash -c "node '$PROBE' '$WS' --seconds 1 | grep -q '\"type\":\"state\"'"

# ---- the camera and the sensor mode ---------------------------------------------------
# uav_has PATTERN: the first UAV of the next picture (its JSON) matches PATTERN.
uav_has () {
    node -e '
        const WebSocket = require(process.argv[1]);
        const ws = new WebSocket(process.argv[2]);
        setTimeout(() => process.exit(1), 5000);
        ws.on("error", () => process.exit(2));
        ws.on("message", (d) => {
            const m = JSON.parse(d.toString());
            if (m.type !== "state" || !m.uavs.length) return;
            console.log(JSON.stringify(m.uavs[0]));
            process.exit(0);
        });' "$CGS_ROOT/tests/browser/node_modules/ws" "$WS" | tee "$TMP/uav.json" | grep -q "$1"
}
check "the picture's UAV carries its camera, not staring, and no sensor mode without an imagerd" \
    uav_has '"camera":{"depression_deg":[0-9.]*,"hfov_deg":[0-9.]*,"vfov_deg":[0-9.]*,"stabilized":false,"stare":"off","stare_point":null,"staring":false,"at_gimbal_limit":false,.*"sensor_mode":null'
diag "$(cat "$TMP/uav.json")"
probe "$WS?token=$TOKEN" --origin "http://127.0.0.1:$PORT" \
    --send '{"op":"camera","req":20,"uav_id":1,"depression":30,"fov":6,"stabilized":true}' \
    --send '{"op":"camera","req":21,"uav_id":1,"stare":{"e":150,"n":-250}}' \
    --send '{"op":"sensor_mode","req":22,"uav_id":1,"mode":"sar"}' --replies 3 --seconds 15 >"$TMP/camera.jsonl"
while IFS= read -r line; do diag "$line"; done < <(grep '"type":"reply"' "$TMP/camera.jsonl")
check "a camera command reaches uavsim, which takes it" \
    grep -q '"req":20,"op":"camera","ok":true,"server":"uavsim","detail":"camera of uav1: depression 30.0 deg, field of view 6.00 x 4.50 deg, stabilized' "$TMP/camera.jsonl"
check "and the picture's UAV carries the new settings" wait_for 10 uav_has \
    '"camera":{"depression_deg":30,"hfov_deg":6,"vfov_deg":4.5,"stabilized":true,'
check "a stare at a point is taken" grep -q '"req":21,"op":"camera","ok":true,"server":"uavsim",.*staring at a point' "$TMP/camera.jsonl"
check "and the camera stares there" wait_for 15 uav_has '"stare":"point","stare_point":\[150,-250\],"staring":true,"at_gimbal_limit":false'
check "a sensor mode without an imagerd for the UAV is refused, saying so" \
    grep -q '"req":22,"op":"sensor_mode","ok":false,"error":"the exercise has no imagerd for uav1 that takes commands' "$TMP/camera.jsonl"
check "counted: commands_ok and commands_unanswered" wait_for 10 bash -c \
    "[ \$('$MSCGS' status --exercise '$EX' 2>/dev/null | grep -o 'commands_ok=[0-9]*' | head -1 | cut -d= -f2) -ge 3 ]"
probe "$WS" --send '{"op":"camera","req":23,"uav_id":1,"stare":"off"}' \
    --send '{"op":"sensor_mode","req":24,"uav_id":1,"mode":"infrared"}' --replies 2 >"$TMP/camera-view.jsonl"
check "without the token camera and sensor-mode commands are refused" bash -c \
    "[ \$(grep -c '\"ok\":false,\"error\":\"commands need the operators' '$TMP/camera-view.jsonl') -eq 2 ]"
probe "$WS?token=$TOKEN" --origin "http://127.0.0.1:$PORT" \
    --send '{"op":"camera","req":25,"uav_id":1,"depression":1}' --replies 1 >"$TMP/camera-low.jsonl"
check "a depression under the scenario's least comes back refused with uavsim's reason" \
    grep -q '"req":25,"op":"camera","ok":false,"server":"uavsim","error":".*outside the scenario' "$TMP/camera-low.jsonl"

# ---- MGRS against GeographicLib's tools --------------------------------------------
for pt in "1234.5 -6789.2" "-15000 12000" "0 0"; do
    read -r e n <<<"$pt"
    probe "$WS" --send "{\"op\":\"mgrs\",\"req\":1,\"e\":$e,\"n\":$n}" --replies 1 >"$TMP/mgrs.jsonl"
    got=$(sed -n 's/.*"mgrs":"\([0-9A-Z]*\)".*/\1/p' "$TMP/mgrs.jsonl")
    want=$(CartConvert -r -l $ORIGIN -p 9 <<<"$e $n 0" | awk '{print $1, $2}' | GeoConvert -m -p 0)
    is "$got" "$want" "MGRS of ($e, $n) is GeoConvert's"
done

# ---- guidanced down and back ---------------------------------------------------------
kill9 "$G"
t0=$SECONDS
probe "$WS?token=$TOKEN" --send '{"op":"cancel","req":10}' --replies 1 --seconds 15 >"$TMP/down.jsonl"
check "with guidanced down a command is reported unanswered, naming the endpoint" \
    grep -q '"req":10,.*"ok":false,"error":".*guidanced.cmd' "$TMP/down.jsonl"
check "after the tries (3 of 1 s), not sooner than 2 s: $((SECONDS - t0)) s" test $((SECONDS - t0)) -ge 2
check "counted unanswered" wait_for 5 counter_ge commands_unanswered 1
check "stationd kept pushing meanwhile" bash -c "node '$PROBE' '$WS' --seconds 1 | grep -q '\"type\":\"state\"'"
start G guidanced "$GUIDANCED" --exercise "$EX"
check "guidanced back: commands are answered again" wait_for 20 bash -c \
    "node '$PROBE' '$WS?token=$TOKEN' --send '{\"op\":\"footprint_scale\",\"req\":11,\"value\":1}' --replies 1 --seconds 5 | grep -q '\"req\":11,.*\"ok\":true'"

stop "$S"
is "$EXIT_CODE" 0 "stationd stops on SIGTERM with exit 0"
check "its log is clean" clean_log stationd
check "and gives its totals" grep -q 'pages served, .* pictures pushed' "$TMP/stationd.log"
finish
