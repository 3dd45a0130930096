"""Training samples rendered directly at virtual cameras (roll-corrected views, zoomed crops).

Cropping a roll-corrected ("unrolled") frame is the same as viewing the scene with a virtual pinhole
camera that has the raw camera's centre, yaw and pitch, roll 0 and shifted/scaled intrinsics. The
renderer is geometric (ray-cast scene, projected planar signs), so every crop is rendered directly
at that virtual camera rather than cut out of a full raw frame: the same samples at a fraction of
the cost. Crops whose raw pixels would be enlarged are rendered at raw resolution and up-sampled, as
the run-time detector sees them.

The run-time pre-processing these samples assume (the C++ detector must match it):
  * unroll: rotate the raw frame about the principal point so that world up is image up
    (render_signs.unroll_matrix);
  * coarse U-Net pass: the whole unrolled frame, aspect kept, resized so that its longer side is
    224, centred in a 224 x 224 input, padding 0 (black);
  * zoom U-Net pass: a square crop of the unrolled frame centred on a coarse detection, side 3.5 x
    the detected sign width (trained on 2.5..5 x), resized to 224 x 224, outside the frame 0;
  * cascade: grey-scale unrolled frame; windows 24 x 16 cover the sign face with about 10 % margin
    (Exit); the wall sign kinds' cascades use square 20 x 20 windows, side 1.1 x the face's larger
    projected extent (kind_window).
"""
from __future__ import annotations

import math
from typing import List, Optional, Tuple

import cv2
import numpy as np

import render_signs as rs


def _virtual(T_raw: np.ndarray, residual_roll: float) -> np.ndarray:
    """Camera-to-world of the roll-corrected virtual camera (plus an optional residual roll)."""
    R = T_raw[:3, :3]
    # ARKit Euler angles of R: pitch = asin(R[2,1]) ... we only need yaw and pitch of the optical axis.
    fwd = -R[:, 2]
    pitch = math.asin(max(-1.0, min(1.0, fwd[1])))
    yaw = math.atan2(-fwd[0], -fwd[2])
    T = np.eye(4)
    T[:3, :3] = rs.camera_rotation(yaw, pitch, residual_roll)
    T[:3, 3] = T_raw[:3, 3]
    return T


def _signs_to(T_from: np.ndarray, T_to: np.ndarray, signs: List[rs.SignSpec]) -> List[rs.SignSpec]:
    """Re-express signs given in camera `T_from` coordinates in camera `T_to` coordinates."""
    out = []
    for s in signs:
        cw = T_from[:3, :3] @ s.center_cam + T_from[:3, 3]
        nw = T_from[:3, :3] @ s.normal_cam
        out.append(rs.SignSpec(center_cam=T_to[:3, :3].T @ (cw - T_to[:3, 3]), normal_cam=T_to[:3, :3].T @ nw,
                               width_m=s.width_m, height_m=s.height_m, kind=s.kind, style=s.style, iso=s.iso))
    return out


def unrolled_intrinsics(intr_raw: dict, T_raw: np.ndarray) -> dict:
    """Intrinsics of the unrolled full frame for a raw camera pose."""
    R = T_raw[:3, :3]
    # roll as ARKit reports it: angle of camera x about the optical axis relative to level
    roll = math.atan2(R[1, 0], R[1, 1]) if abs(R[1, 2]) < 0.999 else 0.0
    return rs.unroll_matrix(intr_raw, roll)[1]


def sign_box_unrolled(T_virtual: np.ndarray, intr_u: dict, sign: rs.SignSpec, T_cam: np.ndarray) -> Tuple[np.ndarray, float, float]:
    """Projected corners (4,2), width and height in pixels of a sign in the virtual camera's image."""
    cw = T_cam[:3, :3] @ sign.center_cam + T_cam[:3, 3]
    nw = T_cam[:3, :3] @ sign.normal_cam
    corners_w = rs.quad_corners_world(cw, nw, sign.width_m, sign.height_m)
    uv, _ = rs.project_points(corners_w, T_virtual[:3, :3], T_virtual[:3, 3], intr_u)
    w = float(uv[:, 0].max() - uv[:, 0].min())
    h = float(uv[:, 1].max() - uv[:, 1].min())
    return uv, w, h


