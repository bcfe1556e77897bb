# shellcheck shell=bash disable=SC2034  # T_N and T_FAILED are read by the scripts
# tests/tap.sh — TAP output for the shell tests (integration, fault, systemd);
# sourced, never run. Gives diag, check, is, bail, skip_all, relay and finish.

T_N=0
T_FAILED=0

diag () { printf '# %s\n' "$*"; }

# check NAME COMMAND...: one TAP line, ok when COMMAND succeeds.
check () {
    local name=$1; shift
    T_N=$((T_N + 1))
    if "$@"; then
        echo "ok $T_N - $name"
    else
        echo "not ok $T_N - $name"
        T_FAILED=$((T_FAILED + 1))
    fi
}

# is ACTUAL EXPECTED NAME: one TAP line, ok when the two strings are equal.
is () {
    T_N=$((T_N + 1))
    if [ "$1" = "$2" ]; then
        echo "ok $T_N - $3"
    else
        echo "not ok $T_N - $3"
        diag "  got '$1', expected '$2'"
        T_FAILED=$((T_FAILED + 1))
    fi
}

# bail WHY: a setup step failed; the rest of the script cannot run.
bail () {
    T_N=$((T_N + 1))
    echo "not ok $T_N - $*"
    T_FAILED=$((T_FAILED + 1))
    exit 1
}

# skip_all WHY: the whole test cannot run here; one skipped case, exit 0.
skip_all () {
    echo "ok 1 # SKIP $*"
    echo "1..1"
    exit 0
}

# relay FILE: the "ok - NAME", "not ok - NAME" and "# ..." lines a
# script wrote (the browser tests' node scripts) as checks, numbered here.
relay () {
    local line
    while IFS= read -r line; do
        case "$line" in
        "ok - "*) check "${line#ok - }" true ;;
        "not ok - "*) check "${line#not ok - }" false ;;
        "# "*) echo "$line" ;;
        esac
    done <"$1"
}

# finish: the plan (at the end, as TAP allows) and the exit code.
finish () {
    echo "1..$T_N"
    [ "$T_FAILED" -eq 0 ]
}
