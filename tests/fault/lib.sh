# shellcheck shell=bash disable=SC2034  # variables used by the scripts that source it
# tests/fault/lib.sh — fault injection into one service during intercepts;
# sourced by tests/fault/SERVICE.sh (so not executable itself).
#
# fault_main INSTANCE runs the whole exercise (uavsim, mtid, bcisd, trackerd,
# guidanced, imagerd, gateway, stationd, on ipc:// endpoints, under the test
# build's sanitizers and its fault channel) and then, for each fault kind in
# FAULT_KINDS, FAULT_TRIALS times: designates a hostile track, waits a random
# moment, injects the fault into INSTANCE, sends operator commands while it
# is out, heals it, and checks that
#   - the service is back: its output is heard again (the recovery time, from
#     the heal to its first message, goes to test-artifacts/fault/recovery.tsv);
#   - the others resume without a restart of their own (same processes, no new
#     publisher epoch, each heard after the heal);
#   - every operator command sent during the fault was answered (the
#     airspeed ok; the designation ok, or refused because its track ended
#     meanwhile), the designation number went up by exactly one for an
#     accepted designation and not at all for a refused one (none lost, none
#     applied twice), and the commanded airspeed is the one sent;
#   - the intercept completes (the target comes under the footprint).
# Fault kinds:
#   kill9     SIGKILL, restarted 0.2 to 1 s later (as systemd's RestartSec)
#   stop      SIGSTOP for 3 s, then SIGCONT
#   restart2  stopped (SIGTERM) and started twice in a row
#   crash     the fault channel's crash (abort), restarted 0.5 s later
#   hang      the fault channel's hang for 3 s
#   slow      the fault channel's slow-down: 60 ms stalls in every 100 ms for 4 s
# Environment: FAULT_KINDS (default "kill9 stop restart2" and one of crash,
# hang, slow by turn), FAULT_TRIALS (per kind, default 1), FAULT_SEED (the
# random moments; default from the clock, printed), FAULT_SCALE (time scale,
# default 20).
# shellcheck source=tests/integration/lib.sh
. "$CGS_ROOT/tests/integration/lib.sh"

B=$CGS_BUILD/bin
OBSERVER=$CGS_BUILD/tests/fault/observer
ART=$CGS_BUILD/test-artifacts/fault
for b in uavsim mtid bcisd trackerd guidanced imagerd gateway stationd mscgs; do
    [ -x "$B/$b" ] || bail "no $B/$b"
done
[ -x "$OBSERVER" ] || bail "no $OBSERVER (make O=... SAN=1 test-build)"
mkdir -p "$ART"

ALL="uavsim mtid.uav1 bcisd.uav1 trackerd guidanced imagerd.uav1 gateway stationd"
# Each instance's output: the topic whose messages show it is back.
declare -A TOPIC=([uavsim]=clock [mtid.uav1]=mti [bcisd.uav1]=bcis [trackerd]=track
    [guidanced]=intercept [imagerd.uav1]=image [gateway]=health [stationd]=health)
declare -A PID=()
EX=$TMP/exercise.ini
OBS=$TMP/observer.txt
SCALE=${FAULT_SCALE:-20}

now () { date +%s.%N; }
M () { "$MSCGS" "$@" --exercise "$EX"; }
# Seconds between two times, to the millisecond.
since () { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }

