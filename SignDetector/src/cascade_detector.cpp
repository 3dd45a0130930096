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

namespace {

/// Windows detectMultiScale scans at one scale on a `rows` x `cols` image: the image is shrunk by `factor`, the
/// window (trained size) moves in steps of 2 below factor 2 and 1 above (OpenCV's scan).
double windowsAtScale(int rows, int cols, double factor, cv::Size trained) {
    const double step = factor > 2.0 ? 1.0 : 2.0;
    const double nx = std::floor((cols / factor - trained.width) / step) + 1;
    const double ny = std::floor((rows / factor - trained.height) / step) + 1;
    return std::max(0.0, nx) * std::max(0.0, ny);
}

/// Fixed cost of one detectMultiScale call (pyramid and evaluator set-up), in windows' worth of scanning: about
/// 30 us here against about 0.06 us per window.
constexpr double kCallCostWindows = 500;

/// One pyramid scale of the search: its window and the image rows [rowFirst, rowLast) it scans.
struct ScaleBand {
    double factor = 1;
    cv::Size window;
    int rowFirst = 0, rowLast = 0;
};

}  // namespace

void CascadeDetector::scanOne(size_t index, const cv::Mat& image, cv::Point origin, const CascadeParams& params,
                              const FrameGeometry* geometry, std::vector<cv::Rect>* hitsOut, int minWindowWidthPx,
                              int maxWindowWidthPx) {
    const cv::Size trained = cascades_[index]->getOriginalWindowSize();
    cv::Size minSize = params.minWindow.empty() ? trained : params.minWindow;
    cv::Size maxSize = image.size();
    if (params.maxWindowFactor > 0) {
        maxSize = cv::Size(std::min(maxSize.width, static_cast<int>(minSize.width * params.maxWindowFactor)),
                           std::min(maxSize.height, static_cast<int>(minSize.height * params.maxWindowFactor)));
    }
    if (minWindowWidthPx > minSize.width) {
        minSize = cv::Size(minWindowWidthPx, static_cast<int>(std::lround(double(minWindowWidthPx) * minSize.height /
                                                                          minSize.width)));
    }
    if (maxWindowWidthPx > 0 && maxWindowWidthPx < maxSize.width) {
        maxSize = cv::Size(maxWindowWidthPx, std::min(maxSize.height, static_cast<int>(std::lround(
                                                         double(maxWindowWidthPx) * minSize.height / minSize.width))));
    }
    if (image.cols < minSize.width || image.rows < minSize.height) return;
    // The scales detectMultiScale scans (its own loop, so the windows are the same), each with its rows.
    const bool banded = params.placement.enabled && geometry != nullptr;
    std::vector<ScaleBand> scales;
    for (double factor = 1;; factor *= params.scaleFactor) {
        const cv::Size window(cvRound(trained.width * factor), cvRound(trained.height * factor));
        if (window.width > maxSize.width || window.height > maxSize.height) break;
        if (window.width < minSize.width || window.height < minSize.height) continue;
        ScaleBand s{factor, window, 0, image.rows};
        if (banded) {
            const auto band = placementRowBand(params.placement, window.width, window.height, geometry->pitchRad,
                                               geometry->unrolled);
            s.rowFirst = std::clamp(band.first - origin.y, 0, image.rows);
            s.rowLast = std::clamp(band.second - origin.y, 0, image.rows);
        }
        if (s.rowLast - s.rowFirst >= window.height) scales.push_back(s);
    }
    // Runs of consecutive scales share one call over the union of their rows while that costs less than
    // separate calls (without the prior every scale has every row: one call, as detectMultiScale alone).
    std::vector<cv::Rect>& hits = *hitsOut;
    auto scan = [&](size_t first, size_t last, int rowFirst, int rowLast) {  // scales [first, last]
        std::vector<cv::Rect> found;
        cascades_[index]->detectMultiScale(image.rowRange(rowFirst, rowLast), found, params.scaleFactor, 0, 0,
                                           scales[first].window, scales[last].window);
        for (cv::Rect& r : found) hits.push_back(r + cv::Point(0, rowFirst) + origin);
    };
    auto cost = [&](size_t first, size_t last, int rowFirst, int rowLast) {
        double windows = kCallCostWindows;
        for (size_t i = first; i <= last; ++i) windows += windowsAtScale(rowLast - rowFirst, image.cols, scales[i].factor, trained);
        return windows;
    };
    for (size_t first = 0; first < scales.size();) {
        size_t last = first;
        int rowFirst = scales[first].rowFirst, rowLast = scales[first].rowLast;
        while (last + 1 < scales.size()) {
            const ScaleBand& next = scales[last + 1];
            const int unionFirst = std::min(rowFirst, next.rowFirst), unionLast = std::max(rowLast, next.rowLast);
            const double together = cost(first, last + 1, unionFirst, unionLast);
            const double apart = cost(first, last, rowFirst, rowLast) + cost(last + 1, last + 1, next.rowFirst, next.rowLast);
            if (together > apart) break;
            ++last;
            rowFirst = unionFirst;
            rowLast = unionLast;
        }
        scan(first, last, rowFirst, rowLast);
        first = last + 1;
    }
}

