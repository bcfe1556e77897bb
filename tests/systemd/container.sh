#!/bin/bash
# container.sh — the units of deploy/systemd/ under a real systemd: a Debian
# 12 container (debootstrap, cached) booted with systemd-nspawn, the project
# installed into a throw-away copy of it with `make install`, every instance
# of the lab exercise enabled. Checks that `systemctl start mscgs.target`
# brings every Type=notify service to active (running) and that they talk
# (`mscgs status`, `mscgs echo`), that a service killed with SIGKILL is
# restarted by systemd while the others go on, that a service stopped with
# SIGSTOP is killed by the watchdog (WatchdogSec=) and restarted, and that
# `systemctl stop mscgs.target` stops them all cleanly. TAP on stdout.
#
# Usage (as root, on the host):
#   tests/systemd/container.sh --make-cache   debootstrap the image (minutes)
#   tests/systemd/container.sh                run the test (skips without an image)
#
# Environment: CGS_BUILD (absolute release build folder, required), CGS_ROOT
# (source tree), CGS_CACHE (image cache, default /var/cache/mscgs-test),
# CGS_MIRROR (Debian mirror for --make-cache), CGS_MAKE_CACHE=1 makes the
# image first when there is none (make test does), CGS_KEEP=1 keeps the temporary
# folder (the container's root, its console and journal) for a post-mortem.
# Needs debootstrap (--make-cache only), systemd-container (systemd-nspawn)
# and util-linux (nsenter).