def render_view(rng: np.random.Generator, T_raw: np.ndarray, signs_raw: List[rs.SignSpec], intr_u: dict,
                x0: float, y0: float, side_w: float, side_h: float, out_w: int, out_h: int,
                residual_roll: float = 0.0, degrade_unit: float = 1.0, **kw) -> Tuple[np.ndarray, np.ndarray, List[dict]]:
    """Render the window [x0, x0+side_w) x [y0, y0+side_h) of the unrolled frame at out_w x out_h.

    Rendered at min(out, window) resolution and resized up when the window is smaller than the
    output (so enlarged crops look like enlarged raw pixels). degrade_unit: raw (1920-wide) pixels per
    pixel of the source sensor's unrolled frame, inverted (1 for the 1920 x 1440 sensor, 1/3 for a
    640 x 480 one), so that blur sizes drawn in raw pixels keep their angular size.
    """
    Tv = _virtual(T_raw, residual_roll)
    rw, rh = min(out_w, int(math.ceil(side_w))), min(out_h, int(math.ceil(side_h)))
    rw, rh = max(rw, 8), max(rh, 8)
    sx, sy = rw / side_w, rh / side_h
    intr = dict(fx=intr_u["fx"] * sx, fy=intr_u["fy"] * sy, cx=(intr_u["cx"] - x0) * sx, cy=(intr_u["cy"] - y0) * sy,
                width=rw, height=rh)
    signs_v = _signs_to(T_raw, Tv, signs_raw)
    img, mask, labels = rs.render_frame(Tv, intr, signs_v, rng, degrade_scale=sx * degrade_unit, **kw)
    if (rw, rh) != (out_w, out_h):
        img = cv2.resize(img, (out_w, out_h), interpolation=cv2.INTER_LINEAR)
        mask = cv2.resize(mask, (out_w, out_h), interpolation=cv2.INTER_NEAREST)
    return img, mask, labels


def letterbox_params(w: int, h: int, size: int = 224) -> Tuple[float, int, int, int, int]:
    """(scale, new_w, new_h, pad_x, pad_y) to fit a w x h image centred in size x size."""
    s = size / max(w, h)
    nw, nh = int(round(w * s)), int(round(h * s))
    return s, nw, nh, (size - nw) // 2, (size - nh) // 2


def letterbox(img: np.ndarray, size: int = 224, interp=cv2.INTER_AREA) -> Tuple[np.ndarray, Tuple[float, int, int]]:
    """Resize keeping aspect into size x size with zero padding; returns (image, (scale, pad_x, pad_y))."""
    h, w = img.shape[:2]
    s, nw, nh, px, py = letterbox_params(w, h, size)
    out = np.zeros((size, size) + img.shape[2:], img.dtype)
    out[py:py + nh, px:px + nw] = cv2.resize(img, (nw, nh), interpolation=interp)
    return out, (s, px, py)


def phone_sensor(rng: np.random.Generator) -> dict:
    """Sensor of a phone-style sample: 1920 x 1440 (50 %) or 640 x 480 at fx 534 px, the pixel
    density of the 360 x 640 real test photos (50 %)."""
    return rs.RAW_INTRINSICS.copy() if rng.random() < 0.5 else rs.scaled_intrinsics(640, 480)


def _scene(rng: np.random.Generator, with_sign: bool, phone: bool):
    """(T, signs, sensor intrinsics, PhoneCamera or None) of one sample's source frame."""
    import phone_camera as pc
    if not phone:
        intr_raw = rs.RAW_INTRINSICS
        if with_sign:
            T, signs, _ = rs.sample_scene(rng, intr_raw)
        else:
            T, _ = rs.sample_empty(rng)
            signs = []
        return T, signs, intr_raw, None
    intr_raw = phone_sensor(rng)
    if with_sign:
        T, signs, _ = rs.sample_scene(rng, intr_raw, phone=True)
    else:
        T, _ = rs.sample_empty(rng, phone=True)
        signs = []
    return T, signs, intr_raw, pc.sample_phone_camera(rng, T[:3, :3], intr_raw)


