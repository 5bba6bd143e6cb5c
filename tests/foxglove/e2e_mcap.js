// @mcap/core (the reader Foxglove uses) on tlvlink's MCAP recordings: of a replayed fixture
// recording (`tlvlink replay FIXTURE --json --record x.mcap`) and of a live session on the fake
// board (`tlvlink listen --json --record live.mcap`). Checks the channels, their schemas and
// every message against the JSON lines the same run printed: counts equal, content equal, the
// `timestamp` key equal to the log time; with the indexed reader (summary, chunk indexes, CRCs)
// and the streaming reader (every record, CRCs validated).
"use strict";
const fs = require("fs");
const path = require("path");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const t = require("./e2e_common");

const [tlvlink, streamCheck, work] = process.argv.slice(2);
const kTopics = ["hello", "frame_prediction", "grasp_prediction", "stats", "error", "ack", "nack", "pong", "frame_image"];

function streamRead(bytes) {
  const reader = new McapStreamReader({ validateCrcs: true });
  reader.append(bytes);
  const records = [];
  for (let r; (r = reader.nextRecord()); ) records.push(r);
  t.check(reader.done(), "the streaming reader reached the end of the file");
  return records;
}

async function checkFile(label, file, lines) {
  const bytes = fs.readFileSync(file);
  const readable = { size: async () => BigInt(bytes.length), read: async (o, n) => bytes.subarray(Number(o), Number(o + n)) };
  const indexed = await McapIndexedReader.Initialize({ readable });

  // Channels and schemas.
  const byTopic = new Map([...indexed.channelsById.values()].map((c) => [c.topic, c]));
  for (const type of kTopics) {
    const c = byTopic.get(`/tlvlink/${type}`);
    if (!t.check(c !== undefined, `${label}: channel /tlvlink/${type}`)) continue;
    t.check(c.messageEncoding === "json", `${label}: /tlvlink/${type} is json`, c.messageEncoding);
    const schema = indexed.schemasById.get(c.schemaId);
    t.check(schema && schema.encoding === "jsonschema", `${label}: /tlvlink/${type} has a jsonschema schema`);
    const parsed = JSON.parse(new TextDecoder().decode(schema.data));
    if (type === "frame_image") t.check(schema.name === "foxglove.CompressedImage", `${label}: the image channel's schema is foxglove.CompressedImage`, schema.name);
    t.check(parsed.type === "object" && parsed.properties.timestamp, `${label}: ${schema.name} is an object schema with timestamp`);
  }
  const records = byTopic.get("/tlvlink/records");
  t.check(records && records.messageEncoding === "tlvlink.record" && records.schemaId === 0,
          `${label}: the raw record channel (replay) has no schema`);
  t.check(byTopic.size === kTopics.length + 1, `${label}: ${kTopics.length} JSON channels and the record channel`, [...byTopic.keys()]);

  // The streaming reader: every message in file order equals the printed lines, in order.
  const streamed = streamRead(bytes).filter((r) => r.type === "Message" && r.channelId !== records.id);
  t.check(streamed.length === lines.length, `${label}: as many JSON messages as printed lines`, `${streamed.length} vs ${lines.length}`);
  const channels = indexed.channelsById;
  const schemas = new Map([...channels.values()].map((c) => [c.id, JSON.parse(new TextDecoder().decode(indexed.schemasById.get(c.schemaId)?.data ?? new Uint8Array([123, 125])))]));
  let same = 0;
  let stamped = 0;
  let declared = 0;
  streamed.forEach((m, i) => {
    const { json, ns } = t.splitTimestamp(new TextDecoder().decode(m.data));
    if (lines[i].type === "frame_image") t.checkCompressedImage(label, json, lines[i]);
    if (JSON.stringify(json) === JSON.stringify(lines[i]) && channels.get(m.channelId).topic === `/tlvlink/${lines[i].type}`) same++;
    else if (same === i) t.check(false, `${label}: message ${i} equals its line`, `${JSON.stringify(json)}\n  vs ${JSON.stringify(lines[i])}`);
    if (ns === m.logTime) stamped++;
    if (t.undeclaredKeys(json, schemas.get(m.channelId), lines[i].type).length === 0) declared++;
  });
  t.check(same === lines.length, `${label}: every message equals its printed line (${same} of ${lines.length})`);
  t.check(stamped === lines.length, `${label}: every timestamp is the log time (${stamped} of ${lines.length})`);
  t.check(declared === lines.length, `${label}: every key of every message is in its schema (${declared} of ${lines.length})`);

  // The indexed reader: statistics, and every message again (in log-time order: compared per channel).
  const recordCount = [...indexed.chunkIndexes].length;
  t.check(recordCount > 0, `${label}: chunk indexes present`);
  const all = [];
  for await (const m of indexed.readMessages()) all.push(m);
  t.check(BigInt(all.length) === indexed.statistics.messageCount, `${label}: the indexed reader reads every message the statistics count`);
  const perChannel = (list, id) => list.filter((m) => m.channelId === id).sort((a, b) => a.sequence - b.sequence);
  let indexedSame = 0;
  for (const type of kTopics) {
    const id = byTopic.get(`/tlvlink/${type}`).id;
    const got = perChannel(all, id).map((m) => t.withoutFrameId(t.splitTimestamp(new TextDecoder().decode(m.data)).json));
    const want = lines.filter((l) => l.type === type);
    t.check(got.length === want.length, `${label}: indexed /tlvlink/${type} count`, `${got.length} vs ${want.length}`);
    got.forEach((g, i) => (indexedSame += JSON.stringify(g) === JSON.stringify(want[i]) ? 1 : 0));
  }
  t.check(indexedSame === lines.length, `${label}: the indexed reader's messages equal the lines (${indexedSame} of ${lines.length})`);
}

