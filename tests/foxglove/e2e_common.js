// Shared by the e2e tests: running tlvlink, the listener's JSON lines, the fake board, checks.
"use strict";
const { spawn, spawnSync } = require("child_process");
const fs = require("fs");

let passed = 0;
let failed = 0;
function check(condition, what, detail) {
  if (condition) {
    passed++;
  } else {
    failed++;
    console.error(`FAILED: ${what}${detail === undefined ? "" : `\n  ${detail}`}`);
  }
  return condition;
}
function finish(name) {
  console.log(`${name}: ${passed} passed, ${failed} failed`);
  process.exit(failed === 0 && passed > 0 ? 0 : 1);
}

function run(binary, args) {
  const r = spawnSync(binary, args, { encoding: "utf8", maxBuffer: 256 << 20 });
  if (r.error) throw r.error;
  return { code: r.status, stdout: r.stdout, stderr: r.stderr };
}

// The message lines of `--json` output (the final link_stats line is the listener's, not a message).
function messageLines(stdout) {
  return stdout
    .split("\n")
    .filter((l) => l.startsWith("{"))
    .map((l) => JSON.parse(l))
    .filter((j) => j.type !== "link_stats");
}

// A channel message's JSON without its `timestamp`, and the timestamp in ns (BigInt).
function splitTimestamp(text) {
  const j = JSON.parse(text);
  const t = j.timestamp;
  delete j.timestamp;
  return { json: j, ns: t === undefined ? undefined : BigInt(t.sec) * 1000000000n + BigInt(t.nsec) };
}

// Every key of `value` (through arrays) is declared in `schema`'s properties.
function undeclaredKeys(value, schema, where, out = []) {
  if (value !== null && typeof value === "object" && !Array.isArray(value)) {
    for (const [k, v] of Object.entries(value)) {
      if (!schema.properties || !(k in schema.properties)) out.push(`${where}.${k}`);
      else undeclaredKeys(v, schema.properties[k], `${where}.${k}`, out);
    }
  } else if (Array.isArray(value) && schema.items) {
    value.forEach((v) => undeclaredKeys(v, schema.items, `${where}[]`, out));
  }
  return out;
}

// The fake board (the real Sender) on a pty; resolves once its pty exists.
async function startBoard(check_binary, tty, frames, rate, extra = []) {
  // --wait-host: the board posts once the listener has connected and synchronised its clock, so
  // a listener that opens the link late (it waits for its Foxglove client first) misses nothing.
  const board = spawn(check_binary, ["board", "--link", `pty:${tty}`, "--frames", `${frames}`, "--rate", `${rate}`,
                                     "--hold", "3", "--wait-host", "20", ...extra], { stdio: ["ignore", "ignore", "inherit"] });
  // The board creates the pty link when it is ready to serve: wait for it (bounded, 5 s).
  for (let i = 0; i < 500 && !fs.existsSync(tty); i++) await new Promise((r) => setTimeout(r, 10));
  check(fs.existsSync(tty), `the fake board made its pty ${tty}`);
  return board;
}

// Spawns tlvlink and resolves with its "foxglove: serving on HOST:PORT" address (the readiness
// line on stderr) and a promise of its exit {code, stdout, stderr}.
function startServing(binary, args) {
  return new Promise((resolve, reject) => {
    const p = spawn(binary, args, { stdio: ["ignore", "pipe", "pipe"] });
    let stdout = "";
    let stderr = "";
    let address;
    const exited = new Promise((r) => p.on("close", (code) => r({ code, stdout, stderr })));
    p.stdout.on("data", (d) => (stdout += d));
    p.stderr.on("data", (d) => {
      stderr += d;
      const m = /foxglove: serving on (\S+)/.exec(stderr);
      if (m && address === undefined) {
        address = m[1];
        resolve({ address, exited, process: p });
      }
    });
    p.on("close", (code) => {
      if (address === undefined) reject(new Error(`tlvlink exited (${code}) before serving:\n${stderr}`));
    });
  });
}

// A /tlvlink/frame_image message as Foxglove's Image panel reads it (foxglove.CompressedImage:
// frame_id, format "jpeg", data a base64 JPEG), and otherwise the listener's line; `json` loses
// its frame_id (the one key the channel adds) so the caller compares the rest with the line.
function checkCompressedImage(label, json, line) {
  const id = line.sensor_name !== undefined ? line.sensor_name : `sensor${line.sensor}`;
  check(json.frame_id === id, `${label}: a frame image's frame_id names its sensor`, `${json.frame_id} vs ${id}`);
  check(json.format === "jpeg", `${label}: a frame image's format is jpeg`, json.format);
  const jpeg = Buffer.from(json.data || "", "base64");
  check(jpeg.length > 4 && jpeg[0] === 0xff && jpeg[1] === 0xd8 && jpeg[jpeg.length - 2] === 0xff && jpeg[jpeg.length - 1] === 0xd9,
        `${label}: a frame image's data is a base64 JPEG (SOI .. EOI)`, jpeg.length);
  check(Array.isArray(json.mask) && json.mask.length === json.mask_height && json.mask.every((r) => r.length === json.mask_width),
        `${label}: a frame image's mask is mask_height rows of mask_width cells`);
  delete json.frame_id;
}
function withoutFrameId(json) {
  delete json.frame_id;
  return json;
}

module.exports = { checkCompressedImage, withoutFrameId, check, finish, run, messageLines, splitTimestamp, undeclaredKeys, startBoard, startServing };
