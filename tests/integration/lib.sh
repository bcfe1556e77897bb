# shellcheck shell=bash disable=SC2034  # variables used by the scripts that source it
# lib.sh — shared helpers of the integration tests; sourced, never run (so
# not executable: tests/run runs every executable tests/integration/*.sh).
#
# Gives: TAP output (check, is, diag, bail, finish), a temporary folder
# ($TMP) removed on exit, processes started in the background and stopped on
# exit (start, running, wait_exit, stop, kill9), polling with a deadline
# (wait_for), the peer's report files (rep, rep_ge, state_list, state_has),
# sanitizer checks (clean_log) and network namespaces (net, netns_add,
# netns_hosts), deleted on exit. Every process a test starts goes through
# `start`, so the EXIT trap can stop it whatever happens.
#
# Environment: CGS_BUILD (absolute build folder, required), CGS_ROOT (source
# tree), CGS_KEEP=1 keeps $TMP for a post-mortem.

set -u
: "${CGS_BUILD:?set CGS_BUILD to the absolute build folder, e.g. \$PWD/build/asan}"
: "${CGS_ROOT:=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}"
PEER=$CGS_BUILD/tests/integration/peer
MSCGS=$CGS_BUILD/bin/mscgs

# The sanitizer settings of tests/run, for a script run on its own.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$CGS_ROOT/tests/lsan.supp:print_suppressions=0}

# ---- TAP ------------------------------------------------------------------------------

# shellcheck source=tests/tap.sh
. "$CGS_ROOT/tests/tap.sh"

# ---- temporary folder and processes -----------------------------------------------------

