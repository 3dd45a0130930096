// Colour gate for the cascade (detector A): Exit signs have saturated red or green lettering (lit signs
// glow), so the cascade only needs to search where the frame has a strong local red-green contrast.
//
// Method (ours; a cheap colour pre-filter in front of a Viola-Jones cascade, the same idea as the colour
// candidate stage of classic traffic-sign detectors): at a low working resolution (long side about 320 px),
// the red-green opponent difference d = R - G (Lab a*-like axis: red letters d > 0, green or teal letters
// d < 0; blue, grey and white surfaces d ~ 0) minus its local mean over a k x k box, so a global colour cast
// (white balance, tinted walls) cancels; pixels with |d - mean_k(d)| >= threshold form the mask, which is
// dilated (merges the letters of one sign) and split into 8-connected components (large ones cut into tiles).
// Each blob is mapped
// to the unrolled image, expanded by a margin large enough to hold the whole sign face, and overlapping
// regions are merged. The cascade then runs on those regions only (CascadeDetector::detectInRegions).
//
// Degrades to the full search when the frame has no colour (GRAY8, NV12 without chroma, or an RGB frame
// whose R - G is ~0 everywhere) or when the regions would cover most of the searched image.
#pragma once

#include "unroll.hpp"
#include "wf_sign_detector.h"

#include <opencv2/core.hpp>

#include <vector>

