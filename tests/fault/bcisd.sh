#!/bin/bash
# bcisd.sh — faults injected into bcisd.uav1 during intercepts (tests/fault/lib.sh
# says what is injected and what is checked). TAP on stdout.
: "${CGS_ROOT:=$(cd "$(dirname "$0")/../.." && pwd)}"
# shellcheck source=tests/fault/lib.sh
. "$CGS_ROOT/tests/fault/lib.sh"
fault_main bcisd.uav1
