// Synthetic camera frames with Exit signs placed by exact pinhole geometry, for tests and benchmarks
// (the trained models are evaluated on the training engineer's renderer output; this is a small,
// dependency-free stand-in with known truth).
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace wf::sign::synthetic {

/// How the sign face is painted.
enum class SignStyle {
    /// Red "EXIT" letters on an off-white plate (the common US Exit sign).
    RedLettersOnWhite,
    /// White "EXIT" letters on a red plate (segments cleanly with a red-pixel model).
    WhiteLettersOnRed,
    /// A room-number placard: SignPlacement::legend in white on a near-black plate (characters a sixth of the
    /// plate's height: 25 mm on a 0.15 m plate).
    PlacardLightOnDark,
};

/// A camera: raw image size and intrinsics (pixels, pixel-centre convention), gravity angles.
struct Camera {
    cv::Size size{1920, 1440};
    double fx = 1602, fy = 1602, cx = 959.5, cy = 719.5;
    /// Radians: pitch positive looking up; roll 0 landscape, -pi/2 portrait (ARKit Euler roll).
    double pitchRad = 0, rollRad = -1.5707963267948966;

    /// The same camera at another resolution (intrinsics scaled about the pixel-edge origin).
    Camera resized(cv::Size newSize) const;
};

/// A rectangular, vertical sign facing the camera.
struct SignPlacement {
    /// Horizontal distance from the camera to the sign face centre, meters.
    double rangeMeters = 3;
    /// Horizontal angle of the sign centre from camera forward, radians, positive to the left.
    double bearingRad = 0;
    /// Height of the sign's bottom edge above the camera centre, meters.
    double bottomAboveCameraMeters = 0.8;
    /// Face size, meters.
    double heightMeters = 0.21;
    double widthMeters = 0.33;
    SignStyle style = SignStyle::RedLettersOnWhite;
    /// Legend of a placard (SignStyle::PlacardLightOnDark), e.g. "214".
    std::string legend = "214";
};

/// Truth of a rendered sign.
struct RenderedSign {
    SignPlacement placement;
    /// Corners in raw pixels: top-left, top-right, bottom-right, bottom-left (as seen upright).
    std::vector<cv::Point2d> cornersRaw;
    bool visible = false;
};

/// Projects a camera-frame-independent world point (camera at origin; x right of the un-yawed forward,
/// y up, z backward, forward = -z) to raw pixels; returns false behind the camera.
bool projectToRaw(const Camera& camera, const cv::Vec3d& pointInWorld, cv::Point2d* pixel);

/// Background: mid-gray wall/floor with seeded noise and a few door-like rectangles; BGR CV_8UC3.
cv::Mat renderBackground(const Camera& camera, uint32_t seed);

/// Paints `sign` into `bgr` (raw image of `camera`) by a perspective warp of a rendered face. Returns the truth.
RenderedSign drawSign(cv::Mat& bgr, const Camera& camera, const SignPlacement& sign);

/// The face texture alone (upright), `heightPx` tall.
cv::Mat renderSignFace(const SignPlacement& sign, int heightPx);

}  // namespace wf::sign::synthetic