fault_exercise () {
    local gwport=$((20000 + RANDOM % 20000))
    HTTP_PORT=$((gwport + 1))
    {
        exercise_header $((40 + RANDOM % 100)) fault-test scenario=scenario.ini
        exercise_service uavsim command
        exercise_service mtid.uav1 uav=uav1
        exercise_service bcisd.uav1 uav=uav1
        exercise_service trackerd
        exercise_service guidanced command params=guidance.ini
        exercise_service imagerd.uav1 command uav=uav1 params=imager.ini
        exercise_service gateway params=gateway.ini
        exercise_service stationd params=station.ini
    } | sed "s/^time_scale = 1$/time_scale = $SCALE/" >"$EX"
    # Flat ground; the UAV circles the origin; hostile movers go to and fro
    # on four 12 km roads that run out from 2 to 14 km along the axes, and a
    # friendly truck on a diagonal between them. The roads point at the
    # orbit, so the radar sees the movers' full speed whether the UAV
    # loiters or flies along the road to intercept: the tests judge the
    # services' recovery, and a mover driving across the radar's line of
    # sight (in its Doppler notch for minutes while the UAV flies abeam of
    # it) is a tracking case, measured by make montecarlo's notch family.
    {
        scenario_ground
        scenario_uav
        scenario_vehicle east hostile EAST "2000 0" "14000 0" 9 end=reverse
        scenario_vehicle west hostile WEST "-14000 0" "-2000 0" 7 end=reverse
        scenario_vehicle north hostile NORTH "0 2000" "0 14000" 8 end=reverse
        scenario_vehicle south hostile SOUTH "0 -14000" "0 -2000" 6 end=reverse
        scenario_vehicle truck friendly "FRIEND TRK" "-3000 -7000" "-7000 -3000" 9 kind=wheeled end=reverse
    } >"$TMP/scenario.ini"
    sed -e 's/^width_px = 640$/width_px = 320/' -e 's/^height_px = 480$/height_px = 240/' \
        -e 's/^frame_rate_hz = 5$/frame_rate_hz = 1/' \
        "$CGS_ROOT/deploy/params/imager.ini" >"$TMP/imager.ini"
    printf '[network]\nport = %d\nmode = unicast\npeer = 127.0.0.1:%d\nbind = 127.0.0.1\n' \
        "$gwport" "$((gwport + 2))" >"$TMP/gateway.ini"
    printf '[http]\nport = %d\n' "$HTTP_PORT" >"$TMP/station.ini"
    # The hand-over by nearness as well as by the tracker's links: the
    # tracker still ends the track of a vehicle that halts and turns back at
    # its road's end and links no successor, and these tests judge the
    # services' recovery, not that (the default, links alone, is measured
    # by make montecarlo).
    sed -e 's/^handover = links$/handover = near/' "$CGS_ROOT/deploy/params/guidance.ini" >"$TMP/guidance.ini"
    grep -q '^handover = near$' "$TMP/guidance.ini" ||
        bail "deploy/params/guidance.ini has no 'handover = links' line for the fault tests to change"
}

# svc_start INSTANCE TAG: start it (log INSTANCE-TAG.log), its pid in PID.
svc_start () {
    local in=$1 p prog=${1%%.*}
    local extra=()
    [ "$prog" = imagerd ] && extra=(--out "$TMP/images")
    start p "$in-$2" "$B/$prog" --exercise "$EX" --instance "$in" "${extra[@]}"
    PID[$in]=$p
}

# heard SOURCE TOPIC AFTER: the wall time of SOURCE's first TOPIC message
# after AFTER in the observer's file ("" when none yet).
heard () {
    awk -v s="$1" -v t="$2" -v a="$3" '$1 > a && $2 == "msg" && $3 == s && $4 == t { print $1; exit }' "$OBS"
}
# restarted SOURCE AFTER: a new epoch of SOURCE seen after AFTER.
restarted () { awk -v s="$1" -v a="$2" '$1 > a && $2 == "epoch" && $3 == s { f = 1 } END { exit !f }' "$OBS"; }
# The latest intercept line of uav 1: "STATE NUMBER TRACK".
icpt_now () { awk '$2 == "icpt" && $3 == 1 { l = $4 " " $5 " " $6 } END { print l }' "$OBS"; }

