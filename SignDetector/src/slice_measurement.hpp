// Slice measurement of a detected sign (Fusco et al. 2020, section 3): vertical slices across the sign
// give a median apparent height and a median bottom edge, robust to ragged, noisy segmentations.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace wf::sign {

/// How slices are taken.
struct SliceParams {
    /// 0 = every column of the band; N > 0 = N evenly spaced columns across it.
    int sliceCount = 0;
    /// Fraction of the sign's horizontal extent, centred, that is sampled (0.6 = middle 60 %).
    double bandFraction = 0.6;
};

/// Result of measuring one sign, in the pixel frame of the box or mask it came from (pixel-centre
/// convention: pixel (i, j) covers [i-0.5, i+0.5] x [j-0.5, j+0.5]).
struct SliceMeasurement {
    /// False when no slice hit the sign (empty mask).
    bool valid = false;
    /// Median over slices of the bottom edge of the sign (last sign row + 0.5), pixels.
    double medianBottomEdgePx = 0;
    /// Median over slices of the height (bottom edge - top edge = rows covered), pixels.
    double medianHeightPx = 0;
    /// Centre of the sign's horizontal extent, pixels.
    double centerColumnPx = 0;
    /// Width of the extent: last sign column - first sign column, pixels.
    double extentWidthPx = 0;
    /// Slopes dv/du of the bottom and top edges: medians of the slopes between slice i and slice
    /// i + n/2 (0 for a box or a single slice). Scale-invariant.
    double bottomEdgeSlope = 0;
    double topEdgeSlope = 0;
    /// Bounding box (edges): x, y = left/top edge, width, height.
    cv::Rect2d box;
    /// Number of slices the medians were taken over.
    int sliceCount = 0;

    /// The same measurement expressed in another pixel frame in which this frame's pixel grid is scaled
    /// by `scale` (target pixels per source pixel) and whose top-left pixel edge (-0.5, -0.5) lands at
    /// `originEdge` (target coordinates). Used to map crop/letterbox masks back to the unrolled image.
    SliceMeasurement mapped(double scale, cv::Point2d originEdge) const;
};

/// Measures an axis-aligned integer box covering columns box.x .. box.x+width-1 and rows box.y ..
/// box.y+height-1: every slice has the box's height and bottom edge.
SliceMeasurement measureBox(const cv::Rect& box, const SliceParams& params = {});

/// Measures a binary mask (CV_8UC1, non-zero = sign). The caller passes one sign (e.g. one connected
/// component). Per slice (column): top = first sign row, bottom = last sign row; columns without sign
/// pixels are skipped. Medians over slices; the even-count median is the mean of the two middle values.
SliceMeasurement measureMask(const cv::Mat& mask, const SliceParams& params = {});

/// The columns slices sample across a sign whose extent covers pixel columns first .. last (inclusive): the
/// centred band of params.bandFraction of the extent, every column or params.sliceCount evenly spaced ones.
std::vector<int> sliceColumns(int first, int last, const SliceParams& params);

/// One slice with sub-pixel edges (edge coordinates, pixels: top < bottom).
struct SliceEdges {
    double column = 0, topEdgePx = 0, bottomEdgePx = 0;
};

/// Measures slices given as edges (e.g. the face-edge refiner's): medians of the heights and bottom edges, and
/// edge slopes as measureMask takes them (slices in column order; the slope between slice i and i + n/2). Centre
/// column, extent and box are left as in `base` (valid and sliceCount are set). Invalid when `edges` is empty.
SliceMeasurement measureSliceEdges(const std::vector<SliceEdges>& edges, const SliceMeasurement& base);

}  // namespace wf::sign
