// C ABI of range estimation (wf_range.h): argument checks, conversion to the internal C++ API, and a
// catch-all so that no exception crosses the boundary.
#include "wf_range.h"

#include "range_geometry.hpp"

#include <cmath>
#include <exception>

using wf::range::Corners;
using wf::range::Intrinsics;
using wf::range::RangeBearing;
using wf::range::Status;

namespace {

Intrinsics toIntrinsics(const wf_range_intrinsics &k) { return {k.fx, k.fy, k.cx, k.cy}; }

Corners toCorners(const wf_range_point corners[4]) {
    Corners c;
    for (int i = 0; i < 4; ++i) c[static_cast<std::size_t>(i)] = {corners[i].u, corners[i].v};
    return c;
}

void toResult(const RangeBearing &r, wf_range_result *out) {
    out->range_m = r.rangeMeters;
    out->bearing_rad = r.bearingRad;
    out->center_height_above_camera_m = r.centerHeightAboveCameraMeters;
}

/// Runs f, mapping any exception to WF_STATUS_INTERNAL.
template <typename F>
int guarded(F &&f) noexcept {
    try {
        return f();
    } catch (...) {
        return WF_STATUS_INTERNAL;
    }
}

}  // namespace

extern "C" {

int wf_range_camera_to_world_from_pitch_roll(double out_camera_to_world[16], double pitch_rad, double roll_rad) {
    if (!out_camera_to_world) return WF_STATUS_INVALID_ARGUMENT;
    if (!std::isfinite(pitch_rad) || !std::isfinite(roll_rad)) return WF_STATUS_NON_FINITE_INPUT;
    return guarded([&]() -> int {
        const Eigen::Matrix3d r = wf::range::rotationFromPitchRoll(pitch_rad, roll_rad);
        for (int i = 0; i < 16; ++i) out_camera_to_world[i] = 0;
        for (int col = 0; col < 3; ++col)
            for (int row = 0; row < 3; ++row) out_camera_to_world[col * 4 + row] = r(row, col);
        out_camera_to_world[15] = 1;
        return WF_STATUS_OK;
    });
}

int wf_range_pitch_roll_from_camera_to_world(double *out_pitch_rad, double *out_roll_rad,
                                             const double camera_to_world[16]) {
    if (!out_pitch_rad || !out_roll_rad || !camera_to_world) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        Eigen::Matrix3d r;
        if (const Status s = wf::range::rotationFromColumnMajor(camera_to_world, &r); s != WF_STATUS_OK) return s;
        wf::range::pitchRollFromRotation(r, out_pitch_rad, out_roll_rad);
        return WF_STATUS_OK;
    });
}

int wf_range_unroll_map_make(wf_range_unroll_map *out_map, const wf_range_intrinsics *raw, double roll_rad,
                             double image_width_px, double image_height_px) {
    if (!out_map || !raw) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        return wf::range::makeUnrollMap(toIntrinsics(*raw), roll_rad, image_width_px, image_height_px, out_map);
    });
}

namespace {
/// Checks a map made by wf_range_unroll_map_make (finite, positive focal lengths).
Status checkMap(const wf_range_unroll_map &m) {
    const double v[9] = {m.raw.fx, m.raw.fy, m.raw.cx, m.raw.cy, m.roll_rad,
                         m.unrolled.fx, m.unrolled.fy, m.unrolled.cx, m.unrolled.cy};
    if (!wf::range::allFinite(v, 9)) return WF_STATUS_NON_FINITE_INPUT;
    if (!(m.raw.fx > 0) || !(m.raw.fy > 0) || !(m.unrolled.fx > 0) || !(m.unrolled.fy > 0))
        return WF_STATUS_NONPOSITIVE_SIZE;
    return WF_STATUS_OK;
}
}  // namespace

int wf_range_unroll_point(wf_range_point *out_unrolled, const wf_range_unroll_map *map, const wf_range_point *raw) {
    if (!out_unrolled || !map || !raw) return WF_STATUS_INVALID_ARGUMENT;
    if (const Status s = checkMap(*map); s != WF_STATUS_OK) return s;
    if (!std::isfinite(raw->u) || !std::isfinite(raw->v)) return WF_STATUS_NON_FINITE_INPUT;
    const Eigen::Vector2d p = wf::range::unrollPoint(*map, {raw->u, raw->v});
    *out_unrolled = {p.x(), p.y()};
    return WF_STATUS_OK;
}

int wf_range_reroll_point(wf_range_point *out_raw, const wf_range_unroll_map *map, const wf_range_point *unrolled) {
    if (!out_raw || !map || !unrolled) return WF_STATUS_INVALID_ARGUMENT;
    if (const Status s = checkMap(*map); s != WF_STATUS_OK) return s;
    if (!std::isfinite(unrolled->u) || !std::isfinite(unrolled->v)) return WF_STATUS_NON_FINITE_INPUT;
    const Eigen::Vector2d p = wf::range::rerollPoint(*map, {unrolled->u, unrolled->v});
    *out_raw = {p.x(), p.y()};
    return WF_STATUS_OK;
}

int wf_range_paper_equation3(double *out_range_m, double pitch_rad, double alpha_rad, double delta_rad,
                             double sign_height_m) {
    if (!out_range_m) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int { return wf::range::paperEquation3(pitch_rad, alpha_rad, delta_rad, sign_height_m, out_range_m); });
}

