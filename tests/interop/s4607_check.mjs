// s4607_check.mjs — compares what Wireshark's STANAG 4607 dissector reads in
// a .4607 file with the radar's `mti` (and `mti.truth`) messages on the bus.
//
//   node s4607_check.mjs PDML MTI_JSONL TRUTH_JSONL LAT0 LON0 H0
//
// PDML is `tshark -r FILE -T pdml`; the JSONL files are `mscgs echo mti
// --json` and `mscgs echo mti.truth --json`. Every raw value is read from the
// PDML's `value` attribute (the field's bytes in hex), never from what
// tshark shows (tshark 4.0 shows SA16 angles at twice their value).
// Expected values are computed here from the data types as Wireshark's
// dissector reads them: SA32 latitude = round(lat * 2^31 / 90), BA32
// longitude = round(lon mod 360 * 2^32 / 360), geodetic height in metres, line-of-sight velocity in cm/s
// (positive: range opening); the hits' positions go to latitude, longitude
// and height with GeographicLib's CartConvert (the local frame at LAT0 LON0
// H0). Prints one JSON line of counts; exits 1 on the first mismatch, with it.
import { readFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';

const [pdmlPath, mtiPath, truthPath, lat0, lon0, h0] = process.argv.slice(2);
const fail = (why) => {
    console.log(JSON.stringify({ ok: false, why }));
    process.exit(1);
};

// ---- the PDML: packets of fields --------------------------------------------------------
const pdml = readFileSync(pdmlPath, 'utf8');
const packets = pdml.split('<packet>').slice(1);
const attr = (tag, name) => {
    const m = tag.match(new RegExp(`\\s${name}="([^"]*)"`));
    return m ? m[1] : undefined;
};
const signed = (hex) => {
    const bits = hex.length * 4;
    let v = BigInt('0x' + hex);
    if (v >= 1n << BigInt(bits - 1)) v -= 1n << BigInt(bits);
    return Number(v);
};
const unsigned = (hex) => Number(BigInt('0x' + hex));

let malformed = 0;
const dwells = new Map(); // "scan/dwell" -> [{reports}]
let nreports = 0;
for (const p of packets) {
    if (/name="_ws\.malformed"|name="_ws\.expert"/.test(p)) malformed++;
    // The dwell segment's fields, in order; a report starts at its index.
    const fields = [...p.matchAll(/<field name="(s4607\.dwell\.[^"]*)"[^>]*>/g)];
    let d = null;
    let rpt = null;
    for (const f of fields) {
        const name = f[1];
        const value = attr(f[0], 'value');
        if (value === undefined) continue;
        if (name === 's4607.dwell.revisit') {
            d = { revisit: unsigned(value), reports: [] };
            rpt = null;
        }
        else if (!rpt && name === 's4607.dwell.time') d.time = unsigned(value);
        else if (!rpt && name === 's4607.dwell.sensor.lat') d.lat = signed(value);
        else if (!rpt && name === 's4607.dwell.sensor.lon') d.lon = unsigned(value);
        else if (name === 's4607.dwell.dwell') {
            d.dwell = unsigned(value);
            const key = `${d.revisit}/${d.dwell}`;
            if (!dwells.has(key)) dwells.set(key, []);
            dwells.get(key).push(d);
        } else if (name === 's4607.dwell.count') d.count = unsigned(value);
        else if (name === 's4607.dwell.rpt.idx') {
            rpt = { idx: unsigned(value) };
            d.reports.push(rpt);
            nreports++;
        } else if (rpt && name === 's4607.dwell.rpt.lat') rpt.lat = signed(value);
        else if (rpt && name === 's4607.dwell.rpt.lon') rpt.lon = unsigned(value);
        else if (rpt && name === 's4607.dwell.rpt.height') rpt.height = signed(value);
        else if (rpt && name === 's4607.dwell.rpt.radial') rpt.radial = signed(value);
        else if (rpt && name === 's4607.dwell.rpt.wrap') rpt.wrap = unsigned(value);
        else if (rpt && name === 's4607.dwell.rpt.tag.entity') rpt.entity = unsigned(value);
        else if (rpt && name === 's4607.dwell.rpt.snr') rpt.snr = signed(value);
        else if (rpt && name === 's4607.dwell.rpt.class') rpt.cls = unsigned(value);
        else if (rpt && name === 's4607.dwell.rpt.unc.slant') rpt.slant = unsigned(value);
        else if (rpt && name === 's4607.dwell.rpt.unc.cross') rpt.cross = unsigned(value);
        else if (rpt && name === 's4607.dwell.rpt.unc.radial') rpt.vunc = unsigned(value);
    }
}
if (malformed) fail(`${malformed} packets malformed or with expert info`);

// ---- the bus ------------------------------------------------------------------------------
const lines = (path) =>
    readFileSync(path, 'utf8')
        .split('\n')
        .filter((l) => l.startsWith('{'))
        .map((l) => JSON.parse(l));
const mtis = lines(mtiPath);
const truth = new Map(); // hit id -> entity id
for (const t of lines(truthPath))
    for (const it of t.items || []) if (it.hit_id) truth.set(it.hit_id, it.entity_id);

// Every hit's position to geodetic with CartConvert, in one call.
const hits = [];
for (const m of mtis) for (const h of m.hits || []) hits.push(h);
const xyz = (p) => `${p?.east_m || 0} ${p?.north_m || 0} ${p?.up_m || 0}`;
// The hits' positions, then each dwell's platform position.
const enu = hits.map((h) => xyz(h.position)).concat(mtis.map((m) => xyz(m.platform_position)));
const geo = execFileSync('CartConvert', ['-r', '-l', lat0, lon0, h0, '-p', '9'], {
    input: enu.join('\n') + '\n',
    maxBuffer: 1 << 28,
})
    .toString()
    .trim()
    .split('\n')
    .map((l) => l.trim().split(/\s+/).map(Number));

// ---- compare ------------------------------------------------------------------------------
const sa32 = (lat) => Math.round((lat * 2 ** 31) / 90);
const ba32 = (lon) => Math.round(((((lon % 360) + 360) % 360) * 2 ** 32) / 360) % 2 ** 32;
const near = (a, b, lsb) => Math.min(Math.abs(a - b), 2 ** 32 - Math.abs(a - b)) <= lsb;
let k = 0;
let compared = 0;
let firstTime = null;
let tagged = 0;
let matchedDwells = 0;
let maxLat = 0;
let maxLon = 0;
for (const m of mtis) {
    const key = `${m.scan_number || 0}/${m.dwell_number || 0}`;
    const segs = dwells.get(key);
    const n = (m.hits || []).length;
    if (!segs) {
        // A dwell the file does not have: one published before the gateway
        // heard the bus, or after it stopped. The caller bounds how many.
        k += n;
        continue;
    }
    matchedDwells++;
    // The dwell: the sensor where the radar was, and its time on the
    // exercise clock (ms since the reference date's midnight: the dwell
    // centre, 1 s of it a second of simulation time).
    const [plat, plon] = geo[hits.length + mtis.indexOf(m)];
    for (const seg of segs) {
        if (!near(seg.lat, sa32(plat), 1) || !near(seg.lon, ba32(plon), 1))
            fail(`dwell ${key}: sensor at ${seg.lat} ${seg.lon}, want ${sa32(plat)} ${ba32(plon)}`);
        const t = ((m.dwell_start_s || 0) + (m.dwell_end_s || 0)) / 2;
        if (firstTime === null) firstTime = { ms: seg.time, t };
        const want = firstTime.ms + Math.round((t - firstTime.t) * 1000);
        if (Math.abs(seg.time - want) > 1) fail(`dwell ${key}: time ${seg.time} ms, want ${want}`);
    }
    const reports = segs.flatMap((s) => s.reports);
    if (reports.length !== n) fail(`dwell ${key}: ${reports.length} target reports, ${n} hits`);
    for (let i = 0; i < n; i++, k++) {
        const h = m.hits[i];
        const r = reports[i];
        const [lat, lon, height] = geo[k];
        const wantLat = Math.round((lat * 2 ** 31) / 90);
        const wantLon = Math.round(((((lon % 360) + 360) % 360) * 2 ** 32) / 360) % 2 ** 32;
        const wantH = Math.round(height);
        const wantV = Math.round((h.radial_velocity_mps || 0) * 100);
        const wantWrap = Math.round((m.wrap_velocity_mps || 0) * 100);
        const dLat = Math.abs(r.lat - wantLat);
        const dLon = Math.min(Math.abs(r.lon - wantLon), 2 ** 32 - Math.abs(r.lon - wantLon));
        maxLat = Math.max(maxLat, dLat);
        maxLon = Math.max(maxLon, dLon);
        if (dLat > 1 || dLon > 1)
            fail(`dwell ${key} report ${i}: lat/lon ${r.lat} ${r.lon}, want ${wantLat} ${wantLon}`);
        if (Math.abs(r.height - wantH) > 1) fail(`dwell ${key} report ${i}: height ${r.height}, want ${wantH}`);
        if (Math.abs(r.radial - wantV) > 1)
            fail(`dwell ${key} report ${i}: LOS velocity ${r.radial} cm/s, want ${wantV}`);
        if (Math.abs(r.wrap - wantWrap) > 1) fail(`dwell ${key} report ${i}: wrap ${r.wrap} cm/s, want ${wantWrap}`);
        const want = {
            snr: Math.max(-128, Math.min(127, Math.round(h.snr_db || 0))),
            cls: 128, // no information, simulated target
            slant: Math.min(65535, Math.round((h.range_sigma_m || 0) * 100)),
            cross: Math.min(65535, Math.round((((h.range_m || 0) * (h.azimuth_sigma_deg || 0) * Math.PI) / 180) * 10)),
            vunc: Math.min(5000, Math.round((m.radial_velocity_sigma_mps || 0) * 100)),
        };
        for (const f of Object.keys(want))
            if (Math.abs(r[f] - want[f]) > 1) fail(`dwell ${key} report ${i}: ${f} ${r[f]}, want ${want[f]}`);
        const ent = truth.get(h.hit_id);
        if (ent !== undefined) {
            if (r.entity !== ent) fail(`dwell ${key} report ${i}: truth tag ${r.entity}, want entity ${ent}`);
            tagged++;
        }
        compared++;
    }
}
console.log(
    JSON.stringify({
        ok: true,
        packets: packets.length,
        dwell_segments: [...dwells.values()].reduce((a, s) => a + s.length, 0),
        reports_in_file: nreports,
        mti_messages: mtis.length,
        matched_dwells: matchedDwells,
        reports_compared: compared,
        truth_tags_compared: tagged,
        max_lat_lsb: maxLat,
        max_lon_lsb: maxLon,
    }),
);
