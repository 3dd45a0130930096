// The whole per-frame pipeline behind wf_detector: validate -> unroll -> detect (cascade or U-Net) ->
// slice measurement -> observations.
#pragma once

#include "cascade_detector.hpp"
#include "face_edge_refiner.hpp"
#include "image_input.hpp"
#include "search_frame.hpp"
#include "sign_catalogue.hpp"
#include "text_reader.hpp"
#include "unet_detector.hpp"
#include "unroll.hpp"
#include "wf_sign_detector.h"

#include <optional>
#include <string>
#include <vector>

namespace wf::sign {

/// Options with defaults resolved (zero fields of wf_detector_options replaced by their defaults).
struct ResolvedOptions {
    wf_detector_kind kind = WF_DETECTOR_CASCADE;
    std::vector<std::string> cascadePaths, cascadeKinds;
    std::string unetPath;
    std::vector<std::string> classNames;
    int unetInputSize = 224;
    /// U-Net upsampling as a 1 x 1 convolution plus depth-to-space (UnetDetector::load): wf_detector_options.
    /// unet_transposed_convolution.
    bool unetSubPixelUpsampling = true;
    CascadeParams cascade;
    UnetParams unet;
    /// wf_detector_options.unet_coarse_min_elevation_rad was set (not 0): the coarse pass's elevation cut stays as
    /// given even when the U-Net has classes for kinds mounted at eye level (Detector::loadUnet).
    bool unetCoarseCutGiven = false;
    double minScore = 0;
    double rollSnapToleranceRad = 0;
    /// Face-edge refinement of every detection (both detectors; the U-Net's copy is unet.faceEdges).
    FaceEdgeParams faceEdges;
    /// Sign kinds and their face sizes (may be empty: then sense() fails).
    std::vector<SignKindSpec> catalogue;
    /// sense() reports no sighting for a face measured shorter than this, unrolled pixels: below it the range
    /// from apparent height is not worth having. Each face edge is located to about half a pixel, but a face of
    /// under about 9 px blends with what surrounds it (housing, bloom, a ceiling edge behind it) and its edges
    /// are found outside the face: on the end-to-end study's 640 x 480 frames, Exit signs 13-17 m away (7-8.6 px)
    /// were measured at about 12 px and read 9-10 m (-30 to -45 %), where the localizer's range model allows
    /// about 12 % + 0.1 m. Read against true range by measured height: at 10-12 px at least a tenth read 0.52-0.76
    /// of the truth, at 13 px the tenth percentile was 0.74, from 14 px none fell below 0.75 (docs/benchmarks.md,
    /// "Third stop"). 13 px: Exit signs out to 8.6 m on a VGA frame, 26 m on a 1920 x 1440 one.
    double minRangingHeightPx = 13;
    /// sense() reports no sighting for a face with a measured corner within this many raw pixels of the frame's
    /// edge (or outside it): the frame cuts the face, so its apparent height and centre are not the sign's. A
    /// sign 1.3 m away, cut by the top corner of a 640 x 480 frame, read 3.2 m on the end-to-end study and broke
    /// a correct lock (conv-4-00 at 27 s).
    double frameEdgeMarginPx = 2;
    /// Kinds searched without the colour gate (pictograms, placards: SignKindSpec::colourGated() false) are
    /// searched on the unrolled frame shrunk so that its long side is at most this, pixels: the VGA frames their
    /// cascades were trained and measured on (the phone sends the cascade VGA; a 1920 x 1440 U-Net frame is
    /// shrunk 3 x for them, 9 x fewer windows). Boxes are mapped back to the frame's own pixels.
    int plainKindSearchMaxLongSidePx = 640;
    /// The cascade detector searches the frame shrunk so that its long side is at most this, pixels (-1 = the
    /// frame's own size), and measures what it finds on the frame itself (search_frame.hpp): given a 1920 x 1440
    /// frame, the windows cost what VGA costs and the face edges are located at full resolution (the shrink
    /// itself costs 2-5 ms here, so the phone still hands the cascade VGA frames).
    /// wf_detector_options.cascade_search_max_long_side_px (0 = this default).
    int cascadeSearchMaxLongSidePx = 640;
    /// How many of those kinds a searched frame searches, in rotation (-1 = all of them):
    /// wf_detector_options.cascade_wall_kinds_per_frame.
    int wallKindsPerFrame = 2;
    /// Those kinds are searched on one frame in this many: wf_detector_options.cascade_wall_kind_frame_period.
    int wallKindFramePeriod = 2;
    /// Legends (kinds that read text) are read only off plates at least this tall, unrolled pixels: a 0.15 m placard's
    /// 25 mm characters are then 10 px, about the smallest tesseract reads (text_reader.hpp enlarges the crop, but
    /// cannot add detail; on the rendered VGA placards 7 of 72 were misread with confidence >= 75, all from plates
    /// of 30-67 px). 60 px: a placard within about 1.3 m on a VGA frame, 4 m on a 1920 x 1440 one.
    double minReadablePlateHeightPx = 60;
    /// At most this many legends are read per frame, best detection scores first (tesseract: about 10-30 ms each).
    int maxLegendReadsPerFrame = 3;

