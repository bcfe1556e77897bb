/*
 * bench_stationd.js — the browser half of bench_stationd (tests/bench/
 * bench_stationd.c runs it once per run, against a stationd it feeds with
 * 5,000 MTI hits and 1,000 tracks): how often stationd pushes the picture,
 * how often the page applies it, and how long each update takes the page.
 *
 *   node tests/bench/bench_stationd.js --url http://127.0.0.1:PORT/
 *        [--seconds 20] [--hits 5000] [--tracks 1000] [--viewport 1920x1080]
 *        [--stationd-pid PID] [--profile SECONDS] [--chromium /usr/bin/chromium]
 *
 * Needs CGS_ROOT (the source tree): playwright-core and ws come from
 * tests/browser/node_modules.
 *
 * 1. A WebSocket client of its own (the `ws` package, no Origin header, so
 *    stationd takes it as a local tool) connects to /ws and records every
 *    `state` message: its arrival time, its `seq` and its size. It parses
 *    them until one carries at least --hits hits and --tracks tracks (the
 *    picture is full); after that it reads only the head of each.
 * 2. Headless Chromium (playwright-core, the system's /usr/bin/chromium,
 *    --no-sandbox) opens the page in a window of --viewport. Before the page's
 *    own script runs, a small hook wraps the WebSocket message handler the
 *    page installs: after each message that counted as an update
 *    (window.cgs.stats.updates went up) it notes the update's seq, the time
 *    it ended, the page's own apply time for it (the last of
 *    window.cgs.stats.applyMs: from the handler's start, JSON.parse
 *    included, to after map.renderSync()), and the hits and tracks the page
 *    then holds. It keeps the latest message's text too, for 4. below.
 * 3. Once window.cgs.ready is set and the page holds the whole picture, and
 *    3 s more for the page to settle, the window of --seconds starts. Over it:
 *      push_hz_ws     pushes the client received in each whole second of
 *                     the window: the median over those seconds
 *      push_hz_page   updates the page finished in each second, the same way
 *      apply_ms_*     median, p95 (nearest rank) and max of the page's apply
 *                     times of those updates; apply_over_goal counts those of
 *                     100 ms or more
 *      lag_ms_*       the time from the client's receipt of a push to the
 *                     end of the page's applying the same push (same seq):
 *                     it adds the browser's delivery and any queueing behind
 *                     an earlier update to the apply time (both ends read
 *                     performance.timeOrigin + performance.now(), which
 *                     agree to about a millisecond)
 *      page_missed    pushes the client received, within the seq range the
 *                     page applied, that the page never applied
 *      push_bytes     median size of a push
 *      hits_min/max, tracks  what the page held over the window
 *      cpu_*_pct      CPU over the window: the whole machine (% of all
 *                     cores), stationd (--stationd-pid) and every Chromium
 *                     process (% of one core), from /proc
 *      apply_ms_scan_end_median, apply_ms_between_median  the median apply
 *                     time of the updates at a scan's end (the page holds
 *                     fewer hits than before: the oldest grey scan went;
 *                     every track moved in the same push) and of the others
 * 4. After the window, JSON.parse of the latest push's text alone, in the
 *    page (median of 7): parse_ms. With --profile S the page is then profiled
 *    for S seconds (the DevTools protocol's sampling profiler): the samples
 *    from a message handler's start to the next idle sample make one
 *    update; updates of 25 ms or more and the others are each split into
 *    what the handler was doing (onMessage's own time, which is mostly
 *    JSON.parse, applyState's parts, map.renderSync) and the heaviest
 *    functions by self time. This is printed, not judged; the profiler
 *    slows the page, so it runs after the window.
 *
 * Output on stdout: readable lines, and the figures as `fig key=value`
 * lines for bench_stationd. Exit 0; 1 with an `error ...` line when the
 * measurement broke (no connection, no full picture, Chromium failed, no
 * updates in the window).
 */
'use strict';

