// mcap_open.mjs — an MCAP file opened indexed with @mcap/core (footer,
// summary, chunk indexes), its zstd chunks read with fzstd; shared by
// mcap_check.mjs and mcap_same.mjs. Returns { reader, close }.
import { open } from "node:fs/promises";
import { McapIndexedReader } from "@mcap/core";
import { decompress as zstdDecompress } from "fzstd";

export const decompressHandlers = {
    zstd: (buf, size) => zstdDecompress(buf, new Uint8Array(Number(size))),
};

export async function openIndexed(path) {
    const fh = await open(path, "r");
    const readable = {
        size: async () => BigInt((await fh.stat()).size),
        read: async (offset, size) => {
            const buf = new Uint8Array(Number(size));
            const { bytesRead } = await fh.read(buf, 0, Number(size), Number(offset));
            if (bytesRead !== Number(size)) throw new Error("short read");
            return buf;
        },
    };
    try {
        const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
        return { reader, close: () => fh.close() };
    } catch (e) {
        await fh.close();
        throw e;
    }
}
