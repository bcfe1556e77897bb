/*
 * klv.js — a reader of MISB ST 0601 (UAS Datalink Local Set) KLV packets,
 * the metadata imagerd sends in the video's transport stream, one packet
 * per frame. Pure: no imports, no DOM (node's tests load it as it is).
 *
 * A packet: the 16-byte Universal Label 06 0E 2B 34 02 0B 01 01 0E 01 03 01
 * 01 00 00 00, a BER length (short form below 128, long form 0x81 / 0x82 /
 * ...), then items, each a BER-OID tag (tag 129 is 0x81 0x01), a BER length
 * and the value; the last item is the checksum (tag 1, two bytes): the
 * 16-bit running sum bcc += byte << (8 * ((i + 1) % 2)) over every byte from
 * the key's first through the checksum item's length byte. A packet whose
 * checksum differs, or that is cut short, is refused whole.
 *
 * Values (ST 0601 section 8): sNN ±R is value × R / (2^(NN-1) - 1); uNN
 * lo..hi is lo + value × (hi - lo) / (2^NN - 1). A signed value's reserved
 * minimum (0x8000..., "N/A" or "out of range") reads as null.
 */

export const UAS_LS_KEY = Object.freeze([
  0x06, 0x0E, 0x2B, 0x34, 0x02, 0x0B, 0x01, 0x01, 0x0E, 0x01, 0x03, 0x01, 0x01, 0x00, 0x00, 0x00,
]);

const OFFSET_CORNER_DEG = 0.075;     // tags 26-33: ±0.075° of the frame centre

// ---------------------------------------------------------------------------
// Bytes

// The standard's checksum over bytes[start, end).
export function klvChecksum(bytes, start, end) {
  let bcc = 0;
  for (let i = start; i < end; i++) bcc = (bcc + (bytes[i] << (8 * ((i - start + 1) % 2)))) & 0xFFFF;
  return bcc;
}

// A BER length at bytes[at]: { value, size } or null (cut short, or longer
// than four bytes).
function berLength(bytes, at, end) {
  if (at >= end) return null;
  const b = bytes[at];
  if (b < 0x80) return { value: b, size: 1 };
  const n = b & 0x7F;
  if (n < 1 || n > 4 || at + 1 + n > end) return null;
  let v = 0;
  for (let i = 0; i < n; i++) v = v * 256 + bytes[at + 1 + i];
  return { value: v, size: 1 + n };
}

// A BER-OID tag at bytes[at]: { value, size } or null.
function berOid(bytes, at, end) {
  let v = 0;
  for (let i = 0; i < 4 && at + i < end; i++) {
    const b = bytes[at + i];
    v = v * 128 + (b & 0x7F);
    if (!(b & 0x80)) return { value: v, size: i + 1 };
  }
  return null;
}

function uint(b) {
  let v = 0;
  for (let i = 0; i < b.length; i++) v = v * 256 + b[i];
  return v;
}

// A two's-complement integer of b.length bytes; null for its minimum (the
// standard's reserved "N/A" / "out of range" value).
function sint(b) {
  const u = uint(b);
  const half = 2 ** (8 * b.length - 1);
  if (u === half) return null;
  return u >= half ? u - 2 * half : u;
}

const text = (b) => new TextDecoder('utf-8').decode(b);

// sNN ±range, as the standard maps it (NN from the item's length).
function signedMap(b, range) {
  const v = sint(b);
  return v === null ? null : v * range / (2 ** (8 * b.length - 1) - 1);
}

// uNN lo..hi.
function unsignedMap(b, lo, hi) {
  return lo + uint(b) * (hi - lo) / (2 ** (8 * b.length) - 1);
}

// Each item this reader knows: [name, decode].
const ITEMS = {
  1: ['checksum', uint],
  2: ['time_us', uint],                                          // µs since 1970 (UTC)
  3: ['mission_id', text],
  5: ['platform_heading_deg', (b) => unsignedMap(b, 0, 360)],
  6: ['platform_pitch_deg', (b) => signedMap(b, 20)],
  7: ['platform_roll_deg', (b) => signedMap(b, 50)],
  13: ['sensor_lat_deg', (b) => signedMap(b, 90)],
  14: ['sensor_lon_deg', (b) => signedMap(b, 180)],
  15: ['sensor_true_alt_m', (b) => unsignedMap(b, -900, 19000)],
  16: ['hfov_deg', (b) => unsignedMap(b, 0, 180)],
  17: ['vfov_deg', (b) => unsignedMap(b, 0, 180)],
  18: ['sensor_rel_az_deg', (b) => unsignedMap(b, 0, 360)],
  19: ['sensor_rel_el_deg', (b) => signedMap(b, 180)],
  20: ['sensor_rel_roll_deg', (b) => unsignedMap(b, 0, 360)],
  21: ['slant_range_m', (b) => unsignedMap(b, 0, 5e6)],
  23: ['frame_center_lat_deg', (b) => signedMap(b, 90)],
  24: ['frame_center_lon_deg', (b) => signedMap(b, 180)],
  25: ['frame_center_elev_m', (b) => unsignedMap(b, -900, 19000)],
  40: ['target_lat_deg', (b) => signedMap(b, 90)],
  41: ['target_lon_deg', (b) => signedMap(b, 180)],
  65: ['ls_version', uint],
  75: ['sensor_hae_m', (b) => unsignedMap(b, -900, 19000)],
  129: ['target_id', text],
};
// Offset corners 26-33 (lat 1, lon 1, ... lat 4, lon 4), full corners 82-89.
for (let k = 0; k < 8; k++) {
  const corner = (k >> 1) + 1;
  const axis = k % 2 ? 'lon' : 'lat';
  ITEMS[26 + k] = ['offset_corner' + corner + '_' + axis + '_deg', (b) => signedMap(b, OFFSET_CORNER_DEG)];
  ITEMS[82 + k] = ['corner' + corner + '_' + axis + '_deg', (b) => signedMap(b, axis === 'lat' ? 90 : 180)];
}

