#!/usr/bin/env python3
"""Writes TorchScript vision encoders for the trainer tests (run with Debian's /usr/bin/python3,
which has python3-torch):
  make_teacher.py OUT_DIR  ->  OUT_DIR/teacher64.pt   [N,3,H,W] -> [N,64] (needs a projection)
                               OUT_DIR/bad_shape.pt   [N,3,H,W] -> [N,4,4] (must be rejected)
"""
import os
import sys

import torch


class Teacher(torch.nn.Module):
    def __init__(self, dim):
        super().__init__()
        self.conv = torch.nn.Conv2d(3, 16, 3, stride=2, padding=1)
        self.fc = torch.nn.Linear(16, dim)

    def forward(self, x):
        return self.fc(torch.relu(self.conv(x)).mean(dim=(2, 3)))


class BadShape(torch.nn.Module):
    def forward(self, x):
        return x.mean(dim=1)[:, :4, :4]


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    torch.manual_seed(0)
    torch.jit.script(Teacher(64).eval()).save(os.path.join(out, "teacher64.pt"))
    torch.jit.script(BadShape()).save(os.path.join(out, "bad_shape.pt"))


if __name__ == "__main__":
    main()
