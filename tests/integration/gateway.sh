#!/bin/bash
# gateway.sh — the real gateway beside the real uavsim, mtid, trackerd and
# guidanced, checked with DIS tools nobody here wrote: Wireshark's dissector
# (tshark) decodes every PDU the gateway sends, in each protocol version 3 (the
# paper's DIS 2.0.3) to 7, with no malformed packet, and shows the scenario's entity ids and
# markings; the npm open-dis library decodes our Entity State PDUs (location
# within 1 mm of GeographicLib's CartConvert for the entity) and the Action
# Request that carries guidanced's intercept route; an Entity State PDU that
# open-dis encodes becomes an external entity on the bus at the right local
# position, the radar model sees it, and it is removed after 12 s of silence;
# an open-dis Action Request to our UAV becomes a uavsim route task, answered
# with an Action Response (a retransmission is answered, not done twice; one
# to an entity that is not a UAV is rejected with the reason); garbage, bad
# lengths and other exercises are rejected or ignored, counted, and the
# gateway keeps running. The gateway's own capture of what it sent and
# received ([dis] pcapng), over five runs appended to one file, holds every
# datagram the peer received and every one the gateway was sent: tshark
# reads it, editcap cuts it and mergecap joins it.
# TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
GATEWAY=$CGS_BUILD/bin/gateway
for b in "$UAVSIM" "$MTID" "$TRACKERD" "$GUIDANCED" "$GATEWAY"; do [ -x "$b" ] || bail "no $b"; done
command -v tshark >/dev/null || bail "no tshark (scripts/install-deps installs it)"
command -v CartConvert >/dev/null || bail "no CartConvert (geographiclib-tools)"
command -v node >/dev/null || bail "no node"
DISJS=$CGS_ROOT/tests/interop/dis.js
[ -d "$CGS_ROOT/tests/interop/node_modules/open-dis" ] || bail "no open-dis (npm ci in tests/interop)"

ORIGIN="35.96 -121.23 0"
EXID=11
# Two free UDP ports on loopback: the gateway's, and the open-dis peer's.
GWPORT=$((20000 + RANDOM % 20000))
PEERPORT=$((GWPORT + 1))

EX=$TMP/exercise.ini
{
    exercise_header $EXID gateway-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service trackerd
    exercise_service guidanced command
    exercise_service gateway params=gateway.ini
} >"$EX"
gwparams () {
    cat >"$TMP/gateway.ini" <<EOF
[network]
port = $GWPORT
mode = unicast
peer = 127.0.0.1:$PEERPORT
[dis]
version = $1
pcapng = yes
EOF
}
# Flat ground; the UAV circles the origin; two movers drive north 5 km
# either side of it; a friendly truck drives east.
{
    scenario_ground
    scenario_uav
    scenario_vehicle target hostile TARGET "5000 -4000" "5000 16000" 10
    scenario_vehicle other unknown OTHER "-5000 -4000" "-5000 16000" 8
    scenario_vehicle truck friendly "FRIEND TRK" "-2000 3000" "8000 3000" 12 kind=wheeled
} >"$TMP/scenario.ini"

M () { "$MSCGS" "$@" --exercise "$EX"; }
JSONL=$TMP/dis.jsonl
PCAP=$TMP/dis.pcap

# ENU (east north up) to ECEF with GeographicLib's own tools.
enu2ecef () { CartConvert -r -l $ORIGIN -p 9 <<<"$1" | CartConvert -p 6; }
ecef2enu () { CartConvert -l $ORIGIN -p 9 <<<"$(CartConvert -r -p 9 <<<"$1")"; }
# Confirmed tracks of the latest batch: id east north.
tracks () { confirmed_tracks "$EX"; }
# Entities of the first `entity` batch JSON line on stdin: id east north up
# (proto3 JSON leaves out zero fields: node reads them as 0).
entity_rows () {
    node -e 'let s = ""; process.stdin.on("data", (d) => (s += d)).on("end", () => {
        const line = s.split("\n").find((l) => l.startsWith("{"));
        for (const e of line ? JSON.parse(line).entities || [] : []) {
            const p = e.position || {};
            console.log(e.entity_id, p.east_m || 0, p.north_m || 0, p.up_m || 0);
        }
    });'
}
# A health counter of the gateway: counter NAME.
counter () { M status 2>/dev/null | grep -o "$1=[0-9]*" | head -1 | cut -d= -f2; }

