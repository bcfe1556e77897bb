#!/bin/bash
# stationd.sh — the tactical map end to end: the real uavsim, mtid, bcisd,
# trackerd, guidanced and imagerd of a small exercise, two real stationd
# (one open to every local page, one that needs an operators' token), and
# Debian's Chromium driving the page (stationd.js, playwright-core). It
# checks that the page loads clean with its shaded relief; MTI hits, tracks
# and a BCIS reply appear; clicking the newest hit of an unknown track
# designates that track and the purple route is drawn (and hidden on
# request); the status panel follows the intercept; Cancel Intercept sends
# the UAV back to loiter; a refused command shows uavsim's reason; two
# browsers get the same pictures; a page without the token only watches and
# a page with it commands; the cursor's MGRS agrees with GeographicLib's
# command-line tools; the sensor image loads; the live video plays in the
# imaging-sensor panel (or, where this Chromium cannot play H.264 through
# MSE, the picture shows and says so), its KLV footprint agrees with the
# image message's, its delay from the bus to the screen is measured, a page
# that stops reading is dropped to the next keyframe and counted, and a
# foreign Origin is refused on /video; the Sensors menu switches imagerd to
# FLIR and SAR and the status follows the frames, the camera panel sets the
# depression, zoom, stabilization and a stare at a clicked point (and a
# watching page cannot). Also: a stationd told to listen
# on 0.0.0.0 without a token refuses to start, naming the key; both
# stationd stop with exit code 0 and clean logs. Screenshots of every step go
# to $CGS_BUILD/test-artifacts/browser/NN-step.png. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/../integration/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
BCISD=$CGS_BUILD/bin/bcisd
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
IMAGERD=$CGS_BUILD/bin/imagerd
STATIOND=$CGS_BUILD/bin/stationd
for b in "$UAVSIM" "$MTID" "$BCISD" "$TRACKERD" "$GUIDANCED" "$IMAGERD" "$STATIOND"; do
    [ -x "$b" ] || bail "no $b"
done
[ -f "$CGS_BUILD/web/js/main.js" ] || bail "no page at $CGS_BUILD/web (make test-build)"
command -v node >/dev/null || bail "no node"
for t in CartConvert GeoConvert; do
    command -v $t >/dev/null || bail "no $t (geographiclib-tools)"
done
CHROMIUM=${CGS_CHROMIUM:-/usr/bin/chromium}
[ -x "$CHROMIUM" ] || bail "no Chromium at $CHROMIUM (scripts/install-deps installs it)"
BROWSER_DIR=$(cd "$(dirname "$0")" && pwd)
[ -d "$BROWSER_DIR/node_modules/playwright-core" ] || bail "no playwright-core (npm ci in tests/browser)"
ART=$CGS_BUILD/test-artifacts/browser
mkdir -p "$ART" || bail "cannot make $ART"
rm -f "$ART"/[0-9][0-9]-*.png

ORIGIN="35.96 -121.23 0"
TOKEN=s3cret-token-1

