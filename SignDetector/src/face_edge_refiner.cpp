#include "face_edge_refiner.hpp"

#include "image_input.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace wf::sign {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// 8-bit code value -> light, in 0..255 units.
const std::array<float, 256>& transferTable(PixelTransfer transfer) {
    static const std::array<float, 256> linear = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[i] = float(i);
        return t;
    }();
    static const std::array<float, 256> srgb = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;  // IEC 61966-2-1 decoding
            t[i] = float(255.0 * (c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4)));
        }
        return t;
    }();
    return transfer == PixelTransfer::kSrgb ? srgb : linear;
}

double medianOf(std::vector<double>& v) {
    const size_t n = v.size();
    std::nth_element(v.begin(), v.begin() + n / 2, v.end());
    const double upper = v[n / 2];
    if (n % 2 == 1) return upper;
    return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + n / 2));
}

/// Rise-finding settings in rows (resolved from FaceEdgeParams for one measurement).
struct RowSettings {
    int stripRows = 2, persistenceRows = 2, blurRows = 2;
    double minRiseLevels = 12, minRiseNoiseFactor = 4;
    EdgeLocator locator = EdgeLocator::kGradientPeak;
};

/// A rise found by outermostRise: its edge's index (NaN: none), or the index to restart the search from when the
/// rise was the background's (restartAt >= 0; the rise's top sample).
struct Rise {
    double edge = kNaN;
    int restartAt = -1;
};

/// The outermost significant, persistent rise of `d` (distance from the background colour, index 0 = outermost
/// sample, the first `stripRows` samples are the background strip). Returns the edge's index (fractional, between
/// sample centres; s.locator: the peak of the parabola through the three steps around the steepest one, or the
/// point where the rise crosses half-way from its foot to its top), or NaN.
///
/// A rise is found at a maximum of the step d[k + 1] - d[k] over +-blurRows (the edge's gradient peak) and followed both ways
/// while the steps stay above a sixth of the peak, at most blurRows samples (the blur's half-width): a halo or a
/// vignetting slope is far less steep than the edge and is not followed, so the foot and top are the levels on
/// either side of the edge itself, and the window is near-symmetric about the peak (no shift for a symmetric blur).
/// It counts when it rises by at least max(minRiseLevels, minRiseNoiseFactor x noise) and d stays at or above its
/// half level over most of the persistenceRows after its top (a line on the wall returns to the wall's colour).
/// `isBackground(foot, top)` (sample indices) says whether the wall beside the face shows the same change: then
/// the search stops there and asks to be restarted behind the rise.
template <class Veto>
Rise outermostRise(const std::vector<double>& d, double noise, const RowSettings& s, const Veto& isBackground) {
    const int n = static_cast<int>(d.size());
    Rise none;
    if (n < 3) return none;
    const double threshold = std::max(s.minRiseLevels, s.minRiseNoiseFactor * noise);
    auto step = [&](int k) { return d[k + 1] - d[k]; };  // between samples k and k + 1
    for (int k = std::max(0, s.stripRows - 1); k + 1 < n; ++k) {
        const double peak = step(k);
        if (!(peak > 0)) continue;
        // The steepest step within the blur's half-width on either side (ties: the outer one): on a halo's slope,
        // which steepens towards the face, and on noise, the edge itself or a steeper step is near.
        bool steepest = true;
        for (int j = std::max(0, k - s.blurRows); j <= std::min(n - 2, k + s.blurRows) && steepest; ++j) {
            steepest = j < k ? step(j) <= peak : (j == k || step(j) < peak);
        }
        if (!steepest) continue;
        const double floor = peak / 6;
        int a = k;  // foot sample
        while (a > 0 && k - a < s.blurRows && step(a - 1) > floor) --a;
        int b = k + 1;  // top sample
        while (b + 1 < n && b - (k + 1) < s.blurRows && step(b) > floor) ++b;
        const double rise = d[b] - d[a];
        if (rise < threshold) continue;
        const double half = 0.5 * (d[a] + d[b]);
        int total = 0, above = 0;
        for (int j = b; j < std::min(n, b + s.persistenceRows); ++j) {
            ++total;
            above += d[j] >= half;
        }
        if (total == 0 || above < 0.6 * total) {
            k = b - 1;  // past this rise
            continue;
        }
        Rise found;
        if (isBackground(a, b)) {
            found.restartAt = b;
            return found;
        }
        if (s.locator == EdgeLocator::kGradientPeak) {
            const double l = k > 0 ? step(k - 1) : 0.0, r = k + 2 < n ? step(k + 1) : 0.0;
            const double den = l - 2 * peak + r;
            const double delta = den < 0 ? std::clamp(0.5 * (l - r) / den, -0.5, 0.5) : 0.0;
            found.edge = k + 0.5 + delta;
            return found;
        }
        found.edge = a;
        for (int j = a + 1; j <= b; ++j) {
            if (d[j] >= half) {
                found.edge = (j - 1) + (half - d[j - 1]) / std::max(1e-9, d[j] - d[j - 1]);
                break;
            }
        }
        return found;
    }
    return none;
}