def coarse_sample(rng: np.random.Generator, with_sign: bool, size: int = 224, phone: bool = False) -> Tuple[np.ndarray, np.ndarray]:
    """Whole unrolled frame letterboxed to size x size (image RGB uint8, mask uint8).
    phone: phone-style source frame (render_signs phone style, sensor from phone_sensor)."""
    T, signs, intr_raw, ph = _scene(rng, with_sign, phone)
    kw = dict(phone=ph) if ph is not None else {}
    return _letterboxed(rng, T, signs, intr_raw, size, **kw)


def _letterboxed(rng: np.random.Generator, T: np.ndarray, signs, intr_raw: dict, size: int,
                 **kw) -> Tuple[np.ndarray, np.ndarray]:
    """The unrolled frame of camera T (sensor intr_raw) letterboxed to size x size: (image, mask)."""
    intr_u = unrolled_intrinsics(intr_raw, T)
    s, nw, nh, px, py = letterbox_params(intr_u["width"], intr_u["height"], size)
    # render the letterboxed area at 2x then area-downsample (as a resize of the full frame would)
    img, mask, _ = render_view(rng, T, signs, intr_u, 0, 0, intr_u["width"], intr_u["height"], 2 * nw, 2 * nh,
                               residual_roll=math.radians(rng.normal(0, 2)), **kw)
    img = cv2.resize(img, (nw, nh), interpolation=cv2.INTER_AREA)
    mask = cv2.resize(mask, (nw, nh), interpolation=cv2.INTER_NEAREST)
    out = np.zeros((size, size, 3), np.uint8)
    outm = np.zeros((size, size), np.uint8)
    out[py:py + nh, px:px + nw] = img
    outm[py:py + nh, px:px + nw] = mask
    return out, outm


def kind_sample(rng: np.random.Generator, kind: str, zoom: bool, size: int = 224) -> Tuple[np.ndarray, np.ndarray]:
    """A U-Net training sample of a wall sign kind (one of rs.WALL_KINDS), mask classes rs.CLASSES: the whole
    unrolled frame letterboxed to size x size (zoom False, as coarse_sample), or a square crop centred (with
    jitter N(0, 0.12) of the side) on the kind's face, side 2.5-5 x its larger projected side (zoom True: the
    run-time zoom crops zoomFactor x max(blob width, height) of a square face). The scene is
    rs.sample_kind_scene's (ranges rs.KIND_RANGE_M, a second wall sign of another kind 30 %, an Exit sign
    across the corridor 30 %, the usual distractors), from a 1920 x 1440 or the phone's 640 x 480 sensor
    (_cascade_sensor, blur sizes kept at their angular size)."""
    intr_raw = _cascade_sensor(rng)
    T, signs, _ = rs.sample_kind_scene(rng, intr_raw, kind, extra_kinds=[k for k in rs.WALL_KINDS if k != kind])
    unit = intr_raw["width"] / rs.RAW_INTRINSICS["width"]
    if not zoom:
        return _letterboxed(rng, T, signs, intr_raw, size, degrade_unit=unit)
    intr_u = unrolled_intrinsics(intr_raw, T)
    uv, w, h = sign_box_unrolled(_virtual(T, 0.0), intr_u, signs[0], T)
    side = rng.uniform(2.5, 5.0) * max(w, h)
    c = uv.mean(axis=0) + rng.normal(0, 0.12, 2) * side
    img, mask, _ = render_view(rng, T, signs, intr_u, c[0] - side / 2, c[1] - side / 2, side, side, size, size,
                               residual_roll=math.radians(rng.normal(0, 2)), degrade_unit=unit)
    return img, mask


