"""kinds_branch.py: the wall kinds' decoder beside a frozen Exit U-Net. The combined output keeps the Exit model's
odds exactly, the folded export computes the same logits, an exported model loads back (whole, or its Exit trunk
alone into a plain two-class U-Net), and the trunk neither trains nor moves its BatchNorm statistics. Skipped
without torch (training-time dependency)."""
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))


def _random_model(torch, seed):
    import kinds_branch as kb
    torch.manual_seed(seed)
    m = kb.KindsBranchUNet(0.35, (8, 8, 8))
    # random, non-trivial BatchNorm statistics so that a train/eval mix-up shows
    for mod in m.modules():
        if isinstance(mod, torch.nn.BatchNorm2d):
            mod.running_mean.uniform_(-0.2, 0.2)
            mod.running_var.uniform_(0.5, 1.5)
    return m.eval()


def test_combined_output_keeps_the_exit_models_odds_and_any_sign_is_never_below_exit():
    torch = pytest.importorskip("torch")
    m = _random_model(torch, 1)
    x = torch.rand(2, 3, 64, 96, generator=torch.Generator().manual_seed(2))
    with torch.no_grad():
        z = m(x)
        e, _ = m.trunk_outputs(x)
    assert z.shape == (2, 6, 64, 96)
    # log odds of exit against background are the Exit model's, to float rounding
    assert float(((z[:, 1] - z[:, 0]) - (e[:, 1] - e[:, 0])).abs().max()) < 1e-4
    p, pe = z.softmax(1), e.softmax(1)
    assert bool((1 - p[:, 0] >= pe[:, 1] - 1e-6).all())


def test_the_folded_export_form_computes_the_same_logits():
    torch = pytest.importorskip("torch")
    import kinds_branch as kb
    m = _random_model(torch, 3)
    f = kb.FoldedKindsBranchUNet(m).eval()
    x = torch.rand(2, 3, 64, 64, generator=torch.Generator().manual_seed(4))
    with torch.no_grad():
        assert float((f(x) - m(x)).abs().max()) < 1e-4


def test_an_exported_model_loads_back_whole_and_as_the_exit_trunk(tmp_path):
    torch = pytest.importorskip("torch")
    pytest.importorskip("onnx")
    import export_unet
    import kinds_branch as kb
    import train_unet as tu
    m = _random_model(torch, 5)
    path = str(tmp_path / "combined.onnx")
    export_unet.export_onnx(kb.FoldedKindsBranchUNet(m).eval(), path, input_hw=(64, 64))
    x = torch.rand(1, 3, 64, 64, generator=torch.Generator().manual_seed(6))
    back = kb.KindsBranchUNet(0.35, (8, 8, 8))
    assert kb.init_from_exported(back, path) == "trunk and branch"
    back.eval()
    trunk = tu.SignUNet(0.35, 2)
    assert tu.init_from_onnx(trunk, path) == 68
    trunk.eval()
    with torch.no_grad():
        assert float((back(x) - m(x)).abs().max()) < 1e-3
        e_back, e = trunk(x), m.trunk_outputs(x)[0]  # the same up to a constant per pixel: compare the log odds
        assert float(((e_back[:, 1] - e_back[:, 0]) - (e[:, 1] - e[:, 0])).abs().max()) < 1e-3
    with pytest.raises(ValueError, match="combined.onnx"):
        kb.init_from_exported(kb.KindsBranchUNet(0.35, (8, 8, 16)), path)  # other widths


def test_training_moves_the_branch_only():
    torch = pytest.importorskip("torch")
    m = _random_model(torch, 7)
    m.train()
    before = {k: v.clone() for k, v in m.trunk.state_dict().items()}
    branch_before = [q.clone() for q in m.branch.parameters()]
    opt = torch.optim.SGD([q for q in m.parameters() if q.requires_grad], lr=0.1)
    x = torch.rand(2, 3, 64, 64)
    y = torch.randint(0, 6, (2, 64, 64))
    for _ in range(2):
        loss = torch.nn.functional.cross_entropy(m(x), y)
        opt.zero_grad()
        loss.backward()
        opt.step()
    for k, v in m.trunk.state_dict().items():  # weights and BatchNorm statistics alike
        assert torch.equal(v, before[k]), k
    assert any(not torch.equal(a, b) for a, b in zip(branch_before, m.branch.parameters()))
    assert not m.trunk.training
