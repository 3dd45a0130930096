// Camera geometry shared by detection and range (the one definition of each): pinhole intrinsics and the
// "unrolling" rotation about the optical axis that undoes the camera roll (Fusco et al. 2020, section 3; the
// conventions of wf_sign_detector.h and wf_range.h: pixel-centre coordinates, u right, v down, roll = ARKit's
// Euler roll). Header-only, no OpenCV or Eigen, so both the detector (src/unroll.*) and the range estimator
// (src/range/*) include it.
#pragma once

#include <algorithm>
#include <cmath>

namespace wf::camera {

/// Pinhole intrinsics, pixels (pixel-centre convention: pixel (i, j) is centred on (i, j)).
struct Intrinsics {
    double fx = 0, fy = 0, cx = 0, cy = 0;
};

/// Normalised camera coordinates (x = (u - cx) / fx, y = (v - cy) / fy, v down) rotated about the optical axis
/// by -roll, given c = cos(roll), s = sin(roll): the coordinates in the virtual camera whose roll is 0 (world up is
/// image up). x' = c x + s y, y' = -s x + c y.
inline void unrollNormalised(double c, double s, double x, double y, double* xUnrolled, double* yUnrolled) {
    *xUnrolled = c * x + s * y;
    *yUnrolled = -s * x + c * y;
}

/// The inverse of unrollNormalised: x = c x' - s y', y = s x' + c y'.
inline void rerollNormalised(double c, double s, double xUnrolled, double yUnrolled, double* x, double* y) {
    *x = c * xUnrolled - s * yUnrolled;
    *y = s * xUnrolled + c * yUnrolled;
}

/// Row v (pixels, growing downwards) of an unrolled image with intrinsics `unrolled` where rays at elevation
/// `elevationRad` (radians above the horizontal) appear, for a camera pitched up by `pitchRad`:
/// v = cy' - fy' tan(elevation - pitch) (pinhole model, roll already removed). The angle is clamped to +-1.5 rad,
/// so the row is always finite (far outside the image for rays behind or beside the frame).
inline double unrolledRowAtElevation(const Intrinsics& unrolled, double elevationRad, double pitchRad) {
    return unrolled.cy - unrolled.fy * std::tan(std::clamp(elevationRad - pitchRad, -1.5, 1.5));
}

}  // namespace wf::camera