gwparams 7
start L dis-peer node "$DISJS" listen "$PEERPORT" "$TMP/dis"
start U uavsim "$UAVSIM" --exercise "$EX" --time-scale 20
start R mtid "$MTID" --exercise "$EX" --instance mtid.uav1
start T trackerd "$TRACKERD" --exercise "$EX"
start G guidanced "$GUIDANCED" --exercise "$EX"
start W gateway-7 "$GATEWAY" --exercise "$EX"

check "Entity State PDUs of the UAV and the three vehicles reach the open-dis peer" wait_for 15 \
    bash -c "for id in 1:1:1 1:1:2 1:1:3 1:1:4; do grep -qs \"\\\"type\\\":1,.*\\\"id\\\":\\\"\$id\\\"\" '$JSONL' || exit 1; done"
first=$(grep -m1 '"id":"1:1:1"' "$JSONL")
check "open-dis reads the UAV as RVW, version 7, PDU status LVC constructive" \
    bash -c "grep -q '\"version\":7' <<<'$first' && grep -q '\"dr\":4' <<<'$first' && grep -q '\"status\":6' <<<'$first'"
check "and the ground vehicles as FPW" grep -q '"id":"1:1:2".*"dr":2' "$JSONL"
check "markings as the scenario gives them" bash -c \
    "grep -q '\"id\":\"1:1:1\".*\"marking\":\"uav1\"' '$JSONL' && grep -q '\"id\":\"1:1:2\".*\"marking\":\"TARGET\"' '$JSONL' && grep -q '\"id\":\"1:1:4\".*\"marking\":\"FRIEND TRK\"' '$JSONL'"

# ---- guidanced's intercept route goes out as an Action Request ----------------------------
tgt=""
for _ in $(seq 1 40); do
    tracks >"$TMP/tracks.txt"
    tgt=$(awk '$2 > 4500 && $2 < 5500 { print $1; exit }' "$TMP/tracks.txt")
    [ -n "$tgt" ] && break
    sleep 0.5
done
check "the target has a confirmed track (${tgt:-none})" test -n "$tgt"
M designate "$tgt" >"$TMP/designate.out" 2>&1
is "$?" 0 "designating it is accepted"
check "the intercept route reaches the open-dis peer as an Action Request" wait_for 10 \
    grep -q '"type":16,.*"from":"1:1:0","to":"1:1:1"' "$JSONL"
req=$(grep '"type":16' "$JSONL" | tail -1)
icpt=$(M echo intercept --json --count 1 --timeout 5 2>/dev/null | tail -1)
npts=$(grep -o '"route":\[[^]]*\]' <<<"$icpt" | grep -o 'east_m' | wc -l)
rpts=$(node -e 'const r=JSON.parse(process.argv[1]); console.log(r.points.length)' "$req")
diag "Action Request: $(cut -c1-300 <<<"$req")"
check "it has action 40 and one route point per intercept route point ($rpts of $npts)" \
    bash -c "grep -q '\"action\":40' <<<'$req' && [ '$rpts' -ge 2 ] && [ '$rpts' = '$npts' ]"
