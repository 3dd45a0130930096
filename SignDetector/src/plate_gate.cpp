#include "plate_gate.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace wf::sign {

std::vector<cv::Rect> plateCandidates(const cv::Mat& gray, int rowFirst, int rowLast, int minSidePx, int maxSidePx,
                                      const PlateGateParams& params) {
    CV_Assert(gray.type() == CV_8UC1);
    std::vector<cv::Rect> boxes;
    rowFirst = std::clamp(rowFirst, 0, gray.rows);
    rowLast = std::clamp(rowLast, rowFirst, gray.rows);
    if (rowLast - rowFirst < 3 || gray.cols < 3) return boxes;
    // At working resolution: the band shrunk by an integer factor (INTER_AREA); boxes scaled back below.
    const int shrink = std::max(1, params.shrinkFactor);
    cv::Mat band = gray.rowRange(rowFirst, rowLast);  // a view: + (0, rowFirst) gives gray's pixels
    if (shrink > 1) {
        if (band.cols < 3 * shrink || band.rows < 3 * shrink) return boxes;
        cv::Mat small;
        cv::resize(band, small, cv::Size(band.cols / shrink, band.rows / shrink), 0, 0, cv::INTER_AREA);
        band = small;
    }
    const cv::Mat closing = params.closePx > 1
                                ? cv::getStructuringElement(cv::MORPH_RECT, cv::Size(params.closePx, params.closePx))
                                : cv::Mat();
    auto keep = [&](const cv::Rect& working) {
        const cv::Rect r(working.x * shrink, working.y * shrink, working.width * shrink, working.height * shrink);
        if (r.width < minSidePx || r.height < minSidePx || r.width > maxSidePx || r.height > maxSidePx) return;
        const double aspect = double(r.width) / r.height;
        if (aspect < params.minAspect || aspect > params.maxAspect) return;
        boxes.push_back(r + cv::Point(0, rowFirst));
    };
    // 1. Canny's edges, closed; the bounding boxes of their contours.
    cv::Mat edges;
    cv::Canny(band, edges, params.cannyLowLevels, params.cannyHighLevels);
    if (!closing.empty()) cv::morphologyEx(edges, edges, cv::MORPH_CLOSE, closing);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(edges, contours, cv::RETR_LIST, cv::CHAIN_APPROX_SIMPLE);
    for (const auto& c : contours) keep(cv::boundingRect(c));
    // 2. The morphological gradient above its threshold, closed; its 8-connected components' bounding boxes (the
    //    outer contours': the same boxes as connectedComponentsWithStats, at a seventh of its cost here).
    cv::Mat gradient, mask;
    cv::morphologyEx(band, gradient, cv::MORPH_GRADIENT, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    cv::threshold(gradient, mask, params.gradientMinLevels - 1, 255, cv::THRESH_BINARY);  // >= the minimum
    if (!closing.empty()) cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, closing);
    // RETR_CCOMP: the outer boundary of every component at the top level (those inside another's hole too), the
    // holes' boundaries below them.
    contours.clear();
    std::vector<cv::Vec4i> hierarchy;
    cv::findContours(mask, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
    for (size_t i = 0; i < contours.size(); ++i) {
        if (hierarchy[i][3] < 0) keep(cv::boundingRect(contours[i]));
    }
    return boxes;
}

GateDecision plateRegions(const std::vector<cv::Rect>& candidates, const cv::Rect& searched,
                          const PlateGateParams& params) {
    GateDecision decision;
    if (!params.enabled) return decision;
    decision.fullSearch = false;
    if (searched.area() == 0) return decision;
    // Near-duplicates (a plate's outline found by both masks, or its outline and its legend's): one box, their union.
    std::vector<cv::Rect> boxes;
    for (const cv::Rect& c : candidates) {
        bool merged = false;
        for (cv::Rect& b : boxes) {
            const double overlap = (b & c).area();
            if (overlap >= params.duplicateOverlap * (b.area() + c.area() - overlap)) {
                b |= c;
                merged = true;
                break;
            }
        }
        if (!merged) boxes.push_back(c);
    }
    std::vector<SearchRegion> regions;
    regions.reserve(boxes.size());
    for (const cv::Rect& b : boxes) {
        const int side = std::max(b.width, b.height);
        const int margin = std::max(params.minMarginPx, int(std::lround(params.marginFactor * side)));
        const cv::Rect r = cv::Rect(b.x - margin, b.y - margin, b.width + 2 * margin, b.height + 2 * margin) & searched;
        if (r.area() > 0) {
            regions.push_back({r, int(std::floor(params.minWindowFraction * side)),
                               int(std::ceil(params.maxWindowFraction * side))});
        }
    }
    double area = 0;
    for (const SearchRegion& r : regions) area += r.unrolledRect.area();
    decision.coveredFraction = area / searched.area();
    if (int(regions.size()) > params.maxRegions) {
        decision.fullSearch = true;
        return decision;
    }
    decision.regions = std::move(regions);
    return decision;
}

}  // namespace wf::sign
