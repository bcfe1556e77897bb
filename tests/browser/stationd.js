#!/usr/bin/env node
/*
 * stationd.js — the tactical map in Debian's Chromium (playwright-core),
 * against a running exercise and two running stationd (stationd.sh starts
 * them): the page loads with no page or console error, with its shaded
 * relief and the sensor image; MTI hits, an unknown confirmed track and a
 * BCIS reply appear; clicking the newest hit of an unknown track designates
 * that very track and the purple route is drawn on screen (and hidden by
 * "Show Intercept Route"); the status panel shows the phase, the track and a
 * range; Cancel Intercept sends the UAV back to loiter; refused commands show
 * why; a second browser gets the same pictures; on the stationd with a token
 * a page without it only watches (the server refuses its commands too) and a
 * page with it commands; the cursor's MGRS agrees with GeographicLib's
 * CartConvert and GeoConvert. The live video (stationd's /video, played by
 * mpegts.js through Media Source Extensions): whether this Chromium can
 * play H.264 that way at all; the imaging-sensor panel plays it (its width,
 * its time moving on at the exercise's time scale) and says so; the KLV
 * footprint is drawn and, with the exercise paused, its corners are those
 * of the `image` message's footprint of the same frame to within 1% of the
 * footprint's width; the delay from each frame's publication on the bus to
 * its display (median and 95th percentile); a page that does not read is
 * dropped to the next keyframe and counted while the others play on; a
 * fresh /video client starts at a keyframe; a foreign Origin is refused on
 * /video; without MSE, or with a /video that fails, the panel shows the
 * latest picture and says why. The imaging sensor: FLIR and SAR chosen from
 * the Sensors menu are accepted by imagerd and the status says which mode is
 * live as the `image` messages say (and follows a mode switched elsewhere);
 * the camera panel's depression, zoom and Stabilized reach uavsim and come
 * back on the `uav` state, out-of-range values are refused (by the page, by
 * uavsim with its reason, by stationd for malformed ones); "At point…" and a
 * click on the map make the camera stare there (staring true, the point
 * marked); a page without the token has these controls disabled and its
 * commands are refused. Screenshots of every step go to --artifacts.
 *
 * Output: one "ok - NAME" or "not ok - NAME" line per check and "# ..."
 * comments (stationd.sh numbers them as TAP). Exit code 0 when the script ran
 * to its end (whatever the checks said), 1 when it could not.
 *
 * Usage: node stationd.js --url URL --token-url URL --token T --origin "LAT LON H"
 *        --chromium PATH --artifacts DIR --exercise FILE --mscgs PATH
 */
'use strict';

const path = require('path');
const CHROMIUM_ARGS = require('./chromium_args.js');
const crypto = require('crypto');
const net = require('net');
const { execFile, execFileSync, spawn } = require('child_process');
const { chromium } = require('playwright-core');
const WebSocket = require('ws');

// ---- arguments and output --------------------------------------------------------------

