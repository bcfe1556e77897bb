#!/bin/bash
# tactical.sh — the gateway's STANAG 4607 and Cursor on Target translators in
# the default scenario (its terrain, traffic and radar), with the real
# uavsim, mtid, trackerd and guidanced, checked by decoders nobody here
# wrote:
#  - STANAG 4607: the file the gateway writes is read by Wireshark's
#    dissector (tshark -r) with no malformed packet or expert warning; every
#    target report's raw fields equal the `mti` messages on the bus
#    (positions to the format's quantisation through GeographicLib's
#    CartConvert, line-of-sight and wrap velocities to 1 cm/s, truth tags
#    the entities of `mti.truth`); the same packets arrive over UDP.
#  - Cursor on Target: every event a client receives is valid against
#    MITRE's base-event schema (xmllint) and parsed by @tak-ps/node-cot;
#    tracks, the UAV (with its sensor), the intercept route and the
#    footprint are there, track positions equal the bus's tracks through
#    CartConvert to 1e-6 degrees; a point node-cot sends designates the
#    track nearest it and is answered y-a-w; malformed events are rejected,
#    counted, and change nothing; the TAK protobuf option decodes with
#    node-cot and protoc. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
BCISD=$CGS_BUILD/bin/bcisd
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
GATEWAY=$CGS_BUILD/bin/gateway
for b in "$UAVSIM" "$MTID" "$BCISD" "$TRACKERD" "$GUIDANCED" "$GATEWAY"; do [ -x "$b" ] || bail "no $b"; done
command -v tshark >/dev/null || bail "no tshark (scripts/install-deps installs it)"
command -v xmllint >/dev/null || bail "no xmllint (libxml2-utils)"
command -v protoc >/dev/null || bail "no protoc (protobuf-compiler)"
command -v CartConvert >/dev/null || bail "no CartConvert (geographiclib-tools)"
command -v node >/dev/null || bail "no node"
INTEROP=$CGS_ROOT/tests/interop
[ -d "$INTEROP/node_modules/@tak-ps/node-cot" ] || bail "no node-cot (npm ci in tests/interop)"
XSD=$CGS_ROOT/tests/data/cot/Event-PUBLIC.xsd
[ -f "$XSD" ] || bail "no $XSD"

ORIGIN="35.96 -121.23 0"
EXID=12
# Free UDP ports on loopback: DIS (to nobody), 4607 to our listener, CoT to
# our listener, and the gateway's CoT input.
BASE=$((20000 + RANDOM % 20000))
DISPORT=$BASE S4607PORT=$((BASE + 1)) COTPORT=$((BASE + 2)) COTIN=$((BASE + 3))

EX=$TMP/exercise.ini
{
    exercise_header $EXID tactical-test "scenario=$CGS_ROOT/deploy/scenarios/default.ini"
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service bcisd.uav1 uav=uav1
    exercise_service trackerd "params=$CGS_ROOT/deploy/params/tracker.ini"
    exercise_service guidanced command "params=$CGS_ROOT/deploy/params/guidance.ini"
    exercise_service gateway params=gateway.ini
} >"$EX"
gwparams () {
    cat >"$TMP/gateway.ini" <<EOF
[network]
port = $DISPORT
mode = unicast
peer = 127.0.0.1:$((DISPORT + 100))
[stanag4607]
file = yes
udp = unicast
peer = 127.0.0.1:$S4607PORT
truth_tag = yes
[cot]
mode = unicast
peer = 127.0.0.1:$COTPORT
input_port = $COTIN
format = $1
rate_hz = 2
stale_s = 10
EOF
}
M () { "$MSCGS" "$@" --exercise "$EX"; }
counter () { M status 2>/dev/null | grep -o "$1=[0-9]*" | head -1 | cut -d= -f2; }

# A UDP listener: every datagram to PORT as a file DIR/NNNNNN.
listen () {
    mkdir -p "$2"
    node -e 'const dgram = require("node:dgram"), fs = require("node:fs");
        const s = dgram.createSocket("udp4"); let n = 0;
        s.on("message", (m) => { const f = `${process.argv[2]}/${String(n++).padStart(6, "0")}`;
            fs.writeFileSync(f + ".part", m); fs.renameSync(f + ".part", f); });
        s.bind(Number(process.argv[1]), "127.0.0.1");' "$1" "$2"
}

