#!/bin/bash
# localnet.sh — the default exercise keeps its traffic on this machine.
#
# A machine is a network namespace "host" with its loopback and a real
# network: a veth "eth0" (10.78.0.2/24, default route via 10.78.0.1) whose
# other end is in a second namespace, "net", where tshark captures every
# frame that leaves "host". In "host", `mscgs run` runs the default exercise
# (deploy/exercises/default.ini with its own parameter files; only its ipc://
# folder and state folder moved into $TMP) for a while, with
#   - tshark on "host"'s lo, decoding DIS (a Wireshark user on this machine),
#   - an open-dis receiver (tests/interop/dis.js) joined to the gateway's
#     group on 127.0.0.1 (a DIS application on this machine).
# Checks: not one frame reaches "net" during the run, while both receivers
# decode our Entity State PDUs; `mscgs run` says DIS stays on this machine
# and the gateway logs nothing about leaving it. A datagram sent on purpose
# through eth0 after the run must be captured, so the capture was live.
#
# Then what the gateway hears: with the default parameters, a DIS datagram
# sent from "net" to the group, while another program on "host" has joined
# the group on eth0 (so the datagram does reach "host": that program gets
# it), is not heard by the gateway, which hears only its group on lo.
#
# Then the control: the same exercise with the lab's gateway parameters
# (deploy/params/gateway-lab.ini: broadcast on eth0). Its Entity State PDUs
# must be captured in "net" (so the first capture could have failed), the
# gateway must log once, at notice level, that DIS leaves this machine, and
# `mscgs run` must say so.
#
# Needs root (network namespaces), iproute2, tshark and node with the
# interop packages (scripts/install-deps). TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

[ "$(id -u)" = 0 ] || bail "needs root for network namespaces"
for c in ip tshark node; do command -v "$c" >/dev/null || bail "no $c (scripts/install-deps installs it)"; done
[ -d "$CGS_ROOT/tests/interop/node_modules/open-dis" ] || bail "no open-dis (npm ci in tests/interop)"
for b in uavsim mtid bcisd trackerd guidanced imagerd gateway stationd; do
    [ -x "$CGS_BUILD/bin/$b" ] || bail "no $CGS_BUILD/bin/$b"
done

RUN_S=20                    # wall seconds each exercise runs
DIS_PORT=3000               # the default parameters' port
GROUP=239.1.2.3             # and group

