// Detector B: U-Net segmentation (Ronneberger et al. 2015; MobileNetV2 encoder as in Fusco et al. 2020,
// section 3) run with cv::dnn on an ONNX model, in the paper's multi-scale procedure: a coarse pass over
// the whole unrolled frame letterboxed to the network size finds candidate blobs; each is re-segmented
// from a zoomed crop centred on it, and measured by vertical slices.
#pragma once

#include "detection.hpp"
#include "unroll.hpp"

#include <opencv2/dnn.hpp>

#include <string>
#include <vector>

namespace wf::sign {

/// Multi-scale parameters.
struct UnetParams {
    /// Probability above which a pixel belongs to a class.
    double maskThreshold = 0.5;
    /// Crop side = zoomFactor x the coarse blob's larger side (unrolled pixels) ...
    double zoomFactor = 3.5;
    /// ... but at least this many unrolled (original-resolution) pixels.
    int minCropPx = 64;
    /// Coarse blobs smaller than this many network pixels are ignored.
    int minBlobAreaPx = 3;
    /// At most this many coarse candidates (largest first) are zoomed.
    int maxCandidates = 8;
    /// Slicing of the fine mask.
    SliceParams slices;
};

/// A coarse-pass candidate, in unrolled pixels.
struct UnetCandidate {
    int classIndex = 0;
    cv::Rect2d boxInUnrolled;
    double areaPx = 0;
    double meanProbability = 0;
};

/// The raw RGB frame and its halvings (INTER_AREA), built on demand, so that network inputs can be sampled
/// straight from raw pixels through the unrolling map without materialising the full-resolution unrolled
/// image (a 1920 x 1440 RGB warp costs more than the network's coarse pass).
class RawPyramid {
public:
    explicit RawPyramid(cv::Mat rgbRaw) { levels_.push_back(std::move(rgbRaw)); }
    /// Level k: the raw image downscaled about 2^k times; `scale` receives its exact (x, y) scale to raw.
    const cv::Mat& level(int k, cv::Point2d* scale);

private:
    std::vector<cv::Mat> levels_;
};

/// Samples an SxS network input whose pixel (i, j) (pixel centre) shows the unrolled point
/// (originEdge.x + (i + 0.5) * scaleX, originEdge.y + (j + 0.5) * scaleY), i.e. an unrolled region whose
/// top-left pixel edge is `originEdge`, `scaleX` unrolled pixels per network pixel. One cv::warpAffine from
/// the pyramid level that leaves at most a 2x downscale; outside the frame is black.
cv::Mat sampleUnrolled(RawPyramid& raw, const Unrolling& unrolling, cv::Point2d originEdge, double scaleX, double scaleY,
                       int size);

/// Runs an ONNX U-Net: input "image" 1x3xSxS float32 RGB in [0, 1]; output 1xKxSxS logits, class 0 =
/// background. Not thread-safe (cv::dnn::Net keeps state).
class UnetDetector {
public:
    /// Loads the model and its class names (index 0 = background). Returns false and sets `error`
    /// (naming the file) on failure. `inputSize` is the network side S (224).
    bool load(const std::string& path, const std::vector<std::string>& classNames, int inputSize, std::string* error);

    /// Per-class probabilities (softmax over the K logits) of an SxS RGB CV_8UC3 image: K CV_32FC1 maps.
    std::vector<cv::Mat> probabilities(const cv::Mat& rgbSquare);

    /// Raw logits of a 1x3xSxS float blob (for parity checks): a 1xKxSxS CV_32F blob.
    cv::Mat forwardBlob(const cv::Mat& blob);

    /// Coarse pass: the whole unrolled frame letterboxed to SxS (sampled from the raw pyramid); returns the
    /// candidate blobs in unrolled pixels.
    std::vector<UnetCandidate> coarseCandidates(RawPyramid& raw, const Unrolling& unrolling, const UnetParams& params);

    /// Zoomed pass on one candidate: a square crop (zoomFactor x blob, >= minCropPx; out-of-frame parts
    /// black) resized to SxS; the mask component of the candidate's class nearest the crop centre is
    /// sliced and mapped back to unrolled pixels. Returns false when the zoomed pass finds nothing.
    bool refine(RawPyramid& raw, const Unrolling& unrolling, const UnetCandidate& candidate, const UnetParams& params,
                Detection* out);

    /// Full multi-scale detection on a raw RGB frame (CV_8UC3) seen through `unrolling`; detections are in
    /// unrolled pixels, overlaps suppressed.
    std::vector<Detection> detect(const cv::Mat& rgbRaw, const Unrolling& unrolling, const UnetParams& params);

    /// Class names, index 0 = background.
    const std::vector<std::string>& classNames() const { return classNames_; }
    int inputSize() const { return inputSize_; }

private:
    cv::dnn::Net net_;
    std::vector<std::string> classNames_;
    int inputSize_ = 224;
};

/// Reads {"classes": ["background", "exit", ...]} (classes.json). Returns false and sets `error` on failure.
bool readClassList(const std::string& path, std::vector<std::string>* classes, std::string* error);

}  // namespace wf::sign
