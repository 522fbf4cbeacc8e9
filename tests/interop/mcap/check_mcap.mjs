// Reads an hcosim MCAP recording with MCAP's and Foxglove's own libraries,
// none of it written from hcosim's code: @mcap/core's stream reader
// checks every CRC record by record, its indexed reader seeks through the
// summary, @foxglove/omgidl-parser parses each channel's schema and
// @foxglove/omgidl-serialization decodes every message with it. The
// decoded samples must equal `hcosim export --wall` of the same file.
// Usage: node check_mcap.mjs REC.mcap EXPORT_DIR (TOPIC.jsonl per topic).
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import { open, readFile } from "node:fs/promises";

const [file, exportDir] = process.argv.slice(2);
const fail = (what) => {
  console.error(`check_mcap: ${what}`);
  process.exit(1);
};
const decompressHandlers = await loadDecompressHandlers();

// Every record in file order, CRCs checked.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(await readFile(file));
const counted = new Map();
let records = 0, streamed = 0, dataEnd = false, footer = false;
const times = [];
for (let r; (r = stream.nextRecord()); ++records) {
  if (r.type === "Message") {
    counted.set(r.channelId, (counted.get(r.channelId) ?? 0) + 1);
    times.push(r.logTime);
    ++streamed;
  }
  if (r.type === "DataEnd") dataEnd = true;
  if (r.type === "Footer") footer = true;
}
if (!stream.done()) fail(`the stream reader stopped with ${stream.bytesRemaining()} bytes left`);
if (!dataEnd || !footer) fail("no data end or footer record");

// The summary, and seeking through its indexes.
const handle = await open(file, "r");
const readable = {
  size: async () => BigInt((await handle.stat()).size),
  read: async (offset, size) => {
    const b = new Uint8Array(Number(size));
    await handle.read(b, 0, b.length, Number(offset));
    return b;
  },
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
const stats = reader.statistics;
if (!stats || stats.messageCount !== BigInt(streamed))
  fail(`statistics count ${stats?.messageCount} messages, the file holds ${streamed}`);
for (const [id, n] of counted)
  if (stats.channelMessageCounts.get(id) !== BigInt(n)) fail(`channel ${id}: statistics ${stats.channelMessageCounts.get(id)}, file ${n}`);
if (reader.chunkIndexes.length === 0) fail("no chunk index");
times.sort((a, b) => (a < b ? -1 : a > b ? 1 : 0));
const middle = times[Math.floor(times.length / 2)];
let after = 0;
for await (const m of reader.readMessages({ startTime: middle, validateCrcs: true })) {
  if (m.logTime < middle) fail(`a seek from ${middle} gave a message at ${m.logTime}`);
  ++after;
}
const want = times.filter((t) => t >= middle).length;
if (after !== want) fail(`a seek from the middle read ${after} messages, ${want} are there`);

// Each channel's schema parsed, its messages decoded.
const decoders = new Map();
for (const [id, c] of reader.channelsById) {
  const s = reader.schemasById.get(c.schemaId);
  if (c.messageEncoding !== "cdr" || s.encoding !== "omgidl") fail(`channel ${c.topic}: ${c.messageEncoding}, ${s.encoding}`);
  const definitions = parseIDL(new TextDecoder().decode(s.data));
  decoders.set(id, { topic: c.topic, reader: new MessageReader(s.name, definitions) });
}
const plain = (v) => {
  if (typeof v === "bigint") return Number(v);
  if (ArrayBuffer.isView(v)) return Array.from(v, plain);
  if (Array.isArray(v)) return v.map(plain);
  if (v && typeof v === "object") return Object.fromEntries(Object.entries(v).map(([k, x]) => [k, plain(x)]));
  return v;
};
const decoded = new Map();
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const d = decoders.get(m.channelId);
  let sample = plain(d.reader.readMessage(m.data));
  // hcosim export gives an image's size, not its bytes.
  if (d.topic === "CameraFrame") {
    const { data, ...rest } = sample;
    sample = { ...rest, data_bytes: data.length };
  }
  if (!decoded.has(d.topic)) decoded.set(d.topic, []);
  decoded.get(d.topic).push(sample);
}
await handle.close();

// Against hcosim export: the same samples, field by field. Its floats are
// their shortest text, so a float32 read back is fround of the text. Both
// lists are put in one order by their text, integers (steps, stamps) exact
// so that two nearly equal meshes a step apart never tie.
const canonical = (v) =>
  Array.isArray(v) ? `[${v.map(canonical).join(",")}]`
  : v && typeof v === "object" ? `{${Object.keys(v).sort().map((k) => `${k}:${canonical(v[k])}`).join(",")}}`
  : typeof v === "number" ? (Number.isInteger(v) ? v.toString() : Number(v.toPrecision(6)).toString())
  : JSON.stringify(v);
const same = (a, b, path) => {
  if (typeof a === "number" && typeof b === "number") {
    if (a === b || Math.fround(a) === b || (Number.isNaN(b) && a === null)) return;
    fail(`${path}: hcosim export ${a}, decoded ${b}`);
  }
  if (a === null && typeof b === "number" && !Number.isFinite(b)) return;
  if (Array.isArray(a) || (a && typeof a === "object")) {
    const ka = Object.keys(a).sort(), kb = Object.keys(b ?? {}).sort();
    if (ka.join() !== kb.join()) fail(`${path}: fields ${ka} in hcosim export, ${kb} decoded`);
    for (const k of ka) same(a[k], b[k], `${path}.${k}`);
    return;
  }
  if (a !== b) fail(`${path}: hcosim export ${JSON.stringify(a)}, decoded ${JSON.stringify(b)}`);
};
let compared = 0;
for (const [topic, samples] of decoded) {
  const text = await readFile(`${exportDir}/${topic}.jsonl`, "utf8");
  const exported = text.split("\n").filter((l) => l).map((l) => JSON.parse(l));
  if (exported.length !== samples.length) fail(`${topic}: ${exported.length} exported, ${samples.length} decoded`);
  const order = (list) => list.map((s) => [canonical(s), s]).sort((x, y) => (x[0] < y[0] ? -1 : x[0] > y[0] ? 1 : 0));
  const a = order(exported), b = order(samples);
  for (let i = 0; i < a.length; ++i) same(a[i][1], b[i][1], `${topic}[${i}]`);
  compared += samples.length;
}
const compression = [...new Set(reader.chunkIndexes.map((c) => c.compression || "none"))].join(",");
console.log(`check_mcap: ${streamed} messages on ${reader.channelsById.size} channels in ${reader.chunkIndexes.length} ` +
  `chunks (${compression}), CRCs checked, a seek from the middle read ${after}; ${compared} decoded equal hcosim export`);
