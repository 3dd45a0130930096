"""Phone-camera image formation for the renderer's `phone` style (render_signs.render_frame(phone=...)).

What a hand-held phone camera does to a corridor scene that the plain renderer leaves out, each
modelled from its physical cause rather than as a free image filter:

  * auto exposure (AE): the exposure is set from the metered scene brightness (centre-weighted mean
    luminance of the linear radiance image), within the sensor's limits. Self-luminous sign faces
    keep their own radiance while the reflective scene scales with the corridor's illuminance, so a
    bright sign in a dim corridor saturates and a lit face over-exposes against its plate;
  * rolling shutter: sensor rows are read out one after another over `readout_s`; under a camera
    rotation (angular velocity `omega_world_rad_s`) each row sees the scene from a slightly
    different orientation. For a pure rotation the image of row time t is the reference image warped
    by the homography K Exp([w]x t) K^-1 (exact for every depth), so the effect is a per-pixel remap;
  * motion blur: the same rotation integrated over the exposure time `exposure_s` (hand sway and
    the step rhythm of walking): the mean of the remaps at several times within the exposure;
  * lens glare: a point-spread function with a narrow core and a wide tail (veiling glare), applied
    to the linear radiance before the sensor clips, so saturated LED letters and ceiling lights get a
    halo whose energy is a fixed small fraction of theirs;
  * sensor saturation with highlight spill: a channel above full scale is clipped and a fraction of
    its excess spills into the other channels (the sensor's and ISP's highlight handling), so an
    over-exposed red LED letter turns pink-white in the core with a red fringe, as in phone photos;
  * gain-dependent noise (higher analog gain in dim scenes) and JPEG compression (video frames);
  * the tone curve: a phone writes display-encoded values, not light. The ISP encodes the linear
    sensor values with the sRGB transfer function (IEC 61966-2-1) before quantising and compressing,
    and its auto exposure places the metered mean at a display value, so the scene's mean sits near
    18 % of full-scale light and highlights keep about 2.5 stops of headroom. `tone_curve="linear"`
    writes light itself (the renders before 2026-12-07).

Camera motion is a rotation only (walking translation over 8-33 ms moves the camera 1-5 cm; ignored).
Conventions as render_signs (arkit-frames.md): a pixel (u, v) is the camera-frame ray
[(u - cx)/fx, -(v - cy)/fy, -1].
"""
from __future__ import annotations

import dataclasses
import math
from typing import Optional, Tuple

import cv2
import numpy as np


@dataclasses.dataclass
class PhoneCamera:
    """One frame's phone-camera parameters.

    omega_world_rad_s: (3,) angular velocity of the camera in WORLD coordinates (rad/s); the same for
      every virtual camera (crop) of the frame.
    exposure_s: exposure (integration) time per row, seconds.
    readout_s: rolling-shutter readout time from the first to the last sensor row, seconds (0 = global
      shutter).
    sensor_R: (3,3) camera-to-world rotation of the physical sensor at the reference time (the middle
      row's read-out time); sensor_intr: its intrinsics (fx, fy, cx, cy, width, height);
    readout_axis: "v" (sensor rows are image rows: raw landscape frames) or "u" (an upright portrait
      image of a landscape sensor: read-out sweeps across columns); readout_sign: +1 or -1, the
      direction of the sweep.
    illuminance: scale of the reflective scene's radiance (corridor lighting level; LED emission is
      not scaled by it).
    ae_target: metered mean luminance the auto exposure aims at (display units, 0..1);
      ev_bias: AE error in stops; exposure_min/max: the sensor's exposure-gain limits.
    glare_core, glare_tail: energy fractions of the glare PSF's core and tail Gaussians;
      glare_core_px, glare_tail_px: their sigmas in raw (1920-wide) pixels.
    spill: fraction of a saturated channel's excess that spills into the other channels.
    noise_sigma: read/shot noise scale at unit gain; jpeg_quality: 0 = none.
    led_gain_scale: multiplier on the LED faces' radiance (1 = as drawn).
    gloss: floor reflectance (0 = matte floor), gloss_blur_px: blur of the reflection (raw pixels).
    tone_curve: "srgb" (display-encoded output, what a phone writes) or "linear" (output proportional to
      light); the AE target is a display value either way.
    """
    omega_world_rad_s: np.ndarray
    exposure_s: float
    readout_s: float
    sensor_R: np.ndarray
    sensor_intr: dict
    readout_axis: str = "v"
    readout_sign: float = 1.0
    illuminance: float = 1.0
    ae_target: float = 0.42
    ev_bias: float = 0.0
    exposure_min: float = 0.25
    exposure_max: float = 4.0
    glare_core: float = 0.04
    glare_tail: float = 0.02
    glare_core_px: float = 4.0
    glare_tail_px: float = 60.0
    spill: float = 0.3
    noise_sigma: float = 0.01
    jpeg_quality: int = 85
    led_gain_scale: float = 1.0
    gloss: float = 0.0
    gloss_blur_px: float = 6.0
    tone_curve: str = "srgb"