# A confirmed track on one of the four roads (not the truck's) within 11 km
# of the orbit (beyond 13 km the radar sees a vehicle in one scan of three),
# with road enough ahead of it that its mover does not reach the road's end
# and turn back during the trial: 4 km for one coming in (a head-on
# intercept), 8 km for one going out (the UAV must overtake it and turn
# back: ten minutes); other than the one designated last. The four speeds
# keep the movers out of step, so one or more qualifies most of the time.
pick_target () {
    "$MSCGS" echo track --json --count 1 --timeout 15 --exercise "$EX" 2>/dev/null | tail -1 |
        sed 's/{"track_id":/\n&/g' | grep '^{"track_id":' | grep -E 'CONFIRMED|COASTING' |
        awk -v last="${LAST_TARGET:-0}" '
        function abs(x) { return x < 0 ? -x : x }
        # The number after "KEY": on the line (0 when protobuf left it out).
        function num(key) {
            if (!match($0, "\"" key "\":[-0-9.e+]*")) return 0
            return substr($0, RSTART + length(key) + 3, RLENGTH - length(key) - 3) + 0
        }
        # Road ahead of a mover at x (along its road) moving at v, and what
        # it needs: more going out than coming in.
        function ahead(x, v) { return x * v > 0 ? 14000 - abs(x) : abs(x) - 2000 }
        function needs(x, v) { return x * v > 0 ? 8000 : 4000 }
        {
            id = num("track_id"); e = num("east_m"); n = num("north_m")
            ve = num("east_mps"); vn = num("north_mps")
            if (id == last) next
            if (abs(n) < 400 && abs(e) > 1600 && abs(e) < 11000 && abs(ve) > 3 && ahead(e, ve) >= needs(e, ve))
                print id
            else if (abs(e) < 400 && abs(n) > 1600 && abs(n) < 11000 && abs(vn) > 3 && ahead(n, vn) >= needs(n, vn))
                print id
        }' |
        shuf -n 1 --random-source=<(yes "$RANDOM")
}

# in_flight: operator commands while the service is out, each in the
# background with its exit code in a file: a designation of the trial's
# target (to guidanced) and an airspeed (to uavsim).
in_flight () {
    SPEED=$((34 + RANDOM % 8))
    (M designate "$TARGET" --wait 30 >"$TMP/cmd-designate.out" 2>&1; echo $? >"$TMP/cmd-designate.rc") &
    CMD1=$!
    (M speed "$SPEED" --wait 30 >"$TMP/cmd-speed.out" 2>&1; echo $? >"$TMP/cmd-speed.rc") &
    CMD2=$!
}

