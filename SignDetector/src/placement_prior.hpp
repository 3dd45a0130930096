// Placement prior for the cascade search: an Exit sign hangs at a known height above the floor and has a known
// size, so a search window of a given size (which fixes the sign's depth) can only appear in a band of rows of
// the unrolled image. Scanning only that band cuts the windows at the small scales, where most of them are.
//
// Model (pinhole, roll removed, camera pitched up by p; ours, from the same geometry as the paper's range
// equation, Fusco et al. 2020 eq. 3): a sign centre dh metres above the camera and d metres ahead (horizontal)
// has camera depth z = d cos p + dh sin p and appears at ray elevation e = atan(dh / d), so
//     tan e = dh cos p / (z - dh sin p),
// and a window W metres wide covering it is w = fx' W / z pixels wide. With dh in [dh_min, dh_max] and W in
// [W_min, W_max] the window's centre row lies between the rows of
//     e_high = atan2(dh_max cos p, fx' W_min / w - dh_max sin p) + margin  and
//     e_low  = atan2(dh_min cos p, fx' W_max / w - dh_min sin p) - margin
// (tan e grows with dh and falls with z). The sign's horizontal bearing does not enter: the camera's pitch is a
// rotation about its x axis only.
#pragma once

#include "unroll.hpp"

#include <utility>

namespace wf::sign {

/// Where signs of one kind hang, relative to the camera, and how large the cascade's window is on them.
struct PlacementPrior {
    /// When false, every row is searched at every scale.
    bool enabled = false;
    /// Height of the sign's centre above the camera, metres. Defaults: Exit signs' bottom edges are at least
    /// 2.03 m (80 in) above the floor and usually at most about 2.6 m, centres 0.1 m higher; a phone on a lanyard
    /// or in the hand is 1.0 (wheelchair user) to 1.7 m above the floor: 0.3 .. 2.0 m with a margin.
    double centreAboveCameraMinMeters = 0.3;
    double centreAboveCameraMaxMeters = 2.0;
    /// Width of the scene the cascade's window covers on a sign, metres: the window is trained at 1.1 x
    /// max(face width, 1.5 x face height) (0.33 m for a 0.30 x 0.19 m US face, 0.44 m for a 0.40 x 0.20 m ISO
    /// face), and the detected scale can be one pyramid step (1.2 x) off: 0.30 .. 0.48 m.
    double windowWidthMinMeters = 0.30;
    double windowWidthMaxMeters = 0.48;
    /// Added above and below the band, radians: pitch error, a residual roll, a tilted sign.
    double elevationMarginRad = 0.05;
};

/// Rows [first, second) of the unrolled image (intrinsics `unrolled`, camera pitched up by `pitchRad`) that a
/// window `windowWidthPx` x `windowHeightPx` (unrolled pixels) covering a sign placed as `prior` says can touch
/// (the centre band widened by half the window height each way). Not clipped to the image: first may be < 0,
/// second may be past the last row; both stay within +-1e6. Requires finite inputs and positive sizes.
std::pair<int, int> placementRowBand(const PlacementPrior& prior, double windowWidthPx, double windowHeightPx,
                                     double pitchRad, const Intrinsics& unrolled);

}  // namespace wf::sign
