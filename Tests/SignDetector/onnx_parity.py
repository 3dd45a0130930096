#!/usr/bin/env python3
"""Output parity of the U-Net between ONNX Runtime (the training side's reference runtime) and OpenCV 4.6
cv::dnn (the detector's run-time path, through the C++ dumper `wf_unet_dump`).

Runs each model on fixed inputs (seeded uniform noise, zeros, ones, a colour gradient) in both runtimes and
asserts max |logit difference| < 1e-3. Models checked:
  * SignDetector/models/sign_unet.onnx, the product model (skipped with a message while it is absent);
  * Tests/SignDetector/data/tiny_red_unet.onnx, the committed test model;
  * a small random-weights network with the decoder's upsampling: a 2 x 2 stride-2 ConvTranspose (the detector
    computes it as a 1 x 1 convolution plus depth-to-space, SignDetector/src/subpixel_transposed_conv.hpp) beside a
    4 x 4 stride-2 one with padding (left to OpenCV's own layer);
  * a small random-weights network built here with the operators a MobileNetV2 U-Net exports to
    (strided and depthwise Conv, BatchNormalization, Relu, Resize x2, Concat skip, 1x1 Conv head). Not Clip:
    OpenCV 4.6's importer rejects Clip with min/max inputs (how opset >= 11 exports ReLU6), so the training
    side replaces ReLU6 with ReLU (SignDetector/training/train_unet.py).

Usage (CTest runs it with the built dumper):
  python3 Tests/SignDetector/onnx_parity.py --dumper /tmp/cmake-build/SignDetector/wf_unet_dump
Exit status: 0 = all checked models agree, 1 = a mismatch or a runtime failure, 77 = skipped (no onnxruntime).
"""
import argparse
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PRODUCT_MODEL = os.path.join(ROOT, "SignDetector", "models", "sign_unet.onnx")
TINY_MODEL = os.path.join(ROOT, "Tests", "SignDetector", "data", "tiny_red_unet.onnx")
TOLERANCE = 1e-3

try:
    import numpy as np
    import onnx
    import onnxruntime as ort
    from onnx import TensorProto, helper, numpy_helper
except ImportError as e:  # pragma: no cover - environment without the Python tools
    print("SKIP: onnx_parity needs numpy, onnx and onnxruntime (scripts/setup.sh installs them): %s" % e)
    sys.exit(77)


def fixed_inputs(size: int):
    """Four deterministic 1x3xSxS float32 inputs in [0, 1]."""
    rng = np.random.default_rng(20240611)
    ramp = np.linspace(0.0, 1.0, size, dtype=np.float32)
    gradient = np.stack([np.tile(ramp, (size, 1)), np.tile(ramp[:, None], (1, size)),
                         np.full((size, size), 0.3, np.float32)])[None]
    return {
        "uniform": rng.random((1, 3, size, size), dtype=np.float32),
        "zeros": np.zeros((1, 3, size, size), np.float32),
        "ones": np.ones((1, 3, size, size), np.float32),
        "gradient": gradient.astype(np.float32),
    }


def random_weights(seed: int):
    """w(name, shape, scale): a float32 initializer of seeded normal noise times scale."""
    rng = np.random.default_rng(seed)

    def w(name, shape, scale=0.3):
        return numpy_helper.from_array((rng.standard_normal(shape) * scale).astype(np.float32), name)

    return rng, w


def segmentation_model(name: str, nodes, inits, size: int) -> onnx.ModelProto:
    """A checked opset-11 model: input "image" 1x3xSxS, output "logits" 1x2xSxS."""
    graph = helper.make_graph(nodes, name, [helper.make_tensor_value_info("image", TensorProto.FLOAT, [1, 3, size, size])],
                              [helper.make_tensor_value_info("logits", TensorProto.FLOAT, [1, 2, size, size])], inits)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 11)], producer_name="wayfinder-tests")
    model.ir_version = 6
    onnx.checker.check_model(model)
    return model


def mobilenet_like_model(size: int = 224, seed: int = 7) -> onnx.ModelProto:
    """A small random-weights segmentation net using the operators of an exported MobileNetV2 U-Net."""
    rng, w = random_weights(seed)

    inits = [
        w("c1_w", (8, 3, 3, 3)), w("c1_b", (8,), 0.1),
        numpy_helper.from_array((1 + 0.1 * rng.standard_normal(8)).astype(np.float32), "bn_scale"),
        w("bn_bias", (8,), 0.1), w("bn_mean", (8,), 0.1),
        numpy_helper.from_array((1 + 0.2 * rng.random(8)).astype(np.float32), "bn_var"),
        w("dw_w", (8, 1, 3, 3)), w("pw_w", (16, 8, 1, 1)), w("pw_b", (16,), 0.1),
        numpy_helper.from_array(np.array([], np.float32), "roi"),
        numpy_helper.from_array(np.array([1, 1, 2, 2], np.float32), "scales"),
        w("skip_w", (4, 3, 3, 3)), w("head_w", (2, 20, 1, 1)), w("head_b", (2,), 0.1),
    ]
    nodes = [
        helper.make_node("Conv", ["image", "c1_w", "c1_b"], ["c1"], kernel_shape=[3, 3], strides=[2, 2], pads=[1, 1, 1, 1]),
        helper.make_node("BatchNormalization", ["c1", "bn_scale", "bn_bias", "bn_mean", "bn_var"], ["bn"], epsilon=1e-5),
        helper.make_node("Relu", ["bn"], ["r1"]),
        helper.make_node("Conv", ["r1", "dw_w"], ["dw"], kernel_shape=[3, 3], pads=[1, 1, 1, 1], group=8),
        helper.make_node("Relu", ["dw"], ["r2"]),
        helper.make_node("Conv", ["r2", "pw_w", "pw_b"], ["pw"], kernel_shape=[1, 1]),
        helper.make_node("Resize", ["pw", "roi", "scales"], ["up"], mode="nearest"),
        helper.make_node("Conv", ["image", "skip_w"], ["skip"], kernel_shape=[3, 3], pads=[1, 1, 1, 1]),
        helper.make_node("Concat", ["up", "skip"], ["cat"], axis=1),
        helper.make_node("Conv", ["cat", "head_w", "head_b"], ["logits"], kernel_shape=[1, 1]),
    ]
    return segmentation_model("mobilenet_like", nodes, inits, size)


