"""Phone style of the renderer (phone_camera.py, render_signs phone=...): the rolling shutter shifts
each row by the rotation during its read-out time, the image and the labels move together, labels
stay exact under oblique views, auto exposure saturates LED faces in dim corridors, the glare PSF
conserves energy, the held-out set is deterministic per seed, and the classic fixed test set is
unchanged."""
import hashlib
import json
import math
import os
import sys
import tempfile

import cv2
import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import eval_detectors as ev  # noqa: E402
import phone_camera as pc  # noqa: E402
import render_signs as rs  # noqa: E402


def _still_phone(R, intr, **kw):
    """A PhoneCamera without motion, blur, glare, gloss or compression, overridable by kw."""
    p = pc.PhoneCamera(omega_world_rad_s=np.zeros(3), exposure_s=1e-4, readout_s=0.0, sensor_R=R, sensor_intr=intr,
                       glare_core=0.0, glare_tail=0.0, noise_sigma=0.0, jpeg_quality=0, gloss=0.0, ev_bias=0.0)
    for k, v in kw.items():
        setattr(p, k, v)
    return p


def _readout_t(p, intr, v):
    return p.readout_sign * p.readout_s * (v - (intr["height"] - 1) / 2.0) / intr["height"]


def test_rolling_shutter_shifts_rows_by_yaw_rate_times_row_time():
    # Pure yaw about the camera's y axis at w rad/s: a point on the optical column is seen in the row
    # read at time t shifted by fx tan(w t) (ray [0, y, -1] rotated about y keeps its y and depth).
    intr = rs.RAW_INTRINSICS.copy()
    R = rs.camera_rotation(0.3, 0.1, 0.0)
    w = 0.8
    p = _still_phone(R, intr, omega_world_rad_s=R @ np.array([0.0, w, 0.0]), readout_s=0.03)
    ref = np.array([[intr["cx"], v] for v in (20.0, 400.0, 720.0, 1100.0, 1420.0)])
    rsp = pc.rolling_shutter_points(p, R, intr, ref)
    for (u0, _), (u1, v1) in zip(ref, rsp):
        expected = intr["fx"] * math.tan(w * _readout_t(p, intr, v1))
        assert abs((u1 - u0) - expected) < 1e-3, (u1 - u0, expected)
    # the skew across the frame is fx w readout (about 38 px here): first and last rows differ by it
    assert abs((rsp[-1, 0] - rsp[0, 0]) - intr["fx"] * w * 0.03 * (1400 / 1440)) < 1.0


def test_rolling_shutter_image_and_corner_labels_agree():
    # A vertical bright line in the reference image must appear, in every row of the remapped image,
    # where rolling_shutter_points puts it: image and labels use the same model, in the same direction.
    intr = rs.scaled_intrinsics(640, 480)
    R = rs.camera_rotation(0.0, 0.0, 0.0)
    p = _still_phone(R, intr, omega_world_rad_s=np.array([0.1, -0.9, 0.2]), readout_s=0.033, readout_sign=-1.0)
    img = np.zeros((480, 640, 3), np.float32)
    img[:, 300:303] = 1.0  # centre column 301
    out, _ = pc.apply_motion(p, R, intr, img, np.zeros((480, 640), np.uint8))
    for v in (40, 160, 240, 320, 440):
        row = out[v, :, 0]
        u_img = float((row * np.arange(640)).sum() / row.sum())
        # the reference point of this output row: solve with the point mapper from a reference guess
        cand = pc.rolling_shutter_points(p, R, intr, np.array([[301.0, float(v)]]))
        # rows shift a little vertically too (roll, pitch); compare the line's column at the row it lands in
        mu, mv = pc.shutter_map(p, R, intr, 0.0)
        assert abs(mu[v, int(round(u_img))] - 301.0) < 0.6, (v, u_img, mu[v, int(round(u_img))])
        assert abs(cand[0, 0] - u_img) < 2.0, (cand, u_img)