# The request's last point, back in the local frame with CartConvert, is the
# intercept's last route point (the route ends where it ends in either order).
last=$(node -e 'const r=JSON.parse(process.argv[1]); const p=r.points[r.points.length-1]; console.log(p.join(" "))' "$req")
got=$(ecef2enu "$last")
want=$(node -e 'const r = JSON.parse(process.argv[1]).route; const p = r[r.length - 1];
    console.log(p.east_m || 0, p.north_m || 0, p.up_m || 0)' "$icpt")
diag "last route point: intercept $want, Action Request $got"
check "the route point decodes to the intercept's within 1 mm" awk -v a="$got" -v b="$want" \
    'BEGIN { split(a, x); split(b, y); d = 0; for (i = 1; i <= 3; i++) d += (x[i] - y[i]) ^ 2; exit !(sqrt(d) < 0.001) }'
# Every task the UAV took while the gateway ran went out, each once, the
# UAV's own task number in the text: from the loiter it had when the
# gateway started to the one it flies now.
sleep 1
tn=$(M echo uav --json --count 1 --timeout 3 2>/dev/null | tail -1 |
    node -e 'let s = ""; process.stdin.on("data", (d) => (s += d)).on("end", () => console.log(Number(JSON.parse(s).task_number || 0)));')
grep '"type":16,.*"from":"1:1:0","to":"1:1:1"' "$JSONL" | grep -o 'mscgs task [0-9]* of uav1' |
    awk '{ print $3 }' >"$TMP/tasks.txt"
diag "task numbers in Action Requests: $(tr '\n' ' ' <"$TMP/tasks.txt"), the UAV's now $tn"
check "every task from the first to the UAV's latest ($tn) went out as an Action Request, once" \
    awk -v last="$tn" 'NR == 1 { first = $1 } { if ($1 != first + NR - 1) { bad = 1; exit } n = $1 } END { if (bad) exit 1; exit !(NR >= 1 && n == last) }' "$TMP/tasks.txt"

# ---- every protocol version ---------------------------------------------------------------
for v in 3 4 5 6; do
    stop "$W"
    gwparams $v
    start W gateway-$v "$GATEWAY" --exercise "$EX"
    check "version $v: Entity State PDUs and the Action Request go out in version $v" wait_for 15 \
        bash -c "grep -q '\"version\":$v,.*\"type\":1,' '$JSONL' && grep -q '\"version\":$v,.*\"type\":16,' '$JSONL'"
done
stop "$W"
gwparams 7
start W gateway-7b "$GATEWAY" --exercise "$EX"
sleep 1

# ---- external entities from open-dis ------------------------------------------------------
# A tank 3 km east and 2 km north of the origin on the ground, driving east at
# 8 m/s: its ECEF location and velocity from CartConvert.
p0=$(enu2ecef "3000 2000 0")
p1=$(enu2ecef "3008 2000 0")
vel=$(awk -v a="$p0" -v b="$p1" 'BEGIN { split(a, x); split(b, y); printf "%.6f,%.6f,%.6f", y[1]-x[1], y[2]-x[2], y[3]-x[3] }')
ecef=$(tr ' ' ',' <<<"$p0")
sent_at=$(date +%s.%N)
node "$DISJS" send-espdu "$GWPORT" --exercise $EXID --id 42:7:5 --ecef "$ecef" --vel "$vel" --marking OPENDIS1
# uavsim publishes 200 entity batches a wall second at 20x, the gateway its
# external entities 10 times: 400 batches hold about 20 of the gateway's.
check "the open-dis Entity State PDU shows up on the bus as an external entity" wait_for 5 bash -c \
    "'$MSCGS' echo entity --json --count 400 --timeout 5 --exercise '$EX' 2>/dev/null | grep -q 'OPENDIS1'"
# The gateway's batches come at 10 Hz among uavsim's many: the first that has it.
ext=$(M echo entity --json --count 2000 --timeout 3 2>/dev/null | grep -m1 'OPENDIS1' |
    node -e 'let s = ""; process.stdin.on("data", (d) => (s += d)).on("end", () => {
        const e = (JSON.parse(s).entities || []).find((x) => x.entity_id === 100000);
        if (e) console.log(JSON.stringify(e)); });')
seen_at=$(date +%s.%N)
diag "external: $ext"
check "external, with its DIS id, force and marking" bash -c \
    "grep -q '\"external\":true' <<<'$ext' && grep -q '\"dis_id\":{\"site\":42,\"application\":7,\"entity\":5}' <<<'$ext' && grep -q 'FORCE_HOSTILE' <<<'$ext'"
