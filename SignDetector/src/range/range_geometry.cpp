// Geometry of range estimation: rays, elevations, the apparent-height and horizon methods, the corner
// constructions and point unrolling. Derivations: docs/range-estimation.md.
#include "range_geometry.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <vector>

namespace wf::range {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Fraction of the extent, centred, whose columns give the medians and slopes (the SignDetector's default
/// slice band is the same 0.6).
constexpr double kSliceBandFraction = 0.6;

/// Wraps an angle to (-pi, pi].
double wrapAngle(double a) {
    a = std::remainder(a, 2 * kPi);
    return a <= -kPi ? a + 2 * kPi : a;
}

/// Azimuth of a world direction seen from above, CCW from world +x toward world -z (VIO east -> north).
double azimuth(const Eigen::Vector3d &d) { return std::atan2(-d.z(), d.x()); }

/// Median of a copy of the values (mean of the two middle ones for an even count). count >= 1.
double median(std::vector<double> values) {
    const std::size_t n = values.size();
    const std::size_t mid = n / 2;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
    const double upper = values[mid];
    if (n % 2 == 1) return upper;
    const double lower = *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
    return 0.5 * (lower + upper);
}

/// Homogeneous point of a pixel.
Eigen::Vector3d homogeneous(const Eigen::Vector2d &p) { return {p.x(), p.y(), 1.0}; }

/// Normalised cross product (join of points / meet of lines); zero vector stays zero.
Eigen::Vector3d joinOrMeet(const Eigen::Vector3d &a, const Eigen::Vector3d &b) {
    Eigen::Vector3d c = a.cross(b);
    const double n = c.norm();
    return n > 0 ? Eigen::Vector3d(c / n) : c;
}

/// Dehomogenises a unit-norm homogeneous point of O(1) normalised coordinates; false when at infinity.
bool finitePoint(const Eigen::Vector3d &h, Eigen::Vector2d *out) {
    if (!(std::abs(h.z()) > 1e-12)) return false;
    *out = h.head<2>() / h.z();
    return out->allFinite();
}

}  // namespace

bool allFinite(const double *values, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i)
        if (!std::isfinite(values[i])) return false;
    return true;
}

Status checkIntrinsics(const Intrinsics &k) {
    const double v[4] = {k.fx, k.fy, k.cx, k.cy};
    if (!allFinite(v, 4)) return WF_STATUS_NON_FINITE_INPUT;
    if (!(k.fx > 0) || !(k.fy > 0)) return WF_STATUS_NONPOSITIVE_SIZE;
    return WF_STATUS_OK;
}

Status rotationFromColumnMajor(const double cameraToWorld[16], Eigen::Matrix3d *outRotation) {
    if (!allFinite(cameraToWorld, 16)) return WF_STATUS_NON_FINITE_INPUT;
    Eigen::Matrix3d r;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) r(row, col) = cameraToWorld[col * 4 + row];
    const double orthoError = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (!(orthoError < 1e-3) || !(std::abs(r.determinant() - 1.0) < 1e-3)) return WF_STATUS_NOT_A_ROTATION;
    *outRotation = r;
    return WF_STATUS_OK;
}

Eigen::Matrix3d rotationFromPitchRoll(double pitchRad, double rollRad) {
    return (Eigen::AngleAxisd(pitchRad, Eigen::Vector3d::UnitX()) *
            Eigen::AngleAxisd(rollRad, Eigen::Vector3d::UnitZ()))
        .toRotationMatrix();
}

void pitchRollFromRotation(const Eigen::Matrix3d &r, double *pitchRad, double *rollRad) {
    const Eigen::Vector3d forward = -r.col(2);
    *pitchRad = std::asin(std::clamp(forward.y(), -1.0, 1.0));
    // up = R^T * (0, 1, 0): the world-y components of the camera axes (row 1 of R).
    *rollRad = std::atan2(r(1, 0), r(1, 1));
}

