#include "unet_detector.hpp"

#include "subpixel_transposed_conv.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <cstdio>

namespace wf::sign {

bool readClassList(const std::string& path, std::vector<std::string>* classes, std::string* error) {
    if (!std::ifstream(path).good()) {
        *error = "cannot open class list " + path;
        return false;
    }
    try {
        cv::FileStorage fs(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_JSON);
        if (!fs.isOpened()) {
            *error = "cannot open class list " + path;
            return false;
        }
        cv::FileNode node = fs["classes"];
        if (!node.isSeq() || node.size() < 2) {
            *error = "class list " + path + " needs \"classes\": [\"background\", ...] with at least 2 names";
            return false;
        }
        classes->clear();
        for (const auto& item : node) classes->push_back(static_cast<std::string>(item));
        return true;
    } catch (const cv::Exception& e) {
        *error = "class list " + path + " is not valid JSON: " + e.what();
        return false;
    }
}

bool UnetDetector::load(const std::string& path, const std::vector<std::string>& classNames, int inputSize,
                        std::string* error, bool subPixelUpsampling) {
    if (!std::ifstream(path).good()) {
        *error = "U-Net model not found or unreadable: " + path;
        return false;
    }
    try {
        std::ifstream file(path, std::ios::binary);
        modelBytes_.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
        subPixelUpsampling_ = subPixelUpsampling;
        nets_.clear();
        net_ = makeNet();
    } catch (const cv::Exception& e) {
        *error = "U-Net model " + path + " could not be read by cv::dnn: " + e.what();
        return false;
    }
    if (net_.empty()) {
        *error = "U-Net model " + path + " is empty";
        return false;
    }
    inputSize_ = inputSize > 0 ? inputSize : 224;
    classNames_ = classNames;
    // Probe once: checks the input shape and learns K.
    try {
        cv::Mat probe = cv::Mat::zeros(inputSize_, inputSize_, CV_8UC3);
        cv::Mat logits = forwardBlob(cv::dnn::blobFromImage(probe, 1.0 / 255.0));
        if (logits.dims != 4 || logits.size[0] != 1 || logits.size[2] != inputSize_ || logits.size[3] != inputSize_) {
            *error = "U-Net model " + path + " must output 1xKx" + std::to_string(inputSize_) + "x" +
                     std::to_string(inputSize_) + " logits";
            return false;
        }
        const int k = logits.size[1];
        if (k < 2) {
            *error = "U-Net model " + path + " outputs " + std::to_string(k) + " class(es); need background + >= 1";
            return false;
        }
        if (classNames_.empty()) {
            classNames_.push_back("background");
            for (int c = 1; c < k; ++c) classNames_.push_back("class" + std::to_string(c));
        }
        if (static_cast<int>(classNames_.size()) != k) {
            *error = "U-Net model " + path + " outputs " + std::to_string(k) + " classes but the class list has " +
                     std::to_string(classNames_.size());
            return false;
        }
    } catch (const cv::Exception& e) {
        *error = "U-Net model " + path + " failed on a " + std::to_string(inputSize_) + "x" +
                 std::to_string(inputSize_) + " input: " + e.what();
        return false;
    }
    return true;
}

cv::dnn::Net UnetDetector::makeNet() const {
    cv::dnn::Net net = readOnnxNet(modelBytes_.data(), modelBytes_.size(), subPixelUpsampling_);
    net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    return net;
}

cv::dnn::Net& UnetDetector::netFor(int rows, int cols) {
    // cv::dnn re-plans the whole network (allocation, layer finalisation, fusion) whenever the input shape
    // differs from the previous call's; one frame runs three shapes (coarse, band, zoom), so each shape gets
    // its own Net, built once from the model bytes (least recently used one replaced beyond kMaxNets).
    ++useClock_;
    for (auto& e : nets_) {
        if (e.rows == rows && e.cols == cols) {
            e.lastUse = useClock_;
            return e.net;
        }
    }
    if (nets_.empty() && !net_.empty()) {
        nets_.push_back({rows, cols, useClock_, net_});  // the loaded net serves the first shape
        net_ = cv::dnn::Net();
        return nets_.back().net;
    }
    if (static_cast<int>(nets_.size()) < kMaxNets) {
        nets_.push_back({rows, cols, useClock_, makeNet()});
        return nets_.back().net;
    }
    auto lru = std::min_element(nets_.begin(), nets_.end(),
                                [](const CachedNet& a, const CachedNet& b) { return a.lastUse < b.lastUse; });
    lru->rows = rows;
    lru->cols = cols;
    lru->lastUse = useClock_;
    return lru->net;  // re-planned for the new shape on its next forward
}

cv::Mat UnetDetector::forwardShared(const cv::Mat& blob) {
    CV_Assert(blob.dims == 4);
    cv::dnn::Net& net = netFor(blob.size[2], blob.size[3]);
    net.setInput(blob, "image");
    return net.forward();
}

cv::Mat UnetDetector::forwardBlob(const cv::Mat& blob) { return forwardShared(blob).clone(); }

std::vector<cv::Mat> UnetDetector::probabilities(const cv::Mat& rgb) {
    CV_Assert(rgb.type() == CV_8UC3 && !rgb.empty());
    // The blob (1x3xHxW, RGB / 255) is written into a reused buffer: split into reused byte planes, each
    // converted straight into its plane of the blob.
    const int dims[4] = {1, 3, rgb.rows, rgb.cols};
    blob_.create(4, dims, CV_32F);
    cv::split(rgb, planes_);
    for (int c = 0; c < 3; ++c) {
        cv::Mat dst(rgb.rows, rgb.cols, CV_32F, blob_.ptr<float>(0, c));
        planes_[c].convertTo(dst, CV_32F, 1.0 / 255.0);
    }
    const cv::Mat logits = forwardShared(blob_);  // the net's own output buffer: read before the next forward
    CV_Assert(logits.dims == 4 && logits.size[2] == rgb.rows && logits.size[3] == rgb.cols);
    const int k = logits.size[1];
    std::vector<cv::Mat> channels(k);
    std::vector<cv::Mat> in(k);
    for (int c = 0; c < k; ++c) {
        channels[c].create(rgb.rows, rgb.cols, CV_32F);
        in[c] = cv::Mat(rgb.rows, rgb.cols, CV_32F, const_cast<float*>(logits.ptr<float>(0, c)));
    }
    if (k == 2) {
        // p1 = 1 / (1 + exp(l0 - l1)), p0 = 1 - p1 (vectorised cv:: calls).
        cv::subtract(in[0], in[1], channels[1]);
        cv::exp(channels[1], channels[1]);
        cv::add(channels[1], 1.0, channels[1]);
        cv::divide(1.0, channels[1], channels[1]);
        cv::subtract(1.0, channels[1], channels[0]);
    } else {
        // Numerically stable softmax over classes.
        cv::Mat maxLogit = in[0].clone();
        for (int c = 1; c < k; ++c) cv::max(maxLogit, in[c], maxLogit);
        cv::Mat sum = cv::Mat::zeros(rgb.rows, rgb.cols, CV_32F);
        for (int c = 0; c < k; ++c) {
            cv::subtract(in[c], maxLogit, channels[c]);
            cv::exp(channels[c], channels[c]);
            sum += channels[c];
        }
        for (int c = 0; c < k; ++c) cv::divide(channels[c], sum, channels[c]);
    }
    return channels;
}

const cv::Mat& RawPyramid::level(int k, cv::Point2d* scale) {
    while (static_cast<int>(levels_.size()) <= k) {
        const cv::Mat& prev = levels_.back();
        if (prev.cols < 32 || prev.rows < 32) break;
        cv::Mat half;
        cv::resize(prev, half, cv::Size((prev.cols + 1) / 2, (prev.rows + 1) / 2), 0, 0, cv::INTER_AREA);
        levels_.push_back(half);
    }
    const cv::Mat& m = levels_[std::min<size_t>(k, levels_.size() - 1)];
    *scale = cv::Point2d(double(m.cols) / levels_[0].cols, double(m.rows) / levels_[0].rows);
    return m;
}

cv::Mat sampleUnrolled(RawPyramid& raw, const Unrolling& unrolling, cv::Point2d originEdge, double scaleX, double scaleY,
                       int size) {
    return sampleUnrolled(raw, unrolling, originEdge, scaleX, scaleY, cv::Size(size, size));
}

cv::Mat sampleUnrolled(RawPyramid& raw, const Unrolling& unrolling, cv::Point2d originEdge, double scaleX, double scaleY,
                       cv::Size size) {
    // Pyramid level leaving a downscale factor in [1, 2) (or an upscale) for the final bilinear warp.
    const double rawPerNetwork = std::max(scaleX, scaleY);
    const int k = rawPerNetwork >= 2.0 ? static_cast<int>(std::floor(std::log2(rawPerNetwork))) : 0;
    cv::Point2d ls;
    const cv::Mat& src = raw.level(k, &ls);
    // network (i, j) -> unrolled -> raw -> level: three affine maps composed (pixel-centre conventions).
    const cv::Matx33d network(scaleX, 0, originEdge.x + 0.5 * scaleX, 0, scaleY, originEdge.y + 0.5 * scaleY, 0, 0, 1);
    const cv::Matx23d& b = unrolling.unrolledToRawMatrix();
    const cv::Matx33d toRaw(b(0, 0), b(0, 1), b(0, 2), b(1, 0), b(1, 1), b(1, 2), 0, 0, 1);
    const cv::Matx33d toLevel(ls.x, 0, 0.5 * ls.x - 0.5, 0, ls.y, 0.5 * ls.y - 0.5, 0, 0, 1);
    const cv::Matx33d m = toLevel * toRaw * network;
    const cv::Matx23d m23(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2));
    cv::Mat out;
    cv::warpAffine(src, out, m23, size, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT,
                   cv::Scalar::all(0));
    if (raw.bgra()) cv::cvtColor(out, out, cv::COLOR_BGRA2RGB);  // the network reads R, G, B
    return out;
}

