// The whole per-frame pipeline behind wf_detector: validate -> unroll -> detect (cascade or U-Net) ->
// slice measurement -> observations.
#pragma once

#include "cascade_detector.hpp"
#include "image_input.hpp"
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

    /// Copies `opts` (borrowed strings are copied) and applies defaults. Returns WF_OK or an error code with
    /// `error` set.
    static int fromOptions(const wf_detector_options& opts, ResolvedOptions* out, std::string* error);
};

/// Result of one frame.
struct FrameResult {
    /// WF_OK, a warning or an error code.
    int status = WF_OK;
    std::string message;
    /// Observations, best score first (empty unless status >= 0).
    std::vector<wf_detector_observation> observations;
};

/// Loaded models plus options. Not thread-safe.
class Detector {
public:
    /// Loads the models named by `options`. Returns WF_OK or WF_ERR_MODEL_LOAD with `error` set.
    int load(const ResolvedOptions& options, std::string* error);

    /// Runs the pipeline on one frame. Never throws (OpenCV exceptions become WF_ERR_INTERNAL).
    FrameResult detect(const wf_frame& frame);

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

}  // namespace wf::sign