# trial SERVICE KIND N
trial () {
    local s=$1 kind=$2 n=$3 t_fault t_heal p what="$2 #$3 of $1" t0=$SECONDS
    diag "---- $what (at ${SECONDS} s)"
    TARGET=""
    for _ in $(seq 1 60); do
        TARGET=$(pick_target)
        [ -n "$TARGET" ] && break
        sleep 0.5
    done
    [ -n "$TARGET" ] || { check "$what: a confirmed hostile track to designate" false; return; }
    LAST_TARGET=$TARGET
    local before
    before=$(icpt_now)
    M designate "$TARGET" --wait 10 >"$TMP/designate.out" 2>&1
    is "$?" 0 "$what: track $TARGET designated"
    wait_for 10 bash -c "[ \"\$(awk '\$2 == \"icpt\" && \$3 == 1 { n = \$5 } END { print n }' '$OBS')\" != '$(cut -d' ' -f2 <<<"$before")' ]"
    local n0
    n0=$(icpt_now | cut -d' ' -f2)
    local others=() o
    for o in $ALL; do [ "$o" = "$s" ] || others+=("$o:${PID[$o]}"); done
    sleep "$(awk -v r=$RANDOM 'BEGIN { printf "%.2f", 0.5 + 2.5 * r / 32767 }')"
    t_fault=$(now)
    p=${PID[$s]}
    case $kind in
    kill9)
        kill9 "$p"
        in_flight
        sleep "$(awk -v r=$RANDOM 'BEGIN { printf "%.2f", 0.2 + 0.8 * r / 32767 }')"
        t_heal=$(now)
        svc_start "$s" "k$n"
        ;;
    stop)
        kill -STOP "$p"
        in_flight
        sleep 3
        t_heal=$(now)
        kill -CONT "$p"
        ;;
    restart2)
        stop "$p"
        check "$what: the first stop is clean (exit $EXIT_CODE)" test "$EXIT_CODE" = 0
        svc_start "$s" "r${n}a"
        check "$what: the first restart is heard (a new epoch)" wait_for 30 restarted "$s" "$t_fault"
        in_flight
        stop "${PID[$s]}"
        check "$what: the second stop is clean (exit $EXIT_CODE)" test "$EXIT_CODE" = 0
        t_heal=$(now)
        svc_start "$s" "r${n}b"
        ;;
    crash)
        M fault "$s" crash >"$TMP/fault.out" 2>&1
        check "$what: the fault channel takes the crash" grep -q "crashing after this reply" "$TMP/fault.out"
        wait_exit "$p" 10
        check "$what: the service died of SIGABRT (exit $EXIT_CODE)" test "$EXIT_CODE" = 134
        in_flight
        sleep 0.5
        t_heal=$(now)
        svc_start "$s" "c$n"
        ;;
    hang)
        M fault "$s" hang 3 >"$TMP/fault.out" 2>&1
        t_heal=$(awk -v t="$(now)" 'BEGIN { printf "%.6f", t + 3 }')
        check "$what: the fault channel takes the hang" grep -q "hanging for 3 s" "$TMP/fault.out"
        in_flight
        ;;
    slow)
        M fault "$s" slow 60 4 >"$TMP/fault.out" 2>&1
        t_heal=$(awk -v t="$(now)" 'BEGIN { printf "%.6f", t + 4 }')
        check "$what: the fault channel takes the slow-down" grep -q "stalling 60 ms" "$TMP/fault.out"
        in_flight
        ;;
    esac
    # Back: its output heard after the heal.
    local t_back=""
    wait_for 40 bash -c "[ -n \"\$(awk -v s='$s' -v t='${TOPIC[$s]}' -v a='$t_heal' '\$1 > a && \$2 == \"msg\" && \$3 == s && \$4 == t { print; exit }' '$OBS')\" ]"
    t_back=$(heard "$s" "${TOPIC[$s]}" "$t_heal")
    if [ -n "$t_back" ]; then
        local r
        r=$(since "$t_heal" "$t_back")
        printf '%s\t%s\t%s\n' "$kind" "$s" "$r" >>"$ART/recovery.tsv"
        check "$what: $s is heard again ${TOPIC[$s]} ${r} s after the heal" true
    else
        check "$what: $s is heard again on ${TOPIC[$s]} within 40 s of the heal" false
    fi
    # The commands sent while it was out: answered ok.
    wait_exit "$CMD1" 40
    wait_exit "$CMD2" 40
    # A designation is answered: ok, or refused with guidanced's reason when
    # the tracker ended the track itself meanwhile (guidanced no longer
    # knows it, or heard it deleted).
    local des_rc
    des_rc=$(cat "$TMP/cmd-designate.rc" 2>/dev/null)
    check "$what: the designation sent during the fault is answered (exit ${des_rc:-none})" \
        bash -c "[ '$des_rc' = 0 ] || grep -Eq '^guidanced: (no track $TARGET |track $TARGET was deleted$)' '$TMP/cmd-designate.out'"
    is "$(cat "$TMP/cmd-speed.rc" 2>/dev/null)" 0 "$what: the airspeed sent during the fault is answered ok"
    grep -v ': ok' "$TMP/cmd-designate.out" "$TMP/cmd-speed.out" | while read -r l; do diag "$l"; done
    # The others: same processes, no new epoch, heard after the heal.
    local bad=""
    for o in "${others[@]}"; do
        local in=${o%%:*} op=${o#*:}
        running "$op" || bad="$bad $in(exited)"
        restarted "$in" "$t_fault" && bad="$bad $in(new epoch)"
    done
    is "${bad:-none}" none "$what: no other service restarted"
    local deaf=""
    for o in "${others[@]}"; do
        local in=${o%%:*}
        wait_for 15 bash -c "[ -n \"\$(awk -v s='$in' -v t='${TOPIC[$in]}' -v a='$t_heal' '\$1 > a && \$2 == \"msg\" && \$3 == s && \$4 == t { print; exit }' '$OBS')\" ]" ||
            deaf="$deaf $in"
    done
    is "${deaf:-none}" none "$what: every other service is heard after the heal"
    # The intercept completes, with the designation number up by one for the
    # designation sent during the fault.
    local st="" num=""
    for _ in $(seq 1 360); do
        read -r st num _ <<<"$(icpt_now)"
        case $st in OVERFLIGHT | DONE) break ;; LOST | CANCELLED) break ;; esac
        sleep 0.5
    done
    # Whatever became of the designation sent during the fault (refused when
    # the tracker ended the track meanwhile), the intercept under way must
    # image its target: a lost one is a failure, of the service or of the
    # tracking, never a pass.
    check "$what: the intercept completes (state ${st:-none})" test "$st" = OVERFLIGHT -o "$st" = DONE
    if [ "$des_rc" = 0 ]; then
        is "$num" "$((n0 + 1))" "$what: the designation during the fault took effect exactly once"
    else
        is "$num" "$n0" "$what: the refused designation took no effect"
    fi
    local cmd_speed
    cmd_speed=$(M echo uav --json --count 1 --timeout 5 2>/dev/null |
        sed -n 's/.*"commanded_airspeed_mps":\([0-9.]*\).*/\1/p' | head -1)
    is "${cmd_speed%.*}" "$SPEED" "$what: the airspeed sent during the fault is the UAV's"
    diag "$what: $((SECONDS - t0)) s"
}

