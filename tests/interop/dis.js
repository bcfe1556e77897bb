#!/usr/bin/env node
// dis.js — a DIS peer built on the open-dis library (npm `open-dis`), for the
// gateway's interoperability test (tests/integration/gateway.sh). Test code.
//
//   node dis.js listen PORT PREFIX [--group G [--join-on ADDR]]
//       receive UDP on 127.0.0.1:PORT until killed: every datagram goes to
//       PREFIX.pcap (for tshark) and is decoded by open-dis into one JSON
//       line of PREFIX.jsonl (dis6 for versions 4-6, dis7 for version 7).
//       With --group, bound to the multicast group G instead (the port
//       shared) and joined to it on the interface of ADDR (default
//       127.0.0.1, loopback: as a DIS tool hears the default exercise)
//   node dis.js send-espdu PORT --exercise N --id S:A:E --ecef X,Y,Z
//       [--vel VX,VY,VZ] [--marking M] [--dr ALG] [--version V] [--deactivate]
//       encode an Entity State PDU with open-dis and send it to 127.0.0.1:PORT
//   node dis.js send-action PORT --exercise N --from S:A:E --to S:A:E
//       --request R [--action A] [--point X,Y,Z]... [--version V]
//       an Action Request whose route points are variable datums 31200
//   node dis.js send-raw PORT HEX
//       send bytes as they are
'use strict';
const dgram = require('dgram');
const fs = require('fs');
const path = require('path');
const vm = require('vm');

// Each open-dis bundle keeps its classes in a global `dis`: load each in a
// context of its own so versions 6 and 7 do not overwrite each other.
function loadDis(file) {
    const code = fs.readFileSync(path.join(__dirname, 'node_modules/open-dis/dist', file), 'utf8');
    const ctx = { exports: {}, require, console };
    vm.createContext(ctx);
    vm.runInContext(code, ctx, { filename: file });
    return ctx.exports;
}
const DIS6 = loadDis('dis6.min.js');
const DIS7 = loadDis('dis7.min.js');

const DATUM_GEOCENTRIC = 31200;
const DATUM_TEXT = 240092;

function arg(args, name, def) {
    const i = args.indexOf(name);
    return i >= 0 ? args[i + 1] : def;
}
function args3(s) {
    const v = s.split(',').map(Number);
    if (v.length !== 3 || v.some((x) => !Number.isFinite(x))) throw new Error(`expected X,Y,Z: ${s}`);
    return v;
}
function id3(s) {
    const v = s.split(':').map(Number);
    if (v.length !== 3) throw new Error(`expected S:A:E: ${s}`);
    return v;
}
// dis6 names an entity id's parts site/application/entity, dis7 siteID/applicationID/entityID.
function idStr(e) {
    return 'siteID' in e ? `${e.siteID}:${e.applicationID}:${e.entityID}` : `${e.site}:${e.application}:${e.entity}`;
}
function setId(e, [s, a, n]) {
    if ('siteID' in e) Object.assign(e, { siteID: s, applicationID: a, entityID: n });
    else Object.assign(e, { site: s, application: a, entity: n });
}

// ---- listen ---------------------------------------------------------------------------------

function pcapHeader() {
    const b = Buffer.alloc(24);
    b.writeUInt32LE(0xa1b2c3d4, 0);
    b.writeUInt16LE(2, 4);
    b.writeUInt16LE(4, 6);
    b.writeUInt32LE(65535, 16);
    b.writeUInt32LE(1, 20); // Ethernet
    return b;
}

// One captured frame: Ethernet, IPv4 and UDP headers around the payload, as
// the datagram was addressed (127.0.0.1:sport -> 127.0.0.1:dport).
function pcapRecord(payload, sport, dport) {
    const eth = Buffer.alloc(14);
    eth.writeUInt16BE(0x0800, 12);
    const ip = Buffer.alloc(20);
    ip.writeUInt8(0x45, 0);
    ip.writeUInt16BE(20 + 8 + payload.length, 2);
    ip.writeUInt8(64, 8);
    ip.writeUInt8(17, 9);
    ip.writeUInt32BE(0x7f000001, 12);
    ip.writeUInt32BE(0x7f000001, 16);
    let sum = 0;
    for (let i = 0; i < 20; i += 2) sum += ip.readUInt16BE(i);
    while (sum > 0xffff) sum = (sum & 0xffff) + (sum >> 16);
    ip.writeUInt16BE(~sum & 0xffff, 10);
    const udp = Buffer.alloc(8);
    udp.writeUInt16BE(sport, 0);
    udp.writeUInt16BE(dport, 2);
    udp.writeUInt16BE(8 + payload.length, 4);
    const frame = Buffer.concat([eth, ip, udp, payload]);
    const now = Date.now();
    const rec = Buffer.alloc(16);
    rec.writeUInt32LE(Math.floor(now / 1000), 0);
    rec.writeUInt32LE((now % 1000) * 1000, 4);
    rec.writeUInt32LE(frame.length, 8);
    rec.writeUInt32LE(frame.length, 12);
    return Buffer.concat([rec, frame]);
}

