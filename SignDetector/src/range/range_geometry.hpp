// Internal C++ API of range estimation (behind wf_range.h). Eigen types, no exceptions thrown by this code
// itself (OpenCV may throw inside estimatePnP; the C layer catches everything).
//
// Frames (wf_range.h, App/SessionFormat/CameraPose.swift): world y up; camera x = image u, y = image -v,
// looking along -z; raw pixel (u, v) -> world ray R * [(u - cx)/fx, -(v - cy)/fy, -1].
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstddef>

#include "../camera_geometry.hpp"
#include "wf_range.h"

namespace wf::range {

/// Status of an internal computation; values are wf_status.h codes.
using Status = int;

/// Range, bearing and centre height (see wf_range_result).
struct RangeBearing {
    double rangeMeters = 0;
    double bearingRad = 0;
    double centerHeightAboveCameraMeters = 0;
};

/// Pinhole intrinsics of an image, pixels (camera_geometry.hpp: the detector's type).
using Intrinsics = wf::camera::Intrinsics;

/// True when every number is finite.
bool allFinite(const double *values, std::size_t count);

/// Checks intrinsics: finite, focal lengths > 0.
Status checkIntrinsics(const Intrinsics &k);

/// Reads the 3x3 rotation block of a column-major 4x4 and checks it is a rotation (R^T R = I and det = +1
/// within 1e-3, loose enough for ARKit's float matrices).
Status rotationFromColumnMajor(const double cameraToWorld[16], Eigen::Matrix3d *outRotation);

/// R = Rx(pitch) * Rz(roll): a camera with that pitch and roll whose forward direction projects on -z.
Eigen::Matrix3d rotationFromPitchRoll(double pitchRad, double rollRad);

/// Pitch asin(forward_y) and roll atan2(up_x, up_y) of a camera-to-world rotation (CameraPose.swift).
void pitchRollFromRotation(const Eigen::Matrix3d &cameraToWorld, double *pitchRad, double *rollRad);

/// World direction (not normalised) of the ray through raw pixel (u, v).
Eigen::Vector3d rayInWorld(const Eigen::Matrix3d &cameraToWorld, const Intrinsics &k, double u, double v);

/// Tangent of a ray's elevation above the horizontal plane, y / hypot(x, z). Returns false (degenerate)
/// when the ray is vertical within 1e-12 relative.
bool tanElevation(const Eigen::Vector3d &ray, double *outTan);

/// Bearing of a world direction relative to the camera's horizontal forward direction: azimuth difference,
/// CCW seen from above (positive left), wrapped to (-pi, pi]. Returns false when the camera forward or the
/// direction is vertical.
bool bearingFromForward(const Eigen::Matrix3d &cameraToWorld, const Eigen::Vector3d &directionInWorld,
                        double *outBearingRad);

/// Apparent-height range from two rays through points of one vertical world line (top above bottom):
/// range = h0 / (tan e_top - tan e_bottom). Bearing: mean azimuth of the two rays.
Status apparentHeightFromRays(const Eigen::Matrix3d &cameraToWorld, const Eigen::Vector3d &topRay,
                              const Eigen::Vector3d &bottomRay, double signHeightMeters, RangeBearing *out);

/// Exact apparent-height method on raw pixels (wf_range_apparent_height_exact).
Status apparentHeightExact(const Eigen::Vector2d &topCenterPx, const Eigen::Vector2d &bottomCenterPx,
                           const Intrinsics &k, const Eigen::Matrix3d &cameraToWorld, double signHeightMeters,
                           RangeBearing *out);

/// Paper equation (3) (wf_range_paper_equation3).
Status paperEquation3(double pitchRad, double alphaRad, double deltaRad, double signHeightMeters,
                      double *outRangeMeters);

/// Apparent-height method on slice medians in the unrolled image (wf_range_apparent_height_slices).
Status apparentHeightSlices(const wf_range_unrolled_camera &camera, const wf_range_slice_measurement &m,
                            double signHeightMeters, wf_range_slice_model model, RangeBearing *out);

/// Slice medians from per-column edges (wf_range_slice_measurement_from_columns).
Status sliceMeasurementFromColumns(const double *columnU, const double *topRow, const double *bottomRow,
                                   std::size_t count, wf_range_slice_measurement *out);

/// Horizon method (wf_range_horizon).
Status horizon(const Eigen::Vector2d &centerPx, const Intrinsics &k, const Eigen::Matrix3d &cameraToWorld,
               double cameraHeightMeters, double signCenterHeightMeters, RangeBearing *out);

/// Corners TL, TR, BR, BL in raw pixels.
using Corners = std::array<Eigen::Vector2d, 4>;

/// Checks the corners: finite, convex, clockwise on screen (v down), not degenerate.
Status checkCorners(const Corners &corners);

/// Centre, top-centre and bottom-centre images (wf_range_sign_center_points). Checks the corners.
Status signCenterPoints(const Corners &corners, Eigen::Vector2d *center, Eigen::Vector2d *topCenter,
                        Eigen::Vector2d *bottomCenter);

/// PnP with OpenCV (wf_range_pnp). May throw cv::Exception; callers across the C ABI catch it.
Status estimatePnP(const Corners &corners, const Intrinsics &k, const Eigen::Matrix3d &cameraToWorld,
                   double signWidthMeters, double signHeightMeters, RangeBearing *out);

/// Unrolling of points (wf_range_unroll_map_make / _point / reroll).
Status makeUnrollMap(const Intrinsics &raw, double rollRad, double imageWidthPx, double imageHeightPx,
                     wf_range_unroll_map *out);
Eigen::Vector2d unrollPoint(const wf_range_unroll_map &map, const Eigen::Vector2d &raw);
Eigen::Vector2d rerollPoint(const wf_range_unroll_map &map, const Eigen::Vector2d &unrolled);

}  // namespace wf::range
