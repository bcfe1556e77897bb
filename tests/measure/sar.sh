#!/bin/bash
# sar.sh — does the SAR chip hold the designated target? The default
# exercise runs live (`mscgs run`: every service, the real bus) at time
# scale SCALE over exercise seeds 1..N with the imaging sensor in SAR mode
# from the start; the scenario's operator designates a track at 120 s and
# the UAV flies its intercept. Every SAR `image` message with a designated
# target counts: is the target's return in the chip (target_in_view), and
# how wide was the chip (its footprint's side against [sar] scene_m).
# Opt-in (make validate-sar): minutes, not a CI test.
#
# Usage: tests/measure/sar.sh BUILD_DIR [N] [SCALE] [DURATION]
#        (defaults 8 seeds, 4x, 360 s of simulation time)
set -u
build=$(cd "${1:?usage: sar.sh BUILD_DIR [N] [SCALE] [DURATION]}" && pwd)
n=${2:-8}
scale=${3:-4}
duration=${4:-360}
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/cgs-sar.XXXXXX") || exit 2
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$tmp"' EXIT
mscgs=$build/bin/mscgs
[ -x "$mscgs" ] || { echo "sar: no $mscgs (make first)" >&2; exit 2; }
command -v node >/dev/null || { echo "sar: no node (scripts/install-deps)" >&2; exit 2; }

sed -e 's/^mode = visible$/mode = sar/' "$root/deploy/params/imager.ini" >"$tmp/imager.ini"
grep -q '^mode = sar$' "$tmp/imager.ini" || { echo "sar: cannot set mode = sar" >&2; exit 2; }
scene=$(sed -n 's/^scene_m = //p' "$tmp/imager.ini")

echo "SAR on the default exercise: $n seeds at ${scale}x, ${duration} s each"
printf '%6s %8s %8s %8s %10s %s\n' seed frames inview share "chip m" "(median, max)"
: >"$tmp/all.txt"
for s in $(seq 1 "$n"); do
    sed -e "s|ipc:///tmp/mscgs/|ipc://$tmp/|" -e "s|^state_dir = .*|state_dir = $tmp/state|" \
        -e "s|= \.\./|= $root/deploy/|" -e "s|^seed = .*|seed = $s|" \
        -e "s|^params = .*imager.ini$|params = $tmp/imager.ini|" \
        "$root/deploy/exercises/default.ini" >"$tmp/ex-$s.ini"
    "$mscgs" echo image --json --exercise "$tmp/ex-$s.ini" >"$tmp/image-$s.log" 2>/dev/null &
    echo_pid=$!
    "$mscgs" run --exercise "$tmp/ex-$s.ini" --speed "$scale" --duration "$duration" \
        --out "$tmp/run-$s" >"$tmp/run-$s.log" 2>&1
    kill "$echo_pid" 2>/dev/null
    wait "$echo_pid" 2>/dev/null
    node -e '
        const fs = require("fs"), scene = Number(process.argv[2]);
        let frames = 0, inview = 0;
        const sides = [];
        for (const l of fs.readFileSync(process.argv[1], "utf8").split("\n")) {
            if (!l.startsWith("{")) continue;
            let m;
            try { m = JSON.parse(l); } catch (e) { continue; }
            if (m.mode !== "IMAGE_MODE_SAR" || !m.target_entity_id) continue;
            frames++;
            if (m.target_in_view) inview++;
            const c = m.footprint.corners, d = (a, b) => Math.hypot(a.east_m - b.east_m, a.north_m - b.north_m);
            sides.push(d(c[0], c[3]));
        }
        sides.sort((a, b) => a - b);
        const med = sides.length ? sides[sides.length >> 1] : 0, max = sides.length ? sides[sides.length - 1] : 0;
        console.log(`${frames} ${inview} ${med.toFixed(0)} ${max.toFixed(0)}`);
    ' "$tmp/image-$s.log" "$scene" >"$tmp/seed-$s.txt"
    read -r frames inview med max <"$tmp/seed-$s.txt"
    echo "$frames $inview" >>"$tmp/all.txt"
    share=$(awk -v a="$inview" -v b="$frames" 'BEGIN { printf "%.1f%%", b ? 100 * a / b : 0 }')
    printf '%6d %8d %8d %8s %10s (%s)\n' "$s" "$frames" "$inview" "$share" "$med" "$max"
    grep -h "SAR: " "$tmp/run-$s"/logs/imagerd*.log 2>/dev/null | sed 's/^/         /' | tail -3
done
awk '{ f += $1; v += $2 } END {
    p = f ? v / f : 0; z = 1.96; den = 1 + z * z / f;
    c = (p + z * z / (2 * f)) / den; h = z * sqrt(p * (1 - p) / f + z * z / (4 * f * f)) / den;
    printf "all: the target in %d of %d SAR frames with a designation, %.1f%% (95%% interval %.1f-%.1f%%)\n",
        v, f, 100 * p, 100 * (c - h), 100 * (c + h) }' "$tmp/all.txt"