Eigen::Vector3d rayInWorld(const Eigen::Matrix3d &r, const Intrinsics &k, double u, double v) {
    return r * Eigen::Vector3d((u - k.cx) / k.fx, -(v - k.cy) / k.fy, -1.0);
}

bool tanElevation(const Eigen::Vector3d &ray, double *outTan) {
    const double horizontal = std::hypot(ray.x(), ray.z());
    if (!(horizontal > 1e-12 * ray.norm())) return false;
    *outTan = ray.y() / horizontal;
    return std::isfinite(*outTan);
}

bool bearingFromForward(const Eigen::Matrix3d &r, const Eigen::Vector3d &d, double *outBearingRad) {
    const Eigen::Vector3d forward = -r.col(2);
    if (!(std::hypot(forward.x(), forward.z()) > 1e-9)) return false;
    if (!(std::hypot(d.x(), d.z()) > 1e-12 * d.norm())) return false;
    *outBearingRad = wrapAngle(azimuth(d) - azimuth(forward));
    return true;
}

Status apparentHeightFromRays(const Eigen::Matrix3d &r, const Eigen::Vector3d &topRay,
                              const Eigen::Vector3d &bottomRay, double signHeightMeters, RangeBearing *out) {
    if (!std::isfinite(signHeightMeters)) return WF_STATUS_NON_FINITE_INPUT;
    if (!(signHeightMeters > 0)) return WF_STATUS_NONPOSITIVE_SIZE;
    double tanTop = 0, tanBottom = 0;
    if (!tanElevation(topRay, &tanTop) || !tanElevation(bottomRay, &tanBottom))
        return WF_STATUS_DEGENERATE_GEOMETRY;
    // tan(e) = height above camera / horizontal distance for both points of one vertical line, so the
    // difference of tangents is h0 / Z (paper eq. 1-3, written with elevations instead of pitch + angle).
    const double difference = tanTop - tanBottom;
    if (!(difference > 0)) return WF_STATUS_DEGENERATE_GEOMETRY;
    const double range = signHeightMeters / difference;
    if (!std::isfinite(range)) return WF_STATUS_DEGENERATE_GEOMETRY;
    // Both rays lie in the same vertical plane when exact; with noise, average their horizontal unit
    // directions.
    Eigen::Vector3d top(topRay.x(), 0, topRay.z()), bottom(bottomRay.x(), 0, bottomRay.z());
    const Eigen::Vector3d mean = top.normalized() + bottom.normalized();
    double bearing = 0;
    if (!bearingFromForward(r, mean, &bearing)) return WF_STATUS_DEGENERATE_GEOMETRY;
    out->rangeMeters = range;
    out->bearingRad = bearing;
    out->centerHeightAboveCameraMeters = 0.5 * (tanTop + tanBottom) * range;
    return WF_STATUS_OK;
}

Status apparentHeightExact(const Eigen::Vector2d &topCenterPx, const Eigen::Vector2d &bottomCenterPx,
                           const Intrinsics &k, const Eigen::Matrix3d &r, double signHeightMeters,
                           RangeBearing *out) {
    if (!topCenterPx.allFinite() || !bottomCenterPx.allFinite()) return WF_STATUS_NON_FINITE_INPUT;
    if (const Status s = checkIntrinsics(k); s != WF_STATUS_OK) return s;
    return apparentHeightFromRays(r, rayInWorld(r, k, topCenterPx.x(), topCenterPx.y()),
                                  rayInWorld(r, k, bottomCenterPx.x(), bottomCenterPx.y()), signHeightMeters,
                                  out);
}

