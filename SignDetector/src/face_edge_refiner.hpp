// Face-edge refiner: locates a sign face's top and bottom edges in the image itself, per vertical slice, to
// sub-pixel precision, starting from a rough measurement (a cascade box or a U-Net mask), and measures the slices
// as slice_measurement.hpp does. Used by both detectors (docs/sign-detection.md "Face-edge refinement").
//
// Physics: a sign face is a region of (nearly) uniform colour F on a background B. Optics (defocus, motion blur,
// the sensor's pixel footprint, resampling) convolve the scene with a point-spread function; for a straight step
// edge blurred by any PSF that is symmetric about the edge, the image's gradient peaks, and the image crosses the
// midpoint between B and F, exactly at the true edge. Per slice the refiner therefore follows the colour profile
// from the wall outside the rough edge inwards, takes the first significant, steep and persistent rise of the
// distance ||c(v) - B|| from the wall's colour B (the face's boundary: the outermost thing on it), and returns the
// sub-pixel position of that rise's gradient peak (or its half-way crossing, EdgeLocator). Only the few samples
// at the edge are used, so a slowly varying halo or bloom around a lit face, vignetting or a colour cast move it
// little; slices whose edges do not lie on straight lines (a face's edges are straight) are dropped. A rise that the
// wall beside the face shows too, at the same rows and with the same change of colour (a ceiling line, the top of a
// door frame, a wall's edge running behind the sign), belongs to the background: the search restarts behind it.
// Learned mask edges and cascade boxes depend on the training renders; this edge depends only on the image.
#pragma once

#include "slice_measurement.hpp"
#include "unroll.hpp"
#include "wf_sign_detector.h"

#include <opencv2/core.hpp>

