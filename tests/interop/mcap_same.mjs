// mcap_same.mjs — are two MCAP recordings the same messages? Each file is
// read with @mcap/core (indexed), every message decoded with protobufjs from
// the schemas the file carries, and keyed by topic, header source, epoch and
// sequence number. A message is the same when its decoded fields are equal,
// but for the header's exercise id (a replay runs in an exercise of its
// own). Prints one JSON object: messages per file, the same, those only in
// one file (their first few keys), those that differ (the first few, with
// both sides), and topics left out (--ignore T,T..).
//
// Usage: node mcap_same.mjs A.mcap B.mcap [--ignore T,T..]
import { openIndexed } from "./mcap_open.mjs";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";

const args = process.argv.slice(2);
const ignoreAt = args.indexOf("--ignore");
const ignore = new Set(ignoreAt >= 0 ? args[ignoreAt + 1].split(",") : []);

async function load(path) {
    const { reader: r, close } = await openIndexed(path);
    const types = new Map();
    const typeOf = (sid) => {
        if (!types.has(sid)) {
            const s = r.schemasById.get(sid);
            const set = descriptor.FileDescriptorSet.decode(s.data);
            types.set(sid, protobuf.Root.fromDescriptor(set).lookupType(s.name));
        }
        return types.get(sid);
    };
    const msgs = new Map();
    let count = 0, dup = 0;
    for await (const m of r.readMessages({ validateCrcs: true })) {
        const ch = r.channelsById.get(m.channelId);
        if (ignore.has(ch.topic)) continue;
        const T = typeOf(ch.schemaId);
        const obj = T.toObject(T.decode(m.data), { longs: String, enums: String, bytes: String, defaults: false });
        const h = obj.header ?? {};
        const key = `${ch.topic}/${h.source}/${h.epoch}/${h.seq}`;
        delete h.exercise_id;
        if (msgs.has(key)) dup++;
        msgs.set(key, JSON.stringify(obj));
        count++;
    }
    await close();
    return { msgs, count, dup };
}

const [a, b] = await Promise.all([load(args[0]), load(args[1])]);
const out = { a: a.count, b: b.count, a_duplicates: a.dup, b_duplicates: b.dup, same: 0,
              only_a: 0, only_b: 0, differ: 0, examples: [], ignored: [...ignore] };
for (const [k, v] of a.msgs) {
    if (!b.msgs.has(k)) {
        out.only_a++;
        if (out.examples.length < 5) out.examples.push({ only_a: k });
    } else if (b.msgs.get(k) !== v) {
        out.differ++;
        if (out.examples.length < 5) out.examples.push({ differ: k, a: v.slice(0, 300), b: b.msgs.get(k).slice(0, 300) });
    } else out.same++;
}
for (const k of b.msgs.keys())
    if (!a.msgs.has(k)) {
        out.only_b++;
        if (out.examples.length < 5) out.examples.push({ only_b: k });
    }
console.log(JSON.stringify(out));
process.exit(out.only_a || out.only_b || out.differ ? 1 : 0);