def sample_phone_camera(rng: np.random.Generator, sensor_R: np.ndarray, sensor_intr: dict, readout_axis: str = "v",
                        strength: float = 1.0) -> PhoneCamera:
    """Random phone-camera parameters for a hand-held phone carried by a walking person.

    Angular velocity: hand sway and step bob, N(0, (0.25, 0.35, 0.2) rad/s) about the camera's
    (x pitch, y yaw, z roll) axes, and a turn of 0.6-1.2 rad/s yaw in 15 % of frames (scaled by
    `strength`). Exposure 1/120..1/30 s (log-uniform, indoor AE); readout 20-33 ms (phone sensors in
    video mode). Corridor illuminance 0.25-1.4 (log-uniform) x the renderer's default lighting.
    """
    sd = np.array([0.25, 0.35, 0.2]) * strength
    w_cam = rng.normal(0.0, 1.0, 3) * sd
    if rng.random() < 0.15:
        w_cam[1] += rng.choice([-1.0, 1.0]) * rng.uniform(0.6, 1.2) * strength
    omega_world = np.asarray(sensor_R, np.float64) @ w_cam
    return PhoneCamera(
        omega_world_rad_s=omega_world,
        exposure_s=float(math.exp(rng.uniform(math.log(1 / 120), math.log(1 / 30)))),
        readout_s=float(rng.uniform(0.020, 0.033)),
        sensor_R=np.asarray(sensor_R, np.float64), sensor_intr=dict(sensor_intr), readout_axis=readout_axis,
        readout_sign=float(rng.choice([-1.0, 1.0])),
        illuminance=float(math.exp(rng.uniform(math.log(0.25), math.log(1.4)))),
        ae_target=float(rng.uniform(0.35, 0.5)), ev_bias=float(rng.normal(0, 0.3)),
        glare_core=float(rng.uniform(0.02, 0.08)), glare_tail=float(rng.uniform(0.005, 0.03)),
        glare_core_px=float(rng.uniform(2.0, 6.0)), glare_tail_px=float(rng.uniform(30.0, 90.0)),
        spill=float(rng.uniform(0.15, 0.45)), noise_sigma=float(rng.uniform(0.004, 0.015)),
        jpeg_quality=int(rng.integers(55, 92)), led_gain_scale=float(rng.uniform(0.8, 1.5)),
        gloss=float(rng.uniform(0.08, 0.3)) if rng.random() < 0.5 else 0.0,
        gloss_blur_px=float(rng.uniform(2.0, 14.0)))


# --------------------------------------------------------------------------------------------------
# Geometry of the rolling shutter
# --------------------------------------------------------------------------------------------------

def pixel_rays(intr: dict, us: np.ndarray, vs: np.ndarray) -> np.ndarray:
    """Camera-frame rays (..., 3) of pixels (us, vs) (arkit-frames.md convention, z = -1)."""
    x = (us - intr["cx"]) / intr["fx"]
    y = -(vs - intr["cy"]) / intr["fy"]
    return np.stack([x, y, -np.ones_like(x)], axis=-1)


