#!/usr/bin/env python3
"""Train the Exit-sign segmentation U-Net (MobileNetV2 encoder, U-Net decoder) on rendered crops.

Architecture: MobileNetV2 (Sandler et al. 2018) with width multiplier --width (default 0.35),
written here with torch.nn (no pretrained weights exist offline: trained from scratch); a U-Net
decoder (Ronneberger et al. 2015) upsamples with 2x2 stride-2 transposed convolutions and
concatenates the encoder features at strides 16, 8, 4 and 2; a 1x1 convolution gives K class logits
at the input resolution (K = 2: background, exit). Input 1 x 3 x 224 x 224 RGB in [0, 1]. Only
Conv, BatchNorm (folded at export), ReLU, Add, Concat and ConvTranspose: operators that OpenCV 4.6's
ONNX importer and Core ML support. ReLU replaces MobileNetV2's ReLU6: ONNX opset >= 11 exports
ReLU6 as Clip with min/max inputs, which OpenCV 4.6's importer rejects.

Data (crops.py): coarse samples (the whole unrolled frame letterboxed to 224) and zoomed samples
(a crop centred on a sign, 2.5-5 x its width, resized to 224; negatives centred on distractors),
rendered once per seed and cached. Loss: cross-entropy + soft Dice of the exit class.

Usage: python3 train_unet.py --out runs/unet --seed 11 --n-train 3000 --minutes 18
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

NUM_CLASSES = 2


def _div(v: float, d: int = 8) -> int:
    """Round channels to a multiple of d (MobileNetV2's make_divisible)."""
    n = max(d, int(v + d / 2) // d * d)
    return n + d if n < 0.9 * v else n


class ConvBNReLU(nn.Sequential):
    def __init__(self, cin, cout, k=3, s=1, groups=1):
        super().__init__(nn.Conv2d(cin, cout, k, s, (k - 1) // 2, groups=groups, bias=False), nn.BatchNorm2d(cout), nn.ReLU(inplace=True))


class InvertedResidual(nn.Module):
    """MobileNetV2 block: 1x1 expand, 3x3 depthwise (stride s), 1x1 linear projection, residual when shapes match."""

    def __init__(self, cin, cout, stride, expand):
        super().__init__()
        hid = cin * expand
        layers = [] if expand == 1 else [ConvBNReLU(cin, hid, 1)]
        layers += [ConvBNReLU(hid, hid, 3, stride, groups=hid), nn.Conv2d(hid, cout, 1, bias=False), nn.BatchNorm2d(cout)]
        self.conv = nn.Sequential(*layers)
        self.res = stride == 1 and cin == cout

    def forward(self, x):
        return x + self.conv(x) if self.res else self.conv(x)


class MobileNetV2Encoder(nn.Module):
    """MobileNetV2 feature extractor returning features at strides 2, 4, 8, 16, 32."""
    CFG = [(1, 16, 1, 1), (6, 24, 2, 2), (6, 32, 3, 2), (6, 64, 4, 2), (6, 96, 3, 1), (6, 160, 3, 2), (6, 320, 1, 1)]

    def __init__(self, width: float = 0.35):
        super().__init__()
        c = _div(32 * width)
        self.stem = ConvBNReLU(3, c, 3, 2)
        blocks = []
        self.out_idx, self.channels = [], []
        for t, ch, n, s in self.CFG:
            co = _div(ch * width)
            for i in range(n):
                blocks.append(InvertedResidual(c, co, s if i == 0 else 1, t))
                c = co
            blocks_len = len(blocks)
            if ch in (16, 24, 32, 96, 320):  # last block at strides 2, 4, 8, 16, 32
                self.out_idx.append(blocks_len - 1)
                self.channels.append(c)
        self.blocks = nn.ModuleList(blocks)

    def forward(self, x):
        feats = []
        x = self.stem(x)
        for i, b in enumerate(self.blocks):
            x = b(x)
            if i in self.out_idx:
                feats.append(x)
        return feats


class Up(nn.Module):
    """Decoder step: 2x transposed conv, concat skip, 1x1 conv, 3x3 depthwise conv, 1x1 conv (BN, ReLU each)."""

    def __init__(self, cin, cskip, cout):
        super().__init__()
        self.up = nn.ConvTranspose2d(cin, cout, 2, 2)
        self.conv = nn.Sequential(ConvBNReLU(cout + cskip, cout, 1), ConvBNReLU(cout, cout, 3, groups=cout), ConvBNReLU(cout, cout, 1))

    def forward(self, x, skip):
        x = self.up(x)
        return self.conv(torch.cat([x, skip], 1) if skip is not None else x)


class SignUNet(nn.Module):
    """MobileNetV2-U-Net: image (N,3,H,W) RGB [0,1] -> logits (N,K,H,W); H, W multiples of 32."""

    def __init__(self, width: float = 0.35, num_classes: int = NUM_CLASSES, dec=(48, 32, 24, 16)):
        super().__init__()
        self.enc = MobileNetV2Encoder(width)
        c2, c4, c8, c16, c32 = self.enc.channels
        self.register_buffer("mean", torch.tensor([0.485, 0.456, 0.406]).view(1, 3, 1, 1))
        self.register_buffer("std", torch.tensor([0.229, 0.224, 0.225]).view(1, 3, 1, 1))
        self.up16 = Up(c32, c16, dec[0])
        self.up8 = Up(dec[0], c8, dec[1])
        self.up4 = Up(dec[1], c4, dec[2])
        self.up2 = Up(dec[2], c2, dec[3])
        # last 2x step straight to class logits (a full-resolution conv stack costs more than the encoder)
        self.head = nn.ConvTranspose2d(dec[3], num_classes, 2, 2)

    def decoder_features(self, feats):
        """The decoder's last features (stride 2, dec[3] channels) from the encoder's (f2, f4, f8, f16, f32)."""
        f2, f4, f8, f16, f32 = feats
        return self.up2(self.up4(self.up8(self.up16(f32, f16), f8), f4), f2)

    def forward(self, x):
        return self.head(self.decoder_features(self.enc((x - self.mean) / self.std)))


# --------------------------------------------------------------------------------------------------
# Data
# --------------------------------------------------------------------------------------------------

#: Sample types (render_samples' `kinds` array).
SAMPLE_TYPES = ["coarse", "coarse_empty", "zoom", "zoom_neg", "kind_coarse", "kind_zoom"]


def render_one(args) -> tuple:
    """Sample i of (seed, split_code) (see render_samples): (image, mask, sample type)."""
    import crops
    import render_signs as rs
    seed, split_code, i, phone_frac, kinds_frac = args
    rng = np.random.default_rng([seed, split_code, i])
    if kinds_frac > 0 and rng.random() < kinds_frac:  # a wall sign kind: half whole frames, half zooms
        kind = str(rng.choice(list(rs.WALL_KINDS)))
        zoom = rng.random() < 0.5
        x, y = crops.kind_sample(rng, kind, zoom)
        return x, y, 5 if zoom else 4
    r = rng.random()
    phone = phone_frac > 0 and rng.random() < phone_frac
    if r < 0.30:
        x, y = crops.coarse_sample(rng, True, phone=phone)
        k = 0
    elif r < 0.40:
        x, y = crops.coarse_sample(rng, False, phone=phone)
        k = 1
    elif r < 0.82:
        x, y = crops.zoom_sample(rng, True, phone=phone)
        k = 2
    else:
        x, y = crops.zoom_sample(rng, False, phone=phone)
        k = 3
    return x, y, k


def render_samples(n: int, seed: int, split_code: int, log, phone_frac: float = 0.0, workers: int = 1,
                   kinds_frac: float = 0.0) -> tuple:
    """n samples: with probability kinds_frac a wall sign kind (crops.kind_sample: a kind drawn uniformly from
    render_signs.WALL_KINDS, whole frame or zoom half and half; 0 skips the draw, keeping the Exit-only
    sets bit for bit), else an Exit sample: 30 % coarse with a sign, 10 % coarse sign-free, 42 % zoomed on a
    sign, 18 % zoomed negatives; each in the phone style with probability phone_frac (0 keeps the original
    samples: the phone draw is skipped). Sample i uses generator (seed, split_code, i), so the set does not
    depend on `workers`."""
    X = np.zeros((n, 224, 224, 3), np.uint8)
    Y = np.zeros((n, 224, 224), np.uint8)
    kinds = np.zeros(n, np.int8)
    t0 = time.time()
    import crops
    jobs = [(seed, split_code, i, phone_frac, kinds_frac) for i in range(n)]
    for i, (x, y, k) in enumerate(crops.imap_in_processes(render_one, jobs, workers)):
        X[i], Y[i], kinds[i] = x, y, k
        if (i + 1) % 250 == 0:
            log("rendered %d/%d samples (%.0f s)" % (i + 1, n, time.time() - t0))
    return X, Y, kinds


def load_or_render(cache_dir: str, n: int, seed: int, split_code: int, log, phone_frac: float = 0.0, workers: int = 1,
                   kinds_frac: float = 0.0):
    """render_samples' set, cached in cache_dir (one .npz per seed, split, n, fractions and, with phone-style
    samples, the phone style's tone curve: a cache rendered before the sRGB tone curve (2026-12-07) is not reused)."""
    from phone_camera import PhoneCamera
    os.makedirs(cache_dir, exist_ok=True)
    tone = PhoneCamera.tone_curve
    tag = "" if phone_frac <= 0 else "_phone%02d%s" % (int(round(100 * phone_frac)), "" if tone == "linear" else "_" + tone)
    tag += "" if kinds_frac <= 0 else "_kinds%02d" % int(round(100 * kinds_frac))
    path = os.path.join(cache_dir, "unet_samples_seed%d_split%d_n%d%s.npz" % (seed, split_code, n, tag))
    if os.path.exists(path):
        z = np.load(path)
        return z["X"], z["Y"], z["kinds"]
    X, Y, kinds = render_samples(n, seed, split_code, log, phone_frac, workers, kinds_frac)
    np.savez(path, X=X, Y=Y, kinds=kinds)
    return X, Y, kinds


def augment(x: torch.Tensor, y: torch.Tensor, g: torch.Generator):
    """Photometric jitter (brightness, contrast, per-channel gain) on a float batch in [0,1]."""
    n = x.shape[0]
    b = (torch.rand(n, 1, 1, 1, generator=g) - 0.5) * 0.3
    c = 0.75 + 0.5 * torch.rand(n, 1, 1, 1, generator=g)
    ch = 0.9 + 0.2 * torch.rand(n, 3, 1, 1, generator=g)
    m = x.mean(dim=(1, 2, 3), keepdim=True)
    x = ((x - m) * c + m + b) * ch
    return x.clamp(0, 1), y


def heavy_augment(x: torch.Tensor, g: torch.Generator) -> torch.Tensor:
    """Camera-like augmentation on a float batch in [0,1] (on top of augment): gamma 0.6-1.6, per-sample
    down- and up-sampling by 1-3x (low-resolution sources), Gaussian blur (defocus), Gaussian noise
    (sigma 0-0.04), colour saturation 0.6-1.4; each with probability 0.3-0.5 per sample."""
    n = x.shape[0]
    out = []
    for k in range(n):
        xi = x[k:k + 1]
        r = torch.rand(6, generator=g)
        if r[0] < 0.5:
            xi = xi.clamp(1e-4, 1).pow(float(math.exp((torch.rand(1, generator=g).item() - 0.5) * 2 * math.log(1.6))))
        if r[1] < 0.3:
            f = 1.0 + 2.0 * torch.rand(1, generator=g).item()
            hw = xi.shape[-2:]
            small = F.interpolate(xi, scale_factor=1.0 / f, mode="area")
            xi = F.interpolate(small, size=hw, mode="bilinear", align_corners=False)
        if r[2] < 0.3:
            sig = 0.5 + 1.5 * torch.rand(1, generator=g).item()
            ks = int(2 * math.ceil(2 * sig) + 1)
            t = torch.arange(ks, dtype=torch.float32) - ks // 2
            w = torch.exp(-t ** 2 / (2 * sig * sig))
            w = (w / w.sum())
            xi = F.conv2d(F.pad(xi, (ks // 2,) * 4, mode="replicate"), (w[None, :] * w[:, None]).expand(3, 1, ks, ks), groups=3)
        if r[3] < 0.4:
            xi = xi + torch.randn(xi.shape, generator=g) * (0.04 * torch.rand(1, generator=g).item())
        if r[4] < 0.4:
            gray = xi.mean(1, keepdim=True)
            xi = gray + (xi - gray) * (0.6 + 0.8 * torch.rand(1, generator=g).item())
        out.append(xi)
    return torch.cat(out).clamp(0, 1)


def random_crops(x: torch.Tensor, y: torch.Tensor, size: int, g: torch.Generator):
    """size x size crops (multiple of 32), containing sign pixels when the sample has any (80 %)."""
    n = x.shape[0]
    xs, ys = [], []
    for k in range(n):
        pos = torch.nonzero(y[k] > 0)
        if len(pos) and torch.rand(1, generator=g).item() < 0.8:
            cy, cx = pos[int(torch.randint(len(pos), (1,), generator=g))].tolist()
            y0 = min(max(cy - int(torch.randint(size, (1,), generator=g)), 0), 224 - size)
            x0 = min(max(cx - int(torch.randint(size, (1,), generator=g)), 0), 224 - size)
        else:
            y0 = int(torch.randint(224 - size + 1, (1,), generator=g))
            x0 = int(torch.randint(224 - size + 1, (1,), generator=g))
        xs.append(x[k, :, y0:y0 + size, x0:x0 + size])
        ys.append(y[k, y0:y0 + size, x0:x0 + size])
    return torch.stack(xs), torch.stack(ys)


def conv_call_order(model: nn.Module) -> list:
    """The model's Conv2d / ConvTranspose2d modules in the order a forward pass calls them (the order of an
    exported graph's Conv / ConvTranspose nodes)."""
    order = []
    hooks = [mod.register_forward_hook(lambda mod, i, o: order.append(mod)) for mod in model.modules()
             if isinstance(mod, (nn.Conv2d, nn.ConvTranspose2d))]
    was = model.training
    model.eval()
    with torch.no_grad():
        model(torch.zeros(1, 3, 224, 224))
    model.train(was)
    for h in hooks:
        h.remove()
    return order


def exported_convs(onnx_path: str) -> list:
    """(weight, bias or None) of each Conv / ConvTranspose node of an exported model, in graph order."""
    import onnx
    from onnx import numpy_helper
    m = onnx.load(onnx_path)
    inits = {i.name: numpy_helper.to_array(i) for i in m.graph.initializer}
    return [(torch.from_numpy(inits[n.input[1]].copy()),
             torch.from_numpy(inits[n.input[2]].copy()) if len(n.input) > 2 else None)
            for n in m.graph.node if n.op_type in ("Conv", "ConvTranspose")]


def copy_convs(model: nn.Module, order: list, convs: list, source: str) -> int:
    """Copies convs[i] (weight, bias: BatchNorm folded in) into order[i]; each folded convolution's bias goes into
    the BatchNorm after it, which becomes the identity (mean 0, variance 1 - eps, scale 1) and must stay frozen
    (freeze_bn). A head with fewer classes than the model's last ConvTranspose2d is widened (_widen_head); one with
    more is cut to the model's first classes (a six-class export loads into the two-class Exit model)."""
    if len(order) != len(convs):
        raise ValueError("init_from_onnx: %s has %d convolutions, the model %d" % (source, len(convs), len(order)))
    mods = list(model.modules())
    bn_after = {id(mods[i]): mods[i + 1] for i in range(len(mods) - 1) if isinstance(mods[i + 1], nn.BatchNorm2d)}
    with torch.no_grad():
        for k, (mod, (w, b)) in enumerate(zip(order, convs)):
            if mod is order[-1] and isinstance(mod, nn.ConvTranspose2d) and w.shape[1] != mod.weight.shape[1] \
                    and tuple(w.shape[:1] + w.shape[2:]) == tuple(mod.weight.shape[:1] + mod.weight.shape[2:]):
                if w.shape[1] < mod.weight.shape[1]:
                    w, b = _widen_head(w, b, mod.weight.shape[1])
                else:  # fewer classes than exported: the first ones (background, exit, ...) kept
                    k = mod.weight.shape[1]
                    w, b = w[:, :k].contiguous(), (b[:k].contiguous() if b is not None else None)
            if tuple(w.shape) != tuple(mod.weight.shape):
                raise ValueError("init_from_onnx: %s convolution %d weight %s, model %s" %
                                 (source, k, tuple(w.shape), tuple(mod.weight.shape)))
            mod.weight.copy_(w)
            bn = bn_after.get(id(mod))
            if bn is not None:
                bn.weight.fill_(1.0)
                bn.bias.copy_(b if b is not None else torch.zeros_like(bn.bias))
                bn.running_mean.zero_()
                bn.running_var.fill_(1.0 - bn.eps)
            elif mod.bias is not None and b is not None:
                mod.bias.copy_(b)
    return len(order)


def init_from_onnx(model: nn.Module, onnx_path: str) -> int:
    """Warm start: copy the weights of an exported model (export_unet.py: BatchNorm folded into the
    convolutions) into `model`. ONNX Conv / ConvTranspose nodes are matched in graph order with the
    model's Conv2d / ConvTranspose2d modules in forward-call order (shapes checked); see copy_convs.
    Returns the number of layers copied."""
    order, convs = conv_call_order(model), exported_convs(onnx_path)
    if isinstance(model, SignUNet) and model.head.out_channels == 2 and len(convs) > len(order):
        # a kinds-branch export (kinds_branch.py): its Exit trunk, the Exit head unfolded from the joint head
        import kinds_branch
        convs = kinds_branch.trunk_convs_of_exported(convs, len(order), model.head.in_channels)
    return copy_convs(model, order, convs, onnx_path)


def _widen_head(w: torch.Tensor, b: torch.Tensor, k: int):
    """Class logits head (ConvTranspose2d weight (cin, K0, 2, 2), bias K0) widened to k classes: the K0
    exported classes kept; each new class starts as a copy of the last exported (sign) class, bias 2 lower
    (at first a new class scores e^-2 of the sign class where both respond), plus 1 % noise so that the new
    classes do not stay identical (seeded by torch's generator)."""
    k0 = w.shape[1]
    ww = torch.empty(w.shape[0], k, *w.shape[2:])
    ww[:, :k0] = w
    bb = torch.zeros(k)
    if b is not None:
        bb[:k0] = b
    for c in range(k0, k):
        ww[:, c] = w[:, k0 - 1] * (1 + 0.01 * torch.randn(w[:, k0 - 1].shape))
        bb[c] = bb[k0 - 1] - 2.0
    return ww, bb


def freeze_bn(model: nn.Module) -> None:
    """Keep every BatchNorm in inference mode (running statistics fixed) while the rest trains."""
    for mod in model.modules():
        if isinstance(mod, nn.BatchNorm2d):
            mod.eval()


def distill_loss(logits: torch.Tensor, teacher_prob: torch.Tensor, keep: torch.Tensor,
                 foreground_weight: float = 0.0) -> torch.Tensor:
    """Learning without forgetting (Li and Hoiem 2016): cross-entropy of the student's K-class softmax against an
    Exit-only teacher's (background, exit) probabilities, the other classes' targets 0, averaged over the pixels of
    the samples `keep` (bool, N: the Exit samples; the teacher knows no wall kind). 0 when none is kept.
    foreground_weight F > 0 weights each pixel by 1 + F x the teacher's exit probability (normalised to mean 1):
    a far sign is a few dozen pixels of a coarse sample, which an unweighted mean hardly sees."""
    if not bool(keep.any()):
        return logits.sum() * 0.0
    logp = F.log_softmax(logits[keep], 1)
    t = teacher_prob[keep]
    ce = -(t[:, 0] * logp[:, 0] + t[:, 1] * logp[:, 1])
    if foreground_weight <= 0:
        return ce.mean()
    w = 1.0 + foreground_weight * t[:, 1]
    return (w * ce).sum() / w.sum()


def loss_fn(logits, y):
    """Cross-entropy + (1 - soft Dice over the batch), the Dice of each sign class (1..K-1, smoothing 1)
    averaged over the classes (K = 2: the exit class's alone, as the Exit-only models were trained)."""
    ce = F.cross_entropy(logits, y)
    prob = logits.softmax(1)
    dices = []
    for c in range(1, logits.shape[1]):
        p = prob[:, c]
        t = (y == c).float()
        dices.append((2 * (p * t).sum() + 1.0) / (p.sum() + t.sum() + 1.0))
    dice = torch.stack(dices).mean()
    return ce + (1 - dice), ce.item(), dice.item()


@torch.no_grad()
def evaluate(model, X, Y, kinds, bs=32, class_names=None):
    """IoU of the exit class over all pixels, per sample type (SAMPLE_TYPES) and overall; false-positive
    pixels on the sign-free types; with more than 2 classes also each sign class's IoU over all samples
    (`class_iou`, keyed by class_names)."""
    model.eval()
    nt = len(SAMPLE_TYPES)
    inter = np.zeros(nt)
    union = np.zeros(nt)
    k_classes = None
    ci = cu = None
    for i in range(0, len(X), bs):
        x = torch.from_numpy(X[i:i + bs]).permute(0, 3, 1, 2).float() / 255.0
        logits = model(x)
        if k_classes is None:
            k_classes = logits.shape[1]
            ci, cu = np.zeros(k_classes), np.zeros(k_classes)
        pred = logits.argmax(1).numpy()
        t = Y[i:i + bs] == 1
        p = pred == 1
        for k in range(nt):
            sel = kinds[i:i + bs] == k
            inter[k] += (p[sel] & t[sel]).sum()
            union[k] += (p[sel] | t[sel]).sum()
        for c in range(1, k_classes):
            tc, pc = Y[i:i + bs] == c, pred == c
            ci[c] += (tc & pc).sum()
            cu[c] += (tc | pc).sum()
    model.train()
    iou_all = inter.sum() / max(union.sum(), 1)
    per = {name: (inter[k] / union[k] if union[k] else float("nan")) for k, name in enumerate(SAMPLE_TYPES)}
    fp_pixels = {"coarse_empty": union[1], "zoom_neg": union[3]}
    if k_classes and k_classes > 2:
        names = class_names or ["class%d" % c for c in range(k_classes)]
        per["class_iou"] = {names[c]: (ci[c] / cu[c] if cu[c] else float("nan")) for c in range(1, k_classes)}
    return iou_all, per, fp_pixels


#: The documented recipes (docs/training.md): argparse settings, plus "budget_minutes" (default wall budget),
#: "init_committed" (start from ../models/sign_unet.onnx unless --init-onnx is given) and "needs" (options the
#: command line must give).
RECIPES = {
    # the 60-minute CPU recipe: render 3600 samples, half phone style, heavy augmentation, train from scratch
    "ci60": dict(seed=11, n_train=3600, n_val=240, batch=16, crop=128, lr=3e-3, warmup=100, phone_frac=0.5,
                 heavy_aug=True, workers=2, threads=2, budget_minutes=60.0),
    # fine-tune the committed model on the ci60 samples (same seed, same cache)
    "ft30": dict(seed=11, n_train=3600, n_val=240, batch=16, crop=128, lr=5e-4, warmup=20, phone_frac=0.5,
                 heavy_aug=True, workers=2, threads=2, init_committed=True, budget_minutes=30.0),
    # the committed (Exit) model widened to the wall sign kinds' classes, fine-tuned on both
    "kinds45": dict(seed=11, n_train=3000, n_val=240, batch=16, crop=128, lr=1e-3, warmup=50, phone_frac=0.5,
                    kinds_frac=0.4, heavy_aug=True, workers=2, threads=2, init_committed=True, budget_minutes=45.0),
    # continue kinds45 at a lower rate, the Exit-only model as teacher
    "kinds25d": dict(seed=11, n_train=3000, n_val=240, batch=16, crop=128, lr=3e-4, warmup=20, phone_frac=0.5,
                     kinds_frac=0.4, heavy_aug=True, workers=2, threads=2, freeze_bn=True, budget_minutes=25.0,
                     needs=("resume", "distill_onnx")),
    # the wall kinds as a light second decoder beside the committed Exit model, which stays frozen (kinds_branch.py)
    "kindsbranch": dict(seed=11, n_train=3000, n_val=240, batch=16, crop=128, lr=3e-3, warmup=100, phone_frac=0.5,
                        kinds_frac=0.4, heavy_aug=True, workers=2, threads=2, init_committed=True, kinds_branch=True,
                        budget_minutes=35.0),
    # kinds45 distilled towards the Exit model from the start, its sign pixels weighted (far Exit signs at coarse scale)
    "kinds45fd": dict(seed=11, n_train=3000, n_val=240, batch=16, crop=128, lr=1e-3, warmup=50, phone_frac=0.5,
                      kinds_frac=0.4, heavy_aug=True, workers=2, threads=2, distill_foreground=30.0,
                      init_committed=True, budget_minutes=45.0, needs=("distill_onnx",)),
    # the Exit model widened, fine-tuned gently on classic-style samples, distilled towards itself from the start
    "kinds35": dict(seed=11, n_train=3000, n_val=240, batch=16, crop=128, lr=5e-4, warmup=20, phone_frac=0.0,
                    kinds_frac=0.3, heavy_aug=True, workers=2, threads=2, budget_minutes=35.0,
                    needs=("init_onnx", "distill_onnx")),
}


def apply_recipe(a: argparse.Namespace, ap: argparse.ArgumentParser) -> None:
    """Sets a's options to recipe a.recipe's (RECIPES); the budget and export directory only where not given."""
    r = dict(RECIPES[a.recipe])
    budget, committed, needs = r.pop("budget_minutes"), r.pop("init_committed", False), r.pop("needs", ())
    for k, v in r.items():
        setattr(a, k, v)
    if committed and a.init_onnx is None:
        a.init_onnx = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models", "sign_unet.onnx")
    for k in needs:
        if getattr(a, k) is None:
            ap.error("--recipe %s needs --%s" % (a.recipe, k.replace("_", "-")))
    if a.budget_minutes is None:
        a.budget_minutes = budget
    if a.export is None:
        a.export = os.path.join(a.out, "export")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Train the MobileNetV2 U-Net Exit-sign segmenter.")
    ap.add_argument("--out", required=True, help="run directory (checkpoint, log)")
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--n-train", type=int, default=3000)
    ap.add_argument("--n-val", type=int, default=300)
    ap.add_argument("--width", type=float, default=0.35)
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--crop", type=int, default=128, help="training crop size (pixels, multiple of 32; 224 = whole sample)")
    ap.add_argument("--lr", type=float, default=3e-3)
    ap.add_argument("--minutes", type=float, default=18.0, help="training wall-time budget (cosine schedule over it)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--resume", default=None, help="start from the weights of this checkpoint (.pt)")
    ap.add_argument("--warmup", type=int, default=100, help="linear learning-rate warm-up steps")
    ap.add_argument("--cache", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "data"))
    ap.add_argument("--phone-frac", type=float, default=0.0, help="fraction of samples rendered in the phone style")
    ap.add_argument("--kinds-frac", type=float, default=0.0,
                    help="fraction of samples showing a wall sign kind (restroom, elevator, stairs, placard); > 0 trains "
                         "the classes of render_signs.CLASSES (background, exit and the four kinds) instead of "
                         "background and exit")
    ap.add_argument("--heavy-aug", action="store_true", help="add heavy_augment (gamma, resolution, blur, noise, saturation)")
    ap.add_argument("--workers", type=int, default=1, help="rendering processes")
    ap.add_argument("--budget-minutes", type=float, default=None,
                    help="total wall budget (rendering + training + export): training gets what rendering leaves, "
                         "minus --export-reserve minutes")
    ap.add_argument("--export-reserve", type=float, default=3.0)
    ap.add_argument("--export", default=None, help="after training, export ONNX + Core ML into this directory (export_unet.py)")
    ap.add_argument("--init-onnx", default=None, help="warm start from an exported model (init_from_onnx); BatchNorm frozen")
    ap.add_argument("--distill-onnx", default=None,
                    help="an exported Exit-only model (background, exit) whose probabilities the Exit samples are also "
                         "trained towards (distill_loss), so that adding classes does not change the Exit sign's")
    ap.add_argument("--distill-weight", type=float, default=1.0)
    ap.add_argument("--distill-foreground", type=float, default=0.0,
                    help="weight the distillation's pixels by 1 + this x the teacher's exit probability (distill_loss)")
    ap.add_argument("--train-from", choices=["enc", "up16", "up8", "up4", "up2", "head"], default="enc",
                    help="train this stage of the network and the ones after it; the earlier stages stay as loaded "
                         "(e.g. up4: the encoder and the two coarsest decoder steps keep the Exit model's features)")
    ap.add_argument("--kinds-branch", action="store_true",
                    help="train the wall kinds as a second, narrower decoder (kinds_branch.py) beside the Exit model given by "
                         "--init-onnx, which stays frozen; needs --kinds-frac > 0")
    ap.add_argument("--branch-dec", default=None,
                    help="the kinds branch's decoder widths at strides 16, 8, 4, comma-separated (default 16,12,8)")
    ap.add_argument("--freeze-bn", action="store_true",
                    help="keep BatchNorm frozen (implied by --init-onnx; for --resume of a run that had it)")
    ap.add_argument("--recipe", choices=sorted(RECIPES), default=None,
                    help="a documented recipe (RECIPES; e.g. ci60: render 3600 samples, half phone style, heavy "
                         "augmentation, train from scratch in 60 minutes, export to OUT/export)")
    a = ap.parse_args(argv)
    if a.recipe:
        apply_recipe(a, ap)
    import render_signs as rs
    class_names = list(rs.CLASSES) if a.kinds_frac > 0 else ["background", "exit"]
    torch.manual_seed(a.seed)
    torch.set_num_threads(a.threads)
    os.makedirs(a.out, exist_ok=True)
    t0 = time.time()
    logf = open(os.path.join(a.out, "train.log"), "a")

    def log(msg):
        line = "[%7.1fs] %s" % (time.time() - t0, msg)
        print(line, flush=True)
        logf.write(line + "\n")
        logf.flush()

    Xtr, Ytr, Ktr = load_or_render(a.cache, a.n_train, a.seed, 1, log, a.phone_frac, a.workers, a.kinds_frac)
    Xva, Yva, Kva = load_or_render(a.cache, a.n_val, a.seed, 2, log, a.phone_frac, a.workers, a.kinds_frac)
    log("data: %d train, %d val (exit pixel fraction %.4f)" % (len(Xtr), len(Xva), float((Ytr == 1).mean())))
    t_data = time.time() - t0
    branch_dec = None
    if a.kinds_branch:
        import kinds_branch
        if a.kinds_frac <= 0 or a.init_onnx is None:
            ap.error("--kinds-branch needs --kinds-frac > 0 and --init-onnx (the Exit model it stands beside)")
        branch_dec = tuple(int(v) for v in a.branch_dec.split(",")) if a.branch_dec else kinds_branch.DEFAULT_BRANCH_DEC
        if len(branch_dec) != 3 or min(branch_dec) < 1:
            ap.error("--branch-dec needs three positive widths, got %s" % a.branch_dec)
        model = kinds_branch.KindsBranchUNet(a.width, branch_dec, len(class_names) - 1)
    else:
        model = SignUNet(a.width, len(class_names))
    if a.resume:
        model.load_state_dict(torch.load(a.resume, map_location="cpu")["state_dict"])
        log("resumed weights from %s" % a.resume)
    if a.init_onnx and a.kinds_branch:
        log("kinds branch %s beside the frozen Exit model: %s loaded from %s" %
            (",".join(map(str, branch_dec)), kinds_branch.init_from_exported(model, a.init_onnx), a.init_onnx))
    elif a.init_onnx:
        log("initialised %d layers from %s (BatchNorm frozen)" % (init_from_onnx(model, a.init_onnx), a.init_onnx))
    teacher = None
    if a.distill_onnx:
        teacher = SignUNet(a.width, 2)
        init_from_onnx(teacher, a.distill_onnx)
        teacher.eval()
        for q in teacher.parameters():
            q.requires_grad_(False)
        log("distilling the Exit samples towards %s (weight %.2f)" % (a.distill_onnx, a.distill_weight))
    stages = ["enc", "up16", "up8", "up4", "up2", "head"]
    for name in stages[:stages.index(a.train_from)]:
        for q in getattr(model, name).parameters():
            q.requires_grad_(False)
    if a.train_from != "enc":
        log("training %s onwards; %s kept as loaded" % (a.train_from, ", ".join(stages[:stages.index(a.train_from)])))
    nparam = sum(p.numel() for p in model.parameters() if p.requires_grad)
    log("model: %d trained parameters" % nparam)
    opt = torch.optim.AdamW([q for q in model.parameters() if q.requires_grad], lr=a.lr, weight_decay=1e-4)
    g = torch.Generator().manual_seed(a.seed)
    budget = a.minutes * 60.0
    if a.budget_minutes is not None:
        budget = a.budget_minutes * 60.0 - (time.time() - t0) - a.export_reserve * 60.0
        if budget < 60:
            log("error: rendering left %.0f s of the %.0f-minute budget" % (budget, a.budget_minutes))
            return 1
    log("training budget %.1f min" % (budget / 60.0))
    t_train0 = time.time()
    step = 0
    ema = None
    Xt = torch.from_numpy(Xtr)
    Yt = torch.from_numpy(Ytr.astype(np.int64))
    Kt = torch.from_numpy(Ktr.astype(np.int64))
    epoch = 0
    done = False
    while not done:
        perm = torch.randperm(len(Xtr), generator=g)
        for i in range(0, len(perm) - a.batch + 1, a.batch):
            frac = (time.time() - t_train0) / budget
            if frac >= 1.0:
                done = True
                break
            lr = a.lr * (min(1.0, step / max(1.0, a.warmup))) * 0.5 * (1 + math.cos(math.pi * min(frac, 1.0)))
            for pg in opt.param_groups:
                pg["lr"] = lr
            idx = perm[i:i + a.batch]
            x = Xt[idx].permute(0, 3, 1, 2).float() / 255.0
            y = Yt[idx]
            if a.crop < 224:  # random crops at the same scale (the net is fully convolutional)
                x, y = random_crops(x, y, a.crop, g)
            if torch.rand(1, generator=g).item() < 0.5:  # horizontal flip (mirrored signs exist)
                x, y = x.flip(3), y.flip(2)
            x, y = augment(x, y, g)
            if a.heavy_aug:
                x = heavy_augment(x, g)
            if (a.init_onnx or a.freeze_bn) and not a.kinds_branch:  # the branch's own BatchNorm trains
                freeze_bn(model)
            logits = model(x)
            loss, ce, dice = loss_fn(logits, y)
            if teacher is not None:
                with torch.no_grad():
                    tp = teacher(x).softmax(1)
                loss = loss + a.distill_weight * distill_loss(logits, tp, Kt[idx] < 4, a.distill_foreground)
            opt.zero_grad()
            loss.backward()
            opt.step()
            ema = loss.item() if ema is None else 0.98 * ema + 0.02 * loss.item()
            step += 1
            if step % 50 == 0:
                log("epoch %d step %d lr %.2e loss %.4f (ema %.4f) ce %.4f dice %.3f" % (epoch, step, lr, loss.item(), ema, ce, dice))
        epoch += 1
    t_train = time.time() - t_train0
    iou, per, fp = evaluate(model, Xva, Yva, Kva, class_names=class_names)
    log("val IoU(exit) %.4f per kind %s; false-positive pixels on sign-free crops %s" % (iou, json.dumps(per), json.dumps(fp)))
    ck = {"state_dict": model.state_dict(), "width": a.width, "num_classes": len(class_names), "classes": class_names}
    if branch_dec is not None:
        ck["kinds_branch"] = list(branch_dec)
    torch.save(ck, os.path.join(a.out, "sign_unet.pt"))
    summary = dict(resume=a.resume, classes=class_names, kinds_frac=a.kinds_frac, seed=a.seed, n_train=a.n_train, n_val=a.n_val, width=a.width, batch=a.batch, crop=a.crop, lr=a.lr, steps=step, epochs=epoch,
                   params=nparam, data_seconds=t_data, train_seconds=t_train, final_loss_ema=ema, val_iou=iou, val_iou_per_kind=per)
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    log("saved %s" % os.path.join(a.out, "sign_unet.pt"))
    if a.export:
        import export_unet
        rc = export_unet.main(["--checkpoint", os.path.join(a.out, "sign_unet.pt"), "--out", a.export])
        log("export to %s: %s; total wall time %.1f min" % (a.export, "ok" if rc == 0 else "failed (%d)" % rc, (time.time() - t0) / 60.0))
        return rc
    log("total wall time %.1f min" % ((time.time() - t0) / 60.0))
    return 0


if __name__ == "__main__":
    sys.exit(main())
