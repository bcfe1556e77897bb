#!/bin/bash
# curve.sh — CURVE security with keys in the exercise file: uavsim and mtid
# run with their key pairs over tcp on loopback; mtid (a listed client)
# subscribes to uavsim through CURVE, and the tools' listed pair can
# subscribe and send commands; a client with an unknown key, and one with
# no CURVE at all, can neither subscribe nor send a command, and uavsim's
# ZAP handler counts the refusals; `mscgs keygen` makes the pairs and never
# overwrites a key; an exercise with keys for some instances only, or a
# secret key that is not the public key's, is refused at start. TAP on stdout.
# shellcheck source=tests/integration/lib.sh
. "$(dirname "$0")/lib.sh"

UAVSIM=$CGS_BUILD/bin/uavsim
MTID=$CGS_BUILD/bin/mtid
for b in "$UAVSIM" "$MTID"; do [ -x "$b" ] || bail "no $b"; done

K=$TMP/keys
mkdir -p "$K"
for n in uavsim mtid ops intruder; do
    "$MSCGS" keygen "$n" --dir "$K" >"$TMP/keygen-$n.out" || bail "keygen $n"
done
check "keygen writes the secret key readable by its owner only" bash -c "[ \"\$(stat -c %a '$K/uavsim.key')\" = 600 ]"
check "and prints the exercise file's lines" grep -qxF "public_key = $(cat "$K/uavsim.pub")" "$TMP/keygen-uavsim.out"
"$MSCGS" keygen uavsim --dir "$K" >/dev/null 2>"$TMP/keygen-again.err"
check "a second keygen of the same name refuses to overwrite it" bash -c \
    "[ $? -ne 0 ] && grep -q 'never overwritten' '$TMP/keygen-again.err' && [ \"\$(wc -l <'$K/uavsim.key')\" = 1 ]"

P=$((20000 + RANDOM % 20000))
pub () { cat "$K/$1.pub"; }
# exercise FILE CLIENT: the exercise with every instance's keys, the tools
# using CLIENT's pair ("" for an exercise without any key).
exercise () {
    local uavsim_keys=() mtid_keys=()
    if [ -n "$2" ]; then
        uavsim_keys=("public_key=$(pub uavsim)" "secret_key_file=$K/uavsim.key")
        mtid_keys=("public_key=$(pub mtid)" "secret_key_file=$K/mtid.key")
    fi
    {
        exercise_header 13 curve-test scenario=scenario.ini
        if [ -n "$2" ]; then
            printf '\n[curve]\nclient_public_key = %s\nclient_secret_key_file = %s\n' "$(pub "$2")" "$K/$2.key"
        fi
        exercise_service uavsim publish="tcp://127.0.0.1:$P" command="tcp://127.0.0.1:$((P + 1))" "${uavsim_keys[@]}"
        exercise_service mtid.uav1 publish="tcp://127.0.0.1:$((P + 2))" uav=uav1 "${mtid_keys[@]}"
    } >"$1"
}
{
    scenario_ground size_m=20000
    scenario_uav
    cat <<'EOF'

[vehicle target]
force = hostile
point = 4000 -3000
point = 4000 8000
speed_mps = 10
EOF
} >"$TMP/scenario.ini"
exercise "$TMP/ok.ini" ops
exercise "$TMP/intruder.ini" intruder
exercise "$TMP/plain.ini" ""

start U uavsim "$UAVSIM" --exercise "$TMP/ok.ini" --time-scale 10
start R mtid "$MTID" --exercise "$TMP/ok.ini" --instance mtid.uav1
check "uavsim runs CURVE with its own key" wait_for 10 grep -qF "CURVE on every socket, as $(pub uavsim)" "$TMP/uavsim.log"

# ---- listed keys -------------------------------------------------------------------------
"$MSCGS" echo mti.scan --count 1 --timeout 30 --exercise "$TMP/ok.ini" >"$TMP/ok-echo.out" 2>&1
is "$?" 0 "mtid, a listed client, hears uavsim: its scans reach the tools' listed key"
"$MSCGS" echo clock --count 1 --timeout 10 --exercise "$TMP/ok.ini" >/dev/null 2>&1
is "$?" 0 "the tools' listed key subscribes to uavsim"
"$MSCGS" ping uavsim --exercise "$TMP/ok.ini" >"$TMP/ok-ping.out" 2>&1
is "$?" 0 "and sends it a command"

# ---- unknown key, and no CURVE -----------------------------------------------------------
"$MSCGS" echo clock --count 1 --timeout 4 --exercise "$TMP/intruder.ini" >/dev/null 2>&1
is "$?" 4 "an unknown key cannot subscribe (nothing in 4 s)"
"$MSCGS" ping uavsim --exercise "$TMP/intruder.ini" >"$TMP/intruder-ping.out" 2>&1
check "nor send a command" bash -c "[ $? -ne 0 ] && grep -qi 'no reply\|did not answer\|silent\|timed out' '$TMP/intruder-ping.out'"
"$MSCGS" echo clock --count 1 --timeout 4 --exercise "$TMP/plain.ini" >/dev/null 2>&1
is "$?" 4 "a client without CURVE cannot subscribe"
"$MSCGS" ping uavsim --exercise "$TMP/plain.ini" >/dev/null 2>&1
check "nor send a command" test $? -ne 0
counter () { "$MSCGS" status --exercise "$TMP/ok.ini" 2>/dev/null | grep -A1 '^uavsim' | grep -o "$1=[0-9]*" | head -1 | cut -d= -f2; }
refused=$(counter curve_refused)
check "uavsim's ZAP handler counts the refused key (${refused:-none})" test "${refused:-0}" -ge 2
admitted=$(counter curve_admitted)
check "and the admitted ones (${admitted:-none})" test "${admitted:-0}" -ge 3

# ---- refused set-ups ---------------------------------------------------------------------------
sed '/^\[service mtid.uav1\]/,$ { /^public_key/d; /^secret_key_file/d }' "$TMP/ok.ini" >"$TMP/half.ini"
timeout 20 "$MTID" --exercise "$TMP/half.ini" --instance mtid.uav1 --state-dir "$TMP/st2" >"$TMP/half.out" 2>&1
check "an instance without keys in an exercise that has them is refused at start" bash -c \
    "[ $? -ne 0 ] && grep -q 'mtid.uav1\] has no public_key, but the exercise uses CURVE' '$TMP/half.out'"
sed "s|$K/mtid.key|$K/intruder.key|" "$TMP/ok.ini" >"$TMP/mismatch.ini"
timeout 20 "$MTID" --exercise "$TMP/mismatch.ini" --instance mtid.uav1 --state-dir "$TMP/st3" >"$TMP/mismatch.out" 2>&1
check "a secret key that is not the public key's is refused at start" bash -c \
    "[ $? -ne 0 ] && grep -q 'does not belong to the public key' '$TMP/mismatch.out'"

stop "$R"
is "$EXIT_CODE" 0 "mtid stops cleanly"
stop "$U"
is "$EXIT_CODE" 0 "uavsim stops cleanly"
check "their logs are clean" bash -c "! grep -qE 'Sanitizer|runtime error' '$TMP/uavsim.log' '$TMP/mtid.log'"
finish
