#!/usr/bin/env python3
"""Measured over labelled face height, per face style: where a detector's range error comes from.

A range from the apparent height is h0 / (measured height in the unrolled image), so a sign measured at a
fraction r of its face's height reads 1 / r too far. This tool reads a rendered test set (render_signs.py
format: labels.jsonl with `cornersRaw` = TL, TR, BR, BL of the upright face in the frame's pixels, and its
`style`) and `wf_detector_eval --dump` output (per matched observation: the median height and centre column in the
detector's unrolled pixels and the unrolled -> raw affine map), maps each labelled face into the unrolled frame
and compares the heights at the measured column. It prints the median ratio per row, per face style (ISO or
US, lit or unlit, plate and letter colours) and per true distance.

The detector's frame may be a resized copy of the test frame (`wf_detector_eval` gives the U-Net rows and
the cascade's 1920 x 1440 rows 1920 x 1440 frames, the VGA cascade rows 640 x 480): labelled corners are scaled
by the row's frame width over the test frame's width (`ROW_FRAME_WIDTH`).

Usage:
  build/cmake/SignDetector/wf_detector_eval --testset DIR --rows unet,unet-rough --dump dump.csv
  python3 height_ratio.py --testset DIR --dump dump.csv

Written by hand (a few lines of geometry on two files no library reads); docs/benchmarks.md "Thirty-second stop".
"""
from __future__ import annotations

import argparse
import collections
import csv
import os
import sys
from typing import Dict, Iterable, List, Optional, Sequence

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from eval_detectors import load_labels  # noqa: E402  (the test set's labels.jsonl reader)

#: Width in pixels of the frame each wf_detector_eval row runs on (its prefix decides; None: the test frame's own).
ROW_FRAME_WIDTH = {"unet": 1920, "unet-native": None, "cascade-hr": 1920, "cascade-vga": 640}


def row_frame_width(row: str) -> Optional[int]:
    """Frame width of a wf_detector_eval row id (suffixes such as -rough, -srgb, -native allowed); None when the row
    runs on the test frame at its own size (unet-native)."""
    for prefix in sorted(ROW_FRAME_WIDTH, key=len, reverse=True):
        if row.startswith(prefix):
            return ROW_FRAME_WIDTH[prefix]
    raise ValueError(f"height_ratio: unknown row {row!r} (known prefixes: {', '.join(sorted(ROW_FRAME_WIDTH))})")


def labelled_height_at_column(corners_raw: Sequence[Sequence[float]], affine_unrolled_to_raw: Sequence[float],
                              column_px: float) -> float:
    """Height in unrolled pixels of the labelled face at unrolled column `column_px`.

    corners_raw: TL, TR, BR, BL of the upright face in the detector's raw frame (pixels).
    affine_unrolled_to_raw: a00, a01, a02, a10, a11, a12 with raw = A [u, v, 1].
    The top edge (TL-TR) and the bottom edge (BL-BR) are mapped into the unrolled frame and read at the column.
    """
    a = np.array([list(affine_unrolled_to_raw[0:3]), list(affine_unrolled_to_raw[3:6]), [0.0, 0.0, 1.0]])
    inv = np.linalg.inv(a)
    c = np.asarray(corners_raw, float)
    u = (inv @ np.c_[c, np.ones(len(c))].T).T[:, :2]

    def at(p, q):
        du = q[0] - p[0]
        if abs(du) < 1e-9:
            raise ValueError("height_ratio: a labelled face edge is vertical in the unrolled frame")
        return p[1] + (column_px - p[0]) / du * (q[1] - p[1])

    return at(u[3], u[2]) - at(u[0], u[1])


def style_key(sign: dict) -> str:
    """'ISO' or 'US' (with plate / letter colours), lit or unlit, from a label's `style`."""
    st = sign.get("style") or {}
    lit = "lit" if st.get("lit") else "unlit"
    if st.get("letter") is None:
        return f"ISO {lit}"
    return f"US {lit}, {st.get('plate')} plate, {st.get('letter')} letters"


def ratios(labels: List[dict], dump_rows: Iterable[Dict[str, str]]) -> Dict[str, list]:
    """Per dump row id: (frame, true range m, style key, measured / labelled height) of every matched observation
    of a frame with one labelled sign (the test frame's width from its label's intrinsics)."""
    out: Dict[str, list] = collections.defaultdict(list)
    for r in dump_rows:
        if r.get("matched") != "1":
            continue
        frame = int(r["frame"])
        signs = labels[frame].get("signs") or []
        if len(signs) != 1:
            continue
        width = row_frame_width(r["row"])
        scale = 1.0 if width is None else width / float(labels[frame]["intrinsics"]["width"])
        corners = np.asarray(signs[0]["cornersRaw"], float) * scale
        affine = [float(r[k]) for k in ("a00", "a01", "a02", "a10", "a11", "a12")]
        h = labelled_height_at_column(corners, affine, float(r["center_px"]))
        if not h > 0:
            continue
        out[r["row"]].append((frame, float(signs[0]["rangeMeters"]), style_key(signs[0]), float(r["height_px"]) / h))
    return out


def report(per_row: Dict[str, list]) -> str:
    """Median ratio per row, per style and per rounded true distance, as Markdown-ish text."""
    lines = []
    for row, items in per_row.items():
        r = np.array([x[3] for x in items])
        q1, q3 = np.percentile(r, [25, 75])
        lines.append(f"{row}: {len(r)} signs, median measured / labelled height {np.median(r):.3f} (IQR {q1:.3f}-{q3:.3f})")
        by_style = collections.defaultdict(list)
        by_distance = collections.defaultdict(list)
        for _, rng, key, ratio in items:
            by_style[key].append(ratio)
            by_distance[int(round(rng))].append(ratio)
        for key in sorted(by_style):
            lines.append(f"  {key:40s} {len(by_style[key]):4d}  {np.median(by_style[key]):.3f}")
        lines.append("  by distance: " + " ".join(f"{d} m {np.median(v):.3f}" for d, v in sorted(by_distance.items())))
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--testset", required=True, help="rendered test set (labels.jsonl)")
    ap.add_argument("--dump", required=True, help="wf_detector_eval --dump CSV")
    a = ap.parse_args(argv)
    try:
        labels = load_labels(a.testset)
        with open(a.dump, newline="") as f:
            rows = list(csv.DictReader(f))
    except (OSError, ValueError) as e:
        print(f"height_ratio: {e}", file=sys.stderr)
        return 1
    try:
        print(report(ratios(labels, rows)))
    except (KeyError, IndexError, ValueError) as e:
        print(f"height_ratio: {a.dump} does not match {a.testset}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
