#!/bin/bash
# video.sh — imagerd's video (STANAG 4609: H.264 and MISB ST 0601 KLV in
# MPEG-TS) in the default scenario, with the real uavsim, mtid, trackerd and
# guidanced (the scenario's operator designates at t = 120 s; the sensor is
# switched to SAR during the intercept and shows the target), checked by
# readers nobody here wrote:
#  - ffprobe: an H.264 stream at the camera's size and a KLV data stream
#    (codec tag KLVA), one KLV packet per video frame, as many as imagerd
#    made; Wireshark's MPEG-TS reader (tshark) finds no continuity error;
#  - GStreamer's tsdemux extracts the same KLV bytes as FFmpeg's demuxer;
#  - the test's own ST 0601 decoder (tests/interop/klv_check.mjs, from the
#    standard's tables) checks every packet's checksum, and every tag
#    against the `image`, `uav`, `intercept` and `track` messages of the same
#    frame (positions through GeographicLib's CartConvert, within each
#    format's quantisation; the frame centre within 1% of the footprint's
#    width of its centre); a flipped byte is detected;
#  - the UDP stream (unicast to a listener on loopback) is the file's bytes,
#    in datagrams of whole 188-byte packets, at most seven;
#  - a decoded frame matches imagerd's PNG of the same frame (PSNR);
#  - a restart cuts a partial packet off the file's end and appends; sent to
#    a multicast group from 127.0.0.1 with TTL 0, a listener joined on
#    loopback gets the same bytes, and ffprobe reads them; those frames are
#    infrared, encoded the same way.
# TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
IMAGERD=$CGS_BUILD/bin/imagerd
for b in "$UAVSIM" "$MTID" "$TRACKERD" "$GUIDANCED" "$IMAGERD"; do [ -x "$b" ] || bail "no $b"; done
for t in ffprobe ffmpeg gst-launch-1.0 tshark CartConvert node; do
    command -v $t >/dev/null || bail "no $t (scripts/install-deps installs it)"
done
gst-inspect-1.0 tsdemux >/dev/null 2>&1 || bail "no GStreamer tsdemux (gstreamer1.0-plugins-bad)"
INTEROP=$CGS_ROOT/tests/interop

ORIGIN="35.96 -121.23 0"
PORT=$((20000 + RANDOM % 20000))
EX=$TMP/exercise.ini
{
    exercise_header 14 video-test "scenario=$CGS_ROOT/deploy/scenarios/default.ini"
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service trackerd "params=$CGS_ROOT/deploy/params/tracker.ini"
    exercise_service guidanced command "params=$CGS_ROOT/deploy/params/guidance.ini"
    exercise_service imagerd.uav1 command uav=uav1 params=imager.ini
} >"$EX"
sed -e "s/^udp =$/udp = 127.0.0.1:$PORT/" "$CGS_ROOT/deploy/params/imager.ini" >"$TMP/imager.ini"
grep -q "^udp = 127.0.0.1:$PORT" "$TMP/imager.ini" || bail "cannot set [video] udp in imager.ini"
M () { "$MSCGS" "$@" --exercise "$EX"; }
OUT=$TMP/images
TS=$OUT/imagerd.uav1.ts

# The UDP listener: every datagram appended to one file, its length to another.
start L listen node -e 'const dgram = require("node:dgram"), fs = require("node:fs");
    const s = dgram.createSocket("udp4");
    const ts = fs.openSync(process.argv[2], "w"), lens = fs.openSync(process.argv[3], "w");
    s.on("message", (m) => { fs.writeSync(ts, m); fs.writeSync(lens, m.length + "\n"); });
    s.bind(Number(process.argv[1]), "127.0.0.1", () => fs.writeFileSync(process.argv[4], ""));' \
    "$PORT" "$TMP/udp.ts" "$TMP/udp.len" "$TMP/udp.ready"
wait_for 10 test -f "$TMP/udp.ready" || bail "the UDP listener did not start"
start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 10
for t in image uav intercept track; do
    start E echo-$t "$MSCGS" echo $t --json --exercise "$EX"
    eval "E_$t=\$E"
done
sleep 1
start I imagerd "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$OUT"
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start T trackerd "$TRACKERD" --exercise "$EX"
start G guidanced "$GUIDANCED" --exercise "$EX"

