// Shared by the benchmark and the evaluation tool: the rendered test-set format (labels.jsonl, written by
// SignDetector/training/render_signs.py), frames at a chosen resolution, detector handles through the C ABI,
// and matching of detections to labelled signs.
#pragma once

#include "wf_sign_detector.h"

#include <opencv2/core.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace wf::sign::bench {

/// One labelled sign of a test frame.
struct LabelledSign {
    std::string kind;
    /// Corners in raw pixels of the labelled image: top-left, top-right, bottom-right, bottom-left.
    std::array<cv::Point2d, 4> cornersRaw;
    /// Truth: horizontal range (m), bearing (rad, positive left), face size (m).
    double rangeMeters = 0, bearingRad = 0, heightMeters = 0.21, widthMeters = 0.30;
    /// Legend text of a sign that has one (a room-number placard); "" otherwise.
    std::string text;
};

/// One line of labels.jsonl: {"image", "intrinsics": {fx, fy, cx, cy, width, height}, "pitchRad", "rollRad",
/// "signs": [{"kind", "cornersRaw", "rangeMeters", "bearingRad", "heightMeters", "widthMeters"}]}.
struct LabelledFrame {
    std::string imagePath;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    int width = 0, height = 0;
    double pitchRad = 0, rollRad = 0;
    std::vector<LabelledSign> signs;
};

/// Reads `<dir>/labels.jsonl`. Returns false with `error` naming the file and line on failure.
bool readLabels(const std::string& dir, std::vector<LabelledFrame>* frames, std::string* error);

/// A frame resized to a working resolution, with its intrinsics and labels scaled (pixel-centre
/// convention: u' = (u + 0.5) s - 0.5). Owns its pixels; `frame` points into `rgb`.
struct PreparedFrame {
    /// Pixels of frame.image: RGB8 as prepared, or after convertPixelFormat the first plane (GRAY8, BGRA8, NV12's
    /// Y plane).
    cv::Mat rgb;
    /// NV12 only: the interleaved CbCr plane (CV_8UC2, half size).
    cv::Mat chroma;
    wf_frame frame{};
    LabelledFrame labels;
};

/// Converts a prepared RGB8 frame in place to `format`, the way a phone delivers it: GRAY8 (luma only),
/// BGRA8 (kCVPixelFormatType_32BGRA), or NV12 (ARKit's capturedImage, kCVPixelFormatType_420YpCbCr8BiPlanarFullRange:
/// full-range BT.601 Y plane plus 2 x 2-averaged interleaved Cb, Cr). RGB8 leaves it as it is.
void convertPixelFormat(PreparedFrame* frame, wf_pixel_format format);

/// Resizes `bgr` (the labelled image) to `size` (INTER_AREA down, INTER_LINEAR up) and fills a wf_frame.
/// `shiftPx` > 0 then drops the first shiftPx columns and rows (intrinsics and labels follow): the same scene
/// with every search grid moved, to tell a search change's real effect from where its scan grid happens to fall.
std::unique_ptr<PreparedFrame> prepareFrame(const cv::Mat& bgr, const LabelledFrame& labels, cv::Size size,
                                            int shiftPx = 0);

/// Owning wrapper of a wf_detector handle.
struct DetectorHandle {
    wf_detector* handle = nullptr;
    std::string error;
    ~DetectorHandle() { wf_detector_free(handle); }
    explicit operator bool() const { return handle != nullptr; }
};

/// Cascade search settings to compare against the defaults (each is a set of named options).
enum class CascadeSearch {
    /// All defaults: 16-pixel gate margins, component-width windows in tiles, placement prior, crowded-frame gate.
    Defaults,
    /// The earlier gate regions: 24-pixel margins, every window size in a large component's tiles.
    WideGateRegions,
    /// ... and no placement prior, no crowded-frame gate (the earliest gated search).
    WideGateRegionsNoPrior,
};

/// Creates a cascade detector for one Exit cascade with the given smallest window and largest-window factor
/// (the reference app's exit_sign_config.yaml: 36 x 24, factor 5; 0 = unlimited).
/// `minElevationRad`: 0 = the detector's default (rows above -0.15 rad), NaN = the whole frame, else only rows at
/// least this elevation (radians).
/// `minWindowWidth/Height` 0 = the cascade's training window. `fullSearch`: true = no colour gate (search the
/// whole frame, as before the gate); false = the default colour gate. `search`: see CascadeSearch.
/// `faceEdges`: wf_detector_options' face_edge_refinement and face_edge_transfer (0, 0 = defaults; -1 = the rough
/// box, as before the refiner).
struct FaceEdgeOptions {
    int refinement = 0, transfer = 0;
};
/// `searchMaxLongSidePx`: wf_detector_options' cascade_search_max_long_side_px (0 = default: search at most VGA,
/// measure on the frame; -1 = search the frame at its own size).
std::unique_ptr<DetectorHandle> makeCascade(const std::string& path, int minWindowWidth = 0, int minWindowHeight = 0,
                                            double maxWindowFactor = 0, double minElevationRad = 0,
                                            bool fullSearch = false,
                                            CascadeSearch search = CascadeSearch::Defaults,
                                            FaceEdgeOptions faceEdges = {}, int searchMaxLongSidePx = 0);
