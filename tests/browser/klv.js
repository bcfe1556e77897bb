#!/usr/bin/env node
/*
 * klv.js — the page's MISB ST 0601 reader (services/stationd/web/js/klv.js)
 * and its geodetic-to-local conversion (web/js/geo.js), in node, without a
 * browser: the standard's checksum example; the standard's worked example
 * frame (ST 0601 section 8, the values imagerd's encoder test reproduces
 * byte for byte) read back to within one step of each item's mapping; the
 * corners in offset form (26-33, about the frame centre) and in full form
 * (82-89); the target id under the two-byte tag 129; BER lengths in short
 * and long form; any flipped bit, a cut-short packet or a missing checksum
 * refused; several packets in one payload; and the local east/north/up of
 * points against GeographicLib's CartConvert. TAP on stdout.
 */
'use strict';

const fs = require('fs');
const path = require('path');
const { execFileSync } = require('child_process');

const WEB_JS = path.join(__dirname, '..', '..', 'services', 'stationd', 'web', 'js');

// The page's modules are ES modules without imports: loaded as data: URLs,
// as they are, without a bundler or a package type.
function importModule(file) {
  const src = fs.readFileSync(path.join(WEB_JS, file), 'utf8');
  return import('data:text/javascript;base64,' + Buffer.from(src).toString('base64'));
}

let n = 0;
let failed = 0;
function check(cond, name, why) {
  n += 1;
  console.log((cond ? 'ok ' : 'not ok ') + n + ' - ' + name);
  if (!cond) {
    failed += 1;
    if (why !== undefined) console.log('#   ' + (typeof why === 'string' ? why : JSON.stringify(why)));
  }
}
const skip = (name, why) => { n += 1; console.log('ok ' + n + ' - ' + name + ' # SKIP ' + why); };

const hex = (s) => Array.from(Buffer.from(s.replace(/\s+/g, ''), 'hex'));

// ---- a packet writer of the test's own -------------------------------------------------

function berLength(len, longForm) {
  if (len < 128 && !longForm) return [len];
  if (len < 256) return [0x81, len];
  return [0x82, len >> 8, len & 0xFF];
}
function berOid(tag) {
  const out = [tag & 0x7F];
  for (let t = tag >> 7; t > 0; t >>= 7) out.unshift(0x80 | (t & 0x7F));
  return out;
}
// A packet of items [[tag, bytes]], the checksum appended; lengthForm
// 'short', 'long' (0x81 even below 128) or 'long2' (0x82).
function packet(K, items, lengthForm = 'auto') {
  const body = [];
  for (const [tag, v] of items) body.push(...berOid(tag), v.length, ...v);
  body.push(0x01, 0x02);
  const total = body.length + 2;
  let len;
  if (lengthForm === 'long2') len = [0x82, total >> 8, total & 0xFF];
  else len = berLength(total, lengthForm === 'long');
  const pkt = [...K.UAS_LS_KEY, ...len, ...body];
  const bcc = K.klvChecksum(pkt, 0, pkt.length);
  pkt.push(bcc >> 8, bcc & 0xFF);
  return Uint8Array.from(pkt);
}

