#!/usr/bin/env python3
"""Head predictions and embeddings of a model on the frames live_path_frames writes, per path.

  paths.py TLVLINK MODEL DIR [SUFFIXES]     SUFFIXES: comma-separated of p, j, r (default p,j,r)

Runs `TLVLINK infer MODEL -i DIR/NNNN_S.{ppm,jpg}` (head labels) and `... -o` (the embedding)
for every scene of DIR/labels.jsonl, then prints per path the material and rough/smooth accuracy
against the labels, the most frequent material predictions, and the cosine similarity of the
embeddings between paths. Needs numpy.
"""
import collections
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

tlvlink, model, d = sys.argv[1:4]
suffixes = sys.argv[4].split(',') if len(sys.argv) > 4 else ['p', 'j', 'r']
labels = [json.loads(line) for line in open(os.path.join(d, 'labels.jsonl'))]
res = {}
with tempfile.TemporaryDirectory() as tmp:
    for lab in labels:
        for s in suffixes:
            img = os.path.join(d, f"{lab['i']:04d}_{s}.{'jpg' if s == 'j' else 'ppm'}")
            out = subprocess.run([tlvlink, 'infer', model, '-i', img], capture_output=True,
                                 text=True, check=True).stdout
            emb = os.path.join(tmp, 'e.npy')
            subprocess.run([tlvlink, 'infer', model, '-i', img, '-o', emb], capture_output=True,
                           check=True)
            res[(lab['i'], s)] = {
                'material': re.search(r'head material\s+probe\s+-> (.+?)\s+p=', out).group(1),
                'rough': re.search(r'head rough_smooth\s+probe\s+-> (\w+)', out).group(1),
                'emb': np.load(emb).ravel()}

names = {'p': 'processed render', 'j': 'processed + JPEG q90 (training sets)',
         'r': 'raw MJPEG -> FrameDecoder (daemon)'}
rough = [l for l in labels if l['rough'] >= 0]
print(f'{d}: {len(labels)} scenes ({len(rough)} with a rough/smooth label); '
      f"most frequent material {collections.Counter(l['material'] for l in labels).most_common(1)[0][1] / len(labels):.1%}")
for s in suffixes:
    mat = np.mean([res[(l['i'], s)]['material'] == l['material'] for l in labels])
    rs = np.mean([res[(l['i'], s)]['rough'] == ('rough' if l['rough'] else 'smooth') for l in rough])
    top = collections.Counter(res[(l['i'], s)]['material'] for l in labels).most_common(3)
    print(f'  {s} {names[s]:38s} material {mat:6.1%}  rough/smooth {rs:6.1%}  top {top}')
for a, b in [('p', 'j'), ('p', 'r'), ('j', 'r')]:
    if a in suffixes and b in suffixes:
        c = [float(res[(l['i'], a)]['emb'] @ res[(l['i'], b)]['emb'] /
                   np.linalg.norm(res[(l['i'], a)]['emb']) / np.linalg.norm(res[(l['i'], b)]['emb']))
             for l in labels]
        same = np.mean([res[(l['i'], a)]['material'] == res[(l['i'], b)]['material'] for l in labels])
        print(f'  embedding cosine {a}-{b}: mean {np.mean(c):.3f} min {np.min(c):.3f}; same material label {same:.1%}')
