// @foxglove/ws-protocol's client (FoxgloveClient, on the ws package) against tlvlink's Foxglove
// WebSocket server: `tlvlink replay FIXTURE --json --foxglove 127.0.0.1:0` and `tlvlink listen
// --json --foxglove 127.0.0.1:0` on the fake board. Checks serverInfo, the advertised channels
// and their schemas, subscribes to every channel, and compares every received message (and its
// timestamp) with the JSON lines the same run printed; then that the server unadvertises and
// closes at the end, and reports no drop. The server's readiness is its stderr line
// "foxglove: serving on HOST:PORT" (port 0: it picks a free one); --foxglove-wait holds the
// session until this client is subscribed to every channel.
"use strict";
const path = require("path");
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const { WebSocket } = require("ws");
const t = require("./e2e_common");

const [tlvlink, streamCheck, work] = process.argv.slice(2);
const kTopics = ["hello", "frame_prediction", "grasp_prediction", "stats", "error", "ack", "nack", "pong"];

// Connects, subscribes to everything advertised, collects until the server unadvertises and closes.
function collect(label, address) {
  return new Promise((resolve) => {
    const ws = new WebSocket(`ws://${address}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new FoxgloveClient({ ws });
    const got = { info: undefined, channels: [], messages: [], unadvertised: [], statuses: [] };
    const channelOf = new Map();  // subscription id -> channel
    client.on("serverInfo", (info) => (got.info = info));
    client.on("status", (s) => got.statuses.push(s));
    client.on("advertise", (channels) => {
      got.channels.push(...channels);
      for (const c of channels) channelOf.set(client.subscribe(c.id), c);
    });
    client.on("message", ({ subscriptionId, timestamp, data }) => {
      got.messages.push({ channel: channelOf.get(subscriptionId), timestamp, text: new TextDecoder().decode(data) });
    });
    client.on("unadvertise", (ids) => got.unadvertised.push(...ids));
    client.on("error", (e) => t.check(false, `${label}: websocket error`, e.message));
    client.on("close", () => resolve(got));
  });
}

async function serveAndCompare(label, args) {
  const server = await t.startServing(tlvlink, args);
  t.check(/^127\.0\.0\.1:\d+$/.test(server.address), `${label}: serving on 127.0.0.1 (${server.address})`);
  const got = await collect(label, server.address);
  const done = await server.exited;
  t.check(done.code === 0, `${label}: tlvlink exited 0`, done.stderr.slice(-2000));
  const lines = t.messageLines(done.stdout);

  t.check(got.info && got.info.name === "tlvlink" && Array.isArray(got.info.capabilities), `${label}: serverInfo`);
  t.check(got.channels.length === kTopics.length, `${label}: ${kTopics.length} channels advertised`, got.channels.map((c) => c.topic));
  const schemas = new Map();
  for (const type of kTopics) {
    const c = got.channels.find((x) => x.topic === `/tlvlink/${type}`);
    if (!t.check(c !== undefined, `${label}: channel /tlvlink/${type} advertised`)) continue;
    t.check(c.encoding === "json" && c.schemaEncoding === "jsonschema" && c.schemaName.startsWith("tlvlink."),
            `${label}: /tlvlink/${type}: json with a jsonschema`, JSON.stringify({ ...c, schema: undefined }));
    const schema = JSON.parse(c.schema);
    t.check(schema.type === "object" && schema.properties.timestamp, `${label}: ${c.schemaName} schema parses`);
    schemas.set(c.id, schema);
  }
  t.check(got.statuses.length === 0, `${label}: no error status`, JSON.stringify(got.statuses));

  t.check(got.messages.length === lines.length, `${label}: every printed message received`, `${got.messages.length} vs ${lines.length}`);
  let same = 0;
  let stamped = 0;
  let declared = 0;
  got.messages.forEach((m, i) => {
    const { json, ns } = t.splitTimestamp(m.text);
    if (JSON.stringify(json) === JSON.stringify(lines[i]) && m.channel.topic === `/tlvlink/${lines[i]?.type}`) same++;
    else if (same === i) t.check(false, `${label}: message ${i} equals its line`, `${m.text}\n  vs ${JSON.stringify(lines[i])}`);
    if (ns === m.timestamp) stamped++;
    if (t.undeclaredKeys(json, schemas.get(m.channel.id), m.channel.topic).length === 0) declared++;
  });
  t.check(same === lines.length, `${label}: every message equals its printed line, in order (${same} of ${lines.length})`);
  t.check(stamped === lines.length, `${label}: every messageData timestamp is the message's timestamp (${stamped})`);
  t.check(declared === lines.length, `${label}: every key of every message is in its schema (${declared})`);
  t.check(got.unadvertised.length === kTopics.length, `${label}: every channel unadvertised at the end`);
  const summary = /foxglove: (\d+) clients, (\d+) messages sent, (\d+) dropped/.exec(done.stderr);
  t.check(summary && summary[1] === "1" && Number(summary[2]) === lines.length && summary[3] === "0",
          `${label}: the server reports 1 client, every message sent, none dropped`, summary && summary[0]);
  return lines;
}

(async () => {
  const fixture = path.join(work, "fixture.tlvrec");
  t.check(t.run(streamCheck, ["record", fixture]).code === 0, "fixture recording written");
  const replayed = await serveAndCompare("replay", ["replay", fixture, "--json", "--foxglove", "127.0.0.1:0", "--foxglove-wait", "20"]);
  t.check(replayed.length >= 13, `replay: the fixture's messages (${replayed.length})`);

  const tty = path.join(work, "tty");
  const board = await t.startBoard(streamCheck, tty, 200, 400);
  const live = await serveAndCompare("live", ["listen", "--serial", tty, "--json", "--count", "200", "--duration", "30",
                                              "--foxglove", "127.0.0.1:0", "--foxglove-wait", "20"]);
  board.kill("SIGTERM");
  t.check(live.filter((l) => l.type === "frame_prediction").length === 200, "live: 200 predictions");
  t.finish("e2e_ws");
})().catch((e) => {
  console.error(e);
  process.exit(1);
});
