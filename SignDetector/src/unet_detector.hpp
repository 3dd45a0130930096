// Detector B: U-Net segmentation (Ronneberger et al. 2015; MobileNetV2 encoder as in Fusco et al. 2020,
// section 3) run with cv::dnn on an ONNX model, in the paper's multi-scale procedure: a coarse pass over
// the whole unrolled frame letterboxed to the network size finds candidate blobs; each is re-segmented
// from a zoomed crop centred on it, and measured by vertical slices.
#pragma once

#include "detection.hpp"
#include "face_edge_refiner.hpp"
#include "unroll.hpp"

#include <opencv2/dnn.hpp>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace wf::sign {

/// Plausibility limits of a zoomed sign's mask, checked before it is reported (verifyZoomedSign). The defaults are
/// the Exit sign's; a class of a multi-class U-Net whose kind has another shape or colour (pictograms, placards)
/// gets its own (UnetParams::classLimits, filled by the detector from the sign-kind catalogue).
struct UnetSignLimits {
    /// Plausible extent width / median height. The Exit face is 0.33 x 0.21 m (1.57); turned +-55 degrees from
    /// facing the camera it is ~0.9; slices of a ragged mask can be a little short.
    double minAspect = 0.8;
    double maxAspect = 3.0;
    /// Plausible physical face height, meters: with UnetParams' minRangeM and maxRangeM, the median height in
    /// pixels must lie in [fy' minSignHeightM / maxRangeM, fy' maxSignHeightM / minRangeM] (fy' = unrolled focal
    /// length).
    double minSignHeightM = 0.12;
    double maxSignHeightM = 0.5;
    /// Minimum fraction of the sign's mask pixels (in the zoomed input) whose chroma max(R, G, B) -
    /// min(R, G, B) is >= UnetParams::colourChromaLevels (0-255): Exit signs have red or green letters or plates;
    /// a ceiling light (white, ~0) zoomed from a far-band blob otherwise passes as a 0.95 sign. On the rendered
    /// test set every true sign had >= 0.14 (motion-blurred and dim ones included). 0 = off (white-on-dark
    /// pictograms have no chroma).
    double minColourFraction = 0.05;
};

/// Multi-scale parameters.
struct UnetParams {
    /// Probability above which a pixel belongs to a class.
    double maskThreshold = 0.5;
    /// Zoomed pass: the sign's component (at maskThreshold) is grown by one network pixel into pixels above
    /// this probability before slicing (the 0.5 contour lies inside the face). >= maskThreshold or 0 = off.
    double edgeThreshold = 0.15;
    /// Crop side = zoomFactor x the coarse blob's larger side (unrolled pixels) ...
    double zoomFactor = 3.5;
    /// ... but at least this many unrolled (original-resolution) pixels.
    int minCropPx = 64;
    /// The zoomed pass runs only the central zoomWindowPx x zoomWindowPx network pixels of that S x S crop
    /// (same scale: the sign still spans ~S / zoomFactor = 64 network pixels, as in training; 2.5 x its
    /// width of context instead of 3.5 x, the low end of the training range): 0.73 x the cost of S = 224.
    /// Rounded down to a multiple of 32; 0 or >= S = the whole crop.
    int zoomWindowPx = 192;
    /// Height of that window, network pixels (rounded down to a multiple of 32; 0 or >= zoomWindowPx =
    /// square). Exit signs are wider than tall (a facing face spans ~64 x 41 network pixels), so 160 keeps
    /// ~3.9 x the sign's height of vertical context at 0.83 x the cost of 192 x 192; on the rendered test set
    /// recall and false positives were unchanged (128: one more 9 m sign missed).
    int zoomWindowHeightPx = 160;
    /// Coarse blobs smaller than this many network pixels are ignored.
    int minBlobAreaPx = 3;
    /// At most this many coarse candidates (largest first) are zoomed.
    int maxCandidates = 8;
    /// Slicing of the fine mask.
    SliceParams slices;
    /// Face-edge refinement of an accepted sign's slices in the zoomed input (face_edge_refiner.hpp): the mask
    /// gives the rough edges, the image the final ones (maskFaceEdgeParams). Verification uses the mask's measurement.
    FaceEdgeParams faceEdges = maskFaceEdgeParams();

