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
const scene = new Map();  // Foxglove's channels: by topic, their decoded messages
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const d = decoders.get(m.channelId);
  if (reader.schemasById.get(reader.channelsById.get(m.channelId).schemaId).name.startsWith("foxglove::")) {
    if (!scene.has(d.topic)) scene.set(d.topic, []);
    scene.get(d.topic).push(d.reader.readMessage(m.data));
    continue;
  }
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
// lists are put in one order by their text, every number as the float32
// nearest it (the same for a sample in both lists, where rounding to a few
// digits split a float and its text at a boundary) and integers (steps,
// stamps) exact.
const canonical = (v) =>
  Array.isArray(v) ? `[${v.map(canonical).join(",")}]`
  : v && typeof v === "object" ? `{${Object.keys(v).sort().map((k) => `${k}:${canonical(v[k])}`).join(",")}}`
  : typeof v === "number" ? (Number.isInteger(v) ? v.toString() : Math.fround(v).toString())
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
// The scene channels against the topics they come from: a mesh's
// triangle list has its DeformedMesh's vertices and its topology's
// triangles, every camera frame is a JPEG, the camera's pose follows the
// marker's, the stylus shows at most 60 times a simulated second.
const sceneNotes = [];
const topology = new Map((decoded.get("DeformedMeshTopology") ?? []).map((t) => [t.mesh, t]));
for (const [topic, messages] of scene) {
  const [kind, name] = topic.split("/");
  if (kind === "scene" && name !== "stylus") {
    const meshes = (decoded.get("DeformedMesh") ?? []).filter((m) => m.mesh === name);
    for (const [i, u] of messages.entries()) {
      const e = u.entities[0];
      if (u.entities.length !== 1 || e.id !== name || e.frame_id !== "world" || e.triangles.length !== 1)
        fail(`${topic}[${i}]: not one entity ${name} in world with one triangle list`);
      const t = e.triangles[0];
      if (meshes.length > 0) {
        const m = meshes[meshes.length - messages.length + i];
        if (t.points.length * 3 !== m.positions.length) fail(`${topic}[${i}]: ${t.points.length} points, its DeformedMesh ${m.positions.length / 3}`);
        if (Math.fround(t.points[0].x) !== m.positions[0]) fail(`${topic}[${i}]: first point ${t.points[0].x}, mesh ${m.positions[0]}`);
        const top = topology.get(name);
        if (top && t.indices.length !== top.triangles.length) fail(`${topic}[${i}]: ${t.indices.length} indices, topology ${top.triangles.length}`);
      } else if (t.points.length === 0) fail(`${topic}[${i}]: an empty body`);
    }
    if (meshes.length > 0 && messages.length < meshes.length - 1)
      fail(`${topic}: ${messages.length} scene updates for ${meshes.length} meshes`);
    sceneNotes.push(`${topic} ${messages.length} (${messages[0].entities[0].triangles[0].points.length} points)`);
  } else if (kind === "image") {
    const frames = (decoded.get("CameraFrame") ?? []).filter((f) => f.camera === name);
    if (messages.length !== frames.length) fail(`${topic}: ${messages.length} images, ${frames.length} camera frames`);
    for (const im of messages)
      if (im.format !== "jpeg" || im.data[0] !== 0xff || im.data[1] !== 0xd8 || im.frame_id !== name) fail(`${topic}: not a JPEG in ${name}`);
    sceneNotes.push(`${topic} ${messages.length} JPEG`);
  } else if (topic === "tf") {
    const poses = (decoded.get("MarkerPose") ?? []).filter((p) => p.tag_id === 0);
    if (messages.length !== poses.length) fail(`tf: ${messages.length} transforms, ${poses.length} marker poses`);
    sceneNotes.push(`tf ${messages.length}`);
  } else if (topic === "scene/stylus") {
    const states = decoded.get("HapticState") ?? [];
    const span = states.length ? (states[states.length - 1].stamp.sim_time_ns - states[0].stamp.sim_time_ns) / 1e9 : 0;
    if (messages.length > 60 * span + 2) fail(`scene/stylus: ${messages.length} in ${span} s`);
    sceneNotes.push(`scene/stylus ${messages.length}`);
  }
}
const compression = [...new Set(reader.chunkIndexes.map((c) => c.compression || "none"))].join(",");
const sceneMessages = [...scene.values()].reduce((n, l) => n + l.length, 0);
console.log(`check_mcap: ${streamed - sceneMessages} messages on ${reader.channelsById.size - scene.size} channels and ` +
  `${sceneMessages} on ${scene.size} scene channels in ${reader.chunkIndexes.length} chunks (${compression}), ` +
  `CRCs checked, a seek from the middle read ${after}; ${compared} decoded equal hcosim export; ` +
  `scene: ${sceneNotes.join(", ") || "none"}`);