// ST 0601 section 8's example frame: each item's bytes (as imagerd's own
// encoder test has them, tests/unit/test_im_klv.c) and the value they stand for.
const STANDARD = [
  [2, '000459F4A6AA4AA8', 'time_us', 1224807209913000, 0],
  [3, '4D495353494F4E3031', 'mission_id', 'MISSION01'],
  [5, '71C2', 'platform_heading_deg', 159.9744, 360 / 65535],
  [6, 'FD3D', 'platform_pitch_deg', -0.4315251, 20 / 32767],
  [7, '08B8', 'platform_roll_deg', 3.405814, 50 / 32767],
  [13, '5595B66D', 'sensor_lat_deg', 60.1768229669783, 90 / 2147483647],
  [14, '5B5360C4', 'sensor_lon_deg', 128.426759042045, 180 / 2147483647],
  [15, 'C221', 'sensor_true_alt_m', 14190.72, 19900 / 65535],
  [16, 'CD9C', 'hfov_deg', 144.5713, 180 / 65535],
  [17, 'D917', 'vfov_deg', 152.6436, 180 / 65535],
  [18, '724A0A20', 'sensor_rel_az_deg', 160.719211474396, 360 / 4294967295],
  [19, '87F84B86', 'sensor_rel_el_deg', -168.792324833941, 180 / 2147483647],
  [20, '7DC55ECE', 'sensor_rel_roll_deg', 176.865437690572, 360 / 4294967295],
  [21, '03830926', 'slant_range_m', 68590.9833, 5e6 / 4294967295],
  [23, 'F101A229', 'frame_center_lat_deg', -10.5423886331461, 90 / 2147483647],
  [24, '14BC082B', 'frame_center_lon_deg', 29.157890122923, 180 / 2147483647],
  [25, '34F3', 'frame_center_elev_m', 3216.037, 19900 / 65535],
  [26, 'C06E'], [27, 'CBE9'], [28, 'D765'], [29, 'E2E0'],
  [30, 'EE5B'], [31, 'F9D6'], [32, '0552'], [33, '10CD'],
  [40, '8F695262', 'target_lat_deg', -79.1638500518929, 90 / 2147483647],
  [41, '765457F2', 'target_lon_deg', 166.400812960416, 180 / 2147483647],
  [65, '11', 'ls_version', 17, 0],
  [75, 'C221', 'sensor_hae_m', 14190.72, 19900 / 65535],
  [129, '3432', 'target_id', '42'],
];
// The example's corners (upper left, upper right, lower right, lower left)
// and their full-form bytes (82-89).
const CORNERS = [
  [-10.579637999887, 29.1273677986333], [-10.5661816260963, 29.140824172424],
  [-10.5527275411938, 29.1542782573265], [-10.5392711674031, 29.1677346311172],
];
const FULL = ['F0F41244', '14B679B9', 'F0F8F87E', '14B8ECD6', 'F0FDDE81', '14BB5FD8', 'F102C4BB', '14BDD2F5'];