def transposed_model(size: int = 64, seed: int = 11) -> onnx.ModelProto:
    """Random weights: Conv s2 -> Relu -> ConvTranspose 2x2 s2 (bias) beside Conv s2 -> ConvTranspose 4x4 s2 pad 1,
    concatenated, 1x1 Conv head."""
    _, w = random_weights(seed)

    inits = [w("c1_w", (8, 3, 3, 3)), w("c1_b", (8,), 0.1), w("up_w", (8, 6, 2, 2)), w("up_b", (6,), 0.1),
             w("c2_w", (5, 3, 3, 3)), w("up4_w", (5, 3, 4, 4)), w("head_w", (2, 9, 1, 1)), w("head_b", (2,), 0.1)]
    nodes = [
        helper.make_node("Conv", ["image", "c1_w", "c1_b"], ["c1"], kernel_shape=[3, 3], strides=[2, 2], pads=[1, 1, 1, 1]),
        helper.make_node("Relu", ["c1"], ["r1"]),
        helper.make_node("ConvTranspose", ["r1", "up_w", "up_b"], ["up"], kernel_shape=[2, 2], strides=[2, 2]),
        helper.make_node("Conv", ["image", "c2_w"], ["c2"], kernel_shape=[3, 3], strides=[2, 2], pads=[1, 1, 1, 1]),
        helper.make_node("ConvTranspose", ["c2", "up4_w"], ["up4"], kernel_shape=[4, 4], strides=[2, 2], pads=[1, 1, 1, 1]),
        helper.make_node("Concat", ["up", "up4"], ["cat"], axis=1),
        helper.make_node("Conv", ["cat", "head_w", "head_b"], ["logits"], kernel_shape=[1, 1]),
    ]
    return segmentation_model("transposed", nodes, inits, size)


def input_size(model_path: str) -> int:
    model = onnx.load(model_path)
    dims = model.graph.input[0].type.tensor_type.shape.dim
    side = dims[-1].dim_value
    return side if side > 0 else 224


def check(model_path: str, dumper: str, label: str, dumper_args=()) -> bool:
    size = input_size(model_path)
    session = ort.InferenceSession(model_path, providers=["CPUExecutionProvider"])
    input_name = session.get_inputs()[0].name
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for name, x in fixed_inputs(size).items():
            expected = session.run(None, {input_name: x})[0]
            in_path, out_path = os.path.join(tmp, "in.f32"), os.path.join(tmp, "out.f32")
            x.tofile(in_path)
            run = subprocess.run([dumper, model_path, str(size), in_path, out_path, *dumper_args], capture_output=True, text=True)
            if run.returncode != 0:
                print("FAIL %s [%s]: wf_unet_dump failed: %s" % (label, name, run.stderr.strip()))
                return False
            got = np.fromfile(out_path, dtype=np.float32)
            if got.size != expected.size:
                print("FAIL %s [%s]: cv::dnn gave %d values, ONNX Runtime %s" % (label, name, got.size, expected.shape))
                return False
            diff = float(np.max(np.abs(got.reshape(expected.shape) - expected)))
            status = "ok" if diff < TOLERANCE else "FAIL"
            ok &= diff < TOLERANCE
            print("%-4s %s [%s]: max |cv::dnn - onnxruntime| = %.3g (tolerance %g), output %s"
                  % (status, label, name, diff, TOLERANCE, list(expected.shape)))
    return ok


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dumper", default=os.environ.get("WF_UNET_DUMP"), help="path of the built wf_unet_dump")
    ap.add_argument("--model", default=PRODUCT_MODEL, help="product model (default SignDetector/models/sign_unet.onnx)")
    args = ap.parse_args()
    if not args.dumper or not os.path.exists(args.dumper):
        print("FAIL: --dumper must name the built wf_unet_dump (got %r)" % args.dumper)
        return 1
    ok = True
    if os.path.exists(args.model):
        ok &= check(args.model, args.dumper, os.path.relpath(args.model, ROOT))
        ok &= check(args.model, args.dumper, os.path.relpath(args.model, ROOT) + " (OpenCV's Deconvolution)",
                    ("--opencv-deconvolution",))
    else:
        print("SKIP product model: %s is not present yet (the training engineer commits it)" % os.path.relpath(args.model, ROOT))
    ok &= check(TINY_MODEL, args.dumper, "tiny_red_unet.onnx")
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "mobilenet_like.onnx")
        onnx.save(mobilenet_like_model(), path)
        ok &= check(path, args.dumper, "mobilenet_like (random weights)")
        path = os.path.join(tmp, "transposed.onnx")
        onnx.save(transposed_model(), path)
        ok &= check(path, args.dumper, "transposed (random weights)")
        ok &= check(path, args.dumper, "transposed (random weights, OpenCV's Deconvolution)", ("--opencv-deconvolution",))
    print("onnx_parity: %s" % ("all models agree" if ok else "MISMATCH"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
