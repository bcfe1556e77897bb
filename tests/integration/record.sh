#!/bin/bash
# record.sh — `mscgs record` on the default scenario with the real uavsim,
# mtid, bcisd, trackerd and guidanced (the scenario's operator designates at
# t = 120 s), checked by a reader nobody here wrote (@mcap/core, with
# protobufjs decoding every message from the schemas the file carries):
#  - the file opens indexed (footer, summary, chunk indexes, CRCs): a channel
#    per topic, each with its message's protobuf schema; every message
#    decodes, its header's sequence is the record's;
#  - it holds exactly the messages an observer saw: `mscgs echo` of uav,
#    track and intercept, run over the same time, against the recording's
#    messages of those topics (source and sequence number, where both
#    listened), and the recorder's own per-topic counts;
#  - a recorder killed with SIGKILL leaves a file the stream reader reads
#    whole up to its last chunk, the last message within 1.5 s of the kill;
#  - a bad --topics or an output that cannot be written is refused.
# TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

for p in uavsim mtid bcisd trackerd guidanced; do [ -x "$CGS_BUILD/bin/$p" ] || bail "no $p"; done
command -v node >/dev/null || bail "no node (scripts/install-deps installs it)"
INTEROP=$CGS_ROOT/tests/interop
[ -d "$INTEROP/node_modules/@mcap/core" ] || bail "no @mcap/core (npm ci in tests/interop)"

EX=$TMP/exercise.ini
exercise_scene 17 record-test "$CGS_ROOT/deploy/scenarios/default.ini" >"$EX"
M () { "$MSCGS" "$@" --exercise "$EX"; }
MCAP=$TMP/run.mcap

# ---- refusals ----------------------------------------------------------------------------
out=$(M record --topics uav,nosuch --out "$TMP/x.mcap" 2>&1)
is "$?" 2 "an unknown topic is refused (exit 2)"
check "with its name" grep -q "unknown topic 'nosuch'" <<<"$out"
out=$(M record --out "$TMP/no/such/dir/x.mcap" --duration 1 2>&1)
is "$?" 1 "an output that cannot be created is refused (exit 1)"
check "with the reason" grep -q "no/such/dir/x.mcap: cannot create" <<<"$out"

# ---- a recording, with observers -------------------------------------------------------
start REC record "$MSCGS" record --exercise "$EX" --out "$MCAP"
for t in uav track intercept; do
    start E echo-$t "$MSCGS" echo $t --json --exercise "$EX"
    eval "E_$t=\$E"
done
sleep 1
start U uavsim "$CGS_BUILD/bin/uavsim" --exercise "$EX" --time-scale 10
start R mtid "$CGS_BUILD/bin/mtid" --exercise "$EX" --instance mtid.uav1
start B bcisd "$CGS_BUILD/bin/bcisd" --exercise "$EX" --instance bcisd.uav1
start T trackerd "$CGS_BUILD/bin/trackerd" --exercise "$EX"
start G guidanced "$CGS_BUILD/bin/guidanced" --exercise "$EX"
check "the recorder says what it records" wait_for 10 \
    grep -q "mscgs record: [0-9]* topics from 5 services of record-test into $MCAP" "$TMP/record.log"
designated () { grep -q '"track_id":[1-9]' "$TMP/echo-intercept.log"; }
check "the scenario's operator designates a track (t = 120 s)" wait_for 90 designated
sleep 3
# A second recorder, killed with SIGKILL.
start K record-killed "$MSCGS" record --exercise "$EX" --out "$TMP/killed.mcap"
sleep 4
kill_ns=$(date +%s%N)
kill9 "$K"
# The services stop first, then the observers and the recorder: all of it heard.
for p in $G $T $B $R $U; do stop "$p"; done
sleep 1
for t in uav track intercept; do eval "stop \$E_$t"; done
stop "$REC"
is "$EXIT_CODE" 0 "mscgs record stops on SIGTERM with exit code 0"
diag "$(tail -2 "$TMP/record.log")"
check "it says what it wrote" grep -q "mscgs record: [0-9]* messages in [0-9]* chunks to $MCAP" "$TMP/record.log"