# A free TCP port on loopback, at random like gateway.sh's, other than $1.
free_port () {
    local p
    for _ in $(seq 1 50); do
        p=$((20000 + RANDOM % 20000))
        [ "$p" = "${1:-}" ] && continue
        # Nobody answers a connection there.
        (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null || { echo "$p"; return 0; }
    done
    return 1
}
PORT=$(free_port) || bail "no free TCP port"
PORT_TOK=$(free_port "$PORT") || bail "no second free TCP port"

EX=$TMP/exercise.ini
{
    exercise_header 13 stationd-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service bcisd.uav1 uav=uav1
    exercise_service trackerd
    exercise_service guidanced command
    exercise_service imagerd.uav1 command uav=uav1 params=imager.ini
    exercise_service stationd
    exercise_service stationd.op publish="ipc://$TMP/stationd-op.pub" params=token.ini
    exercise_service stationd.open publish="ipc://$TMP/stationd-open.pub" params=open.ini
} >"$EX"
# Gentle hills; the UAV circles the origin; hostile and unknown movers 5 to
# 8 km out, each on its own road far from the others; a friendly truck with
# a BCIS transponder (friendlies carry one) 4 km south.
cat >"$TMP/scenario.ini" <<'EOF'
[terrain]
size_m = 30000
resolution_m = 100
relief_m = 150
base_height_m = 300
feature_m = 6000
octaves = 4

[uav uav1]
position = 0 0
altitude_agl_m = 1200
airspeed_mps = 38
loiter_radius_m = 1500

[vehicle target]
force = hostile
marking = TARGET
point = 6000 -6000
point = 6000 12000
speed_mps = 10
end = stop

[vehicle other]
force = unknown
marking = OTHER
point = -6000 -6000
point = -6000 12000
speed_mps = 8
end = stop

[vehicle raider]
force = hostile
marking = RAIDER
point = -3000 8000
point = 3000 8000
speed_mps = 7
end = reverse

[vehicle truck]
force = friendly
kind = wheeled
marking = FRIEND TRK
point = -3000 -4000
point = 3000 -4000
speed_mps = 9
end = reverse
EOF
# A smaller, slower sensor image, so imagerd keeps up under the sanitizers.
sed -e 's/^width_px = 640$/width_px = 320/' -e 's/^height_px = 480$/height_px = 240/' \
    -e 's/^frame_rate_hz = 5$/frame_rate_hz = 1/' \
    "$CGS_ROOT/deploy/params/imager.ini" >"$TMP/imager.ini"
printf '[http]\ntoken = %s\n' "$TOKEN" >"$TMP/token.ini"
printf '[http]\nlisten = 0.0.0.0\n' >"$TMP/open.ini"

# ---- a stationd open to the network without a token refuses to start --------------------
start O stationd-open "$STATIOND" --exercise "$EX" --instance stationd.open --port 0
wait_exit "$O" 20
check "stationd with listen = 0.0.0.0 and no token refuses to start (exit ${EXIT_CODE})" \
    test "$EXIT_CODE" != 0 -a "$EXIT_CODE" != timeout
diag "$(grep -m1 -i 'token' "$TMP/stationd-open.log")"
check "saying why, naming the file, the key and the token keys" grep -q \
    "open.ini:2: \[http\] listen: .*0\.0\.0\.0.*needs an operators' access token.*token" \
    "$TMP/stationd-open.log"

# ---- the exercise --------------------------------------------------------------------------
start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 10
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start B bcisd "$BCISD" --exercise "$EX" --instance bcisd.uav1
start T trackerd "$TRACKERD" --exercise "$EX"
start G guidanced "$GUIDANCED" --exercise "$EX"
start I imagerd "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$TMP/images"
start S stationd "$STATIOND" --exercise "$EX" --port "$PORT" --listen 127.0.0.1
start S2 stationd-op "$STATIOND" --exercise "$EX" --instance stationd.op --port "$PORT_TOK"

page_up () { curl -sf -o /dev/null "http://127.0.0.1:$1/"; }
check "stationd serves the page on port $PORT" wait_for 30 page_up "$PORT"
check "the token stationd serves it on port $PORT_TOK" wait_for 30 page_up "$PORT_TOK"
{ running "$S" && running "$S2"; } || bail "stationd did not stay up"

# ---- the browser ---------------------------------------------------------------------------
# stationd.js prints "ok - NAME", "not ok - NAME" and "# ..." lines; they
# are numbered here, in order.
start N browser node "$BROWSER_DIR/stationd.js" \
    --url "http://127.0.0.1:$PORT/" --token-url "http://127.0.0.1:$PORT_TOK/" \
    --token "$TOKEN" --origin "$ORIGIN" --chromium "$CHROMIUM" --artifacts "$ART" \
    --exercise "$EX" --mscgs "$MSCGS"
wait_exit "$N" 240 || stop "$N"
browser_rc=$EXIT_CODE
relay "$TMP/browser.log"
is "$browser_rc" 0 "the browser script ran to its end"
n_png=$(find "$ART" -name '[0-9][0-9]-*.png' | wc -l)
diag "screenshots in $ART: $n_png"
check "it kept a screenshot of every step ($n_png)" test "$n_png" -ge 10

# ---- stopping ------------------------------------------------------------------------------
stop "$S2"
is "$EXIT_CODE" 0 "the token stationd stops on SIGTERM with exit code 0"
stop "$S"
is "$EXIT_CODE" 0 "stationd stops on SIGTERM with exit code 0"
for p in "$I" "$G" "$T" "$B" "$R" "$U"; do stop "$p"; done
for log in stationd stationd-op stationd-open; do
    check "no sanitizer report in $log" clean_log $log
done
check "no warning or error in stationd's log" bash -c "! grep -E '^<[0-4]>' '$TMP/stationd.log'"
finish
