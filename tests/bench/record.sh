#!/bin/bash
# record.sh — `mscgs record` at the 1,000-vehicle scenario
# (deploy/scenarios/bench-1000.ini) at time scale 10, with the services that
# publish (uavsim, mtid, bcisd, trackerd, guidanced): after WARM s, over RUN
# s of wall time, the messages a second it recorded, its CPU (user + system,
# its own getrusage over its run, percent of one core), and the file's growth per
# simulated hour (bytes written over the simulation time that passed,
# from the clock topic's sim time in the recording's first and last clock
# messages); the same for --no-compress. R runs (default 3), medians.
#   tests/bench/record.sh BUILD_DIR [RUN_S] [RUNS]     (make bench-record)
set -u
build=${1:?usage: tests/bench/record.sh BUILD_DIR [RUN_S] [RUNS]}
export CGS_BUILD=$(cd "$build" && pwd)
RUN=${2:-30}
RUNS=${3:-3}
WARM=10
export CGS_NO_PEER=1
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/../integration/lib.sh"

B=$CGS_BUILD/bin
for p in uavsim mtid bcisd trackerd guidanced mscgs; do [ -x "$B/$p" ] || bail "no $B/$p"; done
EX=$TMP/exercise.ini
exercise_scene 19 record-bench "$CGS_ROOT/deploy/scenarios/bench-1000.ini" >"$EX"
declare -A res
for r in $(seq 1 "$RUNS"); do
    for cfg in zstd plain; do
        rm -rf "$TMP/state"
        start P0 uavsim "$B/uavsim" --exercise "$EX" --time-scale 10
        start P1 mtid "$B/mtid" --exercise "$EX" --instance mtid.uav1
        start P2 bcisd "$B/bcisd" --exercise "$EX" --instance bcisd.uav1
        start P3 trackerd "$B/trackerd" --exercise "$EX"
        start P4 guidanced "$B/guidanced" --exercise "$EX"
        sleep "$WARM"
        extra=()
        [ "$cfg" = plain ] && extra=(--no-compress)
        start REC record-$cfg-$r "$B/mscgs" record --exercise "$EX" --out "$TMP/$cfg-$r.mcap" \
            --duration "$RUN" "${extra[@]}"
        wait_exit "$REC" $((RUN + 20))
        for p in $P4 $P3 $P2 $P1 $P0; do stop "$p"; done
        line=$(grep "messages in" "$TMP/record-$cfg-$r.log" | tail -1)
        msgs=$(sed -n 's/^mscgs record: \([0-9]*\) messages in.*/\1/p' <<<"$line")
        size=$(stat -c %s "$TMP/$cfg-$r.mcap")
        sim=$(node "$CGS_ROOT/tests/interop/mcap_check.mjs" "$TMP/$cfg-$r.mcap" --dump clock 2>/dev/null |
            head -n -1 | node -e 'const l = require("fs").readFileSync(0, "utf8").trim().split("\n").map(JSON.parse);
                const s = (m) => m.header.simTimeS ?? m.header.sim_time_s; console.log(l.length > 1 ? s(l.at(-1)) - s(l[0]) : 0)')
        res[$cfg,rate,$r]=$(awk -v m="$msgs" -v d="$RUN" 'BEGIN { printf "%.0f", m / d }')
        res[$cfg,mbh,$r]=$(awk -v s="$size" -v t="$sim" 'BEGIN { printf "%.1f", (t > 0 ? s / t * 3600 / 1e6 : 0) }')
        res[$cfg,cpu,$r]=$(awk -v c="$(grep -o 'cpu [0-9.]* %' "$TMP/record-$cfg-$r.log" | tail -1 | cut -d' ' -f2)" 'BEGIN { printf "%.1f", c }')
        echo "run $r, $cfg: $msgs messages in $RUN s (${res[$cfg,rate,$r]}/s), $size bytes over $sim s simulated (${res[$cfg,mbh,$r]} MB per simulated hour), recorder CPU ${res[$cfg,cpu,$r]}%"
    done
done
median () { tr ' ' '\n' | sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo
echo "--- figures (medians over $RUNS runs of ${RUN} s, time scale 10, 1,000 vehicles) ---"
for cfg in zstd plain; do
    for n in rate cpu mbh; do
        vals=""
        for r in $(seq 1 "$RUNS"); do vals="$vals ${res[$cfg,$n,$r]}"; done
        echo "record_${cfg}_${n}=$(echo $vals | median)"
    done
done
