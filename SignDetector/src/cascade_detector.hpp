// Detector A: one AdaBoost cascade per sign kind (Viola-Jones as trained by opencv_traincascade; the
// reference app's Exit-sign detector, Fusco et al. 2020 section 3 / [6]) run with
// cv::CascadeClassifier::detectMultiScale on the unrolled gray frame. Gives a rough box per sign.
#pragma once

#include "colour_gate.hpp"
#include "plate_gate.hpp"
#include "detection.hpp"
#include "placement_prior.hpp"

#include <opencv2/objdetect.hpp>

#include <memory>
#include <string>
#include <vector>

namespace wf::sign {

/// Search parameters shared by all cascades of a detector.
struct CascadeParams {
    /// Scale step between pyramid levels (the reference app: 1.2).
    double scaleFactor = 1.2;
    /// Raw hits that must agree for a detection (also its score).
    int minNeighbors = 3;
    /// Smallest window, pixels (the reference app: 36 x 24); empty = each cascade's training window.
    cv::Size minWindow{};
    /// Largest window as a multiple of the smallest window; 0 = unlimited.
    double maxWindowFactor = 0;
    /// When set, only rows whose ray elevation is >= minElevationRad are searched (Detector computes the row).
    /// The C ABI turns it on by default from options version 3 (wf_sign_detector.h).
    bool searchAboveElevation = false;
    /// Lowest searched elevation, radians: -0.15 by default (signs hang above eye level; the margin covers a low
    /// sign or a pitch error of about 8 degrees).
    double minElevationRad = -0.15;
    /// How the box is sliced (a box gives the same height in every slice).
    SliceParams slices;
    /// Colour gate: search only around strongly red/green regions when the frame has colour (colour_gate.hpp).
    ColourGateParams colourGate;
    /// Plate gate: the wall kinds' cascades search only around plate-sized edge contours (plate_gate.hpp).
    PlateGateParams plateGate;
    /// Placement prior: at each scale, search only the rows a sign of that size can hang in (placement_prior.hpp).
    /// Needs the frame's geometry (CascadeDetector::detect's `geometry`); without it every row is searched.
    PlacementPrior placement;
};

/// Camera geometry of the frame being searched, for the placement prior.
struct FrameGeometry {
    /// Camera pitch, radians, positive looking up (ARKit Euler pitch).
    double pitchRad = 0;
    /// Intrinsics of the unrolled image, pixels.
    Intrinsics unrolled;
};

/// A list of (kind, cascade) pairs. Not thread-safe (OpenCV's classifier keeps scratch state).
class CascadeDetector {
public:
    /// Loads one cascade XML per kind. Returns false and sets `error` (naming the file) on failure.
    bool load(const std::vector<std::string>& paths, const std::vector<std::string>& kinds, std::string* error);

    /// Detects every kind on `grayUnrolled` (CV_8UC1), searching rows 0 .. lastRow - 1 only (-1 = all), and at
    /// each scale only the rows of params.placement's band when it is enabled and `geometry` is given (borrowed
    /// for the call). Detections carry box measurements in its pixels.
    /// `kindIndices` (borrowed; nullptr = every kind) limits the search to those cascades.
    std::vector<Detection> detect(const cv::Mat& grayUnrolled, const CascadeParams& params, int lastRow = -1,
                                  const FrameGeometry* geometry = nullptr,
                                  const std::vector<size_t>* kindIndices = nullptr);

    /// Detects every kind inside each of `regions` (rectangles of `grayUnrolled`, unrolled pixels; each is
    /// searched on its own with windows from the smallest window, or the region's minWindowWidthPx if larger, up to
    /// the region's size, or its maxWindowWidthPx if smaller) and maps the boxes
    /// back to `grayUnrolled`'s pixel coordinates (box + region origin, exact). Rows at or below `lastRow`
    /// (>= 0) are not searched; the placement band applies as in detect(). Boxes of overlapping regions are not
    /// merged here (suppressOverlaps does).
    /// `kindIndices` (borrowed; nullptr = every kind) limits the search to those cascades.
    /// `groupAcrossRegions`: the raw hits of all regions are grouped together (overlapping regions with their own
    /// window ranges: the plate gate's), a hit that repeats one of an earlier region (the same size, within half the
    /// scan's step) counted once; otherwise each region's hits are grouped on their own.
    std::vector<Detection> detectInRegions(const cv::Mat& grayUnrolled, const std::vector<SearchRegion>& regions,
                                           const CascadeParams& params, int lastRow = -1,
                                           const FrameGeometry* geometry = nullptr,
                                           const std::vector<size_t>* kindIndices = nullptr,
                                           bool groupAcrossRegions = false);

    /// First unrolled row below the search region: rows v with pitch + atan((cy - v) / fy) >= minElevationRad,
    /// clamped to [0, rows].
    static int searchRowLimit(double minElevationRad, double pitchRad, double fyPx, double cyPx, int rows);

    /// Kind names, in load order.
    const std::vector<std::string>& kinds() const { return kinds_; }

    /// Window size the cascade of kind `index` was trained with (e.g. 24 x 16).
    cv::Size trainedWindow(size_t index) const;

private:
    /// The search of cascade `index` on `image` (a view whose top-left is `origin` in unrolled pixels): the scales
    /// detectMultiScale would scan, each restricted to its placement band (when enabled and `geometry` is given),
    /// scanned in as few detectMultiScale calls as pays (one call per run of scales whose bands are alike); the raw
    /// hits, shifted by `origin`, are appended to `hits`. `minWindowWidthPx` > 0 raises the smallest window to at
    /// least that width, `maxWindowWidthPx` > 0 lowers the largest to at most that width (aspect kept).
    void scanOne(size_t index, const cv::Mat& image, cv::Point origin, const CascadeParams& params,
                 const FrameGeometry* geometry, std::vector<cv::Rect>* hits, int minWindowWidthPx = 0,
                 int maxWindowWidthPx = 0);
    /// Raw hits of cascade `index` grouped as detectMultiScale groups them (cv::groupRectangles, eps 0.2,
    /// params.minNeighbors), appended to `out` as detections with box measurements.
    void groupHits(size_t index, std::vector<cv::Rect> hits, const CascadeParams& params,
                   std::vector<Detection>* out) const;

    std::vector<std::string> kinds_;
    std::vector<std::unique_ptr<cv::CascadeClassifier>> cascades_;
};

}  // namespace wf::sign