set -u
: "${CGS_BUILD:?set CGS_BUILD to the absolute release build folder, e.g. \$PWD/build/release}"
: "${CGS_ROOT:=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}"
CACHE=${CGS_CACHE:-/var/cache/mscgs-test}
IMAGE=$CACHE/rootfs
MIRROR=${CGS_MIRROR:-http://deb.debian.org/debian}
SUITE=bookworm
SELF="tests/systemd/container.sh"
EXERCISE=/etc/mscgs/exercise.ini

# ---- TAP (tests/tap.sh; not lib.sh, which needs the test peer of a test build) ----

# shellcheck source=tests/tap.sh
. "$CGS_ROOT/tests/tap.sh"

# wait_for SECONDS COMMAND...: poll COMMAND every 100 ms until it succeeds (0)
# or the deadline passes (1).
wait_for () {
    local end=$((SECONDS + $1))
    shift
    until "$@"; do
        [ "$SECONDS" -lt "$end" ] || return 1
        sleep 0.1
    done
}

# ---- the cached image ---------------------------------------------------------------

# runtime_packages: the Debian packages holding every shared library the
# built programs load (ldd, so the libraries' own dependencies too).
runtime_packages () {
    local lib pkg
    ldd "$CGS_BUILD"/bin/* 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u |
        while read -r lib; do
            # /lib is /usr/lib on Debian 12; dpkg knows one of the two names
            # (alternatives such as libblas.so.3 only by the real path).
            pkg=$(dpkg -S "$lib" 2>/dev/null || dpkg -S "$(realpath "$lib")" 2>/dev/null ||
                dpkg -S "${lib#/usr}" 2>/dev/null) || { echo "no package holds $lib" >&2; return 1; }
            echo "${pkg%%:*}"
        done | sort -u
}

# make_cache: debootstrap a minimal Debian with systemd and the runtime
# libraries into $IMAGE (built beside it, moved in place when complete).
make_cache () {
    [ "$(id -u)" -eq 0 ] || { echo "$SELF --make-cache: run as root" >&2; return 1; }
    command -v debootstrap >/dev/null || { echo "no debootstrap: apt-get install debootstrap" >&2; return 1; }
    ls "$CGS_BUILD"/bin/mtid >/dev/null || { echo "build first: make -j2 O=$CGS_BUILD all" >&2; return 1; }
    local pkgs new=$IMAGE.new start=$SECONDS
    pkgs=$(runtime_packages) || return 1
    [ -n "$pkgs" ] || { echo "no runtime packages found (ldd $CGS_BUILD/bin/*)" >&2; return 1; }
    pkgs="systemd systemd-sysv dbus $(echo "$pkgs" | tr '\n' ' ')"
    mkdir -p "$CACHE" && rm -rf "$new" || return 1
    echo "debootstrap $SUITE from $MIRROR into $new with: $pkgs" >&2
    debootstrap --variant=minbase --include="${pkgs// /,}" "$SUITE" "$new" "$MIRROR" >"$CACHE/debootstrap.log" 2>&1 || {
        tail -20 "$CACHE/debootstrap.log" >&2
        echo "debootstrap failed: $CACHE/debootstrap.log" >&2
        return 1
    }
    # No package caches or lists in the image: they are never used.
    rm -rf "$new"/var/cache/apt/archives/*.deb "$new"/var/lib/apt/lists/*
    echo "$pkgs" >"$new/etc/mscgs-test-packages"
    rm -rf "$IMAGE" && mv "$new" "$IMAGE" || return 1
    echo "cached image: $IMAGE ($(du -sh "$IMAGE" | cut -f1), $((SECONDS - start)) s)" >&2
}

if [ "${1:-}" = --make-cache ]; then
    make_cache
    exit
fi
[ $# -eq 0 ] || { echo "usage: $SELF [--make-cache]" >&2; exit 2; }

# ---- preconditions: skip, not fail, where the test cannot run ------------------------

[ "$(id -u)" -eq 0 ] || skip_all "not root (systemd-nspawn needs root)"
command -v systemd-nspawn >/dev/null || skip_all "no systemd-nspawn (apt-get install systemd-container)"
command -v nsenter >/dev/null || skip_all "no nsenter (util-linux)"
# CGS_MAKE_CACHE=1 (make test): make the image first when there is none, or
# when the programs now load a library from a package the image lacks.
stale=""
if [ -x "$IMAGE/usr/lib/systemd/systemd" ]; then
    have=$(tr ' ' '\n' <"$IMAGE/etc/mscgs-test-packages" 2>/dev/null)
    for p in $(runtime_packages 2>/dev/null); do
        grep -qxF -- "$p" <<<"$have" || stale="$stale $p"
    done
fi
if [ -n "$stale" ] && [ "${CGS_MAKE_CACHE:-0}" = 1 ]; then
    diag "the cached container image lacks$stale: making it again"
    rm -rf "$IMAGE"
fi
if [ ! -x "$IMAGE/usr/lib/systemd/systemd" ] && [ "${CGS_MAKE_CACHE:-0}" = 1 ]; then
    diag "no cached container image: making it (debootstrap, about 75 s)"
    make_cache 2>&1 | sed 's/^/# /'
    [ "${PIPESTATUS[0]}" -eq 0 ] || bail "cannot make the container image (the reason is above)"
fi
[ -x "$IMAGE/usr/lib/systemd/systemd" ] || skip_all "no cached container image: run $SELF --make-cache (as root)"
if [ -n "$stale" ] && [ "${CGS_MAKE_CACHE:-0}" != 1 ]; then
    bail "the cached container image lacks$stale: run $SELF --make-cache (as root)"
fi
if ldd "$CGS_BUILD/bin/mtid" 2>/dev/null | grep -q libasan; then
    echo "not ok 1 - $CGS_BUILD is a sanitizer build: use a release build (make -j2 O=build/release all)"
    echo "1..1"
    exit 1
fi

# ---- the container ----------------------------------------------------------------

TMP=$(mktemp -d "${TMPDIR:-/tmp}/cgs-sd.XXXXXX") || bail "mktemp"
ROOT=$TMP/root
OVERLAY=0
CGROUPS=()
NSPAWN=
LEADER=
MACHINE=mscgs-test-$$

# The units' processes and the container's are all below the container's
# PID 1: killing it ends its PID namespace. Ask systemd to power off first.
teardown () {
    local end
    if [ -n "$NSPAWN" ] && kill -0 "$NSPAWN" 2>/dev/null; then
        kill -TERM "$NSPAWN" 2>/dev/null   # nspawn asks the container's systemd to power off
        end=$((SECONDS + 20))
        while kill -0 "$NSPAWN" 2>/dev/null && [ "$SECONDS" -lt "$end" ]; do sleep 0.2; done
        if kill -0 "$NSPAWN" 2>/dev/null; then
            diag "the container did not power off in 20 s: killed"
            [ -n "$LEADER" ] && kill -KILL "$LEADER" 2>/dev/null
            sleep 0.5
            kill -KILL "$NSPAWN" 2>/dev/null
        fi
        wait "$NSPAWN" 2>/dev/null
    fi
    # Anything left in the container's cgroups (there should be nothing).
    local cg pid
    for cg in "${CGROUPS[@]}"; do
        [ -d "$cg" ] || continue
        while read -r pid; do
            diag "left behind, killed: $pid $(tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null)"
            kill -KILL "$pid" 2>/dev/null
        done < <(find "$cg" -name cgroup.procs -exec cat {} + 2>/dev/null)
        find "$cg" -depth -type d -exec rmdir {} + 2>/dev/null
    done
    [ "$OVERLAY" = 1 ] && umount "$ROOT" 2>/dev/null
    # nspawn leaves its folder for `machinectl bind` when /run is no tmpfs.
    rm -rf "/run/systemd/nspawn/propagate/$MACHINE"
}

cleanup () {
    if [ "$T_FAILED" -gt 0 ] && [ -n "$LEADER" ] && kill -0 "$LEADER" 2>/dev/null; then
        diag "---- the container's journal (last 60 lines)"
        ct journalctl --no-pager -o short-monotonic -n 60 2>&1 | sed 's/^/#   /'
    fi
    teardown
    if [ "$T_FAILED" -gt 0 ] && [ -s "$TMP/console.log" ]; then
        diag "---- the container's console (last 30 lines)"
        tail -30 "$TMP/console.log" | sed 's/^/#   /'
    fi
    if [ "${CGS_KEEP:-0}" = 1 ]; then
        diag "kept $TMP"
    else
        rm -rf "$TMP"
    fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# ct COMMAND...: run COMMAND inside the booted container (every namespace of
# its PID 1, its root), with a clean environment.
ct () {
    nsenter --target "$LEADER" --mount --uts --ipc --net --pid --cgroup --root --wd=/ \
        env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 SYSTEMD_PAGER= SYSTEMD_COLORS=0 "$@"
}

# prop UNIT PROPERTY: one property of a unit, its value only.
prop () { ct systemctl show -P "$2" "$1" 2>/dev/null; }

# A throw-away root: an overlay over the cached image, or a copy of it.
mkdir -p "$ROOT" "$TMP/upper" "$TMP/work"
if mount -t overlay overlay -o "lowerdir=$IMAGE,upperdir=$TMP/upper,workdir=$TMP/work" "$ROOT" 2>"$TMP/overlay.err"; then
    OVERLAY=1
else
    diag "no overlay ($(cat "$TMP/overlay.err")): copying the image"
    cp -a "$IMAGE/." "$ROOT/" || bail "copy $IMAGE to $ROOT"
fi

make -s -C "$CGS_ROOT" install-built O="$CGS_BUILD" PREFIX=/usr DESTDIR="$ROOT" >"$TMP/install.out" 2>&1 ||
    { cat "$TMP/install.out"; bail "make install into the container's root failed"; }
check "make install puts the units, the programs and the lab exercise into the container" bash -c \
    "[ -f '$ROOT/usr/lib/systemd/system/mscgs.target' ] && [ -x '$ROOT/usr/bin/mtid' ] && [ -f '$ROOT$EXERCISE' ]"

# The instances of the lab exercise, as `mscgs run` reads them: one per
# [service NAME], its program NAME up to the first '.' unless `program =`,
# none with `enabled = no`.
UNITS=()
while read -r unit; do
    UNITS+=("$unit")
done < <(awk '
    function flush () { if (inst != "" && enabled != "no") print prog "@" inst ".service" }
    /^\[/ { flush (); inst = ""; enabled = "" }
    /^\[service [^]]+\]/ { inst = $0; sub (/^\[service +/, "", inst); sub (/ *\].*/, "", inst)
                           prog = inst; sub (/\..*/, "", prog) }
    inst != "" && /^program *=/ { prog = $0; sub (/^program *= */, "", prog); sub (/ .*/, "", prog) }
    inst != "" && /^enabled *=/ { enabled = $0; sub (/^enabled *= */, "", enabled); sub (/ .*/, "", enabled) }
    END { flush () }' "$ROOT$EXERCISE")
