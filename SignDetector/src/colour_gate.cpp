#include "colour_gate.hpp"

#include "image_input.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace wf::sign {

namespace {

cv::Mat wrapPlane(const uint8_t* data, int width, int height, size_t stride, int type) {
    return cv::Mat(height, width, type, const_cast<uint8_t*>(data), stride);
}

/// Integer shrink factor for a frame of `width` x `height` (see ColourGateParams::workingLongSidePx).
int shrinkFactor(int width, int height, const ColourGateParams& params) {
    const double ratio = double(std::max(width, height)) / std::max(1, params.workingLongSidePx);
    return std::max(1, static_cast<int>(std::lround(ratio)));
}

}  // namespace

cv::Mat redGreenOpponent(const wf_image& image, const ColourGateParams& params, cv::Point2d* rawPerWorkingPx) {
    const int format = enumValue(image.format);
    const int factor = shrinkFactor(image.width, image.height, params);
    const cv::Size working(std::max(1, image.width / factor), std::max(1, image.height / factor));
    cv::Mat small, opponent;
    switch (format) {
        case WF_PIXEL_RGB8:
        case WF_PIXEL_BGRA8: {
            const bool rgb = format == WF_PIXEL_RGB8;
            const cv::Mat full = wrapPlane(image.data, image.width, image.height, image.stride, rgb ? CV_8UC3 : CV_8UC4);
            // The first working x factor columns and rows only, so INTER_AREA shrinks by exactly `factor` (its fast
            // path; a 639 x 479 frame took 1.6 ms instead of 0.09 ms); the last factor - 1 columns and rows at most
            // are left out of the gate.
            const cv::Rect exact(0, 0, std::min(image.width, working.width * factor),
                                 std::min(image.height, working.height * factor));
            *rawPerWorkingPx = {double(exact.width) / working.width, double(exact.height) / working.height};
            cv::resize(full(exact), small, working, 0, 0, cv::INTER_AREA);
            // d = R - G: RGB8 channels (R, G, B), BGRA8 channels (B, G, R, A).
            cv::Mat red, green;
            cv::extractChannel(small, red, rgb ? 0 : 2);
            cv::extractChannel(small, green, 1);
            cv::subtract(red, green, opponent, cv::noArray(), CV_32F);
            return opponent;
        }
        case WF_PIXEL_NV12: {
            if (image.data_uv == nullptr) return {};
            *rawPerWorkingPx = {double(image.width) / working.width, double(image.height) / working.height};
            const cv::Mat chroma =
                wrapPlane(image.data_uv, (image.width + 1) / 2, (image.height + 1) / 2, image.stride_uv, CV_8UC2);
            cv::resize(chroma, small, working, 0, 0, cv::INTER_AREA);
            small.convertTo(small, CV_32F);
            // Full-range BT.601: R - G = (Y + 1.402 Cr') - (Y - 0.344136 Cb' - 0.714136 Cr'), Cb' = Cb - 128.
            const float kb = 0.344136f, kr = 1.402f + 0.714136f;
            cv::transform(small, opponent, cv::Matx13f(kb, kr, -128.f * (kb + kr)));
            return opponent;
        }
        default: return {};  // GRAY8: no colour
    }
}

ColourContrast localColourContrast(const wf_image& image, const ColourGateParams& params) {
    ColourContrast out;
    const cv::Mat opponent = redGreenOpponent(image, params, &out.rawPerWorkingPx);
    if (opponent.empty()) return out;
    double minD = 0, maxD = 0;
    cv::minMaxLoc(opponent, &minD, &maxD);
    if (std::max(-minD, maxD) < params.minColourfulness) return out;  // a gray frame: no usable colour
    const int k = std::max(3, params.localWindowPx | 1);
    cv::Mat localMean;
    cv::blur(opponent, localMean, cv::Size(k, k), cv::Point(-1, -1), cv::BORDER_REFLECT);
    cv::absdiff(opponent, localMean, out.contrast);
    return out;
}

ColourBlobs findColourBlobs(const wf_image& image, const ColourGateParams& params) {
    return colourBlobsAbove(localColourContrast(image, params), params.minContrast, params);
}

