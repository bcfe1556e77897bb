#!/bin/bash
# hosts.sh — one exercise spread over three hosts, each a network namespace
# plugged into a fourth, "switch" namespace (a bridge), with tcp:// endpoints
# on 10.77.0.0/24 from one exercise file: host A (10.77.0.1) runs uavsim,
# mtid.uav1 and bcisd.uav1; host B (10.77.0.2) trackerd and guidanced; host C
# (10.77.0.3) the operator's mscgs (designate, echo, status). A full
# intercept runs, designated from host C; during it
#   - host B is cut off for 10 s by taking its switch port down (`ip link set
#     pb down` in the switch: the cable pulled; neither side gets an error,
#     packets just vanish). Host B is the one whose loss tests most: its
#     services subscribe across the network (to host A) and are subscribed
#     to (from host C), and guidanced sends uavsim its tasks across it, so
#     the exercise resumes only when all of A -> B -> C flows again;
#   - then host B drops 20% of its packets (nftables, input and output on its
#     interface) for 10 s.
# After each, the exercise must resume within 2 s of the heal: host C must
# hear guidanced's `intercept` stamped with a simulation time at least that
# of uavsim's clock (which host C hears from host A) at the heal, so
# guidanced has heard host A again and host C hears guidanced. Wall times
# are $EPOCHREALTIME (the clock `date +%s.%N` reads, without a fork) taken
# right after the `ip`/`nft` command and when the test reads, every 20 ms,
# the output of `mscgs echo intercept` left running on host C; they are
# reported as diag lines, the verdict is the 2 s. Also: nothing from host B
# reaches host C during the cut while host A's clock does, the missed
# messages are counted as gaps, the intercept reaches its overflight on the
# same track, every service stops with exit code 0 on SIGTERM and logs no
# sanitizer report. The resume depends on common/cgs_bus.c's liveness
# options (without them it took 6 s). Skipped (ok 1 # SKIP) when not root,
# without `ip` or bash 5 (tests/run fails that skip as root on Debian); a
# namespace, veth or bridge that cannot be made fails it. The packet loss
# needs `nft` (Debian's nftables). Namespaces are named after $TMP and removed on exit.
# About a minute. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

[ "$(id -u)" = 0 ] || skip_all "needs root for network namespaces"
command -v ip >/dev/null || skip_all "no ip command (iproute2)"
[ -n "${EPOCHREALTIME:-}" ] || skip_all "needs bash 5 (EPOCHREALTIME)"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
BCISD=$CGS_BUILD/bin/bcisd
TRACKERD=$CGS_BUILD/bin/trackerd
GUIDANCED=$CGS_BUILD/bin/guidanced
for b in "$UAVSIM" "$MTID" "$BCISD" "$TRACKERD" "$GUIDANCED" "$MSCGS"; do [ -x "$b" ] || bail "no $b"; done

SCALE=3                  # simulation seconds per wall second
OUTAGE_S=10              # how long host B is cut off, and how long it loses packets
LOSS_PCT=20              # packets host B loses, percent
RESUME_LIMIT_US=2000000  # the requirement: resumed within 2 s