std::vector<UnetCandidate> UnetDetector::coarseCandidates(RawPyramid& raw, const Unrolling& unrolling,
                                                          const UnetParams& params, double pitchRad) {
    const int s = inputSize_;
    const cv::Size unrolledSize = unrolling.unrolledSize();
    const double scale = double(s) / std::max(unrolledSize.width, unrolledSize.height);  // network px per unrolled px
    const int w = std::max(1, static_cast<int>(std::lround(unrolledSize.width * scale)));
    const int h = std::max(1, static_cast<int>(std::lround(unrolledSize.height * scale)));
    // The letterbox is cut to the content rounded up to a multiple of 32 (the U-Net's down-sampling): a
    // 4:3 frame runs 224 x 192 instead of 224 x 224 at the same scale (0.86 x the cost).
    const int inW = std::min(s, (w + 31) / 32 * 32);
    int inH = std::min(s, (h + 31) / 32 * 32);
    const int offX = (inW - w) / 2, offY = (inH - h) / 2;
    if (std::isfinite(params.coarseMinElevationRad) && std::isfinite(pitchRad)) {
        // Rows below the lowest elevation a sign can have are left out: the input ends at the first multiple of
        // 32 network rows at or below the cut (same scale and origin as the full letterbox, so the rows kept
        // are exactly the ones the full pass would see).
        const double cutRow = unrolledRowAtElevation(unrolling.unrolledIntrinsics(), params.coarseMinElevationRad, pitchRad);
        const double cutNetworkRow = offY + (cutRow + 0.5) * h / double(unrolledSize.height);
        if (cutNetworkRow <= offY) return {};  // the whole frame is below the cut (camera looking down)
        inH = std::clamp(static_cast<int>(std::ceil(cutNetworkRow / 32.0)) * 32, 32, inH);
    }
    // Exact map network -> unrolled: the letterboxed content's scale is (cols / w, rows / h) unrolled px per
    // network px, its first pixel edge at network (offX - 0.5, offY - 0.5).
    const double sx = double(unrolledSize.width) / w, sy = double(unrolledSize.height) / h;
    const cv::Point2d originEdge(-0.5 - offX * sx, -0.5 - offY * sy);
    const cv::Mat input = sampleUnrolled(raw, unrolling, originEdge, sx, sy, cv::Size(inW, inH));
    return blobs(probabilities(input), originEdge, sx, sy, params);
}

