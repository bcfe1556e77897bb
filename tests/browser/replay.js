#!/usr/bin/env node
/*
 * replay.js — a replay's timeline in Debian's Chromium (playwright-core),
 * against `mscgs replay --station` (replay.sh starts it): the page loads
 * with no page or console error and says it shows a replay; the timeline is
 * shown with a mark for each of the replay's marks (the designation among
 * them) and the operator's controls are off; the replay's time moves on at
 * its speed; the pause button pauses it (its time stands still) and plays
 * it again; the speed menu sets the speed; a click on the bar seeks there
 * (forward, then back before the designation), the picture starts over
 * (a new generation) and fills again from the recording (the UAV, and the
 * tracks after the designation). Screenshots of each step go to
 * --artifacts.
 *
 * Output: "ok - NAME", "not ok - NAME" and "# ..." lines (replay.sh numbers
 * them as TAP). Exit code 0 when the script ran to its end, 1 when not.
 *
 * Usage: node replay.js --url URL --chromium PATH --artifacts DIR
 */
'use strict';

const path = require('path');
const CHROMIUM_ARGS = require('./chromium_args.js');
const { chromium } = require('playwright-core');

const opt = {};
for (let i = 2; i + 1 < process.argv.length; i += 2) opt[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
for (const k of ['url', 'chromium', 'artifacts']) {
  if (!opt[k]) {
    console.error('replay.js: missing --' + k);
    process.exit(2);
  }
}

function diag(s) {
  for (const line of String(s).split('\n')) console.log('# ' + line);
}

function check(cond, name, why) {
  console.log((cond ? 'ok - ' : 'not ok - ') + name);
  if (!cond && why !== undefined) diag('  ' + (typeof why === 'string' ? why : JSON.stringify(why)));
  return !!cond;
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function poll(fn, ms, every = 100) {
  const end = Date.now() + ms;
  let v;
  for (;;) {
    v = await fn();
    if (v || Date.now() >= end) return v;
    await sleep(every);
  }
}

let shot = 0;
async function screenshot(page, step) {
  shot += 1;
  const file = path.join(opt.artifacts, String(shot).padStart(2, '0') + '-' + step + '.png');
  await page.screenshot({ path: file });
}

async function main() {
  const browser = await chromium.launch({ executablePath: opt.chromium, args: CHROMIUM_ARGS });
  const context = await browser.newContext({ viewport: { width: 1400, height: 900 }, deviceScaleFactor: 1 });
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push('page error: ' + e.message));
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push('console error: ' + m.text());
  });
  await page.goto(opt.url);

  const replay = () => page.evaluate(() => (window.cgs.state ? window.cgs.state.replay : null));
  const picture = () => page.evaluate(() => {
    const s = window.cgs.state;
    return s ? { uavs: s.uavs.length, tracks: s.tracks.length, hits: s.hits.length, sim: s.sim_time_s } : null;
  });

  // ---- the page knows it shows a replay
  const hello = await poll(() => page.evaluate(() => window.cgs.hello), 15000);
  check(hello && hello.replay === true, 'the hello says the exercise is a replay', hello);
  const r0 = await poll(async () => {
    const r = await replay();
    return r && r.span_s > 0 ? r : null;
  }, 15000);
  if (!check(r0, 'the pictures carry the replay\'s position', r0)) throw new Error('no replay state');
  diag('recording: ' + r0.file + ', ' + r0.span_s + ' s, exercise ' + r0.recorded_exercise_id +
    ', marks: ' + JSON.stringify(r0.marks));
  check(await page.isVisible('#timeline'), 'the timeline is shown');
  check(await page.isDisabled('#cancel') && await page.isDisabled('#alt-set'),
    'the operator\'s controls are off in a replay');
  check((await page.textContent('#access')).includes('replay'), 'the page says it is a replay',
    await page.textContent('#access'));
  const marks = await page.$$eval('#tl-marks .tl-mark', (els) => els.map((e) => ({ cls: e.className, title: e.title })));
  check(marks.length === r0.marks.length && marks.length > 0,
    `a mark on the bar for each of the replay's ${r0.marks.length} marks (${marks.length})`, marks);
  const designation = r0.marks.find((m) => m.kind === 'designate');
  check(designation && marks.some((m) => m.cls.includes('tl-designate') && m.title.includes('designate')),
    'the designation is marked, with its track in the title', marks);
  await screenshot(page, 'replay-timeline');

  // ---- it plays at its speed
  const a = await replay();
  const wa = Date.now();
  await sleep(2000);
  const b = await replay();
  const rate = (b.t_s - a.t_s) / ((Date.now() - wa) / 1000);
  check(!a.paused && rate > 0.5 * a.speed && rate < 1.6 * a.speed,
    `the replay's time moves on at its speed (${rate.toFixed(2)} s/s at ${a.speed}x)`, { a, b });

  // ---- pause and play
  await page.click('#tl-play');
  const p = await poll(async () => {
    const r = await replay();
    return r && r.paused ? r : null;
  }, 5000);
  check(p, 'the pause button pauses the replay', await replay());
  const p1 = await replay();
  await sleep(1500);
  const p2 = await replay();
  check(p1 && p2 && p2.t_s === p1.t_s, `paused, its time stands still (${p1 && p1.t_s} s, ${p2 && p2.t_s} s)`);
  check((await page.getAttribute('#tl-play', 'title')) === 'play', 'the button then offers to play');

  // ---- speed
  await page.selectOption('#tl-speed', '5');
  const s5 = await poll(async () => {
    const r = await replay();
    return r && r.speed === 5 ? r : null;
  }, 5000);
  check(s5, 'the speed menu sets the replay\'s speed (5x)', await replay());

  // ---- seek forward, past the designation
  const box = await page.$eval('#tl-track', (e) => {
    const r = e.getBoundingClientRect();
    return { x: r.left, y: r.top, w: r.width, h: r.height };
  });
  const seekTo = async (frac) => {
    const before = await replay();
    await page.mouse.click(box.x + frac * box.w, box.y + box.h / 2);
    const r = await poll(async () => {
      const x = await replay();
      return x && x.generation > before.generation ? x : null;
    }, 8000);
    return { before, r };
  };
  const fwd = await seekTo(0.9);
  check(fwd.r, 'a click on the bar seeks (a new generation)', { before: fwd.before, now: await replay() });
  if (fwd.r)
    check(Math.abs(fwd.r.t_s - 0.9 * r0.span_s) < 1.0 && fwd.r.paused,
      `to that time (${fwd.r.t_s} s of ${r0.span_s} s, wanted ${(0.9 * r0.span_s).toFixed(1)}), still paused`, fwd.r);
  // The picture has caught up when its time is the replay's (the preroll sent).
  const after = await poll(async () => {
    const x = await picture(), r = await replay();
    return x && r && x.uavs > 0 && x.tracks > 0 && Math.abs(x.sim - r.sim_time_s) < 3 ? x : null;
  }, 10000);
  check(after, 'the picture fills again from the recording, up to the replay\'s time: the UAV and the tracks',
    { picture: await picture(), replay: await replay() });
  await screenshot(page, 'replay-seek-forward');

  // ---- seek back, before the designation: messages from earlier come again
  const back = await seekTo(0.05);
  check(back.r && back.r.t_s < 0.1 * r0.span_s + 0.5, `a click near the start seeks back (${back.r && back.r.t_s} s)`, back.r);
  const early = await poll(async () => {
    const x = await picture();
    return x && x.uavs > 0 ? x : null;
  }, 8000);
  check(early, 'after a seek back the map shows the UAV again (the earlier messages are not taken for repeats)',
    await picture());
  check(early && after && early.sim < after.sim - 100,
    `at the earlier simulation time (${early && early.sim} s, from ${after && after.sim} s)`, { early, after });

  // ---- play again, at 5x
  await page.click('#tl-play');
  const played = await poll(async () => {
    const r = await replay();
    return r && !r.paused ? r : null;
  }, 5000);
  check(played, 'the play button plays the replay again', await replay());
  const c = await replay();
  const wc = Date.now();
  await sleep(1500);
  const d = await replay();
  const rate5 = (d.t_s - c.t_s) / ((Date.now() - wc) / 1000);
  check(rate5 > 2.5 && rate5 < 8, `it plays at the speed chosen (${rate5.toFixed(2)} s/s at 5x)`, { c, d });
  await screenshot(page, 'replay-playing');

  // ---- the result line said what the replay did
  const result = await page.textContent('#result');
  check(/replay_resume: .*playing/.test(result), 'the page shows the replay\'s answer', result);
  check(errors.length === 0, 'no page or console error', errors);
  await browser.close();
}

main().then(() => process.exit(0), (e) => {
  console.log('not ok - the browser script ran: ' + e.message);
  process.exit(1);
});
