#!/bin/bash
# multicast.sh — one exercise over three hosts whose bus runs wholly over UDP
# multicast (PGM, epgm://) with every payload sealed. (NORM is refused by the
# exercise loader with Debian 12's libzmq 4.3.4, whose NORM engine stops on
# any message over 2038 bytes: test_exercise.) Each host is a network namespace plugged into a fourth,
# "switch" namespace (a bridge): host A (10.78.0.1) runs uavsim, mtid.uav1 and
# bcisd.uav1; host B (10.78.0.2) trackerd and guidanced; host C (10.78.0.3)
# the operator's mscgs, whose monitors (`mscgs echo --multicast`) join the
# publishers' groups as a host of their own would. [bus] transport gives every
# publisher its group and port; `key_file` seals every payload with the
# exercise's group key (mscgs keygen --group). Each round:
#   - host C hears uavsim (host A) and guidanced (host B) over multicast, and
#     trackerd on host B tracks the target from host A's radar over it;
#   - the wire (tshark on host C's interface) carries sealed payloads only:
#     the vehicles' markings, in every `entity` batch, never appear in it;
#   - a subscriber with another group key receives nothing, and counts each
#     message it could not open as unauthenticated;
#   - the operator designates from host C (commands stay on tcp);
#   - host B is cut off for 10 s (its switch port down) and healed: the
#     exercise resumes (reported, and within 10 s); what host B's services
#     counted missing is reported (PGM's window, 5 s at 100 Mbit/s, holds
#     the whole cut: it is repaired);
#   - a subscriber that joins 60 s late converges on the periodic
#     republication within one period of the topic: `track`, every track
#     after each radar scan (10 s of simulation, 3.3 s here);
#   - no message is lost without a gap count: host C's clock monitor's gap
#     count equals the sequence numbers missing from what it printed;
#   - the intercept reaches its overflight on the designated track, every
#     service stops with exit code 0 and no sanitizer report.
# PGM needs a route for its groups and resolves an interface name through
# DNS before the interfaces, so each host has a default route and each
# instance names its host's interface by its address. Skipped (ok 1 # SKIP)
# when not root or without `ip` (tests/run fails that skip as root); a
# namespace, veth or bridge that cannot be made fails it. About 2 minutes.
# TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

[ "$(id -u)" = 0 ] || skip_all "needs root for network namespaces"
command -v ip >/dev/null || skip_all "no ip command (iproute2)"
[ -n "${EPOCHREALTIME:-}" ] || skip_all "needs bash 5 (EPOCHREALTIME)"
command -v tshark >/dev/null || bail "no tshark (Debian package tshark)"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
BCISD=$CGS_BUILD/bin/bcisd
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
for b in "$UAVSIM" "$MTID" "$BCISD" "$TRACKERD" "$GUIDANCED" "$MSCGS"; do [ -x "$b" ] || bail "no $b"; done

SCALE=3        # simulation seconds per wall second
OUTAGE_S=10    # how long host B is cut off
LATE_S=60      # how long after the start the late subscriber joins