    /// Copies `opts` (borrowed strings are copied) and applies defaults. Returns WF_STATUS_OK or an error code with
    /// `error` set.
    static int fromOptions(const wf_detector_options& opts, ResolvedOptions* out, std::string* error);
};

/// Result of one frame.
struct FrameResult {
    /// WF_STATUS_OK, a warning or an error code.
    int status = WF_STATUS_OK;
    std::string message;
    /// Observations, best score first (empty unless status >= 0).
    std::vector<wf_detector_observation> observations;
};

/// Result of sense(): ranged sightings of one frame.
struct FrameSightings {
    /// WF_STATUS_OK, a warning or an error code.
    int status = WF_STATUS_OK;
    std::string message;
    /// Sightings, best score first (empty unless status >= 0).
    std::vector<wf_sign_sighting> sightings;
};

/// Loaded models plus options. Not thread-safe.
class Detector {
public:
    /// Loads the models named by `options`. Returns WF_STATUS_OK or WF_STATUS_MODEL_LOAD with `error` set.
    int load(const ResolvedOptions& options, std::string* error);

    /// Runs the pipeline on one frame. Never throws (OpenCV exceptions become WF_STATUS_INTERNAL).
    FrameResult detect(const wf_frame& frame);

    /// detect(), then range each observation with its kind's face height from the catalogue (see
    /// wf_detector_sense). Never throws.
    FrameSightings sense(const wf_frame& frame);

    /// Kind names the detector reports (cascade kinds, or U-Net classes without background, then the cascade
    /// kinds that run beside the U-Net).
    const std::vector<std::string>& kinds() const { return kinds_; }

    /// Whether the last detect() looked for kind `index` (of kinds()): false when the frame was rejected or the
    /// kind's turn in the wall-kind schedule (ResolvedOptions::wallKindsPerFrame, wallKindFramePeriod) had not
    /// come, and before any frame. The localizer must not take such a kind's absence as a miss.
    bool searchedLastFrame(size_t index) const { return index < lastSearched_.size() && lastSearched_[index] != 0; }

    /// The next detect() searches exactly these of the kinds searched in turn (the wall kinds: the cascades that are
    /// not colour-gated, beside a U-Net every cascade), whatever the schedule says; an empty list: none of them. Indices
    /// of kinds(). Consumed by the next detect() (also by a rejected frame); the schedule's rotation and frame count
    /// do not advance on such a frame. Returns false, with `error` set and nothing requested, when an index is out of
    /// range or names a kind searched on every frame (the U-Net's classes, colour-gated cascades) or is repeated.
    /// The caller's own schedule (the app's pipeline chooses the kinds the localizer expects in view).
    bool requestWallKinds(const std::vector<size_t>& kindIndices, std::string* error);

