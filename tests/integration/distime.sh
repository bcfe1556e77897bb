#!/bin/bash
# distime.sh — DIS time at any time scale: the real uavsim at time scales 1,
# 5 and 20 and the real gateway; an open-dis receiver (tests/interop/dis.js)
# dead-reckons each Entity State PDU of the circling UAV (RVW) and of a
# vehicle (FPW) by the PDU timestamps to the time of the next one, and finds
# it within the 1 m threshold of where the next one puts the entity (the
# gateway sends when its own dead reckoning is 1 m off, checked every 0.1 s
# of simulation time, so a little over 1 m at the send: 1.5 m allowed), with
# relative timestamps and with absolute ones. The same PDUs dead-reckoned by
# the wall clock they arrived at are far off at scale 20 (the check can
# fail). Heartbeats come at least every 5 s of simulation time. TAP on
# stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
GATEWAY=$CGS_BUILD/bin/gateway
for b in "$UAVSIM" "$GATEWAY"; do [ -x "$b" ] || bail "no $b"; done
command -v node >/dev/null || bail "no node"
DISJS=$CGS_ROOT/tests/interop/dis.js
[ -d "$CGS_ROOT/tests/interop/node_modules/open-dis" ] || bail "no open-dis (npm ci in tests/interop)"

EXID=12
GWPORT=$((20000 + RANDOM % 20000))
PEERPORT=$((GWPORT + 1))
EX=$TMP/exercise.ini
{
    exercise_header $EXID distime-test scenario=scenario.ini
    exercise_service uavsim command
    exercise_service gateway params=gateway.ini
} >"$EX"
gwparams () {
    cat >"$TMP/gateway.ini" <<EOF
[network]
port = $GWPORT
mode = unicast
peer = 127.0.0.1:$PEERPORT
[dis]
version = 7
timestamp = $1
EOF
}
# Flat ground; the UAV circles (always turning: every PDU's acceleration
# matters); a vehicle drives a square (corners to dead-reckon through).
{
    scenario_ground
    scenario_uav loiter_radius_m=800
    cat <<'EOF'

[vehicle car]
force = neutral
marking = CAR
point = 2000 2000
point = 2600 2000
point = 2600 2600
point = 2000 2600
end = loop
speed_mps = 15
EOF
} >"$TMP/scenario.ini"

# The dead-reckoning error of consecutive PDUs of each entity in a JSONL
# file: "id pairs max_ts max_wall heartbeat_gap_max": DR by the timestamps
# (max_ts) and by the receive times (max_wall), both in metres, and the
# longest timestamp gap between two PDUs of the entity (simulation seconds).
dr_errors () {
    node -e '
const lines = require("fs").readFileSync(process.argv[1], "utf8").split("\n").filter(Boolean);
const by = {};
for (const l of lines) {
    const p = JSON.parse(l);
    if (p.type !== 1 || p.timestamp === undefined) continue;
    (by[p.id] = by[p.id] || []).push(p);
}
const secs = (ts) => (ts >>> 1) * 3600 / 2147483648;
function at(p, dt) {
    const a = p.dr === 4 ? p.acceleration : [0, 0, 0];
    return p.location.map((x, i) => x + p.velocity[i] * dt + 0.5 * a[i] * dt * dt);
}
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
for (const id of Object.keys(by).sort()) {
    const s = by[id];
    let ts = 0, wall = 0, gap = 0;
    for (let k = 1; k < s.length; k++) {
        let dt = secs(s[k].timestamp) - secs(s[k - 1].timestamp);
        if (dt < -1800) dt += 3600; // past the hour
        gap = Math.max(gap, dt);
        ts = Math.max(ts, dist(at(s[k - 1], dt), s[k].location));
        wall = Math.max(wall, dist(at(s[k - 1], s[k].t - s[k - 1].t), s[k].location));
    }
    console.log(id, s.length - 1, ts.toFixed(3), wall.toFixed(3), gap.toFixed(2));
}' "$1"
}

run_at () { # run_at SCALE TIMESTAMP SECONDS
    local scale=$1 ts=$2 secs=$3 name="s$1-$2"
    gwparams "$ts"
    start L "$name-peer" node "$DISJS" listen "$PEERPORT" "$TMP/$name"
    sleep 0.5
    mkdir -p "$TMP/state-$name" # each run from the start, not from the last one's world
    start U "$name-uavsim" "$UAVSIM" --exercise "$EX" --time-scale "$scale" --state-dir "$TMP/state-$name"
    start W "$name-gateway" "$GATEWAY" --exercise "$EX" --state-dir "$TMP/state-$name"
    sleep "$secs"
    stop "$W"
    stop "$U"
    stop "$L"
    dr_errors "$TMP/$name.jsonl" >"$TMP/$name.dr"
    diag "scale $scale, $ts timestamps: $(tr '\n' ';' <"$TMP/$name.dr")"
    local uav car
    uav=$(grep '^1:1:1 ' "$TMP/$name.dr")
    car=$(grep '^1:1:2 ' "$TMP/$name.dr")
    check "scale $scale, $ts: PDUs of the UAV and the car (${uav:-none}; ${car:-none})" \
        bash -c "[ -n '$uav' ] && [ -n '$car' ] && [ \$(cut -d' ' -f2 <<<'$uav') -ge 3 ] && [ \$(cut -d' ' -f2 <<<'$car') -ge 2 ]"
    check "scale $scale, $ts: dead-reckoned by the timestamps, the UAV within 1.5 m of its next PDU" \
        awk -v e="$(cut -d' ' -f3 <<<"$uav")" 'BEGIN { exit !(e != "" && e <= 1.5) }'
    check "scale $scale, $ts: and the car" \
        awk -v e="$(cut -d' ' -f3 <<<"$car")" 'BEGIN { exit !(e != "" && e <= 1.5) }'
    check "scale $scale, $ts: a PDU of the car at least every 5 s of simulation time (heartbeat)" \
        awk -v g="$(cut -d' ' -f5 <<<"$car")" 'BEGIN { exit !(g != "" && g <= 5.2) }'
}

run_at 1 relative 12
run_at 5 relative 5
run_at 20 relative 4
wall20=$(grep '^1:1:1 ' "$TMP/s20-relative.dr" | cut -d' ' -f4)
check "at scale 20 the same PDUs dead-reckoned by their arrival times are far off (UAV $wall20 m)" \
    awk -v e="$wall20" 'BEGIN { exit !(e > 10) }'
run_at 1 absolute 12
run_at 20 absolute 4

finish
