#!/bin/bash
# klv.sh — the tactical map's MISB ST 0601 reader and its geodetic-to-local
# conversion (services/stationd/web/js/klv.js, geo.js) in node, no browser:
# see klv.js. TAP on stdout.
command -v node >/dev/null || { echo "1..0 # SKIP no node"; exit 0; }
exec node "$(dirname "$0")/klv.js"