# ---- the network -----------------------------------------------------------------------
P=cgm${TMP##*.}
NS_SW=$P-sw NS_A=$P-a NS_B=$P-b NS_C=$P-c
netns_hosts "$P" 10.78.0 a b c
for h in a b c; do net ip -n "$P-$h" route add default dev eth0; done

MSCGS_BIN=$MSCGS
MSCGS=$TMP/mscgs-on-c
printf '#!/bin/sh\nexec ip netns exec %s %s "$@"\n' "$NS_C" "$MSCGS_BIN" >"$MSCGS"
chmod +x "$MSCGS"

# Flat ground; the UAV circles the origin; a hostile mover drives north 5 km
# east of it, an unknown one 7 km west, and a friendly one (with a BCIS
# transponder) back and forth 7 km south.
{
    scenario_ground
    scenario_uav
    scenario_vehicle target hostile TARGET "5000 -4000" "5000 16000" 10 end=stop
    scenario_vehicle other unknown OTHER "-7000 -4000" "-7000 16000" 6 end=stop
    scenario_vehicle friend friendly FRIEND "-6000 -7000" "6000 -7000" 7 bcis_transponder=yes end=reverse
} >"$TMP/scenario.ini"
cp "$CGS_ROOT/deploy/params/guidance.ini" "$TMP/guidance.ini"
"$MSCGS_BIN" keygen --group --dir "$TMP" >/dev/null || bail "mscgs keygen --group"
"$MSCGS_BIN" keygen --group other --dir "$TMP" >/dev/null || bail "mscgs keygen --group other"

now_us () { NOW_US=${EPOCHREALTIME//[^0-9]/}; }
us_s () { printf '%d.%03d' $(($1 / 1000000)) $(($1 % 1000000 / 1000)); }
HDR='^([a-z.]+) from ([^ ]+) #([0-9]+) sim ([0-9]+)\.([0-9]{3}) s: (.*)$'

# last_sim_ms FILE [SOURCE]: the newest simulation time (ms) in an echo's output.
last_sim_ms () {
    local line ms best=0
    while IFS= read -r line; do
        [[ $line =~ $HDR ]] || continue
        [ -z "${2:-}" ] || [ "${BASH_REMATCH[2]}" = "$2" ] || continue
        ms=$((BASH_REMATCH[4] * 1000 + 10#${BASH_REMATCH[5]}))
        [ "$ms" -gt "$best" ] && best=$ms
    done <"$1"
    echo "$best"
}
# state_of FILE: the newest intercept state in an echo's output.
state_of () {
    local s
    s=$(grep -o 'INTERCEPT_STATE_[A-Z_]*' "$1" | tail -1)
    echo "${s#INTERCEPT_STATE_}"
}

# ---- one round ---------------------------------------------------------------------------
# s_round TRANSPORT N: the whole exercise over TRANSPORT, its groups
# 239.192.78+N.1 on.
s_round () {
    local t=$1 n=$2 ia=${ADDR[a]} ib=${ADDR[b]} ic=${ADDR[c]}
    local ex=$TMP/$t.ini wrong=$TMP/$t-wrong.ini
    {
        exercise_header $((30 + n)) "multicast-$t" scenario=scenario.ini
        printf '\n[bus]\ntransport = %s\ngroup = 239.192.%d.1\nport = %d\nkey_file = group.key\n' \
            "$t" $((78 + n)) $((7500 + 10 * n))
        exercise_service uavsim publish="tcp://${ADDR[a]}:7101" command="tcp://${ADDR[a]}:7102" host=host-a interface="$ia"
        exercise_service mtid.uav1 publish="tcp://${ADDR[a]}:7103" host=host-a uav=uav1 interface="$ia"
        exercise_service bcisd.uav1 publish="tcp://${ADDR[a]}:7104" host=host-a uav=uav1 interface="$ia"
        exercise_service trackerd publish="tcp://${ADDR[b]}:7105" host=host-b interface="$ib"
        exercise_service guidanced publish="tcp://${ADDR[b]}:7106" command="tcp://${ADDR[b]}:7107" params=guidance.ini host=host-b interface="$ib"
    } >"$ex"
    sed 's/^key_file = group.key$/key_file = other.key/' "$ex" >"$wrong"
    local U R B T G
    start U "$t-uavsim" ip netns exec "$NS_A" "$UAVSIM" --exercise "$ex" --instance uavsim --time-scale "$SCALE" --state-dir "$TMP/$t-state-a"
    now_us
    local t_start=$NOW_US
    start R "$t-mtid" ip netns exec "$NS_A" "$MTID" --exercise "$ex" --instance mtid.uav1 --state-dir "$TMP/$t-state-a"
    start B "$t-bcisd" ip netns exec "$NS_A" "$BCISD" --exercise "$ex" --instance bcisd.uav1 --state-dir "$TMP/$t-state-a"
    start T "$t-trackerd" ip netns exec "$NS_B" "$TRACKERD" --exercise "$ex" --instance trackerd --state-dir "$TMP/$t-state-b"
    start G "$t-guidanced" ip netns exec "$NS_B" "$GUIDANCED" --exercise "$ex" --instance guidanced --state-dir "$TMP/$t-state-b"
    # Monitors on host C, over multicast.
    local MC MI
    # shellcheck disable=SC2016  # expanded by sh, which becomes mscgs
    start MC "$t-mon-clock" ip netns exec "$NS_C" sh -c 'exec "$0" echo clock --multicast "$1" --exercise "$2" >"$3" 2>"$4"' \
        "$MSCGS_BIN" "$ic" "$ex" "$TMP/$t-clock.mon" "$TMP/$t-clock.err"
    # shellcheck disable=SC2016
    start MI "$t-mon-intercept" ip netns exec "$NS_C" sh -c 'exec "$0" echo intercept --multicast "$1" --exercise "$2" >"$3"' \
        "$MSCGS_BIN" "$ic" "$ex" "$TMP/$t-intercept.mon"
    check "$t: host C hears uavsim's clock from host A over multicast" \
        wait_for 30 test -s "$TMP/$t-clock.mon"
    check "$t: and guidanced's intercept from host B" wait_for 30 grep -q 'from guidanced' "$TMP/$t-intercept.mon"
    grep -h "bus\|publishing on" "$TMP/$t-uavsim.log" | head -3 | while IFS= read -r l; do diag "uavsim: $l"; done

    # The wire, seen from host C: sealed payloads only.
    ip netns exec "$NS_C" tshark -i eth0 -f udp -a duration:6 -w "$TMP/$t.pcap" >"$TMP/$t-tshark.log" 2>&1
    tshark -r "$TMP/$t.pcap" -T fields -e udp.payload 2>/dev/null | tr -d ':' >"$TMP/$t-payloads.hex"
    local pkts sealed plain
    pkts=$(grep -c . "$TMP/$t-payloads.hex")
    sealed=$(grep -c '00434753' "$TMP/$t-payloads.hex") # "\0CGS", the sealed payload's start
    plain=0
    for word in TARGET OTHER FRIEND; do
        plain=$((plain + $(xxd -r -p "$TMP/$t-payloads.hex" | grep -a -c "$word")))
    done
    diag "$t: tshark saw $pkts UDP packets on host C's interface in 6 s, $sealed starting a sealed payload"
    check "$t: the wire carries sealed payloads ($sealed packets of $pkts)" test "$sealed" -gt 20
    is "$plain" 0 "$t: no vehicle's marking (TARGET, OTHER, FRIEND) appears in the clear on the wire"

    # Another key: nothing.
    ip netns exec "$NS_C" "$MSCGS_BIN" echo entity --multicast "$ic" --exercise "$wrong" --timeout 6 \
        >"$TMP/$t-wrong.out" 2>"$TMP/$t-wrong.err"
    diag "$t: with another key: $(tr '\n' ' ' <"$TMP/$t-wrong.err")"
    check "$t: a subscriber with another group key receives nothing" test ! -s "$TMP/$t-wrong.out"
    check "$t: and counts what it could not open as unauthenticated" grep -qE ' [1-9][0-9]* unauthenticated' "$TMP/$t-wrong.err"

    # Designate from host C.
    local tgt=""
    for _ in $(seq 1 60); do
        confirmed_tracks "$ex" >"$TMP/$t-tracks.txt"
        tgt=$(awk '$2 > 4500 && $2 < 5500 { print $1; exit }' "$TMP/$t-tracks.txt")
        [ -n "$tgt" ] && break
        sleep 0.5
    done
    [ -n "$tgt" ] || bail "$t: no confirmed track on the target ($(tr '\n' ';' <"$TMP/$t-tracks.txt"))"
    check "$t: trackerd on host B tracks the target over multicast (track $tgt)" test -n "$tgt"
    "$MSCGS" designate "$tgt" --exercise "$ex" >"$TMP/$t-designate.out" 2>&1
    is "$?" 0 "$t: mscgs designate $tgt from host C (tcp) is accepted"
    # shellcheck disable=SC2016
    check "$t: the intercept follows track $tgt" wait_for 10 bash -c \
        "grep -q '\"track_id\":$tgt' '$TMP/$t-intercept.mon'"

    # Host B cut off for 10 s, then healed.
    ip -n "$NS_SW" link set pb down || bail "ip link set pb down"
    sleep "$OUTAGE_S"
    local clk_ms
    clk_ms=$(last_sim_ms "$TMP/$t-clock.mon")
    ip -n "$NS_SW" link set pb up || bail "ip link set pb up"
    now_us
    local t_heal=$NOW_US resumed=""
    for _ in $(seq 1 500); do
        if [ "$(last_sim_ms "$TMP/$t-intercept.mon" guidanced)" -ge "$clk_ms" ]; then
            now_us
            resumed=$((NOW_US - t_heal))
            break
        fi
        sleep 0.02
    done
    if [ -n "$resumed" ]; then
        diag "$t: host B cut off for ${OUTAGE_S} s: host C heard guidanced again $(us_s "$resumed") s after the heal"
        check "$t: the exercise resumes within 10 s of the heal ($(us_s "$resumed") s)" test "$resumed" -le 10000000
    else
        check "$t: the exercise resumes after host B's cut" false
    fi
    # What host B's services counted missing over the cut (their health,
    # heard over multicast). PGM's transmit window is rate x recovery
    # interval (100 Mbit/s x 5 s), far more than 10 s of this exercise's
    # traffic: a sender repairs the whole cut, and nothing is missing.
    ip netns exec "$NS_C" "$MSCGS_BIN" echo health --json --count 12 --timeout 5 --multicast "$ic" \
        --exercise "$ex" >"$TMP/$t-health.json" 2>/dev/null
    local g_tr g_gd
    gaps_of () { grep "\"instance\":\"$1\"" "$TMP/$t-health.json" | tail -1 | grep -o '"gaps":"[0-9]*"' | head -1 | tr -dc 0-9; }
    g_tr=$(gaps_of trackerd) g_gd=$(gaps_of guidanced)
    diag "$t: after the cut, trackerd and guidanced on host B count ${g_tr:-0} and ${g_gd:-0} messages missed (gaps)"
    check "$t: host C hears host B's health over multicast" grep -q '"instance":"trackerd"' "$TMP/$t-health.json"

    # A late subscriber, LATE_S after the start.
    now_us
    local wait_us=$((t_start + LATE_S * 1000000 - NOW_US))
    [ "$wait_us" -gt 0 ] && sleep "$(us_s "$wait_us")"
    local join_ms ML
    join_ms=$(last_sim_ms "$TMP/$t-clock.mon")
    now_us
    local t_join=$NOW_US
    # shellcheck disable=SC2016
    start ML "$t-mon-late" ip netns exec "$NS_C" sh -c 'exec "$0" echo track --multicast "$1" --exercise "$2" >"$3"' \
        "$MSCGS_BIN" "$ic" "$ex" "$TMP/$t-late.mon"
    local conv=""
    for _ in $(seq 1 1000); do
        if [ -s "$TMP/$t-late.mon" ] && [ "$(last_sim_ms "$TMP/$t-late.mon" trackerd)" -ge "$join_ms" ]; then
            now_us
            conv=$((NOW_US - t_join))
            break
        fi
        sleep 0.02
    done
    local period_us=$((10 * 1000000 / SCALE))
    if [ -n "$conv" ]; then
        diag "$t: a subscriber joining ${LATE_S} s late had the tracks of a scan after its join $(us_s "$conv") s later (a scan is $(us_s $period_us) s at ${SCALE}x)"
        check "$t: the late subscriber converges within one radar scan and 2 s ($(us_s "$conv") s)" \
            test "$conv" -le $((period_us + 2000000))
    else
        check "$t: the late subscriber gets tracks" false
    fi
    stop "$ML"

    # The intercept completes.
    check "$t: the intercept reaches its overflight" wait_for 150 \
        grep -qE 'INTERCEPT_STATE_(OVERFLIGHT|DONE)' "$TMP/$t-intercept.mon"
    check "$t: the intercept was never lost nor cancelled" bash -c \
        "! grep -qE 'INTERCEPT_STATE_(LOST|CANCELLED)' '$TMP/$t-intercept.mon'"
    check "$t: on track $tgt to the end" bash -c \
        "grep 'from guidanced' '$TMP/$t-intercept.mon' | tail -1 | grep -q '\"track_id\":$tgt'"

    # No message lost without a gap count: what the clock monitor missed.
    stop "$MC"
    local first last count gaps
    read -r first last count < <(sed -nE 's/^clock from uavsim #([0-9]+) .*/\1/p' "$TMP/$t-clock.mon" |
        awk 'NR == 1 { f = $1 } { l = $1; n++ } END { print f + 0, l + 0, n + 0 }')
    gaps=$(sed -nE 's/.* ([0-9]+) messages missed \(gaps\).*/\1/p' "$TMP/$t-clock.err")
    diag "$t: host C's clock monitor printed $count messages, #$first to #$last; it counted ${gaps:-0} gaps"
    is "$((last - first + 1 - count))" "${gaps:-0}" "$t: every clock message host C missed is counted as a gap"

    for v in "$G guidanced" "$T trackerd" "$B bcisd" "$R mtid" "$U uavsim" "$MI mon-intercept"; do
        stop "${v%% *}"
        is "$EXIT_CODE" 0 "$t: ${v#* } stops on SIGTERM with exit code 0"
    done
    for name in uavsim mtid bcisd trackerd guidanced mon-clock mon-intercept mon-late; do
        check "$t: no sanitizer report from $name" clean_log "$t-$name"
    done
}

s_round epgm 0
finish
