"""train_unet.py tools: the warm start from an exported ONNX model reproduces that model, heavy
augmentation is deterministic per generator seed and keeps images in range, and rendered training
samples (the U-Net's and the phone-style cascade windows) do not depend on the number of rendering processes.
The torch tests are skipped without torch (training-time dependency)."""
import json
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
MODELS = os.path.join(HERE, "..", "..", "models")


def test_init_from_onnx_reproduces_the_exported_model():
    torch = pytest.importorskip("torch")
    ort = pytest.importorskip("onnxruntime")
    import export_unet
    import train_unet as tu
    with open(os.path.join(MODELS, "classes.json")) as f:
        k = len(json.load(f)["classes"])
    if k == 2:
        m = tu.SignUNet(0.35, k)
        assert tu.init_from_onnx(m, os.path.join(MODELS, "sign_unet.onnx")) == 68
        m.train()
        tu.freeze_bn(m)  # training mode elsewhere, BatchNorm frozen: still the exported function
    else:  # the Exit model with the wall kinds' decoder beside it (kinds_branch.py)
        import kinds_branch as kb
        branch = kb.KindsBranchUNet(0.35, kb.DEFAULT_BRANCH_DEC, k - 1)
        assert kb.init_from_exported(branch, os.path.join(MODELS, "sign_unet.onnx")) == "trunk and branch"
        branch.train()
        tu.freeze_bn(branch)
        m = kb.FoldedKindsBranchUNet(branch)
    x = export_unet.sample_inputs(2)
    with torch.no_grad():
        y = m(torch.from_numpy(x)).numpy()
    s = ort.InferenceSession(os.path.join(MODELS, "sign_unet.onnx"), providers=["CPUExecutionProvider"])
    ref = np.concatenate([s.run(None, {"image": x[i:i + 1]})[0] for i in range(len(x))])
    assert np.abs(y - ref).max() < 1e-3


def test_heavy_augment_is_seeded_and_in_range():
    torch = pytest.importorskip("torch")
    import train_unet as tu
    x = torch.rand(4, 3, 64, 64, generator=torch.Generator().manual_seed(0))
    a = tu.heavy_augment(x, torch.Generator().manual_seed(5))
    b = tu.heavy_augment(x, torch.Generator().manual_seed(5))
    c = tu.heavy_augment(x, torch.Generator().manual_seed(6))
    assert torch.equal(a, b) and not torch.equal(a, c)
    assert a.shape == x.shape and float(a.min()) >= 0.0 and float(a.max()) <= 1.0


def test_rendered_samples_do_not_depend_on_workers():
    pytest.importorskip("torch")
    import train_unet as tu
    X1, Y1, K1 = tu.render_samples(4, 11, 9, lambda m: None, phone_frac=0.5, workers=1)
    X2, Y2, K2 = tu.render_samples(4, 11, 9, lambda m: None, phone_frac=0.5, workers=2)
    assert np.array_equal(X1, X2) and np.array_equal(Y1, Y2) and np.array_equal(K1, K2)


def test_kind_samples_carry_their_own_classes():
    """With kinds_frac 1 every sample shows a wall sign kind (types kind_coarse / kind_zoom) and its mask holds
    that kind's class of render_signs.CLASSES; kinds_frac 0 skips the draw (the Exit-only sets are unchanged)."""
    pytest.importorskip("torch")
    import render_signs as rs
    import train_unet as tu
    X, Y, K = tu.render_samples(6, 11, 9, lambda m: None, kinds_frac=1.0)
    assert set(K.tolist()) <= {4, 5}
    for y in Y:
        assert set(np.unique(y).tolist()) <= set(range(len(rs.CLASSES)))
    # zoomed samples are centred on their kind's face: a wall-kind class covers a real share of the crop
    zooms = [y for y, k in zip(Y, K) if k == 5]
    assert zooms and all(((y >= 2) & (y <= 5)).mean() > 0.002 for y in zooms)
    X0, Y0, K0 = tu.render_samples(3, 11, 9, lambda m: None)
    X1, Y1, K1 = tu.render_samples(3, 11, 9, lambda m: None, kinds_frac=0.0)
    assert np.array_equal(X0, X1) and np.array_equal(K0, K1) and set(K0.tolist()) <= {0, 1, 2, 3}


def test_a_widened_head_keeps_the_exported_classes():
    """init_from_onnx into a model with more classes than the exported one: the exported classes' logits are
    reproduced, each new class starts below the last exported (sign) class."""
    torch = pytest.importorskip("torch")
    ort = pytest.importorskip("onnxruntime")
    import export_unet
    import train_unet as tu
    with open(os.path.join(MODELS, "classes.json")) as f:
        k0 = len(json.load(f)["classes"])
    torch.manual_seed(0)
    m = tu.SignUNet(0.35, k0 + 2)
    assert tu.init_from_onnx(m, os.path.join(MODELS, "sign_unet.onnx")) == 68
    m.eval()
    x = export_unet.sample_inputs(2)
    with torch.no_grad():
        y = m(torch.from_numpy(x)).numpy()
    s = ort.InferenceSession(os.path.join(MODELS, "sign_unet.onnx"), providers=["CPUExecutionProvider"])
    ref = np.concatenate([s.run(None, {"image": x[i:i + 1]})[0] for i in range(len(x))])
    assert np.abs(y[:, :k0] - ref).max() < 1e-3
    assert (y[:, k0:] < y[:, k0 - 1:k0]).mean() > 0.95