function chunkBytes(datum) {
    return Buffer.from(datum.variableDatumData.map((c) => c.data[0]));
}

function decode(buf) {
    const ab = buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.length);
    const version = buf[0];
    const lib = version >= 7 ? DIS7 : DIS6;
    const pdu = new lib.PduFactory().createPdu(ab);
    const out = { t: Date.now() / 1000, version: pdu.protocolVersion, exercise: pdu.exerciseID, type: pdu.pduType };
    if (pdu.pduType === 1) {
        out.status = version >= 7 ? pdu.pduStatus : undefined;
        out.length = version >= 7 ? pdu.length : pdu.pduLength;
        out.id = idStr(pdu.entityID);
        out.force = pdu.forceId;
        const t = pdu.entityType;
        out.entityType = [t.entityKind, t.domain, t.country, t.category, t.subcategory, t.specific ?? t.spec, t.extra];
        out.location = [pdu.entityLocation.x, pdu.entityLocation.y, pdu.entityLocation.z];
        out.velocity = [pdu.entityLinearVelocity.x, pdu.entityLinearVelocity.y, pdu.entityLinearVelocity.z];
        out.orientation = [pdu.entityOrientation.psi, pdu.entityOrientation.theta, pdu.entityOrientation.phi];
        out.dr = pdu.deadReckoningParameters.deadReckoningAlgorithm;
        const acc = pdu.deadReckoningParameters.entityLinearAcceleration;
        out.acceleration = [acc.x, acc.y, acc.z];
        out.timestamp = pdu.timestamp;
        out.appearance = pdu.entityAppearance;
        const m = pdu.marking.characters;
        out.marking = String.fromCharCode(...m.filter((c) => c !== 0));
    } else if (pdu.pduType === 16 || pdu.pduType === 17) {
        out.length = pdu.length ?? pdu.pduLength;
        out.from = idStr(pdu.originatingEntityID);
        out.to = idStr(pdu.receivingEntityID);
        out.request = pdu.requestID;
        if (pdu.pduType === 16) out.action = pdu.actionID;
        else out.requestStatus = pdu.requestStatus;
        out.fixed = pdu.fixedDatums.map((d) => [d.fixedDatumID, d.fixedDatumValue]);
        out.points = [];
        out.text = '';
        for (const d of pdu.variableDatums) {
            const b = chunkBytes(d);
            if (d.variableDatumID === DATUM_GEOCENTRIC && b.length === 24)
                out.points.push([b.readDoubleBE(0), b.readDoubleBE(8), b.readDoubleBE(16)]);
            else if (d.variableDatumID === DATUM_TEXT) out.text = b.toString('latin1');
        }
        out.nvar = pdu.variableDatums.length;
    }
    return out;
}

function listen(port, prefix, group, joinOn) {
    const pcap = fs.openSync(`${prefix}.pcap`, 'w');
    fs.writeSync(pcap, pcapHeader());
    const jsonl = fs.openSync(`${prefix}.jsonl`, 'w');
    const sock = dgram.createSocket({ type: 'udp4', reuseAddr: true });
    sock.on('message', (msg, rinfo) => {
        fs.writeSync(pcap, pcapRecord(msg, rinfo.port, port));
        let line;
        try {
            line = decode(msg);
        } catch (e) {
            line = { t: Date.now() / 1000, error: String(e), bytes: msg.length };
        }
        fs.writeSync(jsonl, JSON.stringify(line) + '\n');
    });
    if (group) {
        sock.bind(port, group, () => {
            sock.addMembership(group, joinOn);
            console.log(`listening on ${group}:${port}, joined on ${joinOn}`);
        });
    } else {
        sock.bind(port, '127.0.0.1');
    }
    const stop = () => {
        fs.closeSync(pcap);
        fs.closeSync(jsonl);
        process.exit(0);
    };
    process.on('SIGTERM', stop);
    process.on('SIGINT', stop);
}