// ---------------------------------------------------------------------------
// Packets

// The UAS Local Set packet at bytes[at]. On success { ok: true, size,
// items: Map tag → value bytes, values: { name: decoded } }; else { ok:
// false, size, error } (size: the bytes to skip, 0 when not even the
// packet's length can be read).
export function decodePacket(bytes, at = 0) {
  const end = bytes.length;
  for (let i = 0; i < 16; i++) {
    if (at + i >= end || bytes[at + i] !== UAS_LS_KEY[i]) return { ok: false, size: 0, error: 'no UAS Local Set key' };
  }
  const len = berLength(bytes, at + 16, end);
  if (!len) return { ok: false, size: 0, error: 'no BER length after the key' };
  const start = at + 16 + len.size;
  const stop = start + len.value;
  const size = stop - at;
  if (stop > end) return { ok: false, size: 0, error: 'the packet is cut short (' + (end - at) + ' of ' + size + ' bytes)' };
  const items = new Map();
  const values = {};
  let sawChecksum = false;
  for (let p = start; p < stop;) {
    const tag = berOid(bytes, p, stop);
    const l = tag && berLength(bytes, p + tag.size, stop);
    if (!tag || !l || p + tag.size + l.size + l.value > stop) {
      return { ok: false, size, error: 'an item runs past the packet\'s end at byte ' + (p - at) };
    }
    const v = bytes.subarray(p + tag.size + l.size, p + tag.size + l.size + l.value);
    if (tag.value === 1) {
      // The checksum: the last item, two bytes, summing all before its value.
      if (l.value !== 2 || p + tag.size + l.size + 2 !== stop) return { ok: false, size, error: 'the checksum is not the last item of two bytes' };
      const want = klvChecksum(bytes, at, stop - 2);
      const got = uint(v);
      if (want !== got) return { ok: false, size, error: 'checksum 0x' + got.toString(16) + ' where the bytes sum to 0x' + want.toString(16) };
      sawChecksum = true;
    }
    items.set(tag.value, v);
    const known = ITEMS[tag.value];
    if (known && l.value > 0) values[known[0]] = known[1](v);
    p += tag.size + l.size + l.value;
  }
  if (!sawChecksum) return { ok: false, size, error: 'no checksum item' };
  return { ok: true, size, items, values };
}

// Every packet in a payload (a PES packet's data may hold several, or
// bytes before one): the decoded ones and the errors, in order.
export function decodePackets(bytes) {
  const out = [];
  for (let at = 0; at + 16 < bytes.length;) {
    if (bytes[at] !== UAS_LS_KEY[0]) { at++; continue; }
    const r = decodePacket(bytes, at);
    if (r.size === 0 && !r.ok && r.error === 'no UAS Local Set key') { at++; continue; }
    out.push(r);
    if (r.size === 0) break;   // cannot tell where it ends
    at += r.size;
  }
  return out;
}

// The footprint's corners [[lat, lon] × 4] (upper left, upper right, lower
// right, lower left) of decoded values, and their form: the full corners
// (82-89) when all eight are there, else the offset corners (26-33) added
// to the frame centre (23, 24); null when neither is whole.
export function footprintOf(values) {
  const full = [];
  const offs = [];
  for (let c = 1; c <= 4; c++) {
    full.push([values['corner' + c + '_lat_deg'], values['corner' + c + '_lon_deg']]);
    offs.push([values['offset_corner' + c + '_lat_deg'], values['offset_corner' + c + '_lon_deg']]);
  }
  const whole = (pts) => pts.every((p) => typeof p[0] === 'number' && typeof p[1] === 'number' && isFinite(p[0]) && isFinite(p[1]));
  if (whole(full)) return { form: 'full', corners: full };
  const lat = values.frame_center_lat_deg;
  const lon = values.frame_center_lon_deg;
  if (whole(offs) && typeof lat === 'number' && typeof lon === 'number') {
    return {
      form: 'offset',
      corners: offs.map((o) => {
        let x = lon + o[1];
        if (x > 180) x -= 360;
        else if (x < -180) x += 360;
        return [lat + o[0], x];
      }),
    };
  }
  return null;
}