# ---- the network -----------------------------------------------------------------------
P=cgs${TMP##*.}
NS_SW=$P-sw NS_A=$P-a NS_B=$P-b NS_C=$P-c
netns_hosts "$P" 10.77.0 a b c
# Static neighbour entries: no ARP. A host that fails to resolve its peer's
# address tells TCP so (a local "host unreachable"), and Linux then undoes
# its retransmission back-off (RFC 6069), which would hide what this test is
# about; a cut beyond a router gives no such signal, nor does this one.
for h in a b c; do
    mac=$(ip -n "$P-$h" -br link show eth0 | awk '{ print $3 }')
    for o in a b c; do
        [ "$o" = "$h" ] || net ip -n "$P-$o" neigh replace "${ADDR[$h]}" lladdr "$mac" dev eth0 nud permanent
    done
done
ADDR_A=${ADDR[a]} ADDR_B=${ADDR[b]}

# The tools run on host C: lib.sh's helpers (confirmed_tracks) call $MSCGS.
MSCGS_BIN=$MSCGS
MSCGS=$TMP/mscgs-on-c
printf '#!/bin/sh\nexec ip netns exec %s %s "$@"\n' "$NS_C" "$MSCGS_BIN" >"$MSCGS"
chmod +x "$MSCGS"

# ---- the exercise ----------------------------------------------------------------------
EX=$TMP/exercise.ini
{
    exercise_header 21 hosts-test scenario=scenario.ini
    exercise_service uavsim publish="tcp://$ADDR_A:7101" command="tcp://$ADDR_A:7102" host=host-a
    exercise_service mtid.uav1 publish="tcp://$ADDR_A:7103" host=host-a uav=uav1
    exercise_service bcisd.uav1 publish="tcp://$ADDR_A:7104" host=host-a uav=uav1
    exercise_service trackerd publish="tcp://$ADDR_B:7105" host=host-b
    exercise_service guidanced publish="tcp://$ADDR_B:7106" command="tcp://$ADDR_B:7107" params=guidance.ini host=host-b
} >"$EX"
cp "$CGS_ROOT/deploy/params/guidance.ini" "$TMP/guidance.ini"
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

# ---- services --------------------------------------------------------------------------
start U uavsim ip netns exec "$NS_A" "$UAVSIM" --exercise "$EX" --instance uavsim --time-scale "$SCALE" --state-dir "$TMP/state-a"
start R mtid ip netns exec "$NS_A" "$MTID" --exercise "$EX" --instance mtid.uav1 --state-dir "$TMP/state-a"
start B bcisd ip netns exec "$NS_A" "$BCISD" --exercise "$EX" --instance bcisd.uav1 --state-dir "$TMP/state-a"
start T trackerd ip netns exec "$NS_B" "$TRACKERD" --exercise "$EX" --instance trackerd --state-dir "$TMP/state-b"
start G guidanced ip netns exec "$NS_B" "$GUIDANCED" --exercise "$EX" --instance guidanced --state-dir "$TMP/state-b"

M () { "$MSCGS" "$@" --exercise "$EX"; }

# ---- monitors on host C ----------------------------------------------------------------
# A monitor is a `mscgs echo TOPIC` left running on host C, its output in
# $TMP/TOPIC.mon (its stderr in mon-TOPIC.log); the test reads the output as
# it grows, every 20 ms, so it knows to within one poll when a message
# reached host C. Each line reads "TOPIC from SOURCE #SEQ sim T s: JSON".
monitor () { # monitor VAR TOPIC
    : >"$TMP/$2.mon"
    # shellcheck disable=SC2016  # expanded by sh, which becomes mscgs (same pid)
    start "$1" "mon-$2" ip netns exec "$NS_C" sh -c 'exec "$0" echo "$1" --exercise "$2" >"$3"' \
        "$MSCGS_BIN" "$2" "$EX" "$TMP/$2.mon"
}
monitor MC clock
monitor MI intercept
monitor MT track
exec {FD_CLOCK}<"$TMP/clock.mon" {FD_ICPT}<"$TMP/intercept.mon" {FD_TRACK}<"$TMP/track.mon"

declare -A PART=()
LINES=()
# mon_read FD: the complete lines appended behind FD since the last call, in LINES.
mon_read () {
    local fd=$1 l=""
    LINES=()
    while IFS= read -r l <&"$fd"; do
        LINES+=("${PART[$fd]:-}$l")
        PART[$fd]=""
        l=""
    done
    PART[$fd]+=$l # a line still being written
}

now_us () { NOW_US=${EPOCHREALTIME//[^0-9]/}; }
# us_s MICROSECONDS: as seconds with three decimals.
us_s () { printf '%d.%03d' $(($1 / 1000000)) $(($1 % 1000000 / 1000)); }
# ms_s MILLISECONDS: as seconds with one decimal.
ms_s () { printf '%d.%d' $(($1 / 1000)) $(($1 % 1000 / 100)); }

HDR='^([a-z.]+) from ([^ ]+) #([0-9]+) sim ([0-9]+)\.([0-9]{3}) s: (.*)$'
CLK_MS=0           # uavsim's latest clock seen on host C, simulation ms
IC_MS=0 IC_N=0     # guidanced's latest intercept seen on host C, and how many
IC_STATE="" IC_TRACK=0
IC_STATES=" "      # every state seen
TR_MS=0 TR_N=0     # trackerd's latest track batch, and how many
FROM_MS=-1         # a resume is a message stamped at or after this simulation time
RES_IC_US="" RES_IC_MS="" RES_TR_US="" RES_TR_MS=""
QUIET_FROM_US=0    # intercepts read after this wall time are counted in QUIET_N
QUIET_N=0

# s_poll: read what the monitors received since the last call.
s_poll () {
    local line ms
    now_us
    mon_read "$FD_CLOCK"
    for line in "${LINES[@]}"; do
        [[ $line =~ $HDR ]] || continue
        ms=$((BASH_REMATCH[4] * 1000 + 10#${BASH_REMATCH[5]}))
        [ "$ms" -gt "$CLK_MS" ] && CLK_MS=$ms
    done
    mon_read "$FD_ICPT"
    for line in "${LINES[@]}"; do
        [[ $line =~ $HDR && ${BASH_REMATCH[2]} == guidanced ]] || continue
        ms=$((BASH_REMATCH[4] * 1000 + 10#${BASH_REMATCH[5]}))
        local json=${BASH_REMATCH[6]}
        IC_N=$((IC_N + 1))
        [ "$ms" -gt "$IC_MS" ] && IC_MS=$ms
        if [[ $json =~ \"state\":\"INTERCEPT_STATE_([A-Z_]+)\" ]]; then
            IC_STATE=${BASH_REMATCH[1]}
        else
            IC_STATE=IDLE # proto3 JSON leaves out the default
        fi
        [[ $IC_STATES == *" $IC_STATE "* ]] || IC_STATES+="$IC_STATE "
        if [[ $json =~ \"track_id\":([0-9]+) ]]; then IC_TRACK=${BASH_REMATCH[1]}; else IC_TRACK=0; fi
        if [ "$FROM_MS" -ge 0 ] && [ -z "$RES_IC_US" ] && [ "$ms" -ge "$FROM_MS" ]; then
            RES_IC_US=$NOW_US RES_IC_MS=$ms
        fi
        [ "$QUIET_FROM_US" -gt 0 ] && [ "$NOW_US" -ge "$QUIET_FROM_US" ] && QUIET_N=$((QUIET_N + 1))
    done
    mon_read "$FD_TRACK"
    for line in "${LINES[@]}"; do
        [[ $line =~ $HDR && ${BASH_REMATCH[2]} == trackerd ]] || continue
        ms=$((BASH_REMATCH[4] * 1000 + 10#${BASH_REMATCH[5]}))
        TR_N=$((TR_N + 1))
        [ "$ms" -gt "$TR_MS" ] && TR_MS=$ms
        if [ "$FROM_MS" -ge 0 ] && [ -z "$RES_TR_US" ] && [ "$ms" -ge "$FROM_MS" ]; then
            RES_TR_US=$NOW_US RES_TR_MS=$ms
        fi
    done
}

# poll_for SECONDS COMMAND...: s_poll every 20 ms until COMMAND succeeds (0)
# or the deadline passes (1).
poll_for () {
    local end_us s=${1%.*} f=000000
    [[ $1 == *.* ]] && f=${1#*.}000000
    now_us
    end_us=$((NOW_US + ${s:-0} * 1000000 + 10#${f:0:6}))
    shift
    while :; do
        s_poll
        "$@" && return 0
        [ "$NOW_US" -lt "$end_us" ] || return 1
        sleep 0.02
    done
}
# poll_sleep SECONDS: keep reading the monitors for that long.
poll_sleep () { poll_for "$1" false; }
resumed () { [ -n "$RES_IC_US" ]; }
resumed_tracks () { [ -n "$RES_TR_US" ]; }
state_in () { [[ " $* " == *" $IC_STATE "* ]]; }

# shellcheck disable=SC2016  # evaluated at each poll
check "host C hears uavsim's clock from host A over tcp" poll_for 30 eval '[ "$CLK_MS" -gt 0 ]'
# shellcheck disable=SC2016
check "and guidanced's intercept from host B" poll_for 30 eval '[ "$IC_N" -gt 0 ]'

# ---- designate from host C -------------------------------------------------------------
tgt=""
for _ in $(seq 1 60); do
    confirmed_tracks "$EX" >"$TMP/tracks.txt"
    tgt=$(awk '$2 > 4500 && $2 < 5500 { print $1; exit }' "$TMP/tracks.txt")
    [ -n "$tgt" ] && break
    poll_sleep 0.5
done
diag "tracks seen from host C: $(tr '\n' ';' <"$TMP/tracks.txt")"
[ -n "$tgt" ] || bail "no confirmed track on the target"
check "trackerd on host B tracks the target (track $tgt), seen from host C" test -n "$tgt"
M designate "$tgt" >"$TMP/designate.out" 2>&1
is "$?" 0 "mscgs designate $tgt from host C is accepted by guidanced on host B"
diag "$(cat "$TMP/designate.out")"
# shellcheck disable=SC2016
check "the intercept follows track $tgt" poll_for 10 eval '[ "$IC_TRACK" = "$tgt" ] && state_in TO_SECONDARY TO_WAYPOINT APPROACH PRECISION'
check "the UAV on host A flies guidanced's route (uavsim's uav in ROUTE mode)" wait_for 10 bash -c \
    "'$MSCGS' echo uav --json --count 1 --timeout 3 --exercise '$EX' | grep -q 'UAV_MODE_ROUTE'"
designated_ms=$IC_MS
IC_STATES=" $IC_STATE "
poll_sleep 2

# ---- cut host B off ------------------------------------------------------------------------
# measure_resume LABEL T0_US: wait (up to 30 s) for host C to hear guidanced
# stamped at or after FROM_MS; diag and check the time from T0_US.
measure_resume () {
    local label=$1 t0=$2
    poll_for 30 resumed
    if [ -z "$RES_IC_US" ]; then
        check "$label: the exercise resumes" false
        RESUMES+=("$label: none")
        return
    fi
    local dt=$((RES_IC_US - t0))
    diag "$label: host C heard guidanced again $(us_s $dt) s after it (intercept at sim $(ms_s "$RES_IC_MS") s, clock was at $(ms_s "$FROM_MS") s)"
    RESUMES+=("$label: $(us_s $dt) s")
    check "$label: the exercise resumes within 2 s ($(us_s $dt) s)" test "$dt" -le "$RESUME_LIMIT_US"
    # trackerd publishes once per radar scan (10 s of simulation), so its
    # first batch comes up to a scan after the link: reported, not judged.
    poll_for 15 resumed_tracks
    [ -n "$RES_TR_US" ] &&
        diag "$label: and trackerd's tracks $(us_s $((RES_TR_US - t0))) s after it (scan at sim $(ms_s "$RES_TR_MS") s)"
}
RESUMES=()

s_poll
check "the intercept is under way when host B is cut off (state $IC_STATE)" state_in TO_SECONDARY TO_WAYPOINT APPROACH PRECISION
clk0=$CLK_MS
now_us
t_cut=$NOW_US
ip -n "$NS_SW" link set pb down || bail "ip link set pb down"
QUIET_FROM_US=$((t_cut + 500000)) QUIET_N=0
diag "host B cut off at sim $(ms_s "$CLK_MS") s, intercept $IC_STATE"
poll_sleep "$OUTAGE_S"
QUIET_FROM_US=0
is "$QUIET_N" 0 "nothing from guidanced reaches host C while host B is cut off"
check "host A's clock still reaches host C ($(ms_s $clk0) -> $(ms_s "$CLK_MS") s)" test "$CLK_MS" -gt $((clk0 + (OUTAGE_S - 2) * SCALE * 1000))
ip -n "$NS_SW" link set pb up || bail "ip link set pb up"
now_us
t_heal=$NOW_US
RES_IC_US="" RES_TR_US=""
s_poll
FROM_MS=$CLK_MS
diag "link healed after $(us_s $((t_heal - t_cut))) s, at sim $(ms_s "$CLK_MS") s"
measure_resume "link down ${OUTAGE_S} s" "$t_heal"
FROM_MS=-1
check "the intercept goes on after the cut (state $IC_STATE)" state_in TO_SECONDARY TO_WAYPOINT APPROACH PRECISION OVERFLIGHT DONE
# What host B missed is counted (health, 1 Hz), never silent.
M echo health --json --count 12 --timeout 4 >"$TMP/health.json" 2>/dev/null
gaps_of () { grep "\"instance\":\"$1\"" "$TMP/health.json" | tail -1 | grep -o '"gaps":"[0-9]*"' | head -1 | tr -dc 0-9; }
g_gd=$(gaps_of guidanced) g_tr=$(gaps_of trackerd)
check "guidanced and trackerd count what they missed as gaps (${g_gd:-0}, ${g_tr:-0})" \
    test "${g_gd:-0}" -gt 0 -a "${g_tr:-0}" -gt 0
poll_sleep 1

# ---- packet loss on host B ---------------------------------------------------------------
if command -v nft >/dev/null; then
    # Only what crosses eth0: trackerd -> guidanced inside host B stays clean.
    ip netns exec "$NS_B" nft -f - <<EOF || bail "nft: cannot add the loss table"
table inet cgs_loss {
    chain in {
        type filter hook input priority 0; policy accept;
        iifname "eth0" counter
        iifname "eth0" numgen random mod 100 < $LOSS_PCT counter drop
    }
    chain out {
        type filter hook output priority 0; policy accept;
        oifname "eth0" counter
        oifname "eth0" numgen random mod 100 < $LOSS_PCT counter drop
    }
}
EOF
    now_us
    t_loss=$NOW_US
    diag "host B loses $LOSS_PCT% of its packets from sim $(ms_s "$CLK_MS") s, intercept $IC_STATE"
    poll_sleep "$OUTAGE_S"
    ip netns exec "$NS_B" nft list table inet cgs_loss >"$TMP/loss.txt" 2>&1
    ip netns exec "$NS_B" nft delete table inet cgs_loss || bail "nft: cannot delete the loss table"
    now_us
    t_clean=$NOW_US
    RES_IC_US="" RES_TR_US=""
    s_poll
    FROM_MS=$CLK_MS
    mapfile -t pk < <(sed -n 's/.*counter packets \([0-9]*\).*/\1/p' "$TMP/loss.txt")
    diag "loss removed after $(us_s $((t_clean - t_loss))) s, at sim $(ms_s "$CLK_MS") s: in ${pk[1]:-?} of ${pk[0]:-?} packets dropped, out ${pk[3]:-?} of ${pk[2]:-?}"
    check "nftables dropped packets both ways" test "${pk[1]:-0}" -gt 0 -a "${pk[3]:-0}" -gt 0
    measure_resume "${LOSS_PCT}% loss ${OUTAGE_S} s" "$t_clean"
    FROM_MS=-1
else
    T_N=$((T_N + 1))
    echo "ok $T_N # SKIP no nft (Debian package nftables): packet loss not tested"
fi

# ---- the intercept completes -------------------------------------------------------------
# shellcheck disable=SC2016  # evaluated at each poll
poll_for 150 eval '[[ $IC_STATES == *" OVERFLIGHT "* || $IC_STATES == *" DONE "* ]]'
# shellcheck disable=SC2016
check "the intercept reaches its overflight (states since designated:$IC_STATES)" \
    eval '[[ $IC_STATES == *" OVERFLIGHT "* || $IC_STATES == *" DONE "* ]]'
# shellcheck disable=SC2016
check "the intercept was never lost nor cancelled" eval '[[ $IC_STATES != *" LOST "* && $IC_STATES != *" CANCELLED "* ]]'
is "$IC_TRACK" "$tgt" "it is still track $tgt's"
diag "designated at sim $(ms_s "$designated_ms") s, overflight by $(ms_s "$IC_MS") s"
M status >"$TMP/status.out" 2>&1
while IFS= read -r l; do diag "$l"; done <"$TMP/status.out"
check "mscgs status shows each service on the exercise's host (trackerd on host-b)" \
    grep -qE '^trackerd +[a-z]+ +host-b ' "$TMP/status.out"
diag "resume times: ${RESUMES[*]}"

# ---- stop ----------------------------------------------------------------------------------
for v in "$G guidanced" "$T trackerd" "$B bcisd" "$R mtid" "$U uavsim" "$MI mscgs echo intercept" \
    "$MT mscgs echo track" "$MC mscgs echo clock"; do
    stop "${v%% *}"
    is "$EXIT_CODE" 0 "${v#* } stops on SIGTERM with exit code 0"
done
for n in uavsim mtid bcisd trackerd guidanced mon-clock mon-intercept mon-track; do
    check "no sanitizer report from $n" clean_log "$n"
done
finish
