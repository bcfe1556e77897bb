#!/bin/bash
# replay.sh — `mscgs replay` of a recording at SPEED (recorded seconds per
# wall second; 50 for "a one-hour exercise at 50x" when the recording is of
# an exercise run at time scale 1), into a bus of its own that a second
# `mscgs record` listens to: the wall time from the replay's start to its
# end, the messages it sent and their rate, its CPU, and how many the
# listener received (every one, or the replay outran the bus). R runs
# (default 3), medians.
#   tests/bench/replay.sh BUILD_DIR RECORDING EXERCISE [SPEED] [RUNS]
#   (make bench-replay REC=FILE [EX=FILE] [SPEED=X])
# A one-hour recording: `mscgs run --record --duration 3600 --out DIR`.
set -u
build=${1:?usage: tests/bench/replay.sh BUILD_DIR RECORDING EXERCISE [SPEED] [RUNS]}
REC=$(realpath "${2:?the recording}")
EXF=$(realpath "${3:?the exercise it was recorded in}")
SPEED=${4:-50}
RUNS=${5:-3}
export CGS_BUILD=$(cd "$build" && pwd)
export CGS_NO_PEER=1
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/../integration/lib.sh"
B=$CGS_BUILD/bin
[ -x "$B/mscgs" ] || bail "no $B/mscgs"
[ -f "$REC" ] || bail "no recording at $REC"

declare -A res
for r in $(seq 1 "$RUNS"); do
    REX=$TMP/replay-$r.ini
    start P replay-$r "$B/mscgs" replay "$REC" --exercise "$EXF" --live none --paused --once \
        --speed "$SPEED" --dir "$TMP/rdir-$r" --replay-exercise "$REX" --id $((200 + r))
    wait_for 600 grep -q "standing in for" "$TMP/replay-$r.log" || bail "the replay did not start"
    start L listen-$r "$B/mscgs" record --exercise "$REX" --out "$TMP/again-$r.mcap"
    wait_for 10 grep -q "topics from" "$TMP/listen-$r.log" || bail "the listener did not start"
    sleep 1
    "$B/mscgs" resume --exercise "$REX" >/dev/null || bail "resume refused"
    wait_exit "$P" 100000
    sleep 1
    stop "$L"
    line=$(grep "the end" "$TMP/replay-$r.log" | tail -1)
    sent=$(sed -n 's/.*, \([0-9]*\) messages sent in.*/\1/p' <<<"$line")
    wall=$(sed -n 's/.*messages sent in \([0-9.]*\) s of wall.*/\1/p' <<<"$line")
    cpu=$(sed -n 's/.*cpu \([0-9.]*\) %.*/\1/p' <<<"$line")
    span=$(sed -n 's/.*the end (\([0-9.]*\) s).*/\1/p' <<<"$line")
    got=$(sed -n 's/^mscgs record: \([0-9]*\) messages in .*/\1/p' "$TMP/listen-$r.log")
    states=$(grep -o 'replay [0-9]*' "$TMP/listen-$r.log" | tail -1 | cut -d' ' -f2)
    res[wall,$r]=$wall
    res[rate,$r]=$(awk -v m="$sent" -v w="$wall" 'BEGIN { printf "%.0f", m / w }')
    res[cpu,$r]=$cpu
    res[lost,$r]=$((sent - (got - ${states:-0})))
    echo "run $r: $span s of recording at ${SPEED}x: $sent messages in $wall s (${res[rate,$r]}/s, achieved $(awk -v s="$span" -v w="$wall" 'BEGIN { printf "%.1f", s / w }')x), replay CPU $cpu%, the listener missed ${res[lost,$r]}"
done
median () { tr ' ' '\n' | sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo
echo "--- figures (medians over $RUNS runs, speed ${SPEED}x, $(basename "$REC")) ---"
for n in wall rate cpu lost; do
    vals=""
    for r in $(seq 1 "$RUNS"); do vals="$vals ${res[$n,$r]}"; done
    echo "replay_${n}=$(echo $vals | median)"
done
finish >/dev/null
