#!/usr/bin/env python3
"""Train an Exit-sign LBP cascade (OpenCV cascade XML) from rendered samples.

OpenCV 4 no longer ships opencv_traincascade, so this is a from-scratch, numpy-vectorised trainer
producing the same model type, loadable by cv::CascadeClassifier / cv2.CascadeClassifier:

  * features: multi-block LBP (Zhang et al. 2007, "Face detection based on multi-block LBP
    representation"): a rect (x, y, w, h) defines a 3 x 3 grid of w x h blocks inside the 24 x 16
    window; the 8-bit code compares each outer block sum with the centre block sum (>= -> 1), bits
    in OpenCV's order (block 0 -> 128, 1 -> 64, 2 -> 32, 5 -> 16, 8 -> 8, 7 -> 4, 6 -> 2, 3 -> 1,
    blocks numbered row-major), exactly as OpenCV's LBP evaluator computes them;
  * weak classifiers (each round searches a random 35 % of the 3680 features, for speed): depth-1 trees with a 256-way categorical split: a 256-bit subset (8 x 32-bit
    masks) sends a code to leaf 0 when its bit is set, else to leaf 1; the best binary partition of
    the categories for weighted squared error is found by sorting categories by their mean response
    (Breiman et al., CART, 1984, sec. 4.2.2);
  * boosting: Gentle AdaBoost (Friedman, Hastie, Tibshirani 2000, Additive logistic regression):
    each stump is the weighted least-squares fit of the labels y in {-1, +1}, weights w *= exp(-y f),
    weight trimming at 0.95 as in opencv_traincascade;
  * cascade (Viola and Jones 2001): each stage adds stumps until, with its threshold set to keep
    the target hit rate (0.995) of positives, at most maxFalseAlarm (0.5) of its negatives pass;
    negatives of stage k are windows of sign-free rendered frames that pass stages 0..k-1 (hard
    negative mining with cv2.CascadeClassifier on the cascade written so far, confirmed by the
    numpy evaluator).

Wall sign kinds (--kind restroom|elevator|stairs|placard, square --window 20x20 by default): positives are
rendered windows of that kind (crops.kind_window), negatives are windows of sign-free frames and of frames
with the other kinds and Exit signs (crops.kind_frame; never a frame with the kind itself; unrolled VGA
frames with their black corners by default, --kind-negatives), plus "confuser"
windows: windows framed like the positives around faces of every other kind (Exit included), those the
cascade so far accepts, up to half of --num-neg per stage (load_kind_samples).

Phone style (Exit, --phone-pos N --phone-neg-frames M): N windows around Exit faces of phone-style frames
(crops.cascade_positive_phone: LED faces, auto exposure, walking blur, rolling shutter, glare, ISO running-man
signs beside the text ones) are added to the positives and M phone-style sign-free frames (posters, ceiling
lights, fiducial markers, glossy floors) to the negative frames.

Usage: python3 train_cascade.py --out ../models/exit_sign_cascade.xml --seed 7
       python3 train_cascade.py --kind placard --out ../models/placard_cascade.xml --seed 7 --num-pos 2000
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
import xml.etree.ElementTree as ET
from typing import List, Tuple

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import crops  # noqa: E402
import render_signs as rs  # noqa: E402

#: Generator codes of the wall-kind samples: windows (seed, 20 + code, i), frames (seed, 30 + code, i).
KIND_CODES = {"exit": 0, "restroom": 1, "elevator": 2, "stairs": 3, "placard": 4}

WIN_W, WIN_H = 24, 16  # the Exit cascade's window; --window (set_window) changes it for the wall kinds


def set_window(w: int, h: int) -> None:
    """Set the training window (every function here reads WIN_W, WIN_H when called)."""
    global WIN_W, WIN_H
    WIN_W, WIN_H = int(w), int(h)


# --------------------------------------------------------------------------------------------------
# MB-LBP features
# --------------------------------------------------------------------------------------------------

def enumerate_features(win_w: int = None, win_h: int = None) -> np.ndarray:
    """All MB-LBP rects (x, y, w, h) with the 3 x 3 block grid inside the window (default WIN_W x WIN_H),
    grouped by (w, h) with x fastest: the order compute_features() produces codes in. Returns (F, 4) int."""
    win_w = WIN_W if win_w is None else win_w
    win_h = WIN_H if win_h is None else win_h
    out = []
    for w in range(1, win_w // 3 + 1):
        for h in range(1, win_h // 3 + 1):
            for y in range(0, win_h - 3 * h + 1):
                for x in range(0, win_w - 3 * w + 1):
                    out.append((x, y, w, h))
    return np.array(out, np.int32)


# OpenCV bit for each block (row-major 3 x 3, centre excluded)
_BITS = {(0, 0): 128, (0, 1): 64, (0, 2): 32, (1, 2): 16, (2, 2): 8, (2, 1): 4, (2, 0): 2, (1, 0): 1}


def compute_features(patches: np.ndarray, win_w: int = None, win_h: int = None) -> np.ndarray:
    """MB-LBP codes of every feature of enumerate_features() for grey patches (N, win_h, win_w), default
    window WIN_W x WIN_H. Returns uint8 (N, F)."""
    win_w = WIN_W if win_w is None else win_w
    win_h = WIN_H if win_h is None else win_h
    p = np.asarray(patches)
    N = p.shape[0]
    I = np.zeros((N, win_h + 1, win_w + 1), np.int32)
    I[:, 1:, 1:] = p.astype(np.int32).cumsum(1).cumsum(2)
    cols = []
    for w in range(1, win_w // 3 + 1):
        for h in range(1, win_h // 3 + 1):
            nx, ny = win_w - 3 * w + 1, win_h - 3 * h + 1
            S = [[I[:, j * h:j * h + ny, i * w:i * w + nx] for i in range(4)] for j in range(4)]

            def block(r, c):
                return S[r + 1][c + 1] - S[r][c + 1] - S[r + 1][c] + S[r][c]

            centre = block(1, 1)
            code = np.zeros((N, ny, nx), np.uint8)
            for (r, c), bit in _BITS.items():
                code |= np.where(block(r, c) >= centre, np.uint8(bit), np.uint8(0))
            cols.append(code.reshape(N, -1))
    return np.concatenate(cols, axis=1)


# --------------------------------------------------------------------------------------------------
# Boosting
# --------------------------------------------------------------------------------------------------

class Stump:
    """Categorical stump: feature index (into enumerate_features()), 256-bool subset, leaf values
    (leaf[0] when the code's subset bit is set, else leaf[1])."""

    def __init__(self, feature: int, subset: np.ndarray, leaf0: float, leaf1: float):
        self.feature, self.subset, self.leaf0, self.leaf1 = int(feature), subset.astype(bool), float(np.float32(leaf0)), float(np.float32(leaf1))

    def predict(self, codes: np.ndarray) -> np.ndarray:
        """Response for the codes of this stump's feature, (N,) uint8 -> (N,) float32."""
        return np.where(self.subset[codes], np.float32(self.leaf0), np.float32(self.leaf1)).astype(np.float32)

    def masks(self) -> List[int]:
        """8 signed 32-bit masks as OpenCV writes them (bit c of mask c//32 = code c in subset)."""
        out = []
        for k in range(8):
            v = 0
            for b in range(32):
                if self.subset[32 * k + b]:
                    v |= 1 << b
            out.append(v - (1 << 32) if v >= (1 << 31) else v)
        return out


class Stage:
    """Boosted stage: stumps and the threshold (a window passes when the sum >= threshold)."""

    def __init__(self):
        self.stumps: List[Stump] = []
        self.threshold = 0.0

    def score(self, X: np.ndarray) -> np.ndarray:
        s = np.zeros(X.shape[0], np.float32)
        for st in self.stumps:
            s += st.predict(X[:, st.feature])
        return s


def best_stump(X: np.ndarray, y: np.ndarray, w: np.ndarray, offsets: np.ndarray) -> Stump:
    """Weighted least-squares categorical stump over all features (Gentle AdaBoost step)."""
    N, F = X.shape
    idx = (X.astype(np.int32) + offsets[None, :]).ravel()
    Wc = np.bincount(idx, weights=np.repeat(w, F), minlength=F * 256).reshape(F, 256)
    Sc = np.bincount(idx, weights=np.repeat(w * y, F), minlength=F * 256).reshape(F, 256)
    mean = np.where(Wc > 0, Sc / np.maximum(Wc, 1e-300), 0.0)
    order = np.argsort(mean, axis=1, kind="stable")
    Ws = np.take_along_axis(Wc, order, 1).cumsum(1)
    Ss = np.take_along_axis(Sc, order, 1).cumsum(1)
    Wt, St = Ws[:, -1:], Ss[:, -1:]
    WL, SL = Ws[:, :-1], Ss[:, :-1]
    WR, SR = Wt - WL, St - SL
    eps = 1e-12
    gain = SL ** 2 / np.maximum(WL, eps) + SR ** 2 / np.maximum(WR, eps)
    gain = np.where((WL > eps) & (WR > eps), gain, -1.0)
    k = np.argmax(gain, axis=1)
    f = int(np.argmax(gain[np.arange(F), k]))
    kk = int(k[f])
    subset = np.zeros(256, bool)
    subset[order[f, :kk + 1]] = True
    leaf0 = SL[f, kk] / WL[f, kk]
    leaf1 = SR[f, kk] / WR[f, kk]
    return Stump(f, subset, leaf0, leaf1)


def train_stage(Xp: np.ndarray, Xn: np.ndarray, min_hit: float, max_fa: float, max_weak: int,
                offsets: np.ndarray, log, rng: np.random.Generator, feature_frac: float = 1.0,
                neg_weights: np.ndarray = None, pos_weight: float = 0.5,
                trim_rate: float = 0.95) -> Tuple[Stage, float, float]:
    """Gentle AdaBoost until the stage meets min_hit on positives and max_fa on negatives; each
    round searches a random `feature_frac` of the features. `neg_weights` (optional, (len(Xn),))
    sets the negatives' relative starting weights (default: equal); positives and negatives start
    with `pos_weight` and 1 - pos_weight of the total weight (default half each; more on the positives
    makes the stumps keep nearly all positives on one side, which a stage of very few stumps with a
    high hit rate needs). The false-alarm rate reported is weighted as the negatives' start weights."""
    X = np.concatenate([Xp, Xn])
    y = np.concatenate([np.ones(len(Xp)), -np.ones(len(Xn))])
    wn = np.ones(len(Xn)) if neg_weights is None else np.asarray(neg_weights, np.float64)
    wn = wn / wn.sum()
    w = np.concatenate([np.full(len(Xp), pos_weight / len(Xp)), (1.0 - pos_weight) * wn])
    F = np.zeros(len(X), np.float64)
    stage = Stage()
    hit = fa = 1.0
    for _ in range(max_weak):
        # weight trimming (keep the heaviest samples carrying trim_rate, default 95 %, of the weight)
        if trim_rate < 1.0:
            ws = np.sort(w)[::-1]
            cut = ws[min(np.searchsorted(np.cumsum(ws), trim_rate), len(ws) - 1)]
            keep = np.nonzero(w >= cut)[0]
        else:
            keep = np.arange(len(w))
        # random feature subset per round (speed; as in randomised boosting), indices mapped back
        cols = np.sort(rng.choice(X.shape[1], max(1, int(round(feature_frac * X.shape[1]))), replace=False))
        st = best_stump(X[np.ix_(keep, cols)], y[keep], w[keep], offsets[:len(cols)])
        st.feature = int(cols[st.feature])
        stage.stumps.append(st)
        f = st.predict(X[:, st.feature]).astype(np.float64)
        F += f
        w = w * np.exp(-y * f)
        w /= w.sum()
        sp = np.sort(stage.score(Xp))
        k = int(math.floor((1.0 - min_hit) * len(sp)))
        thr = float(sp[k]) - 1e-4
        hit = float(np.mean(stage.score(Xp) >= thr))
        fa = float(np.mean(stage.score(Xn) >= thr)) if neg_weights is None else float(np.sum(wn * (stage.score(Xn) >= thr)))
        stage.threshold = thr
        if fa <= max_fa and len(stage.stumps) >= 2:
            break
    log("  stage: %d weak, hit %.4f, false alarm %.4f" % (len(stage.stumps), hit, fa))
    return stage, hit, fa


def cascade_pass(stages: List[Stage], X: np.ndarray) -> np.ndarray:
    """Boolean mask of samples passing every stage."""
    ok = np.ones(len(X), bool)
    for s in stages:
        ok &= s.score(X) >= s.threshold
    return ok


# --------------------------------------------------------------------------------------------------
# XML
# --------------------------------------------------------------------------------------------------

def write_xml(path: str, stages: List[Stage], rects: np.ndarray, min_hit: float, max_fa: float, max_weak: int) -> None:
    """Write the cascade in OpenCV's cascade XML format (stageType BOOST, featureType LBP)."""
    used = sorted({st.feature for s in stages for st in s.stumps})
    remap = {f: i for i, f in enumerate(used)}
    L = ['<?xml version="1.0"?>', "<opencv_storage>", "<cascade>",
         "  <stageType>BOOST</stageType>", "  <featureType>LBP</featureType>",
         "  <height>%d</height>" % WIN_H, "  <width>%d</width>" % WIN_W,
         "  <stageParams>", "    <boostType>GAB</boostType>",
         "    <minHitRate>%.17g</minHitRate>" % min_hit, "    <maxFalseAlarm>%.17g</maxFalseAlarm>" % max_fa,
         "    <weightTrimRate>0.95</weightTrimRate>", "    <maxDepth>1</maxDepth>",
         "    <maxWeakCount>%d</maxWeakCount></stageParams>" % max_weak,
         "  <featureParams>", "    <maxCatCount>256</maxCatCount>", "    <featSize>1</featSize></featureParams>",
         "  <stageNum>%d</stageNum>" % len(stages), "  <stages>"]
    for i, s in enumerate(stages):
        L += ["    <!-- stage %d -->" % i, "    <_>", "      <maxWeakCount>%d</maxWeakCount>" % len(s.stumps),
              "      <stageThreshold>%.9e</stageThreshold>" % s.threshold, "      <weakClassifiers>"]
        for st in s.stumps:
            L += ["        <_>", "          <internalNodes>",
                  "            0 -1 %d %s</internalNodes>" % (remap[st.feature], " ".join(str(m) for m in st.masks())),
                  "          <leafValues>", "            %.9e %.9e</leafValues></_>" % (st.leaf0, st.leaf1)]
        L += ["      </weakClassifiers></_>"]
    L += ["  </stages>", "  <features>"]
    for f in used:
        x, y, w, h = rects[f]
        L += ["    <_>", "      <rect>", "        %d %d %d %d</rect></_>" % (x, y, w, h)]
    L += ["  </features>", "</cascade>", "</opencv_storage>", ""]
    with open(path, "w") as fh:
        fh.write("\n".join(L))


def read_xml(path: str) -> Tuple[List[Stage], np.ndarray]:
    """Read an OpenCV LBP cascade XML back (stages with stumps indexing its own rect list)."""
    root = ET.parse(path).getroot().find("cascade")
    rects = np.array([[int(v) for v in r.find("rect").text.split()] for r in root.find("features")], np.int32)
    stages = []
    for s in root.find("stages"):
        st = Stage()
        st.threshold = float(s.find("stageThreshold").text)
        for wc in s.find("weakClassifiers"):
            nodes = [int(v) for v in wc.find("internalNodes").text.split()]
            leaves = [float(v) for v in wc.find("leafValues").text.split()]
            subset = np.zeros(256, bool)
            for c in range(256):
                subset[c] = bool((nodes[3 + (c >> 5)] & 0xFFFFFFFF) & (1 << (c & 31)))
            st.stumps.append(Stump(nodes[2], subset, leaves[0], leaves[1]))
        stages.append(st)
    return stages, rects


# --------------------------------------------------------------------------------------------------
# Data
# --------------------------------------------------------------------------------------------------

def sample_windows_random(frames: List[np.ndarray], n: int, rng: np.random.Generator) -> np.ndarray:
    """Random 24 x 16 windows (random position and scale) from grey frames."""
    out = np.zeros((n, WIN_H, WIN_W), np.uint8)
    for i in range(n):
        g = frames[int(rng.integers(len(frames)))]
        H, W = g.shape
        s = math.exp(rng.uniform(0, math.log(min(W / WIN_W, H / WIN_H) / 1.2)))
        ww, wh = int(WIN_W * s), int(WIN_H * s)
        x, y = int(rng.integers(0, W - ww + 1)), int(rng.integers(0, H - wh + 1))
        out[i] = cv2.resize(g[y:y + wh, x:x + ww], (WIN_W, WIN_H), interpolation=cv2.INTER_LINEAR)
    return out


def mine_negatives(xml_path: str, frames: List[np.ndarray], n: int, rng: np.random.Generator, max_per_frame: int) -> Tuple[np.ndarray, int]:
    """Windows of sign-free frames that the cascade in xml_path accepts (minNeighbors 0, scale 1.1).
    Returns (patches, number of frames scanned)."""
    cc = cv2.CascadeClassifier(xml_path)
    if cc.empty():
        raise RuntimeError("mine_negatives: cv2 could not load %s" % xml_path)
    out = []
    scanned = 0
    order = rng.permutation(len(frames))
    for fi in order:
        g = frames[fi]
        rects = cc.detectMultiScale(g, scaleFactor=1.1, minNeighbors=0, minSize=(WIN_W, WIN_H))
        scanned += 1
        if len(rects) == 0:
            continue
        rects = np.asarray(rects)
        if len(rects) > max_per_frame:
            rects = rects[rng.choice(len(rects), max_per_frame, replace=False)]
        for x, y, w, h in rects:
            out.append(cv2.resize(g[y:y + h, x:x + w], (WIN_W, WIN_H), interpolation=cv2.INTER_LINEAR))
        if len(out) >= n:
            break
    if not out:
        return np.zeros((0, WIN_H, WIN_W), np.uint8), scanned
    return np.stack(out[:n]), scanned


def codes_for(patches: np.ndarray, rects: np.ndarray) -> np.ndarray:
    """MB-LBP codes (N, len(rects)) of grey patches for the given rects only."""
    p = np.asarray(patches)
    N, Hh, Ww = p.shape
    I = np.zeros((N, Hh + 1, Ww + 1), np.int64)
    I[:, 1:, 1:] = p.astype(np.int64).cumsum(1).cumsum(2)
    out = np.zeros((N, len(rects)), np.uint8)
    for k, (x, y, w, h) in enumerate(rects):
        P = [[I[:, y + j * h, x + i * w] for i in range(4)] for j in range(4)]

        def block(r, c):
            return P[r + 1][c + 1] - P[r][c + 1] - P[r + 1][c] + P[r][c]

        centre = block(1, 1)
        code = np.zeros(N, np.uint8)
        for (r, c), bit in _BITS.items():
            code |= np.where(block(r, c) >= centre, np.uint8(bit), np.uint8(0))
        out[:, k] = code
    return out


def mine_negatives_exact(xml_path: str, stages: List[Stage], rects_all: np.ndarray, frames: List[np.ndarray], n: int,
                         rng: np.random.Generator, max_per_frame: int, scale_factor: float = 1.1,
                         sort_rects: bool = False) -> Tuple[np.ndarray, int]:
    """Windows exactly as cv2.CascadeClassifier.detectMultiScale evaluates them (image pyramid by
    INTER_LINEAR_EXACT resize to round(size / factor), window at step 2 below factor 2 else 1) that
    the cascade accepts: OpenCV finds the accepted rects, each is mapped back to its pyramid level
    and position, and only windows the numpy cascade also accepts are kept. sort_rects: sort OpenCV's
    rects first (its threaded scan returns them in a varying order, so without sorting the random
    subset of max_per_frame, and the training after stage 0, differ between runs)."""
    cc = cv2.CascadeClassifier(xml_path)
    if cc.empty():
        raise RuntimeError("mine_negatives_exact: cv2 could not load %s" % xml_path)
    used = sorted({st.feature for s in stages for st in s.stumps})
    remap = {f: i for i, f in enumerate(used)}
    sub_rects = rects_all[used]
    out = []
    scanned = 0
    for fi in rng.permutation(len(frames)):
        g = frames[fi]
        H, W = g.shape
        rects = cc.detectMultiScale(g, scaleFactor=scale_factor, minNeighbors=0, minSize=(WIN_W, WIN_H))
        scanned += 1
        if len(rects) == 0:
            continue
        rects = np.asarray(rects)
        if sort_rects:
            rects = rects[np.lexsort(rects.T[::-1])]
        if len(rects) > max_per_frame:
            rects = rects[rng.choice(len(rects), max_per_frame, replace=False)]
        factors = []
        f = 1.0
        while round(WIN_W * f) <= W and round(WIN_H * f) <= H:
            factors.append(f)
            f *= scale_factor
        cache = {}
        cands = []
        for x, y, w, h in rects:
            fs = [f for f in factors if int(round(WIN_W * f)) == w and int(round(WIN_H * f)) == h]
            for f in fs[:1]:
                if f not in cache:
                    sz = (int(round(W / f)), int(round(H / f)))
                    cache[f] = cv2.resize(g, sz, interpolation=cv2.INTER_LINEAR_EXACT)
                S = cache[f]
                step = 1 if f > 2 else 2
                for px in {int(math.floor(x / f / step)) * step, int(math.ceil(x / f / step)) * step}:
                    for py in {int(math.floor(y / f / step)) * step, int(math.ceil(y / f / step)) * step}:
                        if px + WIN_W <= S.shape[1] and py + WIN_H <= S.shape[0]:
                            cands.append(S[py:py + WIN_H, px:px + WIN_W])
        if cands:
            P = np.stack(cands)
            C = codes_for(P, sub_rects)
            ok = np.ones(len(P), bool)
            for s in stages:
                sc = np.zeros(len(P), np.float32)
                for st in s.stumps:
                    sc += st.predict(C[:, remap[st.feature]])
                ok &= sc >= s.threshold
            out.extend(P[ok])
        if len(out) >= n:
            break
    if not out:
        return np.zeros((0, WIN_H, WIN_W), np.uint8), scanned
    out = np.stack(out)
    return out[rng.permutation(len(out))[:n]], scanned


def _render_one(job) -> np.ndarray:
    fn, seed, stream, i = job
    return fn(np.random.default_rng([seed, stream, i]))


def rendered(fn, seed: int, stream: int, n: int, workers: int = 1) -> List[np.ndarray]:
    """[fn(default_rng([seed, stream, i])) for i in range(n)], in `workers` processes (the same samples for any
    count: every sample has its own generator)."""
    return list(crops.imap_in_processes(_render_one, [(fn, seed, stream, i) for i in range(n)], workers, chunksize=16))


def kind_windows(cache_dir: str, kind: str, seed: int, n: int, win: Tuple[int, int], log) -> np.ndarray:
    """The first n windows of `kind` (crops.kind_window, generators (seed, 20 + KIND_CODES[kind], i)),
    cached in cache_dir and extended when more are asked for."""
    path = os.path.join(cache_dir, "kind_windows_%s_seed%d_w%dx%d.npz" % (kind, seed, win[0], win[1]))
    have = np.load(path)["windows"] if os.path.exists(path) else np.zeros((0, win[1], win[0]), np.uint8)
    if len(have) < n:
        t0 = time.time()
        new = [crops.kind_window(np.random.default_rng([seed, 20 + KIND_CODES[kind], i]), kind, win) for i in range(len(have), n)]
        have = np.concatenate([have, np.stack(new)])
        np.savez(path, windows=have)
        log("rendered %d %s windows (%.0f s)" % (len(new), kind, time.time() - t0))
    return have[:n]


def kind_frames(cache_dir: str, seed: int, n_empty: int, n_per_kind: int, log, mode: str = "unrolled") -> Tuple[List[np.ndarray], List[List[str]]]:
    """Negative frames shared by the wall-kind cascades: n_empty sign-free frames and, per wall kind,
    n_per_kind frames with that kind, often a second kind and an Exit sign (crops.kind_frame). Returns (grey
    frames, the sign kinds in each).

    mode "unrolled": VGA frames rendered at the sensor pose and unrolled as at run time, black corners
    included (crops.vga_empty_frame, generators (seed, 15, i); crops.kind_frame(unrolled=True), (seed, 40 +
    code, i)); "virtual": rendered at the roll-free virtual camera, no black corners (crops.negative_frame,
    (seed, 11, i); crops.kind_frame, (seed, 30 + code, i)): the first recipe, used for the committed
    restroom and elevator cascades."""
    if mode not in ("unrolled", "virtual"):
        raise ValueError("kind_frames: mode %r" % mode)
    unrolled = mode == "unrolled"
    path = os.path.join(cache_dir, "kind_frames_%sseed%d_e%d_k%d.npz" % ("unrolled_" if unrolled else "", seed, n_empty, n_per_kind))
    if os.path.exists(path):
        z = np.load(path, allow_pickle=True)
        return list(z["frames"]), [str(k).split(",") if str(k) else [] for k in z["kinds"]]
    t0 = time.time()
    frames, kinds = [], []
    for i in range(n_empty):
        frames.append(crops.vga_empty_frame(np.random.default_rng([seed, 15, i])) if unrolled else
                      crops.negative_frame(np.random.default_rng([seed, 11, i])))
        kinds.append([])
    for k in rs.WALL_KINDS:
        for i in range(n_per_kind):
            g, ks = crops.kind_frame(np.random.default_rng([seed, (40 if unrolled else 30) + KIND_CODES[k], i]), k,
                                     [o for o in rs.WALL_KINDS if o != k], unrolled=unrolled)
            frames.append(g)
            kinds.append(ks)
    arr = np.empty(len(frames), object)
    arr[:] = frames
    np.savez(path, frames=arr, kinds=np.array([",".join(k) for k in kinds]))
    log("rendered %d negative frames (%.0f s)" % (len(frames), time.time() - t0))
    return frames, kinds


def load_kind_samples(a, log) -> Tuple[np.ndarray, List[np.ndarray], np.ndarray, np.ndarray]:
    """(positives, negative frames, confuser windows, confuser kinds) of the cascade for a.kind at the
    current window: a.num_pos windows of the kind; the sign-free frames and the frames without the kind;
    a.confusers windows of every other kind (Exit included)."""
    win = (WIN_W, WIN_H)
    pos = kind_windows(a.cache, a.kind, a.seed, a.num_pos, win, log)
    frames_all, kinds_all = kind_frames(a.cache, a.seed, a.neg_frames, a.kind_frames, log, a.kind_negatives)
    frames = [g for g, ks in zip(frames_all, kinds_all) if a.kind not in ks]
    conf, conf_kind = [], []
    for k in ("exit",) + rs.WALL_KINDS:
        if k != a.kind and a.confusers > 0:
            conf.append(kind_windows(a.cache, k, a.seed, a.confusers, win, log))
            conf_kind += [k] * a.confusers
    conf = np.concatenate(conf) if conf else np.zeros((0, WIN_H, WIN_W), np.uint8)
    log("%s: %d positives, %d negative frames (%d with other kinds), %d confuser windows" %
        (a.kind, len(pos), len(frames), sum(1 for g, ks in zip(frames_all, kinds_all) if ks and a.kind not in ks), len(conf)))
    return pos, frames, conf, np.array(conf_kind)


def load_stages_full_index(path: str, rects_all: np.ndarray) -> List[Stage]:
    """Read a cascade XML and re-index its stumps into enumerate_features() order (to continue training)."""
    stages, rects = read_xml(path)
    index = {tuple(r): i for i, r in enumerate(rects_all.tolist())}
    for s in stages:
        for st in s.stumps:
            st.feature = index[tuple(rects[st.feature].tolist())]
    return stages


# --------------------------------------------------------------------------------------------------
# Cheap stages in front of an existing cascade (speed)
# --------------------------------------------------------------------------------------------------

def detection_windows(g: np.ndarray, scale_factor: float = 1.2, max_windows: int = 0,
                      rng: np.random.Generator = None) -> np.ndarray:
    """The 24 x 16 windows cv::CascadeClassifier::detectMultiScale evaluates on grey image `g` with
    `scale_factor` and the training window as smallest window: for each factor 1, s, s^2, ... while
    the window fits, the image resized (INTER_LINEAR_EXACT) to round(size / factor), windows at
    x < width - 24, y < height - 16 with step 2 for factor <= 2, else 1 (OpenCV's scan; the extra
    step OpenCV takes after a stage-0 rejection is ignored). Returns (N, 16, 24) uint8, a random
    subset of at most `max_windows` when that is > 0."""
    H, W = g.shape
    out = []
    f = 1.0
    while int(round(WIN_W * f)) <= W and int(round(WIN_H * f)) <= H:
        sw, sh = int(round(W / f)), int(round(H / f))
        S = cv2.resize(g, (sw, sh), interpolation=cv2.INTER_LINEAR_EXACT)
        step = 1 if f > 2 else 2
        nx, ny = sw - WIN_W, sh - WIN_H
        if nx > 0 and ny > 0:
            V = np.lib.stride_tricks.sliding_window_view(S, (WIN_H, WIN_W))[0:ny:step, 0:nx:step]
            out.append(V.reshape(-1, WIN_H, WIN_W))
        f *= scale_factor
    if not out:
        return np.zeros((0, WIN_H, WIN_W), np.uint8)
    P = np.concatenate(out)
    if max_windows and len(P) > max_windows:
        P = P[(rng or np.random.default_rng(0)).choice(len(P), max_windows, replace=False)]
    return np.ascontiguousarray(P)


def stump_cost(stages: List[Stage], rects: np.ndarray, patches: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Per window: weak classifiers evaluated before the cascade (stages with stumps indexing `rects`)
    rejects or accepts it, and whether it is accepted. Returns (cost float (N,), accepted bool (N,))."""
    used = sorted({st.feature for s in stages for st in s.stumps})
    remap = {f: i for i, f in enumerate(used)}
    C = codes_for(patches, rects[used]) if used else np.zeros((len(patches), 0), np.uint8)
    alive = np.ones(len(patches), bool)
    cost = np.zeros(len(patches))
    for s in stages:
        idx = np.nonzero(alive)[0]
        if len(idx) == 0:
            break
        sc = np.zeros(len(idx), np.float32)
        for st in s.stumps:
            sc += st.predict(C[idx, remap[st.feature]])
        cost[idx] += len(s.stumps)
        alive[idx[sc < s.threshold]] = False
    return cost, alive


def prepend_stages(base: List[Stage], rects: np.ndarray, Xp_all: np.ndarray, frames: List[np.ndarray],
                   weak_counts: List[int], min_hit: float, num_neg: int, windows_per_frame: int,
                   offsets: np.ndarray, rng: np.random.Generator, log, feature_frac: float = 1.0,
                   cost_weighted: bool = True, pos_weight: float = 0.5, trim_rate: float = 1.0,
                   after: int = 0) -> List[Stage]:
    """Train small stages (weak_counts[i] stumps each) to run before the cascade `base` (its stumps
    indexing `rects`, the full feature list): OpenCV's LBP cascade evaluates stages independently, so
    stages put in front only remove windows, and cheap ones that reject most windows early cut the
    average number of weak classifiers per window. Positives: the training positives `base` accepts
    (features Xp_all, full feature list); each new stage keeps min_hit of those still accepted.
    Negatives of new stage i: windows detectMultiScale evaluates (detection_windows) on the sign-free
    frames that new stages 0..i-1 accept; when cost_weighted, each starts with a boosting weight
    proportional to the weak classifiers `base` spends on it (1 + cost), so the stage concentrates on
    windows that are expensive to reject later. Boosting starts with `pos_weight` of the weight on the
    positives and trims no weights by default (trimming would drop the light negatives when the
    positives carry most of the weight). With `after` = k > 0 the new stages go after the first k
    stages of `base` (their negatives are windows those k stages accept): detectMultiScale skips the
    next position after a window its first stage rejects, so keeping `base`'s first stage first keeps
    its scan pattern (new first stages that reject more windows skip more positions and lose weak
    detections of far signs). Returns the new stages only."""
    Xp = Xp_all[cascade_pass(base, Xp_all)]
    log("prepend: %d of %d positives pass the base cascade" % (len(Xp), len(Xp_all)))
    new: List[Stage] = []
    for i, nw in enumerate(weak_counts):
        # Fresh negatives per stage: exact windows of random frames that the new stages so far accept.
        negs, scanned = [], 0
        have = 0
        for fi in rng.permutation(len(frames)):
            P = detection_windows(frames[fi], 1.2, windows_per_frame, rng)
            scanned += 1
            if (new or after) and len(P):
                P = P[cascade_pass(base[:after] + new, compute_features(P))]
            if len(P):
                negs.append(P)
                have += len(P)
            if have >= num_neg:
                break
        if not negs:
            log("prepend: no negatives left after %d new stages" % len(new))
            break
        neg = np.concatenate(negs)
        neg = neg[rng.permutation(len(neg))[:num_neg]]
        Xn = compute_features(neg)
        w_neg = None
        if cost_weighted:
            cost, _ = stump_cost(base, rects, neg)
            w_neg = 1.0 + cost
            log("prepend stage %d: base cascade spends %.1f weak classifiers per negative window" % (i, float(cost.mean())))
        log("prepend stage %d: %d positives, %d negatives from %d frames" % (i, len(Xp), len(Xn), scanned))
        stage, hit, fa = train_stage(Xp, Xn, min_hit, 0.0, nw, offsets, log, rng, feature_frac, neg_weights=w_neg,
                                     pos_weight=pos_weight, trim_rate=trim_rate)
        new.append(stage)
        Xp = Xp[stage.score(Xp) >= stage.threshold]
    return new


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Train an LBP cascade (Exit sign or a wall sign kind) from rendered samples.")
    ap.add_argument("--out", required=True, help="output cascade XML")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--kind", choices=("exit",) + rs.WALL_KINDS, default="exit",
                    help="sign kind (default exit: the committed Exit cascade's recipe, unchanged)")
    ap.add_argument("--window", default=None, metavar="WxH",
                    help="training window (default 24x16 for exit, 20x20 for the wall kinds)")
    ap.add_argument("--kind-frames", type=int, default=100,
                    help="wall kinds: negative frames rendered per wall kind (those without --kind are used)")
    ap.add_argument("--kind-negatives", choices=["unrolled", "virtual"], default="unrolled",
                    help="wall kinds: negative frames rendered at the sensor pose and unrolled as at run time, black "
                         "corners included (default), or 'virtual': at the roll-free virtual camera (the recipe of the "
                         "committed restroom and elevator cascades)")
    ap.add_argument("--confusers", type=int, default=600,
                    help="wall kinds: windows of each other kind (Exit included) used as negatives")
    ap.add_argument("--num-pos", type=int, default=3000)
    ap.add_argument("--num-neg", type=int, default=3000)
    ap.add_argument("--neg-frames", type=int, default=500)
    ap.add_argument("--stages", type=int, default=20)
    ap.add_argument("--min-hit", type=float, default=0.995)
    ap.add_argument("--max-fa", type=float, default=0.5)
    ap.add_argument("--max-weak", type=int, default=100)
    ap.add_argument("--time-limit-min", type=float, default=35.0, help="stop adding stages after this wall time (excluding sample rendering)")
    ap.add_argument("--feature-frac", type=float, default=0.35, help="fraction of features searched per boosting round")
    ap.add_argument("--first-negatives", choices=["random", "detection"], default="random",
                    help="stage 0's negatives: 'random' windows (log-uniform scale, the committed model's recipe) or "
                         "'detection': drawn uniformly from the windows detectMultiScale evaluates (scale 1.2, "
                         "most of them at the smallest scales), as the run-time search sees them")
    ap.add_argument("--resume", default=None, help="continue from the stages of this cascade XML")
    ap.add_argument("--prepend-to", default=None, metavar="CASCADE.xml",
                    help="speed: train small stages to run in front of this cascade (which is kept as it is) and "
                         "write new stages + its stages to --out (see prepend_stages)")
    ap.add_argument("--prepend-weak", default="2,3,4", help="weak classifiers of each prepended stage, comma-separated")
    ap.add_argument("--prepend-min-hit", type=float, default=0.999,
                    help="hit rate of each prepended stage on the positives the cascade accepts")
    ap.add_argument("--prepend-windows-per-frame", type=int, default=400,
                    help="random detection windows taken per sign-free frame as negatives of a prepended stage")
    ap.add_argument("--prepend-pos-weight", type=float, default=0.5,
                    help="share of the starting boosting weight on the positives in prepended stages")
    ap.add_argument("--prepend-neg-images", default=None, metavar="GLOB",
                    help="grey images (e.g. the colour gate's search regions of rendered sign-free frames) to take the "
                         "prepended stages' negative windows from instead of the cached sign-free frames")
    ap.add_argument("--prepend-after", type=int, default=0,
                    help="put the new stages after this many of the cascade's first stages (default 0: in front)")
    ap.add_argument("--prepend-uniform", action="store_true",
                    help="equal starting weights for the negatives (default: weighted by the cascade's cost)")
    ap.add_argument("--phone-pos", type=int, default=0,
                    help="Exit: phone-style positive windows added to --num-pos (crops.cascade_positive_phone, "
                         "generators (seed, 16, i))")
    ap.add_argument("--phone-neg-frames", type=int, default=0,
                    help="Exit: phone-style sign-free frames added to --neg-frames (crops.negative_frame_phone, "
                         "generators (seed, 17, i))")
    ap.add_argument("--workers", type=int, default=1, help="processes rendering the samples (same samples for any count)")
    ap.add_argument("--cache", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "data"))
    a = ap.parse_args(argv)
    t0 = time.time()

    def log(msg):
        print("[%6.1fs] %s" % (time.time() - t0, msg), flush=True)

    os.makedirs(a.cache, exist_ok=True)
    if a.window:
        set_window(*[int(v) for v in a.window.lower().split("x")])
    else:
        set_window(*((24, 16) if a.kind == "exit" else (20, 20)))
    log("kind %s, window %d x %d" % (a.kind, WIN_W, WIN_H))
    conf = conf_kind = None
    cache = os.path.join(a.cache, "cascade_samples_seed%d_p%d_f%d.npz" % (a.seed, a.num_pos, a.neg_frames))
    if a.kind != "exit" or (WIN_W, WIN_H) != (24, 16):
        pos, frames, conf, conf_kind = load_kind_samples(a, log)
    elif os.path.exists(cache):
        z = np.load(cache, allow_pickle=True)
        pos, frames = z["pos"], list(z["frames"])
        log("loaded %s" % cache)
    else:
        pos = np.stack(rendered(crops.cascade_positive, a.seed, 10, a.num_pos, a.workers))
        log("rendered %d positives" % len(pos))
        frames = rendered(crops.negative_frame, a.seed, 11, a.neg_frames, a.workers)
        log("rendered %d negative frames" % len(frames))
        arr = np.empty(len(frames), object)
        arr[:] = frames
        np.savez(cache, pos=pos, frames=arr)
    if a.kind == "exit" and (a.phone_pos > 0 or a.phone_neg_frames > 0):
        phone_cache = os.path.join(a.cache, "cascade_phone_samples_seed%d_p%d_f%d.npz" % (a.seed, a.phone_pos, a.phone_neg_frames))
        if os.path.exists(phone_cache):
            z = np.load(phone_cache, allow_pickle=True)
            phone_pos, phone_frames = z["pos"], list(z["frames"])
            log("loaded %s" % phone_cache)
        else:
            phone_pos = np.stack(rendered(crops.cascade_positive_phone, a.seed, 16, a.phone_pos, a.workers)) \
                if a.phone_pos > 0 else np.zeros((0, WIN_H, WIN_W), np.uint8)
            phone_frames = rendered(crops.negative_frame_phone, a.seed, 17, a.phone_neg_frames, a.workers)
            arr = np.empty(len(phone_frames), object)
            arr[:] = phone_frames
            np.savez(phone_cache, pos=phone_pos, frames=arr)
            log("rendered %d phone-style positives, %d phone-style negative frames" % (len(phone_pos), len(phone_frames)))
        pos = np.concatenate([pos, phone_pos])
        frames = list(frames) + list(phone_frames)
    t_train0 = time.time()
    rects = enumerate_features()
    offsets = (np.arange(len(rects), dtype=np.int32) * 256)
    log("%d MB-LBP features" % len(rects))
    Xp_all = compute_features(pos)
    Xconf = compute_features(conf) if conf is not None and len(conf) else None
    rng = np.random.default_rng([a.seed, 12])
    if a.prepend_to:
        base = load_stages_full_index(a.prepend_to, rects)
        rng_p = np.random.default_rng([a.seed, 13])
        if a.prepend_neg_images:
            import glob
            paths = sorted(glob.glob(a.prepend_neg_images))
            frames = [g for g in (cv2.imread(p_, cv2.IMREAD_GRAYSCALE) for p_ in paths) if g is not None]
            log("prepend: %d negative images from %s" % (len(frames), a.prepend_neg_images))
        # images held out for the cost report: every 10th; new stages train on the others
        train_frames = [g for i, g in enumerate(frames) if i % 10]
        report_frames = frames[::10]
        new = prepend_stages(base, rects, Xp_all, train_frames, [int(v) for v in a.prepend_weak.split(",")],
                             a.prepend_min_hit, a.num_neg, a.prepend_windows_per_frame, offsets, rng_p, log,
                             a.feature_frac, cost_weighted=not a.prepend_uniform,
                             pos_weight=a.prepend_pos_weight, after=a.prepend_after)
        stages = base[:a.prepend_after] + new + base[a.prepend_after:]
        write_xml(a.out, stages, rects, a.min_hit, a.max_fa, a.max_weak)
        P = np.concatenate([detection_windows(g, 1.2, 2000, rng_p) for g in report_frames])
        c0, acc0 = stump_cost(base, rects, P)
        c1, acc1 = stump_cost(stages, rects, P)
        log("held-out frames (%d windows): weak classifiers per window %.2f -> %.2f, accepted %d -> %d" %
            (len(P), float(c0.mean()), float(c1.mean()), int(acc0.sum()), int(acc1.sum())))
        log("done: %d + %d stages, %d weak classifiers, training-positive hit rate %.4f -> %.4f -> %s" %
            (len(new), len(base), sum(len(s.stumps) for s in stages), float(np.mean(cascade_pass(base, Xp_all))),
             float(np.mean(cascade_pass(stages, Xp_all))), a.out))
        return 0
    stages: List[Stage] = load_stages_full_index(a.resume, rects) if a.resume else []
    if stages:
        log("resumed %d stages from %s" % (len(stages), a.resume))
    tmp_xml = a.out + ".partial.xml"
    for k in range(len(stages), a.stages):
        if time.time() - t_train0 > a.time_limit_min * 60:
            log("time limit reached")
            break
        Xp = Xp_all[cascade_pass(stages, Xp_all)]
        if not stages and a.first_negatives == "detection":
            per_frame = max(1, -(-a.num_neg // len(frames)))
            neg = np.concatenate([detection_windows(g, 1.2, per_frame, rng) for g in frames])
            neg = neg[rng.permutation(len(neg))[:a.num_neg]]
            scanned = len(frames)
        elif not stages:
            neg = sample_windows_random(frames, a.num_neg, rng)
            scanned = 0
        else:
            write_xml(tmp_xml, stages, rects, a.min_hit, a.max_fa, a.max_weak)
            neg, scanned = mine_negatives_exact(tmp_xml, stages, rects, frames, a.num_neg, rng, max_per_frame=max(20, a.num_neg // 40),
                                                sort_rects=conf is not None)
        Xn = compute_features(neg) if len(neg) else np.zeros((0, len(rects)), np.uint8)
        if stages and len(Xn):
            Xn = Xn[cascade_pass(stages, Xn)]  # confirm they pass stages 0..k-1
        Xn = Xn[rng.permutation(len(Xn))[:a.num_neg]]
        n_mined = len(Xn)
        if Xconf is not None:  # windows around the other kinds' faces that still pass, up to half of num_neg
            Xc = Xconf[cascade_pass(stages, Xconf)]
            Xc = Xc[rng.permutation(len(Xc))[:a.num_neg // 2]]
            Xn = np.concatenate([Xn, Xc])
            log("stage %d: %d positives, %d negatives (frames scanned %d) + %d confuser windows" %
                (k, len(Xp), n_mined, scanned, len(Xc)))
        else:
            log("stage %d: %d positives, %d negatives (frames scanned %d)" % (k, len(Xp), len(Xn), scanned))
        if n_mined < 100:
            log("too few hard negatives left; cascade done")
            break
        stage, hit, fa = train_stage(Xp, Xn, a.min_hit, a.max_fa, a.max_weak, offsets, log, rng, a.feature_frac)
        stages.append(stage)
        write_xml(a.out, stages, rects, a.min_hit, a.max_fa, a.max_weak)
    if os.path.exists(tmp_xml):
        os.remove(tmp_xml)
    total = float(np.mean(cascade_pass(stages, Xp_all)))
    log("done: %d stages, %d weak classifiers, training-positive hit rate %.4f -> %s" %
        (len(stages), sum(len(s.stumps) for s in stages), total, a.out))
    if Xconf is not None:
        ok = cascade_pass(stages, Xconf)
        log("confuser windows accepted: " + ", ".join("%s %.4f" % (k, float(ok[conf_kind == k].mean()))
                                                       for k in ("exit",) + rs.WALL_KINDS if (conf_kind == k).any()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
