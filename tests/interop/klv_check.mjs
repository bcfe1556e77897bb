// klv_check.mjs — reads a file of MISB ST 0601 packets (the KLV stream a
// demuxer extracted from imagerd's video) with a decoder written here from
// the standard's tables, and checks every packet against the bus messages of
// the same frame.
//
//   node klv_check.mjs KLV IMAGE_JSONL UAV_JSONL INTERCEPT_JSONL TRACK_JSONL MISSION LAT0 LON0 H0
//
// The JSONL files are `mscgs echo TOPIC --json`. The k-th packet is the
// video's k-th frame, imagerd's frame number k + 1 (the file starts with
// imagerd's first frame). For each packet:
//   - the checksum (tag 1: the 16-bit running sum of every byte from the key
//     through the checksum's length byte, even bytes as the high half) and
//     the layout (tag 2 first, checksum last, LS version 17);
//   - against its `image` message (same frame number): sensor latitude,
//     longitude and heights at the camera's position; the fields of view;
//     the slant range from the camera to the footprint's centre; the frame
//     centre at the footprint's centre (and within 1% of the footprint's
//     width of it); the corners at the footprint's corners (upper left =
//     far-left, upper right = far-right, lower right = near-right, lower
//     left = near-left); positions to geodetic with GeographicLib's
//     CartConvert, each within its tag's quantisation;
//   - against the `uav` message of the frame's time: platform heading,
//     pitch and roll; the sensor's relative elevation at −depression,
//     azimuth and roll at 0 (the fixed camera); how many frames had one is
//     counted (with_platform), and video.sh wants most;
//   - against `intercept`: while a track is designated, tag 129 is its id
//     and tags 40/41 lie within 1 m of that track's estimate (from `track`)
//     moved on to the frame's time; with none, no target tags;
//   - the time stamp (tag 2) minus the frame's simulation time is one
//     constant for the whole file (within 1 µs), and the mission id is
//     MISSION.
// Then one packet with a flipped byte must fail its checksum. Prints one
// JSON line of counts; exits 1 on the first mismatch, with it.
import { readFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';

const [klvPath, imagePath, uavPath, icPath, trackPath, mission, lat0, lon0, h0] =
    process.argv.slice(2);
const fail = (why) => {
    console.log(JSON.stringify({ ok: false, why }));
    process.exit(1);
};

// ---- the decoder -----------------------------------------------------------------------------
const KEY = [0x06, 0x0e, 0x2b, 0x34, 0x02, 0x0b, 0x01, 0x01, 0x0e, 0x01, 0x03, 0x01, 0x01, 0x00,
    0x00, 0x00];

// BER length at b[i]: [length, bytes used].
const ber = (b, i) => {
    if (b[i] < 0x80) return [b[i], 1];
    const n = b[i] & 0x7f;
    let v = 0;
    for (let k = 1; k <= n; k++) v = v * 256 + b[i + k];
    return [v, 1 + n];
};
// BER-OID tag at b[i]: [tag, bytes used].
const oid = (b, i) => {
    let v = 0, k = 0;
    do { v = v * 128 + (b[i + k] & 0x7f); } while (b[i + k++] & 0x80);
    return [v, k];
};
const uint = (v) => v.reduce((a, x) => a * 256 + x, 0);
const sint = (v) => {
    const u = uint(v), bits = 8 * v.length;
    return u >= 2 ** (bits - 1) ? u - 2 ** bits : u;
};
// The standard's mappings (ST 0601, section 8).
const u16 = (v, lo, hi) => lo + (uint(v) * (hi - lo)) / 65535;
const u32 = (v, range) => (uint(v) * range) / 4294967295;
const s16 = (v, range) => (sint(v) * range) / 65534;
const s32 = (v, range) => (sint(v) * range) / 4294967294;
const text = (v) => Buffer.from(v).toString('utf8');

// One packet at b[start]: { items: Map tag -> bytes, order, end, sumOk }.
const packet = (b, start) => {
    for (let k = 0; k < 16; k++) if (b[start + k] !== KEY[k]) return { bad: `no UAS LS key at ${start}` };
    const [len, lb] = ber(b, start + 16);
    const end = start + 16 + lb + len;
    if (end > b.length) return { bad: `packet at ${start} runs past the file` };
    const items = new Map(), order = [];
    let i = start + 16 + lb;
    while (i < end) {
        const [tag, tb] = oid(b, i);
        const [l, llb] = ber(b, i + tb);
        const v = b.subarray(i + tb + llb, i + tb + llb + l);
        if (i + tb + llb + l > end) return { bad: `item ${tag} runs past its packet` };
        items.set(tag, v);
        order.push(tag);
        i += tb + llb + l;
    }
    // The running sum over the key .. the checksum's length byte (all but the last two bytes).
    let sum = 0;
    for (let k = start; k < end - 2; k++) sum = (sum + (b[k] << (8 * ((k - start + 1) % 2)))) & 0xffff;
    const stored = items.has(1) ? uint(items.get(1)) : -1;
    return { items, order, end, sumOk: sum === stored, last: order[order.length - 1] };
};

const decode = (items) => {
    const g = (t, f) => (items.has(t) ? f(items.get(t)) : undefined);
    const d = {
        time_us: g(2, uint),
        mission: g(3, text),
        heading: g(5, (v) => u16(v, 0, 360)),
        pitch: g(6, (v) => s16(v, 40)),
        roll: g(7, (v) => s16(v, 100)),
        lat: g(13, (v) => s32(v, 180)),
        lon: g(14, (v) => s32(v, 360)),
        alt: g(15, (v) => u16(v, -900, 19000)),
        hfov: g(16, (v) => u16(v, 0, 180)),
        vfov: g(17, (v) => u16(v, 0, 180)),
        rel_az: g(18, (v) => u32(v, 360)),
        rel_el: g(19, (v) => s32(v, 360)),
        rel_roll: g(20, (v) => u32(v, 360)),
        slant: g(21, (v) => u32(v, 5e6)),
        c_lat: g(23, (v) => s32(v, 180)),
        c_lon: g(24, (v) => s32(v, 360)),
        c_elev: g(25, (v) => u16(v, -900, 19000)),
        t_lat: g(40, (v) => s32(v, 180)),
        t_lon: g(41, (v) => s32(v, 360)),
        version: g(65, uint),
        hae: g(75, (v) => u16(v, -900, 19000)),
        target_id: g(129, text),
        corners: [],
        offset: items.has(26),
    };
    for (let c = 0; c < 4; c++) {
        if (items.has(26)) {
            d.corners.push([d.c_lat + s16(items.get(26 + 2 * c), 0.15), d.c_lon + s16(items.get(27 + 2 * c), 0.15)]);
        } else if (items.has(82)) {
            d.corners.push([s32(items.get(82 + 2 * c), 180), s32(items.get(83 + 2 * c), 360)]);
        }
    }
    return d;
};

// ---- the packets -----------------------------------------------------------------------------
const klv = readFileSync(klvPath);
const pkts = [];
for (let at = 0; at < klv.length;) {
    const p = packet(klv, at);
    if (p.bad) fail(p.bad);
    if (!p.sumOk) fail(`packet ${pkts.length}: checksum wrong`);
    if (p.order[0] !== 2 || p.last !== 1) fail(`packet ${pkts.length}: tag 2 not first or checksum not last`);
    const d = decode(p.items);
    d.start = at;
    d.end = p.end;
    if (d.version !== 17) fail(`packet ${pkts.length}: LS version ${d.version}`);
    if (d.mission !== mission) fail(`packet ${pkts.length}: mission id '${d.mission}', not '${mission}'`);
    pkts.push(d);
    at = p.end;
}
if (!pkts.length) fail('no packet');

// A flipped byte (in the first packet's values) fails the checksum.
const flipped = Buffer.from(klv.subarray(0, pkts[0].end));
flipped[30] ^= 0x10;
const fp = packet(flipped, 0);
const flipDetected = !!fp.bad || !fp.sumOk;

// ---- the bus -----------------------------------------------------------------------------------
const jsonl = (path) => readFileSync(path, 'utf8').split('\n').filter((l) => l.trim()).map((l) => JSON.parse(l));
const images = new Map();
for (const m of jsonl(imagePath)) images.set(Number(m.frame_number), m);
const uavs = new Map();
for (const m of jsonl(uavPath)) uavs.set((m.header.sim_time_s || 0).toFixed(6), m);
const intercepts = jsonl(icPath).map((m) => ({ t: m.header.sim_time_s || 0, m }));
const tracks = jsonl(trackPath);

const xyz = (p) => `${p?.east_m || 0} ${p?.north_m || 0} ${p?.up_m || 0}`;
const enu = [];
const matched = [];
pkts.forEach((d, k) => {
    const im = images.get(k + 1);
    if (!im) return;
    matched.push([d, im]);
    enu.push(xyz(im.camera.position), xyz(im.footprint.center));
    for (const c of im.footprint.corners) enu.push(xyz(c));
});
const geo = execFileSync('CartConvert', ['-r', '-l', lat0, lon0, h0, '-p', '9'], {
    input: enu.join('\n') + '\n',
    maxBuffer: 1 << 28,
}).toString().trim().split('\n').map((l) => l.trim().split(/\s+/).map(Number));

const LAT = 180 / 4294967294, LON = 360 / 4294967294, HGT = 19900 / 65535;
const OFF = 0.15 / 65534; // an offset corner's step
const near = (a, b, tol, what, k) => {
    if (!(Math.abs(a - b) <= tol)) fail(`frame ${k + 1}: ${what} ${a} is not ${b} (within ${tol})`);
};
const angle = (a, b) => Math.abs(((a - b + 540) % 360) - 180);
let withTarget = 0, withPlatform = 0, maxCentreM = 0, maxCentrePct = 0, offset = 0, full = 0;
let dt0;
matched.forEach(([d, im], j) => {
    const k = Number(im.frame_number) - 1;
    const t = im.header.sim_time_s || 0;
    const eye = geo[6 * j], ctr = geo[6 * j + 1];
    // Sensor.
    near(d.lat, eye[0], LAT + 2e-9, 'sensor latitude', k);
    near(d.lon, eye[1], LON + 2e-9, 'sensor longitude', k);
    near(d.alt, eye[2], HGT / 2 + 1e-3, 'sensor true altitude', k);
    near(d.hae, eye[2], HGT / 2 + 1e-3, 'sensor ellipsoid height', k);
    near(d.hfov, im.camera.hfov_deg, 180 / 65535, 'horizontal field of view', k);
    near(d.vfov, im.camera.vfov_deg, 180 / 65535, 'vertical field of view', k);
    // Slant range and frame centre.
    const c = im.camera.position, f = im.footprint.center;
    const slant = Math.hypot((f.east_m || 0) - (c.east_m || 0), (f.north_m || 0) - (c.north_m || 0),
        (f.up_m || 0) - (c.up_m || 0));
    near(d.slant, slant, 5e6 / 4294967295 + 1e-3, 'slant range', k);
    near(d.c_lat, ctr[0], LAT + 2e-9, 'frame centre latitude', k);
    near(d.c_lon, ctr[1], LON + 2e-9, 'frame centre longitude', k);
    near(d.c_elev, ctr[2], HGT / 2 + 1e-3, 'frame centre elevation', k);
    // The frame centre against the footprint's width (1%), in metres on the ground.
    const mPerDegLat = 111132.95, mPerDegLon = 111319.49 * Math.cos((ctr[0] * Math.PI) / 180);
    const err = Math.hypot((d.c_lat - ctr[0]) * mPerDegLat, (d.c_lon - ctr[1]) * mPerDegLon);
    const cs = im.footprint.corners;
    const width = Math.max(Math.hypot(cs[0].east_m - cs[3].east_m, cs[0].north_m - cs[3].north_m),
        Math.hypot(cs[1].east_m - cs[2].east_m, cs[1].north_m - cs[2].north_m));
    maxCentreM = Math.max(maxCentreM, err);
    maxCentrePct = Math.max(maxCentrePct, (100 * err) / width);
    if (!(err <= 0.01 * width)) fail(`frame ${k + 1}: frame centre ${err} m from the footprint's, over 1% of ${width} m`);
    // Corners: upper left, upper right, lower right, lower left = footprint 1, 2, 3, 0.
    if (d.corners.length !== 4) fail(`frame ${k + 1}: ${d.corners.length} corners`);
    d.offset ? offset++ : full++;
    [1, 2, 3, 0].forEach((fi, ci) => {
        const g = geo[6 * j + 2 + fi];
        const tol = d.offset ? OFF / 2 + LAT + 2e-9 : LAT + 2e-9;
        near(d.corners[ci][0], g[0], tol, `corner ${ci + 1} latitude`, k);
        near(d.corners[ci][1], g[1], d.offset ? tol : LON + 2e-9, `corner ${ci + 1} longitude`, k);
    });
    // Platform and relative angles, from the uav message of the frame's time.
    const u = uavs.get(t.toFixed(6));
    if (u) {
        if (angle(d.heading, u.heading_deg || 0) > 360 / 65535) fail(`frame ${k + 1}: heading ${d.heading} not ${u.heading_deg}`);
        near(d.pitch, u.pitch_deg || 0, 40 / 65534, 'platform pitch', k);
        near(d.roll, u.roll_deg || 0, 100 / 65534, 'platform roll', k);
        near(d.rel_el, -(u.sensor?.depression_deg || 0), 1e-6, 'sensor relative elevation', k);
        if (angle(d.rel_az, 0) > 1e-6) fail(`frame ${k + 1}: relative azimuth ${d.rel_az}`);
        if (angle(d.rel_roll, 0) > 1e-6) fail(`frame ${k + 1}: relative roll ${d.rel_roll}`);
        withPlatform++;
    }
    // Time: a constant offset from simulation time.
    const off = d.time_us - Math.round(t * 1e6);
    if (dt0 === undefined) dt0 = off;
    if (Math.abs(off - dt0) > 1) fail(`frame ${k + 1}: time stamp offset ${off} µs, not ${dt0}`);
    // Target: the intercept in force at t.
    let ic;
    for (const x of intercepts) if (x.t <= t + 1e-9) ic = x.m;
    const active = ic && ic.track_id && !['INTERCEPT_STATE_IDLE', 'INTERCEPT_STATE_CANCELLED'].includes(ic.state || 'INTERCEPT_STATE_IDLE');
    if (!active) {
        // imagerd may hear a designation or its end a moment before or after the echo did.
        if (d.target_id !== undefined && !intercepts.some((x) => String(x.m.track_id) === d.target_id))
            fail(`frame ${k + 1}: target id ${d.target_id} was never designated`);
        return;
    }
    if (d.target_id === undefined) return; // imagerd had not yet heard the designation
    if (d.target_id !== String(ic.track_id)) fail(`frame ${k + 1}: target id ${d.target_id}, not track ${ic.track_id}`);
    // The track's estimate, from a batch at or before t, moved on to t: one of them within 1 m.
    const cands = [];
    for (const b of tracks) {
        const bt = b.header.sim_time_s || 0;
        if (bt > t + 1e-9) continue;
        for (const tr of b.tracks || [])
            if (tr.track_id === ic.track_id && tr.status !== 'TRACK_STATUS_DELETED') {
                const dtt = t - bt;
                cands.push(`${(tr.position.east_m || 0) + (tr.velocity.east_mps || 0) * dtt} ${(tr.position.north_m || 0) + (tr.velocity.north_mps || 0) * dtt} ${tr.position.up_m || 0}`);
            }
    }
    if (!cands.length) return;
    const tg = execFileSync('CartConvert', ['-r', '-l', lat0, lon0, h0, '-p', '9'], { input: cands.slice(-4).join('\n') + '\n' })
        .toString().trim().split('\n').map((l) => l.trim().split(/\s+/).map(Number));
    const best = Math.min(...tg.map((g) => Math.hypot((d.t_lat - g[0]) * mPerDegLat, (d.t_lon - g[1]) * mPerDegLon)));
    if (!(best <= 1.0)) fail(`frame ${k + 1}: target location ${best} m from track ${ic.track_id}'s estimate`);
    withTarget++;
});
console.log(JSON.stringify({
    ok: true,
    packets: pkts.length,
    matched: matched.length,
    with_target: withTarget,
    with_platform: withPlatform,
    offset_corners: offset,
    full_corners: full,
    max_centre_error_m: Number(maxCentreM.toFixed(3)),
    max_centre_error_pct_of_width: Number(maxCentrePct.toFixed(5)),
    time_offset_s: dt0 / 1e6,
    flip_detected: flipDetected,
}));