def zoom_sample(rng: np.random.Generator, positive: bool, size: int = 224, phone: bool = False) -> Tuple[np.ndarray, np.ndarray]:
    """Square crop of the unrolled frame centred (with jitter) on a sign (positive) or on a
    distractor / random spot (negative), side 2.5..5 x the object's width, resized to size.
    phone: phone-style source frame."""
    T, signs, intr_raw, ph = _scene(rng, True, phone)
    kw = dict(phone=ph) if ph is not None else {}
    intr_u = unrolled_intrinsics(intr_raw, T)
    Tv = _virtual(T, 0.0)
    uv, w, h = sign_box_unrolled(Tv, intr_u, signs[0], T)
    if not positive:
        if rng.random() < 0.7:
            signs = [rs.SignSpec(center_cam=signs[0].center_cam, normal_cam=signs[0].normal_cam, width_m=signs[0].width_m,
                                 height_m=signs[0].height_m, kind="distractor")]
        else:
            signs = []
    k = rng.uniform(2.5, 5.0)
    side = k * max(w, 1.5 * h)
    c = uv.mean(axis=0) + rng.normal(0, 0.12, 2) * side
    img, mask, _ = render_view(rng, T, signs, intr_u, c[0] - side / 2, c[1] - side / 2, side, side, size, size,
                               residual_roll=math.radians(rng.normal(0, 2)), **kw)
    return img, mask


def cascade_positive(rng: np.random.Generator, win=(24, 16)) -> np.ndarray:
    """Grey 24 x 16 window around a sign face (10 % margin, small jitter), rendered at 2x and area-downsampled."""
    intr_raw = rs.RAW_INTRINSICS
    T, signs, _ = rs.sample_scene(rng, intr_raw)
    intr_u = unrolled_intrinsics(intr_raw, T)
    Tv = _virtual(T, 0.0)
    uv, w, h = sign_box_unrolled(Tv, intr_u, signs[0], T)
    ww = max(w, 1.5 * h) * 1.1 * math.exp(rng.normal(0, 0.05))
    wh = ww / 1.5
    c = uv.mean(axis=0) + rng.normal(0, 0.03, 2) * np.array([ww, wh])
    img, _, _ = render_view(rng, T, signs, intr_u, c[0] - ww / 2, c[1] - wh / 2, ww, wh, 2 * win[0], 2 * win[1],
                            residual_roll=math.radians(rng.normal(0, 1.5)), occlusion_prob=0.05)
    g = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
    return cv2.resize(g, win, interpolation=cv2.INTER_AREA)


def imap_in_processes(fn, jobs, workers: int = 1, chunksize: int = 8):
    """fn(job) for each job, in order, in `workers` forked processes (1: in this one). The training sets render
    each sample from its own generator, so their samples do not depend on `workers`."""
    if workers <= 1 or len(jobs) < 2:
        yield from map(fn, jobs)
        return
    import multiprocessing as mp
    with mp.get_context("fork").Pool(workers) as pool:
        yield from pool.imap(fn, jobs, chunksize=chunksize)


def _phone_frame_vga(rng: np.random.Generator, with_sign: bool, width: int = 640, **kw):
    """A phone-style source frame (_scene, phone=True) unrolled and rendered whole with its long side `width`, as
    the cascade searches it (auto exposure meters the whole frame, so a lit face is exposed as in the frame, not as
    in a crop around it): (grey image, T, signs, unrolled intrinsics, scale from unrolled to rendered pixels)."""
    T, signs, intr_raw, ph = _scene(rng, with_sign, True)
    intr_u = unrolled_intrinsics(intr_raw, T)
    s = width / max(intr_u["width"], intr_u["height"])
    ow, oh = int(round(intr_u["width"] * s)), int(round(intr_u["height"] * s))
    img, _, _ = render_view(rng, T, signs, intr_u, 0, 0, intr_u["width"], intr_u["height"], ow, oh, phone=ph, **kw)
    return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY), T, signs, intr_u, s


