#!/usr/bin/env python3
"""Quick Python evaluation of the sign detectors on a rendered test set (render_signs.py format).

Per true distance (2..9 m): recall and median percent range error |e - a| / a, the paper's Table 1
metric; on sign-free frames: frames with any false detection.

Range from a detection (paper, eq. 3): in the unrolled image, Z = h0 / (tan(e_top) - tan(e_bottom))
where e is the elevation of the ray through the sign's top / bottom point (computed from the full
roll-free rotation Rx(pitch), exact for any column, arkit-frames.md). For masks the top/bottom
come from per-column slices: height = sum of exit probability down the column (sub-pixel), bottom =
probability-weighted centroid row + height / 2, medians over the columns (paper section 3). For
cascade boxes, the box edges.

Detectors:
  * cascade: cv2.CascadeClassifier on the grey unrolled frame, at VGA (frame scaled by 1/3) or HR;
  * U-Net multi-scale: coarse pass on the letterboxed unrolled frame, then a zoomed crop (side 3.5 x
    the detected width) around each coarse candidate, then a second zoom re-centred on the first
    zoom's segmentation; range from the final zoom's mask.

Usage:
  python3 eval_detectors.py --test data/test_raw --cascade ../models/exit_sign_cascade.xml \
      --cascade /work/shared/data/skeri_inavigate/models/exit_sign_cascade.xml --unet ../models/sign_unet.onnx
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from typing import List, Optional, Tuple

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render_signs as rs  # noqa: E402


def load_labels(test_dir: str, limit_per_distance: Optional[int] = None) -> List[dict]:
    """Records of labels.jsonl, optionally at most `limit_per_distance` per distance (and as many sign-free)."""
    path = os.path.join(test_dir, "labels.jsonl")
    if not os.path.exists(path):
        raise FileNotFoundError("eval: %s not found (render it with render_signs.py --split test)" % path)
    recs = [json.loads(l) for l in open(path)]
    if limit_per_distance:
        counts = {}
        out = []
        for r in recs:
            key = round(r["signs"][0]["rangeMeters"]) if r["signs"] else -1
            counts[key] = counts.get(key, 0) + 1
            if counts[key] <= limit_per_distance * (1 if key >= 0 else 5):
                out.append(r)
        recs = out
    return recs


def elevation(u: float, v: float, intr_u: dict, pitch: float) -> float:
    """Elevation (rad) of the ray through unrolled pixel (u, v) for camera pitch `pitch`."""
    d = np.array([(u - intr_u["cx"]) / intr_u["fx"], -(v - intr_u["cy"]) / intr_u["fy"], -1.0])
    w = rs.rot_x(pitch) @ d
    return math.atan2(w[1], math.hypot(w[0], w[2]))


def range_from_top_bottom(u: float, v_top: float, v_bottom: float, intr_u: dict, pitch: float, h0: float,
                          u_bottom: Optional[float] = None) -> float:
    """Paper eq. 3 with elevations of the sign top (u, v_top) and bottom (u_bottom or u, v_bottom)."""
    ub = u if u_bottom is None else u_bottom
    den = math.tan(elevation(u, v_top, intr_u, pitch)) - math.tan(elevation(ub, v_bottom, intr_u, pitch))
    return h0 / den if den > 1e-9 else float("inf")


def slices_from_prob(prob: np.ndarray) -> Optional[Tuple[float, float, float]]:
    """(median column, median top row, median bottom row) of a probability map of one sign (crop
    coordinates, pixel centres at integers); None when empty."""
    cols = np.nonzero(prob.max(axis=0) > 0.5)[0]
    if len(cols) == 0:
        return None
    # use the central 80 % of the columns (edges are partial-volume)
    lo, hi = cols.min(), cols.max()
    span = hi - lo + 1
    c0, c1 = lo + int(0.1 * span), hi - int(0.1 * span)
    cols = np.arange(c0, c1 + 1)
    rows = np.arange(prob.shape[0], dtype=np.float64)
    heights, bottoms = [], []
    for c in cols:
        p = prob[:, c].astype(np.float64)
        s = p.sum()
        if s < 0.5:
            continue
        cen = (p * rows).sum() / s
        heights.append(s)
        bottoms.append(cen + s / 2.0 - 0.5)
    if not heights:
        return None
    h = float(np.median(heights))
    b = float(np.median(bottoms))
    return float(np.median(cols)), b - h, b


class UNetRunner:
    """Runs the exported U-Net (ONNX via onnxruntime, or a .pt checkpoint via torch)."""

    def __init__(self, path: str):
        self.path = path
        if path.endswith(".onnx"):
            import onnxruntime as ort
            so = ort.SessionOptions()
            so.intra_op_num_threads = 2
            self.sess = ort.InferenceSession(path, so, providers=["CPUExecutionProvider"])
            self.torch = None
        else:
            import torch
            from train_unet import SignUNet
            ck = torch.load(path, map_location="cpu")
            self.torch = SignUNet(ck["width"], ck["num_classes"])
            self.torch.load_state_dict(ck["state_dict"])
            self.torch.eval()

    def prob(self, rgb224: np.ndarray) -> np.ndarray:
        """Exit probability (224, 224) for an RGB uint8 224 x 224 image."""
        x = (rgb224.astype(np.float32) / 255.0).transpose(2, 0, 1)[None]
        if self.torch is None:
            logits = self.sess.run(["logits"], {"image": x})[0][0]
        else:
            import torch
            with torch.no_grad():
                logits = self.torch(torch.from_numpy(x)).numpy()[0]
        e = np.exp(logits - logits.max(axis=0, keepdims=True))
        return e[1] / e.sum(axis=0)


def crop_square(img: np.ndarray, cx: float, cy: float, side: float, out: int = 224) -> np.ndarray:
    """Square crop centred at (cx, cy) of `side` pixels resized to out x out (outside the image: 0).
    Output pixel j samples source x = cx + (j - (out - 1) / 2) * side / out; when shrinking, the
    source is first area-averaged by an integer factor (warpAffine has no area filter)."""
    s = out / side
    k = int(max(1, math.floor(1.0 / s)))
    x0, y0 = 0, 0
    src = img
    if k > 1:
        x0, y0 = int(math.floor(cx - side / 2)) - k, int(math.floor(cy - side / 2)) - k
        x1, y1 = int(math.ceil(cx + side / 2)) + k, int(math.ceil(cy + side / 2)) + k
        pad = [max(0, -y0), max(0, y1 - img.shape[0]), max(0, -x0), max(0, x1 - img.shape[1])]
        sub = img[max(y0, 0):min(y1, img.shape[0]), max(x0, 0):min(x1, img.shape[1])]
        sub = cv2.copyMakeBorder(sub, pad[0], pad[1], pad[2], pad[3], cv2.BORDER_CONSTANT, value=0)
        src = cv2.resize(sub, (sub.shape[1] // k, sub.shape[0] // k), interpolation=cv2.INTER_AREA)
    # downsampled pixel q has its centre at original x0 + q k + (k - 1) / 2
    M = np.array([[s * k, 0, s * (x0 + (k - 1) / 2.0 - cx) + (out - 1) / 2.0],
                  [0, s * k, s * (y0 + (k - 1) / 2.0 - cy) + (out - 1) / 2.0]], np.float64)
    return cv2.warpAffine(src, M, (out, out), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)


def components(prob: np.ndarray, thr: float = 0.5, min_area: int = 2) -> List[Tuple[float, float, float, float, float]]:
    """Connected components of prob > thr: (cx, cy, w, h, score = max prob) sorted by score."""
    m = (prob > thr).astype(np.uint8)
    n, lab, stats, cent = cv2.connectedComponentsWithStats(m, connectivity=8)
    maxes = np.zeros(n, np.float64)
    np.maximum.at(maxes, lab.ravel(), prob.ravel().astype(np.float64))
    out = []
    for i in range(1, n):
        if stats[i, cv2.CC_STAT_AREA] < min_area:
            continue
        sc = float(maxes[i])
        out.append((float(cent[i, 0]), float(cent[i, 1]), float(stats[i, cv2.CC_STAT_WIDTH]), float(stats[i, cv2.CC_STAT_HEIGHT]), sc))
    out.sort(key=lambda c: -c[4])
    return out


def unet_detect(runner: UNetRunner, img_u: np.ndarray, max_cands: int = 3, zoom_k: float = 3.5) -> List[dict]:
    """Multi-scale U-Net detection on an unrolled RGB frame. Returns detections with the final zoom
    crop geometry and probability map."""
    H, W = img_u.shape[:2]
    s = 224.0 / max(W, H)
    nw, nh = int(round(W * s)), int(round(H * s))
    px, py = (224 - nw) // 2, (224 - nh) // 2
    lb = np.zeros((224, 224, 3), np.uint8)
    lb[py:py + nh, px:px + nw] = cv2.resize(img_u, (nw, nh), interpolation=cv2.INTER_AREA)
    pc = runner.prob(lb)
    dets = []
    for (cx, cy, w, h, sc) in components(pc, 0.5, 1)[:max_cands]:
        ux, uy = (cx - px + 0.5) / s - 0.5, (cy - py + 0.5) / s - 0.5
        width = max((w + 1) / s, 1.5 * (h + 1) / s, 30.0)
        ok = True
        for it in range(2):
            side = zoom_k * width
            crop = crop_square(img_u, ux, uy, side)
            p = runner.prob(crop)
            comps = components(p, 0.5, 12)
            # keep the component nearest the crop centre
            comps = [c for c in comps if abs(c[0] - 111.5) < 80 and abs(c[1] - 111.5) < 80]
            if not comps:
                ok = False
                break
            c = min(comps, key=lambda c: (c[0] - 111.5) ** 2 + (c[1] - 111.5) ** 2)
            sc2 = side / 224.0
            ux, uy = ux + (c[0] - 111.5) * sc2, uy + (c[1] - 111.5) * sc2
            width = max(c[2] * sc2, 1.0)
            last = dict(cx=ux, cy=uy, side=side, crop_cx=ux - (c[0] - 111.5) * sc2, crop_cy=uy - (c[1] - 111.5) * sc2,
                        prob=p, comp=c, score=max(sc, c[4]))
        if ok:
            dets.append(last)
    # suppress duplicates (same sign found from two coarse candidates)
    out = []
    for d in dets:
        if all(math.hypot(d["cx"] - e["cx"], d["cy"] - e["cy"]) > 0.5 * d["side"] / 3.5 for e in out):
            out.append(d)
    return out


def unet_range(det: dict, intr_u: dict, pitch: float, h0: float) -> float:
    """Range from the final zoom crop's probability map (isolating the detected component)."""
    p = det["prob"].copy()
    m = (p > 0.5).astype(np.uint8)
    n, lab = cv2.connectedComponents(m, connectivity=8)
    c = det["comp"]
    li = lab[int(round(c[1])), int(round(c[0]))]
    if li == 0:
        d2 = [(np.mean(np.nonzero(lab == i)[1]) - c[0]) ** 2 + (np.mean(np.nonzero(lab == i)[0]) - c[1]) ** 2 for i in range(1, n)]
        li = 1 + int(np.argmin(d2))
    keep = cv2.dilate((lab == li).astype(np.uint8), np.ones((5, 5), np.uint8))
    p = p * keep
    sl = slices_from_prob(p)
    if sl is None:
        return float("nan")
    col, top, bot = sl
    sc = det["side"] / 224.0
    # crop pixel (i) centre -> unrolled coordinate
    def to_u(x, ctr):
        return ctr + (x - 111.5) * sc
    u = to_u(col, det["crop_cx"])
    return range_from_top_bottom(u, to_u(top, det["crop_cy"]), to_u(bot, det["crop_cy"]), intr_u, pitch, h0)


