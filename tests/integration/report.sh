#!/bin/bash
# report.sh — `mscgs report`, the after-action review, on a recording of a
# whole run: `mscgs run --record` of the default scenario with the real
# uavsim, mtid, bcisd, trackerd and guidanced (the scenario's operator
# designates at t = 120 s), to 20 s after the intercept ends. Then:
#  - the report is one well-formed XHTML file (xmllint), with nothing fetched
#    (no src or stylesheet link), its charts inline SVG: nine, each with a
#    title, an x label with its unit and a y label (with its unit but for
#    the two charts of lanes), each also a PNG that is a PNG of the SVG's
#    size;
#  - its numbers are the run's: report.json against summary.json (the
#    intercept's members exactly; the tracking figures to within what the
#    order of arrival between publishers can change), and the page says
#    what summary.json says (the track designated, imaged or not);
#  - its marks name the designation; a file that is not MCAP is refused.
# TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

for p in uavsim mtid bcisd trackerd guidanced mscgs; do
    [ -x "$CGS_BUILD/bin/$p" ] || bail "no $p"
done
command -v xmllint >/dev/null || bail "no xmllint (libxml2-utils)"

EX=$TMP/exercise.ini
exercise_scene 23 report-test "$CGS_ROOT/deploy/scenarios/default.ini" >"$EX"
OUT=$TMP/out

# ---- the run, recorded ---------------------------------------------------------------------
start RUN run "$MSCGS" run --exercise "$EX" --speed 10 --duration 900 --stop-after-intercept 20 \
    --out "$OUT" --record
check "the run ends by itself" wait_exit "$RUN" 240
is "$EXIT_CODE" 0 "mscgs run exits 0"
[ -f "$OUT/recording.mcap" ] || bail "no recording"
[ -f "$OUT/summary.json" ] || bail "no summary.json"

# ---- the report ----------------------------------------------------------------------------
"$MSCGS" report "$OUT/recording.mcap" >"$TMP/report.log" 2>&1
is "$?" 0 "mscgs report exits 0 ($(tail -1 "$TMP/report.log"))"
R=$OUT/report
check "it writes report.html, report.json and the figures" \
    test -s "$R/report.html" -a -s "$R/report.json"
check "report.html is well-formed XHTML (xmllint)" xmllint --noout "$R/report.html"
x () { xmllint --xpath "$1" "$R/report.html" 2>/dev/null; }
nsvg=$(x 'count(//*[local-name()="svg"])')
is "$nsvg" 9 "nine charts, inline SVG"
check "nothing is fetched: no src, no linked stylesheet, no script" \
    bash -c "! grep -qE ' src=|<link |<script' '$R/report.html'"
for i in $(seq 1 "${nsvg:-0}"); do
    id=$(x "string((//*[local-name()=\"svg\"])[$i]/@id)")
    title=$(x "string((//*[local-name()=\"svg\"])[$i]/*[local-name()=\"text\"][@class=\"title\"])")
    xl=$(x "string((//*[local-name()=\"svg\"])[$i]/*[local-name()=\"text\"][@class=\"xlabel\"])")
    yl=$(x "string((//*[local-name()=\"svg\"])[$i]/*[local-name()=\"text\"][@class=\"ylabel\"])")
    w=$(x "string((//*[local-name()=\"svg\"])[$i]/@width)")
    h=$(x "string((//*[local-name()=\"svg\"])[$i]/@height)")
    unit='\([^)]+\)'
    ok=1
    [ -n "$title" ] && [[ $xl =~ $unit ]] && [ -n "$yl" ] || ok=0
    case "$id" in fig-timeline | fig-health) ;; *) [[ $yl =~ $unit ]] || ok=0 ;; esac
    check "$id: \"$title\", x: \"$xl\", y: \"$yl\"" test "$ok" = 1
    png=$R/$id.png
    # PNG signature, then the IHDR's width and height (big-endian).
    sig=$(head -c 8 "$png" 2>/dev/null | od -An -tx1 | tr -d ' \n')
    pw=$(od -An -tu1 -j16 -N4 "$png" 2>/dev/null | awk '{print $1*16777216+$2*65536+$3*256+$4}')
    ph=$(od -An -tu1 -j20 -N4 "$png" 2>/dev/null | awk '{print $1*16777216+$2*65536+$3*256+$4}')
    check "$id.png is a PNG of its chart's size (${pw}x$ph)" \
        test "$sig" = 89504e470d0a1a0a -a "$pw" = "$w" -a "$ph" = "$h"
done
check "each chart has its caption" test "$(x 'count(//*[local-name()="figcaption"])')" = 9

# ---- the numbers: the run's ---------------------------------------------------------------
cmp_json () {
    node -e '
const fs = require("fs");
const s = JSON.parse(fs.readFileSync(process.argv[1])), r = JSON.parse(fs.readFileSync(process.argv[2]));
const bad = [];
for (const k of ["designated", "track_id", "target_entity_id", "target_marking", "designation_time_s",
                 "final_state", "replans", "imaged"])
    if (JSON.stringify(s[k]) !== JSON.stringify(r[k])) bad.push(`${k}: run ${s[k]}, report ${r[k]}`);
const near = (k, a, b, tol) => { if (a === null || b === null ? a !== b : Math.abs(a - b) > tol) bad.push(`${k}: run ${a}, report ${b}`); };
near("time_in_footprint_s", s.time_in_footprint_s, r.time_in_footprint_s, 0.5);
near("closest_approach_m", s.closest_approach_m, r.closest_approach_m, 5);
const st = s.tracking, rt = r.tracking;
near("tracking.scans", st.scans, rt.scans, 1);
near("tracking.gospa_m", st.gospa_m, rt.gospa_m, 0.03 * st.gospa_m + 1);
near("tracking.completeness", st.completeness, rt.completeness, 0.02);
near("tracking.position_accuracy_m", st.position_accuracy_m, rt.position_accuracy_m, 0.05 * st.position_accuracy_m + 1);
console.log(bad.length ? bad.join("; ") : "all agree");
process.exit(bad.length ? 1 : 0);' "$OUT/summary.json" "$R/report.json"
}
said=$(cmp_json 2>&1)
check "report.json agrees with the run's summary.json ($said)" test "$said" = "all agree"
track=$(node -e 'console.log(JSON.parse(require("fs").readFileSync(process.argv[1])).track_id)' "$OUT/summary.json")
imaged=$(node -e 'console.log(JSON.parse(require("fs").readFileSync(process.argv[1])).imaged)' "$OUT/summary.json")
diag "run: track $track, imaged $imaged"
check "the page names the designated track ($track)" \
    grep -q "Track $track was designated" "$R/report.html"
if [ "$imaged" = true ]; then
    check "and says it was imaged, as the summary does" grep -q "The vehicle was imaged" "$R/report.html"
else
    check "and says it was not imaged, as the summary does" grep -q "The vehicle was not imaged" "$R/report.html"
fi
check "the marks table has the designation" \
    test "$(x "count(//*[@id=\"marks\"]//*[local-name()=\"td\"][.=\"designate track $track\"])")" -ge 1

# ---- refusals ------------------------------------------------------------------------------
printf 'not an mcap file\n' >"$TMP/not.mcap"
"$MSCGS" report "$TMP/not.mcap" --out "$TMP/r2" >"$TMP/bad.log" 2>&1
is "$?" 1 "a file that is not MCAP is refused (exit 1)"
check "saying so" grep -q "not an MCAP file" "$TMP/bad.log"
check "no sanitizer report" clean_log report
finish