namespace wf::sign {

/// How pixel values relate to light.
enum class PixelTransfer {
    /// Values are proportional to light (the renderer's output: it blurs and writes linear values).
    kLinear,
    /// Values are sRGB-encoded (IEC 61966-2-1), as phone cameras deliver them: decoded to linear light first,
    /// because blur mixes light, not code values (in code values the midpoint of a bright face's edge lies
    /// outside it).
    kSrgb,
};

/// Where on a rise the edge is put. Both are exact for a step edge blurred by a PSF symmetric about it.
enum class EdgeLocator {
    /// The gradient's peak: the vertex of the parabola through the steepest step and its two neighbours (uses
    /// the three steps at the edge only, so an additive halo or vignetting, smooth on that scale, moves it least).
    kGradientPeak,
    /// The half-way crossing between the rise's foot and top levels (linear interpolation between pixel centres).
    kHalfway,
};

/// Parameters of the refiner. Lengths relative to the rough measurement's height H (the rough top-to-bottom
/// distance of the slices), so that they hold at any resolution.
struct FaceEdgeParams {
    /// Off: the rough measurement is kept.
    bool enabled = true;
    /// Each edge is searched from this far outside the rough edge (fraction of H) to the rough centre line:
    /// cascade boxes are up to a third too tall or a tenth too short, U-Net mask edges a few percent off.
    double searchMarginFraction = 0.3;
    /// ... plus this many rows per column of offset from the rough centre column: the steepest slope dv/du a face's
    /// top or bottom edge has in the unrolled image (perspective of a horizontal edge seen up to ~0.35 rad above
    /// the camera and turned up to ~60 degrees: about 0.2). The rough measurement's own slopes are not used.
    double maxEdgeSlope = 0.2;
    /// The wall's colour B is the per-channel median of the outermost rows of the search (this fraction of H,
    /// at least 2 rows), smoothed over 3 columns; the noise level is the median distance from B there.
    double backgroundStripFraction = 0.12;
    /// A rise counts when its distance from B reaches the larger of these: levels (8-bit, in the transfer's
    /// light units) and multiples of the strip's noise level. Filters sensor noise and faint wall texture.
    double minRiseLevels = 12.0;
    double minRiseNoiseFactor = 4.0;
    /// ... and stays above half that level over most (60 %) of this fraction of H after it (a thin line on
    /// the wall, a tile joint, rises and falls again; the face persists).
    double persistenceFraction = 0.2;
    /// The foot and the top of a rise are followed at most this fraction of H (at least 2 rows) from the row
    /// where it reaches the threshold: the blur's half-width; stops earlier where the profile stops rising.
    double blurFraction = 0.12;
    /// A face's boundary ends where the face ends: a colour change that the wall beside the face shows at the same
    /// rows (a ceiling line, a wall's edge, a door frame running behind the sign) belongs to the background, not to
    /// the face. The wall beside the face is sampled in columns this far outside the rough extent (fraction of H,
    /// plus one pixel: past a halo and a box's slack) ...
    double sideGapFraction = 0.2;
    /// ... over this many columns (fraction of H, at least 2), per row the per-channel median of each side.
    double sideWidthFraction = 0.2;
    /// A rise is taken for the background's and the search restarts behind it (the wall's colour re-taken just
    /// inside it) when a side shows the same change of colour across the same rows: the difference of the two
    /// colour changes is below this fraction of the slice's change. 0 turns the check off.
    double sideSameChangeFraction = 0.5;
    /// A face's edges are straight lines: slices whose top or bottom edge lies farther than the larger of these
    /// (pixels; fraction of H) from robust lines through all slices' edges are dropped (they caught a letter, the
    /// halo or the wall).
    double straightnessMinPx = 0.75;
    double straightnessFraction = 0.04;
    /// At least this fraction of the slices (and 3) must give both edges on those lines with a height within
    /// [minHeightRatio, maxHeightRatio] x H; otherwise the rough measurement is kept.
    double minValidFraction = 0.4;
    double minHeightRatio = 0.55;
    double maxHeightRatio = 1.45;
    /// Where the edge is put on its rise (see EdgeLocator). On the rendered test set the gradient peak gave the
    /// U-Net path 2.6-5.4 % median range error per distance against 2.6-7.0 % for the half-way crossing.
    EdgeLocator locator = EdgeLocator::kGradientPeak;
    /// Pixel transfer of the image (see PixelTransfer).
    PixelTransfer transfer = PixelTransfer::kLinear;
};

/// Parameters for a U-Net mask. The mask's edges are much closer to the face's than a cascade box's (on the
/// rendered test set 80 % of masks were within -8..+10 % of the face's height, i.e. a few percent per edge; on
/// real photos the mask read ~6 % short), so the search stays within 0.15 H of them (off the wall structure and
/// housings farther out), and a refined height outside 0.75-1.3 x the mask's is taken for a wrong edge (the mask
/// is kept). A box needs FaceEdgeParams' defaults (0.3 H; 0.55-1.45).
FaceEdgeParams maskFaceEdgeParams(FaceEdgeParams base = {});

/// Outcome of a refinement.
struct FaceEdgeResult {
    /// True when the edges were found and `measurement` holds them; false = `measurement` is the rough one.
    bool refined = false;
    /// Slices that gave both edges, of those searched.
    int validSlices = 0, searchedSlices = 0;
    /// The measurement, in the rough measurement's pixel frame: median height and bottom edge and the edge
    /// slopes from the found edges; centre column, extent and box from the rough measurement.
    SliceMeasurement measurement;
};

/// Refines `rough` (a valid slice measurement in the pixel frame of `image`) from `image` (CV_8UC1 or CV_8UC3,
/// any channel order: only colour distances are used). Slices are the columns sliceColumns() takes across the
/// rough extent with `slices`; each slice is searched around the rough medians (widened by maxEdgeSlope times
/// the column's offset from the centre column). Pixel-centre convention; edges are returned as edge coordinates (as
/// measureMask's: the top edge of a face whose first row is r is r - 0.5). Never throws for a valid image; rows
/// outside the image shorten the search.
FaceEdgeResult refineFaceEdges(const cv::Mat& image, const SliceMeasurement& rough, const SliceParams& slices,
                               const FaceEdgeParams& params);

/// The rows and columns of unrolled pixels that refineFaceEdges reads for `rough` (unrolled pixels): the rough
/// extent plus one column each side and the side samples' columns (sideGapFraction, sideWidthFraction), the rough
/// edges plus the search margin and one row; integer pixel rect.
cv::Rect faceEdgeSearchRect(const SliceMeasurement& rough, const FaceEdgeParams& params);

/// Refines a measurement in unrolled pixels from the raw frame: samples the unrolled pixels of
/// faceEdgeSearchRect (clipped to the unrolled image) from `image` through `unrolling` (bilinear; exact for
/// quarter turns), converting only the raw pixels that patch needs to RGB (any wf_pixel_format; GRAY8 and NV12
/// without chroma give gray), and refines there. `image` must have passed checkFrame.
FaceEdgeResult refineFaceEdgesInFrame(const wf_image& image, const Unrolling& unrolling, const SliceMeasurement& rough,
                                      const SliceParams& slices, const FaceEdgeParams& params);

}  // namespace wf::sign