Status paperEquation3(double pitchRad, double alphaRad, double deltaRad, double signHeightMeters,
                      double *outRangeMeters) {
    const double v[4] = {pitchRad, alphaRad, deltaRad, signHeightMeters};
    if (!allFinite(v, 4)) return WF_STATUS_NON_FINITE_INPUT;
    if (!(signHeightMeters > 0)) return WF_STATUS_NONPOSITIVE_SIZE;
    const double bottom = pitchRad + alphaRad;
    const double top = bottom + deltaRad;
    if (!(std::abs(bottom) < kPi / 2) || !(std::abs(top) < kPi / 2)) return WF_STATUS_DEGENERATE_GEOMETRY;
    const double difference = std::tan(top) - std::tan(bottom);
    if (!(difference > 0)) return WF_STATUS_DEGENERATE_GEOMETRY;
    const double range = signHeightMeters / difference;
    if (!std::isfinite(range)) return WF_STATUS_DEGENERATE_GEOMETRY;
    *outRangeMeters = range;
    return WF_STATUS_OK;
}

namespace {

/// Reconstructs the sign's corners TL, TR, BR, BL in the unrolled image from a slice measurement: the top
/// and bottom edge lines (medians at the extent's middle and slopes), the extent's ends, and the side edges,
/// which are images of world verticals and so pass through the vertical vanishing point
/// (cx, cy - fy / tan(pitch)) (at infinity, straight down, for pitch 0). Each extent end is a corner on the
/// top or the bottom edge: the right one is the choice whose side line leaves the other corner inside the
/// extent. False when degenerate (then the caller falls back to the centre-column construction).
bool cornersFromSlices(const wf_range_unrolled_camera &camera, const wf_range_slice_measurement &m,
                       Corners *out) {
    const double middle = m.center_column_px;
    const double left = middle - 0.5 * m.extent_width_px, right = middle + 0.5 * m.extent_width_px;
    // Edge line v = v0 + slope (u - middle) as homogeneous (a, b, c) with a u + b v + c = 0.
    auto edgeLine = [&](double v0, double slope) { return Eigen::Vector3d(slope, -1.0, v0 - slope * middle); };
    const Eigen::Vector3d bottom = edgeLine(m.median_bottom_row_px, m.bottom_edge_slope);
    const Eigen::Vector3d top = edgeLine(m.median_bottom_row_px - m.median_height_px, m.top_edge_slope);
    const double tanPitch = std::tan(camera.pitch_rad);
    const Eigen::Vector3d vanishing(camera.cx * tanPitch, camera.cy * tanPitch - camera.fy, tanPitch);
    auto meet = [](const Eigen::Vector3d &a, const Eigen::Vector3d &b, Eigen::Vector2d *p) {
        const Eigen::Vector3d h = a.cross(b);
        if (!(std::abs(h.z()) > 1e-12 * h.head<2>().norm())) return false;
        *p = h.head<2>() / h.z();
        return p->allFinite();
    };
    auto sideLine = [&](double u, bool isLeft, Eigen::Vector3d *line) {
        const double tolerance = 1e-6 * (1.0 + m.extent_width_px);
        for (int onTop = 1; onTop >= 0; --onTop) {
            const Eigen::Vector3d &edge = onTop ? top : bottom;
            const Eigen::Vector3d &other = onTop ? bottom : top;
            const Eigen::Vector3d corner(u, edge.x() * u + edge.z(), 1.0);  // v = a u + c on the edge
            const Eigen::Vector3d candidate = vanishing.cross(corner);
            Eigen::Vector2d q;
            if (!meet(candidate, other, &q)) continue;
            if (isLeft ? q.x() >= u - tolerance : q.x() <= u + tolerance) {
                *line = candidate;
                return true;
            }
        }
        return false;
    };
    Eigen::Vector3d leftLine, rightLine;
    if (!sideLine(left, true, &leftLine) || !sideLine(right, false, &rightLine)) return false;
    Corners c;
    return meet(leftLine, top, &c[0]) && meet(rightLine, top, &c[1]) && meet(rightLine, bottom, &c[2]) &&
           meet(leftLine, bottom, &c[3]) && (*out = c, true);
}

}  // namespace

