"""The GelSight pipeline a Python user would write, on the same recorded camera frames and the same
model weights (fp32, python3-torch), one core:
  (a) what the sensor SDKs do: full-size cv2.imdecode, crop the border, cv2.resize to the sensor's
      processed frame, resize to the model input, normalise, the encoder, the heads;
  (b) the best a Python user can do: cv2.IMREAD_REDUCED_COLOR_8 (libjpeg-turbo's 1/8 DCT
      scaling through OpenCV), then the same.
Prints per variant: median / p99 ms per frame, frames/s (frames back to back), CPU ms per frame.
  python3 peer.py --frames DIR --model M-fp32.tlvm --schema runtime/model/schema/tlvm.fbs
        [--crop 0.15 --view 320x240] [--rounds 3] [--json OUT]"""
import argparse
import glob
import json
import os
import time

import cv2
import numpy as np
import torch

from tlvm_torch import TlvmModule


def run(variant, frames, model, crop, view, rounds):
    vw, vh = view
    flag = cv2.IMREAD_COLOR if variant == "full" else cv2.IMREAD_REDUCED_COLOR_8
    mean, std = model.mean, model.std
    wall, cpu = [], []
    start = time.perf_counter()
    for r in range(rounds + 1):  # round 0 warms up and is not counted
        for buf in frames:
            t0, c0 = time.perf_counter(), time.thread_time()
            img = cv2.imdecode(buf, flag)  # BGR
            h, w = img.shape[:2]
            cy, cx = int(crop * h), int(crop * w)
            img = img[cy:h - cy, cx:w - cx]
            img = cv2.resize(img, (vw, vh), interpolation=cv2.INTER_LINEAR)
            img = cv2.resize(img, (model.width, model.height), interpolation=cv2.INTER_LINEAR)
            x = (img[:, :, ::-1].astype(np.float32) / 255.0 - mean) / std
            t = torch.from_numpy(np.ascontiguousarray(x.transpose(2, 0, 1)))[None]
            with torch.no_grad():
                e = model(t)[model.embedding_output]
                model.heads_of(e)
            if r > 0:
                wall.append((time.perf_counter() - t0) * 1e3)
                cpu.append((time.thread_time() - c0) * 1e3)
        if r == 0:
            start = time.perf_counter()
    total = time.perf_counter() - start
    s = sorted(wall)
    row = {"label": "python %s decode" % ("full-size" if variant == "full" else "IMREAD_REDUCED_COLOR_8"),
           "median_ms": s[len(s) // 2], "p99_ms": s[min(len(s) - 1, int(0.99 * len(s)))],
           "cpu_ms": sorted(cpu)[len(cpu) // 2], "fps": len(wall) / total}
    print("%-46s median %8.3f ms  p99 %8.3f ms  CPU %8.3f ms  %8.1f frames/s" %
          (row["label"], row["median_ms"], row["p99_ms"], row["cpu_ms"], row["fps"]))
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", required=True)
    ap.add_argument("--model", required=True)
    ap.add_argument("--schema", required=True)
    ap.add_argument("--crop", type=float, default=0.15)
    ap.add_argument("--view", default="320x240")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--json")
    a = ap.parse_args()
    torch.set_num_threads(1)
    cv2.setNumThreads(1)
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core
    frames = [np.fromfile(p, np.uint8) for p in sorted(glob.glob(os.path.join(a.frames, "*.jpg")))]
    model = TlvmModule(a.model, a.schema).eval()
    err = model.check_golden()
    print("PyTorch forward reproduces the model's golden pair: max relative error %.2g" % err)
    view = tuple(int(v) for v in a.view.split("x"))
    print("%d frames, %s, torch %s, OpenCV %s, one core" % (len(frames), a.model, torch.__version__, cv2.__version__))
    rows = [run(v, frames, model, a.crop, view, a.rounds) for v in ("full", "reduced")]
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rows": rows}, f)


if __name__ == "__main__":
    main()
