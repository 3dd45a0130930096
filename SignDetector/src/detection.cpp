#include "detection.hpp"

#include <algorithm>

namespace wf::sign {

double intersectionOverUnion(const cv::Rect2d& a, const cv::Rect2d& b) {
    const double inter = (a & b).area();
    const double uni = a.area() + b.area() - inter;
    return uni > 0 ? inter / uni : 0.0;
}

std::vector<Detection> suppressOverlaps(std::vector<Detection> detections, double iouThreshold) {
    // Best score first; ties broken by position so the order is deterministic.
    std::sort(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) {
        if (a.score != b.score) return a.score > b.score;
        if (a.measurement.box.y != b.measurement.box.y) return a.measurement.box.y < b.measurement.box.y;
        return a.measurement.box.x < b.measurement.box.x;
    });
    std::vector<Detection> kept;
    for (auto& d : detections) {
        bool overlaps = false;
        for (const auto& k : kept) {
            if (k.kindIndex == d.kindIndex &&
                intersectionOverUnion(k.measurement.box, d.measurement.box) > iouThreshold) {
                overlaps = true;
                break;
            }
        }
        if (!overlaps) kept.push_back(std::move(d));
    }
    return kept;
}

}  // namespace wf::sign