Status apparentHeightSlices(const wf_range_unrolled_camera &camera, const wf_range_slice_measurement &m,
                            double signHeightMeters, wf_range_slice_model model, RangeBearing *out) {
    const double v[12] = {camera.fx, camera.fy, camera.cx, camera.cy, camera.pitch_rad,
                          m.median_bottom_row_px, m.median_height_px, m.center_column_px,
                          m.bottom_edge_slope, m.top_edge_slope, m.extent_width_px, signHeightMeters};
    if (!allFinite(v, 12)) return WF_STATUS_NON_FINITE_INPUT;
    if (m.extent_width_px < 0) return WF_STATUS_NONPOSITIVE_SIZE;
    if (!(camera.fx > 0) || !(camera.fy > 0) || !(m.median_height_px > 0) || !(signHeightMeters > 0))
        return WF_STATUS_NONPOSITIVE_SIZE;
    if (!(std::abs(camera.pitch_rad) < kPi / 2)) return WF_STATUS_DEGENERATE_GEOMETRY;
    if (model != WF_RANGE_SLICE_MODEL_RAY_ELEVATION && model != WF_RANGE_SLICE_MODEL_PAPER_PLANAR)
        return WF_STATUS_MISSING_INPUT;

    // The unrolled image is a camera with roll 0: R' = Rx(pitch) (yaw irrelevant).
    const Eigen::Matrix3d r = rotationFromPitchRoll(camera.pitch_rad, 0.0);
    const Intrinsics intrinsics{camera.fx, camera.fy, camera.cx, camera.cy};

    // Two points of the sign's vertical centre line: exactly from the reconstructed corners when the
    // extent is known, else on the image of the world vertical through the bottom point at the centre column.
    Eigen::Vector2d topPoint, bottomPoint;
    Corners corners;
    Eigen::Vector2d center;
    if (!(m.extent_width_px > 0 && cornersFromSlices(camera, m, &corners) &&
          signCenterPoints(corners, &center, &topPoint, &bottomPoint) == WF_STATUS_OK)) {
        const double column = m.center_column_px;
        const double bottomRow = m.median_bottom_row_px;
        const double topRow = m.median_bottom_row_px - m.median_height_px;
        // World verticals converge in the unrolled image of a pitched camera, to the vanishing point
        // (cx, cy - fy / tan(pitch)) (camera coordinates of world up: (0, cos p, -sin p)). The image of the
        // world vertical through B = (column, bottomRow) is u = column + k (v - bottomRow) with
        // k = (column - cx) tan p / ((bottomRow - cy) tan p + fy); the top point is where it meets the top edge
        // v = topRow + topSlope (u - column). Without this the column's own top point lies beside the sign's
        // centre line: a 1-3 % range error at 30 degrees of pitch and 12 of bearing.
        const double tanPitch = std::tan(camera.pitch_rad);
        const double toVanishing = (bottomRow - camera.cy) * tanPitch + camera.fy;
        if (!(std::abs(toVanishing) > 1e-9 * camera.fy)) return WF_STATUS_DEGENERATE_GEOMETRY;
        const double k = (column - camera.cx) * tanPitch / toVanishing;
        const double topSlope = m.top_edge_slope;
        const double denominator = 1.0 - topSlope * k;
        if (!(std::abs(denominator) > 1e-9)) return WF_STATUS_DEGENERATE_GEOMETRY;
        const double topPointRow = (topRow - topSlope * k * bottomRow) / denominator;
        topPoint = {column + k * (topPointRow - bottomRow), topPointRow};
        bottomPoint = {column, bottomRow};
    }

    RangeBearing result;
    if (const Status s = apparentHeightFromRays(r, rayInWorld(r, intrinsics, topPoint.x(), topPoint.y()),
                                                rayInWorld(r, intrinsics, bottomPoint.x(), bottomPoint.y()),
                                                signHeightMeters, &result);
        s != WF_STATUS_OK)
        return s;
    if (model == WF_RANGE_SLICE_MODEL_PAPER_PLANAR) {
        // Paper, verbatim on the medians: alpha = angle of the bottom row above the optical axis, delta =
        // angle subtended by the median height. (The bearing stays the ray model's.)
        const double alpha = std::atan((camera.cy - m.median_bottom_row_px) / camera.fy);
        const double alphaPlusDelta =
            std::atan((camera.cy - (m.median_bottom_row_px - m.median_height_px)) / camera.fy);
        double range = 0;
        const Status s = paperEquation3(camera.pitch_rad, alpha, alphaPlusDelta - alpha, signHeightMeters, &range);
        if (s != WF_STATUS_OK) return s;
        result.rangeMeters = range;
        result.centerHeightAboveCameraMeters =
            0.5 * (std::tan(camera.pitch_rad + alphaPlusDelta) + std::tan(camera.pitch_rad + alpha)) * range;
    }
    *out = result;
    return WF_STATUS_OK;
}

