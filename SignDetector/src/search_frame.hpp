// The frame the cascade searches: the caller's frame, or a copy shrunk so that its long side is at most a limit
// (ResolvedOptions::cascadeSearchMaxLongSidePx, VGA by default), with the intrinsics that go with it; and the
// map of the detections found on it back to the frame's own unrolled pixels, where the face edges are measured.
//
// Why: the cascade's search costs what its windows cost, so it runs at VGA (its models were trained and its 5 ms
// target is measured there); but at VGA a face 7-9 m away is 11-14 px tall and its edge and the housing or bloom
// around it merge under the blur, so the refined range read 9.5-18 % short there, against 4-10 % when the same
// boxes were refined on the 1920 x 1440 frame (docs/sign-detection.md "Face-edge refinement"). With the full
// frame given, the search is VGA and the measurement full resolution: each box is refined on the searched image
// (face_edge_refiner), mapped to the frame, and refined again there with the narrow search a mask gets
// (maskFaceEdgeParams: its edges are already within a VGA pixel). Measured on 520 held-out renders
// (docs/benchmarks.md "Seventh stop"). Hand-written glue; the resampling is OpenCV's (cv::resize, INTER_AREA:
// the mean over each destination pixel's footprint, as vImageScale does on the phone).
#pragma once

#include "detection.hpp"
#include "unroll.hpp"
#include "wf_sign_detector.h"

#include <opencv2/core.hpp>

#include <vector>

namespace wf::sign {

/// A frame for the search: a view of the caller's image (no copy) when it is small enough, else a shrunk copy
/// this object owns (the wf_image it hands out points into it: keep the object alive while it is used).
class SearchFrame {
public:
    /// `image` with intrinsics `k` (raw pixels); `maxLongSidePx` <= 0 = never shrink. The shrunk size keeps
    /// the aspect, rounded to whole pixels (as the phone's DetectorInputGeometry); every format is shrunk in
    /// its own layout (NV12: each plane), so colour reaches the colour gate as it would from a small frame.
    SearchFrame(const wf_image& image, const Intrinsics& k, int maxLongSidePx);

    /// True when the search image is a shrunk copy.
    bool shrunk() const { return shrunk_; }
    /// The image to search (the caller's, or the copy).
    const wf_image& image() const { return image_; }
    /// Its intrinsics: focal lengths times the scale, principal point mapped with pixel centres aligned
    /// (u' = (u + 0.5) s - 0.5).
    const Intrinsics& intrinsics() const { return k_; }
    /// Search pixels per frame pixel, horizontally and vertically (1 when not shrunk).
    double scaleX() const { return sx_; }
    double scaleY() const { return sy_; }

private:
    bool shrunk_ = false;
    wf_image image_{};
    Intrinsics k_;
    double sx_ = 1, sy_ = 1;
    cv::Mat plane_, chroma_;
};

/// Maps detections found in the search frame's unrolled image (`searchUnrolling`) to the frame's own unrolled
/// image (`frameUnrolling`): the two unrolled images differ by a scale and a shift (the same roll about
/// corresponding principal points), found by mapping points through search unrolled -> search raw -> frame raw
/// -> frame unrolled; every measurement (edges, medians, box) is mapped with them (SliceMeasurement::mapped).
/// Kind, score and text are kept.
std::vector<Detection> mapToFrame(std::vector<Detection> detections, const SearchFrame& search,
                                  const Unrolling& searchUnrolling, const Unrolling& frameUnrolling);
/// The same for a search image of any frame shrunk by `searchScaleX` x `searchScaleY` (search pixels per frame
/// pixel, pixel centres aligned) and unrolled by `searchUnrolling` (e.g. UnrolledSearchImage).
std::vector<Detection> mapToFrame(std::vector<Detection> detections, double searchScaleX, double searchScaleY,
                                  const Unrolling& searchUnrolling, const Unrolling& frameUnrolling);

}  // namespace wf::sign
