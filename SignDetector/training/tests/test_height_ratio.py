"""height_ratio.py: labelled face heights in the detector's unrolled frame, per-style ratios, bad input."""
import csv
import json
import math
import os
import sys
import tempfile

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import height_ratio as hr  # noqa: E402

IDENTITY = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]


def _rolled(angle_rad, tx, ty):
    """Unrolled -> raw affine of a frame rolled by angle_rad (raw = R u + t)."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return [c, -s, tx, s, c, ty]


def _to_raw(affine, pts):
    a = np.array([affine[0:3], affine[3:6]])
    return [list(a @ [u, v, 1.0]) for u, v in pts]


def test_height_at_a_column_of_a_sloped_face():
    # Top edge from (10, 20) to (50, 22), bottom from (10, 60) to (50, 62): at column 30, 21 and 61.
    corners = [[10, 20], [50, 22], [50, 62], [10, 60]]
    assert hr.labelled_height_at_column(corners, IDENTITY, 30.0) == pytest.approx(40.0)
    assert hr.labelled_height_at_column(corners, IDENTITY, 10.0) == pytest.approx(40.0)


def test_height_is_read_in_the_unrolled_frame_whatever_the_roll():
    unrolled = [[100, 50], [160, 50], [160, 92], [100, 92]]  # an upright face 42 px tall, TL TR BR BL
    for roll in (0.3, math.pi / 2, -math.pi / 2 + 0.1):
        affine = _rolled(roll, 400.0, -30.0)
        raw = _to_raw(affine, unrolled)
        assert hr.labelled_height_at_column(raw, affine, 130.0) == pytest.approx(42.0, abs=1e-9)


def test_row_frame_widths_and_an_unknown_row():
    assert hr.row_frame_width("unet") == 1920
    assert hr.row_frame_width("unet-rough") == 1920
    assert hr.row_frame_width("cascade-vga-srgb") == 640
    assert hr.row_frame_width("cascade-hr-native") == 1920
    assert hr.row_frame_width("unet-native") is None  # the test frame at its own size
    assert hr.row_frame_width("unet-native-rough") is None
    with pytest.raises(ValueError, match="unknown row"):
        hr.row_frame_width("reference")


def _label(corners, style, width=640, range_m=4.0):
    return {"intrinsics": {"width": width}, "signs": [{"cornersRaw": corners, "rangeMeters": range_m, "style": style}]}


def test_ratios_scale_vga_labels_to_the_rows_frame_and_group_by_style():
    lit_us = {"letter": "red", "plate": "dark", "lit": True}
    iso = {"letter": None, "lit": False}
    labels = [_label([[10, 20], [50, 20], [50, 40], [10, 40]], lit_us),  # 20 px at VGA, 60 px at 1920
              _label([[10, 20], [50, 20], [50, 40], [10, 40]], iso, range_m=7.2),
              {"intrinsics": {"width": 640}, "signs": []}]
    base = {"a00": 1, "a01": 0, "a02": 0, "a10": 0, "a11": 1, "a12": 0, "center_px": 90}
    rows = [dict(base, row="unet", frame=0, matched="1", height_px=48),      # 0.8 of 60
            dict(base, row="unet", frame=1, matched="1", height_px=63),      # 1.05 of 60
            dict(base, row="cascade-vga", frame=0, matched="1", height_px=22, center_px=30),  # 1.1 of 20
            dict(base, row="unet", frame=1, matched="0", height_px=10),      # a false positive: ignored
            dict(base, row="unet", frame=2, matched="1", height_px=10)]      # no labelled sign: ignored
    rows = [{k: str(v) for k, v in r.items()} for r in rows]
    out = hr.ratios(labels, rows)
    assert sorted(out) == ["cascade-vga", "unet"]
    unet = {frame: (key, ratio) for frame, _, key, ratio in out["unet"]}
    assert unet[0] == ("US lit, dark plate, red letters", pytest.approx(0.8))
    assert unet[1] == ("ISO unlit", pytest.approx(1.05))
    assert out["cascade-vga"][0][3] == pytest.approx(1.1)
    text = hr.report(out)
    assert "unet: 2 signs" in text and "by distance: 4 m 0.800 7 m 1.050" in text


def test_main_names_the_missing_file_and_a_mismatched_dump():
    with tempfile.TemporaryDirectory() as d:
        assert hr.main(["--testset", d, "--dump", os.path.join(d, "none.csv")]) == 1
        with open(os.path.join(d, "labels.jsonl"), "w") as f:
            f.write(json.dumps(_label([[10, 20], [50, 20], [50, 40], [10, 40]], {"letter": None})) + "\n")
        dump = os.path.join(d, "dump.csv")
        with open(dump, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["row", "frame", "matched", "height_px", "center_px", "a00", "a01", "a02", "a10", "a11", "a12"])
            w.writerow(["unet", 5, 1, 10, 30, 1, 0, 0, 0, 1, 0])  # frame 5 is not in the test set
        assert hr.main(["--testset", d, "--dump", dump]) == 1
