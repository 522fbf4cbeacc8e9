// Writes an MCAP file with MCAP's own writer (@mcap/core), its messages
// encoded by Foxglove's (@foxglove/omgidl-serialization) from the schema
// alone: the HapticState samples of an hcosim recording, decoded and
// encoded again, on a channel of its own numbering, in chunks. hcosim
// replay must play it into a service as it plays its own recordings.
// Usage: node write_mcap.mjs IN.mcap OUT.mcap
import { McapIndexedReader, McapWriter } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader, MessageWriter } from "@foxglove/omgidl-serialization";
import { open } from "node:fs/promises";

const [input, output] = process.argv.slice(2);
const handle = await open(input, "r");
const reader = await McapIndexedReader.Initialize({
  readable: {
    size: async () => BigInt((await handle.stat()).size),
    read: async (offset, size) => {
      const b = new Uint8Array(Number(size));
      await handle.read(b, 0, b.length, Number(offset));
      return b;
    },
  },
  decompressHandlers: await loadDecompressHandlers(),
});
const [id, channel] = [...reader.channelsById].find(([, c]) => c.topic === "HapticState");
const schema = reader.schemasById.get(channel.schemaId);
const definitions = parseIDL(new TextDecoder().decode(schema.data));
const decode = new MessageReader(schema.name, definitions);
const encode = new MessageWriter(schema.name, definitions, { kind: 0x01 /* CDR_LE */ });

const out = await open(output, "w");
let position = 0n;
const writer = new McapWriter({
  writable: {
    position: () => position,
    write: async (buffer) => {
      await out.write(buffer);
      position += BigInt(buffer.byteLength);
    },
  },
  chunkSize: 64 * 1024,
});
await writer.start({ profile: "", library: "write_mcap.mjs" });
await writer.registerSchema({ name: "unused", encoding: "jsonschema", data: new TextEncoder().encode("{}") });
const schemaId = await writer.registerSchema({ name: schema.name, encoding: "omgidl", data: schema.data });
const channelId = await writer.registerChannel({ topic: "HapticState", schemaId, messageEncoding: "cdr", metadata: new Map() });
let n = 0;
for await (const m of reader.readMessages({ topics: ["HapticState"] })) {
  const data = encode.writeMessage(decode.readMessage(m.data));
  await writer.addMessage({ channelId, sequence: n++, logTime: m.logTime, publishTime: m.publishTime, data });
}
await writer.end();
await out.close();
await handle.close();
if (n === 0 || id === undefined) {
  console.error("write_mcap: no HapticState in " + input);
  process.exit(1);
}
console.log(`write_mcap: ${n} HapticState samples written to ${output} by @mcap/core`);
