#include "detector.hpp"
#include "search_frame.hpp"
#include "unrolled_search_image.hpp"

#include "wf_range.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

namespace wf::sign {

namespace {
std::string directoryOf(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}
}  // namespace

int ResolvedOptions::fromOptions(const wf_detector_options& opts, ResolvedOptions* out, std::string* error) {
    ResolvedOptions r;
    const int kind = enumValue(opts.kind);
    if (kind != WF_DETECTOR_CASCADE && kind != WF_DETECTOR_UNET) {
        *error = "unknown detector kind " + std::to_string(kind);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.kind = static_cast<wf_detector_kind>(kind);
    if (const int status = parseCatalogue(opts.catalogue, opts.catalogue_count, &r.catalogue, error);
        status != WF_STATUS_OK) {
        return status;
    }
    if (opts.cascade_count > 0 && opts.cascade_paths == nullptr) {
        *error = "cascade_count is " + std::to_string(opts.cascade_count) + " but cascade_paths is NULL";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    for (size_t i = 0; i < opts.cascade_count; ++i) {
        if (opts.cascade_paths[i] == nullptr) {
            *error = "cascade_paths[" + std::to_string(i) + "] is NULL";
            return WF_STATUS_INVALID_ARGUMENT;
        }
        r.cascadePaths.emplace_back(opts.cascade_paths[i]);
        std::string kind = opts.cascade_kinds && opts.cascade_kinds[i] ? opts.cascade_kinds[i] : "exit";
        if (kind.empty() || kind.size() >= WF_KIND_NAME_CAPACITY) {
            *error = "cascade kind name '" + kind + "' must have 1 to " + std::to_string(WF_KIND_NAME_CAPACITY - 1) +
                     " characters";
            return WF_STATUS_INVALID_ARGUMENT;
        }
        r.cascadeKinds.push_back(kind);
    }
    if (opts.unet_path) r.unetPath = opts.unet_path;
    if (opts.class_count > 0 && opts.class_names == nullptr) {
        *error = "class_count is " + std::to_string(opts.class_count) + " but class_names is NULL";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    for (size_t i = 0; i < opts.class_count; ++i) {
        if (opts.class_names[i] == nullptr || std::strlen(opts.class_names[i]) == 0 ||
            std::strlen(opts.class_names[i]) >= WF_KIND_NAME_CAPACITY) {
            *error = "class_names[" + std::to_string(i) + "] must have 1 to " +
                     std::to_string(WF_KIND_NAME_CAPACITY - 1) + " characters";
            return WF_STATUS_INVALID_ARGUMENT;
        }
        r.classNames.emplace_back(opts.class_names[i]);
    }
    if (opts.class_count == 1) {
        *error = "class_names needs background plus at least one class";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    auto positiveOr = [](double v, double d) { return v > 0 ? v : d; };
    r.cascade.scaleFactor = positiveOr(opts.cascade_scale_factor, 1.2);
    if (r.cascade.scaleFactor <= 1.0) {
        *error = "cascade_scale_factor must be > 1";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.minNeighbors = opts.cascade_min_neighbors > 0 ? opts.cascade_min_neighbors : 3;
    if ((opts.cascade_min_window_width > 0) != (opts.cascade_min_window_height > 0)) {
        *error = "cascade_min_window_width and cascade_min_window_height must both be set or both be 0";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.minWindow = opts.cascade_min_window_width > 0
                              ? cv::Size(opts.cascade_min_window_width, opts.cascade_min_window_height)
                              : cv::Size();  // each cascade's training window
    r.cascade.maxWindowFactor = positiveOr(opts.cascade_max_window_factor, 0);
    // cascade_search_above_elevation: 0 = default (rows above CascadeParams' -0.15 rad), 1 = rows above
    // cascade_min_elevation_rad, -1 = the whole frame.
    const int above = opts.cascade_search_above_elevation;
    if (above < -1 || above > 1) {
        *error = "cascade_search_above_elevation must be -1 (whole frame), 0 (default) or 1, not " + std::to_string(above);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.searchAboveElevation = above >= 0;
    if (above == 1) r.cascade.minElevationRad = opts.cascade_min_elevation_rad;
    if (r.cascade.searchAboveElevation && !(std::abs(r.cascade.minElevationRad) < 1.5)) {
        *error = "cascade_min_elevation_rad must be finite and within (-1.5, 1.5) rad";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.unetInputSize = opts.unet_input_size > 0 ? opts.unet_input_size : 224;
    if (opts.unet_transposed_convolution < -1 || opts.unet_transposed_convolution > 1) {
        *error = "unet_transposed_convolution must be -1 (OpenCV's layer), 0 (default: sub-pixel) or 1 (sub-pixel), not " +
                 std::to_string(opts.unet_transposed_convolution);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.unetSubPixelUpsampling = opts.unet_transposed_convolution >= 0;
    if (opts.cascade_plate_gate < -1 || opts.cascade_plate_gate > 1) {
        *error = "cascade_plate_gate must be -1 (off), 0 (default: on) or 1 (on), not " +
                 std::to_string(opts.cascade_plate_gate);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.plateGate.enabled = opts.cascade_plate_gate >= 0;
    r.unet.maskThreshold = positiveOr(opts.unet_mask_threshold, 0.5);
    if (r.unet.maskThreshold >= 1.0) {
        *error = "unet_mask_threshold must be in (0, 1)";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.unet.zoomFactor = positiveOr(opts.unet_zoom_factor, 3.5);
    r.unet.minCropPx = opts.unet_min_crop_px > 0 ? opts.unet_min_crop_px : 64;
    r.unet.minBlobAreaPx = opts.unet_min_blob_area_px > 0 ? opts.unet_min_blob_area_px : 3;
    r.unet.maxCandidates = opts.unet_max_candidates > 0 ? opts.unet_max_candidates : 8;
    r.minScore = std::max(0.0, opts.min_score);
    SliceParams slices;
    slices.sliceCount = std::max(0, opts.slice_count);
    slices.bandFraction = opts.slice_band_fraction > 0 && opts.slice_band_fraction <= 1 ? opts.slice_band_fraction : 0.6;
    r.cascade.slices = slices;
    r.unet.slices = slices;
    // Face-edge refinement (both detectors): on unless -1; the pixels' transfer curve.
    const int refinement = opts.face_edge_refinement;
    if (refinement < -1 || refinement > 1) {
        *error = "face_edge_refinement must be -1 (off), 0 (default: on) or 1 (on), not " + std::to_string(refinement);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.faceEdges.enabled = refinement >= 0;
    const int transfer = opts.face_edge_transfer;
    if (transfer < 0 || transfer > 2) {
        *error = "face_edge_transfer must be 0 (default), 1 (linear) or 2 (sRGB), not " + std::to_string(transfer);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    if (transfer == 1) r.faceEdges.transfer = PixelTransfer::kLinear;
    if (transfer == 2) r.faceEdges.transfer = PixelTransfer::kSrgb;
    r.unet.faceEdges = maskFaceEdgeParams(r.faceEdges);
    r.rollSnapToleranceRad = std::max(0.0, opts.roll_snap_tolerance_rad);
    r.cascade.colourGate.enabled = opts.cascade_full_search == 0;
    if (opts.cascade_gate_min_contrast < 0 || !std::isfinite(opts.cascade_gate_min_contrast)) {
        *error = "cascade_gate_min_contrast must be finite and >= 0";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    if (opts.cascade_gate_min_contrast > 0) r.cascade.colourGate.minContrast = opts.cascade_gate_min_contrast;
    const double cut = opts.unet_coarse_min_elevation_rad;
    if (std::isnan(cut) || cut >= 1.5) {
        *error = "unet_coarse_min_elevation_rad must be a number below 1.5 rad (0 = default, <= -1.5 = off)";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    if (cut <= -1.5) {
        r.unet.coarseMinElevationRad = std::nan("");
    } else if (cut != 0) {
        r.unet.coarseMinElevationRad = cut;
    }
    r.unetCoarseCutGiven = cut != 0;
    // Placement prior: on unless -1.
    const int prior = opts.cascade_placement_prior;
    if (prior < -1 || prior > 1) {
        *error = "cascade_placement_prior must be -1 (off), 0 (default: on) or 1 (on), not " + std::to_string(prior);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.placement.enabled = prior >= 0;
    const double low = opts.cascade_sign_above_camera_min_m, high = opts.cascade_sign_above_camera_max_m;
    if (!std::isfinite(low) || !std::isfinite(high)) {
        *error = "cascade_sign_above_camera_min_m and _max_m must be finite";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    if (low != 0) r.cascade.placement.centreAboveCameraMinMeters = low;
    if (high != 0) r.cascade.placement.centreAboveCameraMaxMeters = high;
    if (!(r.cascade.placement.centreAboveCameraMinMeters < r.cascade.placement.centreAboveCameraMaxMeters)) {
        *error = "cascade_sign_above_camera_min_m (" + std::to_string(r.cascade.placement.centreAboveCameraMinMeters) +
                 ") must be below cascade_sign_above_camera_max_m (" +
                 std::to_string(r.cascade.placement.centreAboveCameraMaxMeters) + ")";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    // Colour gate in crowded frames, margins, and the component-width window floor in tiles.
    const double factor = opts.cascade_gate_crowded_contrast_factor;
    if (!std::isfinite(factor) || factor < 0 || (factor > 0 && factor < 1)) {
        *error = "cascade_gate_crowded_contrast_factor must be 0 (default), 1 (off) or above 1";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.colourGate.crowdedContrastFactor = factor == 0 ? ColourGateParams{}.crowdedContrastFactor : factor;
    const int margin = opts.cascade_gate_min_margin_px;
    if (margin < 0) {
        *error = "cascade_gate_min_margin_px must be 0 (default) or positive, not " + std::to_string(margin);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.colourGate.minMarginPx = margin == 0 ? ColourGateParams{}.minMarginPx : margin;
    const double fraction = opts.cascade_gate_component_window_fraction;
    if (!std::isfinite(fraction) || fraction > 1 || (fraction < 0 && fraction != -1)) {
        *error = "cascade_gate_component_window_fraction must be 0 (default), -1 (off) or in (0, 1]";
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascade.colourGate.componentWindowFraction =
        fraction == 0 ? ColourGateParams{}.componentWindowFraction : std::max(0.0, fraction);
    const int perFrame = opts.cascade_wall_kinds_per_frame;
    if (perFrame < -1) {
        *error = "cascade_wall_kinds_per_frame must be -1 (all), 0 (default: 2) or a positive count, not " +
                 std::to_string(perFrame);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.wallKindsPerFrame = perFrame == 0 ? 2 : perFrame;
    const int period = opts.cascade_wall_kind_frame_period;
    if (period < 0) {
        *error = "cascade_wall_kind_frame_period must be 0 (default) or a positive count of frames, not " +
                 std::to_string(period);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.wallKindFramePeriod = period > 0 ? period : perFrame == 0 ? 2 : 1;
    const int searchLongSide = opts.cascade_search_max_long_side_px;
    if (searchLongSide < -1 || (searchLongSide > 0 && searchLongSide < 64)) {
        *error = "cascade_search_max_long_side_px must be 0 (default: 640), -1 (the frame's own size) or at least 64, not " +
                 std::to_string(searchLongSide);
        return WF_STATUS_INVALID_ARGUMENT;
    }
    r.cascadeSearchMaxLongSidePx = searchLongSide == 0 ? 640 : searchLongSide;
    *out = std::move(r);
    return WF_STATUS_OK;
}

int Detector::load(const ResolvedOptions& options, std::string* error) {
    options_ = options;
    kinds_.clear();
    cascadeSpecs_.clear();
    gatedKinds_.clear();
    plainKinds_.clear();
    wallKindCursor_ = 0;
    wallKindFrames_ = 0;
    requestedPlainKinds_.reset();
    textReaderProblem_.clear();
    if (options_.kind == WF_DETECTOR_CASCADE) {
        if (!cascade_.load(options_.cascadePaths, options_.cascadeKinds, error)) return WF_STATUS_MODEL_LOAD;
        kinds_ = cascade_.kinds();
    } else if (const int status = loadUnet(error); status != WF_STATUS_OK) {
        return status;
    }
    // How each cascade is searched: Exit-like kinds (and kinds the catalogue does not describe) through the colour
    // gate, the others on their own placement band; beside a U-Net every cascade is searched on its band.
    const bool cascadesLoaded = options_.kind == WF_DETECTOR_CASCADE || !options_.cascadePaths.empty();
    for (size_t i = 0; cascadesLoaded && i < cascade_.kinds().size(); ++i) {
        const SignKindSpec* spec = findKind(options_.catalogue, cascade_.kinds()[i]);
        const bool gated = options_.kind == WF_DETECTOR_CASCADE && (spec == nullptr || spec->colourGated());
        (gated ? gatedKinds_ : plainKinds_).push_back(i);
        cascadeSpecs_.push_back(spec);
    }
    // The text reader, when a kind the detector reports reads text. Not fatal: such signs are then reported
    // without their text (the phone reads it with Vision).
    for (const SignKindSpec& spec : options_.catalogue) {
        if (!spec.readsText || std::find(kinds_.begin(), kinds_.end(), spec.kind) == kinds_.end()) continue;
        std::string problem;
        if (!textReader_.load("", &problem)) textReaderProblem_ = problem;
        break;
    }
    return WF_STATUS_OK;
}

int Detector::loadUnet(std::string* error) {
    if (options_.unetPath.empty()) {
        *error = "U-Net detector needs unet_path";
        return WF_STATUS_MODEL_LOAD;
    }
    std::vector<std::string> classes = options_.classNames;
    if (classes.empty()) {
        const std::string classesPath = directoryOf(options_.unetPath) + "/classes.json";
        if (std::ifstream(classesPath).good() && !readClassList(classesPath, &classes, error)) return WF_STATUS_MODEL_LOAD;
    }
    if (!unet_.load(options_.unetPath, classes, options_.unetInputSize, error, options_.unetSubPixelUpsampling)) {
        return WF_STATUS_MODEL_LOAD;
    }
    for (const auto& name : unet_.classNames()) {
        if (name.size() >= WF_KIND_NAME_CAPACITY) {
            *error = "class name '" + name + "' is longer than " + std::to_string(WF_KIND_NAME_CAPACITY - 1);
            return WF_STATUS_MODEL_LOAD;
        }
    }
    kinds_.assign(unet_.classNames().begin() + 1, unet_.classNames().end());
    configureUnetClasses();
    if (options_.cascadePaths.empty()) return WF_STATUS_OK;
    // Cascades beside the U-Net: kinds it has no class for (pictograms, placards).
    if (!cascade_.load(options_.cascadePaths, options_.cascadeKinds, error)) return WF_STATUS_MODEL_LOAD;
    for (const std::string& kind : cascade_.kinds()) {
        if (std::find(kinds_.begin(), kinds_.end(), kind) != kinds_.end()) {
            *error = "cascade kind '" + kind + "' is also a class of the U-Net (or listed twice): give each kind one model";
            return WF_STATUS_MODEL_LOAD;
        }
        kinds_.push_back(kind);
    }
    return WF_STATUS_OK;
}

void Detector::configureUnetClasses() {
    const std::vector<std::string>& names = unet_.classNames();
    options_.unet.classLimits.assign(names.size(), std::nullopt);
    bool eyeLevelKinds = false;
    for (size_t c = 1; c < names.size(); ++c) {
        const SignKindSpec* spec = findKind(options_.catalogue, names[c]);
        if (spec == nullptr || spec->colourGated()) continue;  // Exit-like: the Exit sign's limits
        // The Exit limits scaled to this face: aspect 0.4-1.9 x the facing face's (a face turned 60 degrees is half
        // as wide; slices of a ragged mask a little short), height 0.57-2.4 x the face's (Exit: 0.12-0.5 m of
        // 0.21 m), no colour check (white on blue or dark grey plates).
        UnetSignLimits limits;
        const double aspect = spec->faceWidthMeters / spec->faceHeightMeters;
        limits.minAspect = 0.4 * aspect;
        limits.maxAspect = 1.9 * aspect;
        limits.minSignHeightM = 0.57 * spec->faceHeightMeters;
        limits.maxSignHeightM = 2.4 * spec->faceHeightMeters;
        limits.minColourFraction = 0;
        options_.unet.classLimits[c] = limits;
        eyeLevelKinds = true;
    }
    // Pictograms and placards hang at eye level beside doors (bottom edge 1.3-1.45 m): a near one lies well below the
    // horizon (a placard's bottom edge 0.8 m away, phone at 1.6 m: -0.36 rad), under the Exit-sign cut. So the coarse
    // pass reads the whole frame, unless the caller set the cut.
    if (eyeLevelKinds && !options_.unetCoarseCutGiven) options_.unet.coarseMinElevationRad = std::nan("");
}

void Detector::detectPlainKinds(const cv::Mat& grayUnrolled, const Unrolling& unrolling, double pitchRad,
                                std::vector<Detection>* out) {
    const int longSide = std::max(grayUnrolled.cols, grayUnrolled.rows);
    const int limit = options_.plainKindSearchMaxLongSidePx;
    cv::Mat image = grayUnrolled;
    if (limit > 0 && longSide > limit) {
        const double s = double(limit) / longSide;
        cv::resize(grayUnrolled, image,
                   cv::Size(std::max(1, int(std::lround(grayUnrolled.cols * s))), std::max(1, int(std::lround(grayUnrolled.rows * s)))),
                   0, 0, cv::INTER_AREA);
    }
    const double sx = double(image.cols) / grayUnrolled.cols, sy = double(image.rows) / grayUnrolled.rows;
    const Intrinsics& k = unrolling.unrolledIntrinsics();
    const FrameGeometry geometry{pitchRad, Intrinsics{k.fx * sx, k.fy * sy, (k.cx + 0.5) * sx - 0.5, (k.cy + 0.5) * sy - 0.5}};
    // Which of these kinds this frame searches (about 3 ms each on a cluttered VGA frame through the plate gate;
    // 20-40 ms without it).
    const std::vector<size_t> searched = plainKindsThisFrame();
    for (size_t i : plainKinds_) {
        if (std::find(searched.begin(), searched.end(), i) == searched.end()) markPlainKindUnsearched(i);
    }
    const int indexOffset = options_.kind == WF_DETECTOR_UNET ? int(unet_.classNames().size()) : 0;
    std::vector<CascadeParams> kindParams;
    for (size_t i : searched) kindParams.push_back(plainKindParams(i, geometry, pitchRad));
    const GateDecision gate = plateGate(image, geometry, searched, kindParams);
    for (size_t j = 0; j < searched.size(); ++j) {
        const std::vector<size_t> one{searched[j]};
        std::vector<Detection> found =
            gate.fullSearch ? cascade_.detect(image, kindParams[j], -1, &geometry, &one)
                            : cascade_.detectInRegions(image, gate.regions, kindParams[j], -1, &geometry, &one, true);
        for (Detection& d : found) {
            // Box edges scale with the image (edge coordinates from the image corner).
            const cv::Rect2d& b = d.measurement.box;
            const double left = b.x + 0.5, top = b.y + 0.5;
            const int x0 = int(std::lround(left / sx)), y0 = int(std::lround(top / sy));
            const int x1 = int(std::lround((left + b.width) / sx)), y1 = int(std::lround((top + b.height) / sy));
            d.measurement = measureBox(cv::Rect(x0, y0, std::max(1, x1 - x0), std::max(1, y1 - y0)), kindParams[j].slices);
            d.kindIndex += indexOffset;
            out->push_back(std::move(d));
        }
    }
}

CascadeParams Detector::plainKindParams(size_t i, const FrameGeometry& geometry, double pitchRad) const {
    CascadeParams params = options_.cascade;
    const SignKindSpec* spec = cascadeSpecs_[i];
    const cv::Size trained = cascade_.trainedWindow(i);
    const double aspect = double(trained.width) / trained.height;
    if (spec != nullptr) {
        if (spec->hasPlacement()) {
            params.placement.centreAboveCameraMinMeters = spec->centreAboveCameraMinMeters;
            params.placement.centreAboveCameraMaxMeters = spec->centreAboveCameraMaxMeters;
        }
        // The window covers the face (and a margin): its width on the sign is at least the face's width, or its
        // height at the window's aspect; up to about 1.6 x that with the margin and one pyramid step.
        const double covered = std::max(spec->faceWidthMeters, spec->faceHeightMeters * aspect);
        params.placement.windowWidthMinMeters = 0.8 * covered;
        params.placement.windowWidthMaxMeters = 1.6 * covered;
        if (spec->maxRangeMeters > 0) {
            const double heightPx = geometry.unrolled.fy * spec->faceHeightMeters / spec->maxRangeMeters;
            if (heightPx > std::max(trained.height, params.minWindow.height)) {
                params.minWindow = cv::Size(int(std::lround(heightPx * aspect)), int(std::lround(heightPx)));
            }
        }
    } else {
        params.placement.enabled = false;  // no size or height known
    }
    if (!std::isfinite(pitchRad)) params.placement.enabled = false;
    return params;
}

GateDecision Detector::plateGate(const cv::Mat& image, const FrameGeometry& geometry, const std::vector<size_t>& kinds,
                                 const std::vector<CascadeParams>& kindParams) const {
    GateDecision full;  // fullSearch
    const PlateGateParams& gate = options_.cascade.plateGate;
    if (!gate.enabled || kinds.empty()) return full;
    // Plates as small as the smallest window any of these kinds searches (a candidate may be the legend alone,
    // about 0.6 of the plate: half the window), up to half the image's height.
    int smallestWindow = image.cols;
    for (size_t j = 0; j < kinds.size(); ++j) {
        const cv::Size w = kindParams[j].minWindow.empty() ? cascade_.trainedWindow(kinds[j]) : kindParams[j].minWindow;
        smallestWindow = std::min(smallestWindow, w.width);
    }
    const int minSide = std::max(6, smallestWindow / 2), maxSide = std::max(minSide, image.rows / 2);
    std::vector<cv::Rect> candidates = plateCandidates(image, 0, image.rows, minSide, maxSide, gate);
    // A candidate stays when some kind's placement band holds it at a window of its region's range (0.7-1.9 x its
    // larger side).
    std::vector<cv::Rect> placed;
    for (const cv::Rect& c : candidates) {
        const double side = std::max(c.width, c.height), centreRow = c.y + 0.5 * c.height;
        bool inBand = false;
        for (size_t j = 0; j < kinds.size() && !inBand; ++j) {
            if (!kindParams[j].placement.enabled) {
                inBand = true;
                break;
            }
            const cv::Size trained = cascade_.trainedWindow(kinds[j]);
            const double aspect = double(trained.width) / trained.height;
            for (double f : {gate.minWindowFraction, gate.maxWindowFraction}) {
                const auto band = placementRowBand(kindParams[j].placement, f * side, f * side / aspect,
                                                   geometry.pitchRad, geometry.unrolled);
                if (centreRow >= band.first && centreRow < band.second) inBand = true;
            }
        }
        if (inBand) placed.push_back(c);
    }
    return plateRegions(placed, cv::Rect(0, 0, image.cols, image.rows), gate);
}

std::vector<Detection> Detector::detectPlainKindsShrunk(const cv::Mat& gray, const Intrinsics& k, double rollRad,
                                                        double pitchRad, const Unrolling& frameUnrolling) {
    const int limit = options_.plainKindSearchMaxLongSidePx;
    const cv::Size frameSize = gray.size();
    if (!overSearchSize(frameUnrolling.unrolledSize())) {
        std::vector<Detection> found;
        detectPlainKinds(frameUnrolling.apply(gray), frameUnrolling, pitchRad, &found);
        return found;
    }
    // Sampled bilinearly from at most twice the search size (unrolled_search_image.hpp); a larger frame is first
    // shrunk with INTER_AREA (1920 x 1440: 3 x).
    if (std::max(frameSize.width, frameSize.height) <= 2 * limit) {
        return detectPlainKindsUnrolled(gray, frameSize, k, rollRad, pitchRad, frameUnrolling);
    }
    const SearchFrame small(grayImageView(gray), k, limit);
    const wf_image& s = small.image();
    const cv::Mat smallGray(s.height, s.width, CV_8UC1, const_cast<uint8_t*>(s.data), s.stride);
    return detectPlainKindsUnrolled(smallGray, frameSize, k, rollRad, pitchRad, frameUnrolling);
}

bool Detector::overSearchSize(cv::Size unrolledSize) const {
    const int limit = options_.plainKindSearchMaxLongSidePx;
    return limit > 0 && std::max(unrolledSize.width, unrolledSize.height) > limit;
}

std::vector<Detection> Detector::detectPlainKindsUnrolled(const cv::Mat& sourceGray, cv::Size frameSize,
                                                          const Intrinsics& k, double rollRad, double pitchRad,
                                                          const Unrolling& frameUnrolling) {
    // Unrolled straight into a canvas of the search size (unrolled_search_image.hpp): one resampling where
    // shrinking, unrolling and shrinking the canvas again took three.
    const UnrolledSearchImage search(sourceGray, frameSize, k, rollRad, options_.rollSnapToleranceRad,
                                     options_.plainKindSearchMaxLongSidePx);
    std::vector<Detection> found;
    detectPlainKinds(search.image(), search.unrolling(), pitchRad, &found);
    return mapToFrame(std::move(found), search.scaleX(), search.scaleY(), search.unrolling(), frameUnrolling);
}

std::vector<Detection> Detector::detectPlainKindsBesideUnet(RawPyramid& pyramid, const wf_image& frameImage,
                                                            const Intrinsics& k, double rollRad, double pitchRad,
                                                            const Unrolling& frameUnrolling, cv::Mat* gray) {
    // A colour frame over twice the search size: its half-size copy is already in the U-Net's pyramid, so the
    // search image is sampled from that copy in gray instead of the whole frame in gray shrunk 3 x.
    const int limit = options_.plainKindSearchMaxLongSidePx;
    const cv::Size frameSize(frameImage.width, frameImage.height);
    if (limit > 0 && std::max(frameSize.width, frameSize.height) > 2 * limit &&
        (frameImage.format == WF_PIXEL_BGRA8 || frameImage.format == WF_PIXEL_RGB8)) {
        cv::Point2d scale;
        const cv::Mat& half = pyramid.level(1, &scale);
        if (half.cols * 2 == frameSize.width && half.rows * 2 == frameSize.height &&
            std::max(half.cols, half.rows) >= limit) {  // pixel edges aligned, large enough
            cv::Mat halfGray;
            cv::cvtColor(half, halfGray, half.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_RGB2GRAY);
            return detectPlainKindsUnrolled(halfGray, frameSize, k, rollRad, pitchRad, frameUnrolling);
        }
    }
    *gray = toGray(frameImage);
    return detectPlainKindsShrunk(*gray, k, rollRad, pitchRad, frameUnrolling);
}

bool Detector::takeWallKindTurn() {
    if (plainKinds_.empty()) return false;
    if (requestedPlainKinds_) return !requestedPlainKinds_->empty();
    return wallKindFrames_++ % options_.wallKindFramePeriod == 0;
}

std::vector<size_t> Detector::plainKindsThisFrame() {
    if (requestedPlainKinds_) return *requestedPlainKinds_;
    const int perFrame = options_.wallKindsPerFrame;
    if (perFrame <= 0 || size_t(perFrame) >= plainKinds_.size()) return plainKinds_;
    std::vector<size_t> searched;
    for (int j = 0; j < perFrame; ++j) searched.push_back(plainKinds_[(wallKindCursor_ + j) % plainKinds_.size()]);
    wallKindCursor_ = (wallKindCursor_ + perFrame) % plainKinds_.size();
    return searched;
}

size_t Detector::cascadeKindOffset() const {
    return options_.kind == WF_DETECTOR_UNET ? unet_.classNames().size() - 1 : 0;
}

bool Detector::isWallKind(size_t index) const {
    const size_t offset = cascadeKindOffset();
    return index >= offset && std::find(plainKinds_.begin(), plainKinds_.end(), index - offset) != plainKinds_.end();
}

bool Detector::requestWallKinds(const std::vector<size_t>& kindIndices, std::string* error) {
    std::vector<size_t> cascades;
    for (size_t index : kindIndices) {
        if (index >= kinds_.size()) {
            *error = "kind index " + std::to_string(index) + " is out of range (" + std::to_string(kinds_.size()) +
                     " kinds)";
            return false;
        }
        if (!isWallKind(index)) {
            *error = "kind '" + kinds_[index] + "' is searched on every frame, not in turn";
            return false;
        }
        const size_t cascade = index - cascadeKindOffset();
        if (std::find(cascades.begin(), cascades.end(), cascade) != cascades.end()) {
            *error = "kind '" + kinds_[index] + "' is requested twice";
            return false;
        }
        cascades.push_back(cascade);
    }
    requestedPlainKinds_ = std::move(cascades);
    return true;
}

bool Detector::anyReadsText(const std::vector<Detection>& detections) const {
    return std::any_of(detections.begin(), detections.end(), [&](const Detection& d) {
        const SignKindSpec* spec = findKind(options_.catalogue, d.kind);
        return spec != nullptr && spec->readsText;
    });
}

std::vector<Detection> Detector::refinedBoxes(std::vector<Detection> boxes, const wf_image& image,
                                              const Unrolling& unrolling, const FaceEdgeParams* edgeParams) const {
    std::vector<Detection> kept = suppressOverlaps(std::move(boxes), 0.5);
    // A box is a rough segmentation: its slices all have the box's height. The face's own edges, found in the
    // image around each box, give the slices their heights (face_edge_refiner.hpp).
    const FaceEdgeParams& params = edgeParams != nullptr ? *edgeParams : options_.faceEdges;
    for (Detection& d : kept) {
        const FaceEdgeResult edges =
            refineFaceEdgesInFrame(image, unrolling, d.measurement, options_.cascade.slices, params);
        if (edges.refined) d.measurement = edges.measurement;
    }
    return kept;
}

void Detector::readLegends(const cv::Mat& grayUnrolled, std::vector<Detection>* detections) {
    if (!textReader_.loaded()) return;
    // Best scores first, at most maxLegendReadsPerFrame plates tall enough to read (tesseract costs about 10-30 ms
    // a plate: a frame of false placard hits must not cost a second).
    std::vector<Detection*> order;
    for (Detection& d : *detections) order.push_back(&d);
    std::stable_sort(order.begin(), order.end(), [](const Detection* a, const Detection* b) { return a->score > b->score; });
    int reads = 0;
    for (Detection* dp : order) {
        Detection& d = *dp;
        const SignKindSpec* spec = findKind(options_.catalogue, d.kind);
        if (spec == nullptr || !spec->readsText) continue;
        if (d.measurement.box.height < options_.minReadablePlateHeightPx || reads >= options_.maxLegendReadsPerFrame) continue;
        ++reads;
        const cv::Rect2d& b = d.measurement.box;
        const cv::Rect box(int(std::floor(b.x + 0.5)), int(std::floor(b.y + 0.5)), int(std::ceil(b.width)),
                           int(std::ceil(b.height)));
        d.text = textReader_.read(grayUnrolled, box).text;
    }
}

wf_detector_observation makeObservation(const Detection& d, const Unrolling& unrolling) {
    wf_detector_observation o;
    std::memset(&o, 0, sizeof o);
    std::strncpy(o.kind, d.kind.c_str(), WF_KIND_NAME_CAPACITY - 1);
    o.kind_index = d.kindIndex;
    o.score = d.score;
    const SliceMeasurement& m = d.measurement;
    o.box_x = m.box.x;
    o.box_y = m.box.y;
    o.box_width = m.box.width;
    o.box_height = m.box.height;
    o.median_bottom_row_px = m.medianBottomEdgePx;
    o.median_height_px = m.medianHeightPx;
    o.center_column_px = m.centerColumnPx;
    o.extent_width_px = m.extentWidthPx;
    o.bottom_edge_slope = m.bottomEdgeSlope;
    o.top_edge_slope = m.topEdgeSlope;
    const Intrinsics& k = unrolling.unrolledIntrinsics();
    o.unrolled_fx = k.fx;
    o.unrolled_fy = k.fy;
    o.unrolled_cx = k.cx;
    o.unrolled_cy = k.cy;
    o.unrolled_width = unrolling.unrolledSize().width;
    o.unrolled_height = unrolling.unrolledSize().height;
    o.slice_count = m.sliceCount;
    o.applied_roll_rad = unrolling.appliedRollRad();
    const cv::Matx23d& a = unrolling.unrolledToRawMatrix();
    for (int i = 0; i < 6; ++i) o.unrolled_to_raw[i] = a(i / 3, i % 3);
    std::strncpy(o.text, d.text.c_str(), WF_SIGN_TEXT_CAPACITY - 1);
    return o;
}

void Detector::markPlainKindUnsearched(size_t i) {
    // Reported kinds: the U-Net's classes without background, then the cascades beside it; or the cascades.
    const size_t offset = cascadeKindOffset();
    if (offset + i < lastSearched_.size()) lastSearched_[offset + i] = 0;
}

FrameResult Detector::detect(const wf_frame& frame) {
    // A request for this frame's wall kinds holds for this frame only, whatever becomes of it.
    struct ConsumeRequest {
        std::optional<std::vector<size_t>>& request;
        ~ConsumeRequest() { request.reset(); }
    } consume{requestedPlainKinds_};
    FrameResult result;
    lastSearched_.assign(kinds_.size(), 0);  // a rejected frame looked for nothing
    const FrameCheck check = checkFrame(frame);
    if (!check.ok()) {
        result.status = check.status;
        result.message = check.message;
        return result;
    }
    try {
        const Intrinsics k{frame.intrinsics.fx, frame.intrinsics.fy, frame.intrinsics.cx, frame.intrinsics.cy};
        // The cascade searches a frame of at most cascadeSearchMaxLongSidePx (search_frame.hpp); the U-Net the
        // frame itself. The brightness check samples the searched image; the whole frame is converted to gray
        // only where gray is read (the cascade's search, the plain kinds, the legends).
        const SearchFrame search(frame.image, k,
                                 options_.kind == WF_DETECTOR_CASCADE ? options_.cascadeSearchMaxLongSidePx : 0);
        const FrameCheck brightness = checkBrightness(search.image());
        if (!brightness.ok()) {
            result.status = brightness.status;
            result.message = brightness.message;
            return result;
        }
        const cv::Size searchSize(search.image().width, search.image().height);
        const Unrolling unrolling = Unrolling::forRoll(frame.roll_rad, search.intrinsics(), searchSize,
                                                       options_.rollSnapToleranceRad);
        // Where detections are measured and reported: the frame's own unrolled pixels.
        const Unrolling frameUnrolling =
            search.shrunk() ? Unrolling::forRoll(frame.roll_rad, k, cv::Size(frame.image.width, frame.image.height),
                                                 options_.rollSnapToleranceRad)
                            : unrolling;
        // Whether this frame searches the kinds that are not Exit-like (one frame in wallKindFramePeriod).
        const bool wallKindsNow = takeWallKindTurn();
        lastSearched_.assign(kinds_.size(), 1);
        if (!wallKindsNow) {
            for (size_t i : plainKinds_) markPlainKindUnsearched(i);
        }
        std::vector<Detection> detections;
        if (options_.kind == WF_DETECTOR_CASCADE) {
            const cv::Mat gray = toGray(search.image());
            const cv::Size unrolledSize = unrolling.unrolledSize();
            int lastRow = -1;
            if (options_.cascade.searchAboveElevation) {
                const Intrinsics& ku = unrolling.unrolledIntrinsics();
                lastRow = CascadeDetector::searchRowLimit(options_.cascade.minElevationRad, frame.pitch_rad, ku.fy, ku.cy,
                                                          unrolledSize.height);
            }
            // Colour gate (colour_gate.hpp): only around strongly red/green regions when the frame has colour.
            const GateDecision gate = gateFrame(search.image(), unrolling, lastRow, options_.cascade.colourGate);
            // A quarter turn is a cheap pixel permutation of the whole frame; otherwise only the pixels the cascade
            // reads are warped: the searched rows, or the gate's regions.
            const bool permutation = unrolling.quarterTurns() >= 0;
            const FrameGeometry geometry{frame.pitch_rad, unrolling.unrolledIntrinsics()};
            // Kinds without a colour gate (pictograms, placards) read the whole unrolled frame when it fits the search
            // size; otherwise their own canvas, unrolled and shrunk in one resampling (detectPlainKindsUnrolled).
            const bool plainOnFrame = wallKindsNow && !overSearchSize(unrolledSize);
            const bool warped = permutation || plainOnFrame;
            cv::Mat grayUnrolled = warped ? unrolling.apply(gray) : cv::Mat::zeros(unrolledSize, CV_8UC1);
            if (gatedKinds_.empty()) {
                // nothing searched through the gate
            } else if (gate.fullSearch) {
                const int rows = lastRow < 0 ? unrolledSize.height : lastRow;
                if (!warped) unrolling.applyToRegion(gray, cv::Rect(0, 0, unrolledSize.width, rows), &grayUnrolled);
                detections = cascade_.detect(grayUnrolled, options_.cascade, lastRow, &geometry, &gatedKinds_);
            } else {
                for (const SearchRegion& region : gate.regions) {
                    if (!warped) unrolling.applyToRegion(gray, region.unrolledRect, &grayUnrolled);
                }
                detections = cascade_.detectInRegions(grayUnrolled, gate.regions, options_.cascade, lastRow, &geometry,
                                                      &gatedKinds_);
            }
            if (plainOnFrame) {
                detectPlainKinds(grayUnrolled, unrolling, frame.pitch_rad, &detections);
            } else if (wallKindsNow) {
                std::vector<Detection> extra =
                    detectPlainKindsUnrolled(gray, searchSize, search.intrinsics(), frame.roll_rad, frame.pitch_rad, unrolling);
                detections.insert(detections.end(), extra.begin(), extra.end());
            }
            // Legends (of the plain kinds' plates, below) are read on the whole unrolled frame.
            const bool legends = !plainKinds_.empty() && textReader_.loaded() && anyReadsText(detections);
            if (legends && !warped) grayUnrolled = unrolling.apply(gray);
            if (search.shrunk()) {
                // Search at VGA, measure at full size (search_frame.hpp): each box refined on the searched image,
                // its legend read there (the crops the phone's VGA frames gave), then moved to the frame's own
                // pixels and refined again with a mask's narrow search (its edges are within a VGA pixel).
                detections = refinedBoxes(std::move(detections), search.image(), unrolling);
                if (legends) readLegends(grayUnrolled, &detections);
                detections = mapToFrame(std::move(detections), search, unrolling, frameUnrolling);
                const FaceEdgeParams fine = maskFaceEdgeParams(options_.faceEdges);
                detections = refinedBoxes(std::move(detections), frame.image, frameUnrolling, &fine);
            } else {
                detections = refinedBoxes(std::move(detections), frame.image, unrolling);
                if (legends) readLegends(grayUnrolled, &detections);
            }
        } else {
            // The phone's BGRA frame goes to the network's sampler as it is (RawPyramid): no whole-frame RGB copy.
            RawPyramid pyramid(toNetworkColour(frame.image));
            detections = unet_.detect(pyramid, unrolling, options_.unet, frame.pitch_rad);
            cv::Mat gray, grayUnrolled;
            if (wallKindsNow) {
                // Cascades beside the U-Net (kinds it has no class for), refined as in the cascade detector.
                std::vector<Detection> extra = detectPlainKindsBesideUnet(pyramid, frame.image, k, frame.roll_rad,
                                                                          frame.pitch_rad, unrolling, &gray);
                extra = refinedBoxes(std::move(extra), frame.image, unrolling);
                detections.insert(detections.end(), extra.begin(), extra.end());
            }
            // Legends of the plates found (the U-Net's placard class or a placard cascade beside it).
            if (textReader_.loaded() && anyReadsText(detections)) {
                if (gray.empty()) gray = toGray(frame.image);
                grayUnrolled = unrolling.apply(gray);
                readLegends(grayUnrolled, &detections);
            }
        }
        for (const auto& d : detections) {
            if (d.score >= options_.minScore && d.measurement.valid) {
                result.observations.push_back(makeObservation(d, frameUnrolling));
            }
        }
    } catch (const cv::Exception& e) {
        result.status = WF_STATUS_INTERNAL;
        result.message = std::string("OpenCV error: ") + e.what();
        result.observations.clear();
    } catch (const std::exception& e) {
        result.status = WF_STATUS_INTERNAL;
        result.message = std::string("internal error: ") + e.what();
        result.observations.clear();
    }
    return result;
}

bool sightingFromObservation(const wf_detector_observation& o, const SignKindSpec& kind, double pitchRad,
                             wf_sign_sighting* out) {
    const wf_range_unrolled_camera camera{o.unrolled_fx, o.unrolled_fy, o.unrolled_cx, o.unrolled_cy, pitchRad,
                                          o.applied_roll_rad};
    wf_range_slice_measurement m{};
    m.median_bottom_row_px = o.median_bottom_row_px;
    m.median_height_px = o.median_height_px;
    m.center_column_px = o.center_column_px;
    m.bottom_edge_slope = o.bottom_edge_slope;
    m.top_edge_slope = o.top_edge_slope;
    m.extent_width_px = o.extent_width_px;
    wf_range_result r{};
    if (wf_range_apparent_height_slices(&r, &camera, &m, kind.faceHeightMeters, WF_RANGE_SLICE_MODEL_RAY_ELEVATION) !=
        WF_STATUS_OK) {
        return false;
    }
    std::memset(out, 0, sizeof *out);
    std::strncpy(out->kind, kind.kind.c_str(), WF_KIND_NAME_CAPACITY - 1);
    out->range_m = r.range_m;
    out->bearing_rad = r.bearing_rad;
    out->score = o.score;
    out->center_height_above_camera_m = r.center_height_above_camera_m;
    std::memcpy(out->text, o.text, WF_SIGN_TEXT_CAPACITY);
    out->text[WF_SIGN_TEXT_CAPACITY - 1] = '\0';
    // Corners: the edge lines (medians at the centre column, slopes) at the ends of the extent, unrolled -> raw.
    const double half = 0.5 * o.extent_width_px;
    const double bottom = o.median_bottom_row_px, top = o.median_bottom_row_px - o.median_height_px;
    const double cornerU[4] = {o.center_column_px - half, o.center_column_px + half, o.center_column_px + half,
                               o.center_column_px - half};
    const double cornerV[4] = {top - o.top_edge_slope * half, top + o.top_edge_slope * half,
                               bottom + o.bottom_edge_slope * half, bottom - o.bottom_edge_slope * half};
    const double* a = o.unrolled_to_raw;
    for (int i = 0; i < 4; ++i) {
        out->corners_raw_px[2 * i] = a[0] * cornerU[i] + a[1] * cornerV[i] + a[2];
        out->corners_raw_px[2 * i + 1] = a[3] * cornerU[i] + a[4] * cornerV[i] + a[5];
    }
    return true;
}

bool faceTouchesFrameEdge(const wf_sign_sighting& sighting, int widthPx, int heightPx, double marginPx) {
    for (int i = 0; i < 4; ++i) {
        const double u = sighting.corners_raw_px[2 * i], v = sighting.corners_raw_px[2 * i + 1];
        // Pixel centres run from 0 to width - 1; the negated tests also catch NaN.
        if (!(u >= marginPx && v >= marginPx && u <= widthPx - 1 - marginPx && v <= heightPx - 1 - marginPx)) return true;
    }
    return false;
}

FrameSightings Detector::sense(const wf_frame& frame) {
    FrameSightings out;
    if (options_.catalogue.empty()) {
        out.status = WF_STATUS_INVALID_CATALOGUE;
        out.message = "the sign-kind catalogue is empty: no face size to range with (set catalogue in "
                      "wf_detector_options, e.g. from the map's signKinds)";
        return out;
    }
    FrameResult detected = detect(frame);
    out.status = detected.status;
    out.message = std::move(detected.message);
    if (detected.status < 0) return out;
    for (const wf_detector_observation& o : detected.observations) {
        if (!(o.median_height_px >= options_.minRangingHeightPx)) continue;  // too small to range
        const SignKindSpec* kind = findKind(options_.catalogue, o.kind);
        wf_sign_sighting sighting;
        if (kind != nullptr && sightingFromObservation(o, *kind, frame.pitch_rad, &sighting) &&
            !faceTouchesFrameEdge(sighting, frame.image.width, frame.image.height, options_.frameEdgeMarginPx)) {
            out.sightings.push_back(sighting);
        }
    }
    return out;
}

}  // namespace wf::sign