int wf_range_apparent_height_slices(wf_range_result *out, const wf_range_unrolled_camera *camera,
                                    const wf_range_slice_measurement *measurement, double sign_height_m,
                                    wf_range_slice_model model) {
    if (!out || !camera || !measurement) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        RangeBearing r;
        const Status s = wf::range::apparentHeightSlices(*camera, *measurement, sign_height_m, model, &r);
        if (s == WF_STATUS_OK) toResult(r, out);
        return s;
    });
}

int wf_range_slice_measurement_from_columns(wf_range_slice_measurement *out, const double *column_u,
                                            const double *top_row, const double *bottom_row, size_t count) {
    if (!out || ((!column_u || !top_row || !bottom_row) && count > 0)) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int { return wf::range::sliceMeasurementFromColumns(column_u, top_row, bottom_row, count, out); });
}

int wf_range_apparent_height_exact(wf_range_result *out, const wf_range_point *top_center,
                                   const wf_range_point *bottom_center, const wf_range_intrinsics *intrinsics,
                                   const double camera_to_world[16], double sign_height_m) {
    if (!out || !top_center || !bottom_center || !intrinsics || !camera_to_world) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        Eigen::Matrix3d r;
        if (const Status s = wf::range::rotationFromColumnMajor(camera_to_world, &r); s != WF_STATUS_OK) return s;
        RangeBearing result;
        const Status s = wf::range::apparentHeightExact({top_center->u, top_center->v},
                                                        {bottom_center->u, bottom_center->v},
                                                        toIntrinsics(*intrinsics), r, sign_height_m, &result);
        if (s == WF_STATUS_OK) toResult(result, out);
        return s;
    });
}

int wf_range_horizon(wf_range_result *out, const wf_range_point *center, const wf_range_intrinsics *intrinsics,
                     const double camera_to_world[16], double camera_height_m, double sign_center_height_m) {
    if (!out || !center || !intrinsics || !camera_to_world) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        Eigen::Matrix3d r;
        if (const Status s = wf::range::rotationFromColumnMajor(camera_to_world, &r); s != WF_STATUS_OK) return s;
        RangeBearing result;
        const Status s = wf::range::horizon({center->u, center->v}, toIntrinsics(*intrinsics), r, camera_height_m,
                                            sign_center_height_m, &result);
        if (s == WF_STATUS_OK) toResult(result, out);
        return s;
    });
}

int wf_range_sign_center_points(wf_range_point *out_center, wf_range_point *out_top_center,
                                wf_range_point *out_bottom_center, const wf_range_point corners[4]) {
    if (!out_center || !out_top_center || !out_bottom_center || !corners) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        Eigen::Vector2d c, t, b;
        const Status s = wf::range::signCenterPoints(toCorners(corners), &c, &t, &b);
        if (s != WF_STATUS_OK) return s;
        *out_center = {c.x(), c.y()};
        *out_top_center = {t.x(), t.y()};
        *out_bottom_center = {b.x(), b.y()};
        return WF_STATUS_OK;
    });
}

int wf_range_pnp(wf_range_result *out, const wf_range_point corners[4], const wf_range_intrinsics *intrinsics,
                 const double camera_to_world[16], double sign_width_m, double sign_height_m) {
    if (!out || !corners || !intrinsics || !camera_to_world) return WF_STATUS_INVALID_ARGUMENT;
    return guarded([&]() -> int {
        Eigen::Matrix3d r;
        if (const Status s = wf::range::rotationFromColumnMajor(camera_to_world, &r); s != WF_STATUS_OK) return s;
        RangeBearing result;
        const Status s = wf::range::estimatePnP(toCorners(corners), toIntrinsics(*intrinsics), r, sign_width_m,
                                                sign_height_m, &result);
        if (s == WF_STATUS_OK) toResult(result, out);
        return s;
    });
}

int wf_range_estimate(wf_range_result *out, wf_range_method method, const wf_range_observation *observation) {
    if (!out || !observation) return WF_STATUS_INVALID_ARGUMENT;
    if (observation->version != WF_RANGE_OBSERVATION_VERSION) return WF_STATUS_VERSION;
    const wf_range_observation &o = *observation;
    switch (method) {
    case WF_RANGE_METHOD_APPARENT_HEIGHT: {
        wf_range_point center, top, bottom;
        if (const int s = wf_range_sign_center_points(&center, &top, &bottom, o.corners); s != WF_STATUS_OK) return s;
        return wf_range_apparent_height_exact(out, &top, &bottom, &o.intrinsics, o.camera_to_world, o.sign_height_m);
    }
    case WF_RANGE_METHOD_HORIZON: {
        wf_range_point center, top, bottom;
        if (const int s = wf_range_sign_center_points(&center, &top, &bottom, o.corners); s != WF_STATUS_OK) return s;
        return wf_range_horizon(out, &center, &o.intrinsics, o.camera_to_world, o.camera_height_m,
                                o.sign_center_height_m);
    }
    case WF_RANGE_METHOD_PNP:
        return wf_range_pnp(out, o.corners, &o.intrinsics, o.camera_to_world, o.sign_width_m, o.sign_height_m);
    default:
        return WF_STATUS_MISSING_INPUT;
    }
}

}  // extern "C"