// ---- send -----------------------------------------------------------------------------------

function encode(pdu, lengthField) {
    const ab = new ArrayBuffer(8192);
    const lib = pdu.protocolVersion >= 7 ? DIS7 : DIS6;
    const os = new lib.OutputStream(ab);
    pdu.encodeToBinary(os);
    const bytes = Buffer.from(os.toByteArray());
    bytes.writeUInt16BE(bytes.length, 8); // open-dis leaves the length to the caller
    if (lengthField !== undefined) pdu[lengthField] = bytes.length;
    return bytes;
}

function send(port, bytes) {
    const sock = dgram.createSocket('udp4');
    sock.send(bytes, port, '127.0.0.1', (err) => {
        sock.close();
        if (err) {
            console.error(err.message);
            process.exit(1);
        }
    });
}

function sendEspdu(port, args) {
    const version = Number(arg(args, '--version', '7'));
    const lib = version >= 7 ? DIS7 : DIS6;
    const pdu = new lib.EntityStatePdu();
    pdu.protocolVersion = version;
    pdu.exerciseID = Number(arg(args, '--exercise', '1'));
    setId(pdu.entityID, id3(arg(args, '--id', '42:7:5')));
    pdu.forceId = Number(arg(args, '--force', '2'));
    const t = pdu.entityType;
    t.entityKind = 1;
    t.domain = 1;
    t.country = 222;
    t.category = 1;
    const [x, y, z] = args3(arg(args, '--ecef'));
    pdu.entityLocation.x = x;
    pdu.entityLocation.y = y;
    pdu.entityLocation.z = z;
    const [vx, vy, vz] = args3(arg(args, '--vel', '0,0,0'));
    pdu.entityLinearVelocity.x = vx;
    pdu.entityLinearVelocity.y = vy;
    pdu.entityLinearVelocity.z = vz;
    pdu.deadReckoningParameters.deadReckoningAlgorithm = Number(arg(args, '--dr', '2'));
    if (args.includes('--deactivate')) pdu.entityAppearance = 1 << 23;
    const marking = arg(args, '--marking', 'OPENDIS');
    pdu.marking.characterSet = 1;
    for (let i = 0; i < 11; i++) pdu.marking.characters[i] = i < marking.length ? marking.charCodeAt(i) : 0;
    send(port, encode(pdu, version >= 7 ? 'length' : 'pduLength'));
}

function sendAction(port, args) {
    const version = Number(arg(args, '--version', '7'));
    const lib = version >= 7 ? DIS7 : DIS6;
    const pdu = new lib.ActionRequestPdu();
    pdu.protocolVersion = version;
    pdu.exerciseID = Number(arg(args, '--exercise', '1'));
    setId(pdu.originatingEntityID, id3(arg(args, '--from', '42:7:0')));
    setId(pdu.receivingEntityID, id3(arg(args, '--to', '1:1:1')));
    pdu.requestID = Number(arg(args, '--request', '1'));
    pdu.actionID = Number(arg(args, '--action', '40'));
    args.forEach((v, i) => {
        if (v !== '--point') return;
        const p = args3(args[i + 1]);
        const b = Buffer.alloc(24);
        p.forEach((c, k) => b.writeDoubleBE(c, 8 * k));
        const d = new lib.VariableDatum();
        d.variableDatumID = DATUM_GEOCENTRIC;
        d.variableDatumLength = 192;
        for (const byte of b) {
            const c = new lib.Chunk(1);
            c.data[0] = byte;
            d.variableDatumData.push(c);
        }
        pdu.variableDatums.push(d);
    });
    pdu.numberOfVariableDatumRecords = pdu.variableDatums.length;
    send(port, encode(pdu, version >= 7 ? 'length' : 'pduLength'));
}

const [cmd, port, ...rest] = process.argv.slice(2);
if (!cmd || !port) {
    console.error('usage: node dis.js listen|send-espdu|send-action|send-raw PORT ...');
    process.exit(2);
}
if (cmd === 'listen') listen(Number(port), rest[0], arg(rest, '--group'), arg(rest, '--join-on', '127.0.0.1'));
else if (cmd === 'send-espdu') sendEspdu(Number(port), rest);
else if (cmd === 'send-action') sendAction(Number(port), rest);
else if (cmd === 'send-raw') send(Number(port), Buffer.from(rest[0], 'hex'));
else {
    console.error(`unknown command ${cmd}`);
    process.exit(2);
}
