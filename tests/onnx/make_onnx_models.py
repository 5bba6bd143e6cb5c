#!/usr/bin/python3
"""Exports the ONNX import test models with Debian's python3-torch and records torch's output.

Run with /usr/bin/python3 (Debian's torch 1.13, onnx and numpy live there; a `python3` earlier on
PATH may be another build that cannot import them):

    /usr/bin/python3 tests/onnx/make_onnx_models.py --out DIR

For every parity model NAME it writes NAME.onnx, NAME.input.npy (the NCHW float32 input) and
NAME.output.npy (torch's output). Models the converter must reject are written as NAME.onnx.
DIR/manifest.txt lists one model per line:
    parity NAME
    reject NAME EXPECTED|SUBSTRINGS|OF|THE|ERROR
The gtest (onnx_import_test.cc) holds the same list and fails on any difference, so a model
added here without a test (or the reverse) is noticed.
"""

import argparse
import io
import os
import sys
import warnings

try:
    import numpy as np
    import onnx
    import torch
    import torch.nn as nn
    import torch.nn.functional as F
    from onnx import helper, numpy_helper, TensorProto
except ImportError as e:  # fail loudly: the CTest fixture must not pass without models
    sys.exit(f"make_onnx_models.py: {e}; install Debian's python3-torch python3-onnx "
             f"python3-numpy and run with /usr/bin/python3 (tools/setup/install_deps.sh test)")

warnings.filterwarnings("ignore")
torch.manual_seed(7)
np.random.seed(7)
PRESERVE = torch.onnx.TrainingMode.PRESERVE  # keeps BatchNormalization nodes in the graph
EVAL = torch.onnx.TrainingMode.EVAL          # torch folds Conv+BN itself


def randomize_bn(module):
    """Non-trivial running statistics so BatchNorm folding is actually exercised."""
    for m in module.modules():
        if isinstance(m, (nn.BatchNorm1d, nn.BatchNorm2d)):
            n = m.num_features
            m.running_mean.copy_(torch.randn(n) * 0.5)
            m.running_var.copy_(torch.rand(n) * 1.5 + 0.5)
            m.weight.data.copy_(torch.rand(n) + 0.5)
            m.bias.data.copy_(torch.randn(n) * 0.2)
    return module


class Seq(nn.Module):
    """Applies a function of (self, x) so small test nets read like their description."""

    def __init__(self, fn, **modules):
        super().__init__()
        self.fn = fn
        for k, v in modules.items():
            setattr(self, k, v)

    def forward(self, x):
        return self.fn(self, x)


def inverted_residual(cin, cout, stride, expand=4):
    hidden = cin * expand
    block = nn.Sequential(
        nn.Conv2d(cin, hidden, 1, bias=False), nn.BatchNorm2d(hidden), nn.ReLU6(),
        nn.Conv2d(hidden, hidden, 3, stride, 1, groups=hidden, bias=False),
        nn.BatchNorm2d(hidden), nn.ReLU6(),
        nn.Conv2d(hidden, cout, 1, bias=False), nn.BatchNorm2d(cout))
    residual = stride == 1 and cin == cout
    return Seq(lambda s, x: x + s.block(x) if residual else s.block(x), block=block)


def mobilenetv2_blocks():
    return nn.Sequential(
        nn.Conv2d(3, 16, 3, 2, 1, bias=False), nn.BatchNorm2d(16), nn.ReLU6(),
        inverted_residual(16, 16, 1), inverted_residual(16, 24, 2), inverted_residual(24, 24, 1),
        nn.Conv2d(24, 64, 1, bias=False), nn.BatchNorm2d(64), nn.ReLU6(),
        nn.AdaptiveAvgPool2d(1), nn.Flatten(), nn.Linear(64, 32))