std::vector<UnetCandidate> UnetDetector::farBandCandidates(RawPyramid& raw, const Unrolling& unrolling,
                                                           const UnetParams& params, double pitchRad) {
    if (!params.farBand || !std::isfinite(pitchRad) || !(params.farBandScale > 0) ||
        !(params.farBandMaxElevationRad > params.farBandMinElevationRad)) {
        return {};
    }
    const cv::Size unrolledSize = unrolling.unrolledSize();
    const Intrinsics& k = unrolling.unrolledIntrinsics();
    // Unrolled row of the ray at elevation e: v = cy' - fy' tan(e - pitch) (rows grow downwards).
    auto rowAt = [&](double elevation) { return unrolledRowAtElevation(k, elevation, pitchRad); };
    const double top = std::max(-0.5, rowAt(params.farBandMaxElevationRad));
    const double bottom = std::min(unrolledSize.height - 0.5, rowAt(params.farBandMinElevationRad));
    if (!(bottom - top >= 1.0)) return {};
    // Network px per unrolled px; sides rounded up to multiples of 32 (the U-Net's down-sampling), the
    // band centred vertically in its input, the full width starting at the left edge.
    const double scale = params.farBandScale * double(inputSize_) / std::max(unrolledSize.width, unrolledSize.height);
    auto roundUp32 = [](double v) { return std::max(32, static_cast<int>(std::ceil(v / 32.0)) * 32); };
    const int w = roundUp32(unrolledSize.width * scale);
    const int h = roundUp32((bottom - top) * scale);
    const double step = 1.0 / scale;  // unrolled px per network px
    const double centreRow = 0.5 * (top + bottom);
    const cv::Point2d originEdge(-0.5, centreRow - 0.5 * h * step);
    const cv::Mat band = sampleUnrolled(raw, unrolling, originEdge, step, step, cv::Size(w, h));
    std::vector<UnetCandidate> found = blobs(probabilities(band), originEdge, step, step, params);
    for (auto& c : found) c.minCropPx = std::max(params.minCropPx, params.farBandMinCropPx);
    return found;
}

