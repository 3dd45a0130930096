// A detection in unrolled-image pixels, shared by the cascade and U-Net detectors.
#pragma once

#include "slice_measurement.hpp"

#include <string>
#include <vector>

namespace wf::sign {

/// One detected sign before it is packed into a wf_detector_observation.
struct Detection {
    /// Kind name ("exit"...) and index (cascade index, or U-Net class index >= 1).
    std::string kind;
    int kindIndex = 0;
    /// Cascade: neighbour count; U-Net: mean class probability over the mask, [0, 1].
    double score = 0;
    /// Slice measurement in unrolled pixels.
    SliceMeasurement measurement;
    /// Legend text read off the sign (kinds that read text: a room number); "" = none.
    std::string text;
};

/// Intersection over union of two boxes (0 when either is empty).
double intersectionOverUnion(const cv::Rect2d& a, const cv::Rect2d& b);

/// Greedy non-maximum suppression per kind: keeps the best-scoring detection of every group whose boxes
/// overlap with IoU > `iouThreshold`. Returns the kept detections, best score first.
std::vector<Detection> suppressOverlaps(std::vector<Detection> detections, double iouThreshold);

}  // namespace wf::sign
