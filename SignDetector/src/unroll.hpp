// Unrolling: rotating a raw camera image about its principal point by the camera roll so that the
// horizon is horizontal (Fusco et al. 2020, section 3, "unrolled image"; docs/sign-detection.md).
#pragma once

#include "camera_geometry.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace wf::sign {

/// Pinhole intrinsics, pixels, pixel-centre convention (camera_geometry.hpp: one definition for detection and
/// range).
using Intrinsics = wf::camera::Intrinsics;

/// Row of an unrolled image at a ray elevation (camera_geometry.hpp).
using wf::camera::unrolledRowAtElevation;

/// The exact geometric map between a raw image and its unrolled image, for one roll and one set of
/// intrinsics. A value: cheap to copy, no image data.
///
/// Math: with normalised raw coordinates x = (u - cx)/fx, y = (v - cy)/fy (v down), the unrolled
/// coordinates are the camera rotated about its optical axis by -roll:
///   x' =  cos(r) x + sin(r) y,   y' = -sin(r) x + cos(r) y,   u' = fx' x' + cx',  v' = fy' y' + cy'.
/// For r = -pi/2 (portrait) this is u' = (H-1) - v, v' = u: cv::rotate(ROTATE_90_CLOCKWISE).
/// For multiples of pi/2 the map is an exact pixel permutation (cv::rotate) and fx' = fy, fy' = fx when
/// the turn is odd. Otherwise cv::warpAffine is used with fx' = fy' = sqrt(fx fy) (the map stays affine
/// and exact also when fx != fy) and a canvas just big enough to hold the whole rotated frame.
class Unrolling {
public:
    /// Builds the map for `rollRad` (ARKit Euler roll: 0 = landscape upright, -pi/2 = portrait), raw
    /// intrinsics `raw` and raw image size `rawSize`. Rolls within `snapToleranceRad` of a multiple of
    /// pi/2 are snapped to it (0 = never snap except exact multiples). Inputs must be finite, fx, fy > 0.
    static Unrolling forRoll(double rollRad, const Intrinsics& raw, cv::Size rawSize, double snapToleranceRad = 0.0);

    /// Rotates `raw` (any type, size == rawSize()) into the unrolled image. Quarter turns are exact
    /// (cv::rotate; roll 0 returns a header sharing `raw`'s data); other angles use cv::warpAffine with
    /// `interpolation` and a black border.
    cv::Mat apply(const cv::Mat& raw, int interpolation = cv::INTER_LINEAR) const;

    /// Writes only the pixels of `unrolledRoi` (clipped to the unrolled image) of the unrolled image into
    /// `canvas`, which the caller owns and which must already be unrolledSize() with raw's type; the other pixels
    /// are left as they are. The pixels written are apply()'s (same map and interpolation; for non-quarter turns up to
    /// warpAffine's fixed-point rounding of the sample position, 1/32 pixel). Used by the
    /// cascade, which reads only its search regions: warping a VGA frame costs about 1.3 ms on one core here,
    /// its regions often a tenth of that.
    void applyToRegion(const cv::Mat& raw, const cv::Rect& unrolledRoi, cv::Mat* canvas,
                       int interpolation = cv::INTER_LINEAR) const;

    /// Maps a raw pixel position to the unrolled image (pixel-centre convention, exact).
    cv::Point2d rawToUnrolled(cv::Point2d raw) const;
    /// Maps an unrolled pixel position back to the raw image (exact inverse of rawToUnrolled).
    cv::Point2d unrolledToRaw(cv::Point2d unrolled) const;

    /// Affine matrix raw -> unrolled (2x3, as used by cv::warpAffine).
    const cv::Matx23d& rawToUnrolledMatrix() const { return rawToUnrolled_; }
    /// Affine matrix unrolled -> raw (2x3).
    const cv::Matx23d& unrolledToRawMatrix() const { return unrolledToRaw_; }
    /// Intrinsics of the unrolled image.
    const Intrinsics& unrolledIntrinsics() const { return unrolledK_; }
    /// Size of the raw and the unrolled images, pixels.
    cv::Size rawSize() const { return rawSize_; }
    cv::Size unrolledSize() const { return unrolledSize_; }
    /// Roll removed, radians (the snapped value when snapped).
    double appliedRollRad() const { return appliedRollRad_; }
    /// Number of clockwise quarter turns (0..3) when the map is a pixel permutation, or -1.
    int quarterTurns() const { return quarterTurns_; }

private:
    cv::Matx23d rawToUnrolled_;
    cv::Matx23d unrolledToRaw_;
    Intrinsics unrolledK_;
    cv::Size rawSize_;
    cv::Size unrolledSize_;
    double appliedRollRad_ = 0;
    int quarterTurns_ = 0;
};

}  // namespace wf::sign
