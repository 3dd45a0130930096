#!/usr/bin/env python3
"""Core ML parity without macOS: execute an ML Program (.mlpackage) op by op on Linux.

coremltools cannot run Core ML prediction on Linux (no Core ML framework). This tool loads the
converted MIL program (graph, attributes, and the weights from the package's weight blob) with
coremltools' MIL loader and evaluates it with PyTorch kernels (conv, conv_transpose, relu, add,
sub, mul, concat), so the converted program's structure, weights, padding, strides and groups are
checked numerically against the source model. What it does NOT check: Apple's own kernels and
compute units (CPU / GPU / Neural Engine), their float16 paths, and the model's loading on iOS.

Usage: python3 coreml_parity.py --mlpackage ../models/SignUNet.mlpackage --onnx ../models/sign_unet.onnx
"""
from __future__ import annotations

import argparse
import os
import sys
from typing import Dict

import numpy as np


def load_program(path: str):
    """The MIL program (main function) of an .mlpackage, weights loaded (coremltools' MIL loader)."""
    import coremltools as ct
    from coremltools.converters.mil.frontend.milproto.load import load as mil_load
    if not os.path.isdir(path):
        raise FileNotFoundError("coreml_parity: %s is not an .mlpackage directory" % path)
    m = ct.models.MLModel(path, skip_model_load=True)
    spec = m.get_spec()
    if not spec.HasField("mlProgram"):
        raise ValueError("coreml_parity: %s is not an ML Program" % path)
    return mil_load(spec, spec.specificationVersion, m.weights_dir).functions["main"]


def _pad(op, x_shape_hw, k_hw, strides, dil):
    """Explicit (top, bottom, left, right) padding of a MIL conv."""
    pad_type = op.inputs["pad_type"].val if "pad_type" in op.inputs else "valid"
    if pad_type == "custom":
        return [int(v) for v in op.inputs["pad"].val]
    if pad_type == "valid":
        return [0, 0, 0, 0]
    if pad_type in ("same", "same_lower"):
        out = []
        for i in range(2):
            n = x_shape_hw[i]
            o = -(-n // strides[i])
            tot = max((o - 1) * strides[i] + (k_hw[i] - 1) * dil[i] + 1 - n, 0)
            a, b = (tot // 2, tot - tot // 2) if pad_type == "same" else (tot - tot // 2, tot // 2)
            out += [a, b]
        return out
    raise NotImplementedError("coreml_parity: pad_type %s" % pad_type)


def run_program(fn, inputs: Dict[str, np.ndarray]) -> Dict[str, np.ndarray]:
    """Evaluate the MIL function `fn` on `inputs` (name -> float32 array); returns its outputs."""
    import torch
    import torch.nn.functional as F
    env = {k: torch.from_numpy(np.asarray(v, np.float32)) for k, v in inputs.items()}

    def val(var):
        if var.name in env:
            return env[var.name]
        if var.val is not None:
            return torch.from_numpy(np.array(var.val, np.float32))
        raise KeyError("coreml_parity: value %s not computed" % var.name)

    for op in fn.operations:
        t = op.op_type
        if t == "const":
            continue
        I = op.inputs
        if t in ("add", "sub", "mul", "real_div"):
            a, b = val(I["x"]), val(I["y"])
            y = {"add": a + b, "sub": a - b, "mul": a * b, "real_div": a / b}[t]
        elif t == "relu":
            y = torch.relu(val(I["x"]))
        elif t == "concat":
            if "interleave" in I and bool(I["interleave"].val):
                raise NotImplementedError("coreml_parity: interleaved concat")
            y = torch.cat([val(v) for v in I["values"]], dim=int(I["axis"].val))
        elif t in ("conv", "conv_transpose"):
            x, w = val(I["x"]), val(I["weight"])
            b = val(I["bias"]) if "bias" in I else None
            strides = [int(s) for s in I["strides"].val] if "strides" in I else [1, 1]
            dil = [int(s) for s in I["dilations"].val] if "dilations" in I else [1, 1]
            groups = int(I["groups"].val) if "groups" in I else 1
            if t == "conv":
                p = _pad(op, x.shape[2:], w.shape[2:], strides, dil)
                x = F.pad(x, (p[2], p[3], p[0], p[1]))
                y = F.conv2d(x, w, b, stride=strides, dilation=dil, groups=groups)
            else:
                pad_type = I["pad_type"].val if "pad_type" in I else "valid"
                p = [int(v) for v in I["pad"].val] if pad_type == "custom" else [0, 0, 0, 0]
                if p[0] != p[1] or p[2] != p[3]:
                    raise NotImplementedError("coreml_parity: asymmetric conv_transpose padding")
                y = F.conv_transpose2d(x, w, b, stride=strides, padding=(p[0], p[2]), dilation=dil, groups=groups)
                if "output_shape" in I and I["output_shape"].val is not None:
                    want = [int(s) for s in I["output_shape"].val]
                    if list(y.shape[2:]) != want[-2:]:
                        raise ValueError("coreml_parity: conv_transpose output %s, program says %s" % (list(y.shape), want))
        elif t == "upsample_nearest_neighbor":  # integer factors only (the kinds branch's 2x step)
            fh, fw = float(I["scale_factor_height"].val), float(I["scale_factor_width"].val)
            if fh != int(fh) or fw != int(fw):
                raise NotImplementedError("coreml_parity: fractional nearest-neighbour factors %g, %g" % (fh, fw))
            y = val(I["x"]).repeat_interleave(int(fh), dim=2).repeat_interleave(int(fw), dim=3)
        else:
            raise NotImplementedError("coreml_parity: op %s (%s) is not supported" % (t, op.name))
        env[op.outputs[0].name] = y
    return {v.name: env[v.name].numpy() for v in fn.outputs}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mlpackage", required=True)
    ap.add_argument("--onnx", help="compare with this ONNX model under ONNX Runtime")
    ap.add_argument("--checkpoint", help="compare with this PyTorch checkpoint (train_unet.py .pt)")
    a = ap.parse_args(argv)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import export_unet
    x = export_unet.sample_inputs(3)
    fn = load_program(a.mlpackage)
    ml = np.concatenate([run_program(fn, {"image": x[i:i + 1]})["logits"] for i in range(len(x))])
    rc = 0
    if a.onnx:
        import onnxruntime as ort
        s = ort.InferenceSession(a.onnx, providers=["CPUExecutionProvider"])
        ref = np.concatenate([s.run(None, {"image": x[i:i + 1]})[0] for i in range(len(x))])
        d = float(np.abs(ml - ref).max())
        agree = float((ml.argmax(1) == ref.argmax(1)).mean())
        print("MIL program vs ONNX Runtime: max |logit difference| %.2e, arg-max agreement %.4f" % (d, agree))
        rc |= int(d > 1e-3)
    if a.checkpoint:
        import torch
        import train_unet
        ck = torch.load(a.checkpoint, map_location="cpu")
        model = train_unet.SignUNet(ck.get("width", 0.35), ck.get("num_classes", 2))
        model.load_state_dict(ck["state_dict"])
        model.eval()
        with torch.no_grad():
            ref = model(torch.from_numpy(x)).numpy()
        d = float(np.abs(ml - ref).max())
        print("MIL program vs PyTorch: max |logit difference| %.2e, arg-max agreement %.4f" % (d, float((ml.argmax(1) == ref.argmax(1)).mean())))
        rc |= int(d > 1e-3)
    return rc


if __name__ == "__main__":
    sys.exit(main())