namespace wf::sign {

/// Parameters of the colour gate. Sizes are in working-resolution pixels unless the name says otherwise.
struct ColourGateParams {
    /// When false, the cascade always searches the whole frame.
    bool enabled = true;
    /// Long side of the working resolution, pixels; the raw frame is shrunk by the integer factor
    /// max(1, round(long side / this)) with INTER_AREA (VGA and 1920 x 1440 -> 320 x 240). Rounded, not
    /// floored: a 639-pixel-wide frame must not be gated at full resolution (4 times the pixels, other tiles).
    int workingLongSidePx = 320;
    /// Side of the box over which the local mean of R - G is taken, working pixels (odd).
    int localWindowPx = 31;
    /// Minimum |(R - G) - local mean|, 8-bit levels, for a mask pixel. On the rendered test set the weakest
    /// sign reached 38 (loc. window 31), sign-free frames had a median of 0.2 % of their pixels above 25.
    double minContrast = 25.0;
    /// Frames whose max |R - G| at working resolution is below this (8-bit levels) have no usable colour.
    double minColourfulness = 8.0;
    /// Components larger than this (either side, working pixels) are cut into cells of this side, each cell's
    /// part a blob of its own (long lines and outlines of coloured walls would otherwise cover the frame).
    int tileSidePx = 16;
    /// Margin added on each side of a blob, as a multiple of its larger side in unrolled pixels (the letters
    /// cover about 2/3 of the face's width and 3/4 of its height; the cascade's box is 1.1 x the face) ...
    double marginFactor = 0.5;
    /// ... but at least this many unrolled pixels (2/3 of the cascade's training window width; 24 before options
    /// version 5: the same recall over shifted scan grids, docs/benchmarks.md "options version 5").
    int minMarginPx = 16;
    /// Tiles of a component no larger than this (either side, unrolled pixels: a sign's lettering at about 1.3 m at
    /// VGA) keep at least nearSignMarginPx: such a component may be a near sign, whose face reaches beyond its
    /// lettering by more than minMarginPx (at 16 px, 13 of 160 signs at 2 m were missed over four shifted scan
    /// grids against 4 of 160 with 24 px; docs/benchmarks.md "options version 5").
    int nearSignComponentMaxPx = 96;
    int nearSignMarginPx = 24;
    /// Smallest searched window width as a fraction of a compact blob's width (unrolled pixels); 0 = off.
    double minWindowBlobFraction = 0.6;
    /// Smallest searched window width in a tile's region as a fraction of its whole component's width (unrolled
    /// pixels); 0 = off (every window size, as before options version 5). A sign's letters that form a large
    /// component give a window at least about this wide; a small sign merged into a large coloured component
    /// (a stripe, a poster's edge) is the case this gives up (docs/sign-detection.md "colour gate").
    double componentWindowFraction = 0.4;
    /// Full search when the merged regions cover more than this fraction of the searched image (the
    /// regions' own calls would then cost about as much as one call on the whole image).
    double maxAreaFraction = 0.8;
    /// Full search when there are more regions than this after merging.
    int maxRegions = 64;
    /// Crowded frames: when the regions cover more than crowdedAreaFraction of the searched image (or the gate
    /// would fall back to the full search), gateFrame re-thresholds once at crowdedContrastFactor x minContrast.
    /// On the rendered test set (VGA) all signs peaked above 38 levels, 95 % above 64, and in crowded frames 20 of
    /// 21 above 95; with factor 2.5 and fraction 0.15 the mean cascade time fell 15.0 -> 7.4 ms and recall rose
    /// 0.959 -> 0.963 (docs/benchmarks.md, "Cascade search, options version 4").
    /// A factor <= 1 turns this off (the C ABI's default for option structs before version 4).
    double crowdedAreaFraction = 0.15;
    double crowdedContrastFactor = 2.5;
};

/// The local red-green contrast |d - mean_k(d)| of a frame at working resolution (see the file comment).
struct ColourContrast {
    /// CV_32FC1 at working resolution; empty when the frame carries no usable colour.
    cv::Mat contrast;
    /// Raw pixels per working pixel in x and y.
    cv::Point2d rawPerWorkingPx{1, 1};
};

/// Components of the colour mask in raw pixel coordinates (pixel-centre convention: edges at i - 0.5).
struct ColourBlobs {
    /// False when the frame carries no colour (GRAY8, NV12 without chroma, or max |R - G| below
    /// minColourfulness): the caller must search the whole frame.
    bool colourAvailable = false;
    /// Bounding boxes of the mask components in raw pixels (edges), in no particular order.
    std::vector<cv::Rect2d> rawBoxes;
    /// Per box: true when it is a whole (compact) component, false for a tile of a large one.
    std::vector<bool> wholeComponent;
    /// Per box: the bounding box of its whole component in raw pixels (edges); the box itself for a whole one.
    std::vector<cv::Rect2d> componentRawBoxes;
};

/// One region for the cascade: a rectangle of the unrolled image, unrolled pixels (integer pixel indices:
/// columns x .. x + width - 1).
struct SearchRegion {
    cv::Rect unrolledRect;
    /// Smallest window width worth searching in this region, unrolled pixels (0 = the cascade's own): a
    /// compact blob is (part of) a sign's lettering, so the sign's box is at least about as wide as the
    /// blob (ColourGateParams::minWindowBlobFraction of it); tiles of large components give
    /// ColourGateParams::componentWindowFraction of the whole component's width (0 when that is off).
    int minWindowWidthPx = 0;
    /// Largest window width worth searching in this region, unrolled pixels (0 = as large as the region): the plate
    /// gate's regions hold a plate about the size of the edge contour they come from (plate_gate.hpp).
    int maxWindowWidthPx = 0;
};

/// Result of gating one frame for the cascade.
struct GateDecision {
    /// True: search the whole (row-limited) unrolled image; `regions` is then empty.
    bool fullSearch = true;
    /// Regions to search when fullSearch is false (may be empty: nothing red or green, nothing to search).
    std::vector<SearchRegion> regions;
    /// Contrast threshold the regions come from, 8-bit levels (gateFrame; 0 when not set).
    double minContrast = 0;
    /// Summed area of the merged regions over the searched image's area (gateRegions; 0 when it did not get as far
    /// as merging: gate off, no colour, nothing searched). Overlaps count twice, so it may exceed 1.
    double coveredFraction = 0;
};

/// The red-green opponent image d = R - G of `image` at working resolution, CV_32FC1; empty when the format
/// carries no colour. RGB8 / BGRA8 are shrunk with INTER_AREA then differenced; NV12 uses its CbCr plane
/// (full-range BT.601: R - G = 0.344136 Cb' + 2.116136 Cr', luma cancels). `rawPerWorkingPx` receives the raw
/// pixels per working pixel in x and y.
cv::Mat redGreenOpponent(const wf_image& image, const ColourGateParams& params, cv::Point2d* rawPerWorkingPx);

/// The local contrast image of a frame (empty contrast when the frame has no usable colour).
ColourContrast localColourContrast(const wf_image& image, const ColourGateParams& params);

/// Components of the mask contrast >= minContrast (dilated, large ones tiled; see the file comment).
ColourBlobs colourBlobsAbove(const ColourContrast& colour, double minContrast, const ColourGateParams& params);

/// Mask components of a frame at params.minContrast (see the file comment). Never throws for a valid wf_image.
ColourBlobs findColourBlobs(const wf_image& image, const ColourGateParams& params);

/// Maps raw-pixel blobs into the unrolled image, expands each by its margin, clips to columns
/// [0, unrolledSize.width) and rows [0, lastRow), merges overlapping regions, and decides between the
/// regions and the full search. `lastRow` < 0 means all rows.
GateDecision gateRegions(const ColourBlobs& blobs, const Unrolling& unrolling, int lastRow,
                         const ColourGateParams& params);

/// The whole gate for one frame: blobs at minContrast, their regions, and for a crowded frame the regions at the
/// raised threshold (ColourGateParams::crowdedContrastFactor). Full search when disabled or without colour.
GateDecision gateFrame(const wf_image& image, const Unrolling& unrolling, int lastRow, const ColourGateParams& params);

}  // namespace wf::sign