    /// Whether kind `index` (of kinds()) is one of the kinds searched in turn (a wall kind).
    bool isWallKind(size_t index) const;

    const ResolvedOptions& options() const { return options_; }

    /// True when a kind of the catalogue reads text and the text reader loaded.
    bool readsText() const { return textReader_.loaded(); }

    /// Why the text reader is not loaded although a kind reads text ("" otherwise).
    const std::string& textReaderProblem() const { return textReaderProblem_; }

private:
    /// Loads the U-Net of options_ and the cascades beside it. Returns WF_STATUS_OK or WF_STATUS_MODEL_LOAD.
    int loadUnet(std::string* error);

    /// The plain kinds beside the U-Net on `gray` (the raw frame, intrinsics `k`): on the whole unrolled frame when
    /// it fits plainKindSearchMaxLongSidePx, else on a canvas of that size (detectPlainKindsUnrolled; a frame over
    /// twice that size shrunk first with INTER_AREA); boxes mapped to `frameUnrolling`'s pixels, not yet refined.
    std::vector<Detection> detectPlainKindsShrunk(const cv::Mat& gray, const Intrinsics& k, double rollRad,
                                                  double pitchRad, const Unrolling& frameUnrolling);
    /// True when an unrolled image of `unrolledSize` is larger than the plain kinds' search size.
    bool overSearchSize(cv::Size unrolledSize) const;
    /// The plain kinds searched on the frame (`frameSize` pixels, intrinsics `k`, roll `rollRad`) unrolled into a
    /// canvas of the search size in one resampling of `sourceGray` (the frame in gray or a copy of it shrunk with its
    /// pixel edges aligned, at most about twice the search size: UnrolledSearchImage); boxes mapped to
    /// `frameUnrolling`'s pixels (mapToFrame), not yet refined.
    std::vector<Detection> detectPlainKindsUnrolled(const cv::Mat& sourceGray, cv::Size frameSize, const Intrinsics& k,
                                                    double rollRad, double pitchRad, const Unrolling& frameUnrolling);
    /// The plain kinds beside the U-Net, which has just read `pyramid` (level 0: the frame `frameImage`, intrinsics
    /// `k`): a colour frame over twice the search size is searched on its half-size level in gray; otherwise as
    /// detectPlainKindsShrunk on the frame in gray, which is left in `gray` (else empty).
    std::vector<Detection> detectPlainKindsBesideUnet(RawPyramid& pyramid, const wf_image& frameImage,
                                                      const Intrinsics& k, double rollRad, double pitchRad,
                                                      const Unrolling& frameUnrolling, cv::Mat* gray);
    /// Whether this frame searches the plain kinds (there are some, and it is this frame's turn: one frame in
    /// ResolvedOptions::wallKindFramePeriod); counts the frame.
    bool takeWallKindTurn();
    /// True when some detection's kind reads text (a legend to read).
    bool anyReadsText(const std::vector<Detection>& detections) const;

    /// Cascade kinds searched without the gate: on `grayUnrolled` (the whole unrolled frame) shrunk to at most
    /// plainKindSearchMaxLongSidePx, each with its placement band and smallest window; boxes in `grayUnrolled`'s
    /// pixels appended to `out`.
    /// The search parameters of plain (not colour-gated) kind `i` on an image of `geometry`: its placement band
    /// from the catalogue's face size and mounting height, its smallest window from its range limit.
    CascadeParams plainKindParams(size_t i, const FrameGeometry& geometry, double pitchRad) const;
    /// The plate gate's regions for `kinds` (cascade indices, parameters `kindParams`) on `image` (gray, unrolled):
    /// plate candidates kept where some kind's placement band allows one of their size (plate_gate.hpp); a full
    /// search when the gate is off or finds too much.
    GateDecision plateGate(const cv::Mat& image, const FrameGeometry& geometry, const std::vector<size_t>& kinds,
                           const std::vector<CascadeParams>& kindParams) const;
    void detectPlainKinds(const cv::Mat& grayUnrolled, const Unrolling& unrolling, double pitchRad,
                          std::vector<Detection>* out);