check "imagerd says where its video goes" wait_for 30 \
    grep -q "video: H.264 2000 kbit/s .*file $TS; UDP to 127.0.0.1:$PORT" "$TMP/imagerd.log"
designated () { grep -q '"track_id":[1-9]' "$TMP/echo-intercept.log"; }
check "the scenario's operator designates a track (t = 120 s)" wait_for 90 designated
# 60 more frames with the target designated, then two frames as PNG.
n0=$(wc -l <"$TMP/echo-image.log")
wait_for 60 bash -c "test \$(wc -l <'$TMP/echo-image.log') -ge $((n0 + 60))"
out=$(M snapshot 2 2>&1)
check "mscgs snapshot 2 is acknowledged" grep -q 'next 2 frames' <<<"$out"
check "two snapshot files are written" wait_for 20 bash -c \
    "test \$(ls '$OUT' | grep -c '^snapshot-.*\.png$') -ge 2"
sleep 2
stop "$I"
is "$EXIT_CODE" 0 "imagerd stops on SIGTERM with exit code 0"
for t in image uav intercept track; do eval "stop \$E_$t"; done
sleep 0.5
stop "$L"
frames=$(grep -o 'video: [0-9]* frames' "$TMP/imagerd.log" | tail -1 | grep -o '[0-9]*')
diag "$(grep 'video: [0-9]* frames' "$TMP/imagerd.log" | tail -1)"
check "imagerd encoded frames with no error ($frames)" \
    grep -q "video: [0-9]* frames ([0-9]* keyframes, $frames KLV packets, 0 errors)" "$TMP/imagerd.log"

# ---- the file, read by ffprobe, tshark, GStreamer and FFmpeg ------------------------------
probe=$(ffprobe -v error -show_entries stream=codec_type,codec_name,codec_tag_string,width,height \
    -of compact "$TS" 2>&1)
diag "$probe"
check "ffprobe: an H.264 stream, 640 x 480" \
    grep -q 'codec_name=h264|codec_type=video|codec_tag_string=\[27\]\[0\]\[0\]\[0\]|width=640|height=480' <<<"$probe"
check "ffprobe: a KLV data stream, codec tag KLVA" \
    grep -q 'codec_name=klv|codec_type=data|codec_tag_string=KLVA' <<<"$probe"
nv=$(ffprobe -v error -select_streams v -show_entries packet=pts -of csv "$TS" | grep -c packet)
nd=$(ffprobe -v error -select_streams d -show_entries packet=pts -of csv "$TS" | grep -c packet)
is "$nv" "$frames" "as many video frames as imagerd encoded ($nv)"
is "$nd" "$frames" "and one KLV packet per frame ($nd)"
pts () { ffprobe -v error -select_streams "$1" -show_entries packet=pts -of csv=p=0 "$TS" |
    sed -e 's/,*$//' -e '/^$/d'; }
check "each KLV packet has its frame's PTS" cmp -s <(pts v) <(pts d)
expert () { tshark -r "$TS" -Y 'mp2t.cc.drop || _ws.malformed || _ws.expert.severity >= warning' 2>/dev/null; }
cc=$(expert | wc -l)
tsn=$(tshark -r "$TS" 2>/dev/null | wc -l)
diag "tshark: $tsn transport stream packets"
check "tshark reads the file as MPEG-TS" test "$tsn" -eq $(($(stat -c %s "$TS") / 188))
is "$cc" 0 "with no continuity error or malformed packet"
ffmpeg -v error -i "$TS" -map 0:d -c copy -f data "$TMP/ffmpeg.klv"
gst-launch-1.0 -q filesrc location="$TS" ! tsdemux name=d d. ! meta/x-klv ! \
    filesink location="$TMP/gst.klv" >"$TMP/gst.log" 2>&1
check "GStreamer's tsdemux extracts KLV" test -s "$TMP/gst.klv"
check "the same bytes as FFmpeg's demuxer" cmp "$TMP/gst.klv" "$TMP/ffmpeg.klv"

# ---- the KLV against the bus ---------------------------------------------------------------
# shellcheck disable=SC2086  # ORIGIN is three words
res=$(node "$INTEROP/klv_check.mjs" "$TMP/gst.klv" "$TMP/echo-image.log" "$TMP/echo-uav.log" \
    "$TMP/echo-intercept.log" "$TMP/echo-track.log" video-test $ORIGIN 2>&1)