def cascade_positive_phone(rng: np.random.Generator, win=(24, 16)) -> np.ndarray:
    """Grey win[0] x win[1] window around an Exit face (US text or ISO running man) of a phone-style frame
    (render_signs phone style: LED faces, auto exposure, rolling shutter, walking blur, glare, glossy floor; the
    1920 x 1440 or the 640 x 480 sensor, phone_sensor), cut from the whole unrolled frame rendered at VGA scale
    (_phone_frame_vga) with cascade_positive's framing (window width 1.1 x max(face width, 1.5 x face height),
    scale jitter exp(N(0, 0.05)), centre jitter N(0, 0.03) of the window), but never smaller than the window the
    cascade searches (win[0] px wide: a far face fills less of it, as at run time), area-resized to win."""
    g, T, signs, intr_u, s = _phone_frame_vga(rng, True, residual_roll=math.radians(rng.normal(0, 1.5)))
    uv, w, h = sign_box_unrolled(_virtual(T, 0.0), intr_u, signs[0], T)
    ww = max(float(win[0]), max(w, 1.5 * h) * s * 1.1 * math.exp(rng.normal(0, 0.05)))
    wh = ww * win[1] / win[0]
    c = uv.mean(axis=0) * s + rng.normal(0, 0.03, 2) * np.array([ww, wh])
    size = (int(round(ww)), int(round(wh)))
    crop = cv2.getRectSubPix(g, size, (float(c[0]), float(c[1])))
    return cv2.resize(crop, win, interpolation=cv2.INTER_AREA)


def negative_frame_phone(rng: np.random.Generator, width: int = 640) -> np.ndarray:
    """Grey unrolled sign-free phone-style frame (its clutter: posters, ceiling lights, fiducial markers, doors,
    glossy floors) at VGA scale (long side `width`), 2-9 distractors."""
    return _phone_frame_vga(rng, False, width, n_distractors=int(rng.integers(2, 10)))[0]


def negative_frame(rng: np.random.Generator, width: int = 640) -> np.ndarray:
    """Grey unrolled sign-free frame at VGA-like scale (longer side = width), many distractors."""
    intr_raw = rs.RAW_INTRINSICS
    T, _ = rs.sample_empty(rng)
    intr_u = unrolled_intrinsics(intr_raw, T)
    s = width / max(intr_u["width"], intr_u["height"])
    ow, oh = int(round(intr_u["width"] * s)), int(round(intr_u["height"] * s))
    img, _, _ = render_view(rng, T, [], intr_u, 0, 0, intr_u["width"], intr_u["height"], ow, oh,
                            n_distractors=int(rng.integers(2, 10)))
    return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)


# --------------------------------------------------------------------------------------------------
# Cascade samples of the wall sign kinds (restroom, elevator, stairs, placard) and their negatives
# --------------------------------------------------------------------------------------------------

def _cascade_sensor(rng: np.random.Generator) -> dict:
    """Sensor of a wall-kind cascade sample: 1920 x 1440 (50 %) or the 640 x 480 frame the phone sends the
    cascade (fx 534 px; 50 %)."""
    return rs.RAW_INTRINSICS.copy() if rng.random() < 0.5 else rs.scaled_intrinsics(640, 480)