const fs = require('fs');
const CHROMIUM_ARGS = require('../browser/chromium_args.js');
const path = require('path');

function say(s) {
  console.log(s);
}

function fail(why) {
  console.log('error ' + why);
  process.exit(1);
}

function fig(key, value, decimals) {
  if (typeof value !== 'number' || !isFinite(value)) return;
  console.log('fig ' + key + '=' + value.toFixed(decimals === undefined ? 2 : decimals));
}

const root = process.env.CGS_ROOT;
if (!root) fail('CGS_ROOT is not set (the source tree)');
const modules = path.join(root, 'tests', 'browser', 'node_modules');
let chromium, WebSocket;
try {
  chromium = require(path.join(modules, 'playwright-core')).chromium;
  WebSocket = require(path.join(modules, 'ws'));
} catch (err) {
  fail('cannot load playwright-core and ws from ' + modules + ' (scripts/install-deps): ' + err.message);
}

// ---- options -------------------------------------------------------------------

const opt = {
  url: '',
  seconds: 20,
  hits: 5000,
  tracks: 1000,
  viewport: '1920x1080',
  stationdPid: 0,
  profile: 0,
  chromium: '/usr/bin/chromium',
};
{
  const a = process.argv.slice(2);
  for (let i = 0; i < a.length; i += 2) {
    const k = a[i];
    const v = a[i + 1];
    if (v === undefined) fail('option ' + k + ' needs a value');
    if (k === '--url') opt.url = v;
    else if (k === '--seconds') opt.seconds = Math.floor(Number(v));
    else if (k === '--hits') opt.hits = Number(v);
    else if (k === '--tracks') opt.tracks = Number(v);
    else if (k === '--viewport') opt.viewport = v;
    else if (k === '--stationd-pid') opt.stationdPid = Number(v);
    else if (k === '--profile') opt.profile = Number(v);
    else if (k === '--chromium') opt.chromium = v;
    else fail('unknown option ' + k);
  }
  if (!/^https?:\/\//.test(opt.url)) fail('--url http://HOST:PORT/ is needed');
  if (!(opt.seconds >= 2)) fail('--seconds must be at least 2');
}
const [vw, vh] = opt.viewport.split('x').map(Number);
if (!(vw > 0 && vh > 0)) fail('--viewport must be WIDTHxHEIGHT');

const WARM_MS = 3000;          // after the page is full, before the window
const CONNECT_MS = 10000;      // the client's connection
const FULL_MS = 60000;         // the picture filling up (client, then page)
const GOAL_APPLY_MS = 100;

const now = () => performance.timeOrigin + performance.now(); // Unix ms, sub-ms
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

function median(v) {
  if (!v.length) return NaN;
  const s = v.slice().sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
}

function quantile(v, q) { // nearest rank
  if (!v.length) return NaN;
  const s = v.slice().sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.max(0, Math.ceil(q * s.length) - 1))];
}

// Counts of times in each whole second of [t0, t0 + seconds * 1000).
function perSecond(times, t0, seconds) {
  const c = new Array(seconds).fill(0);
  for (const t of times) {
    const i = Math.floor((t - t0) / 1000);
    if (i >= 0 && i < seconds) c[i] += 1;
  }
  return c;
}

function hitCount(st) {
  let n = 0;
  for (const h of (st && Array.isArray(st.hits) ? st.hits : [])) {
    if (h && Array.isArray(h.xy)) n += h.xy.length >> 1;
  }
  return n;
}

// ---- CPU from /proc -----------------------------------------------------------------

function readStat(pid) { // [ppid, utime + stime in ticks] or null
  try {
    const s = fs.readFileSync('/proc/' + pid + '/stat', 'latin1');
    const f = s.slice(s.lastIndexOf(')') + 2).split(' ');
    return [Number(f[1]), Number(f[11]) + Number(f[12])];
  } catch (err) {
    return null;
  }
}