    /// Coarse pass: the unrolled rows whose ray elevation, pitch + atan((cy' - v) / fy'), is below this are not
    /// run through the network (radians; needs the camera pitch, NaN = off, the whole frame). Exit signs hang
    /// above eye level (bottom edge >= ~2 m, camera at 1.2-1.6 m), so their faces are above the horizon; the
    /// 0.10 rad margin keeps a sign whose centre is 0.1 x its distance below the camera (a low sign, a pitch
    /// error of ~6 degrees). At a typical pitch of 0-20 degrees this skips a fifth to a half of the coarse
    /// input; the cut is rounded up to the U-Net's 32-pixel grid, and frames where it would save nothing run
    /// the full letterbox unchanged.
    double coarseMinElevationRad = -0.10;

    /// Far-sign band pass (needs the camera pitch). Signs beyond ~5 m are only a few network pixels in the
    /// whole-frame coarse pass (a 9 m Exit sign: ~4 x 7 of 224), and the network misses them. A second coarse
    /// pass samples only the band of unrolled rows whose ray elevation, pitch + atan((cy' - v) / fy'), lies
    /// in [farBandMinElevationRad, farBandMaxElevationRad] — where far signs mounted above eye level appear —
    /// over the full width, at farBandScale x the coarse pass's resolution (the network is fully
    /// convolutional: the input is a band, not a square). Its blobs join the coarse candidates; the zoomed
    /// pass verifies them. false = off.
    bool farBand = true;
    /// Lowest elevation of the band, radians (0 = the horizon).
    double farBandMinElevationRad = 0.0;
    /// Highest elevation of the band, radians. A sign centre 0.5-1.4 m above the camera at >= 7 m is below
    /// atan(1.4 / 7) = 0.197 rad; nearer signs (>= ~45 unrolled px tall) are large enough for the coarse pass.
    double farBandMaxElevationRad = 0.20;
    /// Network pixels per unrolled pixel in the band, as a multiple of the coarse pass's (2.25: a 9 m Exit
    /// sign is ~9 x 11 network pixels; at 2 x the network missed some motion-blurred ones).
    double farBandScale = 2.25;
    /// Zoom crop side for far-band candidates: at least this many unrolled pixels (instead of minCropPx).
    /// A band blob can be a fragment of the sign (e.g. 13 x 18 px of a 57 x 42 px sign); zooming it by
    /// zoomFactor over-magnified the sign (~3 x the training scale) and its mask scored below
    /// minMeanProbability. 144 = zoomFactor x a ~41 px wide sign (an Exit face at ~13 m).
    int farBandMinCropPx = 144;

    /// Verification of each zoomed candidate before it is reported (see verifyZoomedSign).
    /// Minimum mean class probability over the sign's mask component. Set for the committed model
    /// (2026-12-07, trained on classic and phone-style renders): on four held-out rendered sets (classic, two
    /// phone-style, the real photos' 360 x 640) its true signs' 5th percentile is 0.95-0.97 and its accepted
    /// false alarms (green or red word and arrow signs, a mirrored EXIT) score 0.925-0.97; 0.94 keeps them under
    /// 0.01 per frame (9-11 of 1,220 frames, 19 at 0.92) for about 10 of 793 signs (docs/benchmarks.md
    /// "Thirty-third stop").
    /// The model before it used 0.92 (its true signs >= 0.94, false alarms 0.5-0.9 on the classic set).
    double minMeanProbability = 0.94;
    /// The Exit sign's plausibility limits (aspect, face height, colour).
    UnetSignLimits limits;
    /// Plausible range, meters (with the limits' face heights).
    double minRangeM = 0.5;
    double maxRangeM = 20.0;
    /// Chroma a mask pixel needs to count as colourful (limits.minColourFraction), 0-255.
    int colourChromaLevels = 20;

    /// Per-class plausibility limits, indexed by class (missing or empty entries: `limits`, the Exit sign's).
    /// Filled by the detector from the sign-kind catalogue (Detector::configureUnetClasses).
    std::vector<std::optional<UnetSignLimits>> classLimits;

    /// These parameters with class `classIndex`'s verification limits in place of the Exit sign's.
    UnetParams forClass(int classIndex) const;
};

/// A coarse-pass candidate, in unrolled pixels.
struct UnetCandidate {
    int classIndex = 0;
    cv::Rect2d boxInUnrolled;
    double areaPx = 0;
    double meanProbability = 0;
    /// Minimum zoom crop side for this candidate, unrolled pixels (0 = UnetParams::minCropPx).
    int minCropPx = 0;
};

