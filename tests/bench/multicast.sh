#!/bin/bash
# multicast.sh — the bus over UDP multicast against TCP, measured between
# network namespaces: a publisher host P and up to three subscriber hosts on a
# bridge (tests/integration/lib.sh's netns_hosts), bench_mcast on each (the
# project's cgs_pub and cgs_sub, sealed with a group key).
#   1. Cost: the publisher's CPU time for 20000 messages at 10000 a second
#      (100-byte and 2-kB payloads; NORM 1500 bytes, see below) with one, two
#      and three subscribing hosts, over tcp://, epgm:// and norm://. Over
#      TCP the publisher copies every message to every subscriber; over
#      multicast it sends it once.
#   2. Throughput: 100000 messages sent as fast as the publisher can (it
#      drops at its high-water mark, and PGM at its rate limit, 100 Mbit/s),
#      to one and to three hosts: what each received a second.
#   3. Loss: nftables drops 5% and 20% of the packets arriving at each of two
#      subscribing hosts; 10000 messages at 2000 a second over epgm and norm;
#      what each host received, and the gaps it counted.
# NORM runs only with payloads under 2038 bytes: Debian 12's libzmq 4.3.4
# stops a NORM socket for good on a bigger message (zeromq/libzmq#3501), which
# is why the exercise loader refuses norm there.
# Needs root, ip and nft. Usage: tests/bench/multicast.sh BUILD_DIR (make
# bench-multicast). About 10 minutes. Prints the tables; exit 1 when a tcp
# or epgm run broke (NORM's stalls and aborts are results, not breakage).
set -u
build=${1:?usage: tests/bench/multicast.sh BUILD_DIR}
CGS_BUILD=$(cd "$build" && pwd) || exit 2
export CGS_BUILD
[ "$(id -u)" = 0 ] || { echo "multicast.sh: needs root (network namespaces)" >&2; exit 2; }
CGS_NO_PEER=1
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/../integration/lib.sh"
BM=$CGS_BUILD/bench/bench_mcast
[ -x "$BM" ] || { echo "multicast.sh: no $BM (make bench)" >&2; exit 2; }

P=cgb${TMP##*.}
netns_hosts "$P" 10.79.0 p s1 s2 s3
for h in p s1 s2 s3; do net ip -n "$P-$h" route add default dev eth0; done
"$CGS_BUILD/bin/mscgs" keygen --group --dir "$TMP" >/dev/null || exit 1
KEY=$TMP/group.key
CASE=0
BROKEN=0

# endpoint TRANSPORT HOST PORT: the endpoint HOST uses (the publisher binds
# it; a subscriber connects to it).
endpoint () {
    case $1 in
    tcp) echo "tcp://${ADDR[p]}:$3" ;;
    epgm) echo "epgm://${ADDR[$2]};239.192.90.$((CASE % 250 + 1)):$3" ;;
    norm) echo "norm://eth0;239.192.90.$((CASE % 250 + 1)):$3" ;;
    esac
}