def gt_box_unrolled(sign: dict, A: np.ndarray) -> np.ndarray:
    """GT corners (4,2) in the unrolled frame."""
    c = np.array(sign["cornersRaw"], np.float64)
    return c @ A[:, :2].T + A[:, 2]


def evaluate(test_dir: str, cascades: List[str], unet: Optional[str], limit: Optional[int], hr: bool, log) -> dict:
    recs = load_labels(test_dir, limit)
    results = {}
    ccs = [(p, cv2.CascadeClassifier(p)) for p in cascades]
    for p, c in ccs:
        if c.empty():
            raise RuntimeError("eval: cannot load cascade %s" % p)
    runner = UNetRunner(unet) if unet else None
    names = [("cascade%d:%s@%s" % (i, os.path.abspath(p), "HR" if hr else "VGA")) for i, p in enumerate(cascades)]
    if runner:
        names.append("unet")
    for n in names + ["gt_corners"]:
        results[n] = {"per_distance": {}, "false_frames": 0, "empty_frames": 0, "errors": {}}
    t0 = time.time()
    for k, r in enumerate(recs):
        img = cv2.cvtColor(cv2.imread(os.path.join(test_dir, r["image"])), cv2.COLOR_BGR2RGB)
        intr = r["intrinsics"]
        img_u, A, intr_u = rs.unroll_image(img, intr, r["rollRad"])
        pitch = r["pitchRad"]
        sign = r["signs"][0] if r["signs"] else None
        dist = int(round(sign["rangeMeters"])) if sign else None
        h0 = sign["heightMeters"] if sign else 0.21
        if sign:
            gt = gt_box_unrolled(sign, A)
            gx0, gy0 = gt.min(axis=0)
            gx1, gy1 = gt.max(axis=0)
            # sanity: range from the exact corners (midpoints of top and bottom edges)
            top = (gt[0] + gt[1]) / 2
            bot = (gt[3] + gt[2]) / 2
            z = range_from_top_bottom(top[0], top[1], bot[1], intr_u, pitch, h0, u_bottom=bot[0])
            results["gt_corners"]["errors"].setdefault(dist, []).append(abs(z - sign["rangeMeters"]) / sign["rangeMeters"])

        def record(name, dets_boxes, ranges):
            res = results[name]
            if sign is None:
                res["empty_frames"] += 1
                res["false_frames"] += int(len(dets_boxes) > 0)
                return
            pd = res["per_distance"].setdefault(dist, {"n": 0, "hit": 0, "fp": 0})
            pd["n"] += 1
            hit = None
            for i, (x0, y0, x1, y1) in enumerate(dets_boxes):
                cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
                mw, mh = 0.25 * (gx1 - gx0), 0.25 * (gy1 - gy0)
                inside = gx0 - mw <= cx <= gx1 + mw and gy0 - mh <= cy <= gy1 + mh
                ratio = (x1 - x0) / max(gx1 - gx0, 1)
                if inside and 0.4 < ratio < 2.5 and hit is None:
                    hit = i
                else:
                    pd["fp"] += 1
            if hit is not None:
                pd["hit"] += 1
                e = ranges[hit]
                if np.isfinite(e):
                    res["errors"].setdefault(dist, []).append(abs(e - sign["rangeMeters"]) / sign["rangeMeters"])

        grey = cv2.cvtColor(img_u, cv2.COLOR_RGB2GRAY)
        for (p, cc), name in zip(ccs, names):
            if hr:
                g, f = grey, 1.0
            else:
                f = 3.0
                g = cv2.resize(grey, (grey.shape[1] // 3, grey.shape[0] // 3), interpolation=cv2.INTER_AREA)
            rects = cc.detectMultiScale(g, scaleFactor=1.1, minNeighbors=3, minSize=(24, 16))
            boxes, ranges = [], []
            for (x, y, w, h) in (rects if len(rects) else []):
                x0, y0, x1, y1 = x * f, y * f, (x + w) * f, (y + h) * f
                boxes.append((x0, y0, x1, y1))
                ranges.append(range_from_top_bottom((x0 + x1) / 2, y0, y1, intr_u, pitch, h0))
            record(name, boxes, ranges)
        if runner:
            dets = unet_detect(runner, img_u)
            boxes, ranges = [], []
            for d in dets:
                c = d["comp"]
                sc = d["side"] / 224.0
                w, h = c[2] * sc, c[3] * sc
                boxes.append((d["cx"] - w / 2, d["cy"] - h / 2, d["cx"] + w / 2, d["cy"] + h / 2))
                ranges.append(unet_range(d, intr_u, pitch, h0))
            record("unet", boxes, ranges)
        if (k + 1) % 40 == 0:
            log("%d/%d frames (%.0f s)" % (k + 1, len(recs), time.time() - t0))
    # summaries
    summary = {}
    for name, res in results.items():
        rows = {}
        for d in range(2, 10):
            pd = res["per_distance"].get(d, {"n": 0, "hit": 0, "fp": 0})
            errs = res["errors"].get(d, [])
            rows[d] = dict(n=pd["n"], recall=(pd["hit"] / pd["n"] if pd["n"] else float("nan")),
                           median_range_error_pct=(100 * float(np.median(errs)) if errs else float("nan")), fp=pd["fp"])
        summary[name] = dict(per_distance=rows, false_frames=res["false_frames"], empty_frames=res["empty_frames"])
    return summary


def format_table(summary: dict) -> str:
    lines = []
    for name, s in summary.items():
        lines.append("### %s" % name)
        lines.append("| distance (m) | " + " | ".join(str(d) for d in range(2, 10)) + " |")
        lines.append("|---" * 9 + "|")
        pd = s["per_distance"]
        if name != "gt_corners":
            lines.append("| recall | " + " | ".join("%.0f%%" % (100 * pd[d]["recall"]) if pd[d]["n"] else "-" for d in range(2, 10)) + " |")
        lines.append("| median range error | " + " | ".join(("%.1f%%" % pd[d]["median_range_error_pct"]) if np.isfinite(pd[d]["median_range_error_pct"]) else "N/A" for d in range(2, 10)) + " |")
        if name != "gt_corners":
            lines.append("| false detections in sign frames | " + " | ".join(str(pd[d]["fp"]) for d in range(2, 10)) + " |")
            lines.append("")
            lines.append("Sign-free frames with a false detection: %d / %d" % (s["false_frames"], s["empty_frames"]))
        lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Evaluate cascades and the U-Net on a rendered test set.")
    ap.add_argument("--test", required=True)
    ap.add_argument("--cascade", action="append", default=[])
    ap.add_argument("--unet", default=None, help="sign_unet.onnx or a training checkpoint .pt")
    ap.add_argument("--limit", type=int, default=None, help="at most this many frames per distance (5x for sign-free)")
    ap.add_argument("--hr", action="store_true", help="run cascades on the full-resolution unrolled frame (default VGA)")
    ap.add_argument("--json", default=None, help="write the summary here")
    a = ap.parse_args(argv)
    summary = evaluate(a.test, a.cascade, a.unet, a.limit, a.hr, lambda m: print(m, file=sys.stderr, flush=True))
    print(format_table(summary))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