diag "instances: ${UNITS[*]}"
[ "${#UNITS[@]}" -ge 8 ] || bail "found ${#UNITS[@]} instances in $EXERCISE, expected 8 or more"

# Enable every instance (mscgs.target wants them); the getty on the console
# would only restart on the closed pipe.
systemctl --root="$ROOT" enable "${UNITS[@]}" >"$TMP/enable.out" 2>&1 ||
    { cat "$TMP/enable.out"; bail "systemctl --root enable the instances"; }
systemctl --root="$ROOT" mask console-getty.service >>"$TMP/enable.out" 2>&1
check "every instance is enabled in mscgs.target.wants" bash -c \
    "[ \$(ls '$ROOT/etc/systemd/system/mscgs.target.wants' | wc -l) -eq ${#UNITS[@]} ]"

# Boot it in cgroups of its own (this host may have no systemd to give
# nspawn a unit): whatever is left in them at the end is killed.
cg_name=mscgs-test.$$
for h in /sys/fs/cgroup/unified /sys/fs/cgroup/systemd /sys/fs/cgroup; do
    if [ "$(stat -fc %T "$h" 2>/dev/null)" = cgroup2fs ] || [ -f "$h/release_agent" ]; then
        mkdir -p "$h/$cg_name" && CGROUPS+=("$h/$cg_name")
    fi
