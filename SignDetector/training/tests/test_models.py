"""The committed models load in OpenCV and work on held-out renders (seed 4242, not a training
seed): the cascade XML in cv2.CascadeClassifier, the ONNX U-Net in cv2.dnn (the Python wheel; the
system OpenCV 4.6 is checked by export_unet.py with tools/onnx_cv_dnn_check.cpp)."""
import json
import math
import os
import sys

import cv2
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
import render_signs as rs  # noqa: E402

MODELS = os.path.join(HERE, "..", "..", "models")


def _held_out_frames(n, distance_m):
    intr = rs.scaled_intrinsics(640, 480)
    out = []
    for i in range(n):
        rng = np.random.default_rng([4242, 9, int(distance_m * 100), i])
        T, signs, info = rs.sample_scene(rng, intr, distance_m, test=True)
        img, mask, labels = rs.render_frame(T, intr, signs, rng, occlusion_prob=0.0)
        u, A, intr_u = rs.unroll_image(img, intr, info["roll"])
        c = np.array(labels[0]["cornersRaw"]) @ A[:, :2].T + A[:, 2]
        out.append((u, c))
    return out


def test_cascade_loads_and_detects_held_out_signs():
    cc = cv2.CascadeClassifier(os.path.join(MODELS, "exit_sign_cascade.xml"))
    assert not cc.empty()
    hits = 0
    frames = _held_out_frames(12, 2.5)
    for img, corners in frames:
        g = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
        rects = cc.detectMultiScale(g, scaleFactor=1.1, minNeighbors=3, minSize=(24, 16))
        cx, cy = corners.mean(axis=0)
        hits += any(x <= cx <= x + w and y <= cy <= y + h for x, y, w, h in rects)
    assert hits / len(frames) >= 0.5, hits  # measured recall at 2-3 m is higher; see docs/training.md


def test_unet_onnx_runs_in_opencv_dnn():
    path = os.path.join(MODELS, "sign_unet.onnx")
    net = cv2.dnn.readNetFromONNX(path)
    x = np.zeros((1, 3, 224, 224), np.float32)
    net.setInput(x, "image")
    y = net.forward("logits")
    assert y.shape == (1, 2, 224, 224)
    classes = json.load(open(os.path.join(MODELS, "classes.json")))["classes"]
    assert classes == ["background", "exit"]
    assert os.path.getsize(path) < 5e6
