#!/usr/bin/env python3
"""Export the trained U-Net to ONNX and Core ML and check output parity across runtimes.

Writes (default into SignDetector/models/):
  * sign_unet.onnx   opset 12, input "image" 1x3x224x224 float32 RGB [0,1], output "logits"
                     1xKx224x224 (BatchNorm folded into the convolutions by the exporter's
                     constant folding in eval mode);
  * classes.json     {"classes": ["background", "exit"]};
  * SignUNet.mlpackage  Core ML ML Program converted from the traced model (same input/output
                     names and layout), when coremltools is installed.

Parity: PyTorch vs ONNX Runtime vs OpenCV dnn on rendered crops, max abs logit difference printed.
OpenCV dnn is checked with the Python cv2 module and, when built (tools/onnx_cv_dnn_check.cpp,
compiled against the system OpenCV 4.6 the C++ detector uses), with that binary too.

Usage: python3 export_unet.py --checkpoint runs/unet/sign_unet.pt --out ../models
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from train_unet import SignUNet  # noqa: E402

CLASSES = ["background", "exit"]


def sample_inputs(n: int = 3) -> np.ndarray:
    """A few rendered 224 x 224 crops (RGB float [0,1], NCHW) for parity checks."""
    import crops
    xs = []
    for i in range(n):
        rng = np.random.default_rng([99, 7, i])
        img, _ = crops.zoom_sample(rng, True) if i % 2 == 0 else crops.coarse_sample(rng, True)
        xs.append(img.astype(np.float32).transpose(2, 0, 1) / 255.0)
    return np.stack(xs)


def simplify_for_opencv(m):
    """Make the graph loadable by OpenCV 4.6's ONNX importer: Identity nodes (which 4.6 rejects
    when their input is a constant) are bypassed and Constant nodes become initializers."""
    import onnx
    from onnx import numpy_helper
    g = m.graph
    rename = {}
    keep = []
    for n in g.node:
        if n.op_type == "Constant":
            t = next(a.t for a in n.attribute if a.name == "value")
            arr = numpy_helper.to_array(t)
            g.initializer.append(numpy_helper.from_array(arr, n.output[0]))
        elif n.op_type == "Identity" and n.output[0] not in [o.name for o in g.output]:
            rename[n.output[0]] = n.input[0]
        else:
            keep.append(n)
    def resolve(name):
        while name in rename:
            name = rename[name]
        return name
    for n in keep:
        for i, inp in enumerate(n.input):
            n.input[i] = resolve(inp)
    del g.node[:]
    g.node.extend(keep)
    return m


def export_onnx(model, path: str, opset: int = 12, input_hw: tuple = (224, 224)):
    """Exports `model` (eval mode) to ONNX at `path` ("image" in, "logits" out, constants folded, made loadable by
    OpenCV 4.6: simplify_for_opencv) and returns the saved onnx.ModelProto."""
    import onnx
    torch.onnx.export(model, torch.zeros(1, 3, *input_hw), path, input_names=["image"], output_names=["logits"],
                      opset_version=opset, do_constant_folding=True, dynamo=False)
    m = simplify_for_opencv(onnx.load(path))
    onnx.save(m, path)
    return m


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--checkpoint", required=True)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models"))
    ap.add_argument("--opset", type=int, default=12)
    ap.add_argument("--cv46-check", default="/tmp/onnx_cv_dnn_check", help="binary built from tools/onnx_cv_dnn_check.cpp")
    ap.add_argument("--no-coreml", action="store_true")
    a = ap.parse_args(argv)
    if not os.path.exists(a.checkpoint):
        print("export: checkpoint %s not found" % a.checkpoint, file=sys.stderr)
        return 1
    ck = torch.load(a.checkpoint, map_location="cpu")
    classes = ck.get("classes", CLASSES)  # checkpoints before the wall kinds hold background and exit only
    if ck.get("kinds_branch"):  # the Exit model and the wall kinds' decoder: exported with the heads folded
        import kinds_branch
        trained = kinds_branch.KindsBranchUNet(ck["width"], tuple(ck["kinds_branch"]), ck["num_classes"] - 1)
        trained.load_state_dict(ck["state_dict"])
        trained.eval()
        model = kinds_branch.FoldedKindsBranchUNet(trained).eval()
        with torch.no_grad():
            x = torch.from_numpy(sample_inputs(1))
            print("folded heads vs the trained combination: max abs logit difference %.3g" %
                  float((model(x) - trained(x)).abs().max()))
    else:
        model = SignUNet(ck["width"], ck["num_classes"])
        model.load_state_dict(ck["state_dict"])
        model.eval()
    os.makedirs(a.out, exist_ok=True)
    onnx_path = os.path.join(a.out, "sign_unet.onnx")
    dummy = torch.zeros(1, 3, 224, 224)
    m = export_onnx(model, onnx_path, a.opset)
    import onnx
    onnx.checker.check_model(m)
    ops = sorted({n.op_type for n in m.graph.node})
    print("onnx: %s (%.2f MB), opset %d, ops %s" % (onnx_path, os.path.getsize(onnx_path) / 1e6, a.opset, ops))
    with open(os.path.join(a.out, "classes.json"), "w") as f:
        json.dump({"classes": classes}, f)
        f.write("\n")

    X = sample_inputs()
    with torch.no_grad():
        ref = np.concatenate([model(torch.from_numpy(X[i:i + 1])).numpy() for i in range(len(X))])
    import onnxruntime as ort
    sess = ort.InferenceSession(onnx_path, providers=["CPUExecutionProvider"])
    ort_out = np.concatenate([sess.run(["logits"], {"image": X[i:i + 1]})[0] for i in range(len(X))])
    print("parity PyTorch vs ONNX Runtime: max abs diff %.3g" % np.abs(ref - ort_out).max())
    import cv2
    net = cv2.dnn.readNetFromONNX(onnx_path)
    cv_out = []
    for i in range(len(X)):
        net.setInput(X[i:i + 1], "image")
        cv_out.append(net.forward("logits"))
    cv_out = np.concatenate(cv_out)
    print("parity PyTorch vs OpenCV dnn (python cv2 %s): max abs diff %.3g" % (cv2.__version__, np.abs(ref - cv_out).max()))
    if os.path.exists(a.cv46_check):
        with tempfile.TemporaryDirectory() as d:
            diffs = []
            for i in range(len(X)):
                fi, fo = os.path.join(d, "in.f32"), os.path.join(d, "out.f32")
                X[i:i + 1].astype("<f4").tofile(fi)
                r = subprocess.run([a.cv46_check, onnx_path, fi, fo], capture_output=True, text=True)
                if r.returncode != 0:
                    print("OpenCV (C++) check failed: %s" % r.stderr.strip())
                    diffs = None
                    break
                out = np.fromfile(fo, "<f4").reshape(ref[i:i + 1].shape)
                diffs.append(np.abs(out - ref[i:i + 1]).max())
            if diffs is not None:
                print("parity PyTorch vs OpenCV dnn (C++ %s): max abs diff %.3g" % (r.stdout.strip(), max(diffs)))
    else:
        print("note: %s not built; skipped the system-OpenCV (C++) parity check" % a.cv46_check)
    agree = (ref.argmax(1) == ort_out.argmax(1)).mean()
    print("argmax agreement PyTorch vs ONNX Runtime: %.6f" % agree)

    if not a.no_coreml:
        try:
            import coremltools as ct
            traced = torch.jit.trace(model, dummy)
            mlmodel = ct.convert(traced, inputs=[ct.TensorType(name="image", shape=(1, 3, 224, 224))],
                                 outputs=[ct.TensorType(name="logits")], convert_to="mlprogram",
                                 minimum_deployment_target=ct.target.iOS15, compute_precision=ct.precision.FLOAT32)
            mlmodel.short_description = "Sign segmentation U-Net (MobileNetV2 encoder); classes %s" % ", ".join(classes)
            mlmodel.input_description["image"] = "1x3x224x224 RGB float in [0,1]"
            mlmodel.output_description["logits"] = "1x%dx224x224 class logits (%s)" % (len(classes), ", ".join(classes))
            ml_path = os.path.join(a.out, "SignUNet.mlpackage")
            if os.path.exists(ml_path):
                shutil.rmtree(ml_path)
            mlmodel.save(ml_path)
            size = sum(os.path.getsize(os.path.join(dp, f)) for dp, _, fs in os.walk(ml_path) for f in fs)
            print("coreml: %s (%.2f MB); Core ML prediction needs macOS, not run here" % (ml_path, size / 1e6))
        except Exception as e:  # conversion is best effort on Linux
            print("coreml: conversion failed: %s" % e)
            return 0
        # parity of the converted MIL program (graph + weights, evaluated op by op: coreml_parity.py)
        import coreml_parity
        fn = coreml_parity.load_program(ml_path)
        ml = np.concatenate([coreml_parity.run_program(fn, {"image": X[i:i + 1]})["logits"] for i in range(len(X))])
        d = float(np.abs(ml - ref).max())
        print("parity PyTorch vs Core ML MIL program (op-by-op on Linux; Apple's kernels not run): max abs diff %.3g, "
              "argmax agreement %.6f" % (d, float((ml.argmax(1) == ref.argmax(1)).mean())))
        if d > 1e-3:
            print("coreml: parity failed", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
