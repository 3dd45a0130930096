#!/usr/bin/env python3
"""Evaluate the wall-sign-kind cascades (restroom, elevator, stairs, placard) on the held-out split test_kinds.

    python3 render_signs.py --out /work/data/test_kinds --split test_kinds --seed 1234
    python3 eval_kinds.py --test /work/data/test_kinds --models ../models

For each kind K with a cascade (`MODELS/K_cascade.xml`, or `--cascade K=PATH`), every frame is read, turned
grey and unrolled (render_signs.unroll_image with the frame's roll: world up is image up), and scanned with
cv2.CascadeClassifier.detectMultiScale (`--scale` 1.1, `--min-neighbors` 3, smallest window the cascade's).

* recall per distance: frames whose first sign (the one placed at the fixed distance) is of kind K, found
  when a detection has IoU >= 0.4 with the axis-aligned box of that sign's unrolled corners;
* false positives: detections that match (IoU >= 0.4) no labelled sign of kind K, per frame, over all
  frames, over the sign-free frames and over the frames of each other kind; a false positive with IoU >= 0.2
  with a labelled sign of another kind (Exit included) counts as a confusion with that kind;
* time: the mean wall time of detectMultiScale per frame (`--threads` OpenCV threads, default 1).

Prints markdown tables (and writes them with the raw numbers to `--json`).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections import defaultdict

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render_signs as rs  # noqa: E402


def unrolled_box(rec: dict, sign: dict, A: np.ndarray) -> np.ndarray:
    """(x0, y0, x1, y1) of a sign's corners mapped into the unrolled frame by the 2x3 matrix A."""
    c = np.array(sign["cornersRaw"]) @ A[:, :2].T + A[:, 2]
    return np.array([c[:, 0].min(), c[:, 1].min(), c[:, 0].max(), c[:, 1].max()])


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two (x0, y0, x1, y1) boxes."""
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    if w <= 0 or h <= 0:
        return 0.0
    inter = w * h
    return float(inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter))


def load_frames(test_dir: str):
    """[(unrolled grey image, record, [(kind, box)])] of a rendered split."""
    out = []
    for line in open(os.path.join(test_dir, "labels.jsonl")):
        rec = json.loads(line)
        g = cv2.imread(os.path.join(test_dir, rec["image"]), cv2.IMREAD_GRAYSCALE)
        u, A, _ = rs.unroll_image(g, rec["intrinsics"], rec["rollRad"])
        out.append((u, rec, [(s["kind"], unrolled_box(rec, s, A)) for s in rec["signs"]]))
    return out


def evaluate(cc: cv2.CascadeClassifier, kind: str, frames, scale: float, min_neighbors: int,
             match_iou: float = 0.4, confusion_iou: float = 0.2) -> dict:
    """Recall per distance, false positives by frame group and by confused kind, time per frame."""
    win = tuple(int(v) for v in cc.getOriginalWindowSize())
    found = defaultdict(lambda: [0, 0])  # distance -> [hits, signs]
    fp_by_group = defaultdict(lambda: [0, 0])  # frame group -> [false positives, frames]
    confusions = defaultdict(int)
    times = []
    for u, rec, signs in frames:
        t0 = time.perf_counter()
        dets = cc.detectMultiScale(u, scaleFactor=scale, minNeighbors=min_neighbors, minSize=win)
        times.append(time.perf_counter() - t0)
        boxes = [np.array([x, y, x + w, y + h], np.float64) for x, y, w, h in (dets if len(dets) else [])]
        group = signs[0][0] if signs else "sign-free"
        if signs and signs[0][0] == kind:
            d = round(float(rec["signs"][0]["rangeMeters"]), 2)
            found[d][1] += 1
            found[d][0] += int(any(iou(b, signs[0][1]) >= match_iou for b in boxes))
        n_fp = 0
        for b in boxes:
            if any(k == kind and iou(b, sb) >= match_iou for k, sb in signs):
                continue
            n_fp += 1
            others = [(iou(b, sb), k) for k, sb in signs if k != kind]
            best = max(others) if others else (0.0, None)
            if best[0] >= confusion_iou:
                confusions[best[1]] += 1
        fp_by_group[group][0] += n_fp
        fp_by_group[group][1] += 1
    return dict(kind=kind, window=list(win), recall={str(d): v for d, v in sorted(found.items())},
                fp_by_group={g: v for g, v in fp_by_group.items()}, confusions=dict(confusions),
                ms_per_frame=1000.0 * float(np.mean(times)), ms_median=1000.0 * float(np.median(times)),
                n_frames=len(frames))


def markdown(results, frames) -> str:
    """Markdown tables of evaluate() results."""
    L = []
    groups = [("pictograms", [r for r in results if r["kind"] != "placard"]), ("placards", [r for r in results if r["kind"] == "placard"])]
    for name, rs_ in groups:
        if not rs_:
            continue
        dists = sorted({float(d) for r in rs_ for d in r["recall"]})
        L.append("| recall (%s) | %s | all |" % (name, " | ".join("%g m" % d for d in dists)))
        L.append("|---" * (len(dists) + 2) + "|")
        for r in rs_:
            cells, h_all, n_all = [], 0, 0
            for d in dists:
                h, n = r["recall"].get(str(round(d, 2)), [0, 0])
                h_all, n_all = h_all + h, n_all + n
                cells.append("%d/%d (%.0f%%)" % (h, n, 100.0 * h / n) if n else "-")
            L.append("| %s | %s | %.2f |" % (r["kind"], " | ".join(cells), h_all / max(n_all, 1)))
        L.append("")
    kinds_all = ["sign-free"] + [k for k in rs.WALL_KINDS]
    L.append("| cascade | FP / frame (all %d) | sign-free | %s | confusions (detections on another kind's sign) | ms / frame |" %
             (len(frames), " | ".join("%s frames" % k for k in rs.WALL_KINDS)))
    L.append("|---" * (5 + len(rs.WALL_KINDS)) + "|")
    for r in results:
        g = r["fp_by_group"]
        tot_fp = sum(v[0] for v in g.values())
        tot_n = sum(v[1] for v in g.values())
        cells = []
        for k in kinds_all:
            fp, n = g.get(k, [0, 0])
            cells.append("%.2f" % (fp / n) if n else "-")
        conf = ", ".join("%s %d" % (k, r["confusions"][k]) for k in ("exit",) + rs.WALL_KINDS if r["confusions"].get(k)) or "none"
        L.append("| %s | %.2f | %s | %s | %.1f |" % (r["kind"], tot_fp / max(tot_n, 1), " | ".join(cells), conf, r["ms_per_frame"]))
    return "\n".join(L)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--test", default="/work/data/test_kinds", help="rendered test_kinds split")
    ap.add_argument("--models", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models"))
    ap.add_argument("--kinds", default=",".join(rs.WALL_KINDS))
    ap.add_argument("--cascade", action="append", default=[], metavar="KIND=PATH", help="cascade of a kind (overrides --models)")
    ap.add_argument("--scale", type=float, default=1.1)
    ap.add_argument("--min-neighbors", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1, help="OpenCV threads (timing)")
    ap.add_argument("--json", default=None, help="write the results here")
    a = ap.parse_args(argv)
    cv2.setNumThreads(a.threads)
    paths = {k: os.path.join(a.models, "%s_cascade.xml" % k) for k in a.kinds.split(",") if k}
    for c in a.cascade:
        k, p = c.split("=", 1)
        paths[k] = p
    frames = load_frames(a.test)
    results = []
    for k, p in paths.items():
        if not os.path.exists(p):
            print("no cascade for %s (%s)" % (k, p), file=sys.stderr)
            continue
        cc = cv2.CascadeClassifier(p)
        if cc.empty():
            raise RuntimeError("cv2 could not load %s" % p)
        results.append(evaluate(cc, k, frames, a.scale, a.min_neighbors))
    md = markdown(results, frames)
    print("scaleFactor %.2f, minNeighbors %d, %d OpenCV thread(s), %d frames of %s\n" % (a.scale, a.min_neighbors, a.threads, len(frames), a.test))
    print(md)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(results=results, markdown=md, scale=a.scale, min_neighbors=a.min_neighbors, threads=a.threads), f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
