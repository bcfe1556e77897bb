#!/usr/bin/env node
// cot.mjs — a Cursor on Target peer built on node-cot (npm `@tak-ps/node-cot`,
// TAK's XML and protobuf in JavaScript), for the gateway's CoT tests. Test code.
//
//   node cot.mjs read [FILE|-]...
//   node cot.mjs [FILE...]
//       read CoT events from files (stdin when none, or "-"): XML (one or
//       more <event>s, split after each </event> as TAK's streams are), or
//       the TAK protocol (0xbf 0x01 0xbf mesh header and one TakMessage, or
//       0xbf <varint length> stream frames, one after another), read with
//       node-cot's from_proto. Prints one JSON line per event (below).
//   node cot.mjs listen PORT [--bind ADDR] [--group G [--join-on ADDR]]
//       [--count N] [--timeout S]
//       receive UDP (default 127.0.0.1:PORT) and print one JSON line per
//       datagram; exits 0 after N events, 3 when S seconds pass first
//   node cot.mjs send HOST:PORT [--format xml|proto] [--type T] [--how H]
//       [--uid U] [--callsign C] [--lat D --lon D --hae M] [--remarks R]
//       [--dest-uid U] [--dest-callsign C] [--stale-s S] [--link LAT,LON[,HAE]]...
//       [--multicast-if ADDR]  (to a group: sent on ADDR, default 127.0.0.1, TTL 0)
//       build one event with node-cot (default a b-m-p-s-p-i point, "sensor
//       point of interest", how h-e, stale in 60 s; --type t-x-... for a task
//       addressed with --dest-*; --type u-d-f and a --link per vertex for a
//       drawing)
//       and send it by UDP as XML (default) or as TAK protocol version 1
//       with the mesh header; prints the JSON line of what it sent
//
// A JSON line: {source, format, valid (node-cot's own schema check passed:
// the structure, not the values), error, times_valid (time, start and
// stale are ISO 8601 UTC times), uid, type, how, opex, time, start, stale,
// point: {lat, lon, hae, ce, le}, callsign, remarks, course, speed, sensor:
// {azimuth, elevation, fov, vfov, range, ...}, links: [[lat, lon, hae]...],
// link_uids: [{uid, relation}...], dest: [{uid, callsign}...], stroke_color,
// geometry: node-cot's to_geojson geometry type ("Point", "LineString",
// "Polygon") and coordinates}. Numbers are numbers; absent values are null.
import dgram from 'node:dgram';
import fs from 'node:fs';
import xmljs from 'xml-js';
import CoT from '@tak-ps/node-cot';

const MAGIC = 0xbf;

function arg(args, name, def) {
    const i = args.indexOf(name);
    return i >= 0 ? args[i + 1] : def;
}

function args(args, name) {
    const out = [];
    for (let i = 0; i < args.length; i++) if (args[i] === name) out.push(args[i + 1]);
    return out;
}

function num(v) {
    if (v === undefined || v === null || v === '') return null;
    const n = Number(v);
    return Number.isFinite(n) ? n : null;
}

function list(v) {
    if (v === undefined || v === null) return [];
    return Array.isArray(v) ? v : [v];
}

function attrs(el) {
    return (el && el._attributes) || {};
}

// An unsigned varint at b[at]: [value, next offset], or null when cut short.
function varint(b, at) {
    let v = 0;
    let mul = 1;
    for (let i = 0; i < 10 && at < b.length; i++) {
        const c = b[at++];
        v += (c & 0x7f) * mul;
        mul *= 128;
        if (!(c & 0x80)) return [v, at];
    }
    return null;
}

// The TakMessage payloads of a buffer that starts with 0xbf: one after a
// mesh header, or each stream frame's.
function takPayloads(b) {
    const r = varint(b, 1);
    if (!r) throw new Error('TAK header cut short');
    const [v, at] = r;
    if (at < b.length && b[at] === MAGIC) {
        if (v !== 1) throw new Error(`TAK protocol version ${v}`);
        return [b.subarray(at + 1)];
    }
    const out = [];
    let p = 0;
    while (p < b.length) {
        if (b[p] !== MAGIC) throw new Error(`stream frame at byte ${p} does not start with 0xbf`);
        const f = varint(b, p + 1);
        if (!f || f[1] + f[0] > b.length) throw new Error(`stream frame at byte ${p} cut short`);
        out.push(b.subarray(f[1], f[1] + f[0]));
        p = f[1] + f[0];
    }
    return out;
}

// The XML events of a text: split after each </event>.
function xmlEvents(text) {
    const out = [];
    for (const part of text.split('</event>')) if (part.trim()) out.push(part + '</event>');
    if (out.length && !text.trimEnd().endsWith('</event>')) out[out.length - 1] = out[out.length - 1].slice(0, -8);
    return out;
}

