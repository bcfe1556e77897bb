// mcap_check.mjs — read an MCAP file with @mcap/core (the reader Foxglove's
// tools are built on; nothing of mscgs), decode every message with
// protobufjs from the FileDescriptorSet the file carries, and print one JSON
// object: how it was read ("indexed": through the footer, summary and chunk
// indexes; "stream": record by record, for a file cut short), its
// schemas and channels, messages per topic, the header sources and sequence
// numbers seen per topic, and every decoding error.
//
// Usage: node mcap_check.mjs FILE [--stream] [--dump TOPIC]
//   --stream       read record by record (a file without its footer)
//   --dump TOPIC   also print each message of TOPIC as JSON, one a line, first
import { readFile } from "node:fs/promises";
import { McapStreamReader } from "@mcap/core";
import { decompressHandlers, openIndexed } from "./mcap_open.mjs";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";

const args = process.argv.slice(2);
const path = args[0];
const stream = args.includes("--stream");
const dumpAt = args.indexOf("--dump");
const dump = dumpAt >= 0 ? args[dumpAt + 1] : null;

const schemas = new Map(), channels = new Map(), types = new Map();
const out = { mode: stream ? "stream" : "indexed", complete: false, schemas: [], channels: [],
              messages: 0, topics: {}, errors: [] };

function typeOf(schema) {
    if (!types.has(schema.id)) {
        const set = descriptor.FileDescriptorSet.decode(schema.data);
        types.set(schema.id, protobuf.Root.fromDescriptor(set).lookupType(schema.name));
    }
    return types.get(schema.id);
}

function onMessage(m) {
    const ch = channels.get(m.channelId);
    const t = out.topics[ch.topic] ??= { count: 0, sources: {}, first_log_ns: null, last_log_ns: null };
    t.count++;
    out.messages++;
    const ns = m.logTime.toString();
    if (t.first_log_ns === null) t.first_log_ns = ns;
    t.last_log_ns = ns;
    if (!ch.schemaId) return; // no schema: counted, not decoded
    try {
        const T = typeOf(schemas.get(ch.schemaId));
        const obj = T.toObject(T.decode(m.data), { longs: String, enums: String, defaults: false });
        const src = obj.header?.source ?? "(none)";
        t.sources[src] = (t.sources[src] ?? 0) + 1;
        if (obj.header && Number(obj.header.seq ?? 0) % 4294967296 !== m.sequence)
            out.errors.push(`${ch.topic}: sequence ${m.sequence} is not the header's ${obj.header.seq}`);
        if (dump === ch.topic) console.log(JSON.stringify(obj));
    } catch (e) {
        if (out.errors.length < 20) out.errors.push(`${ch.topic}: ${e.message}`);
    }
}

try {
    if (!stream) {
        const { reader: r, close } = await openIndexed(path);
        try {
            for (const s of r.schemasById.values()) schemas.set(s.id, s);
            for (const c of r.channelsById.values()) channels.set(c.id, c);
            out.statistics = r.statistics ? { messages: Number(r.statistics.messageCount),
                chunks: r.statistics.chunkCount } : null;
            for await (const m of r.readMessages({ validateCrcs: true })) onMessage(m);
            out.complete = true;
        } finally {
            await close();
        }
    } else {
        const r = new McapStreamReader({ decompressHandlers, validateCrcs: true });
        r.append(await readFile(path));
        for (let rec; (rec = r.nextRecord()); ) {
            if (rec.type === "Schema") schemas.set(rec.id, rec);
            else if (rec.type === "Channel") channels.set(rec.id, rec);
            else if (rec.type === "Message") onMessage(rec);
        }
        out.complete = r.done();
        out.unread_bytes = r.bytesRemaining();
    }
} catch (e) {
    out.errors.push(`read: ${e.message}`);
}
out.schemas = [...schemas.values()].map((s) => ({ id: s.id, name: s.name, encoding: s.encoding }));
out.channels = [...channels.values()].map((c) => ({ id: c.id, topic: c.topic, schema: schemas.get(c.schemaId)?.name,
    encoding: c.messageEncoding }));
console.log(JSON.stringify(out));
process.exit(out.errors.length ? 1 : 0);