/// Distance profile from the background strip of rows `rows` (in order, outermost first) of column `u` of `light`
/// (CV_32FC(ch), horizontally smoothed): d[k] = ||c(rows[k]) - B||, B = per-channel median of the strip; `noise`
/// = median distance over the strip.
void distanceProfile(const cv::Mat& light, int u, int firstRow, int step, int n, int stripRows, std::vector<double>* d,
                     double* noise) {
    const int ch = light.channels();
    std::array<double, 3> background{};
    std::vector<double> values(static_cast<size_t>(stripRows));
    for (int c = 0; c < ch; ++c) {
        for (int k = 0; k < stripRows; ++k) values[k] = light.ptr<float>(firstRow + k * step)[u * ch + c];
        background[c] = medianOf(values);
    }
    d->resize(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) {
        const float* p = light.ptr<float>(firstRow + k * step) + u * ch;
        double sum = 0;
        for (int c = 0; c < ch; ++c) sum += (p[c] - background[c]) * (p[c] - background[c]);
        (*d)[k] = std::sqrt(sum);
    }
    std::vector<double> strip(d->begin(), d->begin() + stripRows);
    *noise = medianOf(strip);
}

/// Robust straight line v = slope (column - centre) + offset through (columns, values): slope = median of the slopes
/// between entry i and i + n/2 (as measureSliceEdges takes them), offset = median of the residual intercepts.
void robustLine(const std::vector<SliceEdges>& e, double centre, bool top, double* slope, double* offset) {
    auto value = [&](const SliceEdges& x) { return top ? x.topEdgePx : x.bottomEdgePx; };
    const size_t n = e.size(), half = n / 2;
    std::vector<double> slopes;
    for (size_t i = 0; i + half < n && half > 0; ++i) {
        const double du = e[i + half].column - e[i].column;
        if (std::abs(du) > 0) slopes.push_back((value(e[i + half]) - value(e[i])) / du);
    }
    *slope = slopes.empty() ? 0.0 : medianOf(slopes);
    std::vector<double> offsets;
    for (const SliceEdges& x : e) offsets.push_back(value(x) - *slope * (x.column - centre));
    *offset = medianOf(offsets);
}

/// The slices whose top and bottom edges both lie within `tolerancePx` of robust straight lines through all of them:
/// a face's edges are straight (a plane rectangle in perspective), so slices whose search caught a letter, a halo
/// or the wall instead are outliers.
std::vector<SliceEdges> straightEdgeInliers(const std::vector<SliceEdges>& e, double centre, double tolerancePx) {
    if (e.size() < 3) return e;
    double topSlope = 0, topOffset = 0, bottomSlope = 0, bottomOffset = 0;
    robustLine(e, centre, true, &topSlope, &topOffset);
    robustLine(e, centre, false, &bottomSlope, &bottomOffset);
    std::vector<SliceEdges> kept;
    for (const SliceEdges& x : e) {
        const double dc = x.column - centre;
        if (std::abs(x.topEdgePx - (topSlope * dc + topOffset)) <= tolerancePx &&
            std::abs(x.bottomEdgePx - (bottomSlope * dc + bottomOffset)) <= tolerancePx) {
            kept.push_back(x);
        }
    }
    return kept;
}

struct RoughGeometry {
    double height = 0, top = 0, bottom = 0, centre = 0;
    int first = 0, last = -1;
};

/// Columns of the wall beside the face, relative to the rough extent: `gap` columns outside it, `width` wide.
struct SideColumns {
    int gap = 1, width = 2;
};

SideColumns sideColumns(double roughHeightPx, const FaceEdgeParams& params) {
    SideColumns c;
    c.gap = 1 + static_cast<int>(std::lround(std::max(0.0, params.sideGapFraction) * roughHeightPx));
    c.width = std::max(2, static_cast<int>(std::lround(std::max(0.0, params.sideWidthFraction) * roughHeightPx)));
    return c;
}