// An ISO 8601 UTC time as CoT writes it (node-cot's own check does not look).
function isoTime(v) {
    return typeof v === 'string' && /^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?Z$/.test(v) && !Number.isNaN(Date.parse(v));
}

// One event's JSON line from node-cot's tree (raw: the xml-js compact form).
function describe(raw, extra) {
    const ev = raw && raw.event ? raw.event : {};
    const a = attrs(ev);
    const p = attrs(ev.point);
    const d = ev.detail || {};
    const track = attrs(d.track);
    const sensor = d.sensor ? Object.fromEntries(Object.entries(attrs(d.sensor)).map(([k, v]) => [k, num(v) ?? v])) : null;
    const links = [];
    const linkUids = [];
    for (const l of list(d.link)) {
        const la = attrs(l);
        if (la.point) links.push(String(la.point).split(',').map((x) => num(x.trim())));
        else if (la.uid) linkUids.push({ uid: la.uid, relation: la.relation ?? null });
    }
    const dest = d.marti ? list(d.marti.dest).map((x) => ({ uid: attrs(x).uid ?? null, callsign: attrs(x).callsign ?? null })) : [];
    return {
        ...extra,
        uid: a.uid ?? null,
        type: a.type ?? null,
        how: a.how ?? null,
        opex: a.opex ?? null,
        time: a.time ?? null,
        start: a.start ?? null,
        stale: a.stale ?? null,
        point: { lat: num(p.lat), lon: num(p.lon), hae: num(p.hae), ce: num(p.ce), le: num(p.le) },
        callsign: attrs(d.contact).callsign ?? null,
        remarks: d.remarks && d.remarks._text !== undefined ? String(d.remarks._text) : null,
        course: num(track.course),
        speed: num(track.speed),
        sensor,
        links,
        link_uids: linkUids,
        dest,
        stroke_color: d.strokeColor ? attrs(d.strokeColor).value ?? null : null,
        times_valid: [a.time, a.start, a.stale].every(isoTime),
    };
}

function geometry(cot) {
    try {
        const g = cot.to_geojson().geometry;
        return { type: g.type, coordinates: g.coordinates };
    } catch (err) {
        return { type: null, error: String(err.message || err) };
    }
}

// Parse one event: node-cot's verdict, and the fields (from xml-js when
// node-cot refused it, so a test sees what was wrong).
function parseXml(text, source) {
    try {
        const cot = new CoT(text);
        return { ...describe(cot.raw, { source, format: 'xml', valid: true, error: null }), geometry: geometry(cot) };
    } catch (err) {
        let raw = null;
        try {
            raw = xmljs.xml2js(text, { compact: true });
        } catch (e) {
            raw = null;
        }
        return { ...describe(raw, { source, format: 'xml', valid: false, error: String(err.message || err) }), geometry: null };
    }
}

function parseProto(payload, source) {
    try {
        const cot = CoT.from_proto(payload);
        return { ...describe(cot.raw, { source, format: 'proto', valid: true, error: null }), geometry: geometry(cot) };
    } catch (err) {
        return { source, format: 'proto', valid: false, error: String(err.message || err) };
    }
}

// Every event in a buffer.
function parseBuffer(b, source) {
    let at = 0;
    if (b.length >= 3 && b[0] === 0xef && b[1] === 0xbb && b[2] === 0xbf) at = 3;
    while (at < b.length && ' \t\r\n'.includes(String.fromCharCode(b[at]))) at++;
    if (at < b.length && b[at] === 0x3c) return xmlEvents(b.subarray(at).toString('utf8')).map((x) => parseXml(x, source));
    if (b.length && b[0] === MAGIC) {
        try {
            return takPayloads(b).map((p) => parseProto(p, source));
        } catch (err) {
            return [{ source, format: 'proto', valid: false, error: String(err.message || err) }];
        }
    }
    return [{ source, format: null, valid: false, error: `neither XML nor TAK protocol (first byte 0x${(b[at] ?? 0).toString(16)})` }];
}

function print(obj) {
    process.stdout.write(JSON.stringify(obj) + '\n');
}

// ---- read -----------------------------------------------------------------------------------

function read(files) {
    if (!files.length) files = ['-'];
    for (const f of files) {
        const b = f === '-' ? fs.readFileSync(0) : fs.readFileSync(f);
        for (const e of parseBuffer(b, f === '-' ? 'stdin' : f)) print(e);
    }
}

// ---- listen ---------------------------------------------------------------------------------

