#include "slice_measurement.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace wf::sign {

namespace {

double median(std::vector<double>& values) {
    const size_t n = values.size();
    std::nth_element(values.begin(), values.begin() + n / 2, values.end());
    const double upper = values[n / 2];
    if (n % 2 == 1) return upper;
    const double lower = *std::max_element(values.begin(), values.begin() + n / 2);
    return 0.5 * (lower + upper);
}

}  // namespace

std::vector<int> sliceColumns(int first, int last, const SliceParams& params) {
    const double fraction = params.bandFraction > 0 && params.bandFraction <= 1 ? params.bandFraction : 0.6;
    const double centre = 0.5 * (first + last);
    const double half = 0.5 * fraction * (last - first + 1);
    int lo = static_cast<int>(std::ceil(centre - half + 0.5 - 1e-9));
    int hi = static_cast<int>(std::floor(centre + half - 0.5 + 1e-9));
    lo = std::max(lo, first);
    hi = std::min(hi, last);
    if (hi < lo) lo = hi = static_cast<int>(std::lround(centre));
    std::vector<int> columns;
    const int span = hi - lo + 1;
    if (params.sliceCount <= 0 || params.sliceCount >= span) {
        for (int c = lo; c <= hi; ++c) columns.push_back(c);
    } else if (params.sliceCount == 1) {
        columns.push_back(static_cast<int>(std::lround(0.5 * (lo + hi))));
    } else {
        for (int i = 0; i < params.sliceCount; ++i) {
            columns.push_back(lo + static_cast<int>(std::lround(double(i) * (span - 1) / (params.sliceCount - 1))));
        }
    }
    return columns;
}

SliceMeasurement SliceMeasurement::mapped(double scale, cv::Point2d originEdge) const {
    SliceMeasurement m = *this;
    m.medianBottomEdgePx = originEdge.y + (medianBottomEdgePx + 0.5) * scale;
    m.medianHeightPx = medianHeightPx * scale;
    m.centerColumnPx = originEdge.x + (centerColumnPx + 0.5) * scale;
    m.extentWidthPx = extentWidthPx * scale;
    m.box = cv::Rect2d(originEdge.x + (box.x + 0.5) * scale, originEdge.y + (box.y + 0.5) * scale,
                       box.width * scale, box.height * scale);
    return m;
}

SliceMeasurement measureBox(const cv::Rect& box, const SliceParams& params) {
    SliceMeasurement m;
    if (box.width <= 0 || box.height <= 0) return m;
    m.valid = true;
    m.medianBottomEdgePx = box.y + box.height - 0.5;
    m.medianHeightPx = box.height;
    m.centerColumnPx = box.x + 0.5 * (box.width - 1);
    m.extentWidthPx = box.width - 1;
    m.box = cv::Rect2d(box.x - 0.5, box.y - 0.5, box.width, box.height);
    m.sliceCount = static_cast<int>(sliceColumns(box.x, box.x + box.width - 1, params).size());
    return m;
}

SliceMeasurement measureMask(const cv::Mat& mask, const SliceParams& params) {
    CV_Assert(mask.type() == CV_8UC1);
    SliceMeasurement m;
    // Per-column extent of the sign.
    std::vector<int> top(mask.cols, -1), bottom(mask.cols, -1);
    int minRow = mask.rows, maxRow = -1;
    for (int r = 0; r < mask.rows; ++r) {
        const uchar* row = mask.ptr<uchar>(r);
        for (int c = 0; c < mask.cols; ++c) {
            if (!row[c]) continue;
            if (top[c] < 0) top[c] = r;
            bottom[c] = r;
            minRow = std::min(minRow, r);
            maxRow = std::max(maxRow, r);
        }
    }
    int first = -1, last = -1;
    for (int c = 0; c < mask.cols; ++c) {
        if (top[c] >= 0) {
            if (first < 0) first = c;
            last = c;
        }
    }
    if (first < 0) return m;
    std::vector<double> heights, bottoms, columns, tops;
    for (int c : sliceColumns(first, last, params)) {
        if (top[c] < 0) continue;
        heights.push_back(bottom[c] - top[c] + 1);
        bottoms.push_back(bottom[c] + 0.5);
        tops.push_back(top[c] - 0.5);
        columns.push_back(c);
    }
    if (heights.empty()) return m;
    m.valid = true;
    m.sliceCount = static_cast<int>(heights.size());
    m.medianHeightPx = median(heights);
    m.medianBottomEdgePx = median(bottoms);
    m.centerColumnPx = 0.5 * (first + last);
    m.extentWidthPx = last - first;
    m.box = cv::Rect2d(first - 0.5, minRow - 0.5, last - first + 1, maxRow - minRow + 1);
    const size_t n = columns.size(), half = n / 2;
    if (half > 0) {
        std::vector<double> bottomSlopes, topSlopes;
        for (size_t i = 0; i + half < n; ++i) {
            const double du = columns[i + half] - columns[i];
            bottomSlopes.push_back((bottoms[i + half] - bottoms[i]) / du);
            topSlopes.push_back((tops[i + half] - tops[i]) / du);
        }
        m.bottomEdgeSlope = median(bottomSlopes);
        m.topEdgeSlope = median(topSlopes);
    }
    return m;
}

SliceMeasurement measureSliceEdges(const std::vector<SliceEdges>& edges, const SliceMeasurement& base) {
    SliceMeasurement m = base;
    m.valid = false;
    m.sliceCount = 0;
    if (edges.empty()) return m;
    std::vector<double> heights, bottoms;
    for (const SliceEdges& e : edges) {
        heights.push_back(e.bottomEdgePx - e.topEdgePx);
        bottoms.push_back(e.bottomEdgePx);
    }
    m.valid = true;
    m.sliceCount = static_cast<int>(edges.size());
    m.medianHeightPx = median(heights);
    m.medianBottomEdgePx = median(bottoms);
    m.bottomEdgeSlope = 0;
    m.topEdgeSlope = 0;
    const size_t n = edges.size(), half = n / 2;
    if (half > 0) {
        std::vector<double> bottomSlopes, topSlopes;
        for (size_t i = 0; i + half < n; ++i) {
            const double du = edges[i + half].column - edges[i].column;
            if (!(std::abs(du) > 0)) continue;
            bottomSlopes.push_back((edges[i + half].bottomEdgePx - edges[i].bottomEdgePx) / du);
            topSlopes.push_back((edges[i + half].topEdgePx - edges[i].topEdgePx) / du);
        }
        if (!bottomSlopes.empty()) {
            m.bottomEdgeSlope = median(bottomSlopes);
            m.topEdgeSlope = median(topSlopes);
        }
    }
    return m;
}

}  // namespace wf::sign