TMP=$(mktemp -d "${TMPDIR:-/tmp}/cgs-it.XXXXXX") || { echo "not ok 1 - mktemp"; exit 1; }
NETS=() # network namespaces made by netns_add, deleted on exit
# ipc:// paths must fit a sockaddr_un (108 bytes).
[ ${#TMP} -le 80 ] || { echo "not ok 1 - temporary folder path too long for ipc://: $TMP"; exit 1; }
PIDS=()

# True while process PID exists and is not a zombie (bash reaps its children
# only now and then; `wait PID` later still gives the exit code).
running () {
    local s
    s=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
    s=${s##*) }
    [ "${s%% *}" != Z ]
}

# start VAR NAME COMMAND...: run COMMAND in the background, its stdout and
# stderr in $TMP/NAME.log (appended: a restarted process shares its log);
# its pid goes in VAR.
start () {
    local __var=$1 name=$2
    shift 2
    "$@" >>"$TMP/$name.log" 2>&1 &
    local pid=$!
    PIDS+=("$pid")
    printf -v "$__var" '%s' "$pid"
}

# wait_exit PID SECONDS: wait for PID to end; 0 and its exit code in
# EXIT_CODE when it did in time, 1 (EXIT_CODE=timeout) when it did not.
wait_exit () {
    local pid=$1 end=$((SECONDS + $2))
    while running "$pid"; do
        if [ "$SECONDS" -ge "$end" ]; then
            EXIT_CODE=timeout
            return 1
        fi
        sleep 0.02
    done
    wait "$pid" 2>/dev/null
    EXIT_CODE=$?
    return 0
}

# stop PID: SIGTERM and wait up to 10 s (then SIGKILL); the exit code in
# EXIT_CODE ("timeout" when it had to be killed).
stop () {
    kill -TERM "$1" 2>/dev/null
    if ! wait_exit "$1" 10; then
        s_kill "$1"
        EXIT_CODE=timeout
    fi
}

# s_kill PID: SIGKILL, and no "Killed" notice from bash for it later.
s_kill () {
    kill -KILL "$1" 2>/dev/null
    disown "$1" 2>/dev/null
    local end=$((SECONDS + 10))
    while running "$1" && [ "$SECONDS" -lt "$end" ]; do sleep 0.02; done
}

# kill9 PID: SIGKILL and wait until it is gone (a crash, not a stop).
kill9 () { s_kill "$1"; }

s_cleanup () {
    local pid
    for pid in "${PIDS[@]}"; do
        running "$pid" && kill -TERM "$pid" 2>/dev/null
    done
    for pid in "${PIDS[@]}"; do
        wait_exit "$pid" 5 || s_kill "$pid"
    done
    if [ "$T_FAILED" -gt 0 ]; then
        # Show every process's log, so tests/run's log has the story.
        local f
        for f in "$TMP"/*.log; do
            [ -f "$f" ] || continue
            diag "---- $(basename "$f")"
            sed 's/^/#   /' "$f" | tail -40
        done
    fi
    # The namespaces last: their processes are gone by now.
    local ns
    for ns in "${NETS[@]}"; do ip netns del "$ns" 2>/dev/null; done
    if [ "${CGS_KEEP:-0}" = 1 ]; then
        diag "kept $TMP"
    else
        rm -rf "$TMP"
    fi
}
trap s_cleanup EXIT

# ---- network namespaces ---------------------------------------------------------------
# Names from $TMP's unique suffix (netns_prefix), so parallel runs never
# share a namespace; each is deleted on exit. A setup step that fails (no
# veth or bridge support here) fails the test: it is not a reason to believe
# the network checks pass.

# net COMMAND...: a network setup step; bail with its error when it fails.
net () { "$@" >>"$TMP/net.log" 2>&1 || bail "network setup: $*: $(tail -1 "$TMP/net.log")"; }

# netns_add NAME: a new namespace with its loopback up, deleted on exit.
netns_add () {
    ip netns add "$1" 2>>"$TMP/net.log" || bail "cannot create a network namespace: $(tail -1 "$TMP/net.log")"
    NETS+=("$1")
    net ip -n "$1" link set lo up
}

# netns_hosts PREFIX SUBNET HOST...: a switch, namespace PREFIX-sw with the
# bridge br0, and for the i-th HOST (from 1) namespace PREFIX-HOST whose
# eth0 (SUBNET.i/24) is plugged into the switch's port pHOST (created in
# place: no name ever lives in the root namespace). ADDR[HOST] is its address.
declare -A ADDR=()
netns_hosts () {
    local p=$1 subnet=$2 h i=0 ns
    shift 2
    netns_add "$p-sw"
    net ip -n "$p-sw" link add br0 type bridge
    net ip -n "$p-sw" link set br0 up
    for h; do
        i=$((i + 1))
        ns=$p-$h
        ADDR[$h]=$subnet.$i
        netns_add "$ns"
        net ip -n "$p-sw" link add "p$h" type veth peer name eth0 netns "$ns"
        net ip -n "$p-sw" link set "p$h" master br0
        net ip -n "$p-sw" link set "p$h" up
        net ip -n "$ns" addr add "${ADDR[$h]}/24" dev eth0
        net ip -n "$ns" link set eth0 up
    done
}

# ---- conditions ---------------------------------------------------------------------------

# wait_for SECONDS COMMAND...: poll COMMAND every 20 ms until it succeeds (0)
# or the deadline passes (1).
wait_for () {
    local end=$((SECONDS + $1))
    shift
    until "$@"; do
        [ "$SECONDS" -lt "$end" ] || return 1
        sleep 0.02
    done
}

# rep FILE KEY: the value of KEY in a peer's report ("" when absent).
rep () {
    [ -f "$1" ] || return 0
    local kv words
    read -r -a words 2>/dev/null <"$1" || [ ${#words[@]} -gt 0 ] || return 0
    for kv in "${words[@]}"; do
        if [ "${kv%%=*}" = "$2" ]; then
            printf '%s' "${kv#*=}"
            return 0
        fi
    done
}

# rep_ge FILE KEY N: KEY in FILE is at least N.
rep_ge () {
    local v
    v=$(rep "$1" "$2")
    [ -n "$v" ] && [ "$v" -ge "$3" ]
}

# state_list FILE: the commands in a peer's state report (--state-report),
# one "client number kind" line each; its first line (pid=P restored=R
# commands=N) is read with rep.
state_list () { tail -n +2 "$1" 2>/dev/null; }

# state_has FILE CLIENT NUMBER: how many times the state report holds that command.
state_has () { state_list "$1" | grep -c "^$2 $3 "; }

# clean_log NAME: $TMP/NAME.log has no sanitizer report.
clean_log () {
    ! grep -qE 'Sanitizer|runtime error:|LeakSanitizer' "$TMP/$1.log"
}

# confirmed_tracks EXERCISE: the confirmed (or coasting) tracks of trackerd's
# latest batch, one "id east north" line each.
confirmed_tracks () {
    "$MSCGS" echo track --json --count 1 --timeout 15 --exercise "$1" 2>/dev/null | tail -1 |
        sed 's/{"track_id":/\n&/g' | grep '^{"track_id":' | grep -E 'CONFIRMED|COASTING' |
        sed -n 's/^{"track_id":\([0-9]*\),.*"position":{"east_m":\([-0-9.e]*\),"north_m":\([-0-9.e]*\).*/\1 \2 \3/p'
}

# ---- the exercise file ---------------------------------------------------------------------
# A test writes it as
#   {
#       exercise_header 4 mtid-test scenario=scenario.ini
#       exercise_service uavsim command
#       exercise_service mtid.uav1 uav=uav1 params=radar.ini
#   } >"$EX"

# s_keys KEY=VALUE...: one "KEY = VALUE" line each.
s_keys () {
    local kv
    for kv; do
        case $kv in
        *=*) printf '%s = %s\n' "${kv%%=*}" "${kv#*=}" ;;
        *) echo "exercise file: '$kv' is not KEY=VALUE" >&2; return 1 ;;
        esac
    done
}

# exercise_header ID NAME [KEY=VALUE ...]: the [exercise] section of a
# test's exercise file; the KEY=VALUEs (scenario=scenario.ini) end it.
exercise_header () {
    cat <<EOF
[exercise]
id = $1
name = $2
origin = geo 35.96 -121.23 0
time_scale = 1
seed = 1
state_dir = $TMP/state
EOF
    shift 2
    s_keys "$@"
}

# exercise_service NAME [command] [KEY=VALUE ...]: a [service NAME] section,
# after a blank line. It publishes on ipc://$TMP/PROG.pub, PROG being NAME up
# to its first '.' (mtid for mtid.uav1), unless publish=ENDPOINT is given;
# the word `command` is command = ipc://$TMP/PROG.cmd; the KEY=VALUEs go in
# as given, in their order.
exercise_service () {
    local name=$1 prog=${1%%.*} kv publish=1
    shift
    for kv; do [ "${kv%%=*}" != publish ] || publish=""; done
    printf '\n[service %s]\n' "$name"
    [ -z "$publish" ] || s_keys "publish=ipc://$TMP/$prog.pub"
    for kv; do
        if [ "$kv" = command ]; then
            s_keys "command=ipc://$TMP/$prog.cmd"
        else
            s_keys "$kv" || return
        fi
    done
}

# exercise_scene ID NAME SCENARIO: an exercise file of the scenario with
# the services of one UAV's chain (uavsim, mtid.uav1, bcisd.uav1, trackerd,
# guidanced: the deployed parameters), on stdout.
exercise_scene () {
    exercise_header "$1" "$2" "scenario=$3"
    exercise_service uavsim command
    exercise_service mtid.uav1 uav=uav1
    exercise_service bcisd.uav1 uav=uav1
    exercise_service trackerd "params=$CGS_ROOT/deploy/params/tracker.ini"
    exercise_service guidanced command "params=$CGS_ROOT/deploy/params/guidance.ini"
}

# ---- the scenario file ---------------------------------------------------------------------
# A test writes it as
#   {
#       scenario_ground relief_m=300
#       scenario_uav loiter_radius_m=900
#       scenario_vehicle target hostile TARGET "5000 -4000" "5000 16000" 10 end=stop
#   } >"$TMP/scenario.ini"

# s_merged N DEFAULT... OVERRIDE...: "KEY = VALUE" lines of the N defaults,
# each replaced by an override of its key, then the other overrides.
s_merged () {
    local n=$1 d o k found out=()
    shift
    local defaults=("${@:1:n}") over=("${@:n+1}")
    for d in "${defaults[@]}"; do
        for o in "${over[@]}"; do [ "${o%%=*}" != "${d%%=*}" ] || d=$o; done
        out+=("$d")
    done
    for o in "${over[@]}"; do
        k=${o%%=*} found=""
        for d in "${defaults[@]}"; do [ "${d%%=*}" != "$k" ] || found=1; done
        [ -n "$found" ] || out+=("$o")
    done
    s_keys "${out[@]}"
}

# scenario_ground [KEY=VALUE ...]: the [terrain] section: flat ground, a
# 40 km square on a 100 m grid, unless the KEY=VALUEs say otherwise.
scenario_ground () {
    echo '[terrain]'
    s_merged 3 size_m=40000 resolution_m=100 relief_m=0 "$@"
}

# scenario_uav [KEY=VALUE ...]: [uav uav1], after a blank line: it circles
# the origin 1500 m out, 1200 m up, at 38 m/s, unless the KEY=VALUEs say
# otherwise.
scenario_uav () {
    printf '\n[uav uav1]\n'
    s_merged 4 'position=0 0' altitude_agl_m=1200 airspeed_mps=38 loiter_radius_m=1500 "$@"
}

# scenario_vehicle NAME FORCE MARKING "E N" "E N" SPEED [KEY=VALUE ...]: a
# [vehicle NAME] section, after a blank line, driving from the first point
# to the second at SPEED m/s; the KEY=VALUEs (end=stop, kind=wheeled) after.
scenario_vehicle () {
    printf '\n[vehicle %s]\n' "$1"
    s_keys "force=$2" "marking=$3" "point=$4" "point=$5" "speed_mps=$6" "${@:7}"
}

# CGS_NO_PEER=1: a script that needs no peer (a benchmark using the namespaces).
[ -n "${CGS_NO_PEER:-}" ] || [ -x "$PEER" ] || bail "no test peer at $PEER (make O=... SAN=1 test-build)"
