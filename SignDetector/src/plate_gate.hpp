// Plate gate for the cascades of the wall kinds (pictogram plates, room-number placards): the colour gate's
// counterpart for signs that are not red or green.
//
// What it relies on (physics and the standard, not one renderer): a tactile sign is a flat plate whose legend
// contrasts strongly with its background (ADA 2010 Standards 703.5.3: characters and their background light on
// dark or dark on light; 70 % contrast is the usual specification), and whose plate usually contrasts with the
// wall. So on the gray frame either the plate's outline or its legend's outline is a closed contour of strong
// edges about as large as the plate. Proposals (ours; the same idea as the edge-based candidate stage of classic
// sign and text detectors):
//   1. Canny edges (OpenCV, thresholds 40 / 100 levels), closed by a 3 x 3 square (bridges a one-pixel gap in
//      a plate's outline), their contours' bounding boxes;
//   2. the 3 x 3 morphological gradient (dilate - erode) at or above 30 levels, closed likewise, its 8-connected
//      components' bounding boxes, from their outer contours (catches an outline that Canny's non-maximum
//      suppression breaks at a corner);
//   3. boxes kept when their sides lie within the caller's size range and their aspect within 0.4-2.5.
// Each kept box becomes a search region for the cascades: the box widened by a margin that holds a window
// about 1.9 x the box (a box may be the legend only, about 0.6 of the plate), searched with windows 0.7-1.9 x
// the box's larger side. Near-duplicate boxes become one; other overlapping regions stay apart, each searched with
// its own narrow range of windows, and their raw hits are grouped together (CascadeDetector::detectInRegions with
// groupAcrossRegions). With more regions than maxRegions the caller searches the whole placement bands as before.
//
// Hand-written: the glue (which boxes, the margins). The edge detection, morphology, contours and components are
// OpenCV's.
#pragma once

#include "colour_gate.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace wf::sign {

/// Parameters of the plate gate. Sizes are pixels of the searched (gray, unrolled) image.
struct PlateGateParams {
    /// When false, the wall kinds' cascades search their whole placement bands (the behaviour before).
    bool enabled = true;
    /// The candidates are found on the image shrunk by this integer factor (INTER_AREA; 1 = as it is): at VGA the
    /// smallest plate searched is about 20 px, 10 px at half size.
    int shrinkFactor = 2;
    /// Canny's hysteresis thresholds, 8-bit levels (L2 gradient off, 3 x 3 Sobel).
    double cannyLowLevels = 40;
    double cannyHighLevels = 100;
    /// Smallest 3 x 3 morphological gradient (max - min) of a mask pixel, 8-bit levels.
    double gradientMinLevels = 30;
    /// Side of the square closing applied to both edge masks, pixels (0 or 1 = none).
    int closePx = 3;
    /// Kept boxes: width / height within [minAspect, maxAspect].
    double minAspect = 0.4;
    double maxAspect = 2.5;
    /// Margin added on each side of a kept box, as a multiple of its larger side, and at least minMarginPx.
    double marginFactor = 0.45;
    int minMarginPx = 6;
    /// Smallest window width searched in a box's region, as a fraction of the box's larger side.
    double minWindowFraction = 0.7;
    /// Largest window width searched in a box's region, as a fraction of the box's larger side (a legend is about
    /// 0.6 of its plate, and the window about 1.1 x the plate).
    double maxWindowFraction = 1.9;
    /// Candidates overlapping by at least this intersection over union are one (their union).
    double duplicateOverlap = 0.9;
    /// Whole-placement-band search when there are more regions than this (a frame full of edges: tiles, text,
    /// clutter; on the rendered test_kinds set at most 95, 99 % of frames at most 75).
    int maxRegions = 128;
};

/// Bounding boxes of plate candidates in `gray` (CV_8UC1) within rows [rowFirst, rowLast), in `gray`'s pixels,
/// with both sides in [minSidePx, maxSidePx] and the aspect within the params' range (steps 1-3 of the file
/// comment). May hold near-duplicates (the same plate from both masks).
std::vector<cv::Rect> plateCandidates(const cv::Mat& gray, int rowFirst, int rowLast, int minSidePx, int maxSidePx,
                                      const PlateGateParams& params);

/// Search regions for the wall kinds' cascades around `plateCandidates` (margins, window range, near-duplicates
/// merged), or a full search (GateDecision::fullSearch) when the gate is off or there are more than maxRegions.
/// `searched` is the part of the image the cascades may read (regions are clipped to it).
GateDecision plateRegions(const std::vector<cv::Rect>& candidates, const cv::Rect& searched,
                          const PlateGateParams& params);

}  // namespace wf::sign
