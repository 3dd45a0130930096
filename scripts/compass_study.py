#!/usr/bin/env python3
"""Indoor compass heading error on real phone walks (Microsoft / XYZ10 Indoor Location Competition 2.0 sample).

Reads the 31 walk traces under ../shared/data/msft_indoor_location_2020 (never copies them) and measures, while
the surveyor walks straight between consecutive surveyed waypoints, the error of the phone's compass heading:

  * compass heading: the azimuth of Android's TYPE_ROTATION_VECTOR (magnetometer-referenced, gyro-fused), and,
    separately, the raw tilt-compensated magnetometer azimuth (TYPE_MAGNETIC_FIELD with gravity from a 1-s
    moving average of TYPE_ACCELEROMETER), both the azimuth of the device's +y axis (the top edge of a phone held
    flat), degrees clockwise from magnetic north (Android SensorManager.getRotationMatrix / getOrientation
    conventions, re-derived here);
  * truth: the bearing of the waypoint leg in the map frame (x east, y north: the floor plans' geojson extents
    in metres equal floor_info's width and height, so map +y is true north), degrees clockwise from map +y;
    "device" truth adds the gyroscope's heading change relative to the leg's circular mean (the phone's sway and
    small turns; assumes the phone points along the leg on average over the leg's middle);
  * map <-> magnetic relation: each floor's constant offset (compass minus map bearing) is the circular median
    over all its walks' samples; the site's offset the same over all its floors (expected: the magnetic
    declination, a few degrees west in Hangzhou, so compass minus true bearing is a few degrees positive);
  * per-walk phone offset: the circular median of each walk's residual after the floor offset (reported; a
    variant of the statistics removes it).

Only the middle of each leg is used (default: 20 % trimmed at each end) and legs whose gyro heading spread over
that middle exceeds a bound (not straight: the surveyor turned) are dropped; the gyroscope does not see the
magnetic field, so this selection does not bias the error.

Statistics: circular mean / median / standard deviation, quantiles of |error|, shares above 30/45/90 degrees, a
von Mises + uniform mixture fitted by EM (kappa by the Best-Fisher approximation of A1^-1), and the error's
autocorrelation against distance walked (sampled on a 0.5-m grid of the path interpolated between waypoints)
and against time (10 Hz), with the 1/e correlation length and an exponential fit.

Usage:  python3 scripts/compass_study.py [--data DIR] [--trim 0.2] [--max-spread-deg 25] [--json OUT.json]
Python 3.11 + numpy only.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
from dataclasses import dataclass, field

import numpy as np

DEFAULT_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data",
                            "msft_indoor_location_2020")


def wrap_deg(a):
    """Wraps degrees to [-180, 180)."""
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


def circ_mean_deg(a):
    a = np.radians(np.asarray(a))
    return math.degrees(math.atan2(np.sin(a).mean(), np.cos(a).mean()))


def circ_std_deg(a):
    """Circular standard deviation sqrt(-2 ln R), degrees."""
    a = np.radians(np.asarray(a))
    r = math.hypot(np.sin(a).mean(), np.cos(a).mean())
    return math.degrees(math.sqrt(-2.0 * math.log(max(r, 1e-12))))


def circ_median_deg(a, step=0.1):
    """Angle minimising the mean absolute wrapped difference (grid search, then refined), degrees."""
    a = np.asarray(a, dtype=float)
    if a.size > 4000:
        a = a[np.linspace(0, a.size - 1, 4000).astype(int)]
    grid = np.arange(-180.0, 180.0, 1.0)
    cost = np.abs(wrap_deg(a[None, :] - grid[:, None])).mean(axis=1)
    best = grid[int(np.argmin(cost))]
    fine = best + np.arange(-1.0, 1.0 + 1e-9, step)
    cost = np.abs(wrap_deg(a[None, :] - fine[:, None])).mean(axis=1)
    return float(wrap_deg(fine[int(np.argmin(cost))]))


# ----------------------------------------------------------------------------------------------- parsing
@dataclass
class Walk:
    path: str
    site: str
    floor: str
    t: np.ndarray            # s since the first sensor sample (rotation-vector timestamps)
    rv: np.ndarray           # (n, 3) rotation vector x, y, z
    mag: np.ndarray          # (n, 3) calibrated magnetic field, uT, device frame
    acc: np.ndarray          # (n, 3) accelerometer, m/s^2, device frame
    gyro: np.ndarray         # (n, 3) rad/s, device frame
    wp_t: np.ndarray         # waypoint times, s
    wp_xy: np.ndarray        # (m, 2) map metres, x east, y north
    derived: dict = field(default_factory=dict)


def parse_trace(path: str, site: str, floor: str) -> Walk:
    rows: dict[str, list] = {k: [] for k in ("TYPE_ROTATION_VECTOR", "TYPE_MAGNETIC_FIELD", "TYPE_ACCELEROMETER",
                                             "TYPE_GYROSCOPE", "TYPE_WAYPOINT")}
    with open(path, encoding="utf-8", errors="replace") as fh:
        for lineno, line in enumerate(fh, 1):
            if not line or line[0] == "#":
                continue
            parts = line.rstrip("\n").split("\t")
            if len(parts) < 2 or parts[1] not in rows:
                continue
            try:
                vals = [float(v) for v in parts[2:5]]
                rows[parts[1]].append([float(parts[0])] + vals)
            except ValueError:
                raise SystemExit(f"{path}:{lineno}: cannot parse a number in {parts[1]} line: {line.strip()!r}")
    for k, v in rows.items():
        if not v:
            raise SystemExit(f"{path}: no {k} samples")

    def arr(k, ncol):
        a = np.asarray(rows[k], dtype=float)
        a = a[np.argsort(a[:, 0], kind="stable")]
        return a[:, : ncol + 1]

    rv = arr("TYPE_ROTATION_VECTOR", 3)
    t0 = rv[0, 0]
    t = (rv[:, 0] - t0) / 1000.0

    def on_rv_times(k):
        a = arr(k, 3)
        ta = (a[:, 0] - t0) / 1000.0
        return np.stack([np.interp(t, ta, a[:, j]) for j in (1, 2, 3)], axis=1)

    wp = arr("TYPE_WAYPOINT", 2)
    return Walk(path=path, site=site, floor=floor, t=t, rv=rv[:, 1:4], mag=on_rv_times("TYPE_MAGNETIC_FIELD"),
                acc=on_rv_times("TYPE_ACCELEROMETER"), gyro=on_rv_times("TYPE_GYROSCOPE"),
                wp_t=(wp[:, 0] - t0) / 1000.0, wp_xy=wp[:, 1:3])


def load_walks(data_dir: str) -> list[Walk]:
    if not os.path.isdir(data_dir):
        raise SystemExit(f"{data_dir}: data folder not found (expected ../shared/data/msft_indoor_location_2020)")
    walks = []
    for site in sorted(os.listdir(data_dir)):
        sd = os.path.join(data_dir, site)
        if not (os.path.isdir(sd) and site.startswith("site")):
            continue
        for floor in sorted(os.listdir(sd)):
            pd = os.path.join(sd, floor, "path_data_files")
            if not os.path.isdir(pd):
                continue
            for name in sorted(os.listdir(pd)):
                if name.endswith(".txt"):
                    walks.append(parse_trace(os.path.join(pd, name), site, floor))
    if not walks:
        raise SystemExit(f"{data_dir}: no siteN/<floor>/path_data_files/*.txt traces")
    return walks


# ----------------------------------------------------------------------------------------------- headings
def moving_average(x: np.ndarray, n: int) -> np.ndarray:
    """Centred moving average over n samples along axis 0 (edges use the available samples)."""
    c = np.cumsum(np.vstack([np.zeros((1,) + x.shape[1:]), x]), axis=0)
    i = np.arange(x.shape[0])
    lo = np.clip(i - n // 2, 0, x.shape[0]); hi = np.clip(i + n // 2 + 1, 0, x.shape[0])
    return (c[hi] - c[lo]) / (hi - lo)[:, None]


def derive(w: Walk) -> None:
    """Rotation-vector azimuth, magnetometer azimuth, gyro heading (all degrees clockwise, device +y axis)."""
    x, y, z = w.rv[:, 0], w.rv[:, 1], w.rv[:, 2]
    qw = np.sqrt(np.clip(1.0 - x * x - y * y - z * z, 0.0, None))
    # Device-to-world (east, north, up) rotation matrix entries that are needed.
    r01 = 2 * (x * y - qw * z)
    r11 = 1 - 2 * (x * x + z * z)
    r20 = 2 * (x * z - qw * y)
    r21 = 2 * (y * z + qw * x)
    r22 = 1 - 2 * (x * x + y * y)
    w.derived["rv_az"] = np.degrees(np.arctan2(r01, r11))
    # Tilt-compensated magnetometer: H = E x A, M = A x H (SensorManager.getRotationMatrix), azimuth of +y.
    dt = np.median(np.diff(w.t))
    g = moving_average(w.acc, max(1, int(round(1.0 / dt))))
    a = g / np.linalg.norm(g, axis=1, keepdims=True)
    h = np.cross(w.mag, a)
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    m = np.cross(a, h)
    w.derived["mag_az"] = np.degrees(np.arctan2(h[:, 1], m[:, 1]))
    # Gyro yaw rate about world up (CCW positive) -> clockwise heading, integrated.
    wz = r20 * w.gyro[:, 0] + r21 * w.gyro[:, 1] + r22 * w.gyro[:, 2]
    inc = np.concatenate([[0.0], -np.degrees(0.5 * (wz[1:] + wz[:-1]) * np.diff(w.t))])
    w.derived["gyro_hd"] = np.cumsum(inc)
    w.derived["field_uT"] = np.linalg.norm(w.mag, axis=1)
    w.derived["dip_deg"] = np.degrees(np.arcsin(np.clip(-(w.mag * a).sum(axis=1) / w.derived["field_uT"], -1, 1)))


# ----------------------------------------------------------------------------------------------- legs
@dataclass
class LegSamples:
    walk: int
    leg: int
    t: np.ndarray
    s: np.ndarray        # distance walked along the waypoint polyline, m
    bearing: float       # leg bearing, degrees clockwise from map north
    raw: dict            # heading source -> compass minus truth (before offsets), degrees, per truth kind


def leg_samples(walks: list[Walk], trim: float, max_spread_deg: float, min_len_m: float, stride: int):
    legs: list[LegSamples] = []
    counts = {"legs": 0, "short_or_fast": 0, "not_straight": 0, "used": 0}
    for wi, w in enumerate(walks):
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(w.wp_xy, axis=0), axis=1))])
        for li in range(len(w.wp_t) - 1):
            counts["legs"] += 1
            t0, t1 = w.wp_t[li], w.wp_t[li + 1]
            d = w.wp_xy[li + 1] - w.wp_xy[li]
            length = float(np.hypot(*d))
            dur = t1 - t0
            if length < min_len_m or dur <= 0 or not (0.3 <= length / dur <= 2.5):
                counts["short_or_fast"] += 1
                continue
            lo, hi = t0 + trim * dur, t1 - trim * dur
            idx = np.nonzero((w.t >= lo) & (w.t <= hi))[0]
            if idx.size < 20:
                counts["short_or_fast"] += 1
                continue
            g = w.derived["gyro_hd"][idx]
            gs = moving_average(g[:, None], 50)[:, 0]
            if gs.max() - gs.min() > max_spread_deg:
                counts["not_straight"] += 1
                continue
            counts["used"] += 1
            idx = idx[::stride]
            g = w.derived["gyro_hd"][idx]
            bearing = math.degrees(math.atan2(d[0], d[1]))
            dev_truth = bearing + wrap_deg(g - circ_mean_deg(g))
            s = cum[li] + length * (w.t[idx] - t0) / dur
            raw = {}
            for src in ("rv_az", "mag_az"):
                az = w.derived[src][idx]
                raw[(src, "walk")] = wrap_deg(az - bearing)
                raw[(src, "device")] = wrap_deg(az - dev_truth)
            legs.append(LegSamples(wi, li, w.t[idx], s, bearing, raw))
    return legs, counts


# ----------------------------------------------------------------------------------------------- statistics
def vm_log_norm(kappa: float) -> float:
    """log(2 pi I0(kappa))."""
    if kappa < 500:
        return math.log(2 * math.pi * float(np.i0(kappa)))
    return math.log(2 * math.pi) + kappa - 0.5 * math.log(2 * math.pi * kappa)


def a1inv(r: float) -> float:
    """Best and Fisher (1981) approximation of the inverse of A1(kappa) = I1/I0."""
    if r < 0.53:
        return 2 * r + r ** 3 + 5 * r ** 5 / 6
    if r < 0.85:
        return -0.4 + 1.39 * r + 0.43 / (1 - r)
    return 1 / (r ** 3 - 4 * r ** 2 + 3 * r)


def fit_vm_uniform(e_deg: np.ndarray, iters: int = 300):
    """EM fit of (1 - w) VonMises(mu, kappa) + w / (2 pi) to errors in degrees. Returns mu_deg, kappa, w, loglik."""
    e = np.radians(e_deg)
    mu, kappa, wout = 0.0, 10.0, 0.1
    for _ in range(iters):
        lv = kappa * np.cos(e - mu) - vm_log_norm(kappa)
        pv = (1 - wout) * np.exp(lv)
        pu = wout / (2 * math.pi)
        r = pv / (pv + pu)
        sr = r.sum()
        c, s = (r * np.cos(e)).sum(), (r * np.sin(e)).sum()
        mu_new = math.atan2(s, c)
        rbar = min(math.hypot(c, s) / sr, 0.999999)
        k_new = a1inv(rbar)
        w_new = float(1 - r.mean())
        done = abs(k_new - kappa) < 1e-6 * kappa and abs(w_new - wout) < 1e-8
        mu, kappa, wout = mu_new, k_new, w_new
        if done:
            break
    ll = float(np.log((1 - wout) * np.exp(kappa * np.cos(e - mu) - vm_log_norm(kappa)) + wout / (2 * math.pi)).sum())
    return math.degrees(mu), kappa, wout, ll


def distribution(e: np.ndarray) -> dict:
    a = np.abs(e)
    mu, kappa, wout, ll = fit_vm_uniform(e)
    e_r = np.radians(e)
    # Single von Mises and wrapped-normal-like comparison: log-likelihood of a pure von Mises ML fit.
    rbar = math.hypot(np.cos(e_r).mean(), np.sin(e_r).mean())
    k1 = a1inv(min(rbar, 0.999999)); m1 = math.atan2(np.sin(e_r).mean(), np.cos(e_r).mean())
    ll1 = float((k1 * np.cos(e_r - m1) - vm_log_norm(k1)).sum())
    return {
        "n": int(e.size),
        "circ_mean_deg": circ_mean_deg(e), "circ_median_deg": circ_median_deg(e), "circ_std_deg": circ_std_deg(e),
        "rms_deg": float(np.sqrt((e ** 2).mean())),
        "abs_q50_deg": float(np.quantile(a, 0.5)), "abs_q90_deg": float(np.quantile(a, 0.9)),
        "abs_q95_deg": float(np.quantile(a, 0.95)), "abs_q99_deg": float(np.quantile(a, 0.99)), "abs_max_deg": float(a.max()),
        "share_gt30": float((a > 30).mean()), "share_gt45": float((a > 45).mean()), "share_gt60": float((a > 60).mean()), "share_gt90": float((a > 90).mean()),
        "vm_mu_deg": mu, "vm_kappa": kappa, "vm_sigma_deg": math.degrees(1 / math.sqrt(kappa)),
        "outlier_share": wout, "loglik_mixture": ll, "loglik_single_vm": ll1, "single_vm_kappa": k1,
    }


def autocorrelation(series: list[tuple[np.ndarray, np.ndarray]], bin_width: float, max_lag: float, grid: float | None):
    """Pooled autocorrelation of errors (sin of the error, robust to wrap and outliers) against lag of the
    coordinate (distance or time). series: per walk (coordinate, error_deg). With grid, each walk's samples are
    first averaged into cells of that size (equal weight per metre). Returns lags, rho, pair counts."""
    nb = int(round(max_lag / bin_width)) + 1
    num = np.zeros(nb); den_a = np.zeros(nb); den_b = np.zeros(nb); cnt = np.zeros(nb)
    allv = np.concatenate([np.sin(np.radians(e)) for _, e in series])
    mean = allv.mean()
    for c, e in series:
        v = np.sin(np.radians(e)) - mean
        if grid is not None:
            cell = np.floor(c / grid).astype(int)
            u, inv = np.unique(cell, return_inverse=True)
            v = np.bincount(inv, weights=v) / np.bincount(inv)
            c = (u + 0.5) * grid
        lag = np.abs(c[:, None] - c[None, :])
        b = np.rint(lag / bin_width).astype(int)
        ok = b < nb
        prod = (v[:, None] * v[None, :])[ok]
        bb = b[ok]
        num += np.bincount(bb, weights=prod, minlength=nb)
        den_a += np.bincount(bb, weights=(v[:, None] ** 2 * np.ones_like(lag))[ok], minlength=nb)
        den_b += np.bincount(bb, weights=(np.ones_like(lag) * v[None, :] ** 2)[ok], minlength=nb)
        cnt += np.bincount(bb, minlength=nb)
    rho = num / np.sqrt(np.maximum(den_a * den_b, 1e-300))
    return np.arange(nb) * bin_width, rho, cnt


def correlation_length(lags, rho, cnt, min_pairs=50):
    """First lag where rho falls below 1/e (linear interpolation), and the least-squares exponential length over
    lags with rho > 0.05 before that crossing's double."""
    ok = cnt >= min_pairs
    l, r = lags[ok], rho[ok]
    cross = float("nan")
    for i in range(1, len(r)):
        if r[i] < 1 / math.e:
            cross = l[i - 1] + (l[i] - l[i - 1]) * (r[i - 1] - 1 / math.e) / max(r[i - 1] - r[i], 1e-12)
            break
    fit = float("nan")
    if not math.isnan(cross):
        sel = (l > 0) & (l <= 2 * cross) & (r > 0.05)
        if sel.sum() >= 2:
            # rho(d) = exp(-d / L): minimise sum (ln rho + d / L)^2 through the origin.
            x, y = l[sel], np.log(r[sel])
            fit = float(-(x * x).sum() / (x * y).sum())
    below = lambda th: next((float(l[i]) for i in range(len(r)) if r[i] < th), float("nan"))
    return {"one_over_e": cross, "exp_fit": fit, "rho_below_0.2": below(0.2), "rho_below_0.1": below(0.1)}