def test_dense_shutter_map_matches_exact_map():
    intr = rs.RAW_INTRINSICS.copy()
    R = rs.camera_rotation(1.0, 0.3, -1.5)
    p = _still_phone(R, intr, omega_world_rad_s=np.array([0.4, 1.2, -0.3]), readout_s=0.033)
    fu, fv = pc.dense_shutter_map(p, R, intr, 0.01)
    mu, mv = pc.shutter_map(p, R, intr, 0.01)
    assert np.abs(fu - mu).max() < 0.02 and np.abs(fv - mv).max() < 0.02


def _render_phone_sign(seed, off_axis_rad, distance_m, intr, omega_cam, illuminance=1.0, lit=None, tone_curve="srgb"):
    rng = np.random.default_rng(seed)
    yaw, pitch, roll = 0.4, 0.2, -math.pi / 2 + 0.05
    R = rs.camera_rotation(yaw, pitch, roll)
    t = np.array([0.0, 1.4, 0.0])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    hdir = np.array([-math.sin(yaw), 0.0, -math.cos(yaw)])
    center = t + distance_m * hdir
    center[1] = 2.3
    normal = rs.rot_y(off_axis_rad) @ (-hdir)
    style = dict(letter="red", plate="white", chevron="none", border=False)
    if lit is not None:
        style["lit"] = lit
    spec = rs.SignSpec(center_cam=R.T @ (center - t), normal_cam=R.T @ normal, width_m=0.30, height_m=0.21, style=style)
    p = _still_phone(R, intr, omega_world_rad_s=R @ np.asarray(omega_cam, float), readout_s=0.03, illuminance=illuminance)
    p.tone_curve = tone_curve
    img, mask, labels = rs.render_frame(T, intr, [spec], rng, n_distractors=0, occlusion_prob=0.0, background="corridor", phone=p)
    return T, p, img, mask, labels


def _mask_poly_iou(mask, corners):
    poly = np.zeros_like(mask)
    cv2.fillConvexPoly(poly, np.round(np.asarray(corners) * 16).astype(np.int32), 1, cv2.LINE_8, 4)
    return ((mask == 1) & (poly == 1)).sum() / max(((mask == 1) | (poly == 1)).sum(), 1)


def test_labels_exact_under_oblique_views_and_rolling_shutter():
    intr = rs.RAW_INTRINSICS.copy()
    for off in (0.0, 0.9, -1.1):  # up to 63 degrees off axis
        # still camera: the mask is the face's coverage and the corners give the true range
        T, p, img, mask, labels = _render_phone_sign(1, off, 3.0, intr, [0, 0, 0])
        s = labels[0]
        assert _mask_poly_iou(mask, s["cornersRaw"]) > 0.95
        A, intr_u = rs.unroll_matrix(intr, math.atan2(T[1, 0], T[1, 1]))
        gt = np.array(s["cornersRaw"]) @ A[:, :2].T + A[:, 2]
        top, bot = (gt[0] + gt[1]) / 2, (gt[3] + gt[2]) / 2
        pitch = math.asin(-T[1, 2])
        z = ev.range_from_top_bottom(top[0], top[1], bot[1], intr_u, pitch, 0.21, u_bottom=bot[0])
        assert abs(z - s["rangeMeters"]) / s["rangeMeters"] < 0.005
        # rotating camera: the mask and the labelled corners move together
        _, _, _, mask2, labels2 = _render_phone_sign(1, off, 3.0, intr, [0.2, 0.9, 0.1])
        shift = np.abs(np.array(labels2[0]["cornersRaw"]) - np.array(s["cornersRaw"])).max()
        assert shift > 1.0  # the rolling shutter really moved the sign (it sits near the middle row)
        assert _mask_poly_iou(mask2, labels2[0]["cornersRaw"]) > 0.93


