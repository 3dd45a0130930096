// The wall kinds' search image, made in one resampling: the frame unrolled at the scale at which the whole unrolled
// canvas fits the search size (long side at most ResolvedOptions::plainKindSearchMaxLongSidePx), sampled straight
// from the frame (a VGA frame on the cascade path) or from a shrunk copy of it that is already there (the U-Net's
// half-size pyramid level).
//
// Why: the search reads a gray, unrolled image whose long side is at most the search size (VGA). Made step by step
// (shrink the half-size copy to VGA with INTER_AREA, unroll it with warpAffine, shrink the unrolled canvas again when
// the roll makes it larger than VGA, as it does at every roll but a quarter turn: a portrait frame 5 degrees off
// upright unrolls to 534 x 680) it took three resamplings of the whole image, 1.3 + 1.1 + 1.4 ms on one core here
// (twenty-first stop, docs/benchmarks.md), half of what the wall kinds cost beside the U-Net. One warpAffine of the
// half-size copy into the final canvas is about 1 ms.
//
// Sampling: bilinear, from a source at most about twice the result's scale (the half-size level of a 1920 x 1440
// frame is 1.5-1.9 x the result): the kernel spans two source pixels, so little aliases at that ratio; from the
// full frame (3 x and more) it would, and that path keeps SearchFrame's INTER_AREA shrink. The geometry is exact
// (pixel centres aligned: u' = (u + 0.5) s - 0.5); the scale is uniform. Hand-written: the choice of scale and the
// composed matrix; the resampling is OpenCV's (cv::warpAffine).
#pragma once

#include "unroll.hpp"

#include <opencv2/core.hpp>

namespace wf::sign {

/// A gray, unrolled search image and its geometry. A value owning its pixels.
class UnrolledSearchImage {
public:
    /// The frame of `frameSize` pixels and raw intrinsics `k`, rolled by `rollRad` (snapped to a quarter turn within
    /// `snapToleranceRad`, as Unrolling::forRoll), unrolled into a canvas of long side at most `maxLongSidePx` (> 0);
    /// its pixels sampled from `sourceGray` (CV_8UC1): the frame itself or a copy of it shrunk with its pixel edges
    /// aligned to the frame's (a pyramid level), ideally at most about twice the result's scale. Throws
    /// cv::Exception on an empty or non-gray source or a non-positive limit.
    UnrolledSearchImage(const cv::Mat& sourceGray, cv::Size frameSize, const Intrinsics& k, double rollRad,
                        double snapToleranceRad, int maxLongSidePx);

    /// The unrolled image to search (gray, unrolling().unrolledSize()).
    const cv::Mat& image() const { return image_; }
    /// The unrolling of the virtual shrunk frame (the frame at scaleX() x scaleY(), intrinsics scaled with pixel
    /// centres aligned) onto image(): its intrinsics are the search image's.
    const Unrolling& unrolling() const { return unrolling_; }
    /// Shrunk-frame pixels per frame pixel, horizontally and vertically (equal up to rounding to whole pixels).
    double scaleX() const { return sx_; }
    double scaleY() const { return sy_; }

private:
    cv::Mat image_;
    Unrolling unrolling_;
    double sx_ = 1, sy_ = 1;
};

}  // namespace wf::sign