/// Per row of `light`, the per-channel median colour of columns [x0, x0 + width) (CV_32FC(ch) rows x 1), or an
/// empty Mat when those columns are not all inside `light`.
cv::Mat sideColours(const cv::Mat& light, int x0, int width) {
    if (x0 < 0 || x0 + width > light.cols || width <= 0) return cv::Mat();
    const int ch = light.channels();
    cv::Mat out(light.rows, 1, CV_32FC(ch));
    std::vector<double> values(static_cast<size_t>(width));
    for (int r = 0; r < light.rows; ++r) {
        const float* p = light.ptr<float>(r);
        for (int c = 0; c < ch; ++c) {
            for (int i = 0; i < width; ++i) values[i] = p[(x0 + i) * ch + c];
            out.ptr<float>(r)[c] = static_cast<float>(medianOf(values));
        }
    }
    return out;
}

/// ||(a1 - a0) - (b1 - b0)|| and ||a1 - a0|| for ch-channel colours.
void colourChanges(const float* a0, const float* a1, const float* b0, const float* b1, int ch, double* difference,
                   double* change) {
    double dd = 0, cc = 0;
    for (int c = 0; c < ch; ++c) {
        const double da = a1[c] - a0[c], db = b1[c] - b0[c];
        dd += (da - db) * (da - db);
        cc += da * da;
    }
    *difference = std::sqrt(dd);
    *change = std::sqrt(cc);
}

RoughGeometry roughGeometry(const SliceMeasurement& rough) {
    RoughGeometry g;
    g.height = rough.medianHeightPx;
    g.bottom = rough.medianBottomEdgePx;
    g.top = g.bottom - g.height;
    g.centre = rough.centerColumnPx;
    g.first = static_cast<int>(std::lround(rough.centerColumnPx - 0.5 * rough.extentWidthPx));
    g.last = static_cast<int>(std::lround(rough.centerColumnPx + 0.5 * rough.extentWidthPx));
    return g;
}

}  // namespace

FaceEdgeParams maskFaceEdgeParams(FaceEdgeParams base) {
    base.searchMarginFraction = 0.15;
    base.minHeightRatio = 0.75;
    base.maxHeightRatio = 1.3;
    return base;
}

cv::Rect faceEdgeSearchRect(const SliceMeasurement& rough, const FaceEdgeParams& params) {
    const RoughGeometry g = roughGeometry(rough);
    const double margin = std::max(0.0, params.searchMarginFraction) * g.height;
    const double half = 0.5 * std::max(0.0, rough.extentWidthPx);
    const double slopeRise = half * std::max(0.0, params.maxEdgeSlope);
    const SideColumns side = sideColumns(g.height, params);
    const int x0 = g.first - side.gap - side.width, x1 = g.last + side.gap + side.width;
    const int y0 = static_cast<int>(std::floor(g.top - margin - slopeRise)) - 1;
    const int y1 = static_cast<int>(std::ceil(g.bottom + margin + slopeRise)) + 1;
    return cv::Rect(x0, y0, std::max(0, x1 - x0 + 1), std::max(0, y1 - y0 + 1));
}