Status sliceMeasurementFromColumns(const double *columnU, const double *topRow, const double *bottomRow,
                                   std::size_t count, wf_range_slice_measurement *out) {
    if (count == 0) return WF_STATUS_NONPOSITIVE_SIZE;
    double minU = columnU[0], maxU = columnU[0];
    for (std::size_t i = 0; i < count; ++i) {
        if (!std::isfinite(columnU[i]) || !std::isfinite(topRow[i]) || !std::isfinite(bottomRow[i]))
            return WF_STATUS_NON_FINITE_INPUT;
        minU = std::min(minU, columnU[i]);
        maxU = std::max(maxU, columnU[i]);
    }
    wf_range_slice_measurement m{};
    m.center_column_px = 0.5 * (minU + maxU);
    m.extent_width_px = maxU - minU;
    // Medians and slopes over the central band of the extent only: near the sign's ends a column's top or
    // bottom is a side edge, slanted under pitch and perspective, not the top or bottom edge.
    const double halfBand = 0.5 * kSliceBandFraction * m.extent_width_px;
    std::vector<std::size_t> band;
    for (std::size_t i = 0; i < count; ++i)
        if (std::abs(columnU[i] - m.center_column_px) <= halfBand) band.push_back(i);
    if (band.empty())
        for (std::size_t i = 0; i < count; ++i) band.push_back(i);
    std::vector<double> bottoms, heights;
    for (std::size_t i : band) {
        bottoms.push_back(bottomRow[i]);
        heights.push_back(bottomRow[i] - topRow[i]);
    }
    m.median_bottom_row_px = median(bottoms);
    m.median_height_px = median(heights);
    // Robust edge slopes: median of the slopes between band columns half the band apart (a Theil-Sen
    // estimate on n/2 pairs).
    const std::size_t n = band.size(), half = n / 2;
    if (half > 0) {
        std::vector<double> bottomSlopes, topSlopes;
        for (std::size_t j = 0; j + half < n; ++j) {
            const std::size_t i = band[j], k = band[j + half];
            const double du = columnU[k] - columnU[i];
            if (!(std::abs(du) > 0)) continue;
            bottomSlopes.push_back((bottomRow[k] - bottomRow[i]) / du);
            topSlopes.push_back((topRow[k] - topRow[i]) / du);
        }
        if (!bottomSlopes.empty()) {
            m.bottom_edge_slope = median(bottomSlopes);
            m.top_edge_slope = median(topSlopes);
        }
    }
    if (!(m.median_height_px > 0)) return WF_STATUS_NONPOSITIVE_SIZE;
    *out = m;
    return WF_STATUS_OK;
}