def test_auto_exposure_saturates_lit_face_in_dim_corridor():
    intr = rs.scaled_intrinsics(640, 480)
    for tone, margin in (("linear", 0.05), ("srgb", 0.03)):
        sat = {}
        for illum in (0.25, 1.4):
            _, p, img, mask, _ = _render_phone_sign(3, 0.2, 2.5, intr, [0, 0, 0], illuminance=illum, lit=True,
                                                    tone_curve=tone)
            red = img[..., 0][mask == 1]
            sat[illum] = float((red >= 250).mean())
        # the LED's radiance does not scale with the corridor light, the exposure does (inversely); the tone
        # curve leaves about 2.5 stops of headroom above the metered mean (1.3 without it), so fewer pixels clip
        assert sat[0.25] > sat[1.4] + margin and sat[0.25] > 0.1, (tone, sat)
    dim = pc.PhoneCamera(np.zeros(3), 0.01, 0.0, np.eye(3), intr, ev_bias=0.0, tone_curve="linear")
    scene = np.full((48, 64, 3), 0.2, np.float32)
    assert abs(pc.auto_exposure(dim, scene) - dim.ae_target / 0.2) < 1e-3
    assert pc.auto_exposure(dim, scene * 0.001) == dim.exposure_max
    # With the tone curve (the default) the AE target is a display value: the metered mean comes out at it.
    srgb = pc.PhoneCamera(np.zeros(3), 0.01, 0.0, np.eye(3), intr, ev_bias=0.0)
    assert srgb.tone_curve == "srgb"
    shown = pc.tone_map(srgb, scene * pc.auto_exposure(srgb, scene))
    assert np.allclose(shown, srgb.ae_target, atol=1e-4)


def test_tone_curve_is_the_srgb_transfer_function():
    light = np.array([0.0, 0.0031308, 0.18, 0.5, 1.0, 1.7], np.float32)
    shown = pc.srgb_encode(light)
    # IEC 61966-2-1: the linear toe meets the power segment at 0.0031308 -> 0.04045; 18 % grey shows at 0.461.
    assert np.allclose(shown, [0.0, 0.04045, 0.4614, 0.7354, 1.0, 1.0], atol=2e-4), shown
    assert np.allclose(pc.srgb_decode(shown[:5]), light[:5], atol=1e-5)
    assert np.all(np.diff(pc.srgb_encode(np.linspace(0, 1, 1001, dtype=np.float32))) > 0)  # monotonic
    p = pc.PhoneCamera(np.zeros(3), 0.01, 0.0, np.eye(3), rs.RAW_INTRINSICS, tone_curve="linear")
    assert np.array_equal(pc.tone_map(p, light), light)
    p.tone_curve = "gamma"
    with pytest.raises(ValueError, match="tone_curve"):
        pc.tone_map(p, light)


def test_glare_conserves_energy_and_halo_decays():
    p = pc.PhoneCamera(np.zeros(3), 0.01, 0.0, np.eye(3), rs.RAW_INTRINSICS, glare_core=0.05, glare_tail=0.02,
                       glare_core_px=4.0, glare_tail_px=60.0)
    img = np.zeros((401, 401, 3), np.float32)
    img[195:206, 195:206] = 10.0  # a saturated LED letter stroke
    out = pc.glare(p, img, 1.0)
    assert abs(out.sum() / img.sum() - 1.0) < 0.02
    prof = out[200, 206:400, 0]
    assert np.all(np.diff(prof[:150]) <= 1e-6)  # monotonic fall-off away from the source
    assert 0.01 < prof[5] < 0.05 * 10.0  # visible halo next to it, far weaker than the source


def test_saturation_spills_into_other_channels():
    p = pc.PhoneCamera(np.zeros(3), 0.01, 0.0, np.eye(3), rs.RAW_INTRINSICS, spill=0.3)
    out = pc.saturate(p, np.array([[[3.0, 0.1, 0.1], [0.5, 0.2, 0.1]]], np.float32))
    assert np.allclose(out[0, 0], [1.0, 0.7, 0.7], atol=1e-6)  # over-exposed red turns pink-white
    assert np.allclose(out[0, 1], [0.5, 0.2, 0.1], atol=1e-6)  # unsaturated pixels untouched


