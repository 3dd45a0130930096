// The whole per-frame pipeline behind wf_detector: validate -> unroll -> detect (cascade or U-Net) ->
// slice measurement -> observations.
#pragma once

#include "cascade_detector.hpp"
#include "face_edge_refiner.hpp"
#include "image_input.hpp"
#include "sign_catalogue.hpp"
#include "unet_detector.hpp"
#include "unroll.hpp"
#include "wf_sign_detector.h"

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
    CascadeParams cascade;
    UnetParams unet;
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

    /// Kind names the detector reports (cascade kinds, or U-Net classes without background).
    const std::vector<std::string>& kinds() const { return kinds_; }

    const ResolvedOptions& options() const { return options_; }

private:
    ResolvedOptions options_;
    CascadeDetector cascade_;
    UnetDetector unet_;
    std::vector<std::string> kinds_;
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