Status horizon(const Eigen::Vector2d &centerPx, const Intrinsics &k, const Eigen::Matrix3d &r,
               double cameraHeightMeters, double signCenterHeightMeters, RangeBearing *out) {
    if (!centerPx.allFinite()) return WF_STATUS_NON_FINITE_INPUT;
    if (std::isnan(cameraHeightMeters) || std::isnan(signCenterHeightMeters)) return WF_STATUS_MISSING_INPUT;
    if (!std::isfinite(cameraHeightMeters) || !std::isfinite(signCenterHeightMeters))
        return WF_STATUS_NON_FINITE_INPUT;
    if (const Status s = checkIntrinsics(k); s != WF_STATUS_OK) return s;
    const Eigen::Vector3d ray = rayInWorld(r, k, centerPx.x(), centerPx.y());
    double tanCenter = 0;
    if (!tanElevation(ray, &tanCenter)) return WF_STATUS_DEGENERATE_GEOMETRY;
    const double heightAboveCamera = signCenterHeightMeters - cameraHeightMeters;
    // A sign near the horizon line makes the ratio blow up: refuse below 1e-6 (0.06 mrad).
    if (!(std::abs(tanCenter) > 1e-6)) return WF_STATUS_DEGENERATE_GEOMETRY;
    const double range = heightAboveCamera / tanCenter;
    if (!(range > 0) || !std::isfinite(range)) return WF_STATUS_DEGENERATE_GEOMETRY;
    double bearing = 0;
    if (!bearingFromForward(r, ray, &bearing)) return WF_STATUS_DEGENERATE_GEOMETRY;
    out->rangeMeters = range;
    out->bearingRad = bearing;
    out->centerHeightAboveCameraMeters = heightAboveCamera;
    return WF_STATUS_OK;
}

Status checkCorners(const Corners &c) {
    for (const auto &p : c)
        if (!p.allFinite()) return WF_STATUS_NON_FINITE_INPUT;
    double scale = 0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, (c[(i + 1) % 4] - c[i]).norm());
    if (!(scale > 0)) return WF_STATUS_DEGENERATE_CORNERS;
    // Clockwise on the screen (v down) = positive z of consecutive edge cross products; each turn must be
    // clearly nonzero (1e-9 of the squared size: collinear or repeated corners fail).
    for (int i = 0; i < 4; ++i) {
        const Eigen::Vector2d e1 = c[(i + 1) % 4] - c[i];
        const Eigen::Vector2d e2 = c[(i + 2) % 4] - c[(i + 1) % 4];
        const double turn = e1.x() * e2.y() - e1.y() * e2.x();
        if (!(turn > 1e-9 * scale * scale)) return WF_STATUS_DEGENERATE_CORNERS;
    }
    return WF_STATUS_OK;
}

Status signCenterPoints(const Corners &c, Eigen::Vector2d *center, Eigen::Vector2d *topCenter,
                        Eigen::Vector2d *bottomCenter) {
    if (const Status s = checkCorners(c); s != WF_STATUS_OK) return s;
    // Work around the centroid for conditioning; translate back at the end.
    const Eigen::Vector2d origin = 0.25 * (c[0] + c[1] + c[2] + c[3]);
    double scale = 0;
    for (const auto &p : c) scale = std::max(scale, (p - origin).norm());
    Eigen::Vector3d tl = homogeneous((c[0] - origin) / scale), tr = homogeneous((c[1] - origin) / scale),
                    br = homogeneous((c[2] - origin) / scale), bl = homogeneous((c[3] - origin) / scale);
    const Eigen::Vector3d topLine = joinOrMeet(tl, tr), bottomLine = joinOrMeet(bl, br);
    const Eigen::Vector3d leftLine = joinOrMeet(tl, bl), rightLine = joinOrMeet(tr, br);
    const Eigen::Vector3d centerH = joinOrMeet(joinOrMeet(tl, br), joinOrMeet(tr, bl));
    // Vanishing point of the verticals (possibly at infinity: z = 0 is fine for a join).
    const Eigen::Vector3d verticalVanishing = joinOrMeet(leftLine, rightLine);
    const Eigen::Vector3d centerLine = joinOrMeet(centerH, verticalVanishing);
    if (centerLine.norm() == 0) return WF_STATUS_DEGENERATE_CORNERS;
    Eigen::Vector2d cN, tN, bN;
    if (!finitePoint(centerH, &cN) || !finitePoint(joinOrMeet(topLine, centerLine), &tN) ||
        !finitePoint(joinOrMeet(bottomLine, centerLine), &bN))
        return WF_STATUS_DEGENERATE_CORNERS;
    *center = origin + scale * cN;
    *topCenter = origin + scale * tN;
    *bottomCenter = origin + scale * bN;
    return WF_STATUS_OK;
}