# ---- the machine and its network ------------------------------------------------------
P=cgs${TMP##*.}
NS_HOST=$P-host NS_NET=$P-net
for ns in "$NS_HOST" "$NS_NET"; do
    netns_add "$ns"
    # No IPv6: its neighbour discovery and router solicitations would be
    # frames of the kernel's own on the capture.
    net ip netns exec "$ns" sysctl -qw net.ipv6.conf.all.disable_ipv6=1 net.ipv6.conf.default.disable_ipv6=1
done
net ip -n "$NS_HOST" link add eth0 type veth peer name wire netns "$NS_NET"
net ip -n "$NS_HOST" addr add 10.78.0.2/24 broadcast 10.78.0.255 dev eth0
net ip -n "$NS_HOST" link set eth0 up
net ip -n "$NS_NET" addr add 10.78.0.1/24 dev wire
net ip -n "$NS_NET" link set wire up
net ip -n "$NS_HOST" route add default via 10.78.0.1
# Each side's address known to the other in advance: the canary and the
# answer to it need no ARP.
# Frames that leave "host" are those from eth0's address (the capture also
# holds what "net" answers to the canary).
WIRE_MAC=$(ip -n "$NS_NET" -br link show wire | awk '{ print $3 }')
HOST_MAC=$(ip -n "$NS_HOST" -br link show eth0 | awk '{ print $3 }')
net ip -n "$NS_HOST" neigh replace 10.78.0.1 lladdr "$WIRE_MAC" dev eth0 nud permanent
net ip -n "$NS_NET" neigh replace 10.78.0.2 lladdr "$HOST_MAC" dev wire nud permanent

# ---- the exercise ---------------------------------------------------------------------
# exercise FILE GATEWAY_PARAMS: the default exercise, its ipc:// endpoints
# and state in $TMP, its relative paths made absolute, the gateway given
# GATEWAY_PARAMS.
exercise () {
    sed -e "s|ipc:///tmp/mscgs/|ipc://$TMP/|" \
        -e "s|^state_dir = .*|state_dir = $TMP/state|" \
        -e "s|= \.\./|= $CGS_ROOT/deploy/|" \
        -e "s|^params = $CGS_ROOT/deploy/params/gateway.ini|params = $2|" \
        "$CGS_ROOT/deploy/exercises/default.ini" >"$1"
}
exercise "$TMP/default.ini" "$CGS_ROOT/deploy/params/gateway.ini"
check "the test's exercise is the default one but for its folders" bash -c \
    "diff <(grep -vE '^(publish|command|state_dir|scenario|params) =' '$CGS_ROOT/deploy/exercises/default.ini') \
          <(grep -vE '^(publish|command|state_dir|scenario|params) =' '$TMP/default.ini') >/dev/null &&
     grep -q '^params = $CGS_ROOT/deploy/params/gateway.ini' '$TMP/default.ini'"

# capture NAME NS IFACE: tshark on IFACE in namespace NS into $TMP/NAME.pcapng,
# started and waited for until it captures; its pid in CAP_PID.
capture () {
    start CAP_PID "tshark-$1" ip netns exec "$2" tshark -n -i "$3" -w "$TMP/$1.pcapng"
    wait_for 20 grep -q "Capturing on" "$TMP/tshark-$1.log" || bail "tshark on $2 $3 did not start"
}
# espdus PCAPNG: the Entity State PDUs (DIS PDU type 1) tshark decodes in a capture.
espdus () {
    tshark -n -r "$1" -d "udp.port==$DIS_PORT,dis" -Y 'dis.pdu_type == 1' -T fields -e frame.number 2>/dev/null | wc -l
}

# run_exercise NAME EXERCISE: `mscgs run` in "host" for RUN_S seconds, with
# the captures on "net"'s wire and "host"'s lo and the open-dis receiver.
run_exercise () {
    local name=$1 ex=$2 wire lo rx run
    capture "$name-wire" "$NS_NET" wire
    wire=$CAP_PID
    capture "$name-lo" "$NS_HOST" lo
    lo=$CAP_PID
    start rx "$name-opendis" ip netns exec "$NS_HOST" node "$CGS_ROOT/tests/interop/dis.js" listen "$DIS_PORT" \
        "$TMP/$name-opendis" --group "$GROUP"
    wait_for 10 grep -q "joined on 127.0.0.1" "$TMP/$name-opendis.log" || bail "the open-dis receiver did not start"
    rm -rf "$TMP/state" "$TMP/$name-out"
    start run "$name-run" ip netns exec "$NS_HOST" "$CGS_BUILD/bin/mscgs" run --exercise "$ex" \
        --duration "$RUN_S" --out "$TMP/$name-out"
    wait_exit "$run" $((RUN_S + 60)) || bail "mscgs run ($name) did not stop"
    is "$EXIT_CODE" 0 "mscgs run ($name) exits 0"
    # The canary: one datagram through eth0 on purpose, after the exercise.
    ip netns exec "$NS_HOST" bash -c "echo canary >/dev/udp/10.78.0.1/9" 2>>"$TMP/net.log"
    sleep 1
    stop "$rx"
    stop "$lo"
    stop "$wire"
}

# ---- 1. the default exercise ----------------------------------------------------------
run_exercise default "$TMP/default.ini"
check "mscgs run says where DIS goes: multicast on lo, this machine only" \
    grep -q "mscgs run: DIS (gateway) multicast to $GROUP:$DIS_PORT on lo, TTL 0: this machine only" \
    "$TMP/default-run.log"
check "every service ran (8 of 8)" grep -q "8 of 8 services built here" "$TMP/default-run.log"
gw_log=$TMP/default-out/logs/gateway.log
check "the gateway says where DIS goes" grep -q "multicast to $GROUP:$DIS_PORT on lo, TTL 0" "$gw_log"
check "and logs nothing about leaving this machine" bash -c "! grep -q 'leaves this machine' '$gw_log'"

tshark -n -r "$TMP/default-wire.pcapng" -Y "eth.src == $HOST_MAC" -T fields -e frame.number \
    -e _ws.col.Protocol -e _ws.col.Info >"$TMP/default-wire.txt" 2>/dev/null
frames=$(wc -l <"$TMP/default-wire.txt")
canary=$(tshark -n -r "$TMP/default-wire.pcapng" \
    -Y "eth.src == $HOST_MAC && udp.dstport == 9 && data.data == 63:61:6e:61:72:79:0a" \
    -T fields -e frame.number 2>/dev/null | wc -l)
diag "captured in \"net\" from \"host\": $frames frames ($canary canary)"
[ "$frames" -gt 1 ] && sed 's/^/#   /' "$TMP/default-wire.txt" | head -20
is "$canary" 1 "the capture outside the machine was live: it caught the canary sent after the run"
is "$((frames - canary))" 0 "not one frame of the default exercise left the machine"

lo_espdus=$(espdus "$TMP/default-lo.pcapng")
od_espdus=$(grep -c '"type":1,.*"marking":"' "$TMP/default-opendis.jsonl" 2>/dev/null)
diag "Entity State PDUs on lo: $lo_espdus by tshark, $od_espdus by open-dis"
check "tshark on lo decodes the gateway's Entity State PDUs ($lo_espdus)" [ "$lo_espdus" -gt 0 ]
check "an open-dis receiver on this machine decodes them ($od_espdus), the UAV's among them" \
    bash -c "[ '${od_espdus:-0}' -gt 0 ] && grep -q '\"marking\":\"UAV1\"' '$TMP/default-opendis.jsonl'"
check "all of them on multicast $GROUP" bash -c \
    "[ \$(tshark -n -r '$TMP/default-lo.pcapng' -Y 'udp.dstport == $DIS_PORT && ip.dst != $GROUP' 2>/dev/null | wc -l) -eq 0 ]"

# ---- 2. the gateway hears nothing from the network ------------------------------------
# A datagram from "net" to the group, which a program on "host" joined on eth0.
net ip -n "$NS_NET" route add 224.0.0.0/4 dev wire
start rx probe-opendis ip netns exec "$NS_HOST" node "$CGS_ROOT/tests/interop/dis.js" listen "$DIS_PORT" \
    "$TMP/probe-opendis" --group "$GROUP" --join-on 10.78.0.2
wait_for 10 grep -q "joined on 10.78.0.2" "$TMP/probe-opendis.log" || bail "the joiner on eth0 did not start"
start gw probe-gateway ip netns exec "$NS_HOST" "$CGS_BUILD/bin/gateway" --exercise "$TMP/default.ini" \
    --state-dir "$TMP/probe-state"
wait_for 20 grep -q "multicast to $GROUP" "$TMP/probe-gateway.log" || bail "the gateway alone did not start"
# A PDU header cut short: rejected and counted, were it heard.
for _ in 1 2 3; do
    ip netns exec "$NS_NET" bash -c "printf '\x07\x01\x01' >/dev/udp/$GROUP/$DIS_PORT" 2>>"$TMP/net.log"
    sleep 0.3
done
check "the probes reach \"host\" (the program joined on eth0 gets them)" \
    wait_for 10 bash -c "[ \$(wc -l <'$TMP/probe-opendis.jsonl') -ge 3 ]"
stop "$gw"
is "$EXIT_CODE" 0 "the gateway stops cleanly"
check "the gateway heard none of them (0 PDUs in, 0 rejected)" \
    grep -q " 0 PDUs in (0 Entity State, 0 of other exercises, 0 rejected)" "$TMP/probe-gateway.log"
stop "$rx"

# ---- 3. the control: the lab's parameters broadcast on eth0 ---------------------------
exercise "$TMP/lab.ini" "$CGS_ROOT/deploy/params/gateway-lab.ini"
run_exercise lab "$TMP/lab.ini"
check "mscgs run says the lab's DIS leaves this machine" \
    grep -q "mscgs run: DIS (gateway) broadcast to 255.255.255.255:$DIS_PORT on eth0: LEAVES THIS MACHINE" \
    "$TMP/lab-run.log"
gw_log=$TMP/lab-out/logs/gateway.log
is "$(grep -c '^<5>.*DIS leaves this machine: broadcast to 255.255.255.255:3000 on eth0' "$gw_log")" 1 \
    "the gateway logs it once, at notice level"
wire_espdus=$(espdus "$TMP/lab-wire.pcapng")
diag "Entity State PDUs captured in \"net\" with the lab's parameters: $wire_espdus"
check "the capture sees DIS that does leave ($wire_espdus Entity State PDUs)" [ "$wire_espdus" -gt 0 ]
check "each on eth0's broadcast, from 10.78.0.2" bash -c \
    "[ \$(tshark -n -r '$TMP/lab-wire.pcapng' -Y 'dis && !(ip.src == 10.78.0.2 && ip.dst == 255.255.255.255)' 2>/dev/null | wc -l) -eq 0 ]"

reports=0
for f in "$TMP"/default-out/logs/*.log "$TMP"/lab-out/logs/*.log; do
    grep -qE 'Sanitizer|runtime error:' "$f" && { diag "sanitizer report in $f"; reports=$((reports + 1)); }
done
is "$reports" 0 "no sanitizer report in any service's log"
finish