    /// `boxes` with overlaps of a kind suppressed (IoU > 0.5) and each box's slices measured from the face edges
    /// found in `image` around it (face-edge refinement, when on), searched with `edges` (options_.faceEdges when
    /// null; a mask's narrow search for boxes refined once already).
    std::vector<Detection> refinedBoxes(std::vector<Detection> boxes, const wf_image& image, const Unrolling& unrolling,
                                        const FaceEdgeParams* edges = nullptr) const;

    /// Reads the legend of every detection whose kind reads text, from `grayUnrolled` (the whole unrolled frame).
    void readLegends(const cv::Mat& grayUnrolled, std::vector<Detection>* detections);
    /// The U-Net's classes of kinds other than the Exit sign (the catalogue's kinds without the colour gate):
    /// their verification limits from their face size (UnetParams::classLimits) and, unless the caller set it,
    /// no coarse-pass elevation cut (they hang at eye level).
    void configureUnetClasses();

    ResolvedOptions options_;
    CascadeDetector cascade_;
    UnetDetector unet_;
    std::vector<std::string> kinds_;
    /// Catalogue entry of each cascade (nullptr = not in the catalogue: searched like an Exit sign).
    std::vector<const SignKindSpec*> cascadeSpecs_;
    /// Cascades searched through the colour gate (Exit-like kinds, the shared CascadeParams) and the others, on
    /// their own placement band and range limit (pictograms, placards).
    std::vector<size_t> gatedKinds_, plainKinds_;
    /// Next of plainKinds_ to search (rotation, ResolvedOptions::wallKindsPerFrame).
    size_t wallKindCursor_ = 0;
    /// Frames that could have searched those kinds so far (ResolvedOptions::wallKindFramePeriod).
    long long wallKindFrames_ = 0;
    /// The plain kinds (cascade indices) the caller asked the next frame to search (requestWallKinds); empty
    /// optional: the schedule decides.
    std::optional<std::vector<size_t>> requestedPlainKinds_;
    /// The plain kinds (cascade indices) this frame searches: the request, else `wallKindsPerFrame` of them in
    /// rotation (advancing the rotation), else all.
    std::vector<size_t> plainKindsThisFrame();
    /// Offset of the cascades' kinds in kinds(): the U-Net's classes without background come first.
    size_t cascadeKindOffset() const;
    /// Per kind of kinds_: 1 when the last frame looked for it (searchedLastFrame).
    std::vector<uint8_t> lastSearched_;
    /// Marks plain kind `i` (a cascade index) as not looked for on this frame.
    void markPlainKindUnsearched(size_t i);
    TextReader textReader_;
    std::string textReaderProblem_;
};

/// Packs a detection into the C observation struct with the unrolling's intrinsics and map.
wf_detector_observation makeObservation(const Detection& detection, const Unrolling& unrolling);

/// Ranges one observation (apparent height, ray-elevation model) with `kind`'s face height, for a camera of
/// pitch `pitchRad`. Returns false (no sighting) when the range estimator rejects the measurement.
bool sightingFromObservation(const wf_detector_observation& o, const SignKindSpec& kind, double pitchRad,
                             wf_sign_sighting* out);

/// True when one of the sighting's face corners (corners_raw_px) lies within `marginPx` of the edge of a
/// `widthPx` x `heightPx` raw frame, outside it, or is not finite: the frame cuts the face.
bool faceTouchesFrameEdge(const wf_sign_sighting& sighting, int widthPx, int heightPx, double marginPx);

}  // namespace wf::sign