# ---- the file, read by @mcap/core ----------------------------------------------------------
node "$INTEROP/mcap_check.mjs" "$MCAP" >"$TMP/check.json" 2>"$TMP/check.err"
is "$?" 0 "@mcap/core reads it indexed, and every message decodes ($(head -c 300 "$TMP/check.err"))"
q () { node -e 'const o = JSON.parse(require("fs").readFileSync(process.argv[1])); console.log(eval(process.argv[2]))' "$TMP/check.json" "$1"; }
is "$(q 'o.complete')" true "the file is complete: footer, summary and chunk indexes"
is "$(q 'o.statistics.messages === o.messages')" true "its statistics count the messages it holds ($(q o.messages))"
is "$(q 'o.channels.length')" "$(M topics 2>/dev/null | tail -n +2 | grep -c .)" "a channel per topic of the catalogue"
is "$(q 'o.channels.every((c) => c.encoding === "protobuf" && /^cgs\./.test(c.schema))')" true \
    "each of protobuf, with its message's schema (cgs.*)"
is "$(q 'o.channels.find((c) => c.topic === "track").schema')" cgs.TrackBatch "track's schema is cgs.TrackBatch"
for t in uav track mti health clock; do
    check "it holds $t messages ($(q "o.topics['$t']?.count ?? 0"))" test "$(q "o.topics['$t']?.count ?? 0")" -gt 0
done
check "health from all five services" test "$(q "Object.keys(o.topics.health.sources).length")" -eq 5
# The recorder's own per-topic counts are the file's.
counts=$(sed -n 's/^mscgs record: [0-9]* messages in [0-9]* chunks to [^:]*: //p' "$TMP/record.log")
mismatch=$(node -e '
    const o = JSON.parse(require("fs").readFileSync(process.argv[1]));
    const bad = [];
    for (const kv of process.argv[2].split(", ")) {
        const [t, n] = kv.split(" ");
        if ((o.topics[t]?.count ?? 0) !== Number(n)) bad.push(`${t} ${n} vs ${o.topics[t]?.count}`);
    }
    console.log(bad.join("; "));' "$TMP/check.json" "$counts")
is "$mismatch" "" "the recorder's per-topic counts are the file's"

# The observers' messages against the recording's: per source, the same
# sequence numbers over the span both heard.
for t in uav track intercept; do
    node "$INTEROP/mcap_check.mjs" "$MCAP" --dump "$t" | head -n -1 >"$TMP/rec-$t.jsonl"
    verdict=$(node -e '
        const fs = require("fs");
        const seqs = (f) => {
            const m = new Map();
            for (const l of fs.readFileSync(f, "utf8").split("\n")) {
                if (!l.startsWith("{")) continue;
                const h = JSON.parse(l).header;
                if (!m.has(h.source)) m.set(h.source, []);
                m.get(h.source).push(Number(h.seq));
            }
            return m;
        };
        const a = seqs(process.argv[1]), b = seqs(process.argv[2]);
        let both = 0;
        const bad = [];
        for (const [src, sa] of a) {
            const sb = b.get(src) ?? [];
            const lo = Math.max(sa[0], sb[0] ?? Infinity), hi = Math.min(sa.at(-1), sb.at(-1) ?? -1);
            const ra = sa.filter((s) => s >= lo && s <= hi), rb = sb.filter((s) => s >= lo && s <= hi);
            if (ra.join() !== rb.join()) bad.push(`${src}: ${ra.length} recorded, ${rb.length} seen`);
            both += ra.length;
        }
        console.log(bad.length ? bad.join("; ") : `same ${both}`);' "$TMP/rec-$t.jsonl" "$TMP/echo-$t.log")
    check "$t: the recording holds exactly what the observer saw ($verdict)" grep -q '^same [1-9]' <<<"$verdict"
done

# ---- the killed recorder's file -------------------------------------------------------
node "$INTEROP/mcap_check.mjs" "$TMP/killed.mcap" --stream >"$TMP/killed.json" 2>&1
is "$?" 0 "a recorder killed with SIGKILL leaves a file @mcap/core's stream reader reads"
k () { node -e 'const o = JSON.parse(require("fs").readFileSync(process.argv[1])); console.log(eval(process.argv[2]))' "$TMP/killed.json" "$1"; }
is "$(k 'o.complete')" false "without its footer (it was killed)"
last=$(k 'Object.values(o.topics).map((t) => BigInt(t.last_log_ns)).reduce((a, b) => a > b ? a : b, 0n).toString()')
lag=$(awk -v k="$kill_ns" -v l="$last" 'BEGIN { printf "%.2f", (k - l) / 1e9 }')
check "its last message is within 1.5 s of the kill ($lag s, $(k 'o.messages') messages)" \
    awk -v x="$lag" 'BEGIN { exit !(x >= 0 && x < 1.5) }'
check "no sanitizer report from the recorder" clean_log record
finish
