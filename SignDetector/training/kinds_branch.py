"""The wall sign kinds as a second, light decoder beside a frozen Exit-sign U-Net ("kinds branch"; an experiment,
not installed: docs/training.md "The wall kinds as a branch beside the frozen Exit model").

Why: a six-class U-Net trained on this machine's CPU budget (docs/training.md, tenth and eleventh stops) either lost
the Exit model's sensitivity to small Exit signs (kinds45, kinds25d, ci60k30) or learned too little of the wall
kinds (kinds35): the Exit sign and the four wall kinds compete for one small network. Here they do not compete:
the Exit model (`SignUNet`, two classes) is loaded and frozen, and only a narrower U-Net decoder of its own
(strides 16, 8, 4, then a nearest-neighbour 2x step) reads the frozen encoder's features and gives logits over
(background, restroom, elevator, stairs, placard). The Exit sign's odds are therefore the shipped model's (to float
rounding), and the extra classes cost one narrow decoder (about 10 % of the network's multiply-adds at the default
widths), not a second network. Ordinary multi-task learning with a shared, frozen trunk (e.g. Kokkinos 2017,
"UberNet"); written here because no library ships this network.

Combined output (what the C++ detector and Core ML read: six class logits, render_signs.CLASSES order):
with e = (e0, e1) the Exit model's logits and k = (k0, k1..k4) the branch's,

    z = (e0 + k0,  e1 + k0,  e0 + k1,  e0 + k2,  e0 + k3,  e0 + k4).

Its softmax keeps the Exit model's odds of exit against background exactly (e^(e1 - e0)) and gives a wall kind j the
branch's odds e^(kj - k0) against background; where the branch sees no wall kind the exit probability is the Exit
model's, and the probability of any sign, 1 - P(background), is never below it (the coarse pass keeps every Exit
blob the Exit model gives). The combination is linear in both heads' inputs, so the export
(`FoldedKindsBranchUNet`) has one transposed convolution over the concatenated stride-2 features of the Exit
decoder and the branch; the graph's operators are the Exit model's (Conv, ConvTranspose, Relu, Add, Concat, Sub,
Div) and Resize (nearest), all read by OpenCV 4.6 and converted to Core ML.
"""
from __future__ import annotations

import torch
import torch.nn as nn
import torch.nn.functional as F

from train_unet import SignUNet, Up, conv_call_order, copy_convs, exported_convs

#: Classes of the combined output (render_signs.CLASSES).
COMBINED_CLASSES = ["background", "exit", "restroom", "elevator", "stairs", "placard"]
#: Default decoder widths of the branch at strides 16, 8, 4 (the Exit decoder's are 48, 32, 24 and 16 at stride 2).
DEFAULT_BRANCH_DEC = (16, 12, 8)


def combination_matrices(num_kinds: int = 5) -> tuple:
    """The fixed maps from (e0, e1) and (k0..k_{n-1}) to the combined logits z (module docstring):
    returns (A_e, A_k) of shapes (n + 1, 2) and (n + 1, n) with z = A_e e + A_k k per pixel."""
    n = num_kinds
    a_e = torch.zeros(n + 1, 2)
    a_k = torch.zeros(n + 1, n)
    a_e[0, 0] = 1.0
    a_k[0, 0] = 1.0  # background: e0 + k0
    a_e[1, 1] = 1.0
    a_k[1, 0] = 1.0  # exit: e1 + k0
    for j in range(1, n):  # wall kind j: e0 + kj
        a_e[j + 1, 0] = 1.0
        a_k[j + 1, j] = 1.0
    return a_e, a_k


class KindsDecoder(nn.Module):
    """U-Net decoder over a MobileNetV2 encoder's features down to stride 4, then a nearest-neighbour 2x step to
    stride 2 (a transposed convolution there costs as much as the Exit model's own step, measured in OpenCV dnn);
    `head` gives num_kinds logits at the input resolution from those stride-2 features."""

    def __init__(self, enc_channels, dec=DEFAULT_BRANCH_DEC, num_kinds: int = 5):
        super().__init__()
        c2, c4, c8, c16, c32 = enc_channels
        self.up16 = Up(c32, c16, dec[0])
        self.up8 = Up(dec[0], c8, dec[1])
        self.up4 = Up(dec[1], c4, dec[2])
        self.head = nn.ConvTranspose2d(dec[2], num_kinds, 2, 2)

    def features(self, feats):
        """The branch's features at stride 2 from the encoder's (f2, f4, f8, f16, f32)."""
        f2, f4, f8, f16, f32 = feats
        return F.interpolate(self.up4(self.up8(self.up16(f32, f16), f8), f4), scale_factor=2.0, mode="nearest")

    def forward(self, feats):
        return self.head(self.features(feats))