def test_foreground_weighted_distillation_emphasises_the_teachers_sign_pixels():
    torch = pytest.importorskip("torch")
    import train_unet as tu
    g = torch.Generator().manual_seed(3)
    logits = torch.randn(2, 6, 8, 8, generator=g)
    teacher = torch.zeros(2, 2, 8, 8)
    teacher[:, 0] = 1.0
    teacher[:, :, 2, 3] = torch.tensor([0.1, 0.9]).view(1, 2)  # one sign pixel per sample
    keep = torch.tensor([True, True])
    plain = tu.distill_loss(logits, teacher, keep)
    assert torch.allclose(tu.distill_loss(logits, teacher, keep, 0.0), plain)
    # the sign pixel's cross-entropy alone, and the weighted loss moves towards it
    logp = torch.log_softmax(logits, 1)
    sign_ce = -(0.1 * logp[:, 0, 2, 3] + 0.9 * logp[:, 1, 2, 3]).mean()
    weighted = tu.distill_loss(logits, teacher, keep, 30.0)
    assert abs(float(weighted - sign_ce)) < abs(float(plain - sign_ce))
    assert float(tu.distill_loss(logits, teacher, torch.tensor([False, False]), 30.0)) == 0.0


def test_a_six_class_export_loads_into_the_two_class_model_as_its_first_classes(tmp_path):
    torch = pytest.importorskip("torch")
    pytest.importorskip("onnx")
    import export_unet
    import train_unet as tu
    torch.manual_seed(4)
    six = tu.SignUNet(0.35, 6).eval()
    path = str(tmp_path / "six.onnx")
    export_unet.export_onnx(six, path, input_hw=(64, 64))
    two = tu.SignUNet(0.35, 2)
    assert tu.init_from_onnx(two, path) == 68
    two.eval()
    x = torch.rand(1, 3, 64, 64, generator=torch.Generator().manual_seed(5))
    with torch.no_grad():
        assert float((two(x) - six(x)[:, :2]).abs().max()) < 1e-3


def test_phone_cascade_samples_are_seeded_sized_and_independent_of_workers():
    """train_cascade.py --phone-pos / --phone-neg-frames: phone-style Exit windows at the cascade's 24 x 16 and
    sign-free VGA frames, the same for a seed whatever the number of rendering processes."""
    import crops
    import train_cascade as tc
    a = tc.rendered(crops.cascade_positive_phone, 7, 16, 4, workers=1)
    b = tc.rendered(crops.cascade_positive_phone, 7, 16, 4, workers=2)
    assert all(x.shape == (16, 24) and x.dtype == np.uint8 for x in a)
    assert all(np.array_equal(x, y) for x, y in zip(a, b))
    assert not np.array_equal(a[0], a[1])
    g = crops.negative_frame_phone(np.random.default_rng([7, 17, 0]))
    assert g.ndim == 2 and max(g.shape) == 640


def test_sample_cache_names_the_phone_styles_tone_curve(tmp_path, monkeypatch):
    """Phone-style samples are cached under their tone curve: samples rendered linear (before 2026-12-07) under the
    old name are not reused for a recipe that now renders sRGB."""
    pytest.importorskip("torch")
    import numpy as np
    import train_unet as tu
    calls = []

    def fake_render(n, seed, split_code, log, phone_frac, workers, kinds_frac):
        calls.append(n)
        return np.full((n, 2, 2, 3), len(calls), np.uint8), np.zeros((n, 2, 2), np.uint8), np.zeros(n, np.int64)

    monkeypatch.setattr(tu, "render_samples", fake_render)
    stale = tmp_path / "unet_samples_seed11_split1_n3_phone50.npz"
    np.savez(stale, X=np.zeros((3, 2, 2, 3), np.uint8), Y=np.zeros((3, 2, 2), np.uint8), kinds=np.zeros(3, np.int64))
    X, _, _ = tu.load_or_render(str(tmp_path), 3, 11, 1, print, phone_frac=0.5)
    assert calls == [3] and X[0, 0, 0, 0] == 1, "the linear-era cache must not be reused"
    assert (tmp_path / "unet_samples_seed11_split1_n3_phone50_srgb.npz").exists()
    X, _, _ = tu.load_or_render(str(tmp_path), 3, 11, 1, print, phone_frac=0.5)
    assert calls == [3] and X[0, 0, 0, 0] == 1, "the sRGB cache is reused"
    tu.load_or_render(str(tmp_path), 3, 11, 1, print, phone_frac=0.0)
    assert calls == [3, 3] and (tmp_path / "unet_samples_seed11_split1_n3.npz").exists(), "classic samples: no tag"