cv::Mat signProbability(const std::vector<cv::Mat>& prob) {
    CV_Assert(prob.size() >= 2);
    if (prob.size() == 2) return prob[1];
    cv::Mat fg;
    cv::subtract(1.0, prob[0], fg);
    return fg;
}

int dominantClass(const std::vector<cv::Mat>& prob, const cv::Mat& mask) {
    if (prob.size() <= 2) return 1;  // the one sign class
    int best = 1;
    double bestSum = -1;
    for (size_t c = 1; c < prob.size(); ++c) {
        const double sum = cv::mean(prob[c], mask)[0];  // the same pixels for every class: mean orders as sum
        if (sum > bestSum) {
            bestSum = sum;
            best = static_cast<int>(c);
        }
    }
    return best;
}

std::vector<UnetCandidate> UnetDetector::blobs(const std::vector<cv::Mat>& prob, cv::Point2d originEdge, double sx,
                                               double sy, const UnetParams& params) const {
    std::vector<UnetCandidate> candidates;
    // One map of "any sign" (signProbability): with more than two classes a small plate's pixels can be shared among
    // look-alike classes at coarse scale (a far elevator plate read partly restroom, partly stairs) and no class
    // alone passes the threshold; the zoomed pass decides the class (refine).
    const cv::Mat sign = signProbability(prob);
    cv::Mat mask = sign > params.maskThreshold;
    // Closing bridges the gaps that letters cut into a plate at coarse scale (one blob per sign).
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
    for (int i = 1; i < n; ++i) {
        const int area = stats.at<int>(i, cv::CC_STAT_AREA);
        if (area < std::max(1, params.minBlobAreaPx)) continue;
        const int bx = stats.at<int>(i, cv::CC_STAT_LEFT), by = stats.at<int>(i, cv::CC_STAT_TOP);
        const int bw = stats.at<int>(i, cv::CC_STAT_WIDTH), bh = stats.at<int>(i, cv::CC_STAT_HEIGHT);
        UnetCandidate cand;
        const cv::Mat member = labels == i;
        cand.classIndex = dominantClass(prob, member);
        cand.areaPx = area * sx * sy;
        cand.meanProbability = cv::mean(sign, member)[0];
        // Edges of the blob in network pixels -> unrolled edge coordinates.
        cand.boxInUnrolled = cv::Rect2d(originEdge.x + bx * sx, originEdge.y + by * sy, bw * sx, bh * sy);
        candidates.push_back(cand);
    }
    std::sort(candidates.begin(), candidates.end(), [](const UnetCandidate& a, const UnetCandidate& b) {
        if (a.areaPx != b.areaPx) return a.areaPx > b.areaPx;
        return a.boxInUnrolled.x < b.boxInUnrolled.x;
    });
    if (params.maxCandidates > 0 && static_cast<int>(candidates.size()) > params.maxCandidates) {
        candidates.resize(params.maxCandidates);
    }
    return candidates;
}

