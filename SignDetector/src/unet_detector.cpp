#include "unet_detector.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

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
                        std::string* error) {
    if (!std::ifstream(path).good()) {
        *error = "U-Net model not found or unreadable: " + path;
        return false;
    }
    try {
        net_ = cv::dnn::readNetFromONNX(path);
    } catch (const cv::Exception& e) {
        *error = "U-Net model " + path + " could not be read by cv::dnn: " + e.what();
        return false;
    }
    if (net_.empty()) {
        *error = "U-Net model " + path + " is empty";
        return false;
    }
    net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
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

cv::Mat UnetDetector::forwardBlob(const cv::Mat& blob) {
    net_.setInput(blob, "image");
    return net_.forward().clone();
}

std::vector<cv::Mat> UnetDetector::probabilities(const cv::Mat& rgbSquare) {
    CV_Assert(rgbSquare.type() == CV_8UC3 && rgbSquare.rows == inputSize_ && rgbSquare.cols == inputSize_);
    const cv::Mat logits = forwardBlob(cv::dnn::blobFromImage(rgbSquare, 1.0 / 255.0, cv::Size(), cv::Scalar(),
                                                              /*swapRB=*/false, /*crop=*/false, CV_32F));
    const int k = logits.size[1];
    const int s = inputSize_;
    std::vector<cv::Mat> channels(k);
    for (int c = 0; c < k; ++c) {
        channels[c] = cv::Mat(s, s, CV_32F, const_cast<float*>(logits.ptr<float>(0, c))).clone();
    }
    // Numerically stable softmax over classes.
    cv::Mat maxLogit = channels[0].clone();
    for (int c = 1; c < k; ++c) cv::max(maxLogit, channels[c], maxLogit);
    cv::Mat sum = cv::Mat::zeros(s, s, CV_32F);
    for (int c = 0; c < k; ++c) {
        cv::exp(channels[c] - maxLogit, channels[c]);
        sum += channels[c];
    }
    for (int c = 0; c < k; ++c) cv::divide(channels[c], sum, channels[c]);
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
    cv::warpAffine(src, out, m23, cv::Size(size, size), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT,
                   cv::Scalar::all(0));
    return out;
}

std::vector<UnetCandidate> UnetDetector::coarseCandidates(RawPyramid& raw, const Unrolling& unrolling,
                                                          const UnetParams& params) {
    const int s = inputSize_;
    const cv::Size unrolledSize = unrolling.unrolledSize();
    const double scale = double(s) / std::max(unrolledSize.width, unrolledSize.height);  // network px per unrolled px
    const int w = std::max(1, static_cast<int>(std::lround(unrolledSize.width * scale)));
    const int h = std::max(1, static_cast<int>(std::lround(unrolledSize.height * scale)));
    const int offX = (s - w) / 2, offY = (s - h) / 2;
    // Exact map network -> unrolled: the letterboxed content's scale is (cols / w, rows / h) unrolled px per
    // network px, its first pixel edge at network (offX - 0.5, offY - 0.5).
    const double sx = double(unrolledSize.width) / w, sy = double(unrolledSize.height) / h;
    const cv::Mat square = sampleUnrolled(raw, unrolling, cv::Point2d(-0.5 - offX * sx, -0.5 - offY * sy), sx, sy, s);
    const std::vector<cv::Mat> prob = probabilities(square);
    std::vector<UnetCandidate> candidates;
    for (size_t c = 1; c < prob.size(); ++c) {
        cv::Mat mask = prob[c] > params.maskThreshold;
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
            cand.classIndex = static_cast<int>(c);
            cand.areaPx = area * sx * sy;
            cand.meanProbability = cv::mean(prob[c], labels == i)[0];
            // Edges of the blob in network pixels -> unrolled edge coordinates.
            cand.boxInUnrolled = cv::Rect2d((bx - offX) * sx - 0.5, (by - offY) * sy - 0.5, bw * sx, bh * sy);
            candidates.push_back(cand);
        }
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

bool UnetDetector::refine(RawPyramid& raw, const Unrolling& unrolling, const UnetCandidate& candidate,
                          const UnetParams& params, Detection* out) {
    const int s = inputSize_;
    cv::Rect2d target = candidate.boxInUnrolled;
    // When the mask reaches the crop border the sign is larger than the coarse blob suggested (e.g. the
    // blob was part of the plate): re-centre on the mask and zoom out, at most twice.
    for (int attempt = 0; attempt < 3; ++attempt) {
        const double side = std::max(params.zoomFactor * std::max(target.width, target.height),
                                     double(std::max(1, params.minCropPx)));
        const int sideI = std::max(1, static_cast<int>(std::lround(side)));
        // Crop columns c0 .. c0+side-1 centred on the target centre (pixel-centre coordinates).
        const double centreX = target.x + 0.5 * target.width, centreY = target.y + 0.5 * target.height;
        const int c0 = static_cast<int>(std::lround(centreX - 0.5 * (sideI - 1)));
        const int r0 = static_cast<int>(std::lround(centreY - 0.5 * (sideI - 1)));
        const cv::Rect cropRect(c0, r0, sideI, sideI);
        const cv::Rect inside = cropRect & cv::Rect(cv::Point(0, 0), unrolling.unrolledSize());
        if (inside.area() == 0) return false;
        // Crop pixels c0 .. c0+side-1: top-left edge (c0 - 0.5, r0 - 0.5), side/S unrolled px per network px.
        const cv::Mat square = sampleUnrolled(raw, unrolling, cv::Point2d(c0 - 0.5, r0 - 0.5), double(sideI) / s,
                                              double(sideI) / s, s);
        const std::vector<cv::Mat> prob = probabilities(square);
        const cv::Mat& p = prob[candidate.classIndex];
        const cv::Mat mask = p > params.maskThreshold;
        // Components of the closed mask group the pieces of one plate; slices use the raw mask inside it.
        cv::Mat closed;
        cv::morphologyEx(mask, closed, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
        cv::Mat labels, stats, centroids;
        const int n = cv::connectedComponentsWithStats(closed, labels, stats, centroids, 8, CV_32S);
        // The component nearest the crop centre (containing it, if any).
        int best = -1;
        double bestDistance = 1e300;
        const double mid = 0.5 * (s - 1);
        for (int i = 1; i < n; ++i) {
            if (stats.at<int>(i, cv::CC_STAT_AREA) < std::max(1, params.minBlobAreaPx)) continue;
            const int bx = stats.at<int>(i, cv::CC_STAT_LEFT), by = stats.at<int>(i, cv::CC_STAT_TOP);
            const int bw = stats.at<int>(i, cv::CC_STAT_WIDTH), bh = stats.at<int>(i, cv::CC_STAT_HEIGHT);
            const double dx = std::max({0.0, bx - mid, mid - (bx + bw - 1)});
            const double dy = std::max({0.0, by - mid, mid - (by + bh - 1)});
            const double d = std::hypot(dx, dy);
            if (d < bestDistance) {
                bestDistance = d;
                best = i;
            }
        }
        if (best < 0) return false;
        const cv::Mat component = (labels == best) & mask;
        SliceMeasurement m = measureMask(component, params.slices);
        if (!m.valid) return false;
        const double scale = double(sideI) / s;  // unrolled px per network px
        const SliceMeasurement inUnrolled = m.mapped(scale, cv::Point2d(c0 - 0.5, r0 - 0.5));
        const int bx = stats.at<int>(best, cv::CC_STAT_LEFT), by = stats.at<int>(best, cv::CC_STAT_TOP);
        const int bw = stats.at<int>(best, cv::CC_STAT_WIDTH), bh = stats.at<int>(best, cv::CC_STAT_HEIGHT);
        const bool touchesBorder = bx == 0 || by == 0 || bx + bw == s || by + bh == s;
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
        out->kind = classNames_[candidate.classIndex];
        out->kindIndex = candidate.classIndex;
        out->score = cv::mean(p, component)[0];
        out->measurement = inUnrolled;
        return true;
    }
    return false;
}

std::vector<Detection> UnetDetector::detect(const cv::Mat& rgbRaw, const Unrolling& unrolling, const UnetParams& params) {
    CV_Assert(rgbRaw.type() == CV_8UC3 && rgbRaw.size() == unrolling.rawSize());
    RawPyramid raw(rgbRaw);
    std::vector<Detection> detections;
    for (const auto& candidate : coarseCandidates(raw, unrolling, params)) {
        Detection d;
        if (refine(raw, unrolling, candidate, params, &d)) detections.push_back(std::move(d));
    }
    return suppressOverlaps(std::move(detections), 0.3);
}

}  // namespace wf::sign