/// The raw colour frame and its halvings (INTER_AREA), built on demand, so that network inputs can be sampled
/// straight from raw pixels through the unrolling map without materialising the full-resolution unrolled
/// image (a 1920 x 1440 RGB warp costs more than the network's coarse pass). The frame is RGB (CV_8UC3) or, as
/// the phone sends it, BGRA (CV_8UC4): the halvings and warps work per channel, so sampling BGRA and swapping the
/// channels of the small result gives the same bytes as converting the whole frame to RGB first (1.9 ms per
/// 1920 x 1440 frame here, docs/sign-detection.md "Pixel formats").
class RawPyramid {
public:
    /// `raw`: CV_8UC3 (R, G, B) or CV_8UC4 (B, G, R, A); borrowed when it is a view of the caller's frame.
    explicit RawPyramid(cv::Mat raw) { levels_.push_back(std::move(raw)); }
    /// True when the levels hold B, G, R, A (sampled inputs are converted to RGB).
    bool bgra() const { return levels_.front().type() == CV_8UC4; }
    /// Level k: the raw image downscaled about 2^k times; `scale` receives its exact (x, y) scale to raw.
    const cv::Mat& level(int k, cv::Point2d* scale);

private:
    std::vector<cv::Mat> levels_;
};

/// Samples a network input of `size` (width, height) pixels whose pixel (i, j) (pixel centre) shows the
/// unrolled point (originEdge.x + (i + 0.5) * scaleX, originEdge.y + (j + 0.5) * scaleY); see the square
/// overload below.
cv::Mat sampleUnrolled(RawPyramid& raw, const Unrolling& unrolling, cv::Point2d originEdge, double scaleX, double scaleY,
                       cv::Size size);

/// Fraction of the pixels under `mask` (CV_8UC1, nonzero = in) of `rgb` (CV_8UC3) whose chroma
/// max(R, G, B) - min(R, G, B) is >= minChroma; 0 for an empty mask.
double colourfulFraction(const cv::Mat& rgb, const cv::Mat& mask, int minChroma);

/// Why a zoomed candidate was rejected (or kAccepted).
enum class UnetVerdict { kAccepted, kLowProbability, kImplausibleAspect, kImplausibleHeight, kColourless };