ColourBlobs colourBlobsAbove(const ColourContrast& colour, double minContrast, const ColourGateParams& params) {
    ColourBlobs blobs;
    if (colour.contrast.empty()) return blobs;
    blobs.colourAvailable = true;
    const cv::Point2d scale = colour.rawPerWorkingPx;
    cv::Mat mask;
    cv::compare(colour.contrast, minContrast, mask, cv::CMP_GE);
    cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));

    // Working pixel j covers raw [j s - 0.5, (j + 1) s - 0.5] (pixel-centre convention).
    auto rawBox = [&](int x, int y, int w, int h) {
        return cv::Rect2d(x * scale.x - 0.5, y * scale.y - 0.5, w * scale.x, h * scale.y);
    };
    cv::Rect2d component;  // the current component's raw box
    auto addBlob = [&](int x, int y, int w, int h, bool whole) {
        blobs.wholeComponent.push_back(whole);
        blobs.rawBoxes.push_back(rawBox(x, y, w, h));
        blobs.componentRawBoxes.push_back(component);
    };
    // Components (8-connected) and their bounding boxes, computed here in one pass over the labels: OpenCV's
    // connectedComponentsWithStats also computes centroids and took 0.45 ms at 320 x 240 against 0.14 ms for the
    // labels alone.
    cv::Mat labels;
    const int n = cv::connectedComponents(mask, labels, 8, CV_32S);
    std::vector<cv::Vec4i> extent(static_cast<size_t>(std::max(n, 1)), cv::Vec4i(INT32_MAX, INT32_MAX, -1, -1));
    for (int r = 0; r < labels.rows; ++r) {
        const int* row = labels.ptr<int>(r);
        for (int c = 0; c < labels.cols; ++c) {
            if (row[c] == 0) continue;
            cv::Vec4i& e = extent[static_cast<size_t>(row[c])];
            e[0] = std::min(e[0], c), e[1] = std::min(e[1], r), e[2] = std::max(e[2], c), e[3] = std::max(e[3], r);
        }
    }
    // A large component (a line across the frame, the outline of a coloured wall or door): its bounding box would
    // cover far more than its pixels, so it is cut into tile x tile cells anchored at its top-left corner and each
    // cell's part of the component becomes a blob of its own. Cell extents of all large components, one pass.
    const int tile = std::max(4, params.tileSidePx);
    std::vector<int> firstCell(static_cast<size_t>(std::max(n, 1)), -1), cellsX(static_cast<size_t>(std::max(n, 1)), 0);
    int cells = 0;
    for (int i = 1; i < n; ++i) {
        const cv::Vec4i& e = extent[static_cast<size_t>(i)];
        const int w = e[2] - e[0] + 1, h = e[3] - e[1] + 1;
        if (std::max(w, h) <= tile) continue;
        firstCell[static_cast<size_t>(i)] = cells;
        cellsX[static_cast<size_t>(i)] = (w + tile - 1) / tile;
        cells += cellsX[static_cast<size_t>(i)] * ((h + tile - 1) / tile);
    }
    std::vector<cv::Vec4i> cellExtent(static_cast<size_t>(cells), cv::Vec4i(INT32_MAX, INT32_MAX, -1, -1));
    if (cells > 0) {
        for (int r = 0; r < labels.rows; ++r) {
            const int* row = labels.ptr<int>(r);
            for (int c = 0; c < labels.cols; ++c) {
                const int l = row[c];
                if (l == 0 || firstCell[static_cast<size_t>(l)] < 0) continue;
                const cv::Vec4i& box = extent[static_cast<size_t>(l)];
                const size_t cell = static_cast<size_t>(firstCell[static_cast<size_t>(l)] +
                                                        ((r - box[1]) / tile) * cellsX[static_cast<size_t>(l)] +
                                                        (c - box[0]) / tile);
                cv::Vec4i& e = cellExtent[cell];
                e[0] = std::min(e[0], c), e[1] = std::min(e[1], r), e[2] = std::max(e[2], c), e[3] = std::max(e[3], r);
            }
        }
    }
    for (int i = 1; i < n; ++i) {
        const cv::Vec4i& e = extent[static_cast<size_t>(i)];
        if (e[2] < 0) continue;
        const int x = e[0], y = e[1], w = e[2] - e[0] + 1, h = e[3] - e[1] + 1;
        component = rawBox(x, y, w, h);
        if (firstCell[static_cast<size_t>(i)] < 0) {
            addBlob(x, y, w, h, true);
            continue;
        }
        const int first = firstCell[static_cast<size_t>(i)];
        const int count = cellsX[static_cast<size_t>(i)] * ((h + tile - 1) / tile);
        for (int k = first; k < first + count; ++k) {
            const cv::Vec4i& c = cellExtent[static_cast<size_t>(k)];
            if (c[2] >= 0) addBlob(c[0], c[1], c[2] - c[0] + 1, c[3] - c[1] + 1, false);
        }
    }
    return blobs;
}