function machineTicks() { // [busy, total]
  const f = fs.readFileSync('/proc/stat', 'latin1').split('\n')[0].trim().split(/\s+/).slice(1).map(Number);
  const total = f.reduce((a, b) => a + b, 0);
  return [total - f[3] - (f[4] || 0), total];
}

// Every process descending from this one (Chromium's), pid -> ticks.
function childTicks() {
  const byParent = new Map();
  const ticks = new Map();
  for (const d of fs.readdirSync('/proc')) {
    if (!/^\d+$/.test(d)) continue;
    const s = readStat(d);
    if (!s) continue;
    const pid = Number(d);
    ticks.set(pid, s[1]);
    if (!byParent.has(s[0])) byParent.set(s[0], []);
    byParent.get(s[0]).push(pid);
  }
  const out = new Map();
  const stack = (byParent.get(process.pid) || []).slice();
  while (stack.length) {
    const p = stack.pop();
    out.set(p, ticks.get(p));
    for (const c of byParent.get(p) || []) stack.push(c);
  }
  return out;
}

function cpuSample() {
  const st = opt.stationdPid > 0 ? readStat(opt.stationdPid) : null;
  return { t: now(), machine: machineTicks(), stationd: st ? st[1] : NaN, children: childTicks() };
}

function cpuFigures(a, b) {
  const hz = 100; // USER_HZ, the unit of /proc's times on Linux
  const wall = (b.t - a.t) / 1000;
  let ch = 0;
  for (const [pid, t] of b.children) ch += t - (a.children.get(pid) || 0);
  return {
    machine: 100 * (b.machine[0] - a.machine[0]) / Math.max(1, b.machine[1] - a.machine[1]),
    stationd: 100 * (b.stationd - a.stationd) / hz / wall,
    chromium: 100 * ch / hz / wall,
  };
}

// ---- the WebSocket client --------------------------------------------------------------

class Client {
  constructor(url) {
    this.url = url;
    this.msgs = [];       // {t, seq, bytes} of every state message
    this.parse = true;    // parse whole messages (until the picture is full)
    this.full = null;     // {hits, tracks, t} of the first full picture
    this.closed = false;
    this.error = null;
  }

  open() {
    return new Promise((resolve, reject) => {
      const ws = new WebSocket(this.url, { perMessageDeflate: false, maxPayload: 1 << 30 });
      this.ws = ws;
      const timer = setTimeout(() => reject(new Error('no connection to ' + this.url + ' in ' + CONNECT_MS / 1000 + ' s')), CONNECT_MS);
      ws.on('open', () => {
        clearTimeout(timer);
        resolve();
      });
      ws.on('error', (err) => {
        this.error = err;
        clearTimeout(timer);
        reject(err);
      });
      ws.on('close', () => { this.closed = true; });
      ws.on('message', (data, isBinary) => this.onMessage(data, isBinary));
    });
  }