const opt = {};
for (let i = 2; i + 1 < process.argv.length; i += 2) opt[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
for (const k of ['url', 'token-url', 'token', 'origin', 'chromium', 'artifacts', 'exercise', 'mscgs']) {
  if (!opt[k]) {
    console.error('stationd.js: missing --' + k);
    process.exit(2);
  }
}

function diag(s) {
  for (const line of String(s).split('\n')) console.log('# ' + line);
}

let failures = 0;
function check(cond, name, why) {
  console.log((cond ? 'ok - ' : 'not ok - ') + name);
  if (!cond) {
    failures += 1;
    if (why !== undefined) diag('  ' + (typeof why === 'string' ? why : JSON.stringify(why)));
  }
  return !!cond;
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Poll fn (async, returns a truthy value when done) every `every` ms until
// `ms` pass; the last value either way.
async function poll(fn, ms, every = 100) {
  const end = Date.now() + ms;
  let v;
  for (;;) {
    v = await fn();
    if (v || Date.now() >= end) return v;
    await sleep(every);
  }
}

// ---- pages -------------------------------------------------------------------------------

const VIEWPORT = { width: 1400, height: 900 };
const ACTIVE = ['TO_SECONDARY', 'TO_WAYPOINT', 'APPROACH', 'PRECISION', 'OVERFLIGHT'];
const OPERATOR_CONTROLS = ['#cancel', '#alt-input', '#alt-set', '#speed-input', '#speed-set', '#fp-scale', '#method',
  '#sensor-eo', '#sensor-flir', '#sensor-sar', '#cam-depression', '#cam-depression-set', '#cam-fov', '#cam-fov-set',
  '#cam-stabilized', '#stare-off', '#stare-target', '#stare-point'];
const MODE_LABELS = { visible: 'Visible (EO)', infrared: 'FLIR (infrared)', sar: 'SAR' };
const pages = [];       // every page opened, with its errors and state frames
let shot = 0;

// A new browser context and page at url, recording page errors, console
// errors and every `state` frame its WebSocket receives; init: a function
// run in the page before its own scripts.
async function openPage(browser, url, label, init) {
  const context = await browser.newContext({ viewport: VIEWPORT, deviceScaleFactor: 1 });
  if (init) await context.addInitScript({ content: '(' + init.toString() + ')();' });
  const page = await context.newPage();
  const rec = { label, page, context, errors: [], frames: new Map(), bcisSeen: null, responses: [] };
  page.on('pageerror', (e) => rec.errors.push('page error: ' + e.message));
  page.on('console', (m) => {
    if (m.type() === 'error') rec.errors.push('console error: ' + m.text());
  });
  page.on('response', (r) => rec.responses.push({ url: r.url(), status: r.status(), type: r.headers()['content-type'] || '' }));
  page.on('websocket', (ws) => {
    ws.on('framereceived', (f) => {
      const text = typeof f.payload === 'string' ? f.payload : f.payload.toString();
      if (!text.startsWith('{"type":"state"')) return;
      let st;
      try {
        st = JSON.parse(text);
      } catch (err) {
        rec.errors.push('a state frame that is not JSON: ' + err.message);
        return;
      }
      rec.frames.set(st.seq, {
        hash: crypto.createHash('sha1').update(text).digest('hex'),
        tracks: (st.tracks || []).map((t) => t.id).sort((a, b) => a - b).join(','),
        at: Date.now(),
      });
      if (!rec.bcisSeen && Array.isArray(st.bcis) && st.bcis.length) rec.bcisSeen = st.bcis[0];
    });
  });
  pages.push(rec);
  await page.goto(url);
  return rec;
}

async function screenshot(page, step) {
  shot += 1;
  const file = path.join(opt.artifacts, String(shot).padStart(2, '0') + '-' + step + '.png');
  const png = await page.screenshot({ path: file });
  return png;
}

async function waitReady(page, ms) {
  await page.waitForFunction(() => window.cgs && window.cgs.ready && window.cgs.hello && window.cgs.state,
    null, { timeout: ms, polling: 100 });
}

// The RGBA pixels of a screenshot around each [x, y] (a (2r+1)^2 square),
// decoded by the browser itself.
async function pixelsAround(page, png, points, r) {
  return page.evaluate(async ({ b64, pts, r }) => {
    const img = new Image();
    img.src = 'data:image/png;base64,' + b64;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.naturalWidth;
    c.height = img.naturalHeight;
    const g = c.getContext('2d', { willReadFrequently: true });
    g.drawImage(img, 0, 0);
    return pts.map((p) => Array.from(g.getImageData(Math.round(p[0]) - r, Math.round(p[1]) - r, 2 * r + 1, 2 * r + 1).data));
  }, { b64: png.toString('base64'), pts: points, r });
}

// The route's colour (#a020f0, with antialiasing) at any pixel of the square.
function hasPurple(rgba) {
  for (let i = 0; i + 3 < rgba.length; i += 4) {
    const [r, g, b] = [rgba[i], rgba[i + 1], rgba[i + 2]];
    if (r >= 110 && r <= 210 && g <= 90 && b >= 170 && b - g >= 120) return true;
  }
  return false;
}

// Points to sample along the longest segment of the current route (viewport
// pixels, inside the map, away from the UAV and the tracks, whose symbols
// are drawn over the route or are purple themselves: the designated
// track's ring).
async function routeSamples(page) {
  return page.evaluate(() => {
    const st = window.cgs.state;
    const i = st.intercepts[0];
    if (!i || !Array.isArray(i.route) || i.route.length < 4) return null;
    const r = window.cgs.map.getTargetElement().getBoundingClientRect();
    const px = [];
    for (let k = 0; k + 1 < i.route.length; k += 2) px.push(window.cgs.pixelOf(i.route[k], i.route[k + 1]));
    const avoid = [];
    st.uavs.forEach((u) => avoid.push([window.cgs.pixelOf(u.e, u.n), 40]));
    st.tracks.forEach((t) => avoid.push([window.cgs.pixelOf(t.e, t.n), t.id === i.track_id ? 35 : 20]));
    let best = null;
    for (let k = 0; k + 1 < px.length; k++) {
      const len = Math.hypot(px[k + 1][0] - px[k][0], px[k + 1][1] - px[k][1]);
      if (!best || len > best.len) best = { a: px[k], b: px[k + 1], len };
    }
    const out = [];
    const count = Math.max(9, Math.min(30, Math.floor(best.len / 12)));
    for (let j = 0; j < count; j++) {
      const f = 0.1 + 0.8 * j / (count - 1);
      const p = [best.a[0] + f * (best.b[0] - best.a[0]), best.a[1] + f * (best.b[1] - best.a[1])];
      const inside = p[0] > r.left + 60 && p[0] < r.right - 20 && p[1] > r.top + 20 && p[1] < r.bottom - 40;
      if (inside && avoid.every(([q, d]) => Math.hypot(q[0] - p[0], q[1] - p[1]) > d)) out.push(p);
    }
    return { points: out, segment_px: Math.round(best.len), route_points: i.route.length / 2 };
  });
}

// How many of the sample points show the route's purple on screen now.
async function purpleCount(rec, step) {
  const s = await routeSamples(rec.page);
  if (!s || !s.points.length) return { s, n: 0, of: 0 };
  const png = step ? await screenshot(rec.page, step) : await rec.page.screenshot();
  const px = await pixelsAround(rec.page, png, s.points, 2);
  return { s, n: px.filter(hasPurple).length, of: s.points.length };
}

// The newest hit of a confirmed track of that identity (any, for null),
// while it is a current (yellow) hit and well inside the map on screen: the
// track farthest from the other confirmed tracks, at least 1.5 km from them
// and 3 km from the UAV. { id, last_hit, sep, px, seq } or null.
async function trackHit(page, identity) {
  return page.evaluate((identity) => {
    const st = window.cgs.state;
    const r = window.cgs.map.getTargetElement().getBoundingClientRect();
    const cur = [];
    st.hits.forEach((h) => { if (h.current) for (let k = 0; k + 1 < h.xy.length; k += 2) cur.push([h.xy[k], h.xy[k + 1]]); });
    let best = null;
    for (const t of st.tracks) {
      if (t.status !== 'confirmed' || (identity && t.identity !== identity) || !Array.isArray(t.last_hit)) continue;
      const [e, n] = t.last_hit;
      if (!cur.some((c) => Math.hypot(c[0] - e, c[1] - n) < 1)) continue;
      const px = window.cgs.pixelOf(e, n);
      if (!px || px[0] < r.left + 60 || px[0] > r.right - 30 || px[1] < r.top + 30 || px[1] > r.bottom - 50) continue;
      let sep = Infinity;
      for (const o of st.tracks) {
        if (o.id !== t.id && o.status !== 'tentative') sep = Math.min(sep, Math.hypot(o.e - t.e, o.n - t.n));
      }
      const uav = st.uavs[0];
      const fromUav = uav ? Math.hypot(uav.e - e, uav.n - n) : 0;
      if (sep > 1500 && fromUav > 3000 && (!best || sep > best.sep)) best = { id: t.id, last_hit: t.last_hit, hit_id: t.last_hit_id, sep, px, seq: st.seq };
    }
    return best;
  }, identity);
}

// The replies the page has received since it had n of them, of one op.
async function replyAfter(page, n, op, ms) {
  const h = await page.waitForFunction(({ n, op }) => window.cgs.stats.replies.slice(n).find((m) => m.op === op) || null,
    { n, op }, { timeout: ms, polling: 50 });
  return h.jsonValue();
}

const repliesNow = (page) => page.evaluate(() => window.cgs.stats.replies.length);
const text = (page, sel) => page.locator(sel).textContent();

// One command through a raw WebSocket opened from the page (same origin),
// as a page could send it whatever its controls show: its hello and reply.
async function rawCommand(page, query, msg) {
  return page.evaluate(({ query, msg }) => new Promise((resolve) => {
    const ws = new WebSocket('ws://' + location.host + '/ws' + query);
    const got = { hello: null, reply: null };
    const timer = setTimeout(() => { ws.close(); resolve(got); }, 8000);
    ws.onmessage = (ev) => {
      const m = JSON.parse(ev.data);
      if (m.type === 'hello') {
        got.hello = m;
        if (msg) ws.send(JSON.stringify(msg));
        else { clearTimeout(timer); ws.close(); resolve(got); }
      } else if (m.type === 'reply' && msg && m.req === msg.req) {
        got.reply = m;
        clearTimeout(timer);
        ws.close();
        resolve(got);
      }
    };
  }), { query, msg });
}

// ---- the live video ----------------------------------------------------------------------

// Run in the measured page before its scripts: each /video message's
// arrival (epoch ms) and the PTS of the video frame it starts (PID 0x100,
// 90 kHz), and each video sample mpegts.js hands to Media Source
// Extensions, in order, with its presentation time on the media timeline
// (ms). One frame per message and one sample per frame, in the same order,
// so the k-th sample is the k-th message's frame.
function videoProbe() {
  const rec = window.__videoProbe = { sessions: [], shown: [] };
  const now = () => performance.timeOrigin + performance.now();
  function ptsOf(b) {
    for (let i = 0; i + 188 <= b.length; i += 188) {
      if (b[i] !== 0x47 || !(b[i + 1] & 0x40) || (((b[i + 1] & 0x1f) << 8) | b[i + 2]) !== 0x100) continue;
      const afc = (b[i + 3] >> 4) & 3;
      if (afc === 2) continue;
      let p = i + 4;
      if (afc === 3) p += 1 + b[p];
      if (b[p] !== 0 || b[p + 1] !== 0 || b[p + 2] !== 1 || !(b[p + 7] & 0x80)) continue;
      const q = p + 9;
      return ((b[q] >> 1) & 7) * 1073741824 + b[q + 1] * 4194304 + (b[q + 2] >> 1) * 32768 + b[q + 3] * 128 + (b[q + 4] >> 1);
    }
    return null;
  }
  const WS = window.WebSocket;
  function Probed(url, protocols) {
    const ws = protocols === undefined ? new WS(url) : new WS(url, protocols);
    if (/\/video$/.test(String(url))) {
      const s = { arrivals: [], samples: [] };
      rec.sessions.push(s);
      ws.addEventListener('message', (ev) => {
        if (!(ev.data instanceof ArrayBuffer)) return;
        const pts = ptsOf(new Uint8Array(ev.data));
        if (pts !== null) s.arrivals.push({ t: now(), pts });
      });
    }
    return ws;
  }
  Probed.prototype = WS.prototype;
  Object.assign(Probed, { CONNECTING: 0, OPEN: 1, CLOSING: 2, CLOSED: 3 });
  window.WebSocket = Probed;
  const u32 = (b, o) => b[o] * 16777216 + (b[o + 1] << 16) + (b[o + 2] << 8) + b[o + 3];
  function boxes(b, start, end, fn) {
    for (let o = start; o + 8 <= end;) {
      const size = u32(b, o);
      if (size < 8 || o + size > end) return;
      fn(String.fromCharCode(b[o + 4], b[o + 5], b[o + 6], b[o + 7]), o + 8, o + size);
      o += size;
    }
  }
  function samples(b) {
    const s = rec.sessions[rec.sessions.length - 1];
    if (!s) return;
    boxes(b, 0, b.length, (type, o, e) => type === 'moof' && boxes(b, o, e, (t2, o2, e2) => {
      if (t2 !== 'traf') return;
      let dts = null;
      boxes(b, o2, e2, (t3, o3) => {
        if (t3 === 'tfdt') dts = b[o3] === 1 ? u32(b, o3 + 4) * 4294967296 + u32(b, o3 + 8) : u32(b, o3 + 4);
        if (t3 !== 'trun' || dts === null) return;
        const flags = (b[o3 + 1] << 16) | (b[o3 + 2] << 8) | b[o3 + 3];
        let p = o3 + 8 + (flags & 1 ? 4 : 0) + (flags & 4 ? 4 : 0);
        for (let k = 0, n = u32(b, o3 + 4); k < n; k++) {
          let dur = 0;
          let cts = 0;
          if (flags & 0x100) { dur = u32(b, p); p += 4; }
          if (flags & 0x200) p += 4;
          if (flags & 0x400) p += 4;
          if (flags & 0x800) { cts = u32(b, p) | 0; p += 4; }
          s.samples.push({ pts: dts + cts, t: now() });
          dts += dur;
        }
      });
    }));
  }
  const append = SourceBuffer.prototype.appendBuffer;
  SourceBuffer.prototype.appendBuffer = function (data) {
    try {
      samples(data instanceof ArrayBuffer ? new Uint8Array(data) : new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    } catch (err) { /* measuring only */ }
    return append.call(this, data);
  };
}

// A page without Media Source Extensions (as a browser without them is).
function withoutMse() {
  delete window.MediaSource;
  delete window.ManagedMediaSource;
  delete window.WebKitMediaSource;
}

// A page whose /video fails (the WebSocket goes to a path nobody serves).
function brokenVideo() {
  const WS = window.WebSocket;
  function Broken(url, protocols) {
    const u = String(url).replace(/\/video$/, '/no-such-video');
    return protocols === undefined ? new WS(u) : new WS(u, protocols);
  }
  Broken.prototype = WS.prototype;
  Object.assign(Broken, { CONNECTING: 0, OPEN: 1, CLOSING: 2, CLOSED: 3 });
  window.WebSocket = Broken;
}

// stationd's (the open one's) health counters, from `mscgs status`.
async function stationCounters() {
  const out = await new Promise((resolve) => {
    execFile(opt.mscgs, ['status', '--exercise', opt.exercise], { timeout: 10000 }, (err, stdout) => resolve(String(stdout || '')));
  });
  const lines = out.split('\n');
  const at = lines.findIndex((l) => /^stationd\s/.test(l));
  const c = {};
  for (let i = at + 1; at >= 0 && i < lines.length && /^\s/.test(lines[i]); i++) {
    for (const m of lines[i].matchAll(/([a-z_]+)=(\d+)/g)) c[m[1]] = Number(m[2]);
  }
  return c;
}

const quantile = (xs, q) => {
  const a = xs.slice().sort((x, y) => x - y);
  return a.length ? a[Math.min(a.length - 1, Math.floor(q * a.length))] : NaN;
};

// The PTS (90 kHz) of the video frame a transport stream starts, in node.
function tsPts(b) {
  for (let i = 0; i + 188 <= b.length; i += 188) {
    if (b[i] !== 0x47 || !(b[i + 1] & 0x40) || (((b[i + 1] & 0x1f) << 8) | b[i + 2]) !== 0x100) continue;
    const afc = (b[i + 3] >> 4) & 3;
    if (afc === 2) continue;
    let p = i + 4;
    if (afc === 3) p += 1 + b[p];
    if (b[p] !== 0 || b[p + 1] !== 0 || b[p + 2] !== 1 || !(b[p + 7] & 0x80)) continue;
    const q = p + 9;
    return ((b[q] >> 1) & 7) * 1073741824 + b[q + 1] * 4194304 + (b[q + 2] >> 1) * 32768 + b[q + 3] * 128 + (b[q + 4] >> 1);
  }
  return null;
}

// `mscgs echo video` for ms: each frame's header wall time (s) by its PTS.
function echoVideo(ms) {
  return new Promise((resolve) => {
    const child = spawn(opt.mscgs, ['echo', 'video', '--json', '--count', '1000', '--timeout', String(Math.ceil(ms / 1000) + 5),
      '--exercise', opt.exercise], { stdio: ['ignore', 'pipe', 'ignore'] });
    const wall = new Map();
    let buf = '';
    child.stdout.on('data', (d) => {
      buf += d.toString();
      let nl;
      while ((nl = buf.indexOf('\n')) >= 0) {
        const line = buf.slice(0, nl);
        buf = buf.slice(nl + 1);
        try {
          const m = JSON.parse(line);
          const pts = tsPts(Buffer.from(m.ts, 'base64'));
          if (pts !== null) wall.set(pts, m.header.wall_time_s);
        } catch (err) { /* not a message line */ }
      }
    });
    const timer = setTimeout(() => child.kill('SIGTERM'), ms);
    child.on('exit', () => { clearTimeout(timer); resolve(wall); });
  });
}

// A /video client that never reads after its handshake (a page that stopped).
function stalledClient(url) {
  const u = new URL(url);
  const sock = net.connect(Number(u.port), u.hostname, () => {
    sock.write('GET /video HTTP/1.1\r\nHost: ' + u.host + '\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n' +
      'Sec-WebSocket-Key: ' + crypto.randomBytes(16).toString('base64') + '\r\nSec-WebSocket-Version: 13\r\n\r\n');
    sock.pause();
  });
  sock.on('error', () => { /* stationd closes it in the end */ });
  return sock;
}

// A /video client for ms: its messages (at most 20 kept) and how it ended.
function videoClient(url, origin, ms) {
  return new Promise((resolve) => {
    const ws = new WebSocket(url.replace(/^http/, 'ws') + 'video', origin ? { origin } : {});
    const got = { opened: false, status: null, messages: [], count: 0, binary: true };
    const done = () => { try { ws.terminate(); } catch (err) { /* closed */ } resolve(got); };
    ws.on('open', () => { got.opened = true; });
    ws.on('message', (d, isBinary) => {
      got.count += 1;
      got.binary = got.binary && isBinary;
      if (got.messages.length < 20) got.messages.push(Buffer.from(d));
    });
    ws.on('unexpected-response', (req, res) => { got.status = res.statusCode; done(); });
    ws.on('error', (e) => { got.error = e.message; done(); });
    setTimeout(done, ms);
  });
}

// The corners of a footprint as [[e, n] × 4] from a flat array.
const cornersOf = (flat) => [0, 1, 2, 3].map((k) => [flat[2 * k], flat[2 * k + 1]]);

async function videoSteps(browser, main) {
  const p = main.page;
  const codec = await p.evaluate(() => ({
    h264High: typeof MediaSource !== 'undefined' && MediaSource.isTypeSupported('video/mp4; codecs="avc1.64001f"'),
    h264Base: typeof MediaSource !== 'undefined' && MediaSource.isTypeSupported('video/mp4; codecs="avc1.42E01E"'),
    mseLive: !!(window.mpegts && window.mpegts.getFeatureList().mseLivePlayback),
    ua: navigator.userAgent,
  }));
  diag('Chromium ' + browser.version() + ': MediaSource.isTypeSupported(avc1.64001f, H.264 High) ' + codec.h264High +
    ', (avc1.42E01E, Baseline) ' + codec.h264Base + '; mpegts.js mseLivePlayback ' + codec.mseLive);
  const canPlay = codec.h264High && codec.mseLive;

  // The pages whose fallback is checked load meanwhile.
  const noMse = openPage(browser, opt.url, 'no-MSE', withoutMse);
  const broken = openPage(browser, opt.url, 'broken-video', brokenVideo);

  if (!canPlay) {
    diag('LIVE PLAYBACK NOT VERIFIED: this Chromium cannot play H.264 through Media Source Extensions; only the fallback is checked');
    const fb = await poll(() => p.evaluate(() => {
      const i = document.getElementById('sensor-image');
      const s = document.getElementById('video-status').textContent;
      return window.cgs.video.status === 'still' && !i.hidden && /^still picture/.test(s) ? s : null;
    }), 15000);
    check(fb, 'this Chromium cannot play the video: the panel shows the latest picture and says so (' + fb + ')');
  }

  // The instrumented page.
  const vid = canPlay ? await openPage(browser, opt.url, 'video', videoProbe) : null;
  if (vid) {
    const v = vid.page;
    let liveAt = null;
    try {
      await waitReady(v, 30000);
      const h = await v.waitForFunction(() => window.cgs.video && window.cgs.video.status === 'live' ? {
        w: document.getElementById('sensor-video').videoWidth, h: document.getElementById('sensor-video').videoHeight,
        text: document.getElementById('video-status').textContent,
      } : null, null, { timeout: 40000, polling: 100 });
      liveAt = await h.jsonValue();
    } catch (err) { /* stays null */ }
    check(liveAt, 'the imaging-sensor panel plays the live video (' + (liveAt ? liveAt.text : await text(v, '#video-status')) + ')');
    check(liveAt && liveAt.w === 320 && liveAt.h === 240, 'the video is imagerd\'s 320x240 (' + (liveAt ? liveAt.w + 'x' + liveAt.h : 'none') + ')');
    const shown = await v.evaluate(() => ({
      video: !document.getElementById('sensor-video').hidden,
      image: !document.getElementById('sensor-image').hidden,
      text: document.getElementById('video-status').textContent,
    }));
    check(shown.video && !shown.image && /^live video · uav 1 · 320×240/.test(shown.text), 'it shows in place of the picture, and the panel says live video (' + shown.text + ')', shown);
    const t0 = await v.evaluate(() => ({ t: document.getElementById('sensor-video').currentTime, rate: document.getElementById('sensor-video').playbackRate, scale: window.cgs.state.time_scale }));
    await sleep(1000);
    const t1 = await v.evaluate(() => document.getElementById('sensor-video').currentTime);
    check(t1 - t0.t > 4, 'its time moves on: ' + t0.t.toFixed(2) + ' s to ' + t1.toFixed(2) + ' s of simulation time in 1 s');
    check(t0.rate === t0.scale && t0.scale === 10, 'at the exercise\'s time scale (playbackRate ' + t0.rate + ', time scale ' + t0.scale + ')');

    // The KLV footprint.
    const klv = await poll(() => v.evaluate(() => {
      const k = window.cgs.video.klv;
      const layer = window.cgs.map.getAllLayers().find((l) => l.get('name') === 'sensor-footprint');
      const polys = layer ? layer.getSource().getFeatures().filter((f) => f.getGeometry() && f.getGeometry().getType() === 'Polygon').length : 0;
      return k.packets >= 5 && k.footprint && k.drawn > 0 ? { packets: k.packets, bad: k.bad, form: k.form, drawn: k.drawn, polys,
        track: k.last.target_id || null, version: k.last.ls_version, error: k.lastError } : null;
    }), 15000);
    check(klv && klv.bad === 0, 'the KLV packets are read, checksums good (' + (klv ? klv.packets + ' read, ' + klv.bad + ' refused, LS version ' + klv.version : 'none') + ')', klv);
    check(klv && klv.polys === 2, 'the KLV footprint (' + (klv ? klv.form : '-') + ' corners) is drawn on the map beside the image message\'s (' + (klv ? klv.polys : 0) + ' polygons)');
    await screenshot(v, 'live-video');

    // Glass to glass, with a page that stopped reading meanwhile.
    await v.evaluate(() => {
      const el = document.getElementById('sensor-video');
      const probe = window.__videoProbe;
      probe.shown = [];
      probe.waiting = 0;
      el.addEventListener('waiting', () => { probe.waiting += 1; });
      const cb = (now, md) => {
        probe.shown.push({ media: md.mediaTime, t: performance.timeOrigin + md.expectedDisplayTime });
        if (probe.shown.length < 5000) el.requestVideoFrameCallback(cb);
      };
      el.requestVideoFrameCallback(cb);
    });
    const counted0 = stationCounters();
    const stalled = stalledClient(opt.url);
    const mainT0 = await p.evaluate(() => document.getElementById('sensor-video').currentTime);
    const echoed = echoVideo(6500);
    const before = await counted0;
    await sleep(1000); // measured from when the echo hears the bus
    await v.evaluate(() => { window.__videoProbe.shown = []; window.__videoProbe.waiting = 0; });
    const wall = await echoed;
    const probe = await v.evaluate(() => window.__videoProbe);
    const mainT1 = await p.evaluate(() => document.getElementById('sensor-video').currentTime);
    const session = probe.sessions[probe.sessions.length - 1];
    const glass = [];
    const page = [];
    const bus = [];
    let unmatched = 0;
    for (const f of probe.shown) {
      const k = session.samples.findIndex((x) => Math.abs(x.pts - f.media * 1000) < 0.5);
      const a = k >= 0 ? session.arrivals[k] : null;
      const w = a ? wall.get(a.pts) : undefined;
      if (!a || w === undefined) { unmatched += 1; continue; }
      glass.push(f.t - w * 1000);
      page.push(f.t - a.t);
      bus.push(a.t - w * 1000);
    }
    const fmt = (xs) => 'median ' + quantile(xs, 0.5).toFixed(0) + ' ms, p95 ' + quantile(xs, 0.95).toFixed(0) + ' ms';
    const from = probe.shown.length ? probe.shown[0].t : Infinity;
    const came = session.arrivals.filter((a) => a.t >= from - 500).length;
    diag('glass to glass (a frame\'s header wall_time_s on the bus to the video\'s expected display time of that frame, ' +
      'requestVideoFrameCallback; frames matched by PTS through the fMP4 samples mpegts.js appends): ' + glass.length +
      ' frames, ' + fmt(glass) + ' (' + unmatched + ' shown frames unmatched, ' + came + ' frames came meanwhile, ' + probe.waiting + ' waiting events)');
    diag('  of which bus to page (the WebSocket message\'s arrival): ' + fmt(bus) + '; arrival to display: ' + fmt(page));
    check(glass.length >= 15 && quantile(glass, 0.5) < 1500, 'glass-to-glass measured on ' + glass.length + ' frames: ' + fmt(glass));
    // The page that stopped reading: behind, dropped to the next keyframe,
    // counted; the other pages played on.
    const counted = await poll(async () => {
      const c = await stationCounters();
      return c.video_dropped > (before.video_dropped || 0) && c.video_behind > (before.video_behind || 0) ? c : null;
    }, 20000, 500);
    stalled.destroy();
    const after = counted || await stationCounters();
    diag('stationd video counters: ' + ['video_pages', 'video_pages_total', 'video_frames', 'video_sent', 'video_bytes', 'video_dropped', 'video_behind', 'video_restarts', 'write_errors']
      .map((k) => k + '=' + after[k]).join(' '));
    check(counted, 'a video page that stops reading is dropped to the next keyframe, counted (video_dropped ' +
      (before.video_dropped || 0) + ' to ' + after.video_dropped + ', video_behind ' + (before.video_behind || 0) + ' to ' + after.video_behind + ')');
    check(mainT1 - mainT0 > 40, 'while the other pages play on (the first page\'s video: ' + (mainT1 - mainT0).toFixed(1) + ' s of simulation time in 6.5 s)');

    // A fresh client starts at a keyframe: its first message has the PAT
    // and the PMT (after libavformat's SDT) before the video's first packet
    // and its IDR picture; every message is whole 188-byte packets.
    const fresh = await videoClient(opt.url, null, 1500);
    const pidsOf = (m) => [...Array(Math.floor(m.length / 188)).keys()].map((i) => ((m[i * 188 + 1] & 0x1f) << 8) | m[i * 188 + 2]);
    const first = fresh.messages.length ? pidsOf(fresh.messages[0]) : [];
    const firstVideo = first.indexOf(0x100);
    const idr = fresh.messages.length && /00000165|000165/.test(fresh.messages[0].toString('hex'));
    const whole = fresh.messages.every((m) => m.length % 188 === 0 && m.length > 0 && [...Array(m.length / 188).keys()].every((i) => m[i * 188] === 0x47));
    check(fresh.opened && fresh.count > 3 && fresh.binary && whole && firstVideo > 0 && first.slice(0, firstVideo).includes(0) &&
      first.slice(0, firstVideo).includes(0x1000) && idr,
    'a new /video client gets binary messages of whole 188-byte packets, the first a keyframe\'s (' + fresh.count + ' messages; the first\'s PIDs ' +
      first.slice(0, 4).map((x) => '0x' + x.toString(16)).join(' ') + ' ..., an IDR picture: ' + !!idr + ')');
    // (On the token stationd, where a refusal is expected: the open one's log stays clean.)
    const foreign = await videoClient(opt['token-url'], 'http://attacker.example', 3000);
    check(!foreign.opened && foreign.count === 0, 'a /video WebSocket with a foreign Origin is refused (' + (foreign.status ? 'HTTP ' + foreign.status : foreign.error || 'no answer') + ')');

    // The KLV footprint is the image message's, frame for frame: with the
    // exercise paused, the last frame's of both.
    execFileSync(opt.mscgs, ['pause', '--exercise', opt.exercise], { timeout: 15000 });
    await poll(() => v.evaluate(() => window.cgs.state.paused === true), 10000);
    await sleep(1000); // the last frame's KLV drawn (at most 250 ms later), its image message pushed
    const both = await v.evaluate(() => ({ klv: window.cgs.video.klv.footprint, form: window.cgs.video.klv.form, image: window.cgs.state.image && window.cgs.state.image.footprint }));
    let agree = null;
    if (both.klv && both.image) {
      // KLV corners: upper left, upper right, lower right, lower left (far
      // edge first); the image message's: clockwise from near left.
      const k = cornersOf(both.klv);
      const im = cornersOf(both.image);
      const d = k.map((c, i) => Math.hypot(c[0] - im[(i + 1) % 4][0], c[1] - im[(i + 1) % 4][1]));
      const width = (Math.hypot(im[1][0] - im[2][0], im[1][1] - im[2][1]) + Math.hypot(im[0][0] - im[3][0], im[0][1] - im[3][1])) / 2;
      agree = { worst_m: Math.max(...d), width_m: width, corners_m: d.map((x) => +x.toFixed(2)) };
    }
    diag('paused: KLV footprint (' + both.form + ') ' + JSON.stringify(both.klv && both.klv.map((x) => Math.round(x))) + ', image footprint ' + JSON.stringify(both.image));
    check(agree && agree.worst_m <= 0.01 * agree.width_m, 'the KLV footprint\'s corners are the image message\'s to within 1% of its width (worst ' +
      (agree ? agree.worst_m.toFixed(2) + ' m of ' + agree.width_m.toFixed(0) + ' m; corners ' + agree.corners_m.join(', ') : 'none') + ')');
    await v.evaluate(() => {
      const k = window.cgs.video.klv.footprint;
      if (!k) return;
      const xs = [k[0], k[2], k[4], k[6]];
      const ys = [k[1], k[3], k[5], k[7]];
      window.cgs.map.getView().fit([Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)], { padding: [150, 150, 150, 150] });
      window.cgs.map.renderSync();
    });
    await screenshot(v, 'klv-footprint');
    execFileSync(opt.mscgs, ['resume', '--exercise', opt.exercise], { timeout: 15000 });
    await vid.context.close();
  }

  // The fallback: without MSE, and with a /video that fails.
  const still = async (rec, want) => poll(() => rec.page.evaluate((want) => {
    const i = document.getElementById('sensor-image');
    const s = document.getElementById('video-status').textContent;
    return window.cgs.video && window.cgs.video.status === 'still' && !i.hidden && document.getElementById('sensor-video').hidden &&
      i.complete && i.naturalWidth > 0 && new RegExp(want).test(s) ? s : null;
  }, want), 20000);
  const nm = await noMse;
  const nmSaid = await still(nm, '^still picture \\(latest\\.png\\): this browser cannot play the live video');
  check(nmSaid, 'without Media Source Extensions the panel shows the latest picture and says why (' + nmSaid + ')');
  await screenshot(nm.page, 'video-fallback');
  const br = await broken;
  const brSaid = await still(br, '^still picture \\(latest\\.png\\): live video failed');
  check(brSaid, 'when the live video fails the panel shows the latest picture and says so (' + brSaid + ')');
  await nm.context.close();
  await br.context.close();
  // That page's only errors are the failed WebSocket's and the player's:
  // filtered once the page is closed, so that none reported meanwhile slips past.
  br.errors = br.errors.filter((e) => !/no-such-video|WebSocket|mpegts|IOController|WebSocketLoader|TransmuxingController|MSEPlayer|PlayerEngine/i.test(e));
}

// ---- the imaging sensor's mode and the camera --------------------------------------------

// The first UAV's live sensor mode and camera, and what the panel says.
async function sensorView(page) {
  return page.evaluate(() => {
    const u = window.cgs.state.uavs[0] || {};
    const checked = ['sensor-eo', 'sensor-flir', 'sensor-sar'].find((id) => document.getElementById(id).checked) || null;
    return {
      mode: u.sensor_mode || null, camera: u.camera || null, image_mode: window.cgs.state.image ? window.cgs.state.image.mode : null,
      status: document.getElementById('status-sensor').textContent, checked,
      camera_text: document.getElementById('camera-state').textContent,
    };
  });
}

// Click a mode in the Sensors menu; the reply.
async function clickMode(p, id) {
  const n0 = await repliesNow(p);
  await p.check(id);
  return replyAfter(p, n0, 'sensor_mode', 10000).catch(() => null);
}

// Wait until the live mode is want and the status says it (and says
// nothing pending); the last view either way.
async function modeLive(p, want, ms) {
  let last = null;
  await poll(async () => {
    last = await sensorView(p);
    return last.mode === want && last.status === MODE_LABELS[want];
  }, ms, 200);
  return last;
}

// One camera command from the panel: fn does the clicking; the reply.
async function cameraCommand(p, fn) {
  const n0 = await repliesNow(p);
  await fn();
  return replyAfter(p, n0, 'camera', 10000).catch(() => null);
}

// The first UAV's camera (the `uav` state's) once test(camera) holds, or null.
async function cameraState(p, test, ms) {
  return poll(async () => {
    const c = await p.evaluate(() => (window.cgs.state.uavs[0] || {}).camera || null);
    return c && test(c) ? c : null;
  }, ms, 100);
}

async function sensorSteps(browser, main) {
  const p = main.page;
  await p.evaluate(() => { document.querySelectorAll('details').forEach((d) => { d.open = true; }); });
  // What the page sends, from now on.
  await p.evaluate(() => { window.cgsSent = []; });
  const sentOf = (op) => p.evaluate((op) => window.cgsSent.filter((m) => m.op === op), op);

  // The live mode, from the `image` messages: visible at first.
  const first = await modeLive(p, 'visible', 20000);
  check(first.mode === 'visible' && first.status === 'Visible (EO)' && first.checked === 'sensor-eo',
    'the status says the visible camera is live, and the Sensors menu has Visible (EO) chosen', first);

  // FLIR, then SAR, from the menu; the status follows the frames.
  const flir = await clickMode(p, '#sensor-flir');
  check(flir && flir.ok === true && /^imagerd/.test(flir.server || ''), 'choosing FLIR is accepted by imagerd (' + (await text(p, '#result')) + ')', flir);
  const toFlir = await modeLive(p, 'infrared', 20000);
  check(toFlir.mode === 'infrared' && toFlir.status === 'FLIR (infrared)' && toFlir.checked === 'sensor-flir',
    'the status says FLIR is live once its frames say so (' + toFlir.status + ')', toFlir);
  await p.locator('#status-sensor').scrollIntoViewIfNeeded();
  await screenshot(p, 'sensor-flir');
  const sar = await clickMode(p, '#sensor-sar');
  check(sar && sar.ok === true, 'choosing SAR is accepted by imagerd (' + (await text(p, '#result')) + ')', sar);
  const toSar = await modeLive(p, 'sar', 30000);
  check(toSar.mode === 'sar' && toSar.status === 'SAR' && toSar.checked === 'sensor-sar',
    'the status says SAR is live once its frames say so (' + toSar.status + ')', toSar);
  const imgSar = await poll(() => p.evaluate(() => window.cgs.state.image && window.cgs.state.image.mode === 'sar' &&
    /· sar ·/.test(document.getElementById('image-caption').textContent)), 20000);
  check(imgSar, 'and the sensor image is a SAR one (' + (await text(p, '#image-caption')) + ')');
  await screenshot(p, 'sensor-sar');
  const modesSent = await sentOf('sensor_mode');
  check(modesSent.length === 2 && modesSent.every((m) => m.uav_id === 1) && modesSent.map((m) => m.mode).join() === 'infrared,sar',
    'the page sent sensor_mode infrared, then sar, for UAV 1', modesSent);
  // Switched elsewhere (mscgs sensor): the page follows the frames, not its
  // clicks. (imagerd busy making SAR chips may be slow to answer: tried again.)
  let back = null;
  for (let attempt = 1; attempt <= 4 && !(back && back.mode === 'visible'); attempt++) {
    const t0 = Date.now();
    const said = await new Promise((resolve) => execFile(opt.mscgs, ['sensor', 'visible', '--exercise', opt.exercise],
      { timeout: 20000 }, (err, stdout, stderr) => resolve((err ? 'failed: ' : '') + String(stdout || '') + String(stderr || ''))));
    diag('mscgs sensor visible (try ' + attempt + ', ' + ((Date.now() - t0) / 1000).toFixed(1) + ' s): ' + said.trim());
    back = await modeLive(p, 'visible', 10000);
  }
  check(back.mode === 'visible' && back.status === 'Visible (EO)' && back.checked === 'sensor-eo',
    'switched back by `mscgs sensor visible`, the status and the menu follow the frames (' + back.status + ')', back);
  // A mode the server does not know is refused with the reason.
  const badMode = await rawCommand(p, '', { op: 'sensor_mode', req: 921, uav_id: 1, mode: 'x-ray' });
  check(badMode.reply && badMode.reply.ok === false && /sensor_mode needs the mode/.test(badMode.reply.error || ''),
    'stationd refuses an unknown sensor mode, saying why', badMode.reply);

  // The camera's depression: set from the panel, seen on `uav`.
  const cam0 = await cameraState(p, (c) => typeof c.depression_deg === 'number', 5000);
  diag('camera at first: ' + JSON.stringify(cam0) + '; panel: ' + (await text(p, '#camera-state')));
  check(cam0 && (await p.inputValue('#cam-depression')) === String(Math.round(cam0.depression_deg * 10) / 10),
    'the camera panel is filled from the UAV\'s camera (' + (await p.inputValue('#cam-depression')) + '° down)');
  const dep = await cameraCommand(p, async () => {
    await p.fill('#cam-depression', '30');
    await p.click('#cam-depression-set');
  });
  check(dep && dep.ok === true && dep.server === 'uavsim', 'a depression of 30° is accepted by uavsim (' + (await text(p, '#result')) + ')', dep);
  const dep30 = await cameraState(p, (c) => c.depression_deg === 30, 10000);
  check(dep30, 'and the uav state\'s depression becomes 30°');
  check(/^30° down/.test(await text(p, '#camera-state')), 'the panel says so (' + (await text(p, '#camera-state')) + ')');
  // Out of the page's range: refused by the page, nothing sent; out of the
  // scenario's: refused by uavsim, with its reason.
  let n0 = await repliesNow(p);
  const sent0 = (await sentOf('camera')).length;
  await p.fill('#cam-depression', '120');
  await p.click('#cam-depression-set');
  await sleep(300);
  const wide = await text(p, '#result');
  check(/^camera: the depression must be/.test(wide) && (await repliesNow(p)) === n0 && (await sentOf('camera')).length === sent0,
    'a depression of 120° is refused by the page, which sends nothing (' + wide + ')');
  const low = await cameraCommand(p, async () => {
    await p.fill('#cam-depression', '1');
    await p.click('#cam-depression-set');
  });
  const lowText = await text(p, '#result');
  check(low && low.ok === false && /^refused: /.test(lowText) && (await p.getAttribute('#result', 'class')).includes('err'),
    'a depression of 1° (under the scenario\'s least) is refused by uavsim, and #result shows why (' + lowText + ')', low);
  // Zoom.
  const fov = await cameraCommand(p, async () => {
    await p.fill('#cam-fov', '5');
    await p.click('#cam-fov-set');
  });
  const fov5 = await cameraState(p, (c) => c.hfov_deg === 5, 10000);
  check(fov && fov.ok === true && fov5 && Math.abs(fov5.vfov_deg - 3.75) < 0.01,
    'a field of view of 5° is accepted, and the uav state\'s becomes 5° × ' + (fov5 ? fov5.vfov_deg : '?') + '° (the aspect kept)', fov);
  // Stabilized, on and off.
  const stabOn = await cameraCommand(p, () => p.check('#cam-stabilized'));
  const on = await cameraState(p, (c) => c.stabilized === true, 10000);
  check(stabOn && stabOn.ok === true && on && (await p.isChecked('#cam-stabilized')), 'ticking Stabilized makes the camera stabilized', stabOn);
  const stabOff = await cameraCommand(p, () => p.uncheck('#cam-stabilized'));
  const off = await cameraState(p, (c) => c.stabilized === false, 10000);
  check(stabOff && stabOff.ok === true && off && !(await p.isChecked('#cam-stabilized')), 'unticking it makes it not stabilized', stabOff);
  const camSent = await sentOf('camera');
  check(camSent.length === 5 && camSent.every((m) => m.uav_id === 1 && Object.keys(m).length === 4) &&
    camSent[0].depression === 30 && camSent[2].fov === 5 && camSent[3].stabilized === true && camSent[4].stabilized === false,
  'each camera command carries only the field set', camSent);

  // Stare at a clicked point: the orbit's centre, which the gimbal reaches
  // from anywhere on the orbit.
  const u = await p.evaluate(() => window.cgs.state.uavs[0]);
  const aim = u.loiter ? [u.loiter.e + 100, u.loiter.n + 100] : [100, 100];
  const px = await p.evaluate((a) => window.cgs.pixelOf(a[0], a[1]), aim);
  await p.click('#stare-point');
  const armed = await p.getAttribute('#stare-point', 'aria-pressed');
  const stare = await cameraCommand(p, () => p.mouse.click(px[0], px[1]));
  const clicked = await p.evaluate((q) => {
    const r = window.cgs.map.getTargetElement().getBoundingClientRect();
    return window.cgs.map.getCoordinateFromPixel([q[0] - r.left, q[1] - r.top]);
  }, px);
  const staring = await cameraState(p, (c) => c.stare === 'point' && c.staring === true, 15000);
  const sentStare = (await sentOf('camera')).pop();
  diag('stare: clicked ' + clicked.map((x) => x.toFixed(1)).join(', ') + '; sent ' + JSON.stringify(sentStare) + '; camera ' + JSON.stringify(staring));
  check(armed === 'true' && stare && stare.ok === true && (await p.getAttribute('#stare-point', 'aria-pressed')) === 'false',
    '"At point…" then a click on the map sends the stare point, accepted (' + (stare ? stare.detail || stare.error : 'no reply') + ')', stare);
  check(sentStare && sentStare.stare && Math.abs(sentStare.stare.e - clicked[0]) < 0.2 && Math.abs(sentStare.stare.n - clicked[1]) < 0.2,
    'the point sent is the clicked one (' + JSON.stringify(sentStare && sentStare.stare) + ')');
  check(staring && staring.at_gimbal_limit === false && Math.hypot(staring.stare_point[0] - clicked[0], staring.stare_point[1] - clicked[1]) < 1,
    'the uav state says the camera is staring at that point', staring);
  const marker = await poll(() => p.evaluate((pt) => {
    const l = window.cgs.map.getAllLayers().find((x) => x.get('name') === 'uav');
    return l.getSource().getFeatures().some((f) => f.getGeometry() && f.getGeometry().getType() === 'Point' &&
      Math.hypot(f.getGeometry().getCoordinates()[0] - pt[0], f.getGeometry().getCoordinates()[1] - pt[1]) < 1);
  }, staring ? staring.stare_point : [NaN, NaN]), 5000);
  const stareText = await text(p, '#camera-state');
  check(marker && /staring at E -?\d+ N -?\d+/.test(stareText), 'the map marks the stare point and the panel says staring (' + stareText + ')');
  await screenshot(p, 'camera-staring');
  // The designation is untouched by that click (it was not a designation).
  check((await sentOf('designate')).length === 0, 'the stare click designated nothing');
  const tgt = await cameraCommand(p, () => p.click('#stare-target'));
  const onTarget = await cameraState(p, (c) => c.stare === 'target', 10000);
  check(tgt && tgt.ok === true && onTarget && (await p.getAttribute('#stare-target', 'class')).includes('on'),
    'On target is accepted and shown (' + (await text(p, '#camera-state')) + ')', tgt);
  const stareOff = await cameraCommand(p, () => p.click('#stare-off'));
  const notStaring = await cameraState(p, (c) => c.stare === 'off' && c.staring === false, 10000);
  check(stareOff && stareOff.ok === true && notStaring, 'Off stops staring', stareOff);
  // Malformed camera commands are refused by stationd, with the reason.
  const bad = await rawCommand(p, '', { op: 'camera', req: 922, uav_id: 1, depression: '30' });
  const none = await rawCommand(p, '', { op: 'camera', req: 923, uav_id: 1 });
  check(bad.reply && bad.reply.ok === false && /camera: depression must be/.test(bad.reply.error || '') &&
    none.reply && none.reply.ok === false && /camera needs at least one of/.test(none.reply.error || ''),
  'stationd refuses malformed camera commands, saying why', [bad.reply, none.reply]);

  // A page without the token: the sensor and camera controls are disabled,
  // and "At point…" cannot be armed.
  const viewer = await openPage(browser, opt['token-url'], 'sensor-viewer');
  let ready = true;
  try {
    await waitReady(viewer.page, 20000);
  } catch (err) {
    ready = false;
  }
  const v = viewer.page;
  const sensorControls = OPERATOR_CONTROLS.slice(7);
  const dis = ready ? await Promise.all(sensorControls.map((sel) => v.isDisabled(sel))) : [];
  check(ready && dis.length && dis.every(Boolean), 'on a page without the token the sensor-mode and camera controls are disabled',
    sensorControls.filter((sel, k) => !dis[k]));
  const vStatus = ready ? await modeLive(v, 'visible', 10000) : null;
  check(vStatus && vStatus.status === 'Visible (EO)', 'while it shows the live mode all the same (' + (vStatus && vStatus.status) + ')');
  await screenshot(v, 'sensor-viewer');
  await viewer.context.close();
}

// ---- the steps ---------------------------------------------------------------------------

async function main() {
  const t0 = Date.now();
  const browser = await chromium.launch({ executablePath: opt.chromium, headless: true, args: CHROMIUM_ARGS });
  try {
    await steps(browser);
  } finally {
    await browser.close();
    diag('browser part took ' + ((Date.now() - t0) / 1000).toFixed(1) + ' s');
  }
}

async function steps(browser) {
  // 1. The page loads.
  const main = await openPage(browser, opt.url, 'main');
  const p = main.page;
  let ready = true;
  try {
    await waitReady(p, 30000);
  } catch (err) {
    ready = false;
  }
  check(ready, 'the page is ready (window.cgs.ready, a hello and a state)');
  if (!ready) {
    await screenshot(p, 'not-ready');
    throw new Error('the page never got ready: ' + (await text(p, '#connection')));
  }
  check((await text(p, '#connection')) === 'connected', '#connection says connected', await text(p, '#connection'));
  const hello = await p.evaluate(() => window.cgs.hello);
  check(hello.operator === true && hello.token_required === false, 'the hello makes a page of the open stationd an operator\'s',
    { operator: hello.operator, token_required: hello.token_required });
  check(hello.relief && Array.isArray(hello.relief.extent) && hello.relief.extent.length === 4,
    'the hello names the shaded relief and its extent', hello.relief);
  // The relief is fetched, and the relief layer draws it (its pixel at the
  // map's centre is opaque).
  const reliefDrawn = await poll(() => p.evaluate(() => {
    const layer = window.cgs.map.getLayers().getArray().find((l) => l.get('name') === 'relief');
    if (!layer || !layer.getSource()) return null;
    const size = window.cgs.map.getSize();
    const d = layer.getData([Math.round(size[0] / 2), Math.round(size[1] / 2)]);
    return d && d[3] > 200 ? Array.from(d) : null;
  }), 10000);
  const reliefResp = main.responses.find((r) => /\/relief\.png$/.test(r.url));
  check(reliefResp && reliefResp.status === 200 && reliefResp.type.startsWith('image/png'), 'GET /relief.png: 200, a PNG', reliefResp);
  check(reliefDrawn, 'the relief layer is drawn (opaque at the map\'s centre: ' + reliefDrawn + ')');
  check(main.errors.length === 0, 'no page or console error while it loads', main.errors.slice(0, 5));
  await screenshot(p, 'loaded');

  // The sensor image (imagerd's latest frame) loads into #sensor-image: shown,
  // or kept behind the live video when that plays.
  let img = null;
  try {
    const h = await p.waitForFunction(() => {
      const i = document.getElementById('sensor-image');
      const live = window.cgs.video && window.cgs.video.status === 'live';
      return (!i.hidden || live) && /\/image\/latest\.png/.test(i.src) && i.complete && i.naturalWidth > 0
        ? { src: i.getAttribute('src'), w: i.naturalWidth, h: i.naturalHeight, live } : null;
    }, null, { timeout: 40000, polling: 200 });
    img = await h.jsonValue();
  } catch (err) { /* img stays null */ }
  check(img && img.w === 320 && img.h === 240, '#sensor-image loads imagerd\'s latest frame (' + (img ? img.w + 'x' + img.h + ' from ' + img.src +
    (img.live ? ', behind the live video' : '') : 'none') + ')');
  await screenshot(p, 'sensor-image');

  // 2. Hits, tracks and a BCIS reply.
  let picture = null;
  try {
    const h = await p.waitForFunction(() => {
      const st = window.cgs.state;
      const cur = st.hits.filter((x) => x.current && Array.isArray(x.xy) && x.xy.length >= 2);
      const unk = st.tracks.filter((t) => t.status === 'confirmed' && t.identity === 'unknown' && Array.isArray(t.last_hit));
      if (!cur.length || !unk.length) return null;
      return {
        current_hits: cur.reduce((s, x) => s + x.xy.length / 2, 0),
        tracks: st.tracks.filter((t) => t.status !== 'tentative').map((t) => t.id + ':' + t.status + ':' + t.identity).join(' ') +
          ' and ' + st.tracks.filter((t) => t.status === 'tentative').length + ' tentative',
        unknown_confirmed: unk.length,
        sim_time_s: st.sim_time_s,
      };
    }, null, { timeout: 60000, polling: 100 });
    picture = await h.jsonValue();
  } catch (err) { /* stays null */ }
  if (picture) diag('picture at T+' + picture.sim_time_s + ' s: ' + picture.current_hits + ' current hits; tracks ' + picture.tracks);
  check(picture && picture.current_hits > 0, 'current (yellow) MTI hits appear');
  check(picture && picture.unknown_confirmed > 0, 'a confirmed unknown track with a last hit appears');
  await poll(() => main.bcisSeen, 30000);
  check(main.bcisSeen && main.bcisSeen.marking === 'FRIEND TRK',
    'a BCIS reply of the friendly appears (state.bcis: ' + JSON.stringify(main.bcisSeen) + ')');
  const friendly = await poll(() => p.evaluate(() => window.cgs.state.tracks.find((t) => t.identity === 'friendly') || null), 20000);
  diag('friendly track: ' + JSON.stringify(friendly));
  await screenshot(p, 'hits-and-tracks');
  if (!picture) throw new Error('no track to designate');

  // 3. Click the newest hit of an unknown confirmed track (one whose last
  // hit is a current hit, well apart from the other confirmed tracks); a
  // click that missed because the scan moved on is tried again.
  // What the page sends, as the server receives it.
  await p.evaluate(() => {
    const send = WebSocket.prototype.send;
    window.cgsSent = [];
    WebSocket.prototype.send = function (d) {
      try { window.cgsSent.push(JSON.parse(d)); } catch (err) { /* not JSON */ }
      return send.call(this, d);
    };
  });
  let pick = null;
  for (let attempt = 0; attempt < 3 && !pick; attempt++) {
    pick = await poll(() => trackHit(p, 'unknown'), 10000);
    if (!pick) continue;
    const before = await repliesNow(p);
    await p.mouse.click(pick.px[0], pick.px[1]);
    diag('clicked track ' + pick.id + "'s newest hit " + pick.last_hit.join(', ') + ' at pixel ' + pick.px.map(Math.round).join(', ') + ' (state ' + pick.seq + ')');
    let reply = null;
    try {
      reply = await replyAfter(p, before, 'designate', 8000);
    } catch (err) {
      diag('no designate reply: #result says ' + JSON.stringify(await text(p, '#result')));
      pick = null;  // the click missed the hit (the scan moved on): again
      continue;
    }
    pick.reply = reply;
  }
  check(pick && pick.reply && pick.reply.ok === true, 'the click is a designation and guidanced accepts it', pick && pick.reply);
  if (!pick || !pick.reply) throw new Error('no designation');
  diag('reply: ' + JSON.stringify(pick.reply) + '; #result: ' + JSON.stringify(await text(p, '#result')));
  let icpt = null;
  try {
    const h = await p.waitForFunction((id) => {
      const i = window.cgs.state.intercepts[0];
      return i && i.track_id === id && i.route.length >= 4 ? i : null;
    }, pick.id, { timeout: 10000, polling: 50 });
    icpt = await h.jsonValue();
  } catch (err) {
    icpt = await p.evaluate(() => window.cgs.state.intercepts[0] || null);
  }
  check(icpt && icpt.track_id === pick.id, 'the intercept follows the clicked track (' + pick.id + '; intercept track ' + (icpt && icpt.track_id) + ', state ' + (icpt && icpt.state) + ')');
  const sent = await p.evaluate(() => window.cgsSent.filter((m) => m.op === 'designate').pop() || null);
  check(sent && sent.hit === pick.hit_id && Number.isInteger(sent.radar) && sent.e === undefined,
    'the click sends the clicked hit by its id (hit ' + pick.hit_id + ', track ' + pick.id + '\'s newest), not a point', sent);
  // Refused with the reason: a hit no track took, and a friendly track's.
  const none = await rawCommand(p, '', { op: 'designate', req: 905, uav_id: 1, hit: 4000000000, radar: 1 });
  check(none.reply && none.reply.ok === false && /hit 4000000000 is in no track/.test(none.reply.error || ''),
    'a hit no track took is refused, with the reason', none.reply);
  if (friendly && friendly.last_hit_id) {
    const fr = await rawCommand(p, '', { op: 'designate', req: 906, uav_id: 1, hit: friendly.last_hit_id, radar: 1 });
    check(fr.reply && fr.reply.ok === false && /BCIS says is friendly/.test(fr.reply.error || ''),
      'a friendly track\'s hit is refused, with the reason', fr.reply);
  } else {
    check(false, 'a friendly track with a newest hit to click', friendly);
  }
  const still = await p.evaluate(() => (window.cgs.state.intercepts[0] || {}).track_id);
  check(still === pick.id, 'the refusals leave the intercept on the clicked track', still);
  check(icpt && Array.isArray(icpt.route) && icpt.route.length >= 4, 'the intercept has a route (' + (icpt && icpt.route ? icpt.route.length / 2 : 0) + ' points)');
  // The route layer draws it: purple along its longest segment, on screen.
  let drawn = { n: 0, of: 0 };
  await poll(async () => {
    drawn = await purpleCount(main, null);
    return drawn.of >= 3 && drawn.n >= 0.7 * drawn.of;
  }, 10000, 300);
  await screenshot(p, 'designated-route');
  diag('route samples: ' + JSON.stringify(drawn.s));
  check(drawn.of >= 3 && drawn.n >= 0.7 * drawn.of, 'the purple route is drawn on the map (' + drawn.n + ' of ' + drawn.of + ' points along its longest segment)');
  // Unchecking "Show Intercept Route" hides it.
  await p.click('#show-route');
  let hidden = { n: 1, of: 0 };
  await poll(async () => {
    hidden = await purpleCount(main, null);
    return hidden.of >= 3 && hidden.n === 0;
  }, 5000, 200);
  await screenshot(p, 'route-hidden');
  check(!(await p.isChecked('#show-route')) && hidden.of >= 3 && hidden.n === 0,
    'unchecking #show-route hides it (' + hidden.n + ' of ' + hidden.of + ' points purple)');
  await p.click('#show-route');

  // 4. The status panel.
  let status = null;
  try {
    const h = await p.waitForFunction(({ id, active }) => {
      const t = (s) => document.getElementById(s).textContent;
      const s = { phase: t('status-phase'), target: t('status-target'), range: t('status-range'), ttg: t('status-ttg') };
      return active.includes(s.phase) && s.target === 'track ' + id && /^\d+(\.\d)? (m|km)$/.test(s.range) ? s : null;
    }, { id: pick.id, active: ACTIVE }, { timeout: 5000, polling: 100 });
    status = await h.jsonValue();
  } catch (err) {
    status = await p.evaluate(() => ['status-phase', 'status-target', 'status-range'].map((s) => document.getElementById(s).textContent));
  }
  check(status && status.phase, 'the status panel shows the phase, "track ' + pick.id + '" and a range', status);
  if (status && status.phase) diag('status: ' + JSON.stringify(status));
  await screenshot(p, 'status');

  // 4b. The intercept's settings, the Sensors menu and the instructors' layer.
  const layerOf = (name) => p.evaluate((name) => {
    const l = window.cgs.map.getAllLayers().find((x) => x.get('name') === name);
    return l ? { visible: l.getVisible(), features: l.getSource() && l.getSource().getFeatures ? l.getSource().getFeatures().length : 0 } : null;
  }, name);
  let n0 = await repliesNow(p);
  await p.selectOption('#fp-scale', '5');
  let scaleReply = null;
  try { scaleReply = await replyAfter(p, n0, 'footprint_scale', 8000); } catch (err) { /* null */ }
  check(scaleReply && scaleReply.ok === true, 'the footprint scale 5x is accepted', scaleReply);
  // The drawn trapezoid is the true footprint scaled 5 times about its centre: 25 times its area.
  const ratio = await poll(() => p.evaluate(() => {
    const x = window.cgs.state.intercepts[0] || {};
    const l = window.cgs.map.getAllLayers().find((y) => y.get('name') === 'footprint');
    const f = l && l.getSource().getFeatures().find((g) => g.getGeometry() && g.getGeometry().getType() === 'Polygon');
    if (x.scale !== 5 || !x.footprint || !f) return null;
    const area = (xy) => {
      let a = 0;
      for (let i = 0; i < xy.length / 2; i++) {
        const j = (i + 1) % (xy.length / 2);
        a += xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1];
      }
      return Math.abs(a) / 2;
    };
    return f.getGeometry().getArea() / area(x.footprint);
  }), 8000);
  check(ratio && Math.abs(ratio - 25) < 0.25, 'the footprint is drawn 5x: 25 times the true area (' + ratio + ')');
  await screenshot(p, 'footprint-5x');
  n0 = await repliesNow(p);
  await p.selectOption('#fp-scale', '1');
  await replyAfter(p, n0, 'footprint_scale', 8000).catch(() => null);
  n0 = await repliesNow(p);
  await p.selectOption('#method', 'mti-hits');
  let methodReply = null;
  try { methodReply = await replyAfter(p, n0, 'intercept_mode', 8000); } catch (err) { /* null */ }
  const methodShown = await poll(() => p.evaluate(() => (window.cgs.state.intercepts[0] || {}).method === 'mti-hits'), 8000);
  check(methodReply && methodReply.ok === true && methodShown, 'the intercept method mti-hits is accepted and reported back', methodReply);
  n0 = await repliesNow(p);
  await p.selectOption('#method', 'head-on');
  await replyAfter(p, n0, 'intercept_mode', 8000).catch(() => null);

  check(await p.isEnabled('#sensor-eo') && await p.isEnabled('#sensor-flir') && await p.isEnabled('#sensor-sar'),
    'the Sensors menu offers Visible (EO), FLIR and SAR to an operator');
  await p.evaluate(() => { document.querySelectorAll('details').forEach((d) => { d.open = true; }); });
  const grey = await poll(async () => ((await layerOf('hits-old')) || {}).features > 0, 20000);
  check(grey, 'the grey history of earlier scans is drawn', await layerOf('hits-old'));
  await p.uncheck('#sensor-mti');
  const mtiOff = [await layerOf('hits-current'), await layerOf('hits-old'), await layerOf('tracks'),
    await layerOf('target')];
  await p.uncheck('#sensor-bcis');
  const bcisOff = await layerOf('bcis');
  await screenshot(p, 'sensors-off');
  check(mtiOff.every((l) => l && l.visible === false) && bcisOff && bcisOff.visible === false,
    'unticking MTI and BCIS in the Sensors menu hides their layers (MTI: hits, tracks and the target marker)', { mtiOff, bcisOff });
  await p.check('#sensor-mti');
  await p.check('#sensor-bcis');
  const back = [await layerOf('hits-current'), await layerOf('bcis'), await layerOf('tracks')];
  check(back.every((l) => l && l.visible === true), 'ticking them again shows them');
  await p.uncheck('#show-tracks');
  const tracksOff = [await layerOf('tracks'), await layerOf('target'), await layerOf('hits-current')];
  await p.check('#show-tracks');
  const tracksBack = await layerOf('tracks');
  check(tracksOff[0] && tracksOff[0].visible === false && tracksOff[1] && tracksOff[1].visible === false &&
    tracksOff[2] && tracksOff[2].visible === true && tracksBack && tracksBack.visible === true,
  'Map Features: Show Tracks hides and shows the tracks and the target marker alone', tracksOff);
  const truthOff = await layerOf('truth');
  await p.check('#truth');
  const truthOn = await poll(async () => {
    const l = await layerOf('truth');
    return l && l.visible && l.features >= 4 ? l : null;
  }, 5000);
  check(truthOff && truthOff.visible === false && truthOn,
    'the ground-truth layer is off until an instructor ticks it, then shows the vehicles', { truthOff, truthOn });
  await screenshot(p, 'ground-truth');
  await p.uncheck('#truth');

  // 5. Cancel Intercept: back to loiter.
  n0 = await repliesNow(p);
  await p.click('#cancel');
  let cancel = null;
  try {
    cancel = await replyAfter(p, n0, 'cancel', 8000);
  } catch (err) { /* null */ }
  check(cancel && cancel.ok === true, 'Cancel Intercept is accepted', cancel || (await text(p, '#result')));
  const cancelled = await poll(() => p.evaluate(() => (window.cgs.state.intercepts[0] || {}).state === 'CANCELLED'), 5000);
  check(cancelled, 'the intercept is CANCELLED', await p.evaluate(() => window.cgs.state.intercepts[0]));
  const loiter = await poll(() => p.evaluate(() => (window.cgs.state.uavs[0] || {}).mode === 'loiter'), 30000);
  check(loiter, 'the UAV goes back to loiter', await p.evaluate(() => window.cgs.state.uavs[0]));
  check(/^cancel: /.test(await text(p, '#result')), '#result shows the cancel went through (' + (await text(p, '#result')) + ')');
  const ended = await poll(() => p.evaluate(() => document.getElementById('status-phase').textContent === 'CANCELLED' &&
    document.getElementById('status-target').textContent === '—'), 5000);
  check(ended, 'the status panel shows CANCELLED and no target any more');
  await screenshot(p, 'cancelled');

  // 6. Refused commands show why.
  n0 = await repliesNow(p);
  await p.fill('#alt-input', '-50');
  await p.click('#alt-set');
  const neg = await text(p, '#result');
  await sleep(300);
  const sentNeg = (await repliesNow(p)) !== n0;
  diag('altitude -50: #result ' + JSON.stringify(neg));
  check(/^altitude: /.test(neg) && !sentNeg && (await p.getAttribute('#result', 'class')).includes('err'),
    'altitude -50 is refused by the page, which says so and sends nothing (' + neg + ')');
  n0 = await repliesNow(p);
  await p.fill('#alt-input', '25000');
  await p.click('#alt-set');
  let alt = null;
  try {
    alt = await replyAfter(p, n0, 'altitude', 8000);
  } catch (err) { /* null */ }
  const altText = await text(p, '#result');
  check(alt && alt.ok === false, 'altitude 25000 is refused by uavsim', alt);
  check(altText.includes('altitude must be in (0, 20000] m above ground'), '#result shows uavsim\'s reason (' + altText + ')');
  await screenshot(p, 'refused');

  // 7. A second browser sees the same picture: the same state frames,
  // byte for byte, for every seq both got.
  const second = await openPage(browser, opt.url, 'second');
  let secondReady = true;
  try {
    await waitReady(second.page, 20000);
  } catch (err) {
    secondReady = false;
  }
  check(secondReady, 'a second browser opens the map at the same time');
  const openedAt = Date.now();
  let common = [];
  await poll(() => {
    common = [...second.frames.keys()].filter((s) => main.frames.has(s) && main.frames.get(s).at >= openedAt);
    return common.length >= 10;
  }, 15000, 200);
  const differ = common.filter((s) => main.frames.get(s).hash !== second.frames.get(s).hash);
  const trackIds = common.length ? main.frames.get(common[common.length - 1]).tracks : '';
  diag('common seqs ' + (common.length ? common[0] + '..' + common[common.length - 1] : 'none') + ' (' + common.length + '), tracks ' + trackIds);
  check(common.length >= 10 && differ.length === 0, 'both get the same state frames for ' + common.length + ' common seqs (' + differ.length + ' differ)');
  const sameTracks = common.length && common.every((s) => main.frames.get(s).tracks === second.frames.get(s).tracks) && trackIds !== '';
  check(sameTracks, 'with identical track ids (' + trackIds + ')');
  const seqs = [...second.frames.keys()];
  check(seqs.length > 5 && seqs.every((s, k) => k === 0 || s > seqs[k - 1]), 'the second page\'s seqs only grow (' + seqs.length + ' frames)');
  await screenshot(second.page, 'second-browser');

  // 8. The stationd with a token: a page without it only watches...
  const viewer = await openPage(browser, opt['token-url'], 'viewer');
  const v = viewer.page;
  let viewerReady = true;
  try {
    await waitReady(v, 20000);
  } catch (err) {
    viewerReady = false;
  }
  const vh = viewerReady ? await v.evaluate(() => window.cgs.hello) : {};
  check(viewerReady && vh.operator === false && vh.token_required === true, 'without ?token= the hello says view only (operator false, token required)',
    { operator: vh.operator, token_required: vh.token_required });
  const disabled = await Promise.all(OPERATOR_CONTROLS.map((s) => v.isDisabled(s)));
  check(disabled.every(Boolean), 'and every operator control is disabled', OPERATOR_CONTROLS.filter((s, k) => !disabled[k]));
  const access = await text(v, '#access');
  check(/view only/.test(access) && await v.isVisible('#access'), 'the page says it is view only (' + access + ')');
  // A click on a current hit is not sent: the page says why.
  let said = null;
  let clicks = 0;
  n0 = await repliesNow(v);
  for (let attempt = 0; attempt < 3 && !said; attempt++) {
    const hit = await poll(() => trackHit(v, null), 10000);
    if (!hit) continue;
    clicks += 1;
    await v.mouse.click(hit.px[0], hit.px[1]);
    said = await poll(async () => {
      const t = await text(v, '#result');
      return /view only/.test(t) ? t : null;
    }, 3000);
    if (!said) diag('clicked track ' + hit.id + "'s newest hit on the view-only page: #result says " + JSON.stringify(await text(v, '#result')));
  }
  check(said && (await repliesNow(v)) === n0, 'clicking a hit on it designates nothing and says view only (' + said + ' after ' + clicks + ' clicks)');
  // The server refuses a command from a page without the token (sent over a
  // WebSocket of the page's own origin, whatever its controls say), and
  // with a wrong token.
  const raw = await rawCommand(v, '', { op: 'altitude', req: 901, uav_id: 1, value: 1300 });
  check(raw.reply && raw.reply.ok === false && /operators' access token/.test(raw.reply.error || ''),
    'stationd refuses a command without the token, saying so', raw.reply);
  const rawCam = await rawCommand(v, '', { op: 'camera', req: 903, uav_id: 1, stare: { e: 0, n: 0 } });
  const rawMode = await rawCommand(v, '', { op: 'sensor_mode', req: 904, uav_id: 1, mode: 'sar' });
  check([rawCam, rawMode].every((r) => r.reply && r.reply.ok === false && /operators' access token/.test(r.reply.error || '')),
    'and its camera and sensor-mode commands too', [rawCam.reply, rawMode.reply]);
  const wrong = await rawCommand(v, '?token=wrong-token-9', { op: 'cancel', req: 902, uav_id: 1 });
  check(wrong.hello && wrong.hello.operator === false && wrong.reply && wrong.reply.ok === false && /access token/.test(wrong.reply.error || ''),
    'and one with a wrong token', wrong);
  await screenshot(v, 'view-only');
  // A WebSocket from another web site's page (a foreign Origin) is refused.
  const foreign = await new Promise((resolve) => {
    const u = opt['token-url'].replace(/^http/, 'ws') + 'ws?token=' + opt.token;
    const ws = new WebSocket(u, { origin: 'http://attacker.example' });
    ws.on('open', () => { ws.close(); resolve('opened'); });
    ws.on('unexpected-response', (req, res) => resolve('HTTP ' + res.statusCode));
    ws.on('error', (e) => resolve('error ' + e.message));
  });
  check(foreign !== 'opened', 'a WebSocket with a foreign Origin is refused, even with the token (' + foreign + ')');
  // ... and a page with the token commands.
  const op = await openPage(browser, opt['token-url'] + '?token=' + encodeURIComponent(opt.token), 'operator');
  const o = op.page;
  let opReady = true;
  try {
    await waitReady(o, 20000);
  } catch (err) {
    opReady = false;
  }
  const oh = opReady ? await o.evaluate(() => window.cgs.hello) : {};
  check(opReady && oh.operator === true, 'with ?token= the hello makes it an operator\'s page');
  const enabled = await Promise.all(OPERATOR_CONTROLS.map((s) => o.isEnabled(s)));
  check(enabled.every(Boolean), 'with every operator control enabled', OPERATOR_CONTROLS.filter((s, k) => !enabled[k]));
  n0 = await repliesNow(o);
  await o.fill('#speed-input', '41');
  await o.click('#speed-set');
  let spd = null;
  try {
    spd = await replyAfter(o, n0, 'speed', 8000);
  } catch (err) { /* null */ }
  check(spd && spd.ok === true, 'its airspeed command is accepted (' + (await text(o, '#result')) + ')', spd);
  const cmdSpeed = await poll(() => o.evaluate(() => {
    const u = window.cgs.state.uavs[0];
    return u && u.cmd_airspeed_mps === 41 ? u.cmd_airspeed_mps : null;
  }), 5000);
  check(cmdSpeed === 41, 'and the UAV\'s commanded airspeed becomes 41 m/s');
  await screenshot(o, 'operator-with-token');

  // 9. The cursor's MGRS, against GeographicLib's tools for the same point.
  const target = await p.evaluate(() => {
    const r = window.cgs.map.getTargetElement().getBoundingClientRect();
    return [Math.round(r.left + r.width * 0.37), Math.round(r.top + r.height * 0.61)];
  });
  await p.mouse.move(target[0] - 40, target[1] - 30);
  await p.mouse.move(target[0], target[1], { steps: 4 });
  const coord = await p.evaluate((t) => {
    const r = window.cgs.map.getTargetElement().getBoundingClientRect();
    const c = window.cgs.map.getCoordinateFromPixel([t[0] - r.left, t[1] - r.top]);
    return [Math.round(c[0] * 10) / 10, Math.round(c[1] * 10) / 10];
  }, target);
  const want = 'E ' + Math.round(coord[0]) + ' N ' + Math.round(coord[1]) + ' · ';
  const cursor = await poll(async () => {
    const t = await text(p, '#cursor-mgrs');
    return t.startsWith(want) ? t : null;
  }, 5000);
  const shown = cursor || (await text(p, '#cursor-mgrs'));
  check(cursor, '#cursor-mgrs shows the hovered point\'s E/N and an MGRS (' + shown + '; wanted ' + want + '...)');
  const ll = execFileSync('CartConvert', ['-r', '-l', ...opt.origin.split(/\s+/), '-p', '9'],
    { input: coord[0] + ' ' + coord[1] + ' 0\n' }).toString().trim();
  const grid = execFileSync('GeoConvert', ['-m', '-p', '0'], { input: ll.split(/\s+/).slice(0, 2).join(' ') + '\n' }).toString().trim();
  const pageGrid = shown.split(' · ')[1] || '';
  diag('hovered E ' + coord[0] + ' N ' + coord[1] + ': CartConvert ' + ll + ', GeoConvert ' + grid + ', page ' + pageGrid);
  check(pageGrid.replace(/\s+/g, '') === grid, 'its MGRS is GeographicLib\'s for that point (' + pageGrid + ' vs ' + grid + ')');
  await screenshot(p, 'mgrs-cursor');

  // 10. The live video (the other pages closed: on two cores their drawing
  // slows the sanitizer build's services).
  for (const rec of pages) if (rec !== main) await rec.context.close();
  await videoSteps(browser, main);

  // 11. The imaging sensor's mode and the camera.
  await sensorSteps(browser, main);

  // No page error and no console error on any page, from start to end.
  for (const rec of pages) {
    check(rec.errors.length === 0, 'no page or console error on the ' + rec.label + ' page', rec.errors.slice(0, 5));
  }
}

main().then(() => {
  diag(failures + ' browser checks failed');
  process.exit(0);
}, (err) => {
  check(false, 'the browser steps ran to the end', err && err.stack ? err.stack.split('\n').slice(0, 4).join(' | ') : String(err));
  process.exit(1);
});
