#!/bin/bash
# commands.sh — the command channel across processes (common/cgs_cmd through
# the service shell): (1) a command sent while its server is killed and
# restarted arrives exactly once; (2) a server that crashes after applying a
# command but before writing its state file and replying, and is restarted:
# the retry is applied once to the saved state, while the handler's own apply
# log (a side effect outside that state) holds it twice; a clean restart
# restores exactly the state saved; (3) duplicates within one server life,
# and after a clean restart, are answered from the stored reply and applied
# once. TAP on stdout. See README.md.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

EX=$TMP/exercise.ini
{
    exercise_header 8 it-commands
    for s in cmd crash dup; do
        exercise_service "peer.$s" publish="ipc://$TMP/$s.pub" command="ipc://$TMP/$s.ipc"
    done
} >"$EX"

# start_server VAR NAME INSTANCE [options]: a command server whose apply log
# is $TMP/INSTANCE.applied, reporting its counters to $TMP/NAME.rep and its
# state (the commands applied, restored then as saved) to $TMP/NAME.st;
# returns once it serves (its first report is written after the ROUTER
# socket is bound and the saved state restored).
start_server () {
    local var=$1 name=$2 inst=$3
    shift 3
    start "$var" "$name" "$PEER" --exercise "$EX" --instance "$inst" --serve-commands \
        --apply-log "$TMP/$inst.applied" --report "$TMP/$name.rep" \
        --state-report "$TMP/$name.st" "$@"
    wait_for 10 test -f "$TMP/$name.rep"
}
# start_client VAR NAME INSTANCE CLIENT_ID [options]: peer --call ping in the
# background, its reply line in $TMP/NAME.log.
start_client () {
    local var=$1 name=$2 inst=$3 id=$4
    shift 4
    start "$var" "$name" "$PEER" --call ping --endpoint "ipc://$TMP/${inst#peer.}.ipc" \
        --client-id "$id" "$@"
}
# applied INSTANCE CLIENT_ID NUMBER: how many times the apply log holds that command.
applied () { grep -c "^$2 $3 ping\$" "$TMP/$1.applied" 2>/dev/null; }
# field NAME KEY: KEY=value from the reply line in $TMP/NAME.log.
field () { sed -n "s/^reply .*\b$2=\([^ ]*\).*/\1/p" "$TMP/$1.log"; }
# detail NAME: the reply's detail (spaces and all).
detail () { sed -n 's/^reply .* detail=\(.*\) error=.*/\1/p' "$TMP/$1.log"; }

# ---- (1) the server is killed and restarted while a command is on its way -----------------
t0=$SECONDS
start_server S 1-server peer.cmd || bail "1: server peer.cmd did not start"
kill9 "$S"
start_client C 1-client peer.cmd restart-client --timeout-ms 300 --attempts 30
sleep 1 # scenario: the server stays down about 1 s while the client retries
check "1: the client keeps retrying while the server is down" running "$C"
start_server S 1-server-again peer.cmd || bail "1: server peer.cmd did not restart"
check "1: the client gets a reply after the restart" wait_exit "$C" 20
is "$EXIT_CODE $(field 1-client status)" "0 OK" "1: the reply is OK"
is "$(applied peer.cmd restart-client 1)" 1 "1: the command was applied exactly once"
is "$(wc -l <"$TMP/peer.cmd.applied")" 1 "1: and nothing else was applied"
is "$(state_list "$TMP/1-server-again.st")" "restart-client 1 ping" \
    "1: the saved state holds it once, and nothing else"
diag "1: reply after $(field 1-client elapsed_ms) ms, duplicate=$(field 1-client duplicate)"
if [ -x "$MSCGS" ]; then
    "$MSCGS" ping peer.cmd --exercise "$EX" >"$TMP/1-mscgs-ping.out" 2>"$TMP/1-mscgs-ping.log"
    is "$?" 0 "1: mscgs ping peer.cmd answers"
    is "$(grep -c ' ping$' "$TMP/peer.cmd.applied") $(rep "$TMP/1-server-again.st" commands)" \
        "2 2" "1: the mscgs ping was applied once too (apply log and state)"
fi
stop "$S"
is "$EXIT_CODE" 0 "1: restarted server stops on SIGTERM with exit code 0"
diag "1: $((SECONDS - t0)) s"

# ---- (2) crash between apply and acknowledgement --------------------------------------------
# A first command is applied and saved. On the second the handler adds it to
# the state in memory and appends it to its apply log (fsync), then the
# server _exits (3) before the handler returns: the command server never
# writes the state file (nor sends the reply). The restarted server restores
# the state as it was saved (the first command only), has no stored reply
# for the retry, and applies it afresh: once in the saved state, but twice in
# the apply log, which the crash cannot roll back.
t0=$SECONDS
start_server S 2-server peer.crash --die-after-apply 2 || bail "2: server peer.crash did not start"
start_client C 2-first peer.crash first-client --timeout-ms 2000 --attempts 3
check "2: a first command gets a reply" wait_exit "$C" 20
is "$EXIT_CODE $(field 2-first status)" "0 OK" "2: ... OK, applied and saved"
start_client C 2-client peer.crash crash-client --timeout-ms 300 --attempts 30
check "2: the server dies right after applying the second command" wait_exit "$S" 10
is "$EXIT_CODE" 3 "2: ... with exit code 3 (--die-after-apply)"
is "$(applied peer.crash crash-client 1)" 1 "2: the command is in the apply log (fsync'd before the crash)"
is "$(state_list "$TMP/2-server.st")" "first-client 1 ping" \
    "2: the last state saved holds the first command only"