/// Creates a U-Net detector (class names from classes.json next to the model). `coarseMinElevationRad`: as
/// wf_detector_options::unet_coarse_min_elevation_rad (0 = the default cut, <= -1.5 = the whole frame).
/// `faceEdges` as for makeCascade (refinement -1 = the mask's own edges). `catalogue` (borrowed for the call;
/// may be null): the sign kinds, as the product passes the map's (a multi-class U-Net's kinds other than the Exit
/// sign are verified against their own face sizes, and lift the coarse pass's elevation cut).
struct CatalogueEntry;
std::unique_ptr<DetectorHandle> makeUnet(const std::string& path, double coarseMinElevationRad = 0,
                                         FaceEdgeOptions faceEdges = {},
                                         const std::vector<CatalogueEntry>* catalogue = nullptr,
                                         int transposedConvolution = 0);

/// The class names of the U-Net `modelPath` from the classes.json beside it (as the detector reads them). False
/// with `error` naming the file when it cannot be read.
bool readUnetClasses(const std::string& modelPath, std::vector<std::string>* classes, std::string* error);

/// Runs a detector on a prepared frame; returns the status and fills `observations`.
int detect(DetectorHandle& detector, const PreparedFrame& frame, std::vector<wf_detector_observation>* observations);

/// One kind of a map's "signKinds" catalogue with its strings owned (wf_sign_kind borrows them from here).
struct CatalogueEntry {
    std::string kind, faceColour, legendColour;
    wf_sign_kind entry{};
};

/// Reads the "signKinds" of a map-v1 JSON file (e.g. Maps/Buildings/wayfinder-office.json) as the Swift wrapper
/// turns them into wf_sign_kind: sizes, colours, recognition range, reads_text, and the placement band from
/// "mountingHeightMeters" for a phone 1.0-1.7 m up with 0.1 m of margin (DetectorConfiguration.placementBand).
/// Returns false with `error` naming the file on failure. The entries' pointers stay valid while `out` lives and
/// is not resized.
bool readMapCatalogue(const std::string& mapPath, std::vector<CatalogueEntry>* out, std::string* error);

/// A detector with `catalogue` and the cascades `paths` of kinds `kinds` (borrowed for the call): a cascade detector,
/// or with `unetPath` set the U-Net with those cascades beside it. `wallKindsPerFrame`: as
/// wf_detector_options.cascade_wall_kinds_per_frame (0 = default 2, -1 = all); `plateGate`: as
/// wf_detector_options.cascade_plate_gate (0 = default on, -1 = off); `wallKindFramePeriod`: as
/// wf_detector_options.cascade_wall_kind_frame_period (0 = default).
std::unique_ptr<DetectorHandle> makeWithCatalogue(const std::vector<std::string>& paths, const std::vector<std::string>& kinds,
                                                  const std::vector<CatalogueEntry>& catalogue, const std::string& unetPath = "",
                                                  int wallKindsPerFrame = 0, int plateGate = 0, int wallKindFramePeriod = 0);

/// Default locations: SignDetector/models in this checkout, the reference cascade in ../shared, and the
/// tiny test model.
std::string productModelsDir();
std::string referenceCascadePath();
std::string tinyUnetPath();
/// The bundled office map (Maps/Buildings/wayfinder-office.json), whose catalogue has every sign kind.
std::string officeMapPath();
bool fileExists(const std::string& path);

/// Range (m) from an observation and the sign's face height: the paper's equation 3 on the unrolled
/// image (bench/range_formula.hpp).
double observationRangeMeters(const wf_detector_observation& o, double signHeightMeters, double pitchRad);

/// Whether an observation matches a labelled sign: the observation's centre lies in the sign's unrolled
/// bounding box (corners mapped with the observation's own unrolled<->raw map) and its height is within a
/// factor 2 of the sign's.
bool matches(const wf_detector_observation& o, const LabelledSign& sign);

}  // namespace wf::sign::bench