class KindsBranchUNet(nn.Module):
    """The frozen Exit U-Net (`trunk`, two classes) and a trainable `KindsDecoder` (`branch`) on its encoder's
    features; forward gives the six combined logits (module docstring). The trunk stays in inference mode and
    takes no gradient whatever `train()` is called with."""

    def __init__(self, width: float = 0.35, dec=DEFAULT_BRANCH_DEC, num_kinds: int = 5):
        super().__init__()
        self.trunk = SignUNet(width, 2)
        self.branch = KindsDecoder(self.trunk.enc.channels, dec, num_kinds)
        self.dec = tuple(dec)
        a_e, a_k = combination_matrices(num_kinds)
        self.register_buffer("a_e", a_e)
        self.register_buffer("a_k", a_k)
        for q in self.trunk.parameters():
            q.requires_grad_(False)

    def train(self, mode: bool = True):
        super().train(mode)
        self.trunk.eval()
        return self

    def trunk_features(self, x):
        """(the Exit decoder's stride-2 features y, the encoder's features) of the frozen trunk, without gradient;
        the Exit logits are trunk.head(y)."""
        t = self.trunk
        if t.training:  # e.g. left in training mode by init_from_onnx: BatchNorm would use batch statistics
            t.eval()
        with torch.no_grad():
            feats = t.enc((x - t.mean) / t.std)
            y = t.decoder_features(feats)
        return y, feats

    def trunk_outputs(self, x):
        """(exit logits e, encoder features) of the frozen trunk, without gradient."""
        y, feats = self.trunk_features(x)
        with torch.no_grad():
            e = self.trunk.head(y)
        return e, feats

    def forward(self, x):
        e, feats = self.trunk_outputs(x)
        k = self.branch(feats)
        return torch.einsum("cj,njhw->nchw", self.a_e, e) + torch.einsum("cj,njhw->nchw", self.a_k, k)


class FoldedKindsBranchUNet(nn.Module):
    """Export form of a `KindsBranchUNet`: the same six logits (up to float rounding) from one transposed
    convolution over the concatenated stride-2 features (the Exit decoder's, then the branch's), whose weights are
    each head's times its combination matrix (z = A_e e + A_k k is linear in both feature sets)."""

    def __init__(self, m: KindsBranchUNet):
        super().__init__()
        t = m.trunk
        self.trunk = t  # its head is not called: the joint head below replaces it
        self.branch = m.branch
        he, hk = t.head, m.branch.head
        self.head = nn.ConvTranspose2d(he.in_channels + hk.in_channels, m.a_e.shape[0], he.kernel_size, he.stride)
        with torch.no_grad():
            self.head.weight.copy_(torch.cat([torch.einsum("ck,ikhw->ichw", m.a_e, he.weight),
                                              torch.einsum("ck,ikhw->ichw", m.a_k, hk.weight)], 0))
            self.head.bias.copy_(m.a_e @ he.bias + m.a_k @ hk.bias)

    def forward(self, x):
        t = self.trunk
        feats = t.enc((x - t.mean) / t.std)
        return self.head(torch.cat([t.decoder_features(feats), self.branch.features(feats)], 1))


def _conv_modules(module: nn.Module) -> list:
    return [m for m in module.modules() if isinstance(m, (nn.Conv2d, nn.ConvTranspose2d))]


def unfold_joint_head(w: torch.Tensor, b: torch.Tensor, trunk_channels: int, num_kinds: int) -> tuple:
    """The two heads of an exported joint head (weight (cin_trunk + cin_branch, n + 1, kh, kw), bias n + 1):
    ((w_e, b_e), (w_k, b_k)) such that A_e e + A_k k gives the same logits. The weights are the rows that copy a
    logit (background e0 and exit e1 from the trunk's inputs; k0 and the kinds from the branch's); the bias is
    split as b_e = (z_bg, z_exit) and b_k = (0, z_j - z_bg): the exported sum, exactly."""
    kind_rows = [0] + list(range(2, num_kinds + 1))
    w_e = w[:trunk_channels, [0, 1]].contiguous()
    w_k = w[trunk_channels:, kind_rows].contiguous()
    b_e = b[[0, 1]].contiguous()
    b_k = torch.cat([torch.zeros(1, dtype=b.dtype), b[2:num_kinds + 1] - b[0]])
    return (w_e, b_e), (w_k, b_k)


def init_from_exported(model: KindsBranchUNet, onnx_path: str) -> str:
    """Loads an exported model into `model`: an Exit-only U-Net (two classes) into the trunk (the branch keeps its
    initialisation), or an exported kinds-branch model (graph order: the trunk's convolutions up to its stride-2
    features, the branch's, the joint head) into both (unfold_joint_head). Returns "trunk" or "trunk and branch";
    raises ValueError naming the file when the shapes match neither."""
    convs = exported_convs(onnx_path)
    trunk_order = conv_call_order(model.trunk)
    if len(convs) == len(trunk_order):
        copy_convs(model.trunk, trunk_order, convs, onnx_path)
        return "trunk"
    branch_order = _conv_modules(model.branch)
    n_t = len(trunk_order) - 1  # the trunk's convolutions without its head
    if len(convs) != n_t + len(branch_order):
        raise ValueError("%s has %d convolutions: neither an Exit U-Net (%d) nor a kinds-branch model (%d)" %
                         (onnx_path, len(convs), n_t + 1, n_t + len(branch_order)))
    w, b = convs[-1]
    if b is None or w.shape[0] != model.trunk.head.in_channels + model.branch.head.in_channels:
        raise ValueError("%s: joint head weight %s does not fit this model" % (onnx_path, tuple(w.shape)))
    head_e, head_k = unfold_joint_head(w, b, model.trunk.head.in_channels, model.a_k.shape[1])
    copy_convs(model.trunk, trunk_order, convs[:n_t] + [head_e], onnx_path)
    copy_convs(model.branch, branch_order, convs[n_t:-1] + [head_k], onnx_path)
    return "trunk and branch"


def trunk_convs_of_exported(convs: list, trunk_conv_count: int, trunk_head_channels: int) -> list:
    """An exported kinds-branch model's convolutions reduced to its Exit trunk's (for a plain two-class SignUNet):
    the trunk's up to its stride-2 features and the Exit head unfolded from the joint head."""
    w, b = convs[-1]
    (w_e, b_e), _ = unfold_joint_head(w, b, trunk_head_channels, w.shape[1] - 1)
    return convs[:trunk_conv_count - 1] + [(w_e, b_e)]