def test_fiducial_marker_is_black_and_white_with_black_border():
    tex, w, h = rs.make_fiducial_texture(np.random.default_rng(4))
    rgb = tex.rgb
    assert w == h and 0.1 <= w <= 0.3
    vals = np.unique(rgb)
    assert len(vals) == 2 and abs(vals[0] - 15 / 255) < 1e-6 and abs(vals[1] - 245 / 255) < 1e-6
    px = rgb.shape[0] // ((rgb.shape[0] // 12))
    assert rgb[px + 2, px + 2:-px - 2].max() < 0.1  # black border row inside the white quiet zone
    assert rgb[2, :].min() > 0.9


def _render_to_bytes(split, seed, **kw):
    with tempfile.TemporaryDirectory() as d:
        rs.render_dataset(d, split, seed, verbose=False, **kw)
        h = hashlib.sha256()
        for f in sorted(os.listdir(d)):
            if f.endswith(".png"):
                h.update(cv2.imread(os.path.join(d, f), cv2.IMREAD_UNCHANGED).tobytes())
        labels = open(os.path.join(d, "labels.jsonl")).read()
        h.update(labels.encode())
        return h.hexdigest(), [json.loads(l) for l in labels.splitlines()]


def test_test_phone_split_is_deterministic_and_covers_the_effects():
    a, recs = _render_to_bytes("test_phone", 1234, n_per_distance=1, n_empty=1, resolution="vga", jpeg=False)
    b, _ = _render_to_bytes("test_phone", 1234, n_per_distance=1, n_empty=1, resolution="vga", jpeg=False)
    c, _ = _render_to_bytes("test_phone", 1235, n_per_distance=1, n_empty=1, resolution="vga", jpeg=False)
    assert a == b and a != c
    assert len(recs) == 9 and recs[-1]["signs"] == []
    for r in recs:
        assert r["phone"]["readoutSeconds"] != 0 and r["phone"]["exposureSeconds"] > 0
    for i, r in enumerate(recs[:-1]):
        assert abs(r["signs"][0]["rangeMeters"] - (2 + i)) < 1e-9


def test_portrait360_frames_are_upright_with_column_readout():
    intr, upright = rs.frame_intrinsics("portrait360", 0)
    assert (intr["width"], intr["height"]) == (360, 640) and upright
    rng = rs.frame_rng(1, "test_phone", 0)
    T, signs, info = rs.sample_scene(rng, intr, 4.0, test=True, phone=True, upright=True)
    assert abs(info["roll"]) < math.radians(40)
    p = pc.sample_phone_camera(rng, T[:3, :3], intr, readout_axis="u")
    t_left = pc.readout_time(p, T[:3, :3], intr, np.array([0.0]), np.array([320.0]))
    t_right = pc.readout_time(p, T[:3, :3], intr, np.array([359.0]), np.array([320.0]))
    t_top = pc.readout_time(p, T[:3, :3], intr, np.array([179.5]), np.array([0.0]))  # the middle column
    assert abs(abs(t_right - t_left)[0] - p.readout_s * 359 / 360) < 1e-9 and abs(t_top[0]) < 1e-9


def test_classic_fixed_test_set_is_unchanged():
    # sha256 of the classic test split rendered before the phone style existed (VGA, PNG, 10 frames):
    # the phone style must not change what `--split test --seed 1234` produces. Depends on the
    # installed OpenCV and numpy (text drawing, resizing, the generator).
    digest, _ = _render_to_bytes("test", 1234, n_per_distance=1, n_empty=2, resolution="vga", jpeg=False)
    assert digest == "b32c744b838b7e5fae60c65a460aa88e5d67dd8e9a18600789cac958d5d7e29d"