  onMessage(data, isBinary) {
    const t = now();
    if (isBinary) return;
    const head = data.toString('latin1', 0, Math.min(data.length, 96));
    if (!/^\{\s*"type"\s*:\s*"state"/.test(head)) return;
    const m = /"seq"\s*:\s*(\d+)/.exec(head);
    const rec = { t: t, seq: m ? Number(m[1]) : -1, bytes: data.length };
    this.msgs.push(rec);
    if (this.parse) {
      const st = JSON.parse(data.toString('utf8'));
      rec.seq = st.seq;
      const hits = hitCount(st);
      const tracks = Array.isArray(st.tracks) ? st.tracks.length : 0;
      this.last = { hits: hits, tracks: tracks };
      if (hits >= opt.hits && tracks >= opt.tracks && !this.full) {
        this.full = { hits: hits, tracks: tracks, t: t };
        this.parse = false;
      }
    }
  }

  async waitFull(ms) {
    const end = now() + ms;
    while (!this.full) {
      if (this.closed) throw new Error('stationd closed the WebSocket');
      if (now() > end) {
        const l = this.last;
        throw new Error('the picture did not fill in ' + ms / 1000 + ' s: ' +
          (l ? l.hits + ' hits and ' + l.tracks + ' tracks' : 'no state message') +
          ', waiting for ' + opt.hits + ' and ' + opt.tracks);
      }
      await sleep(50);
    }
  }

  close() {
    if (this.ws) this.ws.terminate();
  }
}

// ---- the page's hook (runs in the page before its own script) ------------------------------

function pageHook() {
  const rec = [];
  window.__cgsBench = { rec: rec, lastText: null };
  function wrap(fn) {
    return function (ev) {
      const c0 = window.cgs;
      const before = c0 && c0.stats ? c0.stats.updates : -1;
      const result = fn.apply(this, arguments);
      const c = window.cgs;
      if (c && c.stats && c.state && c.stats.updates !== before) {
        const t = performance.timeOrigin + performance.now();
        const a = c.stats.applyMs;
        let hits = 0;
        const hs = Array.isArray(c.state.hits) ? c.state.hits : [];
        for (let i = 0; i < hs.length; i++) if (hs[i] && hs[i].xy) hits += hs[i].xy.length >> 1;
        const tracks = Array.isArray(c.state.tracks) ? c.state.tracks.length : 0;
        rec.push([c.state.seq, t, a && a.length ? a[a.length - 1] : NaN, hits, tracks]);
        if (ev && typeof ev.data === 'string') window.__cgsBench.lastText = ev.data;
      }
      return result;
    };
  }
  const d = Object.getOwnPropertyDescriptor(WebSocket.prototype, 'onmessage');
  if (d && d.set && d.get) {
    Object.defineProperty(WebSocket.prototype, 'onmessage', {
      configurable: true,
      enumerable: d.enumerable,
      get: function () { return d.get.call(this); },
      set: function (fn) { d.set.call(this, typeof fn === 'function' ? wrap(fn) : fn); },
    });
  }
  const add = WebSocket.prototype.addEventListener;
  const remove = WebSocket.prototype.removeEventListener;
  const wrapped = new WeakMap();
  WebSocket.prototype.addEventListener = function (type, fn, o) {
    if (type === 'message' && typeof fn === 'function') {
      if (!wrapped.has(fn)) wrapped.set(fn, wrap(fn));
      return add.call(this, type, wrapped.get(fn), o);
    }
    return add.call(this, type, fn, o);
  };
  WebSocket.prototype.removeEventListener = function (type, fn, o) {
    return remove.call(this, type, (type === 'message' && wrapped.get(fn)) || fn, o);
  };
}

function pageFull(want) {
  const c = window.cgs;
  if (!c || !c.ready || !c.state) return false;
  let hits = 0;
  for (const h of Array.isArray(c.state.hits) ? c.state.hits : []) if (h && h.xy) hits += h.xy.length >> 1;
  return hits >= want.hits && Array.isArray(c.state.tracks) && c.state.tracks.length >= want.tracks;
}

// ---- the profile -------------------------------------------------------------------------

async function profilePage(context, page, seconds) {
  const cdp = await context.newCDPSession(page);
  await cdp.send('Profiler.enable');
  await cdp.send('Profiler.setSamplingInterval', { interval: 200 });
  const u0 = await page.evaluate(() => window.cgs.stats.updates);
  await cdp.send('Profiler.start');
  await sleep(seconds * 1000);
  const { profile } = await cdp.send('Profiler.stop');
  const u1 = await page.evaluate(() => window.cgs.stats.updates);
  await cdp.detach();
  const updates = u1 - u0;
  if (updates <= 0) {
    say('profile: no update in ' + seconds + ' s');
    return;
  }
  const byId = new Map();
  const parent = new Map();
  for (const n of profile.nodes) {
    byId.set(n.id, n);
    for (const c of n.children || []) parent.set(c, n.id);
  }
  const fname = (id) => byId.get(id).callFrame.functionName || '(anonymous)';
  const where = (id) => {
    const f = byId.get(id).callFrame;
    const file = f.url ? f.url.slice(f.url.lastIndexOf('/') + 1) : '';
    return fname(id) + (file ? ' ' + file + ':' + (f.lineNumber + 1) : '');
  };
  // Each sample: its part (what onMessage was doing, or what ran outside it)
  // and its own function. Samples from one message handler up to the next
  // idle sample make one update (garbage collection and the browser's own
  // work in between included).
  const updatesSeen = [];
  let cur = null;
  const samples = profile.samples || [];
  const deltas = profile.timeDeltas || [];
  const add = (m, k, v) => m.set(k, (m.get(k) || 0) + v);
  for (let i = 0; i < samples.length; i++) {
    const dt = (i + 1 < deltas.length ? deltas[i + 1] : 0) / 1000; // ms
    if (dt <= 0) continue;
    const ids = [];
    for (let id = samples[i]; id !== undefined; id = parent.get(id)) ids.push(id); // leaf first
    let h = -1;
    for (let k = 0; k < ids.length; k++) {
      const f = byId.get(ids[k]).callFrame;
      if (f.functionName === 'onMessage' && /app\.js/.test(f.url)) { h = k; break; }
    }
    const leaf = fname(samples[i]);
    if (h < 0 && leaf === '(idle)') {
      cur = null;
      continue;
    }
    if (h >= 0 && !cur) {
      cur = { handler: 0, parts: new Map(), self: new Map() };
      updatesSeen.push(cur);
    }
    if (!cur) continue; // before the first handler
    let part;
    if (h < 0) part = /^\(/.test(leaf) ? leaf : '(other script)';
    else if (h === 0) part = 'onMessage itself (JSON.parse)';
    else if (fname(ids[h - 1]) === 'applyState' && h > 1) part = 'applyState > ' + fname(ids[h - 2]);
    else part = fname(ids[h - 1]);
    if (h >= 0) cur.handler += dt;
    add(cur.parts, part, dt);
    add(cur.self, where(samples[i]), dt);
  }
  const heavy = updatesSeen.filter((u) => u.handler >= 25);
  const light = updatesSeen.filter((u) => u.handler < 25);
  const sorted = (m) => [...m.entries()].sort((a, b) => b[1] - a[1]);
  const describe = (list, what) => {
    if (!list.length) return;
    const parts = new Map();
    const self = new Map();
    let handler = 0;
    for (const u of list) {
      handler += u.handler;
      for (const [k, v] of u.parts) add(parts, k, v);
      for (const [k, v] of u.self) add(self, k, v);
    }
    const per = (v) => (v / list.length).toFixed(1);
    say('  ' + what + ': ' + list.length + ', ' + per(handler) + ' ms each in the message handler; by part (ms each):');
    say('    ' + sorted(parts).filter(([, v]) => v / list.length >= 0.1).map(([k, v]) => k + ' ' + per(v)).join(', '));
    say('    heaviest functions (self): ' + sorted(self).slice(0, 8).map(([k, v]) => k + ' ' + per(v)).join(', '));
  };
  say('profile over ' + seconds + ' s, ' + updates + ' updates (the profiler slows the page; not in the figures):');
  describe(heavy, 'updates of 25 ms or more');
  describe(light, 'the others');
}

// ---- main ------------------------------------------------------------------------------

async function main() {
  const base = opt.url.replace(/\/*$/, '/');
  const client = new Client(base.replace(/^http/, 'ws') + 'ws');
  const tStart = now();
  await client.open();
  await client.waitFull(FULL_MS);
  say('the WebSocket client saw the whole picture (' + client.full.hits + ' hits, ' + client.full.tracks +
    ' tracks) after ' + ((client.full.t - tStart) / 1000).toFixed(1) + ' s');

  let browser;
  try {
    browser = await chromium.launch({
      executablePath: opt.chromium, args: CHROMIUM_ARGS, headless: true, timeout: 60000,
    });
  } catch (err) {
    fail('Chromium did not start (' + opt.chromium + '): ' + err.message.split('\n')[0]);
  }
  const errors = [];
  let result;
  try {
    const context = await browser.newContext({ viewport: { width: vw, height: vh } });
    await context.addInitScript(pageHook);
    const page = await context.newPage();
    page.on('pageerror', (err) => errors.push('page error: ' + err.message));
    page.on('console', (m) => { if (m.type() === 'error') errors.push('console: ' + m.text()); });
    const tLoad = now();
    await page.goto(base, { waitUntil: 'load', timeout: 30000 });
    try {
      await page.waitForFunction(pageFull, { hits: opt.hits, tracks: opt.tracks }, { timeout: FULL_MS, polling: 200 });
    } catch (err) {
      const st = await page.evaluate(() => {
        const c = window.cgs;
        return c ? { ready: c.ready, updates: c.stats && c.stats.updates, has: !!c.state } : null;
      }).catch(() => null);
      throw new Error('the page did not show the whole picture in ' + FULL_MS / 1000 + ' s (window.cgs: ' +
        JSON.stringify(st) + ')' + (errors.length ? '; ' + errors[0] : ''));
    }
    say('the page showed it ' + ((now() - tLoad) / 1000).toFixed(1) + ' s after it began to load');
    await sleep(WARM_MS);

    const cpu0 = cpuSample();
    const t0 = cpu0.t;
    await sleep(opt.seconds * 1000);
    const cpu1 = cpuSample();
    const t1 = t0 + opt.seconds * 1000;
    const recs = await page.evaluate(() => window.__cgsBench.rec.slice());
    const parseMs = await page.evaluate(() => {
      const s = window.__cgsBench.lastText;
      if (typeof s !== 'string') return NaN;
      const t = [];
      for (let i = 0; i < 7; i++) {
        const a = performance.now();
        JSON.parse(s);
        t.push(performance.now() - a);
      }
      t.sort((x, y) => x - y);
      return t[3];
    });
    report({ recs: recs, t0: t0, t1: t1, cpu: cpuFigures(cpu0, cpu1), parseMs: parseMs }, client, errors);
    if (opt.profile > 0) await profilePage(context, page, opt.profile);
  } catch (err) {
    await browser.close().catch(() => {});
    client.close();
    fail(err.message.split('\n')[0]);
  }
  await browser.close().catch(() => {});
  client.close();
}

// The window's figures: readable lines and `fig` lines.
function report(result, client, errors) {
  const { recs, t0, t1, cpu, parseMs } = result;
  const secs = opt.seconds;
  const wsIn = client.msgs.filter((m) => m.t >= t0 && m.t < t1);
  const pgIn = recs.filter((r) => r[1] >= t0 && r[1] < t1);
  if (!wsIn.length) fail('the WebSocket client received no push in the ' + secs + ' s window');
  if (!pgIn.length) fail('the page applied no update in the ' + secs + ' s window (hook records: ' + recs.length + ')');
  const hzWs = median(perSecond(wsIn.map((m) => m.t), t0, secs));
  const hzPage = median(perSecond(pgIn.map((r) => r[1]), t0, secs));
  const meanWs = wsIn.length > 1 ? 1000 * (wsIn.length - 1) / (wsIn[wsIn.length - 1].t - wsIn[0].t) : NaN;
  const apply = pgIn.map((r) => r[2]).filter((v) => isFinite(v));
  const arrival = new Map(client.msgs.map((m) => [m.seq, m.t]));
  const lags = pgIn.filter((r) => arrival.has(r[0])).map((r) => r[1] - arrival.get(r[0]));
  const pageSeqs = new Set(recs.map((r) => r[0]));
  const lo = Math.min(...pgIn.map((r) => r[0]));
  const hi = Math.max(...pgIn.map((r) => r[0]));
  const missed = client.msgs.filter((m) => m.seq >= lo && m.seq <= hi && !pageSeqs.has(m.seq)).length;
  let wsGaps = 0;
  for (let i = 1; i < wsIn.length; i++) wsGaps += Math.max(0, wsIn[i].seq - wsIn[i - 1].seq - 1);
  const hits = pgIn.map((r) => r[3]);
  const over = apply.filter((v) => v >= GOAL_APPLY_MS).length;
  // A scan's end drops the oldest grey scan, so the page holds fewer hits than
  // before; the same push moves every track (their batch follows the scan's end).
  const scanEnd = [];
  const others = [];
  for (const r of pgIn) {
    const k = recs.indexOf(r);
    if (!isFinite(r[2])) continue;
    (k > 0 && r[3] < recs[k - 1][3] ? scanEnd : others).push(r[2]);
  }

  say('over ' + secs + ' s: ' + wsIn.length + ' pushes to the client (' + hzWs.toFixed(1) + ' Hz median of 1 s, ' +
    meanWs.toFixed(2) + ' Hz mean, ' + wsGaps + ' seq numbers skipped by stationd, median ' +
    Math.round(median(wsIn.map((m) => m.bytes))) + ' bytes); ' + pgIn.length + ' updates applied by the page (' +
    hzPage.toFixed(1) + ' Hz, ' + missed + ' missed)');
  say('apply time: median ' + median(apply).toFixed(1) + ' ms, p95 ' + quantile(apply, 0.95).toFixed(1) +
    ' ms, max ' + Math.max(...apply).toFixed(1) + ' ms (' + over + ' of ' + apply.length + ' at ' + GOAL_APPLY_MS +
    ' ms or more); JSON.parse alone ' + parseMs.toFixed(1) + ' ms; push to applied: median ' +
    median(lags).toFixed(1) + ' ms, p95 ' + quantile(lags, 0.95).toFixed(1) + ' ms');
  if (scanEnd.length) {
    say('  updates at a scan\'s end (tracks moved, grey history changed): ' + scanEnd.length + ', median ' +
      median(scanEnd).toFixed(1) + ' ms, max ' + Math.max(...scanEnd).toFixed(1) + ' ms; the others: median ' +
      median(others).toFixed(1) + ' ms, max ' + (others.length ? Math.max(...others) : NaN).toFixed(1) + ' ms');
  }
  say('page held ' + Math.min(...hits) + '..' + Math.max(...hits) + ' hits and ' + pgIn[pgIn.length - 1][4] +
    ' tracks; CPU: machine ' + cpu.machine.toFixed(0) + '% of all cores, stationd ' + cpu.stationd.toFixed(0) +
    '%, Chromium ' + cpu.chromium.toFixed(0) + '% of one core');
  for (const e of errors.slice(0, 5)) say('warning: ' + e);

  fig('push_hz_ws', hzWs);
  fig('push_hz_ws_mean', meanWs);
  fig('push_hz_page', hzPage);
  fig('apply_ms_median', median(apply), 2);
  fig('apply_ms_p95', quantile(apply, 0.95), 2);
  fig('apply_ms_max', Math.max(...apply), 2);
  fig('apply_over_goal', over, 0);
  fig('page_updates', apply.length, 0);
  fig('page_missed', missed, 0);
  fig('lag_ms_median', median(lags), 2);
  fig('lag_ms_p95', quantile(lags, 0.95), 2);
  fig('parse_ms', parseMs, 2);
  fig('apply_ms_scan_end_median', median(scanEnd), 2);
  fig('apply_ms_between_median', median(others), 2);
  fig('push_bytes', median(wsIn.map((m) => m.bytes)), 0);
  fig('hits_min', Math.min(...hits), 0);
  fig('hits_max', Math.max(...hits), 0);
  fig('tracks', pgIn[pgIn.length - 1][4], 0);
  fig('cpu_machine_pct', cpu.machine, 1);
  fig('cpu_stationd_pct', cpu.stationd, 1);
  fig('cpu_chromium_pct', cpu.chromium, 1);
}

main().then(() => process.exit(0), (err) => fail(err && err.message ? err.message.split('\n')[0] : String(err)));