read -r east north up < <(node -e 'const p = (JSON.parse(process.argv[1] || "{}").position) || {};
    console.log(p.east_m || 0, p.north_m || 0, p.up_m || 0)' "$ext")
# Dead-reckoned (FPW) at 8 m/s east since it was sent: between the send and
# the echo it moved 8 m/s times that; allow the 0.1 s publication period.
check "at the right local position, dead-reckoned east (east $east, north $north, up $up)" awk \
    -v e="$east" -v n="$north" -v u="$up" -v t0="$sent_at" -v t1="$seen_at" \
    'BEGIN { lo = 3000 - 1; hi = 3000 + 8 * (t1 - t0) + 1; exit !(e >= lo && e <= hi && n > 1999.9 && n < 2000.1 && u > -0.1 && u < 0.1) }'
# One mti.truth a dwell, 120 dwells a revolution: 130 of them cover every azimuth.
check "the radar model sees it (mti.truth lists entity 100000)" wait_for 10 bash -c \
    "'$MSCGS' echo mti.truth --json --count 130 --timeout 8 --exercise '$EX' 2>/dev/null | grep -q '\"entity_id\":100000'"

# ---- Action Requests from open-dis --------------------------------------------------------
# guidanced lets the UAV go first, so it does not re-task it meanwhile.
M cancel >/dev/null 2>&1
a=$(enu2ecef "1000 -2000 0" | tr ' ' ',')
b=$(enu2ecef "2000 -2500 0" | tr ' ' ',')
node "$DISJS" send-action "$GWPORT" --exercise $EXID --from 42:7:0 --to 1:1:1 --request 501 --point "$a" --point "$b"
check "an Action Request to our UAV is answered with an Action Response: executing" wait_for 5 \
    grep -q '"type":17,.*"from":"1:1:1","to":"42:7:0","request":501,"requestStatus":2' "$JSONL"
# The first point of the UAV's route, as uavsim publishes it: east north.
route1 () {
    M echo uav --json --count 1 --timeout 3 2>/dev/null | grep '"UAV_MODE_ROUTE"' |
        sed -n 's/.*"route":\[{"east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\).*/\1 \2/p'
}
route_ok () {
    awk -v r="$(route1)" 'BEGIN { split(r, p); exit !(r != "" && (p[1] - 1000) ^ 2 + (p[2] + 2000) ^ 2 < 1) }'
}
check "uavsim flies the route from the Action Request" wait_for 5 route_ok
node "$DISJS" send-action "$GWPORT" --exercise $EXID --from 42:7:0 --to 1:1:1 --request 501 --point "$a" --point "$b"
check "a retransmission is answered again" wait_for 5 \
    bash -c "[ \$(grep -c '\"request\":501,\"requestStatus\":2' '$JSONL') -ge 2 ]"
is "$(grep -c 'Action Request 501 from' "$TMP/gateway-7b.log")" 1 "and not done twice (one task for request 501)"
node "$DISJS" send-action "$GWPORT" --exercise $EXID --from 42:7:0 --to 1:1:2 --request 502 --point "$a"
check "one to an entity that is not a UAV is rejected, with the reason" wait_for 5 \
    grep -q '"request":502,"requestStatus":5.*"text":"entity 1:1:2 is not a UAV' "$JSONL"

# ---- bad input ----------------------------------------------------------------------------
rej0=$(counter rejected)
node "$DISJS" send-raw "$GWPORT" 0700010203
# A version 7 Entity State PDU header whose length field says 200 bytes, 12 sent.
node "$DISJS" send-raw "$GWPORT" 070b0101000000000000c8000600
node "$DISJS" send-espdu "$GWPORT" --exercise 99 --id 42:7:6 --ecef "$ecef" --marking OTHEREX
node "$DISJS" send-espdu "$GWPORT" --exercise $EXID --version 2 --id 42:7:7 --ecef "$ecef" --marking OLD
# An all-zero location: the Earth's centre.
node "$DISJS" send-espdu "$GWPORT" --exercise $EXID --id 42:7:9 --ecef 0,0,0 --marking CENTRE
check "garbage, a bad length, an unknown version and a location off the Earth are rejected and counted" wait_for 5 \
    bash -c "[ \"\$('$MSCGS' status --exercise '$EX' 2>/dev/null | grep -o 'rejected=[0-9]*' | cut -d= -f2)\" -ge $((${rej0:-0} + 4)) ]"
check "another exercise's PDU is ignored and counted" wait_for 3 \
    bash -c "[ \"\$('$MSCGS' status --exercise '$EX' 2>/dev/null | grep -o 'other_exercise=[0-9]*' | cut -d= -f2)\" -ge 1 ]"
check "and none becomes an entity" bash -c \
    "! '$MSCGS' echo entity --json --count 400 --timeout 5 --exercise '$EX' 2>/dev/null | grep -q 'OTHEREX\|\"OLD\"\|CENTRE'"
check "the gateway logs why, once" bash -c \
    "[ \$(grep -c 'a DIS datagram from 127.0.0.1' '$TMP/gateway-7b.log') -eq 1 ]"
check "and keeps running" kill -0 "$W"

# ---- silence and deactivation -------------------------------------------------------------
node "$DISJS" send-espdu "$GWPORT" --exercise $EXID --id 42:7:8 --ecef "$ecef" --marking GOER
check "a second external entity joins" wait_for 5 bash -c \
    "'$MSCGS' echo entity --json --count 400 --timeout 5 --exercise '$EX' 2>/dev/null | grep -q 'GOER'"
node "$DISJS" send-espdu "$GWPORT" --exercise $EXID --id 42:7:8 --ecef "$ecef" --marking GOER --deactivate
check "and leaves at once when its PDU says it is deactivated" wait_for 5 bash -c \
    "grep -q 'external entity 42:7:8 (entity [0-9]*) deactivated' '$TMP/gateway-7b.log'"
check "OPENDIS1, silent since it was sent, is removed after 12 s" wait_for 20 \
    grep -q 'external entity 42:7:5 (entity 100000) timed out' "$TMP/gateway-7b.log"
gone_at=$(date +%s.%N)
silence=$(awk -v a="$sent_at" -v b="$gone_at" 'BEGIN { printf "%.1f", b - a }')
check "no sooner than 12 s after its last PDU (${silence} s)" awk -v s="$silence" 'BEGIN { exit !(s >= 12) }'

# ---- locations against GeographicLib, paused ----------------------------------------------
M pause >/dev/null 2>&1
sleep 1.5
paused_at=$(date +%s.%N)
"$MSCGS" echo entity --json --count 1 --timeout 3 --exercise "$EX" 2>/dev/null | entity_rows >"$TMP/paused.txt"
diag "paused entities: $(tr '\n' ';' <"$TMP/paused.txt")"
sleep 6 # one heartbeat
worst=0 n=0
while read -r id e nn u; do
    [ "$id" -ge 100000 ] && continue
    want=$(enu2ecef "$e $nn $u")
    got=$(awk -v t="$paused_at" -v id="\"1:1:$id\"" -F'"location":\\[' \
        'index($0, "\"id\":" id) && $0 ~ /"type":1,/ { split($1, a, "\"t\":"); split(a[2], b, ","); if (b[1] > t) { split($2, c, "]"); loc = c[1] } } END { gsub(",", " ", loc); print loc }' "$JSONL")
    d=$(awk -v a="$want" -v b="$got" 'BEGIN { split(a, x); split(b, y); if (b == "") { print 1e9; exit } d = 0; for (i = 1; i <= 3; i++) d += (x[i] - y[i]) ^ 2; printf "%.6f", sqrt(d) }')
    diag "entity $id: CartConvert $want, open-dis $got, difference $d m"
    worst=$(awk -v a="$worst" -v b="$d" 'BEGIN { print (b > a ? b : a) }')
    n=$((n + 1))
done <"$TMP/paused.txt"
is "$n" 4 "four internal entities while paused"
check "every Entity State PDU's location is within 1 mm of GeographicLib's (worst $worst m)" \
    awk -v w="$worst" 'BEGIN { exit !(w < 0.001) }'
M resume >/dev/null 2>&1

# ---- Wireshark's dissector ----------------------------------------------------------------
stop "$W"
stop "$L"
tshark -r "$PCAP" -d "udp.port==$PEERPORT,dis" -T fields -e frame.number -e dis.proto_ver \
    -e dis.pdu_type -e dis.entity_id_site -e dis.entity_id_application -e dis.entity_id_entity \
    -e dis.entity_marking -e _ws.malformed >"$TMP/tshark.txt" 2>"$TMP/tshark.err"
frames=$(wc -l <"$TMP/tshark.txt")
dis=$(awk -F'\t' '$3 != ""' "$TMP/tshark.txt" | wc -l)
datagrams=$(grep -c . "$JSONL")
diag "tshark: $frames frames, $dis decoded as DIS, $datagrams datagrams received"
check "tshark decodes every datagram received as DIS ($dis of $datagrams)" \
    bash -c "[ $frames -eq $datagrams ] && [ $dis -eq $datagrams ] && [ $datagrams -gt 50 ]"
is "$(awk -F'\t' '$8 != ""' "$TMP/tshark.txt" | wc -l)" 0 "no malformed packet"
tshark -r "$PCAP" -d "udp.port==$PEERPORT,dis" -q -z expert >"$TMP/expert.txt" 2>&1
check "no expert warnings or errors" bash -c "! grep -qiE '^(Errors|Warnings) \(' '$TMP/expert.txt'"
for v in 3 4 5 6 7; do
    check "tshark sees version $v Entity State and Action Request PDUs" bash -c \
        "awk -F'\t' '\$2 == $v && \$3 == 1' '$TMP/tshark.txt' | grep -q . && awk -F'\t' '\$2 == $v && \$3 == 16' '$TMP/tshark.txt' | grep -q ."
done
check "with the scenario's entity ids and markings" bash -c \
    "grep -qP '\t1\t1\t1\t1\tuav1' '$TMP/tshark.txt' && grep -qP '\t1\t1\t1\t2\tTARGET' '$TMP/tshark.txt' && grep -qP '\t1\t1\t1\t3\tOTHER' '$TMP/tshark.txt' && grep -qP '\t1\t1\t1\t4\tFRIEND TRK' '$TMP/tshark.txt'"
check "and only those" bash -c \
    "! awk -F'\t' '\$3 == 1 && !(\$4 == 1 && \$5 == 1 && \$6 >= 1 && \$6 <= 4)' '$TMP/tshark.txt' | grep -q ."

# ---- the gateway's own capture ([dis] pcapng) ----------------------------------------------
# Five runs of the gateway (versions 7, 3..6, 7 again) appended their sections
# to one file; every datagram the peer received is in it.
GWCAP=$(sed -n 's/.*DIS capture: \(.*\) (pcapng)$/\1/p' "$TMP/gateway-7.log" | head -1)
check "the gateway says where it captures DIS ($GWCAP)" test -s "${GWCAP:-/nonexistent}"
caps=$(tshark -r "$GWCAP" -d "udp.port==$PEERPORT,dis" -Y "dis && udp.srcport==$GWPORT" -T fields \
    -e dis.pdu_type 2>"$TMP/gwcap.err" | wc -l)
is "$caps" "$datagrams" "tshark reads as many DIS PDUs sent from it as the peer received ($datagrams)"
# What came in: the eleven datagrams open-dis and the raw sends sent the
# gateway, garbage too, from their senders to the gateway's port.
tshark -r "$GWCAP" -Y "udp.dstport==$GWPORT" -T fields -e ip.dst -e udp.payload \
    >"$TMP/gwcap-in.txt" 2>>"$TMP/gwcap.err"
is "$(wc -l <"$TMP/gwcap-in.txt")" 11 "and every datagram the gateway received (11)"
check "garbage too, as it came (07:00:01:02:03)" grep -qP '\t0700010203$' "$TMP/gwcap-in.txt"
check "to the gateway's address" bash -c "! cut -f1 '$TMP/gwcap-in.txt' | grep -vqx '127.0.0.1'"
sections=$(capinfos -T -m "$GWCAP" 2>/dev/null | tail -1)
diag "capinfos: $sections"
check "capinfos reads it whole" capinfos "$GWCAP"
is "$(grep -o 'mscgs gateway' <<<"$sections" | wc -l)" 6 "a section for each of the six gateway runs (appended)"
srcs_gw=$(tshark -r "$GWCAP" -Y "udp.srcport==$GWPORT" -T fields -e ip.src -e udp.srcport -e udp.dstport 2>/dev/null | sort -u | tr '\n\t' '; ')
srcs_peer=$(tshark -r "$PCAP" -T fields -e ip.src -e udp.srcport -e udp.dstport 2>/dev/null | sort -u | tr '\n\t' '; ')
is "$srcs_gw" "$srcs_peer" "its addresses and ports are those the peer saw the datagrams come from and to"
total=$(tshark -r "$GWCAP" 2>/dev/null | wc -l)
half=$((total / 2))
editcap -r "$GWCAP" "$TMP/first.pcapng" "1-$half" >/dev/null 2>&1
editcap "$GWCAP" "$TMP/second.pcapng" "1-$half" >/dev/null 2>&1
mergecap -w "$TMP/joined.pcapng" "$TMP/first.pcapng" "$TMP/second.pcapng" 2>/dev/null
n1=$(tshark -r "$TMP/first.pcapng" 2>/dev/null | wc -l)
n2=$(tshark -r "$TMP/second.pcapng" 2>/dev/null | wc -l)
nj=$(tshark -r "$TMP/joined.pcapng" -d "udp.port==$PEERPORT,dis" -Y "dis && udp.srcport==$GWPORT" 2>/dev/null | wc -l)
check "editcap cuts it in two ($n1 + $n2 of $total) and mergecap joins them again ($nj)" \
    bash -c "[ $n1 -eq $half ] && [ $((n1 + n2)) -eq $total ] && [ $nj -eq $caps ]"

stop "$G"
stop "$T"
stop "$R"
stop "$U"
for log in gateway-7 gateway-4 gateway-5 gateway-6 gateway-7b uavsim; do
    check "no sanitizer report in $log" clean_log $log
done
finish