function listen(port, rest) {
    const group = arg(rest, '--group');
    const bind = arg(rest, '--bind', group || '127.0.0.1');
    const count = Number(arg(rest, '--count', 0));
    const timeout = Number(arg(rest, '--timeout', 0));
    const sock = dgram.createSocket({ type: 'udp4', reuseAddr: true });
    let seen = 0;
    sock.on('message', (msg, rinfo) => {
        for (const e of parseBuffer(msg, `udp:${rinfo.address}:${rinfo.port}`)) {
            print(e);
            seen++;
        }
        if (count && seen >= count) {
            sock.close();
            process.exit(0);
        }
    });
    sock.bind(port, bind, () => {
        if (group) sock.addMembership(group, arg(rest, '--join-on', '127.0.0.1'));
    });
    if (timeout)
        setTimeout(() => {
            console.error(`cot.mjs: ${seen} event(s) in ${timeout} s`);
            process.exit(count && seen < count ? 3 : 0);
        }, timeout * 1000);
}

// ---- send -----------------------------------------------------------------------------------

function build(rest) {
    const type = arg(rest, '--type', 'b-m-p-s-p-i');
    const callsign = arg(rest, '--callsign', 'node-cot');
    const now = Date.now();
    const props = {
        type,
        how: arg(rest, '--how', 'h-e'),
        callsign,
        time: new Date(now).toISOString(),
        start: new Date(now).toISOString(),
        stale: new Date(now + 1000 * Number(arg(rest, '--stale-s', 60))).toISOString(),
    };
    const remarks = arg(rest, '--remarks');
    if (remarks !== undefined) props.remarks = remarks;
    const destUid = arg(rest, '--dest-uid');
    const destCallsign = arg(rest, '--dest-callsign');
    if (destUid || destCallsign) {
        props.dest = {};
        if (destUid) props.dest.uid = destUid;
        if (destCallsign) props.dest.callsign = destCallsign;
    }
    const lat = Number(arg(rest, '--lat', 0));
    const lon = Number(arg(rest, '--lon', 0));
    const hae = Number(arg(rest, '--hae', 0));
    const feature = {
        id: arg(rest, '--uid', `node-cot-${process.pid}`),
        type: 'Feature',
        properties: props,
        geometry: { type: 'Point', coordinates: [lon, lat, hae] },
    };
    const cot = CoT.from_geojson(feature);
    // Drawing vertices as links (from_geojson would recompute the point).
    for (const l of args(rest, '--link')) cot.addLink({ point: l });
    // from_geojson writes hae "0.0" for 0 and keeps the type; make them exact.
    cot.raw.event._attributes.type = type;
    cot.raw.event.point._attributes.hae = String(hae);
    return cot;
}

function send(target, rest) {
    const m = /^(.*):(\d+)$/.exec(target || '');
    if (!m) throw new Error(`expected HOST:PORT, not ${target}`);
    const [, host, port] = m;
    const format = arg(rest, '--format', 'xml');
    const cot = build(rest);
    let bytes;
    if (format === 'xml') bytes = Buffer.from('<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n' + cot.to_xml(), 'utf8');
    else if (format === 'proto') bytes = Buffer.concat([Buffer.from([MAGIC, 1, MAGIC]), Buffer.from(cot.to_proto())]);
    else throw new Error(`--format xml or proto, not ${format}`);
    const sock = dgram.createSocket('udp4');
    const go = () =>
        sock.send(bytes, Number(port), host, (err) => {
            sock.close();
            if (err) {
                console.error(`cot.mjs: send: ${err.message}`);
                process.exit(1);
            }
            print(parseBuffer(bytes, `sent:${host}:${port}`)[0]);
        });
    // To a multicast group: out on --multicast-if (default 127.0.0.1) with
    // TTL 0, so that it never leaves this machine.
    const first = Number(host.split('.')[0]);
    if (first >= 224 && first <= 239)
        sock.bind(0, () => {
            sock.setMulticastInterface(arg(rest, '--multicast-if', '127.0.0.1'));
            sock.setMulticastTTL(0);
            sock.setMulticastLoopback(true);
            go();
        });
    else go();
}

// ---- main -----------------------------------------------------------------------------------

const [cmd, ...rest] = process.argv.slice(2);
try {
    if (cmd === 'read') read(rest);
    else if (cmd === 'listen' && rest[0]) listen(Number(rest[0]), rest.slice(1));
    else if (cmd === 'send') send(rest[0], rest.slice(1));
    else if (cmd === undefined) read([]);
    else if (cmd !== '-h' && cmd !== '--help') read([cmd, ...rest]);
    else {
        console.error('usage: node cot.mjs read [FILE|-]... | listen PORT [...] | send HOST:PORT [...]');
        process.exit(2);
    }
} catch (err) {
    console.error(`cot.mjs: ${err.message || err}`);
    process.exit(1);
}