def torch_models():
    """(name, module, input shape, opset, training mode, dynamic axes)."""
    m = []
    m.append(("conv_dense_relu", nn.Sequential(nn.Conv2d(3, 8, 3, padding=1), nn.ReLU()),
              (1, 3, 16, 16), 13, EVAL, None))
    m.append(("conv_strided_dilated", nn.Sequential(
        nn.Conv2d(3, 8, 3, stride=2, dilation=2, padding=2, bias=False), nn.ReLU(),
        nn.Conv2d(8, 6, (3, 5), stride=(1, 2), padding=(1, 2))), (1, 3, 17, 20), 13, EVAL, None))
    m.append(("conv_depthwise", nn.Sequential(
        nn.Conv2d(3, 8, 1), nn.Conv2d(8, 8, 3, padding=1, groups=8), nn.ReLU6(),
        nn.Conv2d(8, 16, 3, stride=2, groups=8)), (1, 3, 15, 15), 13, EVAL, None))
    m.append(("conv_grouped", nn.Sequential(
        nn.Conv2d(3, 8, 3), nn.Conv2d(8, 12, 3, padding=1, groups=4), nn.ReLU()),
        (1, 3, 12, 12), 13, EVAL, None))
    bn = Seq(lambda s, x: s.fc_bn(s.fc(torch.flatten(s.gap(
        s.bn_act(torch.relu(s.conv_bn(s.conv(s.bn_in(x))))) ), 1))),
        bn_in=nn.BatchNorm2d(3), conv=nn.Conv2d(3, 8, 3, padding=1), conv_bn=nn.BatchNorm2d(8),
        bn_act=nn.BatchNorm2d(8), gap=nn.AdaptiveAvgPool2d(1), fc=nn.Linear(8, 6),
        fc_bn=nn.BatchNorm1d(6))
    m.append(("batchnorm", randomize_bn(bn), (1, 3, 10, 10), 13, PRESERVE, None))
    clip = Seq(lambda s, x: torch.clamp(F.hardtanh(
        torch.clamp(s.c2(F.relu6(s.c1(x))), -1.0, 2.0), -0.5, 0.5) + torch.clamp(s.c3(x), min=0.0),
        min=-0.25), c1=nn.Conv2d(3, 4, 3, padding=1), c2=nn.Conv2d(4, 4, 1),
        c3=nn.Conv2d(3, 4, 3, padding=1))
    m.append(("relu6_clip", clip, (1, 3, 8, 8), 13, EVAL, None))
    m.append(("relu6_clip_opset9", clip, (1, 3, 8, 8), 9, EVAL, None))
    # The residual joins two activations; the per-channel and scalar constants after it
    # cannot fold into a conv (their producer is the Add).
    res = Seq(lambda s, x: (lambda y: s.c2(torch.relu(s.c1(y))) + y)(s.c0(x)) + s.bias + 0.25,
              c0=nn.Conv2d(3, 4, 1), c1=nn.Conv2d(4, 4, 3, padding=1),
              c2=nn.Conv2d(4, 4, 3, padding=1), bias=nn.Parameter(torch.randn(1, 4, 1, 1)))
    m.append(("residual_add", res, (1, 3, 9, 7), 13, EVAL, None))
    mul = Seq(lambda s, x: ((torch.relu(s.c(x)) * torch.sigmoid(s.c(x))) * s.scale * 0.5) / 2.0
              - 0.1, c=nn.Conv2d(3, 5, 3), scale=nn.Parameter(torch.randn(1, 5, 1, 1)))
    m.append(("mul_div_sub", mul, (1, 3, 8, 8), 13, EVAL, None))
    # Squeeze-and-excitation: Unsqueeze on activations and a broadcast Mul of two activations.
    se = Seq(lambda s, x: (lambda y: y * torch.sigmoid(s.fc(y.mean((2, 3)))).unsqueeze(-1)
                           .unsqueeze(-1))(torch.relu(s.c(x))),
             c=nn.Conv2d(3, 6, 3), fc=nn.Linear(6, 6))
    m.append(("se_block", se, (1, 3, 9, 9), 13, EVAL, None))
    m.append(("gap_linear_sigmoid", nn.Sequential(
        nn.Conv2d(3, 8, 3, stride=2), nn.ReLU(), nn.AdaptiveAvgPool2d(1), nn.Flatten(),
        nn.Linear(8, 5), nn.Sigmoid()), (1, 3, 16, 16), 13, EVAL, None))
    m.append(("maxpool", nn.Sequential(
        nn.Conv2d(3, 6, 3, padding=1), nn.MaxPool2d(3, 2, 1), nn.ReLU(), nn.MaxPool2d(2),
        nn.Conv2d(6, 4, 1)), (1, 3, 19, 16), 13, EVAL, None))
    m.append(("flatten_spatial", nn.Sequential(
        nn.Conv2d(3, 4, 3), nn.ReLU(), nn.Flatten(), nn.Linear(4 * 6 * 4, 7), nn.ReLU(),
        nn.Linear(7, 3)), (1, 3, 8, 6), 13, EVAL, None))
    view = Seq(lambda s, x: torch.matmul(s.c(x).view(x.size(0), -1), s.w),
               c=nn.Conv2d(3, 4, 3), w=nn.Parameter(torch.randn(4 * 5 * 5, 6) * 0.1))
    m.append(("view_matmul", view, (1, 3, 7, 7), 13, EVAL, None))
    pad = Seq(lambda s, x: F.pad(s.c2(F.pad(s.c1(s.zero(x)), (1, 1, 1, 1), value=0.5)),
                                 (0, 0, 0, 0, 1, 2)),
              zero=nn.ZeroPad2d((1, 2, 0, 1)), c1=nn.Conv2d(3, 4, 3), c2=nn.Conv2d(4, 4, 3))
    m.append(("pad", pad, (1, 3, 9, 8), 13, EVAL, None))
    m.append(("pad_opset9", pad, (1, 3, 9, 8), 9, EVAL, None))
    m.append(("mobilenetv2_blocks", randomize_bn(mobilenetv2_blocks()), (1, 3, 64, 64), 13,
              PRESERVE, None))
    m.append(("mobilenetv2_blocks_opset17", randomize_bn(mobilenetv2_blocks()), (1, 3, 48, 48),
              17, EVAL, None))
    m.append(("gray_dynamic_batch", nn.Sequential(
        nn.Conv2d(1, 4, 3), nn.ReLU(), nn.AdaptiveAvgPool2d(1), nn.Flatten(), nn.Linear(4, 3)),
        (1, 1, 12, 12), 11, EVAL, {"input": {0: "N"}, "output": {0: "N"}}))
    return m


