#!/bin/bash
# bus.sh — publish/subscribe across processes (common/cgs_bus through the
# service shell): (a) every message arrives at a modest rate; (b) a
# subscriber that falls behind a burst counts what it lost as gaps;
# (c) a publisher killed with -9 and restarted is counted as a restart, what
# it sent before the subscriber reconnected as gaps, and the subscriber keeps
# receiving; (d) malformed payloads are counted and
# dropped, and the subscriber keeps running. TAP on stdout. See README.md.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

EX=$TMP/exercise.ini
{
    exercise_header 7 it-bus
    # The test publisher runs as program uavsim, the publisher of `clock` in the
    # topic catalogue, so a subscriber to clock connects to it.
    exercise_service peer.pub program=uavsim publish="ipc://$TMP/pub.ipc"
    # The raw sender of malformed messages (peer --send-garbage), also a clock publisher.
    exercise_service peer.bad program=uavsim publish="ipc://$TMP/bad.ipc"
    # The subscriber publishes nothing.
    exercise_service peer.sub publish="ipc://$TMP/sub.pub"
} >"$EX"

# start_sub VAR NAME [options]: a subscriber to clock (counted) and health
# (to know it is connected), reporting to $TMP/NAME.rep.
start_sub () {
    local var=$1 name=$2
    shift 2
    start "$var" "$name" "$PEER" --exercise "$EX" --instance peer.sub --subscribe clock \
        --subscribe health --report "$TMP/$name.rep" "$@"
}
# start_pub VAR NAME [options]: the clock publisher, reporting to $TMP/NAME.rep.
start_pub () {
    local var=$1 name=$2
    shift 2
    start "$var" "$name" "$PEER" --as uavsim --exercise "$EX" --instance peer.pub \
        --report "$TMP/$name.rep" "$@"
}
# The subscriber is connected and subscribed once it has the publisher's
# health: it subscribed to clock before health, over the same connection.
subscribed () { wait_for 10 rep_ge "$TMP/$1.rep" health 1; }

# ---- (a) every message arrives ------------------------------------------------------------
t0=$SECONDS
N=400
start_sub SUB a-sub
start_pub PUB a-pub --publish-clock $N --rate 200 --wait-go
check "a: subscriber connected (it hears the publisher's health)" subscribed a-sub
kill -USR1 "$PUB"
check "a: all $N clock messages arrive at 200 Hz" wait_for 15 rep_ge "$TMP/a-sub.rep" received $N
stop "$SUB"
is "$EXIT_CODE" 0 "a: subscriber stops on SIGTERM with exit code 0"
stop "$PUB"
is "$EXIT_CODE" 0 "a: publisher stops on SIGTERM with exit code 0"
R=$TMP/a-sub.rep
is "$(rep "$R" received) $(rep "$R" gaps) $(rep "$R" stale) $(rep "$R" malformed) $(rep "$R" restarts)" \
    "$N 0 0 0 0" "a: received $N, gaps 0, stale 0, malformed 0, restarts 0"
is "$(rep "$R" first_seq)-$(rep "$R" last_seq) $(rep "$R" mismatch)" "1-$N 0" \
    "a: sequence numbers 1..$N, each message's tick equal to its sequence number"
is "$(rep "$TMP/a-pub.rep" published)" $N "a: publisher published $N"
diag "a: $((SECONDS - t0)) s"

# ---- (b) a slow subscriber counts gaps ------------------------------------------------------
# The subscriber holds in its handler on the first message while the
# publisher bursts B messages; past the high-water marks (100000 at the
# publisher, 100000 at the subscriber) the PUB socket drops. After the
# release, the publisher's next message (every 0.5 s after the burst) shows
# the subscriber what it missed.
t0=$SECONDS
B=300000
start_sub SUB b-sub --slow-ms 30000
start_pub PUB b-pub --burst $B --wait-go
check "b: subscriber connected" subscribed b-sub
kill -USR1 "$PUB"
check "b: publisher sent a burst of $B" wait_for 30 rep_ge "$TMP/b-pub.rep" published $B
check "b: subscriber holds on its first message" wait_for 10 rep_ge "$TMP/b-sub.rep" held 1
kill -USR1 "$SUB"
check "b: subscriber catches up to a message after the burst" \
    wait_for 30 rep_ge "$TMP/b-sub.rep" last_seq $((B + 1))
stop "$SUB"
is "$EXIT_CODE" 0 "b: subscriber stops on SIGTERM with exit code 0"
stop "$PUB"
is "$EXIT_CODE" 0 "b: publisher stops on SIGTERM with exit code 0"
R=$TMP/b-sub.rep
r=$(rep "$R" received) g=$(rep "$R" gaps) f=$(rep "$R" first_seq) l=$(rep "$R" last_seq)
diag "b: received $r, gaps $g, sequence $f..$l; publisher published $(rep "$TMP/b-pub.rep" published)"
is "$f" 1 "b: the first message received is #1"
is "$((r + g))" "$((l - f + 1))" "b: received + gaps == messages sent since the first one received"
check "b: gaps > 0 (the subscriber fell behind its high-water mark)" test "$g" -gt 0
is "$(rep "$R" stale) $(rep "$R" malformed) $(rep "$R" restarts) $(rep "$R" mismatch)" "0 0 0 0" \
    "b: stale 0, malformed 0, restarts 0, ticks equal to sequence numbers"
