#!/usr/bin/env python3
"""Synthetic Exit-sign renderer for training and testing the Wayfinder sign detectors.

No licensed real Exit-sign photographs exist for this project, so every training and test image is
rendered: a procedural indoor scene (corridor ray-cast per pixel: floor, walls, ceiling, doors,
ceiling lights) seen by a pinhole camera with a known pose, with procedurally drawn sign faces
(US "EXIT" in red or green on a white or dark plate, with or without chevrons, lit or unlit; ISO
green running-man) placed in 3-D at their real sizes, plus distractors (red/green text that is not
EXIT, door signs, fire alarms, lights) and image degradations (glow, motion blur, defocus, noise,
JPEG, partial occlusion).

Camera conventions follow ../shared/reference/arkit-frames.md exactly:
  * world: gravity-aligned, y up; camera-to-world rotation R = Ry(yaw) * Rx(pitch) * Rz(roll)
    (ARKit Euler order: roll applied first, then pitch, then yaw);
  * camera looks along -z, x along the long sensor side (image u, right), y = -v;
  * a pixel (u, v) is the world ray R * [(u - cx)/fx, -(v - cy)/fy, -1];
  * roll 0 = landscape upright, roll -pi/2 = portrait (camera x points down in the world);
  * pitch positive = looking up; bearing positive = to the LEFT; range = horizontal meters.

Besides Exit signs it draws the wall sign kinds of WALL_KINDS (restroom, elevator and stairs pictograms,
room-number placards), flat on a corridor wall beside a door at tactile-sign height (sample_kind_scene).

Outputs (one directory per split): images (JPEG), masks (PNG, class index per pixel: 0 background,
1 exit, 2 restroom, 3 elevator, 4 stairs, 5 placard) and labels.jsonl, one JSON object per image
(format in docs/training.md).

Every frame is rendered from its own generator seeded by (seed, split, index), so a frame does not
depend on how many frames were rendered before it.

Public entry points besides the CLI:
  * render_frame(...)   render one frame given a camera pose and signs in camera coordinates;
  * sample_scene(...)   draw a random camera pose and sign placement;
  * unroll_matrix(...)  the affine map from the raw image to the roll-corrected ("unrolled") image.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
from typing import List, Optional, Sequence, Tuple

import cv2
import numpy as np

#: Sign kinds besides the Exit sign ("More sign kinds"): wall-mounted plates, flat on the wall beside
#: doors, at the height of tactile signs (ADA 2010 Standards 703.4.1 / 703.4.2).
WALL_KINDS = ("restroom", "elevator", "stairs", "placard")

#: Class indices written into the masks: 0 background, 1 exit, 2 restroom, 3 elevator, 4 stairs,
#: 5 placard (models/classes.json lists the U-Net's classes, background and exit).
CLASSES = ("background", "exit") + WALL_KINDS
CLASS_INDEX = {k: i for i, k in enumerate(CLASSES)}

#: Face size (width, height) in meters of each wall kind (fixed; the C++ side and the map catalogue
#: use the same numbers).
KIND_FACE_M = {"restroom": (0.23, 0.23), "elevator": (0.23, 0.23), "stairs": (0.23, 0.23), "placard": (0.15, 0.15)}
#: Bottom edge above the floor (meters), drawn uniformly.
KIND_BOTTOM_M = {"restroom": (1.30, 1.45), "elevator": (1.30, 1.45), "stairs": (1.30, 1.45), "placard": (1.30, 1.40)}
#: Largest angle between the face normal and the direction to the camera (radians).
KIND_MAX_OFF_AXIS = {"restroom": math.radians(60), "elevator": math.radians(60), "stairs": math.radians(60),
                     "placard": math.radians(50)}
#: Ranges (horizontal meters) drawn log-uniformly for training samples: the specified viewing ranges
#: (pictograms 1-6 m, placards 0.8-2.5 m) with about 10 % margin.
KIND_RANGE_M = {"restroom": (0.9, 6.6), "elevator": (0.9, 6.6), "stairs": (0.9, 6.6), "placard": (0.7, 2.8)}
#: Distances of the held-out split test_kinds.
KIND_TEST_DISTANCES = {"restroom": (1.5, 2.0, 3.0, 4.0, 5.0, 6.0), "elevator": (1.5, 2.0, 3.0, 4.0, 5.0, 6.0),
                       "stairs": (1.5, 2.0, 3.0, 4.0, 5.0, 6.0), "placard": (0.8, 1.2, 1.6, 2.0, 2.5)}
#: A wall sign's face is this far in front of its wall (plate thickness).
WALL_GAP_M = 0.004

#: iPhone 8 raw intrinsics at 1920 x 1440 (arkit-frames.md).
RAW_INTRINSICS = dict(fx=1602.0, fy=1602.0, cx=960.0, cy=720.0, width=1920, height=1440)


# --------------------------------------------------------------------------------------------------
# Geometry
# --------------------------------------------------------------------------------------------------

def rot_x(a: float) -> np.ndarray:
    """Rotation about the x axis by `a` radians (right-handed)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]], dtype=np.float64)


def rot_y(a: float) -> np.ndarray:
    """Rotation about the y axis by `a` radians (right-handed)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], dtype=np.float64)


def rot_z(a: float) -> np.ndarray:
    """Rotation about the z axis by `a` radians (right-handed)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]], dtype=np.float64)


def camera_rotation(yaw_rad: float, pitch_rad: float, roll_rad: float) -> np.ndarray:
    """Camera-to-world rotation from ARKit Euler angles: R = Ry(yaw) Rx(pitch) Rz(roll)."""
    return rot_y(yaw_rad) @ rot_x(pitch_rad) @ rot_z(roll_rad)


def scaled_intrinsics(width: int, height: int) -> dict:
    """Intrinsics of the iPhone 8 camera scaled to `width` x `height` (same 4:3 field of view)."""
    s = width / RAW_INTRINSICS["width"]
    return dict(fx=RAW_INTRINSICS["fx"] * s, fy=RAW_INTRINSICS["fy"] * s,
                cx=RAW_INTRINSICS["cx"] * s, cy=RAW_INTRINSICS["cy"] * s,
                width=int(width), height=int(height))