# A listener on TAK's group on lo: listen_group PORT DIR.
listen_group () {
    mkdir -p "$2"
    node -e 'const dgram = require("node:dgram"), fs = require("node:fs");
        const s = dgram.createSocket({ type: "udp4", reuseAddr: true }); let n = 0;
        s.on("message", (m) => { const f = `${process.argv[2]}/${String(n++).padStart(6, "0")}`;
            fs.writeFileSync(f + ".part", m); fs.renameSync(f + ".part", f); });
        s.bind(Number(process.argv[1]), "239.2.3.1", () => s.addMembership("239.2.3.1", "127.0.0.1"));' "$1" "$2"
}

gwparams xml
start L4 listen-4607 listen "$S4607PORT" "$TMP/udp4607"
start LC listen-cot listen "$COTPORT" "$TMP/cot"
# The bus as the radar publishes it, from before the radar starts.
start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start EM echo-mti "$MSCGS" echo mti --json --exercise "$EX"
start ET echo-truth "$MSCGS" echo mti.truth --json --exercise "$EX"
start EK echo-track "$MSCGS" echo track --json --exercise "$EX"
start EU echo-uav "$MSCGS" echo uav --json --exercise "$EX"
start W gateway "$GATEWAY" --exercise "$EX" --out "$TMP"
sleep 1
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start B bcisd "$BCISD" --exercise "$EX" --instance bcisd.uav1
start T trackerd "$TRACKERD" --exercise "$EX"
start G guidanced "$GUIDANCED" --exercise "$EX"

# ---- Cursor on Target out -----------------------------------------------------------------
# node-cot's view of every event received: uid type how time stale point
# detail, one JSON line each.
cot_parse () { node "$INTEROP/cot.mjs" read "$@"; }
check "CoT: the UAV, with its sensor, reaches the client" wait_for 20 \
    bash -c "grep -lqs 'a-f-A-M-F-Q' '$TMP'/cot/* && grep -ls 'a-f-A-M-F-Q' '$TMP'/cot/* | head -1 | xargs grep -q '<sensor '"
check "CoT: confirmed tracks reach the client" wait_for 60 \
    bash -c "grep -lqs 'uid=\"mscgs-$EXID.track.' '$TMP'/cot/*"

# Designate from a CoT client: a spot at the lead APC (APC1) as the bus
# has it, with the exercise paused so that the vehicles, the tracks and the
# point hold still. (The scenario's operator designates at t = 120 s too:
# what is checked is the gateway's designation.)
apc_now () {
    M echo entity --json --count 200 --timeout 5 2>/dev/null |
        node -e 'let s = ""; process.stdin.on("data", (d) => (s += d)).on("end", () => {
            for (const l of s.split("\n")) { if (!l.startsWith("{")) continue;
                const e = (JSON.parse(l).entities || []).find((x) => x.marking === "APC1");
                if (e) { const p = e.position || {}; console.log(p.east_m || 0, p.north_m || 0); break; } } });'
}
near=""
for _ in $(seq 1 60); do
    apc=$(apc_now)
    near=$(confirmed_tracks "$EX" | awk -v p="$apc" 'BEGIN { split(p, a) } { d = sqrt(($2 - a[1]) ^ 2 + ($3 - a[2]) ^ 2); if (d < 300) { print $1; exit } }')
    [ -n "$near" ] && break
    sleep 0.5
done
check "a confirmed track near APC1 (${near:-none})" test -n "$near"
M pause >/dev/null 2>&1
sleep 1
apc=$(apc_now)
# The last batch before the pause (none come while paused): each track's
# newest hit, which is what a designation at a point goes by.
grep '^{' "$TMP/echo-track.log" | tail -1 | node -e 'let s = ""; process.stdin.on("data", (d) => (s += d)).on("end", () => {
    for (const t of JSON.parse(s).tracks || []) { const h = (t.history || []).slice(-1)[0];
        if (h && /CONFIRMED|COASTING/.test(t.status)) console.log(t.track_id, h.position.east_m || 0, h.position.north_m || 0); } });' \
    >"$TMP/paused_tracks.txt"
diag "paused; APC1 at $apc (local metres)"
read -r lat lon _ < <(CartConvert -r -l $ORIGIN -p 9 <<<"$apc 0")