# ----------------------------------------------------------------------------------------------- main
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=DEFAULT_DATA, help="folder of the dataset (siteN/<floor>/path_data_files)")
    ap.add_argument("--trim", type=float, default=0.2, help="share of each leg's duration dropped at each end")
    ap.add_argument("--max-spread-deg", type=float, default=25.0,
                    help="drop legs whose smoothed gyro heading spread over the used middle exceeds this")
    ap.add_argument("--min-leg-m", type=float, default=3.0, help="shortest leg used, m")
    ap.add_argument("--json", help="also write every figure to this JSON file")
    args = ap.parse_args(argv)

    walks = load_walks(os.path.normpath(args.data))
    for w in walks:
        derive(w)
    stride = 5  # 50 Hz -> 10 Hz
    legs, counts = leg_samples(walks, args.trim, args.max_spread_deg, args.min_leg_m, stride)
    out: dict = {"walks": len(walks), "waypoints": int(sum(len(w.wp_t) for w in walks)), "legs": counts,
                 "used_leg_length_m": float(sum(
                     np.hypot(*(walks[L.walk].wp_xy[L.leg + 1] - walks[L.walk].wp_xy[L.leg])) for L in legs)),
                 "field_uT_median": float(np.median(np.concatenate([w.derived["field_uT"] for w in walks]))),
                 "field_uT_q05_q95": [float(np.quantile(np.concatenate([w.derived["field_uT"] for w in walks]), q))
                                      for q in (0.05, 0.95)],
                 "dip_deg_median": float(np.median(np.concatenate([w.derived["dip_deg"] for w in walks])))}

    print(f"{len(walks)} walks, {out['waypoints']} waypoints; legs {counts}; "
          f"{out['used_leg_length_m']:.0f} m of legs used (middle {100 * (1 - 2 * args.trim):.0f} % of each)")
    print(f"field magnitude median {out['field_uT_median']:.1f} uT (5-95 %: "
          f"{out['field_uT_q05_q95'][0]:.1f}-{out['field_uT_q05_q95'][1]:.1f}), dip median {out['dip_deg_median']:.1f} deg")

    for src in ("rv_az", "mag_az"):
        for truth in ("walk", "device"):
            key = f"{src}/{truth}"
            res: dict = {}
            # Offsets: per floor and per site (circular median of compass minus map bearing).
            floors = sorted({(walks[L.walk].site, walks[L.walk].floor) for L in legs})
            floor_off = {}
            for sf in floors:
                e = np.concatenate([L.raw[(src, truth)] for L in legs if (walks[L.walk].site, walks[L.walk].floor) == sf])
                floor_off[sf] = circ_median_deg(e)
            site_off = {}
            for site in sorted({s for s, _ in floors}):
                e = np.concatenate([L.raw[(src, truth)] for L in legs if walks[L.walk].site == site])
                site_off[site] = circ_median_deg(e)
            res["floor_offset_deg"] = {f"{s}/{f}": v for (s, f), v in floor_off.items()}
            res["site_offset_deg"] = site_off
            # Residuals under three references.
            e_site = [wrap_deg(L.raw[(src, truth)] - site_off[walks[L.walk].site]) for L in legs]
            e_floor = [wrap_deg(L.raw[(src, truth)] - floor_off[(walks[L.walk].site, walks[L.walk].floor)]) for L in legs]
            walk_off = {}
            for wi in sorted({L.walk for L in legs}):
                walk_off[wi] = circ_median_deg(np.concatenate([e for e, L in zip(e_floor, legs) if L.walk == wi]))
            e_walk = [wrap_deg(e - walk_off[L.walk]) for e, L in zip(e_floor, legs)]
            res["walk_offset_deg"] = {os.path.relpath(walks[wi].path, args.data): v for wi, v in walk_off.items()}
            wo = np.array(list(walk_off.values()))
            res["walk_offset_summary"] = {"median_abs": float(np.median(np.abs(wo))), "max_abs": float(np.abs(wo).max()),
                                          "circ_std": circ_std_deg(wo)}
            for name, es in (("site_offset", e_site), ("floor_offset", e_floor), ("floor_and_walk_offset", e_walk)):
                e = np.concatenate(es)
                d = distribution(e)
                leg_means = np.array([circ_mean_deg(x) for x in es])
                d["per_leg_mean_abs_q50_deg"] = float(np.quantile(np.abs(leg_means), 0.5))
                d["per_leg_mean_abs_q90_deg"] = float(np.quantile(np.abs(leg_means), 0.9))
                d["per_leg_mean_std_deg"] = circ_std_deg(leg_means)
                # Correlation over distance walked (0.5-m cells) and time (10 Hz), per walk.
                by_walk_s, by_walk_t = [], []
                for wi in sorted({L.walk for L in legs}):
                    sel = [(L, x) for L, x in zip(legs, es) if L.walk == wi]
                    by_walk_s.append((np.concatenate([L.s for L, _ in sel]), np.concatenate([x for _, x in sel])))
                    by_walk_t.append((np.concatenate([L.t for L, _ in sel]), np.concatenate([x for _, x in sel])))
                ls, rs, cs = autocorrelation(by_walk_s, 0.5, 40.0, grid=0.5)
                lt, rt, ct = autocorrelation(by_walk_t, 0.5, 40.0, grid=None)
                d["corr_distance_m"] = correlation_length(ls, rs, cs)
                d["corr_time_s"] = correlation_length(lt, rt, ct)
                d["rho_distance"] = {f"{l:g}": float(r) for l, r, c in zip(ls, rs, cs) if c >= 50 and l in
                                     (0.5, 1, 2, 3, 4, 5, 6, 8, 10, 15, 20, 30, 40)}
                d["rho_time"] = {f"{l:g}": float(r) for l, r, c in zip(lt, rt, ct) if c >= 50 and l in
                                 (0.5, 1, 2, 3, 5, 8, 10, 15, 20, 30, 40)}
                res[name] = d
            out[key] = res

            print(f"\n=== {src} vs {truth} heading ===")
            print("site offsets (compass - map bearing), deg: " + ", ".join(f"{k} {v:+.1f}" for k, v in site_off.items()))
            print("floor offsets, deg: " + ", ".join(f"{s}/{f} {v:+.1f}" for (s, f), v in floor_off.items()))
            print(f"per-walk phone offsets after floor offset: median |.| {res['walk_offset_summary']['median_abs']:.1f}, "
                  f"max |.| {res['walk_offset_summary']['max_abs']:.1f}, circ std {res['walk_offset_summary']['circ_std']:.1f} deg")
            for name in ("site_offset", "floor_offset", "floor_and_walk_offset"):
                d = res[name]
                print(f"[{name}] n={d['n']} mean {d['circ_mean_deg']:+.1f} median {d['circ_median_deg']:+.1f} "
                      f"circ-std {d['circ_std_deg']:.1f} rms {d['rms_deg']:.1f} | |e| q50 {d['abs_q50_deg']:.1f} "
                      f"q90 {d['abs_q90_deg']:.1f} q95 {d['abs_q95_deg']:.1f} q99 {d['abs_q99_deg']:.1f} max {d['abs_max_deg']:.0f} | "
                      f">30 {100 * d['share_gt30']:.1f}% >45 {100 * d['share_gt45']:.1f}% >60 {100 * d['share_gt60']:.2f}% >90 {100 * d['share_gt90']:.1f}%")
                print(f"    von Mises+uniform: mu {d['vm_mu_deg']:+.1f} kappa {d['vm_kappa']:.1f} (sigma "
                      f"{d['vm_sigma_deg']:.1f} deg) outlier share {100 * d['outlier_share']:.1f}% "
                      f"(loglik {d['loglik_mixture']:.0f} vs single VM {d['loglik_single_vm']:.0f}, kappa {d['single_vm_kappa']:.1f})")
                print(f"    per-leg mean |.| q50 {d['per_leg_mean_abs_q50_deg']:.1f} q90 {d['per_leg_mean_abs_q90_deg']:.1f} "
                      f"std {d['per_leg_mean_std_deg']:.1f} deg")
                cd, ct_ = d["corr_distance_m"], d["corr_time_s"]
                print(f"    corr length over distance: 1/e {cd['one_over_e']:.1f} m, exp fit {cd['exp_fit']:.1f} m, "
                      f"rho<0.2 at {cd['rho_below_0.2']:.1f} m, rho<0.1 at {cd['rho_below_0.1']:.1f} m")
                print("      rho(d): " + " ".join(f"{k}m:{v:.2f}" for k, v in d["rho_distance"].items()))
                print(f"    corr time: 1/e {ct_['one_over_e']:.1f} s, exp fit {ct_['exp_fit']:.1f} s, rho<0.2 at "
                      f"{ct_['rho_below_0.2']:.1f} s")
                print("      rho(t): " + " ".join(f"{k}s:{v:.2f}" for k, v in d["rho_time"].items()))

    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
