#!/bin/bash
# translators.sh — the gateway's CPU at the 1,000-vehicle scenario
# (deploy/scenarios/bench-1000.ini: 1,000 vehicles, one UAV and its radar)
# with DIS alone and with all three translators on (DIS, STANAG 4607 to a
# file and over UDP with truth tags, Cursor on Target XML to a listener at
# 1 Hz), beside the services that feed it (uavsim, mtid, bcisd, trackerd,
# guidanced), at time scale 10. Each configuration runs WARM s, then CPU
# (user + system, from /proc/PID/stat) is measured over RUN s of wall time;
# figures: each process's CPU in percent of one core, and the gateway's
# share of the exercise's CPU. The same run measures both configurations,
# one after the other, R times (default 3); medians.
#   tests/bench/translators.sh BUILD_DIR [RUN_S] [RUNS]     (make bench-translators)
set -u
build=${1:?usage: tests/bench/translators.sh BUILD_DIR [RUN_S] [RUNS]}
export CGS_BUILD=$(cd "$build" && pwd)
RUN=${2:-30}
RUNS=${3:-3}
WARM=15
export CGS_NO_PEER=1
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/../integration/lib.sh"

B=$CGS_BUILD/bin
for p in uavsim mtid bcisd trackerd guidanced gateway mscgs; do [ -x "$B/$p" ] || bail "no $B/$p"; done
command -v node >/dev/null || bail "no node"
BASE=$((20000 + RANDOM % 20000))

EX=$TMP/exercise.ini
{
    exercise_header 13 translators-bench "scenario=$CGS_ROOT/deploy/scenarios/bench-1000.ini"
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service bcisd.uav1 uav=uav1
    exercise_service trackerd "params=$CGS_ROOT/deploy/params/tracker.ini"
    exercise_service guidanced command "params=$CGS_ROOT/deploy/params/guidance.ini"
    exercise_service gateway params=gateway.ini
} >"$EX"
params () {
    cat >"$TMP/gateway.ini" <<EOF
[network]
port = $BASE
mode = unicast
peer = 127.0.0.1:$((BASE + 1))
EOF
    [ "$1" = all ] && cat >>"$TMP/gateway.ini" <<EOF
[stanag4607]
file = yes
udp = unicast
peer = 127.0.0.1:$((BASE + 2))
truth_tag = yes
[cot]
mode = unicast
peer = 127.0.0.1:$((BASE + 3))
input_port = $((BASE + 4))
EOF
}
# A sink for every UDP port the gateway sends to: counts datagrams.
node -e 'const dgram = require("node:dgram"); const n = {};
    for (const p of process.argv.slice(1)) { const s = dgram.createSocket("udp4"); n[p] = 0;
        s.on("message", () => n[p]++); s.bind(Number(p), "127.0.0.1"); }
    process.on("SIGTERM", () => { console.log(JSON.stringify(n)); process.exit(0); });' \
    $((BASE + 1)) $((BASE + 2)) $((BASE + 3)) >"$TMP/sink.out" 2>&1 &
SINK=$!
PIDS+=("$SINK")

# cpu PID: its user + system clock ticks.
cpu () { awk '{ print $14 + $15 }' "/proc/$1/stat" 2>/dev/null || echo 0; }
HZ=$(getconf CLK_TCK)

declare -A res
for r in $(seq 1 "$RUNS"); do
    for cfg in dis all; do
        params "$cfg"
        rm -rf "$TMP/state"
        names=(uavsim mtid bcisd trackerd guidanced gateway)
        start P0 uavsim "$B/uavsim" --exercise "$EX" --time-scale 10
        start P1 mtid "$B/mtid" --exercise "$EX" --instance mtid.uav1
        start P2 bcisd "$B/bcisd" --exercise "$EX" --instance bcisd.uav1
        start P3 trackerd "$B/trackerd" --exercise "$EX"
        start P4 guidanced "$B/guidanced" --exercise "$EX"
        start P5 gateway "$B/gateway" --exercise "$EX" --out "$TMP"
        pids=("$P0" "$P1" "$P2" "$P3" "$P4" "$P5")
        sleep "$WARM"
        c0=()
        for p in "${pids[@]}"; do c0+=("$(cpu "$p")"); done
        t0=$(date +%s.%N)
        sleep "$RUN"
        t1=$(date +%s.%N)
        total=0
        line="run $r, $cfg:"
        for i in "${!pids[@]}"; do
            c=$(($(cpu "${pids[$i]}") - ${c0[$i]}))
            pct=$(awk -v c="$c" -v hz="$HZ" -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", 100 * c / hz / (b - a) }')
            res[$cfg,${names[$i]},$r]=$pct
            total=$(awk -v t="$total" -v p="$pct" 'BEGIN { print t + p }')
            line="$line ${names[$i]} $pct%"
        done
        res[$cfg,total,$r]=$total
        res[$cfg,share,$r]=$(awk -v g="${res[$cfg,gateway,$r]}" -v t="$total" 'BEGIN { printf "%.1f", (t > 0 ? 100 * g / t : 0) }')
        echo "$line; total $total%, the gateway's share ${res[$cfg,share,$r]}%"
        for p in "${pids[@]}"; do stop "$p"; done
        [ "$cfg" = all ] && echo "  (4607 file: $(stat -c %s "$TMP/gateway.4607" 2>/dev/null || echo 0) bytes so far)"
    done
done
kill -TERM "$SINK" 2>/dev/null
wait "$SINK" 2>/dev/null
echo "datagrams received by port (DIS, 4607, CoT): $(cat "$TMP/sink.out")"

median () { tr ' ' '\n' | sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo
echo "--- figures (medians over $RUNS runs of ${RUN} s, time scale 10) ---"
for cfg in dis all; do
    for n in gateway total share; do
        vals=""
        for r in $(seq 1 "$RUNS"); do vals="$vals ${res[$cfg,$n,$r]}"; done
        echo "translators_${cfg}_${n}_pct=$(echo $vals | median)"
    done
done