# Malformed events first: each rejected and counted, nothing designated.
rej0=$(counter cot_rejected)
# udp_send TEXT: one datagram to the gateway's CoT input.
udp_send () {
    node -e 'const s = require("node:dgram").createSocket("udp4");
        s.send(Buffer.from(process.argv[2]), Number(process.argv[1]), "127.0.0.1", () => s.close());' "$COTIN" "$1"
}
NOW=$(date -u +%Y-%m-%dT%H:%M:%SZ)
LATER=$(date -u -d '+60 seconds' +%Y-%m-%dT%H:%M:%SZ)
cot_counter_is () { [ "$(counter "$1")" = "$2" ]; }
udp_send 'garbage'
udp_send "<?xml version=\"1.0\"?><event version=\"2.0\" uid=\"x1\" type=\"b-m-p-s-p-i\" how=\"h-e\" time=\"$NOW\" start=\"$NOW\" stale=\"$LATER\"><point lat=\"91\" lon=\"0\" hae=\"0\" ce=\"1\" le=\"1\"/></event>"
udp_send "<?xml version=\"1.0\"?><event version=\"2.0\" uid=\"x2\" type=\"b-m-p-s-p-i\" how=\"h-e\" time=\"$NOW\" start=\"$NOW\" stale=\"$LATER\"><point lat=\"35.9\" lon"
check "three malformed CoT datagrams are rejected and counted (${rej0:-none} before)" \
    wait_for 10 cot_counter_is cot_rejected $((${rej0:-0} + 3))
is "$(grep -c 'from gateway-cot' "$TMP/guidanced.log")" 0 "and designate nothing"
check "the gateway keeps running" running "$W"
check "the gateway logged the reason" grep -q 'a CoT datagram from 127.0.0.1:[0-9]*: ' "$TMP/gateway.log"

node "$INTEROP/cot.mjs" send "127.0.0.1:$COTIN" --type b-m-p-s-p-i --uid "tak-user-1.spi" \
    --lat "$lat" --lon "$lon" --callsign "TAK USER 1" >"$TMP/send.out" 2>&1
designated_by_cot () { grep -q 'from gateway-cot' "$TMP/guidanced.log"; }
check "a b-m-p-s-p-i point from node-cot designates" wait_for 10 designated_by_cot
# The point reached guidanced where the client put it: the gateway's
# local point against CartConvert's, and guidanced's answer names the track
# the intercept now has.
local_pt=$(grep -o 'tak-user-1.spi at [-0-9.]* [-0-9.]* (local [-0-9.]* [-0-9.]*)' "$TMP/gateway.log" | head -1 |
    sed 's/.*(local \(.*\))/\1/')
diag "APC1 at $apc; the gateway's local point: ${local_pt:-none}"
check "the designation's point is the client's to 0.5 m" awk -v a="$local_pt" -v b="$apc" \
    'BEGIN { if (split(a, x) < 2) exit 1; split(b, y); exit !(sqrt((x[1] - y[1]) ^ 2 + (x[2] - y[2]) ^ 2) < 0.5) }'
