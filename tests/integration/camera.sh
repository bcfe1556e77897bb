#!/bin/bash
# camera.sh — the imaging sensor at run time, with the real uavsim and
# imagerd: `mscgs camera` sets the depression, zoom, stabilization and stare
# within the scenario's limits (uavsim puts them on `uav`, with the camera's
# attitude) and refuses what is outside them with the reason; imagerd's
# frames are taken with that very camera (the `image` pose equals the `uav`
# attitude of the same time, and a staring camera's footprint centre is on
# the stare point); `mscgs sensor` switches imagerd between visible,
# infrared and SAR, the frames say which is live, and a restarted imagerd
# keeps the mode. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
IMAGERD=$CGS_BUILD/bin/imagerd
[ -x "$UAVSIM" ] || bail "no uavsim at $UAVSIM"
[ -x "$IMAGERD" ] || bail "no imagerd at $IMAGERD"

EX=$TMP/exercise.ini
{
    exercise_header 8 camera-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service imagerd.uav1 command uav=uav1 params=imager.ini
} >"$EX"
{
    scenario_ground size_m=12000 resolution_m=50 relief_m=150
    scenario_uav altitude_agl_m=1000 airspeed_mps=30 loiter_radius_m=900 \
        sensor_depression_min_deg=20 sensor_depression_max_deg=89.5 sensor_hfov_max_deg=30
    scenario_vehicle apc hostile APC "0 1200" "0 3000" 8 kind=tracked end=reverse
} >"$TMP/scenario.ini"
sed -e 's/^width_px = 640$/width_px = 320/' -e 's/^height_px = 480$/height_px = 240/' \
    -e '/^\[video\]/,/^\[/ s/^enabled = true$/enabled = false/' \
    "$CGS_ROOT/deploy/params/imager.ini" >"$TMP/imager.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