def export(module, shape, opset, training, dynamic_axes):
    module.eval()
    x = torch.randn(*shape)
    f = io.BytesIO()
    torch.onnx.export(module, x, f, opset_version=opset, training=training,
                      input_names=["input"], output_names=["output"], dynamic_axes=dynamic_axes)
    with torch.no_grad():
        y = module(x)
    return f.getvalue(), x.numpy(), y.numpy()


# ---- models written with onnx.helper: forms torch does not export ----------------------------

def tensor(name, a):
    return numpy_helper.from_array(np.asarray(a, dtype=np.float32), name)


def conv_auto_pad():
    """SAME_UPPER / SAME_LOWER with an odd total pad, VALID, and asymmetric explicit pads."""
    w = [np.random.randn(*s) / np.sqrt(s[1] * s[2] * s[3])  # unit-variance outputs
         for s in ((4, 3, 3, 3), (4, 4, 3, 3), (4, 4, 2, 2), (4, 4, 3, 3))]
    b = np.random.randn(4)
    nodes = [
        helper.make_node("Conv", ["input", "w0", "b"], ["a"], name="same_upper",
                         auto_pad="SAME_UPPER", strides=[2, 2]),
        helper.make_node("Conv", ["a", "w1"], ["c"], name="same_lower", auto_pad="SAME_LOWER",
                         strides=[2, 2]),
        helper.make_node("Conv", ["c", "w2", "b"], ["d"], name="valid", auto_pad="VALID"),
        helper.make_node("Conv", ["d", "w3"], ["output"], name="explicit_asymmetric",
                         pads=[0, 1, 2, 1]),
    ]
    inits = [tensor(f"w{i}", w[i]) for i in range(4)] + [tensor("b", b)]
    x = np.random.randn(1, 3, 16, 16).astype(np.float32)
    t = lambda a: torch.from_numpy(np.asarray(a, dtype=np.float32))
    y = F.conv2d(F.pad(t(x), (0, 1, 0, 1)), t(w[0]), t(b), stride=2)      # SAME_UPPER: end
    y = F.conv2d(F.pad(y, (1, 0, 1, 0)), t(w[1]), stride=2)               # SAME_LOWER: begin
    y = F.conv2d(y, t(w[2]), t(b))
    y = F.conv2d(F.pad(y, (1, 1, 0, 2)), t(w[3]))                         # (left,right,top,bottom)
    return graph_model("conv_auto_pad", nodes, inits, x, y.numpy(), 13)


def gemm_matmul():
    """Gemm with transB=0, alpha and beta; MatMul with a constant right operand."""
    b = np.random.randn(48, 10)
    c = np.random.randn(1, 10)
    m = np.random.randn(10, 4)
    nodes = [
        helper.make_node("Flatten", ["input"], ["f"], name="flatten", axis=1),
        helper.make_node("Gemm", ["f", "B", "C"], ["g"], name="gemm", transB=0, alpha=0.5,
                         beta=2.0),
        helper.make_node("Relu", ["g"], ["r"], name="relu"),
        helper.make_node("MatMul", ["r", "M"], ["output"], name="matmul"),
    ]
    inits = [tensor("B", b), tensor("C", c), tensor("M", m)]
    x = np.random.randn(1, 3, 4, 4).astype(np.float32)
    f = x.reshape(1, -1).astype(np.float64)
    y = np.maximum(0.5 * f @ b + 2.0 * c, 0) @ m
    return graph_model("gemm_matmul", nodes, inits, x, y.astype(np.float32), 13)


