// chromium_args.js — how the tests start Debian's Chromium: on this machine
// only. No background, sync, update or autofill traffic, and no name lookups
// but localhost (every page a test opens is on loopback), so a test or a
// benchmark puts nothing on the network. Shared by tests/browser/stationd.js
// and tests/bench/bench_stationd.js.
'use strict';
module.exports = [
  '--no-sandbox', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--no-first-run', '--no-default-browser-check',
  '--disable-features=AutofillServerCommunication,OptimizationHints,MediaRouter,Translate',
  '--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE localhost , EXCLUDE 127.0.0.1',
];