# num JSON KEY: the first value of KEY.
num () { sed -n "s/.*\"$2\":\"\{0,1\}\([-0-9.e]*\).*/\1/p" <<<"$1" | head -1; }
# near A B TOL
near () { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 2
start I imagerd-1 "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$TMP/images"
check "imagerd publishes frames" wait_for 30 bash -c \
    "'$MSCGS' echo image --count 1 --timeout 2 --exercise '$EX' >/dev/null 2>&1"

# ---- the camera command ----
out=$(M camera --depression 30 --fov 6 --stabilized on 2>&1)
diag "$out"
check "mscgs camera is acknowledged with the settings" \
    grep -q 'depression 30.0 deg, field of view 6.00 x 4.50 deg, stabilized' <<<"$out"
u=$(M echo uav --json --count 1 --timeout 5 2>/dev/null)
check "uav carries the depression, the zoom and stabilization" \
    bash -c "grep -q '\"depression_deg\":30' <<<'$u' && grep -q '\"hfov_deg\":6' <<<'$u' && grep -q '\"stabilized\":true' <<<'$u'"
roll=$(num "$u" sensor_roll_deg)
check "a stabilized camera's roll is 0 (${roll:-0})" near "${roll:-0}" 0 1e-6
el=$(num "$u" sensor_elevation_deg)
pitch=$(num "$u" pitch_deg)
check "its boresight is 30 degrees below the nose ($el, the UAV's pitch ${pitch:-0})" \
    near "$el" "$(awk -v p="${pitch:-0}" 'BEGIN { print p - 30 }')" 0.01
out=$(M camera --depression 10 2>&1)
is "$?" 1 "a depression below the scenario's 20 degrees is refused (exit 1)"
check "saying why" grep -q 'outside the scenario' <<<"$out"
out=$(M camera --fov 45 2>&1)
check "a field of view over the scenario's 30 degrees is refused" grep -q 'outside the scenario' <<<"$out"
M camera --stabilized maybe >"$TMP/bad.log" 2>&1
is "$?" 2 "--stabilized maybe is a usage error (exit 2)"
M camera >"$TMP/none.log" 2>&1
is "$?" 2 "nothing to set is a usage error (exit 2)"

# The image's camera is the uav message's: the frames of the same time have its attitude.
M echo uav --json --count 40 --timeout 20 >"$TMP/uav.json" 2>/dev/null &
echo_pid=$!
M echo image --json --count 20 --timeout 20 >"$TMP/image.json" 2>/dev/null
wait "$echo_pid"
match=$(awk '
    function val(s, k,   m) { if (match(s, "\"" k "\":[-0-9.e]+")) return substr(s, RSTART + length(k) + 3, RLENGTH - length(k) - 3); return "" }
    FNR == NR { t = val($0, "sim_time_s"); az[t] = val($0, "sensor_azimuth_deg"); el[t] = val($0, "sensor_elevation_deg"); next }
    { t = val($0, "sim_time_s"); if (t in az) { n++; d1 = val($0, "heading_deg") - az[t]; d2 = val($0, "pitch_deg") - el[t];
      if (d1 > 180) d1 -= 360; if (d1 < -180) d1 += 360; if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2;
      if (d1 < 1e-6 && d2 < 1e-6) ok++ } }
    END { printf "%d %d\n", n, ok }' "$TMP/uav.json" "$TMP/image.json")
diag "frames with a uav message of their time, and those whose pose is its attitude: $match"
check "every frame of a uav message's time has that message's camera attitude" \
    awk -v m="$match" 'BEGIN { split(m, a, " "); exit !(a[1] >= 5 && a[1] == a[2]) }'

# Staring at a point: the footprint's centre is on it.
out=$(M camera --stare 300,1500 2>&1)
check "staring at a point is acknowledged" grep -q 'staring at a point' <<<"$out"
check "uav says the camera is staring" wait_for 10 bash -c \
    "'$MSCGS' echo uav --json --count 1 --timeout 3 --exercise '$EX' 2>/dev/null | grep -q '\"staring\":true'"
img=$(M echo image --json --count 3 --timeout 10 2>/dev/null | tail -1)
# The footprint's centre: the "center" object inside "footprint".
ce=$(sed -n 's/.*"footprint":{.*"center":{"east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\).*/\1 \2/p' <<<"$img")
diag "footprint centre $ce"
check "the frame's footprint centre is on the stare point (${ce})" \
    awk -v c="$ce" 'BEGIN { split(c, a, " "); d = sqrt((a[1] - 300)^2 + (a[2] - 1500)^2); exit !(d < 15) }'
out=$(M camera --stare 90000,0 2>&1)
check "a stare point off the terrain is refused" grep -q 'not on the terrain' <<<"$out"
M camera --stare off --stabilized off >/dev/null 2>&1
check "staring off again" wait_for 10 bash -c \
    "'$MSCGS' echo uav --json --count 1 --timeout 3 --exercise '$EX' 2>/dev/null | grep -q '\"staring\":true' && exit 1 || exit 0"

# ---- the sensor mode ----
# mode_is MODE: the latest frame's mode (visible, the default value, is not printed).
mode_is () {
    local m
    m=$("$MSCGS" echo image --json --count 3 --timeout 10 --exercise "$EX" 2>/dev/null | tail -1)
    [ -n "$m" ] || return 1
    if [ "$1" = IMAGE_MODE_VISIBLE ]; then
        ! grep -q '"mode":' <<<"$m"
    else
        grep -q "\"mode\":\"$1\"" <<<"$m"
    fi
}
check "the frames start visible" mode_is IMAGE_MODE_VISIBLE
out=$(M sensor flir 2>&1)
diag "$out"
check "mscgs sensor flir is acknowledged" grep -q 'imaging sensor infrared (was visible)' <<<"$out"
check "the frames become infrared" wait_for 10 mode_is IMAGE_MODE_INFRARED
# Looking almost straight down, levelled against the bank, no SAR image can
# be made (grazing over 85°): the frames still say SAR, dark, and the log
# and health say why.
M camera --depression 89.5 --stabilized on >/dev/null 2>&1
sleep 1 # imagerd hears the new depression on uav
out=$(M sensor sar 2>&1)
diag "$out"
check "mscgs sensor sar is acknowledged" grep -q 'imaging sensor SAR (was infrared)' <<<"$out"
check "the frames become SAR" wait_for 10 mode_is IMAGE_MODE_SAR
check "with no chip at 89.5 degrees down, imagerd says why" wait_for 30 \
    grep -q 'SAR: no image of .*grazing angle is outside' "$TMP/imagerd-1.log"
M camera --depression 30 --stabilized off >/dev/null 2>&1
# The SAR frame's footprint is its chip: a square of [sar] scene_m (256 m) on the ground.
chip_side () {
    local img side
    img=$("$MSCGS" echo image --json --count 2 --timeout 10 --exercise "$EX" 2>/dev/null | tail -1)
    side=$(sed -n 's/.*"corners":\[{"east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\)[^}]*},{"east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\).*/\1 \2 \3 \4/p' <<<"$img")
    awk -v c="$side" 'BEGIN { split(c, a, " "); d = sqrt((a[3] - a[1])^2 + (a[4] - a[2])^2); exit !(d > 255 && d < 257) }'
}
check "at 30 degrees down a SAR frame's footprint is its 256 m chip" wait_for 20 chip_side
check "the chip is written as a GeoTIFF (latest-sar.tif)" wait_for 20 test -s "$TMP/images/latest-sar.tif"
gdalinfo "$TMP/images/latest-sar.tif" >"$TMP/gdalinfo.txt" 2>&1
is "$?" 0 "gdalinfo reads it"
check "north-up in a UTM zone (WGS 84)" grep -q 'UTM zone' "$TMP/gdalinfo.txt"
check "with nodata 0 and the chip's grazing angle" \
    bash -c "grep -q 'NoData Value=0' '$TMP/gdalinfo.txt' && grep -qi 'grazing' '$TMP/gdalinfo.txt'"
M sensor radio >"$TMP/radio.log" 2>&1
is "$?" 2 "an unknown mode is a usage error (exit 2)"
stop "$I"
start I2 imagerd-2 "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$TMP/images"
check "a restarted imagerd keeps its mode" wait_for 30 mode_is IMAGE_MODE_SAR
M sensor visible >/dev/null 2>&1
check "and goes back to visible when told" wait_for 10 mode_is IMAGE_MODE_VISIBLE
stop "$I2"
is "$EXIT_CODE" 0 "imagerd stops on SIGTERM with exit code 0"
stop "$U"
check "no sanitizer report from imagerd" clean_log imagerd-1
check "no sanitizer report from the restarted imagerd" clean_log imagerd-2
check "no sanitizer report from uavsim" clean_log uavsim
finish
