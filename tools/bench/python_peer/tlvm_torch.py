"""A .tlvm model as a PyTorch module (fp32), for the Python peer benchmark: the same architecture
and weights a user would run with python3-torch. Reads the flatbuffer through Python code that
flatc generates from runtime/model/schema/tlvm.fbs (Debian's flatbuffers-compiler and
python3-flatbuffers); supports the operators of float encoders (Conv2D, FullyConnected, Add,
Mul, Clamp, Sigmoid, GlobalAveragePool, MaxPool2D, Pad, Reshape, ResizeBilinear)."""
import importlib
import os
import subprocess
import sys
import tempfile

import numpy as np
import torch
import torch.nn.functional as F


def _schema_module(schema):
    out = tempfile.mkdtemp(prefix="tlvm_py_")
    subprocess.run(["flatc", "--python", "-o", out, schema], check=True)
    sys.path.insert(0, out)
    return importlib.import_module("tlvlink.fb.Model")


def _floats(buffers, index, dtype=np.float32):
    data = buffers(index).DataAsNumpy()
    return np.frombuffer(data.tobytes(), dtype=dtype)


class TlvmModule(torch.nn.Module):
    def __init__(self, path, schema):
        super().__init__()
        mod = _schema_module(schema)
        fb = importlib.import_module("tlvlink.fb")
        with open(path, "rb") as f:
            buf = f.read()
        m = mod.Model.GetRootAsModel(buf, 0)
        g = m.Graph()
        self.tensors = []
        for i in range(g.TensorsLength()):
            t = g.Tensors(i)
            shape = [t.Shape(k) for k in range(t.ShapeLength())]
            data = None
            if t.Buffer() != 0:
                if t.Dtype() != 0:
                    raise ValueError("%s: only float32 models (tensor %s is dtype %d)" % (path, t.Name(), t.Dtype()))
                data = _floats(m.Buffers, t.Buffer()).reshape(shape)
            self.tensors.append((t.Name().decode(), shape, data))
        self.ops = []
        O = importlib.import_module("tlvlink.fb.OpType").OpType
        for i in range(g.OperatorsLength()):
            op = g.Operators(i)
            ins = [op.Inputs(k) for k in range(op.InputsLength())]
            out = op.Outputs(0)
            opts = op.Options()
            t = op.Type()
            if t == O.Conv2D:
                c = importlib.import_module("tlvlink.fb.Conv2DOptions").Conv2DOptions()
                c.Init(opts.Bytes, opts.Pos)
                w = torch.from_numpy(self.tensors[ins[1]][2].transpose(0, 3, 1, 2).copy())  # OHWI->OIHW
                b = torch.from_numpy(self.tensors[ins[2]][2].copy()) if len(ins) > 2 and ins[2] >= 0 else None
                self.ops.append(("conv", ins[0], out, dict(w=w, b=b, stride=(c.StrideH(), c.StrideW()),
                                 dilation=(c.DilationH(), c.DilationW()), groups=c.Groups(),
                                 pad=(c.PadLeft(), c.PadRight(), c.PadTop(), c.PadBottom()), act=c.Activation())))
            elif t == O.FullyConnected:
                c = importlib.import_module("tlvlink.fb.FullyConnectedOptions").FullyConnectedOptions()
                c.Init(opts.Bytes, opts.Pos)
                w = torch.from_numpy(self.tensors[ins[1]][2].copy())
                b = torch.from_numpy(self.tensors[ins[2]][2].copy()) if len(ins) > 2 and ins[2] >= 0 else None
                self.ops.append(("fc", ins[0], out, dict(w=w, b=b, act=c.Activation())))
            elif t in (O.Add, O.Mul):
                c = importlib.import_module("tlvlink.fb.BinaryOptions").BinaryOptions()
                c.Init(opts.Bytes, opts.Pos)
                self.ops.append(("add" if t == O.Add else "mul", ins, out, dict(act=c.Activation())))
            elif t == O.GlobalAveragePool:
                self.ops.append(("gap", ins[0], out, {}))
            elif t == O.Reshape:
                self.ops.append(("reshape", ins[0], out, dict(shape=self.tensors[out][1])))
            elif t == O.Sigmoid:
                self.ops.append(("sigmoid", ins[0], out, {}))
            elif t == O.Clamp:
                c = importlib.import_module("tlvlink.fb.ClampOptions").ClampOptions()
                c.Init(opts.Bytes, opts.Pos)
                self.ops.append(("clamp", ins[0], out, dict(lo=c.Min(), hi=c.Max())))
            else:
                raise ValueError("%s: operator type %d is not supported by the Python peer" % (path, t))
        self.inputs = [g.Inputs(k) for k in range(g.InputsLength())]
        self.outputs = [g.Outputs(k) for k in range(g.OutputsLength())]
        md = m.Metadata()
        # The model's first golden pair: the forward pass must reproduce it (same weights, same
        # arithmetic up to summation order), or this peer is not running the same model.
        self.golden = None
        if md.GoldenLength() > 0:
            gp = md.Golden(0)
            in_shape, out_shape = self.tensors[self.inputs_of(g)[0]][1], self.tensors[g.Outputs(0)][1]
            self.golden = (_floats(m.Buffers, gp.Input()).reshape(in_shape),
                           _floats(m.Buffers, gp.Output()).reshape(out_shape))
        spec = md.Input()
        self.height, self.width = spec.Height(), spec.Width()
        self.mean = np.array([spec.Mean(k) for k in range(spec.MeanLength())], np.float32)
        self.std = np.array([spec.Std(k) for k in range(spec.StdLength())], np.float32)
        self.embedding_output = md.EmbeddingOutput()
        self.heads = []
        for k in range(md.LinearHeadsLength()):
            h = md.LinearHeads(k)
            labels = [h.Labels(j).decode() for j in range(h.LabelsLength())]
            w = h.WeightAsNumpy().astype(np.float32).reshape(len(labels), -1)
            self.heads.append((h.Name().decode(), labels, torch.from_numpy(w.copy()),
                               torch.from_numpy(h.BiasAsNumpy().astype(np.float32).copy())))

    @staticmethod
    def inputs_of(g):
        return [g.Inputs(k) for k in range(g.InputsLength())]

    def check_golden(self, rel_tolerance=1e-4):
        """Max |torch - golden| / max|golden| on the model's first golden pair (1e-4: summation
        order differs between kernels, as tlvlink verify allows for float models)."""
        x, want = self.golden
        with torch.no_grad():
            got = self.forward(torch.from_numpy(x.transpose(0, 3, 1, 2).copy()))[0].numpy()
        err = float(np.abs(got.reshape(want.shape) - want).max() / max(np.abs(want).max(), 1e-30))
        if err > rel_tolerance:
            raise ValueError("the PyTorch peer does not reproduce the model's golden pair: "
                             "relative error %.3g > %g" % (err, rel_tolerance))
        return err
        return F.relu(x) if a == 1 else torch.clamp(x, 0, 6) if a == 2 else x

    @staticmethod
    def _act(x, a):
        return F.relu(x) if a == 1 else torch.clamp(x, 0, 6) if a == 2 else x

    def forward(self, x):  # x: NCHW float
        v = {self.inputs[0]: x}
        for kind, src, out, p in self.ops:
            if kind == "conv":
                y = F.pad(v[src], p["pad"]) if any(p["pad"]) else v[src]
                y = F.conv2d(y, p["w"], p["b"], p["stride"], 0, p["dilation"], p["groups"])
                v[out] = self._act(y, p["act"])
            elif kind == "fc":
                v[out] = self._act(F.linear(v[src], p["w"], p["b"]), p["act"])
            elif kind in ("add", "mul"):
                a, b = v[src[0]], v[src[1]]
                v[out] = self._act(a + b if kind == "add" else a * b, p["act"])
            elif kind == "gap":
                v[out] = v[src].mean(dim=(2, 3), keepdim=True)
            elif kind == "reshape":
                t = v[src]
                if t.dim() == 4:
                    t = t.permute(0, 2, 3, 1)  # back to the model's NHWC order
                v[out] = t.reshape(p["shape"])
            elif kind == "sigmoid":
                v[out] = torch.sigmoid(v[src])
            elif kind == "clamp":
                v[out] = torch.clamp(v[src], p["lo"], p["hi"])
        return [v[o] for o in self.outputs]

    def heads_of(self, e):
        out = {}
        for name, labels, w, b in self.heads:
            p = torch.softmax(F.linear(e, w, b), dim=-1)[0]
            k = int(torch.argmax(p))
            out[name] = (labels[k], float(p[k]))
        return out
