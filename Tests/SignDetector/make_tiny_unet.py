#!/usr/bin/env python3
"""Writes the tiny stand-in segmentation model used by the SignDetector tests.

data/tiny_red_unet.onnx has the interface of SignDetector/models/sign_unet.onnx (input "image"
1x3x224x224 float32 RGB in [0, 1], output "logits" 1x2x224x224, class 0 background, class 1 exit) but is
a single 3x3 convolution that marks saturated red pixels:
    logit_exit = 30 R - 30 G - 30 B - 5,   logit_background = 0
(centre tap only), so a red sign plate segments cleanly and a white/gray wall does not. It is
deterministic and a few hundred bytes.

data/tiny_kinds/sign_unet.onnx (classes.json beside it: background, exit, restroom) is the same convolution
with a third class: the red pixels are "restroom" (logit 30 R - 30 G - 30 B - 5) and the exit class never wins
(logit -100), so a drawn sign stands for a wall sign kind of a multi-class U-Net. Re-run after changing them:
    python3 Tests/SignDetector/make_tiny_unet.py
"""
import json
import os

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

HERE = os.path.dirname(os.path.abspath(__file__))


def build(size: int = 224, red_class: int = 1, classes: int = 2) -> onnx.ModelProto:
    """The red-pixel segmenter with `classes` output classes; red pixels are class `red_class`, the other sign
    classes never win (bias -100)."""
    weights = np.zeros((classes, 3, 3, 3), dtype=np.float32)
    weights[red_class, :, 1, 1] = [30.0, -30.0, -30.0]
    bias = np.full(classes, -100.0, dtype=np.float32)
    bias[0] = 0.0
    bias[red_class] = -5.0
    graph = helper.make_graph(
        [helper.make_node("Conv", ["image", "w", "b"], ["logits"], kernel_shape=[3, 3], pads=[1, 1, 1, 1])],
        "tiny_red_unet",
        [helper.make_tensor_value_info("image", TensorProto.FLOAT, [1, 3, size, size])],
        [helper.make_tensor_value_info("logits", TensorProto.FLOAT, [1, classes, size, size])],
        [numpy_helper.from_array(weights, "w"), numpy_helper.from_array(bias, "b")],
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 11)], producer_name="wayfinder-tests")
    model.ir_version = 6
    onnx.checker.check_model(model)
    return model


def main() -> None:
    out_dir = os.path.join(HERE, "data")
    os.makedirs(out_dir, exist_ok=True)
    onnx.save(build(), os.path.join(out_dir, "tiny_red_unet.onnx"))
    with open(os.path.join(out_dir, "classes.json"), "w") as f:
        json.dump({"classes": ["background", "exit"]}, f)
        f.write("\n")
    print("wrote", os.path.join(out_dir, "tiny_red_unet.onnx"))
    kinds_dir = os.path.join(out_dir, "tiny_kinds")
    os.makedirs(kinds_dir, exist_ok=True)
    onnx.save(build(red_class=2, classes=3), os.path.join(kinds_dir, "sign_unet.onnx"))
    with open(os.path.join(kinds_dir, "classes.json"), "w") as f:
        json.dump({"classes": ["background", "exit", "restroom"]}, f)
        f.write("\n")
    print("wrote", os.path.join(kinds_dir, "sign_unet.onnx"))


if __name__ == "__main__":
    main()