Status makeUnrollMap(const Intrinsics &raw, double rollRad, double imageWidthPx, double imageHeightPx,
                     wf_range_unroll_map *out) {
    if (const Status s = checkIntrinsics(raw); s != WF_STATUS_OK) return s;
    const double v[3] = {rollRad, imageWidthPx, imageHeightPx};
    if (!allFinite(v, 3)) return WF_STATUS_NON_FINITE_INPUT;
    if (!(imageWidthPx > 0) || !(imageHeightPx > 0)) return WF_STATUS_NONPOSITIVE_SIZE;
    wf_range_unroll_map map{};
    map.raw = {raw.fx, raw.fy, raw.cx, raw.cy};
    map.roll_rad = rollRad;
    const double f = std::sqrt(raw.fx * raw.fy);
    // Canvas: bounding box of the raw image corners mapped with principal point (0, 0).
    map.unrolled = {f, f, 0, 0};
    double minU = 0, maxU = 0, minV = 0, maxV = 0;
    const double cornersU[4] = {0, imageWidthPx, imageWidthPx, 0};
    const double cornersV[4] = {0, 0, imageHeightPx, imageHeightPx};
    for (int i = 0; i < 4; ++i) {
        const Eigen::Vector2d p = unrollPoint(map, {cornersU[i], cornersV[i]});
        if (i == 0) {
            minU = maxU = p.x();
            minV = maxV = p.y();
        }
        minU = std::min(minU, p.x());
        maxU = std::max(maxU, p.x());
        minV = std::min(minV, p.y());
        maxV = std::max(maxV, p.y());
    }
    map.unrolled.cx = -minU;
    map.unrolled.cy = -minV;
    map.unrolled_width_px = maxU - minU;
    map.unrolled_height_px = maxV - minV;
    *out = map;
    return WF_STATUS_OK;
}

Eigen::Vector2d unrollPoint(const wf_range_unroll_map &map, const Eigen::Vector2d &raw) {
    const double x = (raw.x() - map.raw.cx) / map.raw.fx;
    const double y = (raw.y() - map.raw.cy) / map.raw.fy;
    // Rotation by -roll in (u, v) (v down): world up, seen at angle roll in the camera, becomes image up.
    double xu, yu;
    wf::camera::unrollNormalised(std::cos(map.roll_rad), std::sin(map.roll_rad), x, y, &xu, &yu);
    return {map.unrolled.cx + map.unrolled.fx * xu, map.unrolled.cy + map.unrolled.fy * yu};
}

Eigen::Vector2d rerollPoint(const wf_range_unroll_map &map, const Eigen::Vector2d &unrolled) {
    const double xu = (unrolled.x() - map.unrolled.cx) / map.unrolled.fx;
    const double yu = (unrolled.y() - map.unrolled.cy) / map.unrolled.fy;
    double x, y;
    wf::camera::rerollNormalised(std::cos(map.roll_rad), std::sin(map.roll_rad), xu, yu, &x, &y);
    return {map.raw.cx + map.raw.fx * x, map.raw.cy + map.raw.fy * y};
}

}  // namespace wf::range