def project_points(points_world: np.ndarray, R: np.ndarray, t: np.ndarray, intr: dict) -> Tuple[np.ndarray, np.ndarray]:
    """Project world points (N,3) into pixels (N,2) with the arkit-frames.md pinhole model.

    Returns (uv, depth) where depth = distance along the viewing direction (-z_camera), positive in
    front of the camera.
    """
    pc = (np.asarray(points_world, np.float64) - t) @ R  # = R^T (p - t) per row
    depth = -pc[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = intr["cx"] + intr["fx"] * pc[:, 0] / depth
        v = intr["cy"] - intr["fy"] * pc[:, 1] / depth
    return np.stack([u, v], axis=1), depth


def unroll_matrix(intr: dict, roll_rad: float) -> Tuple[np.ndarray, dict]:
    """Affine 2x3 matrix mapping raw pixels to the roll-corrected image, and that image's intrinsics.

    The unrolled image is the view of a virtual camera with the same centre, pitch and yaw but roll
    0: a rotation of the raw image about the principal point (exact for fx == fy). The unrolled
    image is sized so that a raw frame fits whole when the roll is near 0 or +-90 degrees.
    """
    c, s = math.cos(roll_rad), math.sin(roll_rad)
    w, h = intr["width"], intr["height"]
    portrait = abs(s) > abs(c)
    wu, hu = (h, w) if portrait else (w, h)
    cxu = intr["cx"] * (wu / w) if not portrait else intr["cy"] * (wu / h)
    cyu = intr["cy"] * (hu / h) if not portrait else intr["cx"] * (hu / w)
    f = intr["fx"]
    # unrolled normalized (x', y') = Rz(roll) (x, y): x' = c x - s y, y' = s x + c y, with
    # x = (u - cx)/f, y = -(v - cy)/f, u' = cxu + f x', v' = cyu - f y'.
    # => u' = cxu + c (u-cx) + s (v-cy);  v' = cyu - s (u-cx) + c (v-cy)... derived below.
    A = np.array([[c, s, 0.0], [-s, c, 0.0]], dtype=np.float64)
    # check sign: y' = s x + c y -> -(v'-cyu)/f = s (u-cx)/f - c (v-cy)/f -> v' - cyu = -s (u-cx) + c (v-cy)
    # x' = c x - s y -> (u'-cxu)/f = c (u-cx)/f + s (v-cy)/f
    A[0, 2] = cxu - c * intr["cx"] - s * intr["cy"]
    A[1, 2] = cyu + s * intr["cx"] - c * intr["cy"]
    intr_u = dict(fx=f, fy=intr["fy"], cx=cxu, cy=cyu, width=int(wu), height=int(hu))
    return A, intr_u


def unroll_image(img: np.ndarray, intr: dict, roll_rad: float, interp=cv2.INTER_LINEAR) -> Tuple[np.ndarray, np.ndarray, dict]:
    """Rotate a raw image into the roll-corrected frame; returns (image, 2x3 raw->unrolled, intrinsics)."""
    A, intr_u = unroll_matrix(intr, roll_rad)
    out = cv2.warpAffine(img, A, (intr_u["width"], intr_u["height"]), flags=interp,
                         borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return out, A, intr_u


# --------------------------------------------------------------------------------------------------
# Sign and distractor textures (procedural)
# --------------------------------------------------------------------------------------------------

#: Texture resolution of sign faces, pixels per meter.
TEX_PPM = 1600.0


@dataclasses.dataclass
class Texture:
    """A planar texture: `rgb` float32 (H,W,3) in [0,1] (may exceed 1 when emissive), `alpha` (H,W)
    coverage in [0,1], `emissive` whether it glows (not shaded by scene light), `mask_class` the
    class written into the mask where it is visible (0 for distractors)."""
    rgb: np.ndarray
    alpha: np.ndarray
    emissive: float
    mask_class: int
    #: phone style: self-emitted radiance (H,W,3), added on top of the shaded reflectance `rgb` and
    #: not scaled by the scene's illuminance (LED letters, backlit panels, light fittings); None: none.
    emission: Optional[np.ndarray] = None


def _text_block(text: str, color, canvas_wh: Tuple[int, int], bg, thickness_frac=0.16, font=cv2.FONT_HERSHEY_SIMPLEX) -> np.ndarray:
    """Draw `text` stretched to fill a canvas (W,H) on background `bg` (uint8 RGB)."""
    W, H = canvas_wh
    (tw, th), base = cv2.getTextSize(text, font, 4.0, 1)
    thick = max(1, int(round(thickness_frac * th)))
    (tw, th), base = cv2.getTextSize(text, font, 4.0, thick)
    tmp = np.zeros((th + 2 * thick + 4, tw + 2 * thick + 4, 3), np.uint8)
    tmp[:] = bg
    cv2.putText(tmp, text, (thick + 2, th + thick + 2), font, 4.0, color, thick, cv2.LINE_AA)
    # tight crop on the glyphs
    diff = np.abs(tmp.astype(int) - np.array(bg)).sum(axis=2) > 30
    ys, xs = np.nonzero(diff)
    if len(xs) > 0:
        tmp = tmp[ys.min():ys.max() + 1, xs.min():xs.max() + 1]
    return cv2.resize(tmp, (W, H), interpolation=cv2.INTER_AREA)


def make_us_exit_texture(rng: np.random.Generator, width_m: float, height_m: float, style: Optional[dict] = None,
                         phone: bool = False) -> Tuple[Texture, dict]:
    """US Exit sign face: 6 in (0.152 m) letters "EXIT", red or green, white or dark plate, optional
    chevrons, lit or unlit. Returns the texture and the style chosen.

    phone: a lit face is an LED sign: the letters (behind a diffuser stencil) emit `led_radiance`
    (3-10 x a white wall's radiance under the default corridor light, a luminance ratio of real LED
    exit signs to lit corridor walls) with the spotty profile of the LEDs behind them, and reflect
    the room light like the rest of the face."""
    st = dict(letter=rng.choice(["red", "red", "red", "green"]),
              plate=rng.choice(["white", "white", "dark", "aluminium"]),
              chevron=rng.choice(["none", "none", "left", "right", "both"]),
              lit=bool(rng.random() < 0.6), border=bool(rng.random() < 0.4))
    if style:
        st.update(style)
    W, H = int(round(width_m * TEX_PPM)), int(round(height_m * TEX_PPM))
    plate = {"white": (236, 236, 230), "dark": (30, 30, 32), "aluminium": (175, 178, 180)}[st["plate"]]
    plate = tuple(int(np.clip(p + rng.normal(0, 6), 0, 255)) for p in plate)
    if st["letter"] == "red":
        col = (int(rng.uniform(190, 235)), int(rng.uniform(10, 45)), int(rng.uniform(15, 45)))
    else:
        col = (int(rng.uniform(0, 40)), int(rng.uniform(140, 200)), int(rng.uniform(60, 110)))
    img = np.zeros((H, W, 3), np.uint8)
    img[:] = plate
    letter_h = int(round(0.152 * TEX_PPM * rng.uniform(0.9, 1.0) * min(1.0, height_m / 0.19)))
    letter_h = min(letter_h, H - 8)
    chev = st["chevron"]
    n_chev = {"none": 0, "left": 1, "right": 1, "both": 2}[chev]
    chev_w = int(0.06 * TEX_PPM)
    text_w = int(min(W * 0.84 - n_chev * (chev_w + 0.015 * TEX_PPM), letter_h * rng.uniform(1.65, 1.95)))
    x0 = (W - text_w - n_chev * (chev_w + int(0.015 * TEX_PPM))) // 2
    if chev in ("left", "both"):
        x0 += chev_w + int(0.015 * TEX_PPM)
    y0 = (H - letter_h) // 2
    block = _text_block("EXIT", col, (text_w, letter_h), plate, thickness_frac=rng.uniform(0.13, 0.2))
    img[y0:y0 + letter_h, x0:x0 + text_w] = block
    cy = H // 2

    def chevron(xc, direction):
        h2 = letter_h * 0.35
        pts = np.array([[xc + direction * chev_w / 2, cy], [xc - direction * chev_w / 2, cy - h2],
                        [xc - direction * chev_w / 6, cy], [xc - direction * chev_w / 2, cy + h2]], np.int32)
        cv2.fillPoly(img, [pts], col, cv2.LINE_AA)

    if chev in ("left", "both"):
        chevron(x0 - int(0.015 * TEX_PPM) - chev_w / 2, -1)
    if chev in ("right", "both"):
        chevron(x0 + text_w + int(0.015 * TEX_PPM) + chev_w / 2, +1)
    if st["border"]:
        b = max(2, int(0.006 * TEX_PPM))
        cv2.rectangle(img, (b, b), (W - 1 - b, H - 1 - b), col, b)
    rgb = img.astype(np.float32) / 255.0
    emissive = 0.0
    if phone:
        return _led_face(rng, rgb, img, plate, st), st
    if st["lit"]:
        # letters (and a white plate) emit light: brighter than the shaded scene, may saturate.
        gain = rng.uniform(1.1, 1.8)
        letters = (np.abs(img.astype(int) - np.array(plate)).sum(axis=2) > 60).astype(np.float32)
        rgb = rgb * (1.0 + (gain - 1.0) * letters[..., None])
        emissive = 1.0
    tex = Texture(rgb=rgb, alpha=np.ones((H, W), np.float32), emissive=emissive, mask_class=1)
    return tex, st


def _led_face(rng: np.random.Generator, rgb: np.ndarray, img: np.ndarray, plate, st: dict) -> Texture:
    """Phone style: LED-lit US face (see make_us_exit_texture); unlit faces only reflect."""
    emission = None
    if st["lit"]:
        letters = (np.abs(img.astype(int) - np.array(plate)).sum(axis=2) > 60).astype(np.float32)
        H, W = letters.shape
        pitch = max(4, int(0.012 * TEX_PPM))  # LEDs about 12 mm apart behind the stencil
        yy, xx = np.mgrid[0:H, 0:W]
        ph = rng.uniform(0, pitch, 2)
        spots = np.cos(np.pi * ((xx + ph[0]) % pitch - pitch / 2) / pitch) * np.cos(np.pi * ((yy + ph[1]) % pitch - pitch / 2) / pitch)
        profile = (1.0 - rng.uniform(0.0, 0.35)) + rng.uniform(0.0, 0.35) * spots.astype(np.float32)
        radiance = rng.uniform(3.0, 10.0)
        emission = (rgb * letters[..., None] * (radiance * profile)[..., None]).astype(np.float32)
        st["led_radiance"] = float(radiance)
    return Texture(rgb=rgb, alpha=np.ones(rgb.shape[:2], np.float32), emissive=0.0, mask_class=1, emission=emission)


def make_iso_exit_texture(rng: np.random.Generator, width_m: float, height_m: float, phone: bool = False) -> Tuple[Texture, dict]:
    """ISO 7010 E001-like green 'running man' emergency exit sign (approximated procedurally).
    phone: a lit face is a backlit panel emitting 1.2-2.5 x a white wall's radiance over the whole face."""
    W, H = int(round(width_m * TEX_PPM)), int(round(height_m * TEX_PPM))
    green = (int(rng.uniform(0, 30)), int(rng.uniform(120, 170)), int(rng.uniform(60, 100)))
    white = (245, 245, 240)
    img = np.zeros((H, W, 3), np.uint8)
    img[:] = green
    s = H / 100.0  # pictogram units
    mirror = rng.random() < 0.5
    lw = max(2, int(7 * s))
    # door (white outline, right part of sign)
    dx0 = int(W * 0.55)
    cv2.rectangle(img, (dx0, int(12 * s)), (dx0 + int(30 * s), int(88 * s)), white, max(2, int(5 * s)))
    # running man (left part)
    hx, hy = int(W * 0.3), int(22 * s)
    cv2.circle(img, (hx, hy), int(8 * s), white, -1, cv2.LINE_AA)
    body = [(hx - int(3 * s), int(33 * s)), (hx - int(10 * s), int(60 * s))]
    cv2.line(img, body[0], body[1], white, lw, cv2.LINE_AA)
    cv2.line(img, body[0], (hx + int(14 * s), int(45 * s)), white, lw, cv2.LINE_AA)
    cv2.line(img, body[0], (hx - int(20 * s), int(42 * s)), white, lw, cv2.LINE_AA)
    cv2.line(img, body[1], (hx + int(6 * s), int(86 * s)), white, lw, cv2.LINE_AA)
    cv2.line(img, body[1], (hx - int(28 * s), int(78 * s)), white, lw, cv2.LINE_AA)
    # arrow
    if rng.random() < 0.6:
        ax = int(W * 0.1)
        cv2.arrowedLine(img, (ax + int(14 * s), int(50 * s)), (ax - int(4 * s), int(50 * s)), white, lw, cv2.LINE_AA, tipLength=0.6)
    if mirror:
        img = img[:, ::-1].copy()
    lit = bool(rng.random() < 0.5)
    rgb = img.astype(np.float32) / 255.0
    if phone:
        em = (rgb * rng.uniform(1.2, 2.5)).astype(np.float32) if lit else None
        return Texture(rgb=rgb, alpha=np.ones((H, W), np.float32), emissive=0.0, mask_class=1, emission=em), dict(kind="iso", lit=lit)
    if lit:
        rgb = rgb * rng.uniform(1.1, 1.5)
    return Texture(rgb=rgb, alpha=np.ones((H, W), np.float32), emissive=1.0 if lit else 0.0, mask_class=1), dict(kind="iso", lit=lit)


# --------------------------------------------------------------------------------------------------
# Wall sign kinds (restroom, elevator, stairs pictograms; room-number placards), drawn with cv2
# primitives at TEX_PPM. Pictograms are white (light) on a dark or blue plate; every drawing call
# works in texture pixels with 4 fractional bits (shift 4) so that small parts stay anti-aliased.
# --------------------------------------------------------------------------------------------------

_SH = 4  # fractional bits of the drawing calls
_SF = float(1 << _SH)


def _poly(img: np.ndarray, pts, col) -> None:
    """Filled anti-aliased polygon with float vertices."""
    cv2.fillPoly(img, [np.round(np.asarray(pts, np.float64) * _SF).astype(np.int32)], col, cv2.LINE_AA, _SH)


def _disc(img: np.ndarray, c, r: float, col, thickness: int = -1) -> None:
    """Anti-aliased disc (or ring of `thickness` px) with a float centre and radius."""
    cv2.circle(img, (int(round(c[0] * _SF)), int(round(c[1] * _SF))), int(round(r * _SF)), col,
               thickness if thickness < 0 else max(1, int(round(thickness))), cv2.LINE_AA, _SH)


def _seg(img: np.ndarray, p, q, col, thickness: float) -> None:
    """Thick anti-aliased line segment with round caps."""
    cv2.line(img, (int(round(p[0] * _SF)), int(round(p[1] * _SF))), (int(round(q[0] * _SF)), int(round(q[1] * _SF))),
             col, max(1, int(round(thickness))), cv2.LINE_AA, _SH)


def _jitter_colour(rng: np.random.Generator, base, sd: float = 6.0):
    return tuple(int(np.clip(b + rng.normal(0, sd), 0, 255)) for b in base)


def _draw_man(img, cx: float, top: float, h: float, col) -> None:
    """Man pictogram (head, torso, arms apart from the torso, two legs), `h` px tall, head top at `top`."""
    r = 0.085 * h
    _disc(img, (cx, top + r), r, col)
    sy, hy, fy = top + 0.205 * h, top + 0.56 * h, top + h
    tw = 0.14 * h
    _poly(img, [(cx - tw, sy), (cx + tw, sy), (cx + 0.85 * tw, hy), (cx - 0.85 * tw, hy)], col)
    for sd in (-1, 1):
        a0, a1 = cx + sd * (tw + 0.025 * h), cx + sd * (tw + 0.095 * h)
        _poly(img, [(a0, sy + 0.01 * h), (a1, sy + 0.03 * h), (a1, top + 0.50 * h), (a0, top + 0.50 * h)], col)
        l0, l1 = cx + sd * 0.015 * h, cx + sd * 0.85 * tw
        _poly(img, [(l0, hy - 1), (l1, hy - 1), (l1, fy), (l0, fy)], col)


def _draw_woman(img, cx: float, top: float, h: float, col) -> None:
    """Woman pictogram (head, dress widening to the hem, arms, legs below the dress)."""
    r = 0.085 * h
    _disc(img, (cx, top + r), r, col)
    sy, hem, fy = top + 0.205 * h, top + 0.68 * h, top + h
    _poly(img, [(cx - 0.115 * h, sy), (cx + 0.115 * h, sy), (cx + 0.24 * h, hem), (cx - 0.24 * h, hem)], col)
    for sd in (-1, 1):
        a0 = cx + sd * 0.14 * h
        _poly(img, [(a0, sy + 0.005 * h), (a0 + sd * 0.06 * h, sy + 0.02 * h), (a0 + sd * 0.13 * h, top + 0.47 * h),
                    (a0 + sd * 0.075 * h, top + 0.48 * h)], col)
        l0, l1 = cx + sd * 0.04 * h, cx + sd * 0.115 * h
        _poly(img, [(l0, hem - 1), (l1, hem - 1), (l1, fy), (l0, fy)], col)


def _draw_wheelchair(img, x0: float, top: float, h: float, col, mirror: bool = False) -> None:
    """International Symbol of Accessibility (a seated figure in a wheelchair, facing right), in an
    h x h box whose left edge is x0."""
    def X(f):
        return x0 + (1.0 - f) * h if mirror else x0 + f * h
    lw = 0.085 * h
    _disc(img, (X(0.40), top + 0.09 * h), 0.08 * h, col)
    _seg(img, (X(0.36), top + 0.24 * h), (X(0.38), top + 0.52 * h), col, 1.3 * lw)  # back
    _seg(img, (X(0.38), top + 0.52 * h), (X(0.66), top + 0.52 * h), col, lw)  # thigh
    _seg(img, (X(0.66), top + 0.52 * h), (X(0.78), top + 0.84 * h), col, lw)  # shin
    _seg(img, (X(0.78), top + 0.84 * h), (X(0.92), top + 0.80 * h), col, 0.8 * lw)  # foot
    _seg(img, (X(0.37), top + 0.34 * h), (X(0.60), top + 0.34 * h), col, 0.8 * lw)  # arm
    _disc(img, (X(0.42), top + 0.70 * h), 0.26 * h, col, thickness=0.07 * h)  # wheel


def _draw_walker(img, cx: float, top: float, h: float, col, lw: float) -> None:
    """Walking figure (head and thick limbs), `h` px tall, facing right, feet at top + h."""
    _disc(img, (cx + 0.06 * h, top + 0.09 * h), 0.09 * h, col)
    neck, hip = (cx + 0.03 * h, top + 0.23 * h), (cx - 0.02 * h, top + 0.56 * h)
    _seg(img, neck, hip, col, 1.4 * lw)
    knee_f, knee_b = (cx + 0.16 * h, top + 0.74 * h), (cx - 0.10 * h, top + 0.78 * h)
    _seg(img, hip, knee_f, col, lw)
    _seg(img, knee_f, (cx + 0.17 * h, top + 0.93 * h), col, lw)
    _seg(img, hip, knee_b, col, lw)
    _seg(img, knee_b, (cx - 0.22 * h, top + h), col, lw)
    elbow_f, elbow_b = (cx + 0.16 * h, top + 0.40 * h), (cx - 0.10 * h, top + 0.40 * h)
    _seg(img, (neck[0], neck[1] + 0.04 * h), elbow_f, col, 0.85 * lw)
    _seg(img, elbow_f, (cx + 0.26 * h, top + 0.30 * h), col, 0.85 * lw)
    _seg(img, (neck[0], neck[1] + 0.04 * h), elbow_b, col, 0.85 * lw)
    _seg(img, elbow_b, (cx - 0.14 * h, top + 0.55 * h), col, 0.85 * lw)


def _triangle(img, cx: float, cy: float, s: float, up: bool, col) -> None:
    """Filled isosceles triangle of side `s` centred at (cx, cy), pointing up or down."""
    hh = 0.45 * s
    if up:
        _poly(img, [(cx, cy - hh), (cx + s / 2, cy + hh), (cx - s / 2, cy + hh)], col)
    else:
        _poly(img, [(cx, cy + hh), (cx + s / 2, cy - hh), (cx - s / 2, cy - hh)], col)


def _braille_row(img, cx: float, y: float, n_cells: int, col, rng: np.random.Generator) -> None:
    """A row of Braille-like cells centred at cx, top dot row at y: 2 x 3 dots per cell, dots 2.4 mm apart,
    cells 6.5 mm apart, dot diameter 1.5 mm (ADA 703.3.1 dimensions); random dot patterns."""
    ppm = TEX_PPM
    d, cell, r = 0.0024 * ppm, 0.0065 * ppm, 0.00075 * ppm
    x0 = cx - ((n_cells - 1) * cell + d) / 2
    for k in range(n_cells):
        bits = rng.random(6) < 0.45
        if not bits.any():
            bits[int(rng.integers(6))] = True
        for j in range(6):
            if bits[j]:
                _disc(img, (x0 + k * cell + (j // 3) * d, y + (j % 3) * d), r, col)


def _text_line(img, text: str, cx: float, top: float, height: float, col, max_w: float,
               font=cv2.FONT_HERSHEY_SIMPLEX, thick_frac: float = 0.16) -> float:
    """Draw `text` with its glyph block `height` px tall (natural aspect, at most `max_w` wide) centred at cx,
    top edge at `top`, over whatever is in img. Returns the block's bottom y."""
    (tw, th), _ = cv2.getTextSize(text, font, 4.0, 1)
    thick = max(1, int(round(thick_frac * th)))
    (tw, th), _ = cv2.getTextSize(text, font, 4.0, thick)
    tmp = np.zeros((th + 2 * thick + 8, tw + 2 * thick + 8), np.uint8)
    cv2.putText(tmp, text, (thick + 4, th + thick + 4), font, 4.0, 255, thick, cv2.LINE_AA)
    ys, xs = np.nonzero(tmp > 20)
    tmp = tmp[ys.min():ys.max() + 1, xs.min():xs.max() + 1]
    w = min(max_w, height * tmp.shape[1] / tmp.shape[0])
    Wi, Hi = max(1, int(round(w))), max(1, int(round(height)))
    a = cv2.resize(tmp, (Wi, Hi), interpolation=cv2.INTER_AREA).astype(np.float32)[..., None] / 255.0
    x0, y0 = int(round(cx - Wi / 2)), int(round(top))
    x0, y0 = max(0, x0), max(0, y0)
    Wi, Hi = min(Wi, img.shape[1] - x0), min(Hi, img.shape[0] - y0)
    roi = img[y0:y0 + Hi, x0:x0 + Wi].astype(np.float32)
    img[y0:y0 + Hi, x0:x0 + Wi] = (roi * (1 - a[:Hi, :Wi]) + np.array(col, np.float32) * a[:Hi, :Wi] + 0.5).astype(np.uint8)
    return float(y0 + Hi)


def _plate(rng: np.random.Generator, W: int, H: int, choices) -> Tuple[np.ndarray, tuple, str]:
    """Plate image filled with one of `choices` [(name, rgb, probability)], jittered."""
    p = np.array([c[2] for c in choices], np.float64)
    k = int(rng.choice(len(choices), p=p / p.sum()))
    col = _jitter_colour(rng, choices[k][1])
    img = np.zeros((H, W, 3), np.uint8)
    img[:] = col
    return img, col, choices[k][0]


_SYMBOL_WHITE = (240, 240, 236)


def make_restroom_texture(rng: np.random.Generator, width_m: float, height_m: float, style: Optional[dict] = None) -> Tuple[Texture, dict]:
    """Restroom sign: white man and/or woman figures (optionally the wheelchair symbol) on a blue, dark grey
    or black plate; optional text MEN / WOMEN / RESTROOM under the figures and Braille-like dots."""
    W, H = int(round(width_m * TEX_PPM)), int(round(height_m * TEX_PPM))
    img, plate, plate_name = _plate(rng, W, H, [("blue", (22, 68, 150), 0.65), ("darkgrey", (62, 64, 68), 0.2),
                                                ("black", (22, 22, 24), 0.15)])
    fg = _jitter_colour(rng, _SYMBOL_WHITE, 4)
    variant = str(rng.choice(["men", "women", "unisex", "unisex", "accessible", "family"]))
    text = bool(rng.random() < 0.5)
    braille = text and bool(rng.random() < 0.6)
    fh = H * (rng.uniform(0.50, 0.56) if text else rng.uniform(0.62, 0.72))
    top = (H * 0.08 if text else (H - fh) / 2) + rng.normal(0, 0.01 * H)
    if variant == "men":
        _draw_man(img, W / 2, top, fh, fg)
    elif variant == "women":
        _draw_woman(img, W / 2, top, fh, fg)
    elif variant == "unisex":
        _draw_man(img, W * 0.28, top, fh, fg)
        _seg(img, (W / 2, top), (W / 2, top + fh), fg, max(2.0, 0.025 * W))
        _draw_woman(img, W * 0.72, top, fh, fg)
    elif variant == "accessible":  # one figure and the wheelchair symbol
        fh2 = fh * 0.9
        if rng.random() < 0.5:
            _draw_man(img, W * 0.27, top, fh2, fg)
        else:
            _draw_woman(img, W * 0.27, top, fh2, fg)
        ws = min(0.88 * fh2, 0.5 * W)
        _draw_wheelchair(img, W * 0.95 - ws, top + fh2 - ws, ws, fg)
    else:  # family: man, woman and the wheelchair symbol, smaller
        fh2 = fh * 0.8
        t2 = top + 0.1 * fh
        _draw_man(img, W * 0.18, t2, fh2, fg)
        _draw_woman(img, W * 0.47, t2, fh2, fg)
        ws = min(0.7 * fh2, 0.33 * W)
        _draw_wheelchair(img, W * 0.96 - ws, t2 + fh2 - ws, ws, fg)
    if text:
        word = {"men": "MEN", "women": "WOMEN"}.get(variant, str(rng.choice(["RESTROOM", "RESTROOMS"])))
        yb = _text_line(img, word, W / 2, top + fh + 0.07 * H, 0.1 * H, fg, 0.86 * W)
        if braille:
            _braille_row(img, W / 2, yb + 0.035 * H, min(8, len(word) + 1), fg, rng)
    border = bool(rng.random() < 0.35)
    if border:
        b = 0.03 * W
        cv2.rectangle(img, (int(b), int(b)), (int(W - 1 - b), int(H - 1 - b)), fg, max(2, int(0.008 * W)), cv2.LINE_AA)
    st = dict(variant=variant, plate=plate_name, text=text, braille=braille, border=border)
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones((H, W), np.float32), emissive=0.0,
                   mask_class=CLASS_INDEX["restroom"]), st


def make_elevator_texture(rng: np.random.Generator, width_m: float, height_m: float, style: Optional[dict] = None) -> Tuple[Texture, dict]:
    """Elevator sign: a person in a box with up/down triangles beside it, a box with the up and down
    triangles inside, or a pair of closed doors with the triangles above; white on dark grey, black or blue."""
    W, H = int(round(width_m * TEX_PPM)), int(round(height_m * TEX_PPM))
    img, plate, plate_name = _plate(rng, W, H, [("darkgrey", (62, 64, 68), 0.4), ("black", (22, 22, 24), 0.3),
                                                ("blue", (22, 68, 150), 0.3)])
    fg = _jitter_colour(rng, _SYMBOL_WHITE, 4)
    variant = str(rng.choice(["person_box", "arrows_box", "doors"]))
    text = bool(rng.random() < 0.35)
    y_lo, y_hi = (0.1 * H, 0.72 * H) if text else (0.14 * H, 0.86 * H)
    lw = max(3.0, 0.035 * W)
    if variant == "person_box":
        bx0, bx1 = 0.16 * W, 0.62 * W
        cv2.rectangle(img, (int(bx0), int(y_lo)), (int(bx1), int(y_hi)), fg, int(lw), cv2.LINE_AA)
        ph = (y_hi - y_lo) * 0.78
        _draw_man(img, (bx0 + bx1) / 2, y_lo + (y_hi - y_lo - ph) / 2, ph, fg)
        s = 0.17 * W
        ym = (y_lo + y_hi) / 2
        _triangle(img, 0.80 * W, ym - 0.6 * s, s, True, fg)
        _triangle(img, 0.80 * W, ym + 0.6 * s, s, False, fg)
    elif variant == "arrows_box":
        bx0, bx1 = 0.22 * W, 0.78 * W
        cv2.rectangle(img, (int(bx0), int(y_lo)), (int(bx1), int(y_hi)), fg, int(lw), cv2.LINE_AA)
        s = 0.3 * W
        ym = (y_lo + y_hi) / 2
        _triangle(img, W / 2, ym - 0.27 * (y_hi - y_lo), s, True, fg)
        _triangle(img, W / 2, ym + 0.27 * (y_hi - y_lo), s, False, fg)
    else:  # doors with the call triangles above
        s = 0.16 * W
        _triangle(img, 0.38 * W, y_lo + 0.5 * s, s, True, fg)
        _triangle(img, 0.62 * W, y_lo + 0.5 * s, s, False, fg)
        d0 = y_lo + 1.25 * s
        cv2.rectangle(img, (int(0.2 * W), int(d0)), (int(0.8 * W), int(y_hi)), fg, int(lw), cv2.LINE_AA)
        g = 0.015 * W
        for xa, xb in ((0.2 * W + 2 * lw, W / 2 - g), (W / 2 + g, 0.8 * W - 2 * lw)):
            _poly(img, [(xa, d0 + 2 * lw), (xb, d0 + 2 * lw), (xb, y_hi - 2 * lw), (xa, y_hi - 2 * lw)], fg)
    if text:
        _text_line(img, "ELEVATOR", W / 2, y_hi + 0.08 * H, 0.095 * H, fg, 0.86 * W)
    border = bool(rng.random() < 0.3)
    if border:
        b = 0.03 * W
        cv2.rectangle(img, (int(b), int(b)), (int(W - 1 - b), int(H - 1 - b)), fg, max(2, int(0.008 * W)), cv2.LINE_AA)
    st = dict(variant=variant, plate=plate_name, text=text, border=border)
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones((H, W), np.float32), emissive=0.0,
                   mask_class=CLASS_INDEX["elevator"]), st


def make_stairs_texture(rng: np.random.Generator, width_m: float, height_m: float, style: Optional[dict] = None) -> Tuple[Texture, dict]:
    """Stairs sign: a staircase (step polyline or filled steps) rising to one side with a walking figure on
    it; white on dark grey, black or green; optional text STAIRS."""
    W, H = int(round(width_m * TEX_PPM)), int(round(height_m * TEX_PPM))
    img, plate, plate_name = _plate(rng, W, H, [("darkgrey", (62, 64, 68), 0.35), ("black", (22, 22, 24), 0.3),
                                                ("green", (0, 112, 72), 0.35)])
    fg = _jitter_colour(rng, _SYMBOL_WHITE, 4)
    text = bool(rng.random() < 0.35)
    filled = bool(rng.random() < 0.5)
    n = int(rng.integers(3, 6))
    x0, x1 = 0.12 * W, 0.88 * W
    y_bot = (0.74 if text else 0.86) * H
    y_top = y_bot - 0.36 * H
    sw, sh = (x1 - x0) / n, (y_bot - y_top) / n
    lw = max(3.0, 0.04 * W)
    # steps rising to the right: (x0, y_bot) -> up -> right -> up ...
    pts = [(x0, y_bot)]
    for k in range(n):
        pts.append((x0 + k * sw, y_bot - (k + 1) * sh))
        pts.append((x0 + (k + 1) * sw, y_bot - (k + 1) * sh))
    if filled:
        _poly(img, pts + [(x1, y_bot)], fg)
    else:
        for p, q in zip(pts[:-1], pts[1:]):
            _seg(img, p, q, fg, lw)
    # walker standing on the middle of the flight
    k = n // 2
    fh = 0.34 * H
    foot_y = y_bot - (k + 1) * sh - (0 if filled else lw / 2)
    _draw_walker(img, x0 + (k + 0.45) * sw, foot_y - fh, fh, fg, max(3.0, 0.045 * W))
    down = bool(rng.random() < 0.4)
    if down:
        img = img[:, ::-1].copy()
    if text:
        _text_line(img, str(rng.choice(["STAIRS", "STAIR", "STAIRWAY"])), W / 2, y_bot + 0.07 * H, 0.095 * H, fg, 0.86 * W)
    border = bool(rng.random() < 0.3)
    if border:
        b = 0.03 * W
        cv2.rectangle(img, (int(b), int(b)), (int(W - 1 - b), int(H - 1 - b)), fg, max(2, int(0.008 * W)), cv2.LINE_AA)
    st = dict(variant="down" if down else "up", steps=n, filled=filled, plate=plate_name, text=text, border=border)
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones((H, W), np.float32), emissive=0.0,
                   mask_class=CLASS_INDEX["stairs"]), st


def random_room_number(rng: np.random.Generator) -> str:
    """3-4 characters: 3 digits (e.g. 214), 4 digits (1107) or 3 digits and a letter (402A)."""
    r = rng.random()
    digits = 3 if r < 0.75 else 4
    s = str(int(rng.integers(1, 10))) + "".join(str(int(d)) for d in rng.integers(0, 10, digits - 1))
    if digits == 3 and rng.random() < 0.25:
        s += str(rng.choice(list("ABCD")))
    return s


def make_placard_texture(rng: np.random.Generator, width_m: float, height_m: float, style: Optional[dict] = None) -> Tuple[Texture, dict]:
    """Room-number placard: light digits 25 mm tall on a dark plate (near-black, dark grey, dark blue,
    brown), or (30 %) dark digits on a light plate; optional Braille-like dots under the number and a thin
    border. style may fix "text"; the style returned carries it."""
    W, H = int(round(width_m * TEX_PPM)), int(round(height_m * TEX_PPM))
    light = bool(rng.random() < 0.3)
    if light:
        img, plate, plate_name = _plate(rng, W, H, [("white", (236, 236, 230), 0.4), ("beige", (214, 204, 178), 0.3),
                                                    ("lightgrey", (192, 194, 196), 0.3)])
        fg = _jitter_colour(rng, [(24, 24, 26), (28, 40, 92), (72, 46, 30)][int(rng.integers(3))])
    else:
        img, plate, plate_name = _plate(rng, W, H, [("black", (22, 22, 24), 0.3), ("darkgrey", (62, 64, 68), 0.25),
                                                    ("darkblue", (28, 42, 92), 0.25), ("brown", (82, 52, 32), 0.2)])
        fg = _jitter_colour(rng, (238, 238, 232) if rng.random() < 0.7 else (226, 214, 186))
    text = (style or {}).get("text") or random_room_number(rng)
    braille = bool(rng.random() < 0.6)
    border = bool(rng.random() < 0.5)
    font = cv2.FONT_HERSHEY_SIMPLEX if rng.random() < 0.6 else cv2.FONT_HERSHEY_DUPLEX
    digit_h = 0.025 * TEX_PPM
    top = H * (rng.uniform(0.28, 0.36) if braille else rng.uniform(0.38, 0.45))
    yb = _text_line(img, text, W / 2 + rng.normal(0, 0.01 * W), top, digit_h, fg, 0.8 * W, font=font,
                    thick_frac=rng.uniform(0.14, 0.2))
    if braille:
        _braille_row(img, W / 2, yb + 0.012 * TEX_PPM, len(text) + 1, fg, rng)
    if border:
        b = rng.uniform(0.035, 0.06) * W
        cv2.rectangle(img, (int(b), int(b)), (int(W - 1 - b), int(H - 1 - b)), fg, max(2, int(0.0015 * TEX_PPM)), cv2.LINE_AA)
    st = dict(text=text, plate=plate_name, light=light, braille=braille, border=border)
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones((H, W), np.float32), emissive=0.0,
                   mask_class=CLASS_INDEX["placard"]), st


def make_wall_sign_texture(rng: np.random.Generator, kind: str, width_m: float, height_m: float,
                           style: Optional[dict] = None) -> Tuple[Texture, dict]:
    """Texture and style of a wall sign of `kind` (one of WALL_KINDS)."""
    fn = {"restroom": make_restroom_texture, "elevator": make_elevator_texture, "stairs": make_stairs_texture,
          "placard": make_placard_texture}[kind]
    return fn(rng, width_m, height_m, style)


DISTRACTOR_WORDS_RED = ["FIRE", "EXTRA", "ENTER", "STAFF", "ALARM", "STOP", "PULL", "NO ENTRY", "EXAM", "DANGER", "OFFICE", "TEXT"]
DISTRACTOR_WORDS_GREEN = ["OPEN", "ROOM", "WAY", "EXAM", "TAXI", "EAST", "LIFT", "INFO", "MEN", "WOMEN"]


def make_distractor_texture(rng: np.random.Generator) -> Tuple[Texture, float, float]:
    """A random non-Exit object: coloured text plate, door/room sign, fire alarm, light panel.
    Returns (texture, width_m, height_m)."""
    kind = rng.choice(["red_text", "green_text", "room_sign", "fire_alarm", "light", "poster", "red_box"])
    if kind in ("red_text", "green_text"):
        w, h = rng.uniform(0.2, 0.6), rng.uniform(0.1, 0.25)
        W, H = int(w * 800), int(h * 800)
        plate = (236, 236, 230) if rng.random() < 0.6 else (30, 30, 30)
        col = (210, 30, 30) if kind == "red_text" else (20, 160, 80)
        if rng.random() < 0.3:  # coloured plate, white text
            plate, col = col, (240, 240, 240)
        words = DISTRACTOR_WORDS_RED if kind == "red_text" else DISTRACTOR_WORDS_GREEN
        img = np.zeros((H, W, 3), np.uint8)
        img[:] = plate
        tw, th = int(W * rng.uniform(0.6, 0.9)), int(H * rng.uniform(0.4, 0.75))
        img[(H - th) // 2:(H - th) // 2 + th, (W - tw) // 2:(W - tw) // 2 + tw] = _text_block(str(rng.choice(words)), col, (tw, th), plate)
        emissive = 1.0 if rng.random() < 0.3 else 0.0
    elif kind == "room_sign":
        w, h = rng.uniform(0.15, 0.3), rng.uniform(0.15, 0.3)
        W, H = int(w * 800), int(h * 800)
        plate = tuple(int(x) for x in rng.choice([[40, 60, 120], [90, 90, 95], [200, 200, 195], [30, 30, 30], [120, 40, 40]]))
        img = np.zeros((H, W, 3), np.uint8)
        img[:] = plate
        tw, th = int(W * 0.7), int(H * 0.3)
        img[int(H * 0.5):int(H * 0.5) + th, (W - tw) // 2:(W - tw) // 2 + tw] = _text_block(str(rng.integers(100, 480)), (240, 240, 240), (tw, th), plate)
        cv2.circle(img, (W // 2, int(H * 0.28)), int(H * 0.12), (240, 240, 240), -1)
        emissive = 0.0
    elif kind == "fire_alarm":
        w, h = rng.uniform(0.1, 0.16), rng.uniform(0.12, 0.2)
        W, H = int(w * 800), int(h * 800)
        img = np.zeros((H, W, 3), np.uint8)
        img[:] = (200, 25, 25)
        cv2.rectangle(img, (int(W * 0.2), int(H * 0.45)), (int(W * 0.8), int(H * 0.6)), (235, 235, 235), -1)
        tw, th = int(W * 0.8), int(H * 0.18)
        img[int(H * 0.12):int(H * 0.12) + th, int(W * 0.1):int(W * 0.1) + tw] = _text_block("FIRE", (240, 240, 240), (tw, th), (200, 25, 25))
        emissive = 0.0
    elif kind == "light":
        w, h = rng.uniform(0.3, 1.2), rng.uniform(0.1, 0.3)
        W, H = int(w * 400), int(h * 400)
        img = np.full((H, W, 3), 255, np.uint8)
        emissive = 1.0
        rgb = np.ones((H, W, 3), np.float32) * rng.uniform(1.2, 2.0)
        return Texture(rgb=rgb, alpha=np.ones((H, W), np.float32), emissive=1.0, mask_class=0), w, h
    elif kind == "red_box":  # extinguisher cabinet / red equipment
        w, h = rng.uniform(0.2, 0.5), rng.uniform(0.3, 0.7)
        W, H = int(w * 400), int(h * 400)
        img = np.zeros((H, W, 3), np.uint8)
        img[:] = (int(rng.uniform(150, 220)), 20, 25)
        cv2.rectangle(img, (int(W * 0.15), int(H * 0.15)), (int(W * 0.85), int(H * 0.85)), (220, 220, 220), max(1, W // 30))
        emissive = 0.0
    else:  # poster: random colour blocks and text-like stripes
        w, h = rng.uniform(0.3, 0.8), rng.uniform(0.4, 1.0)
        W, H = int(w * 300), int(h * 300)
        img = np.zeros((H, W, 3), np.uint8)
        img[:] = rng.integers(0, 255, 3)
        for _ in range(int(rng.integers(3, 10))):
            x0, y0 = int(rng.integers(0, W)), int(rng.integers(0, H))
            cv2.rectangle(img, (x0, y0), (x0 + int(rng.integers(5, W // 2 + 6)), y0 + int(rng.integers(3, H // 4 + 4))),
                          tuple(int(c) for c in rng.integers(0, 255, 3)), -1)
        emissive = 0.0
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones(img.shape[:2], np.float32), emissive=emissive, mask_class=0), w, h


# --------------------------------------------------------------------------------------------------
# Scene: procedural corridor ray-cast per pixel
# --------------------------------------------------------------------------------------------------

@dataclasses.dataclass
class Corridor:
    """Axis-aligned corridor in world coordinates: walls at x = x_left, x_right, floor y = 0,
    ceiling y = ceiling_m, end wall at z = z_end (< 0), back wall at z = z_back (> 0)."""
    x_left: float
    x_right: float
    ceiling_m: float
    z_end: float
    z_back: float
    floor_rgb: np.ndarray
    wall_rgb: np.ndarray
    ceil_rgb: np.ndarray
    end_rgb: np.ndarray
    door_rgb: np.ndarray
    tile_m: float
    tile_contrast: float
    door_spacing_m: float
    door_phase_m: float
    light_spacing_m: float
    light_phase_m: float
    light_gain: float
    falloff_m: float


def sample_corridor(rng: np.random.Generator, must_contain: Sequence[np.ndarray], cam_t: np.ndarray) -> Corridor:
    """Random corridor (or hall) that contains the camera and every point of `must_contain`."""
    xs = [cam_t[0]] + [p[0] for p in must_contain]
    zs = [cam_t[2]] + [p[2] for p in must_contain]
    ys = [p[1] for p in must_contain] + [2.4]
    width = rng.uniform(1.8, 4.0)
    lo, hi = min(xs) - 0.5, max(xs) + 0.5
    if hi - lo > width:
        width = hi - lo + rng.uniform(0.2, 2.0)
    x_left = rng.uniform(hi - width, lo)
    def col(base, jitter):
        return np.clip(np.array(base, np.float32) + rng.normal(0, jitter, 3), 0, 1).astype(np.float32)
    wall_base = [[0.85, 0.84, 0.80], [0.78, 0.76, 0.70], [0.70, 0.74, 0.78], [0.9, 0.9, 0.9], [0.6, 0.55, 0.5], [0.75, 0.8, 0.72]][int(rng.integers(0, 6))]
    floor_base = [[0.45, 0.45, 0.45], [0.6, 0.55, 0.45], [0.35, 0.3, 0.28], [0.7, 0.7, 0.68], [0.3, 0.35, 0.45]][int(rng.integers(0, 5))]
    door_base = [[0.55, 0.38, 0.22], [0.45, 0.3, 0.2], [0.6, 0.6, 0.62], [0.25, 0.3, 0.45], [0.7, 0.2, 0.15]][int(rng.integers(0, 5))]
    return Corridor(
        x_left=x_left, x_right=x_left + width,
        ceiling_m=max(rng.uniform(2.6, 3.4), max(ys) + 0.15),
        z_end=min(zs) - rng.uniform(1.0, 20.0), z_back=max(zs) + rng.uniform(0.5, 6.0),
        floor_rgb=col(floor_base, 0.05), wall_rgb=col(wall_base, 0.04), ceil_rgb=col([0.88, 0.88, 0.86], 0.03),
        end_rgb=col(wall_base, 0.08), door_rgb=col(door_base, 0.05),
        tile_m=rng.uniform(0.3, 0.9), tile_contrast=rng.uniform(0.0, 0.15),
        door_spacing_m=rng.uniform(2.5, 7.0), door_phase_m=rng.uniform(0, 7.0),
        light_spacing_m=rng.uniform(2.0, 4.0), light_phase_m=rng.uniform(0, 4.0),
        light_gain=rng.uniform(1.3, 2.2), falloff_m=rng.uniform(5.0, 25.0))


def sample_corridor_on_wall(rng: np.random.Generator, wall_signs, others: Sequence[np.ndarray], cam_t: np.ndarray) -> Corridor:
    """Corridor (or hall) whose side wall carries the wall signs `wall_signs` [(SignSpec, centre, normal) in
    world coordinates; their normals are +-x, all on one wall], containing the camera and the points
    `others`, with a door beside the first sign (sign on the latch side, 8-30 cm from the door frame, as
    ADA 703.4.2 places tactile signs). Draws sample_corridor's values, then places the walls and the door."""
    s0, c0, n0 = wall_signs[0]
    left = n0[0] > 0  # the face looks towards +x: it hangs on the left wall
    x_wall = float(c0[0] - math.copysign(WALL_GAP_M, n0[0]))
    pts = [np.asarray(p, np.float64) for p in others] + [np.asarray(c, np.float64) for _, c, _ in wall_signs]
    cor = sample_corridor(rng, pts, cam_t)
    width = cor.x_right - cor.x_left
    xs = [cam_t[0]] + [p[0] for p in others]
    if left:
        need = max(xs) - x_wall + 0.4
        cor.x_left, cor.x_right = x_wall, x_wall + max(width, need + rng.uniform(0.0, 1.0))
    else:
        need = x_wall - min(xs) + 0.4
        cor.x_right, cor.x_left = x_wall, x_wall - max(width, need + rng.uniform(0.0, 1.0))
    gap = rng.uniform(0.08, 0.30)
    if rng.random() < 0.5:  # the door starts beyond the sign (larger z)
        z0 = float(c0[2]) + s0.width_m / 2 + gap
    else:  # the door (and its 7 cm frame) ends before the sign
        z0 = float(c0[2]) - s0.width_m / 2 - gap - 0.97
    offset = 0.0 if left else 0.37 * cor.door_spacing_m  # render_corridor's door pattern on each wall
    cor.door_phase_m = float((z0 - offset) % cor.door_spacing_m)
    return cor


def _corridor_for(rng: np.random.Generator, signs_world, t: np.ndarray) -> Corridor:
    """The corridor of a frame: sample_corridor around the signs, or sample_corridor_on_wall when wall
    signs (WALL_KINDS) are present."""
    wall = [(s, c, n) for s, c, n in signs_world if s.kind in WALL_KINDS]
    if not wall:
        return sample_corridor(rng, [c for _, c, _ in signs_world], t)
    return sample_corridor_on_wall(rng, wall, [c for s, c, _ in signs_world if s.kind not in WALL_KINDS], t)


def _value_noise(rng: np.random.Generator, n: int = 64) -> np.ndarray:
    """Smooth periodic noise texture (n x n, zero mean, ~unit std)."""
    z = rng.normal(0, 1, (n, n)).astype(np.float32)
    zp = np.pad(z, 6, mode="wrap")  # periodic smoothing
    z = cv2.GaussianBlur(zp, (0, 0), 1.5)[6:-6, 6:-6] + 0.3 * z
    return (z - z.mean()) / (z.std() + 1e-6)


def render_corridor(rng: np.random.Generator, cor: Corridor, R: np.ndarray, t: np.ndarray, intr: dict, downsample: int = 1,
                    gloss: float = 0.0, return_floor: bool = False):
    """Ray-cast the corridor for every pixel; returns linear RGB float32 (H, W, 3).

    gloss (phone style): floor reflectance; floor pixels add `gloss` x the colour of the mirrored ray
    (a second ray cast from the floor hit: reflections of the ceiling lights, walls and doors).
    return_floor: also return the (H, W) float32 map of floor coverage (for reflections of signs).
    """
    W, H = intr["width"], intr["height"]
    w, h = (W + downsample - 1) // downsample, (H + downsample - 1) // downsample
    us = (np.arange(w, dtype=np.float32) + 0.5) * downsample - 0.5
    vs = (np.arange(h, dtype=np.float32) + 0.5) * downsample - 0.5
    x = (us[None, :] - intr["cx"]) / intr["fx"]
    y = -(vs[:, None] - intr["cy"]) / intr["fy"]
    x, y = np.broadcast_to(x, (h, w)), np.broadcast_to(y, (h, w))
    Rf = R.astype(np.float32)
    d = [Rf[i, 0] * x + Rf[i, 1] * y - Rf[i, 2] for i in range(3)]  # world ray components
    o = t.astype(np.float32)
    noise = _value_noise(rng)
    n = noise.shape[0]

    def tex(a, b, scale):
        ia = (np.floor(a * scale).astype(np.int64)) % n
        ib = (np.floor(b * scale).astype(np.int64)) % n
        return noise[ia, ib]

    def cast(o, d):
        """Shade rays from origins o (3 scalars or 3 arrays) along d (3 arrays): (rgb, distance, surface id)."""
        big = np.float32(1e9)
        tt = np.full((h, w), big, np.float32)
        sid = np.zeros((h, w), np.int8)
        with np.errstate(divide="ignore", invalid="ignore"):
            for s, (axis, plane) in enumerate([(1, 0.0), (1, cor.ceiling_m), (0, cor.x_left), (0, cor.x_right), (2, cor.z_end), (2, cor.z_back)]):
                ti = (plane - o[axis]) / d[axis]
                ok = (ti > 1e-4) & (ti < tt)
                tt = np.where(ok, ti, tt)
                sid = np.where(ok, s, sid).astype(np.int8)
        tt = np.minimum(tt, 200.0)
        P = [o[i] + tt * d[i] for i in range(3)]
        img = np.zeros((h, w, 3), np.float32)
        # floor: tiles + noise
        m = sid == 0
        if m.any():
            a, b = P[0][m], P[2][m]
            checker = ((np.floor(a / cor.tile_m) + np.floor(b / cor.tile_m)) % 2) * 2 - 1
            grout = ((np.abs((a / cor.tile_m) - np.round(a / cor.tile_m)) < 0.02) | (np.abs((b / cor.tile_m) - np.round(b / cor.tile_m)) < 0.02))
            shade = 1.0 + cor.tile_contrast * checker + 0.06 * tex(a, b, 20.0) - 0.15 * grout
            img[m] = cor.floor_rgb[None, :] * shade[:, None]
        # ceiling: tiles and light panels
        m = sid == 1
        if m.any():
            a, b = P[0][m], P[2][m]
            grid = ((np.abs(a / 0.6 - np.round(a / 0.6)) < 0.02) | (np.abs(b / 0.6 - np.round(b / 0.6)) < 0.02))
            zc = (b - cor.light_phase_m) % cor.light_spacing_m
            xm = 0.5 * (cor.x_left + cor.x_right)
            light = (zc < 0.6) & (np.abs(a - xm) < 0.6)
            shade = (1.0 - 0.2 * grid + 0.03 * tex(a, b, 10.0))[:, None] * cor.ceil_rgb[None, :]
            shade[light] = cor.light_gain
            img[m] = shade
        # side walls with doors and baseboard
        for s in (2, 3):
            m = sid == s
            if not m.any():
                continue
            yy, zz = P[1][m], P[2][m]
            zd = (zz - cor.door_phase_m - (0.37 * cor.door_spacing_m if s == 3 else 0.0)) % cor.door_spacing_m
            door = (zd < 0.9) & (yy < 2.1)
            frame = ((zd < 0.97) & (yy < 2.17)) & ~door
            shade = (1.0 + 0.03 * tex(yy, zz, 15.0))[:, None] * cor.wall_rgb[None, :]
            shade[door] = cor.door_rgb * (1.0 + 0.05 * tex(yy[door], zz[door], 30.0))[:, None]
            shade[frame] = cor.wall_rgb * 0.6
            shade[yy < 0.1] *= 0.4
            img[m] = shade * (0.85 if s == 2 else 0.95)
        for s in (4, 5):
            m = sid == s
            if m.any():
                img[m] = cor.end_rgb[None, :] * (1.0 + 0.03 * tex(P[0][m], P[1][m], 15.0))[:, None] * 0.9
        return img, tt, sid, P

    img, tt, sid, P = cast(o, d)
    if gloss > 0:
        # mirror ray from the floor hit: (dx, -dy, dz); only floor pixels use it
        o2 = [P[0], np.full_like(P[1], 1e-3), P[2]]
        img2, tt2, _, _ = cast(o2, [d[0], -d[1], d[2]])
        light2 = 0.45 + 0.55 * np.exp(-(tt + tt2) / cor.falloff_m)
        floor = (sid == 0)[..., None]
        img = img + np.where(floor, gloss * img2 * light2[..., None] / (0.45 + 0.55 * np.exp(-tt / cor.falloff_m))[..., None], 0)
    # lighting falloff with distance and a mild vertical gradient
    light = 0.45 + 0.55 * np.exp(-tt / cor.falloff_m)
    img *= light[..., None]
    if downsample > 1:
        img = cv2.resize(img, (W, H), interpolation=cv2.INTER_LINEAR)
    if return_floor:
        fl = (sid == 0).astype(np.float32)
        if downsample > 1:
            fl = cv2.resize(fl, (W, H), interpolation=cv2.INTER_LINEAR)
        return img, fl
    return img


def render_clutter(rng: np.random.Generator, W: int, H: int) -> np.ndarray:
    """Non-corridor background: gradients, random rectangles/lines and texture (linear RGB)."""
    img = np.zeros((H, W, 3), np.float32)
    c0, c1 = rng.uniform(0.1, 0.9, 3), rng.uniform(0.1, 0.9, 3)
    g = np.linspace(0, 1, H, dtype=np.float32)[:, None, None]
    img[:] = c0 * (1 - g) + c1 * g
    for _ in range(int(rng.integers(5, 30))):
        col = tuple(float(c) for c in rng.uniform(0, 1, 3))
        x0, y0 = int(rng.integers(0, W)), int(rng.integers(0, H))
        if rng.random() < 0.7:
            cv2.rectangle(img, (x0, y0), (x0 + int(rng.integers(5, max(6, W // 3))), y0 + int(rng.integers(5, max(6, H // 3)))), col, -1)
        else:
            cv2.line(img, (x0, y0), (int(rng.integers(0, W)), int(rng.integers(0, H))), col, int(rng.integers(1, 8)))
    nz = cv2.resize(_value_noise(rng, 64), (W, H), interpolation=cv2.INTER_LINEAR)
    return np.clip(img * (1 + 0.08 * nz[..., None]), 0, 1)


# --------------------------------------------------------------------------------------------------
# Planar quads (signs, distractors)
# --------------------------------------------------------------------------------------------------

@dataclasses.dataclass
class SignSpec:
    """A sign (or distractor) in CAMERA coordinates: `center_cam` (3,) meters, `normal_cam` (3,)
    unit vector pointing out of the face towards the viewer side, `width_m`, `height_m`, `kind`
    ("exit" for US or ISO exit signs; "restroom", "elevator", "stairs", "placard": WALL_KINDS, flat on a
    side wall whose plane render_frame puts WALL_GAP_M behind the face, so their normal must be world +-x),
    `style` (texture options; see make_us_exit_texture; a placard's may fix "text"), and `iso` selects
    the ISO running-man face. The face's up direction is world up (signs hang level)."""
    center_cam: np.ndarray
    normal_cam: np.ndarray
    width_m: float
    height_m: float
    kind: str = "exit"
    style: Optional[dict] = None
    iso: bool = False


def quad_corners_world(center: np.ndarray, normal: np.ndarray, width_m: float, height_m: float) -> np.ndarray:
    """TL, TR, BR, BL corners (4,3) of an upright rectangle facing along `normal` (seen from the
    front: TL is top-left as the viewer sees it). Up is world +y."""
    n = np.array(normal, np.float64)
    n[1] = 0.0
    n /= np.linalg.norm(n) + 1e-12
    up = np.array([0.0, 1.0, 0.0])
    right = np.cross(up, n)
    hw, hh = width_m / 2, height_m / 2
    c = np.asarray(center, np.float64)
    return np.array([c - right * hw + up * hh, c + right * hw + up * hh, c + right * hw - up * hh, c - right * hw - up * hh])


def paste_quad(img: np.ndarray, mask: Optional[np.ndarray], emissive_layer: np.ndarray, tex: Texture,
               corners_uv: np.ndarray, light: float, emission_scale: float = 1.0) -> bool:
    """Warp `tex` onto `img` at the projected corners (TL,TR,BR,BL). Updates `mask` with the
    texture's class where the quad covers more than half a pixel; adds emissive light to
    `emissive_layer` for the bloom. `tex.emission` (phone style) is added x `emission_scale`,
    unshaded. Returns False if the quad is off-image."""
    H, W = img.shape[:2]
    x0, y0 = np.floor(corners_uv.min(axis=0)).astype(int) - 2
    x1, y1 = np.ceil(corners_uv.max(axis=0)).astype(int) + 2
    x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, W), min(y1, H)
    if x1 <= x0 or y1 <= y0:
        return False
    # pick a texture level close to twice the projected size (anti-aliasing)
    th, tw = tex.rgb.shape[:2]
    proj_w = max(np.linalg.norm(corners_uv[1] - corners_uv[0]), np.linalg.norm(corners_uv[2] - corners_uv[3]), 1.0)
    proj_h = max(np.linalg.norm(corners_uv[3] - corners_uv[0]), np.linalg.norm(corners_uv[2] - corners_uv[1]), 1.0)
    sw, sh = min(1.0, 2.0 * proj_w / tw), min(1.0, 2.0 * proj_h / th)
    rgb, alpha, em = tex.rgb, tex.alpha, tex.emission
    if sw < 1.0 or sh < 1.0:
        nw, nh = max(2, int(round(tw * sw))), max(2, int(round(th * sh)))
        rgb = cv2.resize(rgb, (nw, nh), interpolation=cv2.INTER_AREA)
        alpha = cv2.resize(alpha, (nw, nh), interpolation=cv2.INTER_AREA)
        if em is not None:
            em = cv2.resize(em, (nw, nh), interpolation=cv2.INTER_AREA)
        th, tw = nh, nw
    src = np.array([[0, 0], [tw, 0], [tw, th], [0, th]], np.float32)
    dst = (corners_uv - np.array([x0, y0])).astype(np.float32)
    Hm = cv2.getPerspectiveTransform(src, dst)
    # pad so that edges interpolate to transparent
    rgb_p = cv2.copyMakeBorder(rgb, 1, 1, 1, 1, cv2.BORDER_REPLICATE)
    a_p = cv2.copyMakeBorder(alpha, 1, 1, 1, 1, cv2.BORDER_CONSTANT, value=0)
    size = (x1 - x0, y1 - y0)
    # padded texture index j has its centre at continuous texture coordinate j - 0.5 (edges of the
    # unpadded texture at 0 and tw); destination pixel centres are integer coordinates, the same
    # convention as the projected corners.
    Hp = Hm @ np.array([[1, 0, -0.5], [0, 1, -0.5], [0, 0, 1]], np.float64)
    wr = cv2.warpPerspective(rgb_p, Hp, size, flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    wa = cv2.warpPerspective(a_p, Hp, size, flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    roi = img[y0:y1, x0:x1]
    shaded = wr if tex.emissive > 0 else wr * light
    roi[:] = roi * (1 - wa[..., None]) + shaded * wa[..., None]
    if tex.emissive > 0:
        emissive_layer[y0:y1, x0:x1] += wr * wa[..., None]
    if em is not None:
        we = cv2.warpPerspective(cv2.copyMakeBorder(em, 1, 1, 1, 1, cv2.BORDER_REPLICATE), Hp, size, flags=cv2.INTER_LINEAR,
                                 borderMode=cv2.BORDER_REPLICATE) * wa[..., None] * emission_scale
        roi += we
        if emissive_layer is not None:
            emissive_layer[y0:y1, x0:x1] += we
    if mask is not None:
        mroi = mask[y0:y1, x0:x1]
        if tex.mask_class > 0:
            mroi[wa > 0.5] = tex.mask_class
        else:
            mroi[wa > 0.5] = 0
    return True


# --------------------------------------------------------------------------------------------------
# Frame rendering
# --------------------------------------------------------------------------------------------------

def _distractor_placement(rng: np.random.Generator, R: np.ndarray, t: np.ndarray, cor: Optional["Corridor"],
                          min_distance_m: float, max_bearing_rad: float, normal_spread_rad: float):
    """Where a distractor (poster, light, marker...) goes: min_distance_m..14 m ahead within +-max_bearing_rad of the
    camera's heading (camera_to_world R, position t), 0.9-2.7 m up; in a corridor 60 % of them on a side wall facing
    into it (None when that spot lies behind the camera: no distractor), the others facing the camera within
    +-normal_spread_rad. Returns (center, normal) in world coordinates. The draws' order is part of each test set."""
    dist = rng.uniform(min_distance_m, 14.0)
    ang = rng.uniform(-max_bearing_rad, max_bearing_rad)
    yaw = math.atan2(-R[0, 2], -R[2, 2])
    hx, hz = -math.sin(yaw + ang), -math.cos(yaw + ang)
    center = np.array([t[0] + dist * hx, rng.uniform(0.9, 2.7), t[2] + dist * hz])
    if cor is not None and rng.random() < 0.6:  # on a side wall, facing into the corridor
        left = rng.random() < 0.5
        center[0] = cor.x_left + 0.01 if left else cor.x_right - 0.01
        normal = np.array([1.0, 0, 0]) if left else np.array([-1.0, 0, 0])
        if (center[2] - t[2]) > -0.5:
            return None
    else:
        normal = np.array([t[0] - center[0], 0, t[2] - center[2]])
        normal = rot_y(rng.uniform(-normal_spread_rad, normal_spread_rad)) @ (normal / (np.linalg.norm(normal) + 1e-9))
    return center, normal


def render_frame(camera_to_world: np.ndarray, intr: dict, signs_cam: Sequence[SignSpec], rng: np.random.Generator,
                 n_distractors: Optional[int] = None, occlusion_prob: float = 0.15, degrade: bool = True,
                 background: Optional[str] = None, degrade_scale: Optional[float] = None,
                 phone=None) -> Tuple[np.ndarray, np.ndarray, List[dict]]:
    """Render one frame.

    camera_to_world: 4x4 (rotation R, translation t; world y up, floor at y = 0).
    intr: dict fx, fy, cx, cy, width, height (pixels).
    signs_cam: signs in camera coordinates (see SignSpec); kind "distractor" draws a random
      non-Exit object there instead (background class in the mask, no label).
    degrade_scale: size of one output pixel in raw (1920 x 1440) pixels' units for blur/noise
      (default: width / 1920), for crops rendered directly at a zoomed virtual camera.
    Returns (image uint8 RGB (H,W,3), mask uint8 (H,W) class index, sign labels as in labels.jsonl
    (cornersRaw, rangeMeters, bearingRad, heightMeters, widthMeters, kind, style)).
    phone: a phone_camera.PhoneCamera: render in the phone style instead (LED faces, auto exposure,
      rolling shutter, walking blur, glare, glossy floor, clutter; `degrade` and `degrade_scale` are
      then unused and cornersRaw are where the corners appear in the rolling-shutter image).
    """
    T = np.asarray(camera_to_world, np.float64)
    if phone is not None:
        return _render_frame_phone(T, intr, signs_cam, rng, n_distractors, occlusion_prob, background, phone)
    R, t = T[:3, :3], T[:3, 3]
    W, H = intr["width"], intr["height"]
    signs_world = []
    for s in signs_cam:
        cw = R @ np.asarray(s.center_cam, np.float64) + t
        nw = R @ np.asarray(s.normal_cam, np.float64)
        signs_world.append((s, cw, nw))
    bg_kind = background or ("corridor" if rng.random() < 0.85 else "clutter")
    ds = 2 if W * H > 1_000_000 else 1
    if bg_kind == "corridor":
        cor = _corridor_for(rng, signs_world, t)
        img = render_corridor(rng, cor, R, t, intr, downsample=ds)
    else:
        cor = None
        img = render_clutter(rng, W, H)
    exposure = rng.uniform(0.6, 1.3)
    img *= exposure
    mask = np.zeros((H, W), np.uint8)
    emissive = np.zeros((H, W, 3), np.float32)

    # distractors on the walls or floating in view
    nd = int(rng.integers(0, 6)) if n_distractors is None else n_distractors
    for _ in range(nd):
        tex, dw, dh = make_distractor_texture(rng)
        placed = _distractor_placement(rng, R, t, cor, 1.5, 0.6, 0.7)
        if placed is None:
            continue
        center, normal = placed
        if tex.emissive and tex.mask_class == 0 and rng.random() < 0.5 and cor is not None:
            center[1] = cor.ceiling_m - 0.02
        corners = quad_corners_world(center, normal, dw, dh)
        uv, depth = project_points(corners, R, t, intr)
        if (depth < 0.3).any() or not np.isfinite(uv).all():
            continue
        facing = np.dot(normal, t - center) > 0
        if not facing:
            continue
        paste_quad(img, mask, emissive, tex, uv, light=exposure * rng.uniform(0.7, 1.1))

    labels = []
    for s, cw, nw in signs_world:
        if s.kind == "distractor":
            tex, _, _ = make_distractor_texture(rng)
            style = dict(kind="distractor")
        elif s.kind in WALL_KINDS:
            tex, style = make_wall_sign_texture(rng, s.kind, s.width_m, s.height_m, s.style)
        elif s.iso:
            tex, style = make_iso_exit_texture(rng, s.width_m, s.height_m)
        else:
            tex, style = make_us_exit_texture(rng, s.width_m, s.height_m, s.style)
        corners = quad_corners_world(cw, nw, s.width_m, s.height_m)
        uv, depth = project_points(corners, R, t, intr)
        if (depth < 0.1).any():
            continue
        if s.kind not in WALL_KINDS:  # wall signs are flat plates on the wall
            _paste_housing(img, emissive, rng, s, cw, nw, R, t, intr, light=exposure * 0.9)
        paste_quad(img, mask, emissive, tex, uv, light=exposure * rng.uniform(0.8, 1.1))
        if s.kind == "distractor":
            continue
        labels.append(_sign_label(s, cw, nw, R, t, uv, style))
    # partial occlusion of signs by a foreground object (pillar, hanging fixture, person)
    for lab in labels:
        if rng.random() < occlusion_prob:
            p0, p1 = _occluder_rect(lab["_uv"], rng, W, H)
            col = tuple(float(c) for c in rng.uniform(0.05, 0.8, 3) * exposure)
            cv2.rectangle(img, p0, p1, col, -1)
            cv2.rectangle(mask, p0, p1, 0, -1)
            cv2.rectangle(emissive, p0, p1, (0, 0, 0), -1)
            lab["occluded"] = True
        lab.pop("_uv", None)

    # glow (bloom) of lit faces and lights
    if emissive.any():
        sig = max(1.0, 0.004 * max(W, H) * rng.uniform(0.5, 2.0))
        img += rng.uniform(0.15, 0.5) * cv2.GaussianBlur(emissive, (0, 0), sig)
    if degrade:
        img = degrade_image(img, rng, degrade_scale)
    else:
        img = np.clip(img, 0, 1)
    out = (np.clip(img, 0, 1) * 255.0 + 0.5).astype(np.uint8)
    return out, mask, labels


def degrade_image(img: np.ndarray, rng: np.random.Generator, scale: Optional[float] = None) -> np.ndarray:
    """Camera effects on a float RGB image: white balance, motion blur, defocus, vignetting, noise.
    `scale`: output pixels per raw pixel (blur sizes are drawn in raw pixels)."""
    H, W = img.shape[:2]
    if scale is None:
        scale = max(W, H) / 1920.0
    img = img * rng.uniform(0.9, 1.1, 3).astype(np.float32)
    r = rng.random()
    if r < 0.35:  # motion blur along a random direction: mean of shifted copies along the streak
        L = rng.uniform(2, 25) * scale
        if L > 1.5:
            a = rng.uniform(0, math.pi)
            n = int(min(9, max(3, round(L))))
            acc = np.zeros_like(img)
            for s_ in np.linspace(-L / 2, L / 2, n):
                M = np.array([[1, 0, s_ * math.cos(a)], [0, 1, s_ * math.sin(a)]], np.float32)
                acc += cv2.warpAffine(img, M, (W, H), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
            img = acc / n
    elif r < 0.6:  # defocus
        s = rng.uniform(0.5, 3.0) * scale
        if s > 0.3:
            img = cv2.GaussianBlur(img, (0, 0), s)
    xx = ((np.arange(W, dtype=np.float32) - W / 2) ** 2)[None, :]
    yy = ((np.arange(H, dtype=np.float32) - H / 2) ** 2)[:, None]
    rr = (xx + yy) / ((W / 2) ** 2 + (H / 2) ** 2)
    img = img * (1 - rng.uniform(0, 0.35) * rr)[..., None]
    img = np.clip(img, 0, 1)
    sigma = rng.uniform(0.003, 0.03)
    img = img + rng.standard_normal(img.shape, dtype=np.float32) * (sigma * np.sqrt(img + 0.02))
    return np.clip(img, 0, 1)


# --------------------------------------------------------------------------------------------------
# Phone style (phone_camera.py): LED faces, auto exposure, rolling shutter, walking blur, glare,
# glossy floors, detector-fooling clutter
# --------------------------------------------------------------------------------------------------

def make_fiducial_texture(rng: np.random.Generator) -> Tuple[Texture, float, float]:
    """ArUco / AprilTag-like marker: black border around an n x n grid (n = 4..6) of random black and
    white cells, inside a white quiet zone one cell wide; 0.1-0.3 m square."""
    n = int(rng.integers(4, 7))
    cells = n + 4  # quiet zone + border on each side
    px = 12
    side = rng.uniform(0.1, 0.3)
    img = np.full((cells * px, cells * px, 3), 245, np.uint8)
    img[px:-px, px:-px] = 15
    bits = rng.random((n, n)) < 0.5
    for i in range(n):
        for j in range(n):
            if bits[i, j]:
                img[(i + 2) * px:(i + 3) * px, (j + 2) * px:(j + 3) * px] = 245
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones(img.shape[:2], np.float32), emissive=0.0, mask_class=0), side, side


def make_poster_texture(rng: np.random.Generator) -> Tuple[Texture, float, float]:
    """A printed poster or notice: photo-like colour field, a headline in a saturated colour (often
    red or green words that are not EXIT), text lines; 0.3-0.9 m wide."""
    w, h = rng.uniform(0.3, 0.9), rng.uniform(0.4, 1.1)
    W, H = int(w * 400), int(h * 400)
    c0, c1 = rng.uniform(0, 1, 3), rng.uniform(0, 1, 3)
    g = np.linspace(0, 1, H, dtype=np.float32)[:, None, None]
    img = ((c0 * (1 - g) + c1 * g) * np.ones((1, W, 1), np.float32) * 255).astype(np.uint8)
    for _ in range(int(rng.integers(2, 7))):
        cv2.circle(img, (int(rng.integers(0, W)), int(rng.integers(0, H))), int(rng.integers(5, max(6, W // 3))),
                   tuple(int(c) for c in rng.integers(0, 255, 3)), -1, cv2.LINE_AA)
    words = DISTRACTOR_WORDS_RED + DISTRACTOR_WORDS_GREEN + ["EXHIBIT", "NEXT", "EXPO", "SALE"]
    col = (int(rng.uniform(170, 235)), int(rng.uniform(0, 50)), int(rng.uniform(0, 50))) if rng.random() < 0.6 else \
        (int(rng.uniform(0, 40)), int(rng.uniform(130, 200)), int(rng.uniform(50, 110)))
    bg = (240, 240, 236)
    th = int(H * rng.uniform(0.1, 0.2))
    y0 = int(H * rng.uniform(0.03, 0.3))
    img[y0:y0 + th, int(W * 0.05):int(W * 0.95)] = _text_block(str(rng.choice(words)), col, (int(W * 0.95) - int(W * 0.05), th), bg)
    for k in range(int(rng.integers(2, 8))):
        yy = int(H * 0.45) + k * max(4, H // 16)
        if yy + 3 < H:
            cv2.rectangle(img, (int(W * 0.08), yy), (int(W * rng.uniform(0.4, 0.92)), yy + max(2, H // 60)), (30, 30, 30), -1)
    return Texture(rgb=img.astype(np.float32) / 255.0, alpha=np.ones((H, W), np.float32), emissive=0.0, mask_class=0), w, h


def make_phone_distractor_texture(rng: np.random.Generator) -> Tuple[Texture, float, float]:
    """Phone style clutter that fools detectors: fiducial markers, posters, bright light fittings
    (self-luminous, 4-15 x a white wall), lit red/green signs that are not EXIT, door name plates,
    or one of make_distractor_texture's objects."""
    r = rng.random()
    if r < 0.2:
        return make_fiducial_texture(rng)
    if r < 0.4:
        return make_poster_texture(rng)
    if r < 0.55:  # light fitting (wall sconce, downlight panel, emergency light)
        w, h = rng.uniform(0.15, 1.2), rng.uniform(0.08, 0.3)
        rgb = np.ones((8, 8, 3), np.float32) * np.array([1.0, rng.uniform(0.9, 1.0), rng.uniform(0.75, 1.0)], np.float32) * 0.9
        em = rgb * rng.uniform(4.0, 15.0)
        return Texture(rgb=rgb, alpha=np.ones((8, 8), np.float32), emissive=0.0, mask_class=0, emission=em), w, h
    tex, w, h = make_distractor_texture(rng)
    if tex.emissive > 0:  # lit text signs and lights: LED radiance instead of the classic gain
        em = tex.rgb * rng.uniform(2.0, 8.0)
        tex = Texture(rgb=np.clip(tex.rgb, 0, 1), alpha=tex.alpha, emissive=0.0, mask_class=0, emission=em.astype(np.float32))
    return tex, w, h


def _paste_housing(img, emissive, rng, s, cw, nw, R, t, intr, light: float) -> None:
    """With probability 0.8, the sign's housing: a box 1.5 cm larger on each side, 1 cm behind the face, in one
    of three plain colours, lit by `light`; not part of the mask (both render paths, same draws)."""
    if rng.random() < 0.8:
        hc = quad_corners_world(cw - 0.01 * nw / (np.linalg.norm(nw) + 1e-9), nw, s.width_m + 0.03, s.height_m + 0.03)
        huv, hd = project_points(hc, R, t, intr)
        if (hd > 0.1).all():
            hcol = np.array(rng.choice([[0.92, 0.92, 0.9], [0.15, 0.15, 0.15], [0.7, 0.7, 0.72]]), np.float32)
            htex = Texture(rgb=np.ones((8, 8, 3), np.float32) * hcol, alpha=np.ones((8, 8), np.float32), emissive=0.0, mask_class=0)
            paste_quad(img, None, emissive, htex, huv, light=light)


def _occluder_rect(uv: np.ndarray, rng: np.random.Generator, W: int, H: int):
    """Pixel corners (p0, p1) of a foreground object (pillar, fixture, person) covering 10-35 % of the sign whose
    projected corners are `uv`, from a random side, clipped to the W x H image (both render paths, same draws)."""
    bw, bh = uv[:, 0].max() - uv[:, 0].min(), uv[:, 1].max() - uv[:, 1].min()
    side, frac = rng.integers(0, 4), rng.uniform(0.1, 0.35)
    cx0, cy0 = uv[:, 0].min(), uv[:, 1].min()
    rect = [(cx0 - bw, cy0 - bh, cx0 + frac * bw, cy0 + 2 * bh), (cx0 + (1 - frac) * bw, cy0 - bh, cx0 + 2 * bw, cy0 + 2 * bh),
            (cx0 - bw, cy0 - bh, cx0 + 2 * bw, cy0 + frac * bh), (cx0 - bw, cy0 + (1 - frac) * bh, cx0 + 2 * bw, cy0 + 2 * bh)][side]
    p0 = (int(max(rect[0], 0)), int(max(rect[1], 0)))
    p1 = (int(min(rect[2], W - 1)), int(min(rect[3], H - 1)))
    return p0, p1


def _sign_label(s, cw, nw, R, t, uv, style) -> dict:
    """labels.jsonl entry of a sign (both render paths)."""
    d_h = np.array([cw[0] - t[0], cw[2] - t[2]])
    fwd = np.array([-R[0, 2], -R[2, 2]])
    fwd /= np.linalg.norm(fwd) + 1e-12
    # bearing: angle from camera forward to the sign, positive to the left (CCW seen from above)
    cross = fwd[0] * d_h[1] - fwd[1] * d_h[0]
    bearing = -math.atan2(cross, float(np.dot(fwd, d_h)))
    lab = dict(kind=s.kind, cornersRaw=[[float(a), float(b)] for a, b in uv],
               rangeMeters=float(np.linalg.norm(d_h)), bearingRad=float(bearing),
               heightMeters=float(s.height_m), widthMeters=float(s.width_m),
               centerHeightMeters=float(cw[1]), style={k: (v if isinstance(v, (bool, str)) else str(v)) for k, v in style.items()},
               _uv=uv)
    if s.kind == "placard":
        lab["text"] = str(style["text"])
    return lab


def _render_frame_phone(T: np.ndarray, intr: dict, signs_cam: Sequence[SignSpec], rng: np.random.Generator,
                        n_distractors: Optional[int], occlusion_prob: float, background: Optional[str], phone) -> Tuple[np.ndarray, np.ndarray, List[dict]]:
    """render_frame's phone style (see phone_camera.py for the image formation)."""
    import phone_camera as pc
    R, t = T[:3, :3], T[:3, 3]
    W, H = intr["width"], intr["height"]
    scale = intr["fx"] / RAW_INTRINSICS["fx"]  # output pixels per raw (1920-wide) pixel: PSF sizes are angles
    sensor_scale = intr["fx"] / phone.sensor_intr["fx"]  # output pixels per sensor pixel
    signs_world = []
    for s in signs_cam:
        signs_world.append((s, R @ np.asarray(s.center_cam, np.float64) + t, R @ np.asarray(s.normal_cam, np.float64)))
    bg_kind = background or ("corridor" if rng.random() < 0.88 else "clutter")
    ds = 2 if W * H > 1_000_000 else 1
    illum = phone.illuminance
    floor = None
    if bg_kind == "corridor":
        cor = _corridor_for(rng, signs_world, t)
        cor.light_gain = float(rng.uniform(4.0, 15.0))  # light panels: far brighter than the walls they light
        img, floor = render_corridor(rng, cor, R, t, intr, downsample=ds, gloss=phone.gloss, return_floor=True)
    else:
        cor = None
        img = render_clutter(rng, W, H)
    img = img * illum
    mask = np.zeros((H, W), np.uint8)
    emissive = np.zeros((H, W, 3), np.float32)
    # textures first: glossy-floor reflections go under everything pasted later
    faces = []
    for s, cw, nw in signs_world:
        if s.kind == "distractor":
            tex, _, _ = make_phone_distractor_texture(rng)
            style = dict(kind="distractor")
        elif s.kind in WALL_KINDS:
            tex, style = make_wall_sign_texture(rng, s.kind, s.width_m, s.height_m, s.style)
        elif s.iso:
            tex, style = make_iso_exit_texture(rng, s.width_m, s.height_m, phone=True)
        else:
            tex, style = make_us_exit_texture(rng, s.width_m, s.height_m, s.style, phone=True)
        faces.append((s, cw, nw, tex, style))
    if floor is not None and phone.gloss > 0:
        refl = np.zeros_like(img)
        dummy = np.zeros_like(img)
        for s, cw, nw, tex, _ in faces:
            cm = quad_corners_world(cw, nw, s.width_m, s.height_m) * np.array([1.0, -1.0, 1.0])  # mirrored in the floor
            uvm, dm = project_points(cm, R, t, intr)
            if (dm > 0.3).all() and np.isfinite(uvm).all():
                paste_quad(refl, None, dummy, tex, uvm, light=illum, emission_scale=phone.led_gain_scale)
        refl = cv2.GaussianBlur(refl, (0, 0), max(0.5, phone.gloss_blur_px * scale))
        img += phone.gloss * refl * floor[..., None]
    nd = int(rng.integers(0, 7)) if n_distractors is None else n_distractors
    for _ in range(nd):
        tex, dw, dh = make_phone_distractor_texture(rng)
        placed = _distractor_placement(rng, R, t, cor, 1.0, 0.7, 0.9)
        if placed is None:
            continue
        center, normal = placed
        if tex.emission is not None and cor is not None and rng.random() < 0.5:
            center[1] = cor.ceiling_m - 0.02
        corners = quad_corners_world(center, normal, dw, dh)
        uv, depth = project_points(corners, R, t, intr)
        if (depth < 0.3).any() or not np.isfinite(uv).all() or np.dot(normal, t - center) <= 0:
            continue
        paste_quad(img, mask, emissive, tex, uv, light=illum * rng.uniform(0.7, 1.1), emission_scale=phone.led_gain_scale)
    labels = []
    for s, cw, nw, tex, style in faces:
        corners = quad_corners_world(cw, nw, s.width_m, s.height_m)
        uv, depth = project_points(corners, R, t, intr)
        if (depth < 0.1).any():
            continue
        if s.kind not in WALL_KINDS:
            _paste_housing(img, emissive, rng, s, cw, nw, R, t, intr, light=illum * 0.9)
        paste_quad(img, mask, emissive, tex, uv, light=illum * rng.uniform(0.8, 1.1), emission_scale=phone.led_gain_scale)
        if s.kind != "distractor":
            labels.append(_sign_label(s, cw, nw, R, t, uv, style))
    for lab in labels:  # partial occlusion (as render_frame)
        if rng.random() < occlusion_prob:
            p0, p1 = _occluder_rect(lab["_uv"], rng, W, H)
            cv2.rectangle(img, p0, p1, tuple(float(c) for c in rng.uniform(0.05, 0.8, 3) * illum), -1)
            cv2.rectangle(mask, p0, p1, 0, -1)
            lab["occluded"] = True
    # image formation: AE on the radiance, rolling shutter + walking blur, glare, vignetting, clipping, noise,
    # the tone curve
    e = pc.auto_exposure(phone, img)
    img, mask = pc.apply_motion(phone, R, intr, img, mask)
    for lab in labels:
        uv_rs = pc.rolling_shutter_points(phone, R, intr, lab.pop("_uv"))
        lab["cornersRaw"] = [[float(a), float(b)] for a, b in uv_rs]
    img = pc.glare(phone, img * e, scale)
    xx = ((np.arange(W, dtype=np.float32) - W / 2) ** 2)[None, :]
    yy = ((np.arange(H, dtype=np.float32) - H / 2) ** 2)[:, None]
    img = img * (1 - rng.uniform(0, 0.3) * (xx + yy) / ((W / 2) ** 2 + (H / 2) ** 2))[..., None]
    img = img * rng.uniform(0.93, 1.07, 3).astype(np.float32)  # white-balance error
    img = pc.saturate(phone, img.astype(np.float32))
    img = pc.sensor_noise(phone, rng, img, e / max(illum, 1e-3) * 0.5, sensor_scale)
    img = pc.tone_map(phone, img)
    out = (np.clip(img, 0, 1) * 255.0 + 0.5).astype(np.uint8)
    if phone.jpeg_quality > 0 and sensor_scale > 0.7:
        out = pc.jpeg_roundtrip(out, phone.jpeg_quality)
    return out, mask, labels


# --------------------------------------------------------------------------------------------------
# Scene sampling
# --------------------------------------------------------------------------------------------------

def sample_camera(rng: np.random.Generator, test: bool = False, phone: bool = False, upright: bool = False) -> Tuple[float, float, float, float]:
    """Random (pitch, roll, yaw, camera height) of a hand-held phone (radians, meters).

    phone: pitch -10..35 degrees (a walker looking up at signs close by), roll N(0, 10 degrees)
    about portrait (70 %) or landscape; upright: the image itself is an upright portrait frame
    (e.g. 360 x 640), so roll is N(0, 8 degrees) about 0."""
    if phone:
        pitch = math.radians(rng.uniform(-10, 35))
        if upright:
            roll = math.radians(rng.normal(0, 8))
        else:
            roll = (-math.pi / 2 if rng.random() < 0.7 else 0.0) + math.radians(rng.normal(0, 10))
        return pitch, roll, rng.uniform(-math.pi, math.pi), rng.uniform(1.1, 1.7)
    if rng.random() < 0.8:
        pitch = math.radians(rng.uniform(-5, 20))
    else:
        pitch = math.radians(rng.uniform(-30, 30))
    portrait = rng.random() < 0.7
    roll = (-math.pi / 2 if portrait else 0.0) + math.radians(rng.normal(0, 6 if test else 8))
    yaw = rng.uniform(-math.pi, math.pi)
    cam_h = rng.uniform(1.2, 1.6)
    return pitch, roll, yaw, cam_h


def _exit_scene_if_visible(R, t, intr: dict, center, normal, w_m: float, h_m: float, margin: int, style, iso: bool,
                           angles) -> Optional[Tuple[np.ndarray, List[SignSpec], dict]]:
    """sample_scene's result for an Exit face at `center` (world) facing `normal`, or None when a corner is
    behind the camera (depth < 0.3 m) or within `margin` pixels of the frame's edge. angles = (pitch, roll, yaw)."""
    corners = quad_corners_world(center, normal, w_m, h_m)
    uv, depth = project_points(corners, R, t, intr)
    if (depth < 0.3).any() or (uv[:, 0] < margin).any() or (uv[:, 1] < margin).any() or \
            (uv[:, 0] > intr["width"] - 1 - margin).any() or (uv[:, 1] > intr["height"] - 1 - margin).any():
        return None
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    spec = SignSpec(center_cam=R.T @ (center - t), normal_cam=R.T @ normal, width_m=w_m, height_m=h_m,
                    kind="exit", style=style, iso=iso)
    pitch, roll, yaw = angles
    return T, [spec], dict(pitch=pitch, roll=roll, yaw=yaw)


def sample_scene(rng: np.random.Generator, intr: dict, distance_m: Optional[float] = None, test: bool = False,
                 max_tries: int = 200, phone: bool = False, upright: bool = False) -> Tuple[np.ndarray, List[SignSpec], dict]:
    """Draw a camera pose and one Exit sign visible in the frame.

    distance_m: horizontal range to the sign centre (drawn in 1..12 m when None).
    phone: the phone style's harder views: oblique faces up to +-65 degrees off axis, red or green
      EXIT letters (50/50), ISO running-man faces (25 %), camera as sample_camera(phone=True).
    Returns (camera_to_world 4x4, [SignSpec in camera coordinates], info dict).
    """
    if phone:
        return _sample_scene_phone(rng, intr, distance_m, test, max_tries, upright)
    for _ in range(max_tries):
        pitch, roll, yaw, cam_h = sample_camera(rng, test)
        R = camera_rotation(yaw, pitch, roll)
        t = np.array([0.0, cam_h, 0.0])
        Z = distance_m if distance_m is not None else float(np.exp(rng.uniform(math.log(1.0), math.log(12.0))))
        iso = (not test) and rng.random() < 0.2
        if iso:
            w_m, h_m = (0.30, 0.15) if rng.random() < 0.5 else (0.40, 0.20)
        else:
            w_m, h_m = 0.30, (0.21 if test else float(rng.uniform(0.19, 0.21)))
        bottom = rng.uniform(2.0, 2.5)
        bearing = rng.uniform(-0.6, 0.6)
        hdir = np.array([-math.sin(yaw + bearing), 0.0, -math.cos(yaw + bearing)])
        center = t + Z * hdir
        center[1] = bottom + h_m / 2
        # sign faces back towards the camera with an off-axis angle
        off = rng.uniform(-0.7, 0.7) if test else (rng.uniform(-1.1, 1.1) if rng.random() < 0.15 else rng.uniform(-0.7, 0.7))
        normal = rot_y(off) @ (-hdir)
        scene = _exit_scene_if_visible(R, t, intr, center, normal, w_m, h_m, 4, None, iso, (pitch, roll, yaw))
        if scene is not None:
            return scene
    raise RuntimeError("sample_scene: could not place a visible sign at %.1f m" % (distance_m or -1))


def _sample_scene_phone(rng, intr, distance_m, test, max_tries, upright):
    """sample_scene(phone=True)."""
    for _ in range(max_tries):
        pitch, roll, yaw, cam_h = sample_camera(rng, test, phone=True, upright=upright)
        R = camera_rotation(yaw, pitch, roll)
        t = np.array([0.0, cam_h, 0.0])
        Z = distance_m if distance_m is not None else float(np.exp(rng.uniform(math.log(1.0), math.log(12.0))))
        iso = rng.random() < 0.25
        if iso:
            w_m, h_m = (0.30, 0.15) if rng.random() < 0.5 else (0.40, 0.20)
            style = None
        else:
            w_m, h_m = 0.30, (0.21 if test else float(rng.uniform(0.19, 0.21)))
            style = dict(letter="red" if rng.random() < 0.5 else "green")
        bottom = rng.uniform(2.0, 2.5)
        bearing = rng.uniform(-0.6, 0.6)
        hdir = np.array([-math.sin(yaw + bearing), 0.0, -math.cos(yaw + bearing)])
        center = t + Z * hdir
        center[1] = bottom + h_m / 2
        normal = rot_y(rng.uniform(-1.13, 1.13)) @ (-hdir)
        margin = max(4, int(0.02 * intr["width"]))  # room for the rolling-shutter shift
        scene = _exit_scene_if_visible(R, t, intr, center, normal, w_m, h_m, margin, style, iso, (pitch, roll, yaw))
        if scene is not None:
            return scene
    raise RuntimeError("sample_scene: could not place a visible sign at %.1f m" % (distance_m or -1))


def _visible(uv: np.ndarray, depth: np.ndarray, intr: dict, margin: float = 4) -> bool:
    """All projected corners in front of the camera and inside the image with `margin` pixels."""
    return bool((depth >= 0.3).all() and np.isfinite(uv).all() and (uv[:, 0] >= margin).all() and (uv[:, 1] >= margin).all()
                and (uv[:, 0] <= intr["width"] - 1 - margin).all() and (uv[:, 1] <= intr["height"] - 1 - margin).all())


def sample_kind_scene(rng: np.random.Generator, intr: dict, kind: str, distance_m: Optional[float] = None, test: bool = False,
                      max_tries: int = 200, extra_kinds: Optional[Sequence[str]] = None, extra_kind_prob: float = 0.3,
                      exit_prob: float = 0.3) -> Tuple[np.ndarray, List[SignSpec], dict]:
    """Draw a camera pose and a wall sign of `kind` (one of WALL_KINDS) in view: face KIND_FACE_M[kind], flat on a
    side wall (normal world +-x) with its bottom edge KIND_BOTTOM_M[kind] above the floor, seen at most
    KIND_MAX_OFF_AXIS[kind] off its normal from horizontal range `distance_m` (drawn log-uniformly in
    KIND_RANGE_M[kind] when None), within +-0.6 rad of the camera's heading; camera as sample_camera.

    Then, when they are in view: with `extra_kind_prob` a second wall sign of one of `extra_kinds` on the same
    wall 0.8-4 m along it, and with `exit_prob` a US Exit sign (0.30 x 0.21 m, bottom 2.0-2.5 m) hanging
    across the corridor 2.5-10 m ahead, facing along it. Returns (camera_to_world 4x4, [SignSpec in camera
    coordinates], the `kind` sign first, info dict)."""
    if kind not in WALL_KINDS:
        raise ValueError("sample_kind_scene: kind %r is not one of %s" % (kind, WALL_KINDS))
    w_m, h_m = KIND_FACE_M[kind]
    for _ in range(max_tries):
        pitch, roll, _, cam_h = sample_camera(rng, test)  # the heading follows the sign below
        t = np.array([0.0, cam_h, 0.0])
        lo, hi = KIND_RANGE_M[kind]
        Z = distance_m if distance_m is not None else float(np.exp(rng.uniform(math.log(lo), math.log(hi))))
        off = rng.uniform(-1.0, 1.0) * KIND_MAX_OFF_AXIS[kind]
        normal = np.array([1.0, 0.0, 0.0]) if rng.random() < 0.5 else np.array([-1.0, 0.0, 0.0])
        to_cam = rot_y(off) @ normal
        center = t - Z * to_cam
        center[1] = rng.uniform(*KIND_BOTTOM_M[kind]) + h_m / 2
        bearing = rng.uniform(-0.6, 0.6)
        yaw = math.atan2(to_cam[0], to_cam[2]) - bearing  # the sign lies at `bearing` left of the heading
        R = camera_rotation(yaw, pitch, roll)
        uv, depth = project_points(quad_corners_world(center, normal, w_m, h_m), R, t, intr)
        if not _visible(uv, depth, intr):
            continue
        world = [(kind, center, normal, w_m, h_m)]
        if extra_kinds and rng.random() < extra_kind_prob:
            k2 = str(rng.choice(list(extra_kinds)))
            w2, h2 = KIND_FACE_M[k2]
            c2 = center.copy()
            c2[2] += (1.0 if rng.random() < 0.5 else -1.0) * rng.uniform(0.8, 4.0)
            c2[1] = rng.uniform(*KIND_BOTTOM_M[k2]) + h2 / 2
            uv2, d2 = project_points(quad_corners_world(c2, normal, w2, h2), R, t, intr)
            to2 = np.array([t[0] - c2[0], 0.0, t[2] - c2[2]])
            if _visible(uv2, d2, intr) and np.dot(to2, normal) > math.cos(math.radians(75)) * np.linalg.norm(to2):
                world.append((k2, c2, normal, w2, h2))
        if rng.random() < exit_prob:
            fwd = np.array([-math.sin(yaw), 0.0, -math.cos(yaw)])
            pe = t + rng.uniform(2.5, 10.0) * fwd
            pe[0] = max(pe[0], center[0] + 0.3) if normal[0] > 0 else min(pe[0], center[0] - 0.3)
            pe[1] = rng.uniform(2.0, 2.5) + 0.105
            ne = np.array([0.0, 0.0, 1.0 if t[2] > pe[2] else -1.0])
            uve, de = project_points(quad_corners_world(pe, ne, 0.30, 0.21), R, t, intr)
            toe = np.array([t[0] - pe[0], 0.0, t[2] - pe[2]])
            if _visible(uve, de, intr) and np.dot(toe, ne) > math.cos(math.radians(70)) * np.linalg.norm(toe):
                world.append(("exit", pe, ne, 0.30, 0.21))
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, t
        specs = [SignSpec(center_cam=R.T @ (c - t), normal_cam=R.T @ n, width_m=w, height_m=h, kind=k)
                 for k, c, n, w, h in world]
        return T, specs, dict(pitch=pitch, roll=roll, yaw=yaw, offAxisRad=float(off))
    raise RuntimeError("sample_kind_scene: could not place a visible %s sign at %.1f m" % (kind, distance_m or -1))


def sample_empty(rng: np.random.Generator, test: bool = False, phone: bool = False, upright: bool = False) -> Tuple[np.ndarray, dict]:
    """Camera pose for a sign-free frame."""
    pitch, roll, yaw, cam_h = sample_camera(rng, test, phone=phone, upright=upright) if phone else sample_camera(rng, test)
    T = np.eye(4)
    T[:3, :3] = camera_rotation(yaw, pitch, roll)
    T[:3, 3] = [0.0, cam_h, 0.0]
    return T, dict(pitch=pitch, roll=roll, yaw=yaw)


SPLIT_CODES = {"train": 1, "val": 2, "test": 3, "test_phone": 4, "test_kinds": 5}

#: Low-resolution phone frames: upright portrait 360 x 640, a 16:9 video frame of the iPhone 8
#: sensor (1920 x 1080 at fx 1602) rotated and scaled by 1/3: fx = fy = 534 px, as the real test photos.
PORTRAIT360_INTRINSICS = dict(fx=534.0, fy=534.0, cx=180.0, cy=320.0, width=360, height=640)


def frame_rng(seed: int, split: str, index: int) -> np.random.Generator:
    """Independent generator of frame `index` of `split` for `seed`."""
    return np.random.default_rng([int(seed), SPLIT_CODES[split], int(index)])


def frame_intrinsics(resolution: str, index: int) -> Tuple[dict, bool]:
    """(intrinsics, upright) of frame `index` for a --resolution choice: "raw" 1920 x 1440, "vga"
    640 x 480 (fx 534: the real photos' pixel density), "portrait360" 360 x 640 upright portrait,
    "mixed" raw for even and vga for odd indices. upright: the image is an upright portrait frame
    (roll about 0, rolling shutter across columns)."""
    if resolution == "mixed":
        resolution = "raw" if index % 2 == 0 else "vga"
    if resolution == "raw":
        return RAW_INTRINSICS.copy(), False
    if resolution == "vga":
        return scaled_intrinsics(640, 480), False
    if resolution == "portrait360":
        return PORTRAIT360_INTRINSICS.copy(), True
    raise ValueError("render_signs: unknown resolution %r (raw, vga, portrait360, mixed)" % resolution)


def render_dataset(out_dir: str, split: str, seed: int, n_per_distance: int = 40, n_empty: int = 200,
                   n_train: int = 0, resolution: str = "raw", jpeg: bool = True, verbose: bool = True,
                   style: str = "classic", kinds: Optional[Sequence[str]] = None, tone_curve: str = "srgb") -> int:
    """Render a split into `out_dir` (images, masks, labels.jsonl). Returns the number of frames.

    split "test" / "test_phone": for each distance 2..9 m, `n_per_distance` frames with one sign,
    then `n_empty` sign-free frames. "test" is the fixed classic set (US Exit 0.30 x 0.21 m);
    "test_phone" is the harder held-out set, always in the phone style (phone_camera.py: LED faces,
    auto exposure, rolling shutter, walking blur, glare, glossy floors, clutter; red and green US
    faces 0.30 x 0.21 m and ISO running-man faces; oblique views to 65 degrees). Other splits:
    `n_train` frames with a sign at 1..12 m plus `n_empty` sign-free frames.
    style: "classic" or "phone" (test_phone is always phone).
    kinds: sign kinds ("exit" and WALL_KINDS). "test_kinds": for each kind in `kinds` (default WALL_KINDS) and
    each of its KIND_TEST_DISTANCES, `n_per_distance` frames with one sign of that kind (sample_kind_scene:
    sometimes a second wall sign of another kind and an Exit sign too), then `n_empty` sign-free frames.
    Train/val: sign frame j has kind kinds[j % len(kinds)] (default exit only: the frames are then unchanged).
    Wall kinds are rendered in the classic style only.
    tone_curve: the phone style's output encoding (phone_camera.PhoneCamera.tone_curve): "srgb" (what a phone
    writes; default since 2026-12-07) or "linear" (the phone-style renders before).
    """
    import phone_camera as pc
    os.makedirs(out_dir, exist_ok=True)
    kinds = tuple(kinds) if kinds else (WALL_KINDS if split == "test_kinds" else ("exit",))
    for k in kinds:
        if k != "exit" and k not in WALL_KINDS:
            raise ValueError("render_dataset: unknown sign kind %r" % k)
    if split in ("test", "test_phone") and kinds != ("exit",):
        raise ValueError("render_dataset: split %s holds Exit signs only (use test_kinds)" % split)
    if style == "phone" and any(k != "exit" for k in kinds):
        raise ValueError("render_dataset: wall sign kinds are rendered in the classic style only")
    jobs = []
    if split in ("test", "test_phone"):
        for d in range(2, 10):
            jobs += [("sign", float(d), "exit")] * n_per_distance
    elif split == "test_kinds":
        for k in kinds:
            for d in KIND_TEST_DISTANCES.get(k, range(2, 10)):
                jobs += [("sign", float(d), k)] * n_per_distance
    else:
        jobs += [("sign", None, kinds[j % len(kinds)]) for j in range(n_train)]
    jobs += [("empty", None, None)] * n_empty
    test = split in ("test", "test_phone", "test_kinds")
    if split == "test_phone":
        style = "phone"
    with open(os.path.join(out_dir, "labels.jsonl"), "w") as f:
        for i, (kind, dist, sign_kind) in enumerate(jobs):
            rng = frame_rng(seed, split, i)
            intr, upright = frame_intrinsics(resolution, i)
            ph = style == "phone"
            if kind == "sign" and sign_kind != "exit":
                T, signs, info = sample_kind_scene(rng, intr, sign_kind, dist, test=test,
                                                   extra_kinds=[k for k in WALL_KINDS if k != sign_kind])
            elif kind == "sign":
                T, signs, info = sample_scene(rng, intr, dist, test=test, phone=ph, upright=upright) if ph else \
                    sample_scene(rng, intr, dist, test=test)
            else:
                T, info = sample_empty(rng, test=test, phone=ph, upright=upright) if ph else sample_empty(rng, test=test)
                signs = []
            phone = None
            if ph:
                phone = pc.sample_phone_camera(rng, T[:3, :3], intr, readout_axis="u" if upright else "v")
                phone.tone_curve = tone_curve
                quality = phone.jpeg_quality
                phone.jpeg_quality = 0  # compressed once, when written
            img, mask, labels = render_frame(T, intr, signs, rng, occlusion_prob=0.0 if test else 0.15, phone=phone)
            name = "%06d" % (i + 1)
            ext = ".jpg" if jpeg else ".png"
            bgr = cv2.cvtColor(img, cv2.COLOR_RGB2BGR)
            if jpeg:
                cv2.imwrite(os.path.join(out_dir, name + ext), bgr,
                            [cv2.IMWRITE_JPEG_QUALITY, int(quality) if ph else int(rng.integers(75, 96))])
            else:
                cv2.imwrite(os.path.join(out_dir, name + ext), bgr)
            cv2.imwrite(os.path.join(out_dir, name + "_mask.png"), mask)
            rec = dict(image=name + ext, mask=name + "_mask.png", intrinsics=intr, pitchRad=info["pitch"], rollRad=info["roll"],
                       yawRad=info["yaw"], cameraToWorld=[float(x) for x in T.T.reshape(-1)], signs=labels)
            if ph:
                rec["phone"] = dict(exposureSeconds=phone.exposure_s, readoutSeconds=phone.readout_s * phone.readout_sign,
                                    readoutAxis=phone.readout_axis, omegaWorldRadPerSecond=[float(x) for x in phone.omega_world_rad_s],
                                    illuminance=phone.illuminance, gloss=phone.gloss, jpegQuality=int(quality),
                                    toneCurve=phone.tone_curve)
            f.write(json.dumps(rec) + "\n")
            if verbose and (i + 1) % 50 == 0:
                print("rendered %d/%d" % (i + 1, len(jobs)), file=sys.stderr, flush=True)
    return len(jobs)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--split", choices=["train", "val", "test", "test_phone", "test_kinds"], default="test",
                    help="test: the fixed classic test set; test_phone: the harder phone-style held-out set; "
                         "test_kinds: restroom, elevator, stairs and placard signs at fixed distances (VGA)")
    ap.add_argument("--seed", type=int, default=1234)
    ap.add_argument("--n-per-distance", type=int, default=None,
                    help="test splits: frames per distance (test 40, test_phone 15 at 2..9 m; test_kinds 12 per kind "
                         "and distance: pictograms 1.5, 2, 3, 4, 5, 6 m, placards 0.8, 1.2, 1.6, 2.0, 2.5 m)")
    ap.add_argument("--n-empty", type=int, default=None, help="sign-free frames (default 200; test_phone 60; test_kinds 40)")
    ap.add_argument("--kinds", default=None,
                    help="comma-separated sign kinds: exit, restroom, elevator, stairs, placard (default: exit; "
                         "test_kinds: restroom,elevator,stairs,placard)")
    ap.add_argument("--n", type=int, default=500, help="train/val split: frames with a sign")
    ap.add_argument("--resolution", choices=["raw", "vga", "portrait360", "mixed"], default=None,
                    help="raw 1920x1440, VGA 640x480, portrait360 360x640 upright, mixed (raw/vga alternating); "
                         "default raw, mixed for test_phone")
    ap.add_argument("--style", choices=["classic", "phone"], default="classic", help="image formation (test_phone: phone)")
    ap.add_argument("--png", action="store_true", help="write PNG images instead of JPEG")
    ap.add_argument("--tone-curve", choices=["srgb", "linear"], default="srgb",
                    help="phone style: display-encoded output (srgb, what a phone writes) or light itself (linear, "
                         "the phone-style renders before 2026-12-07)")
    a = ap.parse_args(argv)
    if a.split in ("test", "test_kinds") and a.seed != 1234:
        print("warning: the fixed test sets are --split test / test_kinds --seed 1234", file=sys.stderr)
    res = a.resolution or {"test_phone": "mixed", "test_kinds": "vga"}.get(a.split, "raw")
    if a.n_per_distance is None:
        a.n_per_distance = {"test_phone": 15, "test_kinds": 12}.get(a.split, 40)
    if a.n_empty is None:
        a.n_empty = {"test_phone": 60, "test_kinds": 40}.get(a.split, 200)
    kinds = [k.strip() for k in a.kinds.split(",") if k.strip()] if a.kinds else None
    n = render_dataset(a.out, a.split, a.seed, a.n_per_distance, a.n_empty, a.n, res, jpeg=not a.png, style=a.style,
                       kinds=kinds, tone_curve=a.tone_curve)
    print("wrote %d frames to %s" % (n, a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
