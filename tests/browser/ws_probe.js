// ws_probe.js — a WebSocket client of stationd's protocol for the tests:
// connects (optionally with an Origin header), sends each --send message once
// the hello has come, and prints every message it gets as one JSON line
// (a state as a summary: seq, sim time, counts), for --seconds, or until
// --replies answers to what it sent have come. Exit 0; 2 when it cannot
// connect (the reason on stdout as {"type":"connect-error",...}).
//   node ws_probe.js URL [--origin O] [--host H] [--send JSON]... [--send-size N]
//                    [--seconds S] [--replies N]
// (--host: the Host header to send; --send-size: also send a JSON message N bytes long)
'use strict';
const WebSocket = require(__dirname + '/node_modules/ws');

const args = process.argv.slice(2);
const url = args.shift();
const sends = [];
let origin = null, host = null, seconds = 5, replies = -1;
while (args.length) {
  const a = args.shift();
  if (a === '--origin') origin = args.shift();
  else if (a === '--host') host = args.shift();
  else if (a === '--send') sends.push(args.shift());
  else if (a === '--send-size') {
    const n = Number(args.shift());
    sends.push('{"op":"mgrs","req":99,"pad":"' + 'x'.repeat(Math.max(0, n - 36)) + '"}');
  }
  else if (a === '--seconds') seconds = Number(args.shift());
  else if (a === '--replies') replies = Number(args.shift());
  else { console.error('ws_probe: unknown option ' + a); process.exit(64); }
}

const opts = {};
if (origin) opts.origin = origin;
if (host) opts.headers = { Host: host };
const ws = new WebSocket(url, opts);
let answered = 0;
const done = (code) => { try { ws.terminate(); } catch (e) { /* closing anyway */ } process.exit(code); };
ws.on('unexpected-response', (req, res) => {
  console.log(JSON.stringify({ type: 'connect-error', status: res.statusCode }));
  done(2);
});
ws.on('error', (e) => { console.log(JSON.stringify({ type: 'connect-error', error: String(e.message) })); done(2); });
ws.on('message', (data) => {
  let m;
  try { m = JSON.parse(data.toString()); } catch (e) { console.log(JSON.stringify({ type: 'unparsable' })); return; }
  if (m.type === 'state') {
    console.log(JSON.stringify({
      type: 'state', seq: m.seq, sim_time_s: m.sim_time_s, bytes: data.length,
      hits: m.hits.reduce((a, s) => a + s.xy.length / 2, 0), tracks: m.tracks.length,
      uavs: m.uavs.length, intercepts: m.intercepts.length
    }));
    return;
  }
  console.log(JSON.stringify(m));
  if (m.type === 'hello') for (const s of sends) ws.send(s);
  if (m.type === 'reply' || m.type === 'mgrs' || m.type === 'error') {
    answered++;
    if (replies >= 0 && answered >= replies) done(0);
  }
});
ws.on('close', () => done(0));
setTimeout(() => done(0), seconds * 1000);