# fault_main INSTANCE: the whole test of one service.
fault_main () {
    local s=$1 kinds n
    case " $ALL " in *" $s "*) ;; *) bail "unknown instance $s" ;; esac
    local seed=${FAULT_SEED:-$(($(date +%s) % 32768))}
    RANDOM=$seed
    diag "FAULT_SEED=$seed FAULT_SCALE=$SCALE (set them to repeat this run's random moments)"
    local extra
    extra=(crash hang slow)
    kinds=${FAULT_KINDS:-kill9 stop restart2 ${extra[$(($(cksum <<<"$s" | cut -d' ' -f1) % 3))]}}
    fault_exercise
: >"$OBS"
    start OBSP observer "$OBSERVER" --exercise "$EX" --out "$OBS"
    local in
    for in in $ALL; do svc_start "$in" 0; done
    check "every service is heard" wait_for 60 bash -c \
        "for i in $ALL; do grep -q \" msg \$i \" '$OBS' || exit 1; done"
    for kind in $kinds; do
        for n in $(seq 1 "${FAULT_TRIALS:-1}"); do
            trial "$s" "$kind" "$n"
        done
    done
    for in in $ALL; do
        stop "${PID[$in]}"
        is "$EXIT_CODE" 0 "$in stops on SIGTERM with exit code 0"
    done
    stop "$OBSP"
    local f bad=""
    for f in "$TMP"/*.log; do
        clean_log "$(basename "$f" .log)" || bad="$bad $(basename "$f" .log)"
    done
    is "${bad:-none}" none "no sanitizer report in any log"
    finish
}

# rss_kib PID: resident memory of PID in KiB ("" when gone).
rss_kib () { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status" 2>/dev/null; }

# long_main MINUTES: the long exercise of `make soak`: every service, at
# time scale FAULT_SCALE (default 20; the soak sets 50), intercept after
# intercept, no faults, for MINUTES of wall time. Every 10 s it samples each
# service's resident memory (memory.tsv in test-artifacts/fault). Checks:
#   - no message lost: no gap the observer sees in any publisher's sequence
#     numbers, and every service's own health counts no gap and no drop;
#   - memory does not grow: each service's median over the last quarter is
#     within 5 % + 2 MiB of its median over the second quarter (the first is
#     warm-up: tables fill, the allocator settles);
#   - intercepts keep completing, and the clock keeps its time scale.
long_main () {
    local minutes=${1:?minutes}
    local seed=${FAULT_SEED:-$(($(date +%s) % 32768))}
    RANDOM=$seed
    diag "long run: $minutes min at time scale $SCALE, FAULT_SEED=$seed"
    fault_exercise
: >"$OBS"
    start OBSP observer "$OBSERVER" --exercise "$EX" --out "$OBS"
    local in
    for in in $ALL; do svc_start "$in" 0; done
    check "every service is heard" wait_for 60 bash -c \
        "for i in $ALL; do grep -q \" msg \$i \" '$OBS' || exit 1; done"
    local mem=$ART/memory.tsv t_start t_end next_sample=0 done_n=0 lost_n=0 st num
    printf 'elapsed_s' >"$mem"
    for in in $ALL; do printf '\t%s' "$in" >>"$mem"; done
    printf '\n' >>"$mem"
    t_start=$SECONDS
    t_end=$((SECONDS + minutes * 60))
    TARGET=""
    while [ "$SECONDS" -lt "$t_end" ]; do
        if [ "$SECONDS" -ge "$next_sample" ]; then
            printf '%d' $((SECONDS - t_start)) >>"$mem"
            for in in $ALL; do printf '\t%s' "$(rss_kib "${PID[$in]}")" >>"$mem"; done
            printf '\n' >>"$mem"
            next_sample=$((SECONDS + 10))
        fi
        read -r st num _ <<<"$(icpt_now)"
        if [ -z "$TARGET" ] || [ "$st" = OVERFLIGHT ] || [ "$st" = DONE ] || [ "$st" = LOST ]; then
            [ -n "$TARGET" ] && case $st in OVERFLIGHT | DONE) done_n=$((done_n + 1)) ;; LOST) lost_n=$((lost_n + 1)) ;; esac
            TARGET=$(pick_target)
            if [ -n "$TARGET" ]; then
                LAST_TARGET=$TARGET
                M designate "$TARGET" --wait 10 >/dev/null 2>&1 || diag "designate $TARGET refused"
                wait_for 10 bash -c "[ \"\$(awk '\$2 == \"icpt\" && \$3 == 1 { n = \$5 } END { print n }' '$OBS')\" != '$num' ]"
            fi
        fi
        sleep 1
    done
    diag "intercepts: $done_n completed, $lost_n lost"
    check "intercepts keep completing ($done_n in $minutes min)" test "$done_n" -ge "$minutes"
    local alive=""
    for in in $ALL; do running "${PID[$in]}" || alive="$alive $in"; done
    is "${alive:-none}" none "no service ended during the run"
    local rate
    rate=$(awk '$2 == "msg" && $3 == "uavsim" && $4 == "clock" { if (!w0) { w0 = $1; s0 = $5 } w = $1; s = $5 }
                END { if (w > w0) printf "%.1f", (s - s0) / (w - w0) }' "$OBS")
    diag "the clock ran at $rate simulation seconds per second (time scale $SCALE)"
    check "the clock kept at least 90 % of its time scale ($rate of $SCALE)" \
        awk -v r="${rate:-0}" -v s="$SCALE" 'BEGIN { exit !(r >= 0.9 * s) }'
    is "$(awk '$2 == "gap" { n += $5 } END { print n + 0 }' "$OBS")" 0 "the observer missed no message"
    is "$(awk '$2 == "health" && ($4 > 0 || $5 > 0) { print $3 " gaps " $4 " drops " $5 }' "$OBS" | sort -u | tr '\n' ';')" "" \
        "no service counted a gap or a drop"
    local growth
    growth=$(awk -F'\t' 'NR == 1 { for (i = 2; i <= NF; i++) name[i] = $i; next }
        { n++; for (i = 2; i <= NF; i++) v[n, i] = $i; nf = NF }
        function median(a, b, i,    k, m, x, t) {
            m = 0; for (k = a; k <= b; k++) x[++m] = v[k, i]
            for (k = 2; k <= m; k++) { t = x[k]; j = k - 1; while (j > 0 && x[j] > t) { x[j + 1] = x[j]; j-- } x[j + 1] = t }
            return m % 2 ? x[(m + 1) / 2] : (x[m / 2] + x[m / 2 + 1]) / 2 }
        END { q = int(n / 4); if (q < 1) exit
              for (i = 2; i <= nf; i++) {
                  a = median(q + 1, 2 * q, i); b = median(n - q + 1, n, i)
                  printf "%s %.0f %.0f %s\n", name[i], a, b, (b <= a * 1.05 + 2048) ? "ok" : "GROWS" } }' "$mem")
    while read -r l; do diag "memory KiB (second quarter, last quarter): $l"; done <<<"$growth"
    check "no service's memory grows" bash -c "[ -n '$growth' ] && ! grep -q GROWS <<<'$growth'"
    for in in $ALL; do
        stop "${PID[$in]}"
        is "$EXIT_CODE" 0 "$in stops on SIGTERM with exit code 0"
    done
    stop "$OBSP"
    finish
}