tid=$(grep -o 'tak-user-1.spi at .* designates: uav1: designated track [0-9]*' "$TMP/gateway.log" | grep -o '[0-9]*$' | head -1)
# The confirmed or coasting track whose newest hit is nearest the point
# (guidanced's rule for a designation at a point), from the paused batch.
want=$(awk -v p="$apc" 'BEGIN { split(p, a); best = 1e99 }
    { d = sqrt(($2 - a[1]) ^ 2 + ($3 - a[2]) ^ 2); if (d < best) { best = d; id = $1; at = d } }
    END { if (id != "") printf "%s %.0f\n", id, at }' "$TMP/paused_tracks.txt")
diag "guidanced designated track ${tid:-none}; nearest newest hit to the point $apc when paused: track ${want:-none} m"
check "the track whose newest hit is nearest the point, as the bus had it" \
    bash -c "[ -n '$tid' ] && [ '$tid' = '${want%% *}' ]"
icpt=$(M echo intercept --json --count 1 --timeout 5 2>/dev/null | tail -1)
diag "intercept: $(cut -c1-200 <<<"$icpt")"
check "the intercept is under way on it" bash -c \
    "grep -q '\"track_id\":${tid:-x}[,}]' <<<'$icpt' && ! grep -q 'INTERCEPT_STATE_IDLE' <<<'$icpt'"
M resume >/dev/null 2>&1
check "the client gets the answer: y-a-w about its point, naming the track" wait_for 5 bash -c \
    "grep -ls 'type=\"y-a-w\"' '$TMP'/cot/* | xargs grep -l 'tak-user-1.spi' | xargs grep -q 'track'"
check "the intercept route and the footprint go out as drawings" wait_for 10 bash -c \
    "grep -lqs 'uid=\"mscgs-$EXID.route.uav1\"' '$TMP'/cot/* && grep -lqs 'uid=\"mscgs-$EXID.footprint.uav1\"' '$TMP'/cot/*"
is "$(counter cot_designations)" 1 "cot_designations counts it"

# A task (TAK protobuf) addressed to our UAV, at a point 2,000 km away:
# refused, with the reason; one addressed to somebody else is not ours.
ign0=$(counter cot_ignored)
node "$INTEROP/cot.mjs" send "127.0.0.1:$COTIN" --format proto --type t-x-i --uid "tak-user-1.task" \
    --lat 52.5 --lon 13.4 --dest-callsign uav1 >/dev/null 2>&1
check "a task for uav1 at a point 2,000 km away is answered y-c-f-r with the reason" wait_for 5 bash -c \
    "grep -ls 'type=\"y-c-f-r\"' '$TMP'/cot/* | xargs grep -q 'tak-user-1.task.*not within 1000 km'"
node "$INTEROP/cot.mjs" send "127.0.0.1:$COTIN" --type t-x-i --uid "tak-user-1.task2" \
    --lat "$lat" --lon "$lon" --dest-callsign ANDROID-7 >/dev/null 2>&1
check "a task for somebody else is ignored and counted" wait_for 5 cot_counter_is cot_ignored $((${ign0:-0} + 1))
check "and not answered" bash -c "! grep -lqs 'tak-user-1.task2' '$TMP'/cot/*"
# The same event twice (a client resends): answered twice, done once.
rep0=$(counter cot_repeats)
NOW=$(date -u +%Y-%m-%dT%H:%M:%SZ)
LATER=$(date -u -d '+60 seconds' +%Y-%m-%dT%H:%M:%SZ)
again="<?xml version=\"1.0\"?><event version=\"2.0\" uid=\"tak-user-1.again\" type=\"t-x-i\" how=\"h-e\" time=\"$NOW\" start=\"$NOW\" stale=\"$LATER\"><point lat=\"52.5\" lon=\"13.4\" hae=\"0\" ce=\"10\" le=\"10\"/><detail><marti><dest callsign=\"uav1\"/></marti></detail></event>"
udp_send "$again"
udp_send "$again"
check "the same event twice is answered twice and taken once (cot_repeats ${rep0:-none} + 1)" \
    wait_for 10 cot_counter_is cot_repeats $((${rep0:-0} + 1))
check "both answers carry the first one's reason" bash -c \
    "[ \$(grep -ls 'tak-user-1.again.*not within 1000 km' '$TMP'/cot/* | wc -l) -eq 2 ]"
# Let the exercise run on: more scans, more dwells.
sleep 6

# ---- every event received: the schema, node-cot, the bus ---------------------------------
events=("$TMP"/cot/[0-9][0-9][0-9][0-9][0-9][0-9]) # as they are now: the listener goes on
n=${#events[@]}
xmllint --noout --schema "$XSD" "${events[@]}" >"$TMP/xmllint.out" 2>&1
rc=$?
diag "xmllint: $(grep -vc ' validates$' "$TMP/xmllint.out") lines other than 'validates' of $n events"
is "$rc" 0 "all $n CoT events validate against MITRE's Event-PUBLIC.xsd"
cot_parse "${events[@]}" >"$TMP/cot.jsonl" 2>"$TMP/cot_parse.err"
is "$?" 0 "node-cot parses every event"
is "$(grep -c '"valid":true' "$TMP/cot.jsonl")" "$n" "node-cot validates all $n"
check "every event is marked simulation (opex s-...)" bash -c \
    "[ \$(grep -c '\"opex\":\"s-' '$TMP/cot.jsonl') -eq $n ]"
check "tracks are a-u-G or a-f-G-E-V, how m-p, with course and speed" bash -c \
    "! grep '\"uid\":\"mscgs-$EXID.track.' '$TMP/cot.jsonl' | grep -qv '\"how\":\"m-p\"' &&
     ! grep '\"uid\":\"mscgs-$EXID.track.' '$TMP/cot.jsonl' | grep -Eqv '\"type\":\"(a-u-G|a-f-G-E-V)\"' &&
     grep '\"uid\":\"mscgs-$EXID.track.' '$TMP/cot.jsonl' | grep -q '\"course\"'"
check "BCIS-identified friendly tracks are a-f-G-E-V" grep -q '"type":"a-f-G-E-V"' "$TMP/cot.jsonl"
check "the footprint is a closed polygon of 4 corners for node-cot (5 points, first = last)" \
    bash -c "grep '\"uid\":\"mscgs-$EXID.footprint.uav1\"' '$TMP/cot.jsonl' | grep -v 'ended' | head -1 | node -e 'let s = \"\"; process.stdin.on(\"data\", (d) => (s += d)).on(\"end\", () => { const g = JSON.parse(s).geometry; const c = g.coordinates[0]; process.exit(g.type === \"Polygon\" && c.length === 5 && c[0].join() === c[4].join() ? 0 : 1); })'"
# Positions against the bus: each CoT track event's point equals a track
# of the same id in some batch, and each UAV event's the UAV's in some `uav`
# message, through CartConvert, to 1e-6 degrees.
node -e '
const fs = require("node:fs"), { execFileSync } = require("node:child_process");
const [cotPath, trackPath, uavPath, lat0, lon0, h0] = process.argv.slice(1);
// Whole lines only: the observers are still writing.
const lines = (p) => fs.readFileSync(p, "utf8").split("\n").flatMap((l) => {
    try { return l.startsWith("{") ? [JSON.parse(l)] : []; } catch { return []; } });
const enu = [], want = new Map(); // "track.ID" or "uav.NAME" -> indices into enu
const add = (k, p) => { if (!want.has(k)) want.set(k, []); want.get(k).push(enu.length);
    enu.push(`${p.east_m || 0} ${p.north_m || 0} ${p.up_m || 0}`); };
for (const b of lines(trackPath)) for (const t of b.tracks || []) add(`track.${t.track_id}`, t.position || {});
for (const u of lines(uavPath)) add(`uav.${u.name}`, u.position || {});
const geo = execFileSync("CartConvert", ["-r", "-l", lat0, lon0, h0, "-p", "9"], { input: enu.join("\n") + "\n", maxBuffer: 1 << 28 })
    .toString().trim().split("\n").map((l) => l.trim().split(/\s+/).map(Number));
const n = { track: 0, uav: 0 }, ok = { track: 0, uav: 0 };
let worst = 0;
for (const e of lines(cotPath)) {
    const m = e.uid.match(/\.((track|uav)\.[^.]+)$/);
    if (!m || !want.has(m[1])) continue;
    let best = Infinity;
    for (const k of want.get(m[1])) best = Math.min(best, Math.max(Math.abs(geo[k][0] - e.point.lat), Math.abs(geo[k][1] - e.point.lon)));
    n[m[2]]++;
    if (best <= 1e-6) ok[m[2]]++; else worst = Math.max(worst, best);
}
console.log(n.track, ok.track, n.uav, ok.uav, worst);
' "$TMP/cot.jsonl" "$TMP/echo-track.log" "$TMP/echo-uav.log" $ORIGIN >"$TMP/positions.out"
read -r nrows nok nuav nuok worst <"$TMP/positions.out"
diag "compared: $nrows track events ($nok equal to a bus track within 1e-6 deg), $nuav UAV events ($nuok); worst other $worst deg"
check "every CoT track position equals the bus's track to 1e-6 degrees ($nok of $nrows)" \
    bash -c "[ '$nrows' -gt 0 ] && [ '$nrows' = '$nok' ]"
check "every CoT UAV position equals the bus's UAV to 1e-6 degrees ($nuok of $nuav)" \
    bash -c "[ '$nuav' -gt 0 ] && [ '$nuav' = '$nuok' ]"

# ---- STANAG 4607 ---------------------------------------------------------------------------
# The radar stops first: the gateway and the observers have every dwell it
# published; then the gateway, which sends what it holds.
stop "$R"
sleep 1
stop "$W"
stop "$EM"
stop "$ET"
F=$TMP/gateway.4607
check "the gateway wrote $F" test -s "$F"
tshark -r "$F" -T pdml >"$TMP/s4607.pdml" 2>"$TMP/tshark.err"
is "$?" 0 "tshark reads it"
tshark -r "$F" -q -z expert >"$TMP/expert.txt" 2>&1
diag "tshark expert: $(grep -cE 'Warning|Error' "$TMP/expert.txt") warning or error lines"
check "with no malformed packet, warning or error" bash -c \
    "! grep -qE 'Malformed|Warning|Error' '$TMP/expert.txt' && ! grep -q '_ws.malformed' '$TMP/s4607.pdml'"
node "$INTEROP/s4607_check.mjs" "$TMP/s4607.pdml" "$TMP/echo-mti.log" "$TMP/echo-truth.log" \
    $ORIGIN >"$TMP/check.json"
rc=$?
diag "$(cat "$TMP/check.json")"
is "$rc" 0 "every target report's raw fields (position, height, velocities, SNR, class, uncertainties, truth tag) and every dwell's sensor position and time equal the bus's"
check "every dwell on the bus is in the file, hundreds of reports compared, with truth tags" node -e '
    const r = JSON.parse(require("node:fs").readFileSync(process.argv[1], "utf8"));
    process.exit(r.reports_compared >= 100 && r.truth_tags_compared >= 50 && r.matched_dwells === r.mti_messages ? 0 : 1)' \
    "$TMP/check.json"
refdate=$(tshark -r "$F" -T fields -e s4607.mission.year -e s4607.mission.month -e s4607.mission.day 2>/dev/null |
    awk -F'\t' '$1 != "" { printf "%04d-%02d-%02d\n", $1, $2, $3; exit }')
check "the mission's reference date is today's UTC date ($refdate)" \
    bash -c "[ '$refdate' = \"\$(date -u +%F)\" ] || [ '$refdate' = \"\$(date -u -d '-1 hour' +%F)\" ]"
check "mission, job and platform location segments are in the file" bash -c \
    "tshark -r '$F' -T fields -e s4607.mission.platform -e s4607.exind -e s4607.job.id -e s4607.ploc.lat 2>/dev/null | awk -F'\t' '\$1 != \"\" { m++ } \$3 != \"\" { j++ } \$4 != \"\" { p++ } \$2 == 129 { e++ } END { exit !(m >= 1 && j >= 1 && p >= 5 && e == NR) }'"
nudp=$(find "$TMP/udp4607" -type f | wc -l)
npk=$(grep -c '<packet>' "$TMP/s4607.pdml")
check "the same packets went out over UDP, one a datagram ($nudp of $npk)" \
    bash -c "[ '$nudp' -ge \$(( $npk * 99 / 100 )) ] && [ '$nudp' -le '$npk' ]"
check "and each datagram is a whole packet (its size field equals its length)" bash -c \
    "for f in \$(ls '$TMP/udp4607' | head -50); do s=\$(od -An -tu1 -j2 -N4 '$TMP/udp4607/'\$f | awk '{ print \$1 * 16777216 + \$2 * 65536 + \$3 * 256 + \$4 }'); [ \"\$s\" = \$(stat -c %s '$TMP/udp4607/'\$f) ] || exit 1; done"

# ---- the TAK protobuf option, on TAK's multicast group on lo -------------------------------
# As the default exercise sends CoT (multicast to 239.2.3.1 on lo, TTL 0),
# on a port of this test's own.
cat >"$TMP/gateway.ini" <<EOF
[network]
port = $DISPORT
mode = unicast
peer = 127.0.0.1:$((DISPORT + 100))
[cot]
mode = multicast
address = 239.2.3.1
port = $COTPORT
interface = lo
ttl = 0
format = protobuf
rate_hz = 2
; a UAV the scenario does not have: points are answered with the reason
designate_uav = uav7
[stanag4607]
file = yes
EOF
# The 4607 file as a write cut short leaves it: half a packet at its end.
whole=$(stat -c %s "$F")
head -c 40 "$F" >>"$F"
stop "$LC"
rm -rf "$TMP/cot"
start LC listen-group listen_group "$COTPORT" "$TMP/cot"
start W gateway-proto "$GATEWAY" --exercise "$EX" --out "$TMP"
start R mtid-again "$MTID" --exercise "$EX" --instance mtid.uav1
check "the restarted gateway cuts the file's partial packet off before it appends" \
    wait_for 5 grep -q "gateway.4607 ends in part of a packet (40 bytes from $whole)" "$TMP/gateway-proto.log"
# Until the UAV's event is among them (it goes out once a second; tracks
# come with the radar's batches): whole files only, not one being written.
check "TAK protobuf events reach the client, the UAV's among them" wait_for 10 bash -c \
    "[ \$(ls '$TMP/cot' | grep -c '^[0-9]*\$') -ge 3 ] && grep -lqs 'mscgs-$EXID.uav.uav1' '$TMP'/cot/[0-9][0-9][0-9][0-9][0-9][0-9]"
first=$(ls "$TMP/cot" | head -1)
check "in the mesh framing (0xbf 0x01 0xbf)" bash -c \
    "[ \"\$(od -An -tx1 -N3 '$TMP/cot/$first' | tr -d ' ')\" = bf01bf ]"
cot_parse "$TMP"/cot/[0-9][0-9][0-9][0-9][0-9][0-9] >"$TMP/cotp.jsonl" 2>"$TMP/cotp.err"
is "$?" 0 "node-cot decodes every one (from_proto)"
check "the UAV among them" grep -q '"type":"a-f-A-M-F-Q"' "$TMP/cotp.jsonl"
uavf=$(grep -l 'uav.uav1' "$TMP"/cot/[0-9][0-9][0-9][0-9][0-9][0-9] | head -1)
tail -c +4 "$uavf" | protoc --decode=tak.TakMessage --proto_path="$CGS_ROOT/proto" "$CGS_ROOT/proto/tak.proto" >"$TMP/protoc.txt" 2>&1
check "protoc decodes it as a TakMessage with the UAV's uid and type" bash -c \
    "grep -q 'uid: \"mscgs-$EXID.uav.uav1\"' '$TMP/protoc.txt' && grep -q 'type: \"a-f-A-M-F-Q\"' '$TMP/protoc.txt'"
# A designation sent to the group, in TAK protobuf: heard, answered on the
# group; the gateway's own events coming back are dropped, not taken.
node "$INTEROP/cot.mjs" send "239.2.3.1:$COTPORT" --format proto --type b-m-p-s-p-i \
    --uid "tak-user-2.spi" --lat "$lat" --lon "$lon" >/dev/null 2>&1
# designate_uav names a UAV the exercise does not have: the point is heard
# and answered on the group with that reason, not silently ignored.
check "a protobuf point sent to the group is heard and answered on the group: no UAV uav7" \
    wait_for 10 bash -c \
    "grep -q 'CoT b-m-p-s-p-i tak-user-2.spi at .*no UAV uav7 in this exercise' '$TMP/gateway-proto.log' && grep -lqs 'tak-user-2.spi' '$TMP'/cot/*"
own=$(counter cot_own_echo)
cin=$(counter cot_in)
check "the gateway's own events, back over loopback, are known by their source and dropped undecoded (${own:-none} of them; ${cin:-none} others in)" \
    bash -c "[ '${own:-0}' -gt 10 ] && [ '${cin:-99}' -le 2 ]"

stop "$R"
stop "$W"
tshark -r "$F" -q -z expert >"$TMP/expert2.txt" 2>&1
check "and tshark reads the whole file again, the packets appended after the cut too" bash -c \
    "[ \$(stat -c %s '$F') -gt $whole ] && ! grep -qE 'Malformed|Warning|Error' '$TMP/expert2.txt'"
for p in "$B" "$T" "$G" "$U"; do stop "$p"; done
check "the gateway encoded every CoT event (none refused by the codec)" bash -c \
    "! grep -q 'cannot be encoded' '$TMP/gateway.log' '$TMP/gateway-proto.log'"
for log in gateway gateway-proto mtid mtid-again bcisd trackerd guidanced uavsim; do
    check "$log: no sanitizer report" clean_log "$TMP/$log.log"
done
finish