FaceEdgeResult refineFaceEdges(const cv::Mat& image, const SliceMeasurement& rough, const SliceParams& slices,
                               const FaceEdgeParams& params) {
    CV_Assert(image.type() == CV_8UC1 || image.type() == CV_8UC3);
    FaceEdgeResult result;
    result.measurement = rough;
    const RoughGeometry g = roughGeometry(rough);
    if (!params.enabled || !rough.valid || !(g.height >= 2) || g.last < g.first) return result;

    // The pixels the search reads, as light, smoothed over 3 columns (edges are near-horizontal in the unrolled
    // image; the symmetric kernel moves no edge).
    const cv::Rect want = faceEdgeSearchRect(rough, params);
    const cv::Rect roi = want & cv::Rect(0, 0, image.cols, image.rows);
    if (roi.width < 3 || roi.height < 4) return result;
    const std::array<float, 256>& table = transferTable(params.transfer);
    const int ch = image.channels();
    cv::Mat light(roi.height, roi.width, CV_32FC(ch));
    for (int r = 0; r < roi.height; ++r) {
        const uchar* in = image.ptr<uchar>(roi.y + r) + roi.x * ch;
        float* out = light.ptr<float>(r);
        for (int i = 0; i < roi.width * ch; ++i) out[i] = table[in[i]];
    }
    cv::blur(light, light, cv::Size(3, 1), cv::Point(-1, -1), cv::BORDER_REPLICATE);

    RowSettings s;
    s.stripRows = std::max(2, static_cast<int>(std::lround(params.backgroundStripFraction * g.height)));
    s.persistenceRows = std::max(2, static_cast<int>(std::lround(params.persistenceFraction * g.height)));
    s.blurRows = std::max(2, static_cast<int>(std::lround(params.blurFraction * g.height)));
    s.minRiseLevels = params.minRiseLevels;
    s.minRiseNoiseFactor = params.minRiseNoiseFactor;
    s.locator = params.locator;
    const double margin = std::max(0.0, params.searchMarginFraction) * g.height;

    // The wall beside the face, per row: left and right of the rough extent (empty where outside the image, and
    // both empty when the check is off).
    const SideColumns side = sideColumns(g.height, params);
    const bool sideCheck = params.sideSameChangeFraction > 0;
    const cv::Mat sideLeft =
        sideCheck ? sideColours(light, g.first - side.gap - side.width - roi.x, side.width) : cv::Mat();
    const cv::Mat sideRight = sideCheck ? sideColours(light, g.last + side.gap + 1 - roi.x, side.width) : cv::Mat();
    // Is the rise between profile samples `foot` and `top` (ROI rows row0 + step * index) the background's? Either
    // side changes colour the same way across the same rows, widened by the blur's half-width each way (the
    // background's line need not be level with the slice).
    auto sameChangeBeside = [&](int u, int row0, int step, int n, int foot, int top) {
        const int rowFoot = row0 + step * foot, rowTop = row0 + step * top;
        const int outer = row0 + step * std::max(0, foot - s.blurRows);
        const int inner = row0 + step * std::min(n - 1, top + s.blurRows);
        const float* a0 = light.ptr<float>(rowFoot) + u * ch;
        const float* a1 = light.ptr<float>(rowTop) + u * ch;
        for (const cv::Mat* sideMat : {&sideLeft, &sideRight}) {
            if (sideMat->empty()) continue;
            double difference = 0, change = 0;
            colourChanges(a0, a1, sideMat->ptr<float>(outer), sideMat->ptr<float>(inner), ch, &difference, &change);
            if (difference < params.sideSameChangeFraction * change) return true;
        }
        return false;
    };
    // The edge on one side of a slice: the outermost rise of the distance from the wall's colour, searched again
    // behind every rise the wall beside the face shares (at most 3 restarts). Returns a sample index or NaN.
    std::vector<double> d;
    auto findEdge = [&](int u, int row0, int step, int n) {
        int start = 0;
        for (int attempt = 0; attempt < 4; ++attempt) {
            if (n - start < s.stripRows + 2) return kNaN;
            double noise = 0;
            distanceProfile(light, u, row0 + step * start, step, n - start, s.stripRows, &d, &noise);
            const Rise rise = outermostRise(d, noise, s, [&](int foot, int top) {
                return sameChangeBeside(u, row0, step, n, start + foot, start + top);
            });
            if (rise.restartAt < 0) return std::isnan(rise.edge) ? kNaN : start + rise.edge;
            start += rise.restartAt;
        }
        return kNaN;
    };

    std::vector<SliceEdges> edges;
    const std::vector<int> columns = sliceColumns(g.first, g.last, slices);
    result.searchedSlices = static_cast<int>(columns.size());
    for (int column : columns) {
        const int u = column - roi.x;
        if (u < 0 || u >= roi.width) continue;
        // The rough edges' slopes are not used to place the search (a ragged mask's slopes can be far off, a box
        // has none): the search is widened by the steepest slope a face's edge has in the unrolled image instead.
        const double widen = margin + params.maxEdgeSlope * std::abs(column - g.centre);
        const double top = g.top, bottom = g.bottom, mid = 0.5 * (top + bottom);
        // Top edge: rows from `widen` above the rough top edge down to the centre line (image rows).
        const int topStart = static_cast<int>(std::ceil(top - widen)), topEnd = static_cast<int>(std::floor(mid));
        const int bottomStart = static_cast<int>(std::floor(bottom + widen)), bottomEnd = static_cast<int>(std::ceil(mid));
        if (topStart < roi.y || bottomStart > roi.y + roi.height - 1) continue;  // the search leaves the image
        if (topEnd > roi.y + roi.height - 1 || bottomEnd < roi.y) continue;
        const int nTop = topEnd - topStart + 1, nBottom = bottomStart - bottomEnd + 1;
        if (nTop < s.stripRows + 2 || nBottom < s.stripRows + 2) continue;
        const double topIndex = findEdge(u, topStart - roi.y, +1, nTop);
        if (std::isnan(topIndex)) continue;
        const double bottomIndex = findEdge(u, bottomStart - roi.y, -1, nBottom);
        if (std::isnan(bottomIndex)) continue;
        SliceEdges e;
        e.column = column;
        e.topEdgePx = topStart + topIndex;  // sample k is the centre of row topStart + k
        e.bottomEdgePx = bottomStart - bottomIndex;
        const double h = e.bottomEdgePx - e.topEdgePx;
        if (!(h >= params.minHeightRatio * g.height && h <= params.maxHeightRatio * g.height)) continue;
        edges.push_back(e);
    }
    edges = straightEdgeInliers(edges, g.centre, std::max(params.straightnessMinPx, params.straightnessFraction * g.height));
    result.validSlices = static_cast<int>(edges.size());
    if (result.validSlices < std::max(3.0, params.minValidFraction * result.searchedSlices)) return result;
    SliceMeasurement refined = measureSliceEdges(edges, rough);
    if (!refined.valid || !(refined.medianHeightPx >= params.minHeightRatio * g.height &&
                            refined.medianHeightPx <= params.maxHeightRatio * g.height)) {
        return result;
    }
    result.refined = true;
    result.measurement = refined;
    return result;
}