void CascadeDetector::groupHits(size_t index, std::vector<cv::Rect> hits, const CascadeParams& params,
                                std::vector<Detection>* out) const {
    // Grouped as detectMultiScale groups its own hits (GROUP_EPS 0.2); the weights are the neighbour counts.
    std::vector<int> neighbours;
    cv::groupRectangles(hits, neighbours, params.minNeighbors, 0.2);
    for (size_t j = 0; j < hits.size(); ++j) {
        Detection d;
        d.kind = kinds_[index];
        d.kindIndex = static_cast<int>(index);
        d.score = j < neighbours.size() ? neighbours[j] : params.minNeighbors;
        d.measurement = measureBox(hits[j], params.slices);
        out->push_back(std::move(d));
    }
}

namespace {
/// The cascade indices to run: `kindIndices`, or 0 .. count - 1.
std::vector<size_t> selectedKinds(size_t count, const std::vector<size_t>* kindIndices) {
    if (kindIndices != nullptr) return *kindIndices;
    std::vector<size_t> all(count);
    for (size_t i = 0; i < count; ++i) all[i] = i;
    return all;
}
}  // namespace

std::vector<Detection> CascadeDetector::detect(const cv::Mat& grayUnrolledFull, const CascadeParams& params, int lastRow,
                                               const FrameGeometry* geometry, const std::vector<size_t>* kindIndices) {
    CV_Assert(grayUnrolledFull.type() == CV_8UC1);
    std::vector<Detection> detections;
    const int rows = lastRow < 0 ? grayUnrolledFull.rows : std::min(lastRow, grayUnrolledFull.rows);
    if (rows <= 0) return detections;
    const cv::Mat grayUnrolled = grayUnrolledFull.rowRange(0, rows);  // a view: same pixel coordinates
    for (size_t i : selectedKinds(cascades_.size(), kindIndices)) {
        if (i >= cascades_.size()) continue;
        std::vector<cv::Rect> hits;
        scanOne(i, grayUnrolled, cv::Point(0, 0), params, geometry, &hits);
        groupHits(i, std::move(hits), params, &detections);
    }
    return detections;
}

std::vector<Detection> CascadeDetector::detectInRegions(const cv::Mat& grayUnrolled,
                                                        const std::vector<SearchRegion>& regions,
                                                        const CascadeParams& params, int lastRow,
                                                        const FrameGeometry* geometry,
                                                        const std::vector<size_t>* kindIndices,
                                                        bool groupAcrossRegions) {
    CV_Assert(grayUnrolled.type() == CV_8UC1);
    std::vector<Detection> detections;
    const int rows = lastRow < 0 ? grayUnrolled.rows : std::min(lastRow, grayUnrolled.rows);
    const cv::Rect searched(0, 0, grayUnrolled.cols, std::max(0, rows));
    const std::vector<size_t> kinds = selectedKinds(cascades_.size(), kindIndices);
    // Whether `hit` repeats one already kept: the same window size, its position within half the scan's step at
    // that size (detectMultiScale moves the window 2 px of the scaled image below scale 2, 1 px above). Overlapping
    // regions scan on grids of their own; a window they both reach counts once, as in one search of the image
    // (counted twice, weak look-alikes pass the neighbour count), while their other grid positions add evidence.
    auto repeats = [&](size_t index, const std::vector<cv::Rect>& kept, size_t keptCount, const cv::Rect& hit) {
        const double factor = double(hit.width) / cascades_[index]->getOriginalWindowSize().width;
        const double halfStep = 0.5 * (factor > 2.0 ? factor : 2.0 * factor);
        for (size_t q = 0; q < keptCount; ++q) {
            const cv::Rect& g = kept[q];
            if (g.size() == hit.size() && std::abs(g.x - hit.x) < halfStep && std::abs(g.y - hit.y) < halfStep) return true;
        }
        return false;
    };
    for (size_t i : kinds) {
        if (i >= cascades_.size()) continue;
        std::vector<cv::Rect> hits;  // of every region, when grouped across them
        for (size_t k = 0; k < regions.size(); ++k) {
            const cv::Rect r = regions[k].unrolledRect & searched;
            if (r.empty()) continue;
            const cv::Mat view = grayUnrolled(r);  // a view: box + r.tl() is in grayUnrolled's pixels
            std::vector<cv::Rect> found;
            scanOne(i, view, r.tl(), params, geometry, &found, regions[k].minWindowWidthPx, regions[k].maxWindowWidthPx);
            if (!groupAcrossRegions) {
                groupHits(i, std::move(found), params, &detections);
                continue;
            }
            const size_t before = hits.size();  // hits of earlier regions: this region's own are all kept
            for (const cv::Rect& h : found) {
                if (!repeats(i, hits, before, h)) hits.push_back(h);
            }
        }
        if (groupAcrossRegions) groupHits(i, std::move(hits), params, &detections);
    }
    return detections;
}

}  // namespace wf::sign
