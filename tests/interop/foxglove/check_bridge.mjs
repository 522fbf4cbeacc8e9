// A live client of hcosim's Foxglove bridge built on Foxglove's own
// libraries: @foxglove/ws-protocol's FoxgloveClient over `ws`, each
// message decoded with its advertised OMG IDL schema by
// @foxglove/omgidl-parser and @foxglove/omgidl-serialization.
//
// node check_bridge.mjs URL SECONDS MESH CAMERA [--stall | --finite TOPIC]
// Subscribes to scene/MESH, image/CAMERA and DeformedMesh for SECONDS,
// checks every scene update's triangle list against the latest
// DeformedMesh of MESH, every image as a JPEG, and prints one JSON line of
// what arrived. --stall: subscribes to every channel and then stops
// reading its socket (a client that hangs), printing what it saw until then.
// --finite TOPIC: subscribes to TOPIC alone and fails on any sample with a
// number that is not finite (the bridge refuses NaN from DDS); with a
// `seq` field, prints the first and last seq it received (`seq`), so that
// the caller can tell how many were lost between them.
import wsProtocol from "@foxglove/ws-protocol";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol; // a CommonJS module

const [url, seconds, mesh, camera, mode, finiteTopic] = process.argv.slice(2);
const stall = mode === "--stall";
const finite = mode === "--finite";
const fail = (why) => {
  console.error(`check_bridge: ${why}`);
  process.exit(1);
};
const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const channels = new Map(); // id -> {channel, reader}
const subs = new Map(); // subscription id -> channel
const seen = new Map(); // topic -> {count, first, last, bytes}
let serverInfo;
let times = 0;
let lastMesh; // the latest DeformedMesh of MESH
let checked = 0;
let closed;
let seq; // --finite: {first, last} of the samples' seq
const wanted = stall ? null : new Set(finite ? [finiteTopic] : [`scene/${mesh}`, `image/${camera}`, "DeformedMesh"]);
// Every number in a decoded message, nested fields included.
const numbers = (v) =>
  typeof v === "number" ? [v]
  : v && typeof v === "object" ? Object.values(v).flatMap(numbers)
  : [];

client.on("error", (e) => fail(`client error: ${e?.message ?? e}`));
client.on("close", (e) => (closed = { code: e.code, reason: String(e.reason ?? "") }));
client.on("serverInfo", (info) => (serverInfo = info));
client.on("status", (s) => fail(`server status ${s.level}: ${s.message}`));
client.on("time", () => ++times);
client.on("advertise", (list) => {
  for (const c of list) {
    if (c.encoding !== "cdr" || c.schemaEncoding !== "omgidl") fail(`${c.topic}: ${c.encoding}/${c.schemaEncoding}`);
    const reader = new MessageReader(c.schemaName, parseIDL(c.schema));
    channels.set(c.id, { channel: c, reader });
    if (stall || wanted.has(c.topic)) subs.set(client.subscribe(c.id), c);
  }
  if (stall && subs.size > 0 && !ws.stalled) {
    // Stop reading after a moment of traffic: the server's sends pile up.
    setTimeout(() => {
      ws.stalled = true;
      ws._socket.pause();
    }, 500);
  }
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const c = subs.get(subscriptionId);
  if (!c) fail(`a message for subscription ${subscriptionId}, never made`);
  const m = channels.get(c.id).reader.readMessage(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
  const now = performance.now();
  const s = seen.get(c.topic) ?? { count: 0, first: now, last: now, bytes: 0 };
  ++s.count, (s.last = now), (s.bytes += data.byteLength);
  seen.set(c.topic, s);
  if (stall) return;
  if (finite && numbers(m).some((x) => !Number.isFinite(x))) fail(`${c.topic}: a sample with a number not finite`);
  if (finite && m.seq !== undefined) {
    const n = Number(m.seq);
    seq = { first: Math.min(seq?.first ?? n, n), last: Math.max(seq?.last ?? n, n) };
  }
  if (c.topic === "DeformedMesh" && m.mesh === mesh) lastMesh = m;
  if (c.topic === `scene/${mesh}`) {
    const e = m.entities?.[0];
    if (m.entities.length !== 1 || e.id !== mesh || e.frame_id !== "world" || e.triangles.length !== 1)
      fail(`scene/${mesh}: not one entity ${mesh} in world with one triangle list`);
    const t = e.triangles[0];
    if (t.indices.length % 3 !== 0 || t.indices.some((i) => i >= t.points.length))
      fail(`scene/${mesh}: ${t.indices.length} indices into ${t.points.length} points`);
    if (lastMesh) {
      if (t.points.length * 3 !== lastMesh.positions.length)
        fail(`scene/${mesh}: ${t.points.length} points, its DeformedMesh ${lastMesh.positions.length / 3} vertices`);
      ++checked;
    }
  }
  if (c.topic === `image/${camera}`) {
    if (m.format !== "jpeg" || m.data[0] !== 0xff || m.data[1] !== 0xd8 || m.frame_id !== camera)
      fail(`image/${camera}: not a JPEG in frame ${camera}`);
  }
});

setTimeout(() => {
  const rates = {};
  for (const [topic, s] of seen)
    rates[topic] = { count: s.count, hz: s.count > 1 ? (1000 * (s.count - 1)) / (s.last - s.first) : 0, bytes: s.bytes };
  const points = lastMesh ? lastMesh.positions.length / 3 : 0;
  console.log(JSON.stringify({ server: serverInfo?.name, capabilities: serverInfo?.capabilities,
    channels: [...channels.values()].map((c) => c.channel.topic), subscribed: subs.size, rates, mesh_vertices: points,
    scene_checked: checked, times, closed, seq }));
  process.exit(0);
}, Number(seconds) * 1000);