FaceEdgeResult refineFaceEdgesInFrame(const wf_image& image, const Unrolling& unrolling, const SliceMeasurement& rough,
                                      const SliceParams& slices, const FaceEdgeParams& params) {
    FaceEdgeResult none;
    none.measurement = rough;
    if (!params.enabled || !rough.valid) return none;
    const cv::Size unrolledSize = unrolling.unrolledSize();
    const cv::Rect patchRect = faceEdgeSearchRect(rough, params) & cv::Rect(0, 0, unrolledSize.width, unrolledSize.height);
    if (patchRect.width < 3 || patchRect.height < 4) return none;
    // Raw pixels under the patch: its corner pixel centres mapped to raw, plus 2 px for the bilinear footprint;
    // even-aligned so that NV12's 2 x 2 chroma stays on its grid.
    double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
    for (int i = 0; i < 4; ++i) {
        const cv::Point2d q = unrolling.unrolledToRaw(cv::Point2d(patchRect.x + (i % 2) * (patchRect.width - 1),
                                                                  patchRect.y + (i / 2) * (patchRect.height - 1)));
        minX = std::min(minX, q.x), maxX = std::max(maxX, q.x), minY = std::min(minY, q.y), maxY = std::max(maxY, q.y);
    }
    int rx0 = std::max(0, static_cast<int>(std::floor(minX)) - 2), ry0 = std::max(0, static_cast<int>(std::floor(minY)) - 2);
    rx0 -= rx0 % 2;
    ry0 -= ry0 % 2;
    const int rx1 = std::min(image.width - 1, static_cast<int>(std::ceil(maxX)) + 2);
    const int ry1 = std::min(image.height - 1, static_cast<int>(std::ceil(maxY)) + 2);
    if (rx1 < rx0 || ry1 < ry0) return none;
    wf_image sub = image;
    const int bpp = bytesPerPixel(enumValue(image.format));
    sub.data = image.data + static_cast<size_t>(ry0) * image.stride + static_cast<size_t>(rx0) * bpp;
    sub.width = rx1 - rx0 + 1;
    sub.height = ry1 - ry0 + 1;
    if (enumValue(image.format) == WF_PIXEL_NV12 && image.data_uv != nullptr) {
        sub.data_uv = image.data_uv + static_cast<size_t>(ry0 / 2) * image.stride_uv + static_cast<size_t>(rx0);
    }
    sub.data_bytes = 0;
    sub.data_uv_bytes = 0;
    const cv::Mat rgb = toRgb(sub);
    // Patch pixel (i, j) = unrolled pixel (patchRect.x + i, patchRect.y + j) = raw A (u, v, 1) - raw origin.
    const cv::Matx23d& a = unrolling.unrolledToRawMatrix();
    cv::Matx23d m = a;
    m(0, 2) = a(0, 0) * patchRect.x + a(0, 1) * patchRect.y + a(0, 2) - rx0;
    m(1, 2) = a(1, 0) * patchRect.x + a(1, 1) * patchRect.y + a(1, 2) - ry0;
    cv::Mat patch;
    cv::warpAffine(rgb, patch, cv::Mat(m), patchRect.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
    // Into the patch's pixel frame and back (scale 1, shifts by whole pixels: exact).
    const SliceMeasurement local = rough.mapped(1.0, cv::Point2d(-patchRect.x - 0.5, -patchRect.y - 0.5));
    FaceEdgeResult r = refineFaceEdges(patch, local, slices, params);
    r.measurement = r.refined ? r.measurement.mapped(1.0, cv::Point2d(patchRect.x - 0.5, patchRect.y - 0.5)) : rough;
    return r;
}

}  // namespace wf::sign
