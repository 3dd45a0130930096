#include "cascade_detector.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace wf::sign {

bool CascadeDetector::load(const std::vector<std::string>& paths, const std::vector<std::string>& kinds,
                           std::string* error) {
    kinds_.clear();
    cascades_.clear();
    if (paths.empty()) {
        *error = "no cascade path given";
        return false;
    }
    for (size_t i = 0; i < paths.size(); ++i) {
        if (!std::ifstream(paths[i]).good()) {
            *error = "cascade file not found or unreadable: " + paths[i];
            return false;
        }
        auto cascade = std::make_unique<cv::CascadeClassifier>();
        bool loaded = false;
        try {
            loaded = cascade->load(paths[i]);
        } catch (const cv::Exception& e) {
            *error = "cascade file " + paths[i] + " is not an OpenCV cascade: " + e.what();
            return false;
        }
        if (!loaded || cascade->empty()) {
            *error = "cascade file " + paths[i] + " is not an OpenCV cascade (cv::CascadeClassifier::load failed)";
            return false;
        }
        cascades_.push_back(std::move(cascade));
        kinds_.push_back(i < kinds.size() && !kinds[i].empty() ? kinds[i] : "exit");
    }
    return true;
}

cv::Size CascadeDetector::trainedWindow(size_t index) const {
    return index < cascades_.size() ? cascades_[index]->getOriginalWindowSize() : cv::Size();
}

int CascadeDetector::searchRowLimit(double minElevationRad, double pitchRad, double fyPx, double cyPx, int rows) {
    // elevation(v) >= min  <=>  v <= cy - fy tan(min - pitch); beyond +-1.5 rad the row is far outside the image.
    const double v = unrolledRowAtElevation(Intrinsics{fyPx, fyPx, 0, cyPx}, minElevationRad, pitchRad);
    return static_cast<int>(std::clamp(std::floor(v) + 1.0, 0.0, double(rows)));
}

void CascadeDetector::detectOne(size_t index, const cv::Mat& image, cv::Point origin, const CascadeParams& params,
                                std::vector<Detection>* out, int minWindowWidthPx) {
    cv::Size minSize = params.minWindow.empty() ? cascades_[index]->getOriginalWindowSize() : params.minWindow;
    cv::Size maxSize;
    if (params.maxWindowFactor > 0) {
        maxSize = cv::Size(static_cast<int>(minSize.width * params.maxWindowFactor),
                           static_cast<int>(minSize.height * params.maxWindowFactor));
    }
    if (minWindowWidthPx > minSize.width) {
        minSize = cv::Size(minWindowWidthPx, static_cast<int>(std::lround(double(minWindowWidthPx) * minSize.height /
                                                                          minSize.width)));
    }
    if (image.cols < minSize.width || image.rows < minSize.height) return;
    std::vector<cv::Rect> boxes;
    std::vector<int> neighbours;
    cascades_[index]->detectMultiScale(image, boxes, neighbours, params.scaleFactor, params.minNeighbors, 0, minSize,
                                       maxSize);
    for (size_t j = 0; j < boxes.size(); ++j) {
        Detection d;
        d.kind = kinds_[index];
        d.kindIndex = static_cast<int>(index);
        d.score = j < neighbours.size() ? neighbours[j] : params.minNeighbors;
        d.measurement = measureBox(boxes[j] + origin, params.slices);
        out->push_back(std::move(d));
    }
}

std::vector<Detection> CascadeDetector::detect(const cv::Mat& grayUnrolledFull, const CascadeParams& params, int lastRow) {
    CV_Assert(grayUnrolledFull.type() == CV_8UC1);
    std::vector<Detection> detections;
    const int rows = lastRow < 0 ? grayUnrolledFull.rows : std::min(lastRow, grayUnrolledFull.rows);
    if (rows <= 0) return detections;
    const cv::Mat grayUnrolled = grayUnrolledFull.rowRange(0, rows);  // a view: same pixel coordinates
    for (size_t i = 0; i < cascades_.size(); ++i) detectOne(i, grayUnrolled, cv::Point(0, 0), params, &detections);
    return detections;
}

std::vector<Detection> CascadeDetector::detectInRegions(const cv::Mat& grayUnrolled,
                                                        const std::vector<SearchRegion>& regions,
                                                        const CascadeParams& params, int lastRow) {
    CV_Assert(grayUnrolled.type() == CV_8UC1);
    std::vector<Detection> detections;
    const int rows = lastRow < 0 ? grayUnrolled.rows : std::min(lastRow, grayUnrolled.rows);
    const cv::Rect searched(0, 0, grayUnrolled.cols, std::max(0, rows));
    for (const SearchRegion& region : regions) {
        const cv::Rect r = region.unrolledRect & searched;
        if (r.empty()) continue;
        const cv::Mat view = grayUnrolled(r);  // a view: box + r.tl() is in grayUnrolled's pixels
        for (size_t i = 0; i < cascades_.size(); ++i) {
            detectOne(i, view, r.tl(), params, &detections, region.minWindowWidthPx);
        }
    }
    return detections;
}

}  // namespace wf::sign