check "b: the publisher published at least up to the last number received" \
    test "$(rep "$TMP/b-pub.rep" published)" -ge "$l"
# A non-blocking PUB drops per subscriber without telling the sender: the
# subscriber's gaps are the record, the publisher's drop count stays 0.
is "$(rep "$TMP/b-pub.rep" drops)" 0 "b: publisher's drop counter is 0 (drops show as gaps downstream)"
diag "b: $((SECONDS - t0)) s"

# ---- (c) publisher killed and restarted -----------------------------------------------------
t0=$SECONDS
start_sub SUB c-sub
start_pub PUB c-pub1 --publish-clock 1000000 --rate 50
check "c: subscriber receives from the first publisher" wait_for 10 rep_ge "$TMP/c-sub.rep" received 5
kill9 "$PUB"
r1=$(rep "$TMP/c-sub.rep" received)
start_pub PUB c-pub2 --publish-clock 1000000 --rate 50
check "c: subscriber counts the restart (a new epoch)" wait_for 10 rep_ge "$TMP/c-sub.rep" restarts 1
check "c: subscriber keeps receiving from the restarted publisher" \
    wait_for 10 rep_ge "$TMP/c-sub.rep" received $((r1 + 10))
if [ -x "$MSCGS" ]; then
    "$MSCGS" echo clock --json --count 3 --timeout 10 --exercise "$EX" >"$TMP/c-echo.out" 2>"$TMP/c-echo.log"
    rc=$?
    is "$rc $(grep -c '"tick"' "$TMP/c-echo.out")" "0 3" "c: mscgs echo clock --json --count 3 prints 3 clock messages"
fi
stop "$SUB"
is "$EXIT_CODE" 0 "c: subscriber stops on SIGTERM with exit code 0"
stop "$PUB"
is "$EXIT_CODE" 0 "c: restarted publisher stops on SIGTERM with exit code 0"
R=$TMP/c-sub.rep
# The restarted publisher's first messages go out before the subscriber has
# reconnected: the bus counts them as gaps (a new epoch numbers from 1).
e=$(rep "$R" epoch_first_seq)
is "$(rep "$R" restarts) $(rep "$R" epochs) $(rep "$R" gaps) $(rep "$R" stale) $(rep "$R" mismatch)" \
    "1 2 $((e - 1)) 0 0" "c: restarts 1 (2 epochs), gaps = the new epoch's messages before the first received ($((e - 1))), stale 0, ticks equal to sequence numbers"
diag "c: received $r1 before the kill, $(rep "$R" received) in all; the new epoch's first message received is #$e"
diag "c: $((SECONDS - t0)) s"

# ---- (d) malformed payloads -------------------------------------------------------------------
# peer --send-garbage binds peer.bad's endpoint with a raw XPUB socket, waits
# for the subscription, and sends clock #1, five malformed clock messages (a
# lone topic frame, a truncated payload, an empty payload, a payload without
# a header, a message with a third frame), then clock #2 and #3.
t0=$SECONDS
start_sub SUB d-sub
start GARBAGE d-garbage "$PEER" --send-garbage "ipc://$TMP/bad.ipc" --wait-ms 10000 --exercise-id 7
check "d: the raw sender found the subscriber and sent" wait_exit "$GARBAGE" 15
is "$EXIT_CODE" 0 "d: the raw sender exits 0"
check "d: the subscriber counts 5 malformed messages" wait_for 10 rep_ge "$TMP/d-sub.rep" malformed 5
check "d: the subscriber handles the 3 valid messages around them" \
    wait_for 10 rep_ge "$TMP/d-sub.rep" received 3
R=$TMP/d-sub.rep
is "$(rep "$R" malformed) $(rep "$R" received) $(rep "$R" gaps) $(rep "$R" stale) $(rep "$R" first_seq)-$(rep "$R" last_seq)" \
    "5 3 0 0 1-3" "d: malformed 5, received 3 (#1..#3), gaps 0, stale 0"
check "d: the subscriber is still running" running "$SUB"
r1=$(rep "$R" received)
start_pub PUB d-pub --publish-clock 1000000 --rate 100
check "d: and still receives from a well-behaved publisher" wait_for 10 rep_ge "$R" received $((r1 + 10))
stop "$SUB"
is "$EXIT_CODE" 0 "d: subscriber stops on SIGTERM with exit code 0"
stop "$PUB"
is "$(rep "$R" malformed)" 5 "d: still 5 malformed at the end"
diag "d: $((SECONDS - t0)) s"

# ---- every process ------------------------------------------------------------------------
for f in "$TMP"/*.log; do
    name=$(basename "$f" .log)
    check "$name: no sanitizer report" clean_log "$name"
done
finish