def graph_model(name, nodes, inits, x, y, opset):
    graph = helper.make_graph(
        nodes, name, [helper.make_tensor_value_info("input", TensorProto.FLOAT, list(x.shape))],
        [helper.make_tensor_value_info("output", TensorProto.FLOAT, list(y.shape))], inits)
    model = helper.make_model(graph, producer_name="make_onnx_models.py",
                              opset_imports=[helper.make_opsetid("", opset)])
    onnx.checker.check_model(model)
    return model.SerializeToString(), x, y


# ---- models the converter must reject --------------------------------------------------------

def node_named(model_bytes, op_type):
    for n in onnx.load_from_string(model_bytes).graph.node:
        if n.op_type == op_type:
            return n.name
    raise SystemExit(f"no {op_type} node in the exported model")


def reject_models():
    """(name, onnx bytes, expected error substrings)."""
    out = []
    softmax = nn.Sequential(nn.Conv2d(3, 4, 3), nn.Flatten(), nn.Softmax(dim=1))
    data, _, _ = export(softmax, (1, 3, 6, 6), 13, EVAL, None)
    out.append(("reject_softmax", data, ["Softmax", node_named(data, "Softmax"), "opset 13"]))

    # [1, 1, 8, 8] -> [8, 1, 8] is a plain reshape (one channel), so the LSTM is what fails.
    lstm = Seq(lambda s, x: s.lstm(x.reshape(8, 1, 8))[0], lstm=nn.LSTM(8, 4))
    data, _, _ = export(lstm, (1, 1, 8, 8), 13, EVAL, None)
    out.append(("reject_lstm", data, ["LSTM", node_named(data, "LSTM")]))

    nan = nn.Sequential(nn.Conv2d(3, 4, 3), nn.ReLU())
    with torch.no_grad():
        nan[0].weight[1, 2, 0, 1] = float("nan")
    data, _, _ = export(nan, (1, 3, 6, 6), 13, EVAL, None)
    init = [i.name for i in onnx.load_from_string(data).graph.initializer if len(i.dims) == 4][0]
    out.append(("reject_nan_weight", data, [f"initializer '{init}'", "NaN"]))

    dyn = nn.Sequential(nn.Conv2d(3, 4, 3), nn.ReLU())
    data, _, _ = export(dyn, (1, 3, 8, 8), 13, EVAL, {"input": {0: "N", 2: "height", 3: "width"}})
    out.append(("reject_dynamic_size", data, ["input 'input' dimension 2", "height", "dynamic"]))

    reflect = nn.Sequential(nn.ReflectionPad2d(1), nn.Conv2d(3, 4, 3))
    data, _, _ = export(reflect, (1, 3, 8, 8), 13, EVAL, None)
    out.append(("reject_reflect_pad", data, ["Pad", node_named(data, "Pad"), "reflect"]))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="output directory")
    out_dir = parser.parse_args().out
    os.makedirs(out_dir, exist_ok=True)
    manifest = []

    def save(name, data, x, y):
        with open(os.path.join(out_dir, name + ".onnx"), "wb") as f:
            f.write(data)
        np.save(os.path.join(out_dir, name + ".input.npy"), np.ascontiguousarray(x, np.float32))
        np.save(os.path.join(out_dir, name + ".output.npy"), np.ascontiguousarray(y, np.float32))
        manifest.append(f"parity {name}")

    for name, module, shape, opset, training, dyn in torch_models():
        save(name, *export(module, shape, opset, training, dyn))
    for name, (data, x, y) in (("conv_auto_pad", conv_auto_pad()), ("gemm_matmul", gemm_matmul())):
        save(name, data, x, y)
    for name, data, expected in reject_models():
        with open(os.path.join(out_dir, name + ".onnx"), "wb") as f:
            f.write(data)
        manifest.append(f"reject {name} " + "|".join(expected))
    with open(os.path.join(out_dir, "manifest.txt"), "w") as f:
        f.write("\n".join(manifest) + "\n")
    print(f"make_onnx_models.py: torch {torch.__version__}, onnx {onnx.__version__}: "
          f"{len(manifest)} models in {out_dir}")


if __name__ == "__main__":
    main()
