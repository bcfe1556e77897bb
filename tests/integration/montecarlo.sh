#!/bin/bash
# montecarlo.sh — `mscgs montecarlo` from the command line on the default
# exercise and scenario (every service's adapter in lockstep): a small set
# runs, its last line is one JSON object with the figures the README names,
# every run not imaged is listed with a replay command, and that command
# repeats the run alone (the same outcome) with the services' log lines; two
# processes give the same result as one; --json and --csv hold every run;
# bad options are refused with the reason. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

[ -x "$MSCGS" ] || bail "no mscgs at $MSCGS"
EX=$CGS_ROOT/deploy/exercises/default.ini
cd "$CGS_ROOT" || bail "cd $CGS_ROOT"

"$MSCGS" montecarlo --exercise "$EX" --runs 3 --seed 2 --jobs 1 --quiet \
    --json "$TMP/runs.json" --csv "$TMP/runs.csv" >"$TMP/one.out" 2>"$TMP/one.err"
is "$?" 0 "mscgs montecarlo --runs 3 runs (no bad input, no error)"
last=$(tail -1 "$TMP/one.out")
diag "$last"
check "its last line is one JSON object with runs 3" bash -c "node -e '
    const r = JSON.parse(process.argv[1]);
    const keys = [\"runs\", \"imaged\", \"imaged_pct\", \"imaged_pct_ci95\", \"wrong_vehicle\", \"lost\",
        \"miss_p50_m\", \"miss_p95_m\", \"time_to_image_p50_s\", \"gospa_m\", \"completeness\",
        \"ambiguity\", \"spuriousness\", \"spuriousness_unseen\", \"position_accuracy_m\", \"swaps_per_truth_hour\",
        \"breaks_per_truth_hour\", \"false_tracks_per_hour\", \"id_completeness\",
        \"id_correctness\", \"id_wrong_fraction\", \"id_hostile_marked\"];
    for (const k of keys) if (!(k in r)) throw new Error(\"no \" + k);
    if (r.runs !== 3 || r.bad_inputs !== 0 || r.errors !== 0) throw new Error(\"counts\");
    if (!(r.imaged_pct_ci95[0] <= r.imaged_pct && r.imaged_pct <= r.imaged_pct_ci95[1])) throw new Error(\"interval\");
' '$last'"
check "--json holds the 3 runs" bash -c "node -e 'if (JSON.parse(require(\"fs\").readFileSync(process.argv[1])).length !== 3) process.exit(1)' '$TMP/runs.json'"
is "$(wc -l <"$TMP/runs.csv")" 4 "--csv holds a header and the 3 runs"
imaged=$(node -e 'console.log(JSON.parse(process.argv[1]).imaged)' "$last")
missed=$(grep -c '^run [0-9]*: ' "$TMP/one.out")
is "$missed" "$((3 - imaged))" "every run not imaged is listed ($missed)"

"$MSCGS" montecarlo --exercise "$EX" --runs 3 --seed 2 --jobs 2 --quiet >"$TMP/two.out" 2>&1
is "$?" 0 "the same set with --jobs 2 runs"
is "$(tail -1 "$TMP/two.out" | sed 's/"jobs":2,//')" "$(echo "$last" | sed 's/"jobs":1,//')" \
    "and gives the same result as one process"

# Replay run 1 alone with its trace: the same outcome as in the set.
"$MSCGS" montecarlo --exercise "$EX" --seed 2 --trace 1 >"$TMP/trace.out" 2>&1
is "$?" 0 "--trace 1 replays run 1 alone"
outcome=$(node -e 'const r = JSON.parse(require("fs").readFileSync(process.argv[1])); console.log(r[1].outcome)' "$TMP/runs.json")
check "with the outcome it had in the set ($outcome)" grep -q "^run 1 (.*): $outcome," "$TMP/trace.out"
check "and the services' log lines" grep -q '\] guidanced: operator script line' "$TMP/trace.out"

# Its timeline: vehicles, radar truth, tracks and intercept states as CSV.
"$MSCGS" montecarlo --exercise "$EX" --seed 2 --trace 1 --timeline "$TMP/tl.csv" >/dev/null 2>&1
is "$?" 0 "--trace 1 --timeline F writes the run's timeline"
is "$(head -1 "$TMP/tl.csv")" \
    "kind,t,id,e,n,ve,vn,status,hits,misses,continues,cont_p,existence,pd,sd,p_stopped,note" \
    "with its header"
for kind in entity truth track intercept; do
    check "and $kind rows" grep -q "^$kind," "$TMP/tl.csv"
done
is "$(awk -F, 'NR > 1 && NF != 17' "$TMP/tl.csv" | wc -l)" 0 "every row has the header's 17 columns"
desig=$(awk -F, '$1 == "intercept" && $3 != 0 { print $3; exit }' "$TMP/tl.csv")
check "the designated track ($desig) has rows of its own" grep -q "^track,[0-9.]*,$desig," "$TMP/tl.csv"
"$MSCGS" montecarlo --exercise "$EX" --timeline "$TMP/x.csv" >/dev/null 2>"$TMP/bad.err"
is "$?" 2 "--timeline without --trace is refused"
check "saying so" grep -q -- "--timeline needs --trace RUN" "$TMP/bad.err"

"$MSCGS" montecarlo --runs 0 >/dev/null 2>"$TMP/bad.err"
is "$?" 2 "--runs 0 is refused"
check "with the reason" grep -q -- "--runs: expected a whole number 1..1000000, got '0'" "$TMP/bad.err"
"$MSCGS" montecarlo --jobs 65 >/dev/null 2>"$TMP/bad.err"
is "$?" 2 "--jobs 65 is refused"
"$MSCGS" montecarlo --spread x >/dev/null 2>"$TMP/bad.err"
is "$?" 2 "--spread x is refused"
"$MSCGS" montecarlo --scenario /nonexistent.ini --runs 1 --quiet >/dev/null 2>"$TMP/bad.err"
is "$?" 1 "a scenario that does not load fails the set"
check "naming the file" grep -q "/nonexistent.ini" "$TMP/bad.err"
"$MSCGS" montecarlo stray >/dev/null 2>"$TMP/bad.err"
is "$?" 2 "a stray argument is refused"
finish