(async () => {
  // 1. A replayed fixture recording (every message type and case).
  const fixture = path.join(work, "fixture.tlvrec");
  t.check(t.run(streamCheck, ["record", fixture]).code === 0, "fixture recording written");
  const mcap = path.join(work, "fixture.mcap");
  const replay = t.run(tlvlink, ["replay", fixture, "--json", "--record", mcap]);
  t.check(replay.code === 0, "tlvlink replay --record x.mcap", replay.stderr);
  const lines = t.messageLines(replay.stdout);
  t.check(lines.length >= 13, `the fixture's messages printed (${lines.length})`);
  await checkFile("fixture", mcap, lines);
  const again = t.run(tlvlink, ["replay", mcap, "--json"]);
  t.check(again.code === 0 && again.stdout === t.run(tlvlink, ["replay", fixture, "--json"]).stdout,
          "tlvlink replay x.mcap prints what replaying the .tlvrec prints");

  // 2. A live session on the fake board.
  const tty = path.join(work, "tty");
  const board = await t.startBoard(streamCheck, tty, 300, 600, ["--images", "10"]);
  const live = path.join(work, "live.mcap");
  const listen = t.run(tlvlink, ["listen", "--serial", tty, "--json", "--count", "300", "--duration", "30", "--record", live]);
  board.kill("SIGTERM");
  t.check(listen.code === 0, "tlvlink listen --record live.mcap", listen.stderr);
  const liveLines = t.messageLines(listen.stdout);
  t.check(liveLines.filter((l) => l.type === "frame_prediction").length === 300, "300 predictions printed");
  t.check(liveLines.filter((l) => l.type === "frame_image").length >= 29, "the fake board's frame images printed (one every 10 predictions)",
          liveLines.filter((l) => l.type === "frame_image").length);
  await checkFile("live", live, liveLines);
  t.finish("e2e_mcap");
})().catch((e) => {
  console.error(e);
  process.exit(1);
});