double colourfulFraction(const cv::Mat& rgb, const cv::Mat& mask, int minChroma) {
    CV_Assert(rgb.type() == CV_8UC3 && mask.type() == CV_8UC1 && rgb.size() == mask.size());
    int total = 0, colourful = 0;
    for (int y = 0; y < rgb.rows; ++y) {
        const cv::Vec3b* px = rgb.ptr<cv::Vec3b>(y);
        const uchar* m = mask.ptr<uchar>(y);
        for (int x = 0; x < rgb.cols; ++x) {
            if (!m[x]) continue;
            ++total;
            const int hi = std::max({px[x][0], px[x][1], px[x][2]}), lo = std::min({px[x][0], px[x][1], px[x][2]});
            colourful += hi - lo >= minChroma;
        }
    }
    return total > 0 ? double(colourful) / total : 0.0;
}

UnetParams UnetParams::forClass(int classIndex) const {
    UnetParams p = *this;
    if (classIndex >= 0 && classIndex < static_cast<int>(classLimits.size()) && classLimits[classIndex]) {
        p.limits = *classLimits[classIndex];
    }
    return p;
}

UnetVerdict verifyZoomedSign(const SliceMeasurement& inUnrolled, double meanProbability, double unrolledFyPx,
                             const UnetParams& params, double colourFraction) {
    if (!(meanProbability >= params.minMeanProbability)) return UnetVerdict::kLowProbability;
    const UnetSignLimits& limits = params.limits;
    if (!(colourFraction >= limits.minColourFraction)) return UnetVerdict::kColourless;
    const double height = inUnrolled.medianHeightPx;
    if (!inUnrolled.valid || !(height > 0)) return UnetVerdict::kImplausibleHeight;
    const double aspect = inUnrolled.extentWidthPx / height;
    if (!(aspect >= limits.minAspect && aspect <= limits.maxAspect)) return UnetVerdict::kImplausibleAspect;
    const double minHeight = params.maxRangeM > 0 ? unrolledFyPx * limits.minSignHeightM / params.maxRangeM : 0.0;
    const double maxHeight =
        params.minRangeM > 0 ? unrolledFyPx * limits.maxSignHeightM / params.minRangeM : std::numeric_limits<double>::infinity();
    if (!(height >= minHeight && height <= maxHeight)) return UnetVerdict::kImplausibleHeight;
    return UnetVerdict::kAccepted;
}