async function main() {
  const K = await importModule('klv.js');
  const G = await importModule('geo.js');

  // The checksum section's example: 060E 2B34 0200 81BB sums to B4FD.
  const ex = hex('060E2B34020081BB');
  check(K.klvChecksum(ex, 0, ex.length) === 0xB4FD, 'the checksum of the standard\'s example bytes is 0xB4FD',
    K.klvChecksum(ex, 0, ex.length).toString(16));
  check(K.klvChecksum([0xAB, 0xCD, 0xEF], 0, 3) === 0x9ACD, 'and of an odd length (0xABCD + 0xEF00, 16 bits)');

  // The example frame, offset corners.
  const std = packet(K, STANDARD.map((r) => [r[0], hex(r[1])]));
  const r = K.decodePacket(std);
  check(r.ok, 'the standard\'s example frame is read (' + std.length + ' bytes)', r.error);
  if (!r.ok) return;
  check(r.size === std.length, 'to its last byte (' + r.size + ')');
  for (const [tag, , name, want, step] of STANDARD) {
    if (!name) continue;
    const got = r.values[name];
    const ok = typeof want === 'string' ? got === want : Math.abs(got - want) <= step * 0.5 + 1e-9 * Math.abs(want);
    check(ok, 'tag ' + tag + ' ' + name + ' = ' + got + ' (the standard\'s ' + want + ')', { got, want });
  }
  const fo = K.footprintOf(r.values);
  const offStep = 0.075 / 32767;
  const offErr = fo ? Math.max(...fo.corners.flatMap((c, i) => [Math.abs(c[0] - CORNERS[i][0]), Math.abs(c[1] - CORNERS[i][1])])) : Infinity;
  check(fo && fo.form === 'offset' && offErr <= offStep, 'the offset corners (26-33) about the frame centre are the example\'s corners to within one step (' +
    offErr.toExponential(2) + ' of ' + offStep.toExponential(2) + ' deg)', fo);

  // Full corners, and no frame centre latitude.
  const fullItems = STANDARD.filter((x) => x[0] !== 23 && (x[0] < 26 || x[0] > 33)).map((x) => [x[0], hex(x[1])]);
  FULL.forEach((h, k) => fullItems.push([82 + k, hex(h)]));
  fullItems.sort((a, b) => (a[0] === 65 ? 1000 : a[0]) - (b[0] === 65 ? 1000 : b[0]));
  const rf = K.decodePacket(packet(K, fullItems));
  const ff = rf.ok ? K.footprintOf(rf.values) : null;
  const fullErr = ff ? Math.max(...ff.corners.flatMap((c, i) => [Math.abs(c[0] - CORNERS[i][0]), Math.abs(c[1] - CORNERS[i][1])])) : Infinity;
  check(ff && ff.form === 'full' && fullErr <= 180 / 2147483647, 'the full corners (82-89) are the example\'s to within one step (' + fullErr.toExponential(2) + ' deg)', rf.error || ff);
  check(rf.ok && rf.values.frame_center_lat_deg === undefined, 'without tag 23 there is no frame centre latitude');

  // Tag 129 is written 0x81 0x01; the reader takes it as one tag.
  check(r.items.size === STANDARD.length + 1 && Buffer.from(r.items.get(129)).toString() === '42',
    'tag 129 (BER-OID 0x81 0x01) is one item, the target id "42" (' + r.items.size + ' items with the checksum)');
  const where = Buffer.from(std).indexOf(Buffer.from([0x81, 0x01, 0x02, 0x34, 0x32]));
  check(where > 0, 'and is written as 81 01 02 34 32 in the packet');

  // Lengths: short, long 0x81 (even below 128, as BER allows) and 0x82.
  const few = [[2, hex('000459F4A6AA4AA8')], [23, hex('F101A229')], [24, hex('14BC082B')]];
  for (const form of ['short', 'long', 'long2']) {
    const p = packet(K, few, form);
    const d = K.decodePacket(p);
    check(d.ok && d.size === p.length && Math.abs(d.values.frame_center_lon_deg - 29.157890122923) < 1e-7,
      'a BER length in ' + form + ' form (' + Array.from(p.subarray(16, 19), (b) => b.toString(16)).join(' ') + '...) is read', d.error);
  }
  const big = packet(K, [[3, Array(120).fill(0x41)], [2, hex('000459F4A6AA4AA8')]]);
  const db = K.decodePacket(big);
  check(db.ok && big[16] === 0x81 && db.values.mission_id.length === 120, 'a packet over 127 bytes, with a long-form length, is read', db.error);

  // Any flipped bit is refused; so is a cut-short packet, and one without a checksum.
  let caught = 0;
  let total = 0;
  for (let i = 0; i < std.length; i++) {
    for (let bit = 0; bit < 8; bit++) {
      const c = Uint8Array.from(std);
      c[i] ^= 1 << bit;
      total += 1;
      if (!K.decodePacket(c).ok) caught += 1;
    }
  }
  check(caught === total, 'every one of ' + total + ' flipped bits is refused (' + caught + ')');
  const cut = K.decodePacket(std.subarray(0, std.length - 5));
  check(!cut.ok && /cut short/.test(cut.error), 'a packet cut short is refused: ' + cut.error);
  const noSum = [...K.UAS_LS_KEY, 6, 0x02, 0x01, 0x05, 0x41, 0x01, 0x11];
  const ns = K.decodePacket(Uint8Array.from(noSum));
  check(!ns.ok && /checksum/.test(ns.error), 'a packet without a checksum item is refused: ' + ns.error);
  const wrongKey = Uint8Array.from(std);
  wrongKey[5] = 0x0C;
  check(K.decodePackets(wrongKey).length === 0, 'bytes without the UAS Local Set key hold no packet');

  // Several packets in one payload, with other bytes before them.
  const two = Uint8Array.from([0x00, 0x06, 0x0E, ...packet(K, few), ...std]);
  const both = K.decodePackets(two);
  check(both.length === 2 && both.every((x) => x.ok) && both[1].values.target_id === '42',
    'two packets in one payload, after stray bytes, are both read', both.map((x) => x.error || 'ok'));

  // The local frame against GeographicLib's CartConvert.
  let cart = true;
  try { execFileSync('CartConvert', ['--version'], { stdio: 'ignore' }); } catch (err) { cart = false; }
  if (!cart) {
    skip('the local east/north/up agrees with CartConvert', 'no CartConvert (geographiclib-tools)');
  } else {
    const origin = [35.96, -121.23, 0];
    const frame = G.localFrame(...origin);
    const pts = [[36.05, -121.11, 420], [35.83, -121.41, 150], [35.96, -121.23, 0], [36.4, -120.5, 2000]];
    let worst = 0;
    for (const p of pts) {
      const want = execFileSync('CartConvert', ['-l', ...origin.map(String), '-p', '6'], { input: p.join(' ') + '\n' })
        .toString().trim().split(/\s+/).map(Number);
      const got = frame.toEnu(...p);
      worst = Math.max(worst, ...got.map((g, i) => Math.abs(g - want[i])));
    }
    check(worst < 1e-3, 'the local east/north/up of ' + pts.length + ' points agrees with CartConvert (worst ' + worst.toExponential(2) + ' m)');
  }
}

main().then(() => {
  console.log('1..' + n);
  process.exit(failed ? 1 : 0);
}, (err) => {
  console.log('not ok ' + (n + 1) + ' - the checks ran to the end');
  console.log('# ' + (err && err.stack ? err.stack.split('\n').slice(0, 4).join(' | ') : String(err)));
  console.log('1..' + (n + 1));
  process.exit(1);
});
