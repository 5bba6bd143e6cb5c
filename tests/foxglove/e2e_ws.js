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
const kTopics = ["hello", "frame_prediction", "grasp_prediction", "stats", "error", "ack", "nack", "pong", "frame_image"];

// Connects, subscribes to everything advertised, collects until the server unadvertises and
// closes; calls onMessage(message) for each.
function collect(label, address, onMessage = () => {}) {
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
      onMessage(got.messages[got.messages.length - 1]);
    });
    client.on("unadvertise", (ids) => got.unadvertised.push(...ids));
    client.on("error", (e) => t.check(false, `${label}: websocket error`, e.message));
    client.on("close", () => resolve(got));
  });
}

// Clients that do not follow the protocol (run while the server waits for a subscriber): a
// handshake without the subprotocol is refused; a subscription to an unknown channel, an
// unknown operation, a non-JSON and a binary message are each answered by an error status.
async function badClients(address) {
  const refused = await new Promise((resolve) => {
    const ws = new WebSocket(`ws://${address}`);
    ws.on("unexpected-response", (req, res) => resolve(res.statusCode));
    ws.on("open", () => (ws.close(), resolve("accepted")));
    ws.on("error", () => {});
  });
  t.check(refused === 400, "a client without the foxglove.websocket.v1 subprotocol is refused (HTTP 400)", refused);
  const statuses = await new Promise((resolve) => {
    const ws = new WebSocket(`ws://${address}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const seen = [];
    ws.on("open", () => {
      ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: 999 }] }));
      ws.send(JSON.stringify({ op: "advertise", channels: [] }));
      ws.send("not json");
      ws.send(Buffer.from([1, 2, 3]));
    });
    ws.on("message", (data, binary) => {
      const j = binary ? {} : JSON.parse(data.toString());
      if (j.op === "status") seen.push(j);
      if (seen.length === 4) (ws.close(), resolve(seen));
    });
  });
  t.check(statuses.every((s) => s.level === 2), "each bad request is answered by an error status");
  t.check(/no channel 999/.test(statuses[0].message), "an unknown channel is named", statuses[0].message);
  t.check(/unsupported operation 'advertise'/.test(statuses[1].message), "an unsupported operation is named", statuses[1].message);
  t.check(/JSON object/.test(statuses[2].message) && /binary/.test(statuses[3].message), "non-JSON and binary messages",
          JSON.stringify(statuses.slice(2)));
}

// A client that comes late (after the board's Hello went out) and subscribes to /tlvlink/hello
// only: it gets that Hello at once (the channel is latched), and nothing else.
function lateHelloSubscriber(address) {
  return new Promise((resolve) => {
    const client = new FoxgloveClient({ ws: new WebSocket(`ws://${address}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
    const texts = [];
    client.on("advertise", (channels) => client.subscribe(channels.find((c) => c.topic === "/tlvlink/hello").id));
    client.on("message", ({ data }) => texts.push(new TextDecoder().decode(data)));
    client.on("close", () => resolve(texts));
  });
}

async function serveAndCompare(label, args, before, late = false) {
  const server = await t.startServing(tlvlink, args);
  t.check(/^127\.0\.0\.1:\d+$/.test(server.address), `${label}: serving on 127.0.0.1 (${server.address})`);
  if (before) await before(server.address);
  let lateClient;
  const got = await collect(label, server.address, (m) => {
    if (late && !lateClient && m.channel.topic === "/tlvlink/frame_prediction") lateClient = lateHelloSubscriber(server.address);
  });
  if (late) {
    const hellos = await lateClient;
    const first = got.messages.find((m) => m.channel.topic === "/tlvlink/hello");
    t.check(hellos.length === 1 && first && hellos[0] === first.text, `${label}: a late subscriber to /tlvlink/hello gets the board's Hello`,
            `${hellos.length} messages`);
  }
  const done = await server.exited;
  t.check(done.code === 0, `${label}: tlvlink exited 0`, done.stderr.slice(-2000));
  const lines = t.messageLines(done.stdout);

  t.check(got.info && got.info.name === "tlvlink" && Array.isArray(got.info.capabilities), `${label}: serverInfo`);
  t.check(got.channels.length === kTopics.length, `${label}: ${kTopics.length} channels advertised`, got.channels.map((c) => c.topic));
  const schemas = new Map();
  for (const type of kTopics) {
    const c = got.channels.find((x) => x.topic === `/tlvlink/${type}`);
    if (!t.check(c !== undefined, `${label}: channel /tlvlink/${type} advertised`)) continue;
    const name = type === "frame_image" ? "foxglove.CompressedImage" : `tlvlink.`;
    t.check(c.encoding === "json" && c.schemaEncoding === "jsonschema" && c.schemaName.startsWith(name),
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
    if (lines[i]?.type === "frame_image") {
      t.check(t.undeclaredKeys(json, schemas.get(m.channel.id), m.channel.topic).length === 0,
              `${label}: a frame image's keys (frame_id too) are in its schema`);
      t.checkCompressedImage(label, json, lines[i]);
    }
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
  const clients = before || late ? "2" : "1";  // the bad or the late client connected too
  const sent = lines.length + (late ? 1 : 0);  // and the late client's Hello
  t.check(summary && summary[1] === clients && Number(summary[2]) === sent && summary[3] === "0",
          `${label}: the server reports ${clients} clients, every message sent, none dropped`, summary && summary[0]);
  return lines;
}

// A client that stops reading: the listener goes on printing (it never waits for a client), the
// server drops that client's oldest queued messages and counts them. The client reads again
// once the session has ended (its last stdout line), while the server drains: it receives the
// printed messages minus the dropped ones, in order, the last one included.
async function slowClient(tty) {
  // The listener waits (--foxglove-wait) for this client before opening the link; the board
  // starts once the client is subscribed and has stopped reading, so the listener sees it all.
  let board;
  const server = await t.startServing(tlvlink, ["listen", "--serial", tty, "--json", "--count", "8000", "--duration", "60",
                                                "--foxglove", "127.0.0.1:0", "--foxglove-queue", "16", "--foxglove-wait", "20"]);
  const got = await new Promise((resolve) => {
    const ws = new WebSocket(`ws://${server.address}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new FoxgloveClient({ ws });
    const texts = [];
    client.on("advertise", (channels) => {
      for (const c of channels) client.subscribe(c.id);
      ws._socket.pause();  // reads nothing more until the session is over
      // Twice what the listener waits for, at half the former pace: 12,000 at 4000/s beside the
      // other stages lost more than a third on the way (the board's send queue drops the oldest
      // when the pty is full) and the count was never reached (2026-12-05: 7,319 of 8,000 in
      // the 60 s). Fewer messages would fit in the paused socket's buffers: nothing to drop.
      board = t.startBoard(streamCheck, tty, 16000, 2000, ["--embedding"]);
      let out = "";
      server.process.stdout.on("data", (d) => {
        out = (out + d).slice(-4096);
        if (out.includes('{"type":"link_stats"')) ws._socket.resume();
      });
    });
    client.on("message", ({ data }) => texts.push(new TextDecoder().decode(data)));
    client.on("close", () => resolve(texts));
  });
  const done = await server.exited;
  (await board).kill("SIGTERM");
  t.check(done.code === 0, "slow client: tlvlink exited 0", done.stderr.slice(-2000));
  const lines = t.messageLines(done.stdout).map((l) => JSON.stringify(l));
  t.check(lines.length >= 8001, `slow client: the listener printed every message (${lines.length})`);
  const summary = /foxglove: (\d+) clients, (\d+) messages sent, (\d+) dropped/.exec(done.stderr);
  const dropped = summary ? Number(summary[3]) : -1;
  console.log(`slow client: ${summary && summary[0]}`);
  t.check(dropped > 0, `slow client: the server dropped and counted (${dropped})`, summary && summary[0]);
  t.check(got.length + dropped === lines.length, `slow client: received ${got.length} + dropped ${dropped} = printed ${lines.length}`);
  let j = 0;
  for (const text of got) {
    const { json } = t.splitTimestamp(text);
    const s = JSON.stringify(json);
    while (j < lines.length && lines[j] !== s) j++;
    j++;
  }
  t.check(j <= lines.length, "slow client: what arrived is the printed messages in order, some left out");
  t.check(got.length > 0 && JSON.stringify(t.splitTimestamp(got[got.length - 1]).json) === lines[lines.length - 1],
          "slow client: the oldest were dropped: the last message arrived");
}

(async () => {
  const fixture = path.join(work, "fixture.tlvrec");
  t.check(t.run(streamCheck, ["record", fixture]).code === 0, "fixture recording written");
  const replayed = await serveAndCompare("replay", ["replay", fixture, "--json", "--foxglove", "127.0.0.1:0", "--foxglove-wait", "20"],
                                         badClients);
  t.check(replayed.length >= 13, `replay: the fixture's messages (${replayed.length})`);

  const tty = path.join(work, "tty");
  const board = await t.startBoard(streamCheck, tty, 200, 400, ["--images", "10"]);
  const live = await serveAndCompare("live", ["listen", "--serial", tty, "--json", "--count", "200", "--duration", "30",
                                              "--foxglove", "127.0.0.1:0", "--foxglove-wait", "20"], undefined, true);
  board.kill("SIGTERM");
  t.check(live.filter((l) => l.type === "frame_prediction").length === 200, "live: 200 predictions");
  t.check(live.filter((l) => l.type === "frame_image").length >= 19, "live: the fake board's frame images (one every 10 predictions)",
          live.filter((l) => l.type === "frame_image").length);
  await slowClient(path.join(work, "tty-slow"));
  t.finish("e2e_ws");
})().catch((e) => {
  console.error(e);
  process.exit(1);
});