done
BOOT_START=$SECONDS
(
    for cg in "${CGROUPS[@]}"; do echo "$BASHPID" >"$cg/cgroup.procs"; done
    exec systemd-nspawn --quiet --keep-unit --register=no --private-network --boot \
        --directory="$ROOT" --machine="$MACHINE" --console=pipe </dev/null
) >"$TMP/console.log" 2>&1 &
NSPAWN=$!

# The container's PID 1: the child of nspawn that runs systemd.
find_leader () {
    local pid
    # shellcheck disable=SC2013  # children: pids separated by spaces
    for pid in $(cat /proc/"$NSPAWN"/task/*/children 2>/dev/null); do
        if [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = systemd ]; then
            LEADER=$pid
            return 0
        fi
    done
    return 1
}
wait_for 30 find_leader || bail "no container PID 1 after 30 s (nspawn: $(tail -3 "$TMP/console.log" | tr '\n' ' '))"

# systemctl needs PID 1's private socket; then it waits for the boot to end.
wait_for 30 ct test -S /run/systemd/private || bail "no /run/systemd/private in the container after 30 s"
state=$(ct timeout 60 systemctl is-system-running --wait 2>&1)
diag "booted in $((SECONDS - BOOT_START)) s: $state"
is "$state" running "the container's systemd finishes booting (running, no failed unit)"
[ "$state" = running ] || ct systemctl --no-pager --failed 2>&1 | sed 's/^/#   /'

# Every library the programs load is in the image (else: remake the cache).
ct sh -c 'ldd /usr/bin/mscgs /usr/bin/uavsim /usr/bin/mtid /usr/bin/bcisd /usr/bin/trackerd \
    /usr/bin/guidanced /usr/bin/imagerd /usr/bin/gateway /usr/bin/stationd' >"$TMP/ldd.out" 2>&1
check "every shared library of the programs is in the image (else: $SELF --make-cache)" \
    bash -c "! grep 'not found' '$TMP/ldd.out'"

# The lab exercise's gateway broadcasts DIS on the interface its parameters
# name (eth0); the container's private network has only lo, so it gets an
# eth0: a veth whose other end (lan0) stays in the container, what is sent
# on it counted and going nowhere else.
nsenter --target "$LEADER" --net sh -c \
    'ip link add eth0 type veth peer name lan0 && ip addr add 10.79.0.1/24 dev eth0 && ip link set lan0 up && ip link set eth0 up' \
    >"$TMP/eth0.out" 2>&1 || bail "an eth0 in the container: $(cat "$TMP/eth0.out")"
# eth0_tx: the packets sent on the container's eth0 (netlink: this host's
# /sys shows its own namespace's interfaces).
eth0_tx () {
    nsenter --target "$LEADER" --net ip -s link show eth0 | awk 'tx { print $2; exit } /^ *TX:/ { tx = 1 }'
}
eth0_tx_grew () { [ "$(eth0_tx)" -gt "$TX0" ]; }
TX0=$(eth0_tx)

# ---- 1. mscgs.target starts every instance; they reach READY and talk -----------------

START=$SECONDS
ct timeout 90 systemctl start mscgs.target >"$TMP/start.out" 2>&1
is "$?" 0 "systemctl start mscgs.target succeeds"
diag "mscgs.target started in $((SECONDS - START)) s"

DOWN=()
for u in "${UNITS[@]}"; do
    is "$(ct systemctl show -p Type,ActiveState,SubState,NRestarts "$u" | sort | tr '\n' ' ')" \
        "ActiveState=active NRestarts=0 SubState=running Type=notify " "$u is active (running), Type=notify, never restarted"
    [ "$(prop "$u" ActiveState)" = active ] || DOWN+=("$u")
    diag "  $u: $(prop "$u" StatusText)"
done
if [ "${#DOWN[@]}" -gt 0 ]; then
    # Nothing else can be checked: say why they died, then stop.
    for u in "${DOWN[@]}"; do
        diag "---- journalctl -u $u (first 12 lines)"
        ct journalctl --no-pager -o cat -u "$u" 2>&1 | head -12 | sed 's/^/#   /'
    done
    if ct journalctl --no-pager -o cat -u '*@*.service' 2>/dev/null | grep -q 'status=31/SYS'; then
        diag "status=31/SYS: killed by SystemCallFilter=; the kernel's audit lines name the call (syscall=N, x86_64 numbers):"
        dmesg 2>/dev/null | grep 'type=1326' | tail -8 | sed 's/^/#   /'
    fi
    bail "${#DOWN[@]} of ${#UNITS[@]} services are not active after systemctl start mscgs.target: ${DOWN[*]}"
fi

ct /usr/bin/mscgs status --exercise "$EXERCISE" --wait 10 >"$TMP/status1.out" 2>&1
rc=$?
sed 's/^/#   /' "$TMP/status1.out"
is "$rc" 0 "mscgs status: every instance is up"
ct /usr/bin/mscgs echo clock --count 1 --timeout 5 --exercise "$EXERCISE" >"$TMP/clock.out" 2>&1
is "$?" 0 "mscgs echo clock: uavsim's clock reaches a client in the container"

# The lab's DIS goes out on the interface named, and the gateway says so once.
GW=gateway@gateway.service
ct journalctl --no-pager -o cat -p notice..notice -u "$GW" >"$TMP/gw.notice" 2>&1
is "$(grep -c 'DIS leaves this machine: broadcast to 255.255.255.255:3000 on eth0' "$TMP/gw.notice")" 1 \
    "$GW logs once, at notice level, that the lab's DIS leaves the machine on eth0"
check "and its Entity State PDUs go out on eth0 (tx_packets $TX0 -> more)" \
    wait_for 15 eth0_tx_grew

# restarts_and_pids [UNIT...]: "UNIT NRESTARTS MAINPID" for every unit but those given.
restarts_and_pids () {
    local u
    for u in "${UNITS[@]}"; do
        [[ " $* " == *" $u "* ]] && continue
        echo "$u $(prop "$u" NRestarts) $(prop "$u" MainPID)"
    done
}
STARTED=$SECONDS
at_start=$(restarts_and_pids)

# restarted UNIT RESTARTS PID: UNIT has been restarted (NRestarts above
# RESTARTS, a new MainPID) and is active (running) again. Every Result the
# unit showed on the way is added to RESULTS.
RESULTS=
restarted () {
    local n=0 pid=0 state='' sub='' r='' kv
    # One systemctl call: Result=watchdog lasts only RestartSec (1 s).
    while read -r kv; do
        case $kv in
            NRestarts=*) n=${kv#*=} ;;
            MainPID=*) pid=${kv#*=} ;;
            ActiveState=*) state=${kv#*=} ;;
            SubState=*) sub=${kv#*=} ;;
            Result=*) r=${kv#*=} ;;
        esac
    done < <(ct systemctl show -p NRestarts,MainPID,ActiveState,SubState,Result "$1" 2>/dev/null)
    [[ " $RESULTS " == *" $r "* ]] || RESULTS="$RESULTS $r"
    [ "${n:-0}" -gt "$2" ] && [ "${pid:-0}" -ne 0 ] && [ "$pid" -ne "$3" ] && [ "$state/$sub" = active/running ]
}

# ---- 2. SIGKILL: systemd restarts the service, the others go on -----------------------

U=mtid@mtid.uav1.service
KILLED_UNIT=$U
n0=$(prop "$U" NRestarts)
pid0=$(prop "$U" MainPID)
others0=$(restarts_and_pids "$U")
ct systemctl kill -s KILL "$U"
KILLED=$SECONDS
check "$U killed with SIGKILL is restarted: NRestarts above $n0, MainPID not $pid0, active (running)" \
    wait_for 30 restarted "$U" "$n0" "$pid0"
diag "restarted in $((SECONDS - KILLED)) s: NRestarts $(prop "$U" NRestarts), MainPID $(prop "$U" MainPID)"
ct journalctl --no-pager -o cat -u "$U" >"$TMP/kill.journal" 2>&1
check "the journal says it was killed by SIGKILL" grep -q 'code=killed, status=9/KILL' "$TMP/kill.journal"
ct /usr/bin/mscgs echo mti --count 3 --timeout 20 --exercise "$EXERCISE" >"$TMP/mti.out" 2>&1
is "$?" 0 "its topic flows again: mscgs echo mti gets 3 messages"
check "from the new mtid.uav1" grep -q 'from mtid.uav1' "$TMP/mti.out"
is "$(restarts_and_pids "$U")" "$others0" "no other service restarted (NRestarts and MainPID unchanged)"

# ---- 3. SIGSTOP: the watchdog kills the wedged service, systemd restarts it ---------------

U=trackerd@trackerd.service
n0=$(prop "$U" NRestarts)
pid0=$(prop "$U" MainPID)
others0=$(restarts_and_pids "$U")
is "$(prop "$U" WatchdogUSec)" 10s "$U has a 10 s watchdog"
ct systemctl kill -s STOP "$U"
STOPPED=$SECONDS
RESULTS=
check "$U stopped with SIGSTOP is restarted: NRestarts above $n0, MainPID not $pid0, active (running)" \
    wait_for 40 restarted "$U" "$n0" "$pid0"
diag "restarted $((SECONDS - STOPPED)) s after SIGSTOP: NRestarts $(prop "$U" NRestarts), MainPID $(prop "$U" MainPID), Result seen:$RESULTS"
check "systemctl show -p Result said watchdog before the restart" bash -c "[[ ' $RESULTS ' == *' watchdog '* ]]"
ct journalctl --no-pager -o cat -u "$U" >"$TMP/watchdog.journal" 2>&1
grep -E 'atchdog|result' "$TMP/watchdog.journal" | sed 's/^/#   /'
check "the journal says the watchdog timed out" grep -q 'Watchdog timeout' "$TMP/watchdog.journal"
check "and that it failed with result 'watchdog'" grep -q "Failed with result 'watchdog'" "$TMP/watchdog.journal"
ct /usr/bin/mscgs echo track --count 1 --timeout 20 --exercise "$EXERCISE" >"$TMP/track.out" 2>&1
is "$?" 0 "its topic flows again: mscgs echo track gets a batch"
is "$(restarts_and_pids "$U")" "$others0" "no other service restarted (NRestarts and MainPID unchanged)"

ct /usr/bin/mscgs status --exercise "$EXERCISE" --wait 10 >"$TMP/status2.out" 2>&1
rc=$?
[ "$rc" -eq 0 ] || sed 's/^/#   /' "$TMP/status2.out"
is "$rc" 0 "mscgs status: every instance is up after both"
# Longer than WatchdogSec: the others' loops feed the watchdog.
is "$(restarts_and_pids "$KILLED_UNIT" "$U")" "$(grep -vE "^($KILLED_UNIT|$U) " <<<"$at_start")" \
    "in $((SECONDS - STARTED)) s (watchdog 10 s) no other service restarted or changed its process"

# ---- 4. systemctl stop mscgs.target stops every instance cleanly ---------------------

# The target stops before its instances (it is ordered after them), so
# systemctl returns before they are down: wait for each, within TimeoutStopSec.
ct timeout 60 systemctl stop mscgs.target >"$TMP/stop.out" 2>&1
is "$?" 0 "systemctl stop mscgs.target succeeds"
STOPPING=$SECONDS
inactive () { [ "$(prop "$1" ActiveState)" = inactive ] || [ "$(prop "$1" ActiveState)" = failed ]; }
for u in "${UNITS[@]}"; do
    wait_for 20 inactive "$u"
done
diag "every instance down $((SECONDS - STOPPING)) s after systemctl returned"
for u in "${UNITS[@]}"; do
    is "$(ct systemctl show -p ActiveState,Result "$u" | sort | tr '\n' ' ')" \
        "ActiveState=inactive Result=success " "$u stopped cleanly (inactive, Result=success)"
done
finish