diag "$res"
check "every KLV packet decodes and agrees with the bus" grep -q '"ok":true' <<<"$res"
n=$(sed -n 's/.*"packets":\([0-9]*\).*/\1/p' <<<"$res")
is "${n:-0}" "$frames" "every packet decoded ($n)"
m=$(sed -n 's/.*"matched":\([0-9]*\).*/\1/p' <<<"$res")
check "most frames matched to their image message ($m of $n)" test "${m:-0}" -ge $((n * 3 / 4))
pl=$(sed -n 's/.*"with_platform":\([0-9]*\).*/\1/p' <<<"$res")
check "most frames' platform and sensor angles checked against their uav message ($pl of $m)" \
    test "${pl:-0}" -ge $((${m:-0} * 3 / 4))
tg=$(sed -n 's/.*"with_target":\([0-9]*\).*/\1/p' <<<"$res")
check "frames after the designation carry the target and its track id ($tg)" test "${tg:-0}" -ge 20
check "a flipped byte is detected" grep -q '"flip_detected":true' <<<"$res"

# ---- UDP ---------------------------------------------------------------------------------
check "the UDP stream is the file's bytes" cmp "$TMP/udp.ts" "$TS"
check "in datagrams of whole 188-byte packets, at most seven" \
    awk '$1 % 188 || $1 > 1316 || $1 == 0 { bad = 1 } END { exit bad || NR == 0 }' "$TMP/udp.len"