/// Verification rule of a zoomed candidate: `inUnrolled` is its slice measurement in unrolled pixels,
/// `meanProbability` the mean class probability over its mask component, `unrolledFyPx` the unrolled focal
/// length (pixels). Accepted when the mean probability, the aspect (extent width / median height) and the
/// median height (consistent with a face of [minSignHeightM, maxSignHeightM] at [minRangeM, maxRangeM])
/// are all plausible for a sign (UnetParams), and `colourFraction` (colourfulFraction of its mask at
/// colourChromaLevels; default 1 = not checked) is >= minColourFraction.
UnetVerdict verifyZoomedSign(const SliceMeasurement& inUnrolled, double meanProbability, double unrolledFyPx,
                             const UnetParams& params, double colourFraction = 1.0);

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
    /// (naming the file) on failure. `inputSize` is the network side S (224). `subPixelUpsampling`: the
    /// decoder's 2 x 2 stride-2 transposed convolutions run as a 1 x 1 convolution plus a depth-to-space copy
    /// (subpixel_transposed_conv.hpp; same logits within about 3e-6, 15-17 % less time per pass); false =
    /// OpenCV's own Deconvolution layer.
    bool load(const std::string& path, const std::vector<std::string>& classNames, int inputSize, std::string* error,
              bool subPixelUpsampling = true);

    /// Per-class probabilities (softmax over the K logits) of an RGB CV_8UC3 image: K CV_32FC1 maps of its
    /// size. The network is fully convolutional: any size whose sides are multiples of 32 works; the
    /// model was trained on SxS.
    std::vector<cv::Mat> probabilities(const cv::Mat& rgb);

    /// Raw logits of a 1x3xSxS float blob (for parity checks): a 1xKxSxS CV_32F blob.
    cv::Mat forwardBlob(const cv::Mat& blob);

    /// Coarse pass: the whole unrolled frame letterboxed to SxS (sampled from the raw pyramid); returns the
    /// candidate blobs in unrolled pixels.
    std::vector<UnetCandidate> coarseCandidates(RawPyramid& raw, const Unrolling& unrolling, const UnetParams& params,
                                                double pitchRad);

    /// Far-sign band pass (UnetParams::farBand): the unrolled rows whose elevation lies in the band, full
    /// width, at farBandScale x the coarse resolution; returns its blobs in unrolled pixels (empty when the
    /// band is off, the pitch is not finite or the band misses the frame).
    std::vector<UnetCandidate> farBandCandidates(RawPyramid& raw, const Unrolling& unrolling, const UnetParams& params,
                                                 double pitchRad);

    /// Zoomed pass on one candidate: a square crop (zoomFactor x blob, >= minCropPx; out-of-frame parts
    /// black) resized to SxS; the mask component of any sign class nearest the crop centre (reported as the class
    /// holding most of its probability) is sliced and mapped back to unrolled pixels. Returns false when the zoomed pass finds nothing or the
    /// result fails verifyZoomedSign (`verdict`, optional, says why).
    bool refine(RawPyramid& raw, const Unrolling& unrolling, const UnetCandidate& candidate, const UnetParams& params,
                Detection* out, UnetVerdict* verdict = nullptr);

    /// Full multi-scale detection on a raw RGB frame (CV_8UC3; or BGRA, CV_8UC4: RawPyramid) seen through `unrolling`, camera pitch
    /// `pitchRad` (radians, up positive; NaN = unknown: no far-band pass): coarse and far-band candidates,
    /// each zoomed and verified; detections are in unrolled pixels, overlaps suppressed. A far-band blob that
    /// overlaps a coarse blob is zoomed only when that coarse blob's zoom found no sign.
    std::vector<Detection> detect(const cv::Mat& rgbRaw, const Unrolling& unrolling, const UnetParams& params,
                                  double pitchRad = std::numeric_limits<double>::quiet_NaN());
    /// The same on the caller's pyramid of the frame (its level 0), whose levels it fills as it samples them: the
    /// caller may read them afterwards (the wall kinds' cascades search the half-size level).
    std::vector<Detection> detect(RawPyramid& raw, const Unrolling& unrolling, const UnetParams& params,
                                  double pitchRad = std::numeric_limits<double>::quiet_NaN());

    /// Class names, index 0 = background.
    const std::vector<std::string>& classNames() const { return classNames_; }
    int inputSize() const { return inputSize_; }

private:
    /// Blobs of per-class probability maps of a network input whose pixel (i, j) shows unrolled
    /// (originEdge.x + (i + 0.5) sx, originEdge.y + (j + 0.5) sy).
    std::vector<UnetCandidate> blobs(const std::vector<cv::Mat>& prob, cv::Point2d originEdge, double sx, double sy,
                                     const UnetParams& params) const;

    /// A fresh Net from modelBytes_ (OpenCV backend, CPU target; sub-pixel upsampling as loaded).
    cv::dnn::Net makeNet() const;
    /// The Net planned for a 1x3xrowsxcols input (one per input shape, see netFor in the .cpp).
    cv::dnn::Net& netFor(int rows, int cols);
    /// Logits of a blob: the net's own output buffer, valid until the next forward.
    cv::Mat forwardShared(const cv::Mat& blob);

    struct CachedNet {
        int rows = 0, cols = 0;
        unsigned long lastUse = 0;
        cv::dnn::Net net;
    };
    static constexpr int kMaxNets = 6;
    std::vector<char> modelBytes_;
    bool subPixelUpsampling_ = true;
    cv::dnn::Net net_;  // the net loaded by load(), until netFor adopts it
    std::vector<CachedNet> nets_;
    unsigned long useClock_ = 0;
    cv::Mat blob_;                 // network input buffer, reused
    std::vector<cv::Mat> planes_;  // byte planes of the input, reused
    std::vector<std::string> classNames_;
    int inputSize_ = 224;
};

/// Probability that a pixel shows a sign of any class, of per-class maps (index 0 = background): the sign class's
/// map itself with two classes, else 1 - background (a new map).
cv::Mat signProbability(const std::vector<cv::Mat>& prob);

/// The sign class (index >= 1) with the largest summed probability under `mask` (CV_8UC1, nonzero = in); 1 with
/// two classes.
int dominantClass(const std::vector<cv::Mat>& prob, const cv::Mat& mask);

/// Reads {"classes": ["background", "exit", ...]} (classes.json). Returns false and sets `error` on failure.
bool readClassList(const std::string& path, std::vector<std::string>* classes, std::string* error);

}  // namespace wf::sign