# run TRANSPORT SUBS SIZE MESSAGES PER_S LOSS_PCT: one measurement; sets
# PUB_OUT (the publisher's line) and SUB_OUT[i] (each subscriber's).
run () {
    local t=$1 n=$2 size=$3 msgs=$4 per_s=$5 loss=$6 i port pids=()
    CASE=$((CASE + 1))
    port=$((7800 + CASE))
    for ((i = 1; i <= n; i++)); do
        if [ "$loss" -gt 0 ]; then
            ip netns exec "$P-s$i" nft -f - <<EOF || bail "nft"
table inet cgs_loss {
    chain in {
        type filter hook input priority 0; policy accept;
        iifname "eth0" numgen random mod 100 < $loss drop
    }
}
EOF
        fi
        # Idle longer than PGM's recovery interval (5 s): a receiver waits that
        # long for a repair before it gives the loss up.
        ip netns exec "$P-s$i" "$BM" sub --endpoint "$(endpoint "$t" "s$i" "$port")" --key "$KEY" \
            --idle 8 >"$TMP/sub$i.out" 2>"$TMP/sub$i.err" &
        pids+=($!)
    done
    ip netns exec "$P-p" "$BM" pub --endpoint "$(endpoint "$t" p "$port")" --key "$KEY" \
        --messages "$msgs" --size "$size" --per-s "$per_s" --wait 3 --linger 8 >"$TMP/pub.out" 2>"$TMP/pub.err" ||
        BROKEN=1
    local k=0
    SUB_OUT=()
    for i in "${pids[@]}"; do
        k=$((k + 1))
        { wait "$i"; } 2>/dev/null || SUB_OUT[k]="aborted" # libzmq asserted
    done
    PUB_OUT=$(cat "$TMP/pub.out")
    for ((i = 1; i <= n; i++)); do
        # NORM's aborts are what is measured (libzmq 4.3.4); anything else broke.
        [ -n "${SUB_OUT[i]:-}" ] && { [ "$t" = norm ] || BROKEN=1; continue; }
        SUB_OUT[i]=$(cat "$TMP/sub$i.out")
        [ "$loss" -gt 0 ] && ip netns exec "$P-s$i" nft delete table inet cgs_loss
    done
}
field () { sed -n "s/.*\b$1=\([0-9.]*\).*/\1/p" <<<"$2"; }
# got OUT: "received (gaps)", or "aborted" for a subscriber that crashed.
got () { if [ "$1" = aborted ]; then echo aborted; else echo "$(field received "$1") ($(field gaps "$1"))"; fi; }

echo "bench_mcast between namespaces, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores," \
    "load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "1. Publisher CPU for 20000 sealed messages at 10000/s (ms; each host's received (gaps))"
echo "| transport | payload | 1 host | 2 hosts | 3 hosts | 3 hosts / 1 host |"
echo "|---|---|---|---|---|---|"
for t in tcp epgm norm; do
    for size in 100 2048; do
        [ "$t" = norm ] && [ "$size" -gt 2000 ] && size=1500
        row="| $t | $size B |"
        c1=""
        for n in 1 2 3; do
            run "$t" "$n" "$size" 20000 10000 0
            cpu=$(field cpu_s "$PUB_OUT")
            recv=""
            for ((i = 1; i <= n; i++)); do recv+="${recv:+/}$(got "${SUB_OUT[i]}")"; done
            ms=$(awk -v c="${cpu:-0}" 'BEGIN { printf "%.0f", c * 1000 }')
            row+=" $ms ($recv) |"
            [ "$n" = 1 ] && c1=$ms
            [ "$n" = 3 ] && row+=" $(awk -v a="$ms" -v b="$c1" 'BEGIN { printf "%.2f", (b > 0 ? a / b : 0) }') |"
        done
        echo "$row"
    done
done
echo
echo "2. Throughput: 100000 sealed messages sent as fast as the publisher can (messages/s each host received; received (gaps))"
echo "| transport | payload | 1 host | 3 hosts |"
echo "|---|---|---|---|"
for t in tcp epgm; do
    for size in 100 2048; do
        row="| $t | $size B |"
        for n in 1 3; do
            run "$t" "$n" "$size" 100000 0 0
            cell=""
            for ((i = 1; i <= n; i++)); do
                cell+="${cell:+; }$(awk -v r="$(field received "${SUB_OUT[i]}")" -v s="$(field span_s "${SUB_OUT[i]}")" \
                    'BEGIN { printf "%.0f/s", (s > 0 ? r / s : 0) }') $(got "${SUB_OUT[i]}")"
            done
            row+=" $cell |"
        done
        echo "$row"
    done
done
echo
echo "3. Loss: 10000 sealed messages at 2000/s to two hosts, each dropping a share of its input"
echo "| transport | payload | loss | host 1 received (gaps) | host 2 received (gaps) |"
echo "|---|---|---|---|---|"
for t in epgm norm; do
    for size in 100 1500; do
        for loss in 0 5 20; do
            run "$t" 2 "$size" 10000 2000 "$loss"
            row="| $t | $size B | $loss% |"
            for i in 1 2; do row+=" $(got "${SUB_OUT[i]}") |"; done
            echo "$row"
        done
    done
done
[ "$BROKEN" = 0 ] || echo "multicast.sh: a run broke (see above)"
exit "$BROKEN"