bool UnetDetector::refine(RawPyramid& raw, const Unrolling& unrolling, const UnetCandidate& candidate,
                          const UnetParams& params, Detection* out, UnetVerdict* verdict) {
    const int s = inputSize_;
    // Zoom window side in network pixels: a multiple of 32 in [32, S].
    const int win = params.zoomWindowPx > 0 ? std::clamp(params.zoomWindowPx / 32 * 32, 32, s) : s;
    // Window height: signs are wider than tall, so less context above and below costs nothing (same scale).
    const int winH = params.zoomWindowHeightPx > 0 ? std::clamp(params.zoomWindowHeightPx / 32 * 32, 32, win) : win;
    cv::Rect2d target = candidate.boxInUnrolled;
    // When the mask reaches the crop border the sign is larger than the coarse blob suggested (e.g. the
    // blob was part of the plate): re-centre on the mask and zoom out, at most twice.
    for (int attempt = 0; attempt < 3; ++attempt) {
        const double side = std::max(params.zoomFactor * std::max(target.width, target.height),
                                     double(std::max(1, candidate.minCropPx > 0 ? candidate.minCropPx : params.minCropPx)));
        const int sideI = std::max(1, static_cast<int>(std::lround(side)));
        const double scale = double(sideI) / s;  // unrolled px per network px: the crop of `side` fills S
        // Only the central win x win network pixels of that crop are run (same scale, less context).
        const double windowSide = win * scale;  // unrolled px
        const double windowHeight = winH * scale;
        const double centreX = target.x + 0.5 * target.width, centreY = target.y + 0.5 * target.height;
        // Top-left pixel edge of the window, on the unrolled pixel grid's edges.
        const double c0 = std::round(centreX - 0.5 * windowSide), r0 = std::round(centreY - 0.5 * windowHeight);
        const cv::Rect2d cropRect(c0, r0, windowSide, windowHeight);
        if ((cropRect & cv::Rect2d(-0.5, -0.5, unrolling.unrolledSize().width, unrolling.unrolledSize().height)).area() <= 0) {
            return false;
        }
        const cv::Mat square = sampleUnrolled(raw, unrolling, cv::Point2d(c0, r0), scale, scale, cv::Size(win, winH));
        const std::vector<cv::Mat> prob = probabilities(square);
        // The sign's pixels: of any sign class (the class is the one holding most of the component's probability,
        // below).
        const cv::Mat p = signProbability(prob);
        const cv::Mat mask = p > params.maskThreshold;
        // Components of the closed mask group the pieces of one plate; slices use the raw mask inside it.
        cv::Mat closed;
        cv::morphologyEx(mask, closed, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
        cv::Mat labels, stats, centroids;
        const int n = cv::connectedComponentsWithStats(closed, labels, stats, centroids, 8, CV_32S);
        // The component nearest the crop centre (containing it, if any).
        int best = -1;
        double bestDistance = 1e300;
        const double midX = 0.5 * (win - 1), midY = 0.5 * (winH - 1);
        for (int i = 1; i < n; ++i) {
            if (stats.at<int>(i, cv::CC_STAT_AREA) < std::max(1, params.minBlobAreaPx)) continue;
            const int bx = stats.at<int>(i, cv::CC_STAT_LEFT), by = stats.at<int>(i, cv::CC_STAT_TOP);
            const int bw = stats.at<int>(i, cv::CC_STAT_WIDTH), bh = stats.at<int>(i, cv::CC_STAT_HEIGHT);
            const double dx = std::max({0.0, bx - midX, midX - (bx + bw - 1)});
            const double dy = std::max({0.0, by - midY, midY - (by + bh - 1)});
            const double d = std::hypot(dx, dy);
            if (d < bestDistance) {
                bestDistance = d;
                best = i;
            }
        }
        if (best < 0) return false;
        // The sign's pixels: the component, grown by one network pixel where the probability exceeds the
        // (lower) edge threshold: the network's 0.5 contour lies inside the face (heights ~3 % short).
        const cv::Mat core = (labels == best) & mask;
        cv::Mat component;  // a fresh Mat: assigning a MatExpr to one sharing core's data would overwrite core
        if (params.edgeThreshold > 0 && params.edgeThreshold < params.maskThreshold) {
            cv::Mat grown;
            cv::dilate(core, grown, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
            component = grown & (p > params.edgeThreshold);
        } else {
            component = core;
        }
        SliceMeasurement m = measureMask(component, params.slices);
        if (!m.valid) return false;
        const SliceMeasurement inUnrolled = m.mapped(scale, cv::Point2d(c0, r0));
        const int bx = stats.at<int>(best, cv::CC_STAT_LEFT), by = stats.at<int>(best, cv::CC_STAT_TOP);
        const int bw = stats.at<int>(best, cv::CC_STAT_WIDTH), bh = stats.at<int>(best, cv::CC_STAT_HEIGHT);
        const bool touchesBorder = bx == 0 || by == 0 || bx + bw == win || by + bh == winH;
        if (touchesBorder && attempt < 2) {
            const cv::Rect2d grown = inUnrolled.box;
            // Only retry if the crop did not already cover the whole frame around the sign.
            if (grown.width * params.zoomFactor > side * 1.01 || grown.height * params.zoomFactor > side * 1.01 ||
                std::abs(grown.x + 0.5 * grown.width - centreX) > 0.1 * side ||
                std::abs(grown.y + 0.5 * grown.height - centreY) > 0.1 * side) {
                target = grown;
                continue;
            }
        }
        const int classIndex = dominantClass(prob, core);
        // Score: the mean probability of a sign over the core (not the grown edge); with more than two classes, of
        // any sign (1 - background): which sign is the class decision above, and a face's pixels that lend a
        // little of their probability to look-alike classes are no less a sign.
        const double meanProbability = cv::mean(p, core)[0];
        const UnetParams checks = params.forClass(classIndex);
        const double colour =
            checks.limits.minColourFraction > 0 ? colourfulFraction(square, component, checks.colourChromaLevels) : 1.0;
        const UnetVerdict v =
            verifyZoomedSign(inUnrolled, meanProbability, unrolling.unrolledIntrinsics().fy, checks, colour);
        if (verdict) *verdict = v;
        if (v != UnetVerdict::kAccepted) return false;
        out->kind = classNames_[classIndex];
        out->kindIndex = classIndex;
        out->score = meanProbability;
        out->measurement = inUnrolled;
        // The mask's edges are learned from renders; the face's edges in the zoomed input are measured.
        const FaceEdgeResult edges = refineFaceEdges(square, m, params.slices, params.faceEdges);
        if (edges.refined) out->measurement = edges.measurement.mapped(scale, cv::Point2d(c0, r0));
        return true;
    }
    return false;
}

std::vector<Detection> UnetDetector::detect(const cv::Mat& rgbRaw, const Unrolling& unrolling, const UnetParams& params,
                                            double pitchRad) {
    RawPyramid raw(rgbRaw);
    return detect(raw, unrolling, params, pitchRad);
}

std::vector<Detection> UnetDetector::detect(RawPyramid& raw, const Unrolling& unrolling, const UnetParams& params,
                                            double pitchRad) {
    cv::Point2d scale;
    const cv::Mat& rgbRaw = raw.level(0, &scale);
    CV_Assert((rgbRaw.type() == CV_8UC3 || rgbRaw.type() == CV_8UC4) && rgbRaw.size() == unrolling.rawSize());
    const std::vector<UnetCandidate> coarse = coarseCandidates(raw, unrolling, params, pitchRad);
    std::vector<Detection> detections;
    std::vector<char> found(coarse.size(), 0);
    for (size_t i = 0; i < coarse.size(); ++i) {
        Detection d;
        if (refine(raw, unrolling, coarse[i], params, &d)) {
            detections.push_back(std::move(d));
            found[i] = 1;
        }
    }
    // A far-band blob that overlaps a coarse blob is the same sign: zoomed again only when the coarse blob's
    // zoom found nothing (its finer box gives a better-centred, better-sized crop), or overlaps a detection.
    for (const auto& b : farBandCandidates(raw, unrolling, params, pitchRad)) {
        bool seen = false;
        for (size_t i = 0; i < coarse.size() && !seen; ++i) {
            seen = found[i] && (coarse[i].boxInUnrolled & b.boxInUnrolled).area() > 0;
        }
        for (size_t i = 0; i < detections.size() && !seen; ++i) {
            seen = (detections[i].measurement.box & b.boxInUnrolled).area() > 0;
        }
        if (seen) continue;
        Detection d;
        if (refine(raw, unrolling, b, params, &d)) detections.push_back(std::move(d));
    }
    return suppressOverlaps(std::move(detections), 0.3);
}

}  // namespace wf::sign