def kind_window(rng: np.random.Generator, kind: str, win: Tuple[int, int] = (20, 20)) -> np.ndarray:
    """Grey win[0] x win[1] window around a face of `kind` ("exit" or one of rs.WALL_KINDS) with the Exit
    positives' jitter (about 10 % margin: window width 1.1 x max(face width, aspect x face height), scale
    jitter exp(N(0, 0.05)), centre jitter N(0, 0.03) of the window, residual roll N(0, 1.5 degrees),
    5 % partial occlusion), rendered at 2x and area-downsampled. The source frame is a 1920 x 1440 or a
    640 x 480 sensor (_cascade_sensor); wall kinds are placed by rs.sample_kind_scene (ranges
    rs.KIND_RANGE_M, up to rs.KIND_MAX_OFF_AXIS off axis), Exit faces by rs.sample_scene."""
    intr_raw = _cascade_sensor(rng)
    if kind == "exit":
        T, signs, _ = rs.sample_scene(rng, intr_raw)
    else:
        T, signs, _ = rs.sample_kind_scene(rng, intr_raw, kind, extra_kinds=[k for k in rs.WALL_KINDS if k != kind])
    intr_u = unrolled_intrinsics(intr_raw, T)
    Tv = _virtual(T, 0.0)
    uv, w, h = sign_box_unrolled(Tv, intr_u, signs[0], T)
    aspect = win[0] / win[1]
    ww = max(w, aspect * h) * 1.1 * math.exp(rng.normal(0, 0.05))
    wh = ww / aspect
    c = uv.mean(axis=0) + rng.normal(0, 0.03, 2) * np.array([ww, wh])
    img, _, _ = render_view(rng, T, signs, intr_u, c[0] - ww / 2, c[1] - wh / 2, ww, wh, 2 * win[0], 2 * win[1],
                            residual_roll=math.radians(rng.normal(0, 1.5)), occlusion_prob=0.05,
                            degrade_unit=intr_raw["width"] / rs.RAW_INTRINSICS["width"])
    g = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
    return cv2.resize(g, win, interpolation=cv2.INTER_AREA)


def kind_frame(rng: np.random.Generator, kind: str, extra_kinds, exit_prob: float = 0.5,
               unrolled: bool = False) -> Tuple[np.ndarray, List[str]]:
    """Grey unrolled 640 x 480 (or 480 x 640) frame from the phone's VGA sensor with a wall sign of `kind`, a
    second wall sign of one of `extra_kinds` (50 %), an Exit sign (`exit_prob`) and 2-9 distractors; returns
    (image, the kinds of the labelled signs in it). Negatives for the other kinds' cascades.

    unrolled=False: rendered directly at the roll-free virtual camera (the whole frame is scene);
    unrolled=True: rendered at the sensor's pose and unrolled as at run time (render_signs.unroll_image), so
    it has the black corners the rotation leaves (their diagonal edges fooled a stairs cascade trained
    without them)."""
    intr_raw = rs.scaled_intrinsics(640, 480)
    T, signs, _ = rs.sample_kind_scene(rng, intr_raw, kind, extra_kinds=list(extra_kinds), extra_kind_prob=0.5,
                                       exit_prob=exit_prob)
    if unrolled:
        return _raw_unrolled(rng, T, signs, intr_raw)
    intr_u = unrolled_intrinsics(intr_raw, T)
    img, _, labels = render_view(rng, T, signs, intr_u, 0, 0, intr_u["width"], intr_u["height"], intr_u["width"],
                                 intr_u["height"], n_distractors=int(rng.integers(2, 10)), degrade_unit=1.0 / 3.0)
    return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY), sorted({lab["kind"] for lab in labels})


def _raw_unrolled(rng: np.random.Generator, T: np.ndarray, signs, intr_raw: dict) -> Tuple[np.ndarray, List[str]]:
    """Render at the sensor pose with 2-9 distractors, grey, unrolled as at run time; (image, sign kinds)."""
    img, _, labels = rs.render_frame(T, intr_raw, signs, rng, n_distractors=int(rng.integers(2, 10)))
    R = T[:3, :3]
    roll = math.atan2(R[1, 0], R[1, 1]) if abs(R[1, 2]) < 0.999 else 0.0
    g, _, _ = rs.unroll_image(cv2.cvtColor(img, cv2.COLOR_RGB2GRAY), intr_raw, roll)
    return g, sorted({lab["kind"] for lab in labels})


def vga_empty_frame(rng: np.random.Generator) -> np.ndarray:
    """Grey sign-free frame from the phone's VGA sensor with 2-9 distractors, unrolled as at run time (black
    corners included); negatives of the wall-kind cascades (--kind-negatives unrolled)."""
    intr_raw = rs.scaled_intrinsics(640, 480)
    T, _ = rs.sample_empty(rng)
    return _raw_unrolled(rng, T, [], intr_raw)[0]