def project_rays(intr: dict, c: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Pixels (u, v) of camera-frame directions c (..., 3) (in front: c_z < 0)."""
    dz = -c[..., 2]
    dz = np.where(np.abs(dz) < 1e-9, 1e-9, dz)
    return intr["cx"] + intr["fx"] * c[..., 0] / dz, intr["cy"] - intr["fy"] * c[..., 1] / dz


def rotate_rodrigues(c: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotate vectors c (..., 3) about the unit `axis` (3,) by per-element `angle` (...) radians."""
    k = np.asarray(axis, np.float64)
    ca, sa = np.cos(angle)[..., None], np.sin(angle)[..., None]
    kxc = np.cross(np.broadcast_to(k, c.shape), c)
    kdc = (c @ k)[..., None]
    return c * ca + kxc * sa + k * kdc * (1 - ca)


def readout_time(phone: PhoneCamera, R_render: np.ndarray, intr: dict, us: np.ndarray, vs: np.ndarray) -> np.ndarray:
    """Read-out time (s, 0 = the sensor's middle row) of render-camera pixels (us, vs): the time of
    the sensor row that images the same direction (the render camera may be a crop of the sensor)."""
    c = pixel_rays(intr, us, vs)
    cs = c @ (np.asarray(phone.sensor_R).T @ np.asarray(R_render)).T  # render cam -> world -> sensor cam
    su, sv = project_rays(phone.sensor_intr, cs)
    si = phone.sensor_intr
    if phone.readout_axis == "v":
        s = (sv - (si["height"] - 1) / 2.0) / si["height"]
    else:
        s = (su - (si["width"] - 1) / 2.0) / si["width"]
    return phone.readout_sign * phone.readout_s * s


def omega_in_camera(phone: PhoneCamera, R_render: np.ndarray) -> np.ndarray:
    """The angular velocity in the render camera's frame (rad/s)."""
    return np.asarray(R_render).T @ phone.omega_world_rad_s


def shutter_map(phone: PhoneCamera, R_render: np.ndarray, intr: dict, tau_s: float,
                grid: Optional[Tuple[np.ndarray, np.ndarray]] = None) -> Tuple[np.ndarray, np.ndarray]:
    """cv2.remap maps: for each output pixel, where it lies in the reference (global-shutter, middle
    row time) image when its row is exposed at readout_time + tau_s.

    The ray of pixel p at time t in the reference camera is Exp([w]x t) K^-1 p (w in the camera
    frame), so the source pixel is its projection (pure rotation: exact at every depth)."""
    W, H = intr["width"], intr["height"]
    if grid is None:
        us, vs = np.meshgrid(np.arange(W, dtype=np.float64), np.arange(H, dtype=np.float64))
    else:
        us, vs = grid
    t = readout_time(phone, R_render, intr, us, vs) + tau_s
    w = omega_in_camera(phone, R_render)
    wn = float(np.linalg.norm(w))
    if wn < 1e-12:
        return us.astype(np.float32), vs.astype(np.float32)
    c = rotate_rodrigues(pixel_rays(intr, us, vs), w / wn, wn * t)
    mu, mv = project_rays(intr, c)
    return mu.astype(np.float32), mv.astype(np.float32)


def rolling_shutter_points(phone: PhoneCamera, R_render: np.ndarray, intr: dict, uv_ref: np.ndarray, iters: int = 8) -> np.ndarray:
    """Where reference-image points (N, 2) appear in the rolling-shutter image (N, 2): the pixel p whose
    shutter_map(p) is uv_ref, solved by fixed-point iteration on the row time (converges because
    the shift per row is a small fraction of a row)."""
    uv_ref = np.asarray(uv_ref, np.float64)
    w = omega_in_camera(phone, R_render)
    wn = float(np.linalg.norm(w))
    if wn < 1e-12:
        return uv_ref.copy()
    c_ref = pixel_rays(intr, uv_ref[:, 0], uv_ref[:, 1])
    p = uv_ref.copy()
    for _ in range(iters):
        t = readout_time(phone, R_render, intr, p[:, 0], p[:, 1])
        c = rotate_rodrigues(c_ref, w / wn, -wn * t)
        pu, pv = project_rays(intr, c)
        p = np.stack([pu, pv], axis=1)
    return p


def blur_times(phone: PhoneCamera, R_render: np.ndarray, intr: dict) -> np.ndarray:
    """Sub-exposure sample times (s, relative to the row's mid-exposure): enough that consecutive
    samples move a pixel by <= 1.5 px, at most 9."""
    w = omega_in_camera(phone, R_render)
    f = max(intr["fx"], intr["fy"])
    # image motion of a central pixel: rotation about x, y moves by f w; about z by <= r w (r ~ half diagonal)
    r = 0.5 * math.hypot(intr["width"], intr["height"])
    speed_px_s = f * math.hypot(w[0], w[1]) + r * abs(w[2])
    length = speed_px_s * phone.exposure_s
    n = int(min(9, max(1, math.ceil(length / 1.5))))
    if n == 1:
        return np.zeros(1)
    return np.linspace(-phone.exposure_s / 2, phone.exposure_s / 2, n)


def dense_shutter_map(phone: PhoneCamera, R_render: np.ndarray, intr: dict, tau_s: float, step: int = 8) -> Tuple[np.ndarray, np.ndarray]:
    """shutter_map evaluated on a grid every `step` pixels (and the last row and column) and
    interpolated bilinearly to every pixel: the map is a per-row homography, smooth at this scale
    (interpolation error well under 0.01 px for the rotations drawn here; see the tests)."""
    W, H = intr["width"], intr["height"]
    nw, nh = int(math.ceil((W - 1) / step)) + 1, int(math.ceil((H - 1) / step)) + 1
    gu, gv = np.meshgrid(np.linspace(0, W - 1, nw), np.linspace(0, H - 1, nh))
    mu, mv = shutter_map(phone, R_render, intr, tau_s, (gu, gv))
    # separable bilinear interpolation (cv2.remap would quantize the positions to 1/32 pixel)
    x = np.arange(W, dtype=np.float64) * ((nw - 1) / max(W - 1, 1))
    y = np.arange(H, dtype=np.float64) * ((nh - 1) / max(H - 1, 1))
    i0 = np.minimum(np.floor(x).astype(np.int64), nw - 2) if nw > 1 else np.zeros(W, np.int64)
    j0 = np.minimum(np.floor(y).astype(np.int64), nh - 2) if nh > 1 else np.zeros(H, np.int64)
    ax, ay = (x - i0)[None, :].astype(np.float32), (y - j0)[:, None].astype(np.float32)

    def interp(m):
        rows = m[:, i0] * (1 - ax) + m[:, np.minimum(i0 + 1, nw - 1)] * ax  # (nh, W)
        return rows[j0] * (1 - ay) + rows[np.minimum(j0 + 1, nh - 1)] * ay

    fu, fv = interp(mu), interp(mv)
    return fu, fv


def apply_motion(phone: PhoneCamera, R_render: np.ndarray, intr: dict, img: np.ndarray, mask: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Rolling shutter + motion blur of a linear image (H, W, 3) float32, and the class mask remapped
    at mid-exposure (face coverage > 0.5 after a bilinear remap of the binary coverage)."""
    acc = np.zeros_like(img)
    taus = blur_times(phone, R_render, intr)
    for tau in taus:
        mu, mv = dense_shutter_map(phone, R_render, intr, float(tau))
        acc += cv2.remap(img, mu, mv, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
    out = acc / len(taus)
    mu, mv = dense_shutter_map(phone, R_render, intr, 0.0)
    new_mask = np.zeros_like(mask)
    for k in np.unique(mask):
        if k == 0:
            continue
        cov = cv2.remap((mask == k).astype(np.float32), mu, mv, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        new_mask[cov > 0.5] = k
    return out, new_mask


# --------------------------------------------------------------------------------------------------
# Photometry
# --------------------------------------------------------------------------------------------------

def luminance(img: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of an RGB image (..., 3)."""
    return img[..., 0] * 0.2126 + img[..., 1] * 0.7152 + img[..., 2] * 0.0722


def auto_exposure(phone: PhoneCamera, radiance: np.ndarray) -> float:
    """Exposure gain that brings the centre-weighted mean luminance of `radiance` to the AE target
    (times 2^ev_bias), limited to [exposure_min, exposure_max]. Bright pixels are metered as they
    are (not clipped), so a large lit face near the camera lowers the exposure of the whole frame."""
    H, W = radiance.shape[:2]
    small = cv2.resize(radiance, (max(8, W // 16), max(8, H // 16)), interpolation=cv2.INTER_AREA)
    h, w = small.shape[:2]
    yy, xx = np.mgrid[0:h, 0:w]
    wgt = np.exp(-(((xx - (w - 1) / 2) / (0.35 * w)) ** 2 + ((yy - (h - 1) / 2) / (0.35 * h)) ** 2))
    meter = float((luminance(small) * wgt).sum() / wgt.sum())
    target = float(srgb_decode(np.float32(phone.ae_target))) if phone.tone_curve == "srgb" else phone.ae_target
    e = target * (2.0 ** phone.ev_bias) / max(meter, 1e-4)
    return float(min(max(e, phone.exposure_min), phone.exposure_max))


def srgb_encode(light: np.ndarray) -> np.ndarray:
    """sRGB transfer function (IEC 61966-2-1): linear light in [0, 1] -> display value in [0, 1]."""
    x = np.clip(light, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055).astype(np.float32)


def srgb_decode(value: np.ndarray) -> np.ndarray:
    """Inverse of srgb_encode: display value in [0, 1] -> linear light in [0, 1]."""
    c = np.clip(value, 0.0, 1.0)
    return np.where(c <= 0.04045, c / 12.92, np.power((c + 0.055) / 1.055, 2.4)).astype(np.float32)


def tone_map(phone: PhoneCamera, img: np.ndarray) -> np.ndarray:
    """The ISP's output encoding of the clipped, noisy linear image: sRGB (phone.tone_curve "srgb") or light
    itself ("linear")."""
    if phone.tone_curve == "linear":
        return img
    if phone.tone_curve != "srgb":
        raise ValueError(f"tone_curve must be 'srgb' or 'linear', not {phone.tone_curve!r}")
    return srgb_encode(img)


def glare(phone: PhoneCamera, img: np.ndarray, scale: float) -> np.ndarray:
    """Energy-preserving lens PSF: (1 - a - b) delta + a G(core) + b G(tail); sigmas in raw pixels x
    `scale` (output pixels per raw pixel). The tail is blurred on a 1/8 image (smooth anyway)."""
    H, W = img.shape[:2]
    a, b = phone.glare_core, phone.glare_tail
    s1 = max(0.5, phone.glare_core_px * scale)
    out = img * (1.0 - a - b) + a * cv2.GaussianBlur(img, (0, 0), s1)
    s2 = phone.glare_tail_px * scale
    if s2 > 16:
        f = 8
        small = cv2.resize(img, (max(1, W // f), max(1, H // f)), interpolation=cv2.INTER_AREA)
        tail = cv2.resize(cv2.GaussianBlur(small, (0, 0), s2 / f), (W, H), interpolation=cv2.INTER_LINEAR)
    else:
        tail = cv2.GaussianBlur(img, (0, 0), max(0.5, s2))
    return out + b * tail


def saturate(phone: PhoneCamera, img: np.ndarray) -> np.ndarray:
    """Clip at full scale with highlight spill: each channel's excess over 1 adds `spill` x that
    excess to the other two channels, then everything clips to [0, 1]."""
    ex = np.maximum(img - 1.0, 0.0)
    tot = ex.sum(axis=-1, keepdims=True)
    out = img + phone.spill * (tot - ex)
    return np.clip(out, 0.0, 1.0)


def sensor_noise(phone: PhoneCamera, rng: np.random.Generator, img: np.ndarray, gain: float, scale: float) -> np.ndarray:
    """Shot + read noise whose variance grows with the analog gain (dim scenes are noisier); at
    output pixels larger than raw pixels (scale < 1) the noise averages down by 1/scale."""
    sigma = phone.noise_sigma * math.sqrt(max(gain, 0.25)) * min(1.0, max(scale, 0.05) ** 0.5 / 1.0)
    n = rng.standard_normal(img.shape, dtype=np.float32)
    n = cv2.GaussianBlur(n, (0, 0), 0.7) * 1.6  # demosaicing correlates neighbouring pixels
    return np.clip(img + n * (sigma * np.sqrt(img + 0.01)).astype(np.float32), 0, 1)


def jpeg_roundtrip(img_u8: np.ndarray, quality: int) -> np.ndarray:
    """Encode and decode an RGB uint8 image as JPEG at `quality` (no-op for quality <= 0)."""
    if quality <= 0:
        return img_u8
    ok, enc = cv2.imencode(".jpg", cv2.cvtColor(img_u8, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    return cv2.cvtColor(cv2.imdecode(enc, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
