"""The committed Core ML package (models/SignUNet.mlpackage) computes what the committed ONNX model
computes: its MIL program (graph and weights) is evaluated op by op with coreml_parity.py and
compared with ONNX Runtime. Skipped without coremltools (training-time dependency). Apple's own
kernels are not run (no Core ML on Linux)."""
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
MODELS = os.path.join(HERE, "..", "..", "models")


def test_mlpackage_program_matches_onnx():
    pytest.importorskip("coremltools")
    ort = pytest.importorskip("onnxruntime")
    import coreml_parity
    import export_unet
    x = export_unet.sample_inputs(2)
    fn = coreml_parity.load_program(os.path.join(MODELS, "SignUNet.mlpackage"))
    ml = np.concatenate([coreml_parity.run_program(fn, {"image": x[i:i + 1]})["logits"] for i in range(len(x))])
    s = ort.InferenceSession(os.path.join(MODELS, "sign_unet.onnx"), providers=["CPUExecutionProvider"])
    ref = np.concatenate([s.run(None, {"image": x[i:i + 1]})[0] for i in range(len(x))])
    assert ml.shape == ref.shape == (2, 2, 224, 224)
    assert np.abs(ml - ref).max() < 1e-3
    assert (ml.argmax(1) == ref.argmax(1)).mean() > 0.9999


def test_interpreter_rejects_a_missing_package():
    pytest.importorskip("coremltools")
    import coreml_parity
    with pytest.raises(FileNotFoundError, match="not an .mlpackage"):
        coreml_parity.load_program(os.path.join(MODELS, "no_such.mlpackage"))
