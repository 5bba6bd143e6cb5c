// Takes the README's picture: opens live.html in headless Chromium through the DevTools
// protocol (on the ws package), lets it receive for a few seconds, saves a PNG.
//   NODE_PATH=~/.cache/tlvlink/npm/node_modules node screenshot.js DEVTOOLS_PORT URL OUT.png SECONDS
"use strict";
const fs = require("fs");
const http = require("http");
const { WebSocket } = require("ws");

const [port, url, out, seconds] = process.argv.slice(2);
http.get(`http://127.0.0.1:${port}/json/list`, (res) => {
  let body = "";
  res.on("data", (d) => (body += d));
  res.on("end", () => {
    const page = JSON.parse(body).find((t) => t.type === "page");
    const ws = new WebSocket(page.webSocketDebuggerUrl);
    let id = 0;
    const pending = new Map();
    const call = (method, params = {}) =>
      new Promise((resolve) => {
        pending.set(++id, resolve);
        ws.send(JSON.stringify({ id, method, params }));
      });
    ws.on("message", (m) => {
      const j = JSON.parse(m);
      if (pending.has(j.id)) pending.get(j.id)(j.result), pending.delete(j.id);
    });
    ws.on("open", async () => {
      await call("Emulation.setDeviceMetricsOverride", { width: 768, height: 660, deviceScaleFactor: 1, mobile: false });
      await call("Page.navigate", { url });
      await new Promise((r) => setTimeout(r, Number(seconds) * 1000));  // live data: real time
      const shot = await call("Page.captureScreenshot", { format: "png" });
      fs.writeFileSync(out, Buffer.from(shot.data, "base64"));
      console.log(`screenshot: ${out}`);
      // What the picture shows, read from the page: connected, sensors drawn, gels drawn.
      const seen = await call("Runtime.evaluate", {
        expression: "JSON.stringify({status: document.getElementById('status').textContent, " +
                    "sensors: document.querySelectorAll('.sensor').length, " +
                    "gels: document.querySelectorAll('canvas.gel').length, " +
                    "heads: document.querySelectorAll('.head').length})",
        returnByValue: true });
      const page = JSON.parse(seen.result.value);
      console.log(`page: ${JSON.stringify(page)}`);
      ws.close();
      if (!page.status.startsWith("connected to ws://") || page.sensors < 1 || page.gels < 1 || page.heads < 1) {
        console.error("screenshot: the page did not show the live stream (connected, a sensor, its gel, a head)");
        process.exitCode = 1;
      }
    });
  });
});