GateDecision gateRegions(const ColourBlobs& blobs, const Unrolling& unrolling, int lastRow,
                         const ColourGateParams& params) {
    GateDecision decision;
    if (!params.enabled || !blobs.colourAvailable) return decision;
    const cv::Size canvas = unrolling.unrolledSize();
    const int rows = lastRow < 0 ? canvas.height : std::min(lastRow, canvas.height);
    const cv::Rect searched(0, 0, canvas.width, std::max(0, rows));
    decision.fullSearch = false;
    if (searched.area() == 0) return decision;

    // Bounding box (x0, y0, x1, y1) of a raw box's four corners in the unrolled image (pixel edges).
    auto unrolledBounds = [&](const cv::Rect2d& b) {
        cv::Vec4d e(1e300, 1e300, -1e300, -1e300);
        const cv::Point2d corners[4] = {{b.x, b.y}, {b.x + b.width, b.y}, {b.x, b.y + b.height},
                                        {b.x + b.width, b.y + b.height}};
        for (const cv::Point2d& c : corners) {
            const cv::Point2d u = unrolling.rawToUnrolled(c);
            e = cv::Vec4d(std::min(e[0], u.x), std::min(e[1], u.y), std::max(e[2], u.x), std::max(e[3], u.y));
        }
        return e;
    };
    std::vector<SearchRegion> regions;
    regions.reserve(blobs.rawBoxes.size());
    for (size_t bi = 0; bi < blobs.rawBoxes.size(); ++bi) {
        const cv::Vec4d e = unrolledBounds(blobs.rawBoxes[bi]);
        const double x0 = e[0], y0 = e[1], x1 = e[2], y1 = e[3];
        const bool whole = bi < blobs.wholeComponent.size() && blobs.wholeComponent[bi];
        // A tile's whole component in the unrolled image (a whole blob is its own component: not needed).
        const cv::Vec4d c =
            !whole && bi < blobs.componentRawBoxes.size() ? unrolledBounds(blobs.componentRawBoxes[bi]) : e;
        const double componentSide = std::max(c[2] - c[0], c[3] - c[1]);
        double minMargin = params.minMarginPx;
        if (!whole && componentSide <= params.nearSignComponentMaxPx) {
            minMargin = std::max(minMargin, double(params.nearSignMarginPx));  // may be a near sign's lettering
        }
        const double margin = std::max(minMargin, params.marginFactor * std::max(x1 - x0, y1 - y0));
        // Edges -> integer pixel indices: pixel i covers [i - 0.5, i + 0.5].
        const int left = static_cast<int>(std::floor(x0 - margin + 0.5));
        const int top = static_cast<int>(std::floor(y0 - margin + 0.5));
        const int right = static_cast<int>(std::ceil(x1 + margin - 0.5));   // last column, inclusive
        const int bottom = static_cast<int>(std::ceil(y1 + margin - 0.5));  // last row, inclusive
        const cv::Rect r = cv::Rect(left, top, right - left + 1, bottom - top + 1) & searched;
        int minWidth = whole ? static_cast<int>(params.minWindowBlobFraction * (x1 - x0)) : 0;
        if (!whole && params.componentWindowFraction > 0) {
            minWidth = static_cast<int>(params.componentWindowFraction * (c[2] - c[0]));
        }
        if (r.area() > 0) regions.push_back({r, minWidth});
    }
    // Merge overlapping regions when the union costs no more than searching both (a sign whose letters fell
    // into several blobs, a sign and its glow): each detectMultiScale call then sees the whole sign once.
    // Regions whose union would be larger (an L-shaped chain of tiles) stay apart; suppressOverlaps removes
    // the duplicate boxes their overlap may produce.
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t i = 0; i < regions.size() && !merged; ++i) {
            for (size_t j = i + 1; j < regions.size(); ++j) {
                const cv::Rect &a = regions[i].unrolledRect, &b = regions[j].unrolledRect, both = a | b;
                if ((a & b).area() > 0 && both.area() <= a.area() + b.area()) {
                    regions[i] = {both, std::min(regions[i].minWindowWidthPx, regions[j].minWindowWidthPx)};
                    regions.erase(regions.begin() + static_cast<std::ptrdiff_t>(j));
                    merged = true;
                    break;
                }
            }
        }
    }
    double area = 0;
    for (const SearchRegion& r : regions) area += r.unrolledRect.area();
    decision.coveredFraction = area / searched.area();
    if (static_cast<int>(regions.size()) > params.maxRegions || area > params.maxAreaFraction * searched.area()) {
        decision.fullSearch = true;
        return decision;
    }
    decision.regions = std::move(regions);
    return decision;
}

GateDecision gateFrame(const wf_image& image, const Unrolling& unrolling, int lastRow, const ColourGateParams& params) {
    if (!params.enabled) return GateDecision{};
    const ColourContrast colour = localColourContrast(image, params);
    GateDecision decision = gateRegions(colourBlobsAbove(colour, params.minContrast, params), unrolling, lastRow, params);
    decision.minContrast = params.minContrast;
    if (params.crowdedContrastFactor <= 1.0 || colour.contrast.empty()) return decision;
    if (!decision.fullSearch && !(decision.coveredFraction > params.crowdedAreaFraction)) return decision;
    // A crowded frame (colourful clutter, posters): Exit lettering is among the most saturated things in view, so
    // the threshold is raised once and the regions of the raised threshold are searched.
    const double raised = params.minContrast * params.crowdedContrastFactor;
    decision = gateRegions(colourBlobsAbove(colour, raised, params), unrolling, lastRow, params);
    decision.minContrast = raised;
    return decision;
}

}  // namespace wf::sign
