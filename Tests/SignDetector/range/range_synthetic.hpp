// Synthetic scenes for the range tests: an upright rectangular sign at a known horizontal range and
// bearing, projected exactly by a pinhole camera with an ARKit-style rotation R = Ry(yaw) Rx(pitch) Rz(roll)
// (world y up, camera looks along -z, pixel (u, v) = (cx + fx x/-z, cy - fy y/-z)), plus the slice
// measurement of the sign's mask in the unrolled image. Independent of the code under test except for the
// unroll map (which has its own test against this projection).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "wf_range.h"

namespace wf::range::test {

constexpr double kPi = 3.14159265358979323846;
inline double deg(double d) { return d * kPi / 180.0; }

/// iPhone 8 at 1920 x 1440 (arkit-frames.md).
inline wf_range_intrinsics iphone8() { return {1602, 1602, 960, 720}; }
constexpr double kImageWidth = 1920, kImageHeight = 1440;

/// A scene: camera at the origin with yaw/pitch/roll, sign given relative to the camera.
struct Scene {
    wf_range_intrinsics k = iphone8();
    double yawRad = 0;    ///< ARKit Euler yaw (about world y)
    double pitchRad = 0;  ///< elevation of the optical axis
    double rollRad = 0;   ///< 0 landscape, -pi/2 portrait
    double rangeM = 3;    ///< horizontal distance camera -> sign centre line
    double bearingRad = 0;  ///< from camera forward, positive left
    double centerHeightAboveCameraM = 0.2;
    double facingRad = 0;  ///< sign normal's rotation from facing the camera exactly, about world y
    double signHeightM = 0.21;
    double signWidthM = 0.40;
};

/// Camera-to-world rotation R = Ry(yaw) Rx(pitch) Rz(roll) (ARKit eulerAngles order).
inline Eigen::Matrix3d rotation(const Scene &s) {
    return (Eigen::AngleAxisd(s.yawRad, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(s.pitchRad, Eigen::Vector3d::UnitX()) *
            Eigen::AngleAxisd(s.rollRad, Eigen::Vector3d::UnitZ()))
        .toRotationMatrix();
}

/// Column-major 4x4 of the rotation (zero translation).
inline std::array<double, 16> columnMajor(const Eigen::Matrix3d &r) {
    std::array<double, 16> m{};
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) m[static_cast<std::size_t>(c * 4 + row)] = r(row, c);
    m[15] = 1;
    return m;
}

/// Horizontal unit direction at bearing b (left positive) from the camera's horizontal forward.
inline Eigen::Vector3d horizontalDirection(const Scene &s) {
    const Eigen::Vector3d f = -rotation(s).col(2);
    const double az = std::atan2(-f.z(), f.x()) + s.bearingRad;  // CCW from +x toward -z
    return {std::cos(az), 0, -std::sin(az)};
}

/// World positions of the sign centre and corners TL, TR, BR, BL.
struct SignWorld {
    Eigen::Vector3d center, topCenter, bottomCenter;
    std::array<Eigen::Vector3d, 4> corners;
};

inline SignWorld signInWorld(const Scene &s) {
    const Eigen::Vector3d d = horizontalDirection(s);
    SignWorld w;
    w.center = s.rangeM * d + Eigen::Vector3d(0, s.centerHeightAboveCameraM, 0);
    // Normal toward the camera, then turned by facingRad about world up.
    const Eigen::Vector3d n = Eigen::AngleAxisd(s.facingRad, Eigen::Vector3d::UnitY()) * (-d);
    const Eigen::Vector3d up(0, 1, 0);
    const Eigen::Vector3d right = (-n).cross(up).normalized();  // viewer's right when facing the sign
    const double hw = 0.5 * s.signWidthM, hh = 0.5 * s.signHeightM;
    w.corners = {w.center - hw * right + hh * up, w.center + hw * right + hh * up,
                 w.center + hw * right - hh * up, w.center - hw * right - hh * up};
    w.topCenter = w.center + hh * up;
    w.bottomCenter = w.center - hh * up;
    return w;
}

/// Projects a world point (camera at the origin); nullopt when behind the camera.
inline std::optional<Eigen::Vector2d> project(const Scene &s, const Eigen::Vector3d &p) {
    const Eigen::Vector3d c = rotation(s).transpose() * p;
    if (!(c.z() < -1e-9)) return std::nullopt;
    return Eigen::Vector2d(s.k.cx + s.k.fx * c.x() / -c.z(), s.k.cy - s.k.fy * c.y() / -c.z());
}

/// Raw-image corners of the sign, TL TR BR BL; nullopt when a corner is behind the camera or outside the
/// image (with a margin of 2 px).
inline std::optional<std::array<wf_range_point, 4>> projectCorners(const Scene &s, bool requireInImage = true) {
    const SignWorld w = signInWorld(s);
    std::array<wf_range_point, 4> out{};
    for (std::size_t i = 0; i < 4; ++i) {
        const auto p = project(s, w.corners[i]);
        if (!p) return std::nullopt;
        if (requireInImage && (p->x() < 2 || p->x() > kImageWidth - 2 || p->y() < 2 || p->y() > kImageHeight - 2))
            return std::nullopt;
        out[i] = {p->x(), p->y()};
    }
    return out;
}

/// An observation for wf_range_estimate from a scene and (possibly noisy) corners.
inline wf_range_observation observation(const Scene &s, const std::array<wf_range_point, 4> &corners,
                                        double cameraHeightM = 1.4) {
    wf_range_observation o = WF_RANGE_OBSERVATION_INIT;
    for (std::size_t i = 0; i < 4; ++i) o.corners[i] = corners[i];
    o.intrinsics = s.k;
    const auto m = columnMajor(rotation(s));
    std::copy(m.begin(), m.end(), o.camera_to_world);
    o.sign_height_m = s.signHeightM;
    o.sign_width_m = s.signWidthM;
    o.camera_height_m = cameraHeightM;
    o.sign_center_height_m = cameraHeightM + s.centerHeightAboveCameraM;
    return o;
}

/// Per-column edges of the sign's mask in the unrolled image: the corners unrolled, the convex polygon cut
/// by vertical lines at integer columns. Optional per-column Gaussian noise (sigma px) on both edges, an
/// optional whole-edge offset (one Gaussian draw of edgeBiasSigmaPx per edge, as a blurred or dilated mask
/// shifts a whole edge) and rounding of the edges to the pixel grid (edges at integer + 0.5, as a binary
/// mask gives).
struct Slices {
    std::vector<double> columnU, topRow, bottomRow;
};

inline Slices maskSlices(const wf_range_unroll_map &map, const std::array<wf_range_point, 4> &rawCorners,
                         double noiseSigmaPx = 0, bool quantize = false, std::mt19937_64 *rng = nullptr,
                         double edgeBiasSigmaPx = 0) {
    std::array<Eigen::Vector2d, 4> p;
    for (std::size_t i = 0; i < 4; ++i) {
        wf_range_point q{};
        wf_range_unroll_point(&q, &map, &rawCorners[i]);
        p[i] = {q.u, q.v};
    }
    double minU = p[0].x(), maxU = p[0].x();
    for (const auto &q : p) minU = std::min(minU, q.x()), maxU = std::max(maxU, q.x());
    Slices s;
    std::normal_distribution<double> noise(0.0, 1.0);
    double topBias = 0, bottomBias = 0;
    if (edgeBiasSigmaPx > 0 && rng) {
        topBias = edgeBiasSigmaPx * noise(*rng);
        bottomBias = edgeBiasSigmaPx * noise(*rng);
    }
    for (double u = std::ceil(minU); u <= std::floor(maxU); u += 1.0) {
        double top = 1e300, bottom = -1e300;
        for (std::size_t i = 0; i < 4; ++i) {
            const Eigen::Vector2d a = p[i], b = p[(i + 1) % 4];
            const double lo = std::min(a.x(), b.x()), hi = std::max(a.x(), b.x());
            if (u < lo || u > hi || hi - lo < 1e-12) continue;
            const double t = (u - a.x()) / (b.x() - a.x());
            const double v = a.y() + t * (b.y() - a.y());
            top = std::min(top, v);
            bottom = std::max(bottom, v);
        }
        if (!(bottom > top)) continue;
        top += topBias;
        bottom += bottomBias;
        if (noiseSigmaPx > 0 && rng) {
            top += noiseSigmaPx * noise(*rng);
            bottom += noiseSigmaPx * noise(*rng);
        }
        if (quantize) {
            top = std::round(top - 0.5) + 0.5;
            bottom = std::round(bottom - 0.5) + 0.5;
        }
        if (!(bottom > top)) continue;
        s.columnU.push_back(u);
        s.topRow.push_back(top);
        s.bottomRow.push_back(bottom);
    }
    return s;
}

/// The unrolled camera of a scene (pitch and roll known, as from gravity).
inline wf_range_unrolled_camera unrolledCamera(const Scene &s, const wf_range_unroll_map &map) {
    return {map.unrolled.fx, map.unrolled.fy, map.unrolled.cx, map.unrolled.cy, s.pitchRad, s.rollRad};
}

/// Relative error |e - a| / a.
inline double relativeError(double estimate, double truth) { return std::abs(estimate - truth) / truth; }

/// Wraps an angle to (-pi, pi].
inline double wrap(double a) {
    a = std::remainder(a, 2 * kPi);
    return a <= -kPi ? a + 2 * kPi : a;
}

/// A random visible scene of a wall-mounted sign: its centre 0.6-1.0 m above the camera (an Exit sign at
/// about 2.2 m, the phone at 1.2-1.6 m), camera pitch in +-30 deg, roll in [-90, 90] deg, yaw any, bearing
/// +-14 deg, sign turned up to +-35 deg from facing the camera. Retries until all corners are inside the
/// image (at 1 m only upward pitches see the sign).
inline Scene randomMountedSignScene(std::mt19937_64 &rng, double rangeM) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (;;) {
        Scene s;
        s.yawRad = kPi * unit(rng);
        s.pitchRad = deg(30) * unit(rng);
        s.rollRad = deg(90) * unit(rng);
        s.rangeM = rangeM;
        s.bearingRad = deg(14) * unit(rng);
        s.centerHeightAboveCameraM = 0.8 + 0.2 * unit(rng);
        s.facingRad = deg(35) * unit(rng);
        if (projectCorners(s)) return s;
    }
}

}  // namespace wf::range::test
