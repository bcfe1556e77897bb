#!/bin/bash
# imagerd.sh — the real imagerd beside the real uavsim, on both render
# backends: it publishes `image` frames with a growing frame number, the
# camera at the UAV and the footprint on the ground; keeps latest.png in
# its output folder; writes snapshot files when asked (mscgs snapshot) and
# everything queued before it stops; refuses a GALLIUM_DRIVER that would
# crash Mesa, a missing DEM and malformed parameters with the reason, before
# it touches the bus. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
IMAGERD=$CGS_BUILD/bin/imagerd
[ -x "$UAVSIM" ] || bail "no uavsim at $UAVSIM"
[ -x "$IMAGERD" ] || bail "no imagerd at $IMAGERD"
# The other backend's imagerd, built beside the tests (make test-build).
ALT=$(ls "$CGS_BUILD"/bin-*/imagerd 2>/dev/null | head -1)

EX=$TMP/exercise.ini
{
    exercise_header 8 imagerd-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service imagerd.uav1 command uav=uav1 params=imager.ini
} >"$EX"
{
    scenario_ground size_m=12000 resolution_m=50 relief_m=150
    scenario_uav altitude_agl_m=1000 airspeed_mps=30 loiter_radius_m=900
    cat <<'EOF'

[vehicle apc]
force = hostile
kind = tracked
point = 0 1200
point = 0 3000
speed_mps = 8
end = reverse
EOF
} >"$TMP/scenario.ini"
sed -e 's/^width_px = 640$/width_px = 320/' -e 's/^height_px = 480$/height_px = 240/' \
    "$CGS_ROOT/deploy/params/imager.ini" >"$TMP/imager.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
num () { sed -n "s/.*\"$2\":\"\{0,1\}\([-0-9.e]*\).*/\1/p" <<<"$1" | head -1; }

start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 5
start I1 imagerd-1 "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$TMP/images"
check "imagerd publishes frames" wait_for 30 bash -c \
    "'$MSCGS' echo image --count 1 --timeout 2 --exercise '$EX' >/dev/null 2>&1"
M echo image --json --count 6 --timeout 20 >"$TMP/image.json" 2>/dev/null
n=$(wc -l <"$TMP/image.json")
check "six frames in a row ($n)" test "$n" -ge 6
first=$(num "$(head -1 "$TMP/image.json")" frame_number)
last=$(num "$(tail -1 "$TMP/image.json")" frame_number)
check "their frame numbers grow ($first .. $last)" test "$last" -gt "$first"
check "each carries the image's size" grep -q '"width_px":320,"height_px":240' "$TMP/image.json"
points=$(head -1 "$TMP/image.json" | grep -o '"east_m"' | wc -l)
check "a camera position, four footprint corners and a centre ($points points)" \
    test "$points" -ge 6
m=$(head -1 "$TMP/image.json")
pitch=$(sed -n 's/.*"pitch_deg":\([-0-9.e]*\).*/\1/p' <<<"$m")
diag "camera pitch $pitch"
check "the boresight looks about 45 degrees down" \
    awk -v p="$pitch" 'BEGIN { exit !(p < -35 && p > -55) }'
check "latest.png appears in the output folder" wait_for 20 test -s "$TMP/images/latest.png"
check "and is a PNG" bash -c "head -c 4 '$TMP/images/latest.png' | grep -q PNG"
out=$(M snapshot 3 2>&1)
diag "$out"
check "mscgs snapshot 3 is acknowledged" grep -q 'next 3 frames' <<<"$out"
check "three snapshot files are written" wait_for 20 bash -c \
    "test \$(ls '$TMP/images' | grep -c '^snapshot-.*\.png$') -ge 3"
check "no half-written file is left" bash -c "! ls '$TMP/images' | grep -q '\.tmp$'"
out=$(M snapshot 5000 2>&1)
check "a snapshot of 5000 frames is refused with the limit" grep -q 'at most 1000 frames' <<<"$out"
M snapshot 0 >"$TMP/snap0.log" 2>&1
is "$?" 2 "a snapshot of 0 frames is refused (exit 2)"
check "saying what it takes" grep -q '1 frame at least' "$TMP/snap0.log"
stop "$I1"
is "$EXIT_CODE" 0 "imagerd stops on SIGTERM with exit code 0"
check "no sanitizer report from imagerd" clean_log imagerd-1

if [ -n "$ALT" ]; then
    diag "the other backend: $ALT"
    start I2 imagerd-2 "$ALT" --exercise "$EX" --instance imagerd.uav1 --out "$TMP/images2"
    check "imagerd on the other backend publishes frames" wait_for 30 bash -c \
        "'$MSCGS' echo image --count 2 --timeout 2 --exercise '$EX' >/dev/null 2>&1"
    check "and keeps latest.png" wait_for 20 test -s "$TMP/images2/latest.png"
    stop "$I2"
    is "$EXIT_CODE" 0 "it stops on SIGTERM with exit code 0"
    check "no sanitizer report from it" clean_log imagerd-2
else
    check "the other backend's imagerd is built (make test-build)" false
fi
stop "$U"

# Refusals, before the bus.
GALLIUM_DRIVER=zink "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$TMP/x" \
    >"$TMP/zink.log" 2>&1
is "$?" 1 "imagerd refuses GALLIUM_DRIVER=zink (exit 1, no crash)"
check "saying why" grep -q 'GALLIUM_DRIVER=zink is refused' "$TMP/zink.log"
GALLIUM_DRIVER=zink "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --check \
    >"$TMP/zink2.log" 2>&1
is "$?" 1 "imagerd --check refuses it too"

sed 's/^size_m = 12000$/dem = no-such-dem.tif/' "$TMP/scenario.ini" >"$TMP/nodem.ini"
"$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --scenario "$TMP/nodem.ini" \
    >"$TMP/nodem.log" 2>&1
is "$?" 1 "imagerd refuses a scenario whose DEM is missing"
check "naming the file" grep -q 'no-such-dem.tif' "$TMP/nodem.log"
diag "$(grep -m1 'no-such-dem' "$TMP/nodem.log")"

sed 's/^chunk_cells = 32$/chunk_cells = 24/' "$TMP/imager.ini" >"$TMP/bad.ini"
line=$(grep -n '^chunk_cells' "$TMP/bad.ini" | cut -d: -f1)
"$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --params "$TMP/bad.ini" --check \
    >"$TMP/bad.log" 2>&1
is "$?" 1 "imagerd --check refuses chunk_cells = 24"
check "naming the file, line and key" grep -q "bad.ini:$line: \[scene\] chunk_cells" "$TMP/bad.log"
"$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --check >"$TMP/good.log" 2>&1
is "$?" 0 "imagerd --check accepts the test's parameters"

finish