# ---- a frame decoded against its PNG --------------------------------------------------------
snap=$(ls "$OUT" | grep '^snapshot-.*\.png$' | head -1)
fn=$((10#$(sed 's/snapshot-\([0-9]*\)\.png/\1/' <<<"$snap")))
ffmpeg -v error -i "$TS" -vf "select=eq(n\,$((fn - 1)))" -frames:v 1 "$TMP/decoded.png"
check "frame $fn decodes from the file" test -s "$TMP/decoded.png"
psnr=$(ffmpeg -i "$TMP/decoded.png" -i "$OUT/$snap" -lavfi psnr -f null - 2>&1 |
    sed -n 's/.* average:\([0-9.inf]*\).*/\1/p')
diag "frame $fn: PSNR ${psnr:-none} dB against $snap"
check "its picture matches the PNG of the same frame (PSNR $psnr dB > 30)" \
    awk -v p="${psnr:-0}" 'BEGIN { exit !(p == "inf" || p > 30) }'

# ---- restart: a partial packet cut, then appended to; multicast on loopback -----------------
# The restarted imagerd sends to a multicast group from 127.0.0.1 with TTL 0,
# to a listener that joined the group on loopback.
GROUP=239.7.7.$((RANDOM % 200 + 1))
# It renders the infrared view: those frames go out the same way.
sed -i -e "s/^udp = .*/udp = $GROUP:$PORT/" -e 's/^ttl = 1$/ttl = 0/' \
    -e 's/^local_address =$/local_address = 127.0.0.1/' -e 's/^mode = visible$/mode = infrared/' \
    "$TMP/imager.ini"
start LM listen-group node -e 'const dgram = require("node:dgram"), fs = require("node:fs");
    const s = dgram.createSocket({ type: "udp4", reuseAddr: true });
    const ts = fs.openSync(process.argv[3], "w");
    s.on("message", (m) => fs.writeSync(ts, m));
    s.bind(Number(process.argv[1]), process.argv[2], () => {
        s.addMembership(process.argv[2], "127.0.0.1"); fs.writeFileSync(process.argv[4], ""); });' \
    "$PORT" "$GROUP" "$TMP/group.ts" "$TMP/group.ready"
wait_for 10 test -f "$TMP/group.ready" || bail "the multicast listener did not start"
size=$(stat -c %s "$TS")
head -c 100 /dev/urandom >>"$TS"
start I imagerd "$IMAGERD" --exercise "$EX" --instance imagerd.uav1 --out "$OUT"
check "a restarted imagerd cuts the partial packet" wait_for 30 \
    grep -q "cut a partial packet (100 bytes)" "$TMP/imagerd.log"
check "and appends" wait_for 30 bash -c "test \$(stat -c %s '$TS') -gt $size"
check "it renders the infrared view" grep -q "640 x 480 px, infrared at" "$TMP/imagerd.log"
check "it says it sends to the multicast group" \
    grep -q "UDP to $GROUP:$PORT (multicast)" "$TMP/imagerd.log"
check "the group's listener on loopback gets the video" wait_for 30 \
    bash -c "test \$(stat -c %s '$TMP/group.ts') -ge 18800"
# SAR during the intercept (the restarted imagerd; its frames are not in the
# KLV check above: a chip holds imagerd's loop, about 0.7 s in this build,
# and the track it then holds can be newer than a queued frame's time).
# The chip is centred on the designated target's return (a mover's falls
# R·v_r/V along cross range); a frame with the target in it is waited for.
start E echo-image2 "$MSCGS" echo image --json --exercise "$EX"
out=$(M sensor sar --wait 20 2>&1)
diag "$out"
check "mscgs sensor sar during the intercept is acknowledged" grep -q 'imaging sensor SAR' <<<"$out"
sar_target () { grep '"mode":"IMAGE_MODE_SAR"' "$TMP/echo-image2.log" | grep -q '"target_in_view":true'; }
check "SAR frames show the designated target" wait_for 90 sar_target
diag "SAR frames: $(grep -c '"mode":"IMAGE_MODE_SAR"' "$TMP/echo-image2.log"), with the target in view: $(grep '"mode":"IMAGE_MODE_SAR"' "$TMP/echo-image2.log" | grep -c '"target_in_view":true')"
M sensor infrared --wait 20 >/dev/null 2>&1
stop "$E"
stop "$I"
sleep 0.3
stop "$LM"
gprobe=$(ffprobe -v error -show_entries stream=codec_name,codec_tag_string -of compact \
    "$TMP/group.ts" 2>&1)
ffmpeg -v error -i "$TMP/group.ts" -frames:v 1 -vf format=rgb24 -f rawvideo "$TMP/ir.rgb"
check "a decoded infrared frame is grey (R = G = B within the codec's error)" \
    node -e 'const d = require("node:fs").readFileSync(process.argv[1]); let worst = d.length ? 0 : 1e9;
        for (let i = 0; i + 2 < d.length; i += 3 * 97)
            worst = Math.max(worst, Math.abs(d[i] - d[i + 1]), Math.abs(d[i + 1] - d[i + 2]));
        process.exit(worst > 24 ? 1 : 0);' "$TMP/ir.rgb"
check "ffprobe reads the multicast stream: H.264 and KLV" \
    bash -c "grep -q codec_name=h264 <<<'$gprobe' && grep -q 'codec_name=klv|codec_tag_string=KLVA' <<<'$gprobe'"
check "the multicast bytes are the file's last bytes" \
    cmp "$TMP/group.ts" <(tail -c "$(stat -c %s "$TMP/group.ts")" "$TS")
check "the file is whole packets" test $(($(stat -c %s "$TS") % 188)) -eq 0
n2=$(ffprobe -v error -select_streams v -show_entries packet=pts -of csv "$TS" | grep -c packet)
check "ffprobe reads both runs ($n2 frames)" test "$n2" -gt "$frames"
# The second run's counters start over: its first packet on each of the
# five PIDs (PAT, PMT, SDT, video, KLV) sets the discontinuity indicator,
# which ISO/IEC 13818-1 asks for there. Wireshark flags a counter's jump
# (a restarted counter can land on the expected value, 1 in 16 a PID, and
# is not flagged); every jump it flags is on such a packet.
restart_pkt=$((size / 188))
restarted=$(tshark -r "$TS" -Y "mp2t.af.di == 1 && frame.number > $restart_pkt" -T fields \
    -e mp2t.pid 2>/dev/null | sort -u | wc -l)
jumps=$(tshark -r "$TS" -Y 'mp2t.cc.drop' 2>/dev/null | wc -l)
unflagged=$(tshark -r "$TS" -Y 'mp2t.cc.drop && !(mp2t.af.di == 1)' 2>/dev/null | wc -l)
is "$restarted" 5 "tshark: the second run's counters start over on every PID (discontinuity indicator)"
diag "tshark flags $jumps counter jumps"
is "$unflagged" 0 "each with its discontinuity indicator set"
check "no sanitizer report from imagerd" clean_log imagerd
finish