check "2: the client is still waiting (no reply was sent)" running "$C"
start_server S 2-server-again peer.crash || bail "2: server peer.crash did not restart"
is "$(rep "$TMP/2-server-again.st" restored)" 1 "2: the restarted server restored 1 command"
check "2: ... the first one" grep -q 'restored: first-client 1 ping$' "$TMP/2-server-again.log"
check "2: the client gets a reply from the restarted server" wait_exit "$C" 20
is "$EXIT_CODE $(field 2-client status) $(field 2-client duplicate)" "0 OK no" \
    "2: the reply is OK and not marked duplicate (the server had no stored reply)"
is "$(state_has "$TMP/2-server-again.st" crash-client 1)" 1 \
    "2: the saved state holds the command exactly once"
is "$(state_list "$TMP/2-server-again.st" | tr '\n' ,)" "first-client 1 ping,crash-client 1 ping," \
    "2: ... after the first, and nothing else"
n=$(applied peer.crash crash-client 1)
diag "2: OBSERVED: command crash-client #1 is in the apply log $n times, in the state once"
is "$n" 2 "2: the apply log (a side effect outside the saved state) holds it twice: at-least-once"
stop "$S"
is "$EXIT_CODE" 0 "2: restarted server stops on SIGTERM with exit code 0"
check "2: the state file is STATE_DIR/INSTANCE.state" test -s "$TMP/state/peer.crash.state"
check "2: ... and there is no .replies file any more" \
    test -z "$(find "$TMP/state" -name '*.replies')"

# A clean restart restores exactly the state saved before it.
saved=$(state_list "$TMP/2-server-again.st")
start_server S 2-server-third peer.crash || bail "2r: server peer.crash did not restart"
is "$(rep "$TMP/2-server-third.st" restored) $(rep "$TMP/2-server-third.st" pid)" "2 $S" \
    "2r: after a clean restart, 2 commands restored (by the new process)"
is "$(state_list "$TMP/2-server-third.st")" "$saved" "2r: the restored state equals the state saved"
is "$(state_has "$TMP/2-server-third.st" crash-client 1)" 1 "2r: ... with the crashed command once"
stop "$S"
is "$EXIT_CODE $(rep "$TMP/2-server-third.rep" applied)" "0 0" \
    "2r: server stops with exit code 0, nothing applied"
diag "2: $((SECONDS - t0)) s"

# ---- (3) duplicates answered from the stored reply ---------------------------------------------
# The handler takes 700 ms; the client gives up on each attempt after 200 ms
# and resends the same command (same client id and number) on a new socket.
# The server applies the first copy, then answers the queued copies from the
# stored reply; the client takes the first reply to reach a live attempt.
t0=$SECONDS
start_server S 3-server peer.dup --apply-delay-ms 700 || bail "3: server peer.dup did not start"
start_client C 3-client peer.dup dup-client --timeout-ms 200 --attempts 20
check "3: the client gets a reply" wait_exit "$C" 20
is "$EXIT_CODE $(field 3-client status) $(field 3-client duplicate)" "0 OK yes" \
    "3: the reply is OK, answered from the stored reply (duplicate=yes)"
is "$(applied peer.dup dup-client 1)" 1 "3: the command was applied once"
check "3: the server counts the retries as duplicates" wait_for 5 rep_ge "$TMP/3-server.rep" duplicates 1
is "$(rep "$TMP/3-server.rep" server_applied) $(rep "$TMP/3-server.rep" applied)" "1 1" \
    "3: the server applied 1 command (handler called once)"
first=$(detail 3-client)
diag "3: $(rep "$TMP/3-server.rep" duplicates) duplicates; stored detail: $first"

# A second client process with the same id sends command #1 again.
start_client C 3b-client peer.dup dup-client --timeout-ms 2000 --attempts 3
check "3b: a repeat from a restarted client gets a reply" wait_exit "$C" 20
is "$EXIT_CODE $(field 3b-client duplicate)" "0 yes" "3b: OK, from the stored reply"
is "$(detail 3b-client)" "$first" "3b: the stored reply is the one sent before"
is "$(applied peer.dup dup-client 1)" 1 "3b: still applied once"

# A clean restart: the replies and the state were written to the state file.
stop "$S"
is "$EXIT_CODE" 0 "3c: server stops on SIGTERM with exit code 0"
check "3c: the stored replies are in the state file" test -s "$TMP/state/peer.dup.state"
start_server S 3c-server peer.dup --apply-delay-ms 700 || bail "3c: server peer.dup did not restart"
start_client C 3c-client peer.dup dup-client --timeout-ms 2000 --attempts 3
check "3c: a repeat after the server's restart gets a reply" wait_exit "$C" 20
is "$EXIT_CODE $(field 3c-client duplicate)" "0 yes" "3c: OK, from the reply stored before the restart"
is "$(detail 3c-client)" "$first" "3c: the same reply as before the restart"
is "$(rep "$TMP/3c-server.st" restored) $(state_list "$TMP/3c-server.st")" \
    "1 $(state_list "$TMP/3-server.st")" "3c: the restored state equals the state saved"
is "$(applied peer.dup dup-client 1)" 1 "3c: still applied once"
stop "$S"
is "$EXIT_CODE $(rep "$TMP/3c-server.rep" applied)" "0 0" "3c: server stops with exit code 0, nothing applied"
diag "3: $((SECONDS - t0)) s"

# ---- every process ------------------------------------------------------------------------
for f in "$TMP"/*.log; do
    name=$(basename "$f" .log)
    check "$name: no sanitizer report" clean_log "$name"
done
finish
