// Tests of src/placement_prior: the row band holds every sign the prior allows (exact pinhole projections over
// pitch, distance, height and bearing), excludes signs hung far outside it, and follows the camera pitch.
#include "placement_prior.hpp"
#include "synthetic_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace wf::sign;

namespace {

/// Landscape VGA camera (roll 0: the unrolled image is the raw image) pitched up by `pitchRad`.
synthetic::Camera levelVga(double pitchRad) {
    synthetic::Camera cam;
    cam.rollRad = 0;
    cam = cam.resized({640, 480});
    cam.pitchRad = pitchRad;
    return cam;
}

/// The cascade's window on a 0.30 x 0.21 m face whose centre is `aboveMeters` above the camera, `aheadMeters`
/// ahead (horizontal, along the camera's forward direction) and `leftMeters` to the left: width 1.1 x max(face
/// width, 1.5 x face height) in pixels, height 2/3 of that, centred on the projected face centre.
cv::Rect2d windowOnSign(const synthetic::Camera& cam, double aboveMeters, double aheadMeters, double leftMeters) {
    cv::Point2d corner[4];
    const double hw = 0.15, hh = 0.105;
    const cv::Vec3d c(-leftMeters, aboveMeters, -aheadMeters);
    const cv::Vec3d offsets[4] = {{-hw, hh, 0}, {hw, hh, 0}, {hw, -hh, 0}, {-hw, -hh, 0}};
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(synthetic::projectToRaw(cam, c + offsets[i], &corner[i]));
    const double faceW = 0.5 * (corner[1].x - corner[0].x + corner[2].x - corner[3].x);
    const double faceH = 0.5 * (corner[3].y - corner[0].y + corner[2].y - corner[1].y);
    const double w = 1.1 * std::max(faceW, 1.5 * faceH), h = w * 16.0 / 24.0;
    const cv::Point2d centre = 0.25 * (corner[0] + corner[1] + corner[2] + corner[3]);
    return {centre.x - 0.5 * w, centre.y - 0.5 * h, w, h};
}

Intrinsics intrinsicsOf(const synthetic::Camera& cam) { return Intrinsics{cam.fx, cam.fy, cam.cx, cam.cy}; }

}  // namespace

TEST(PlacementPrior, BandHoldsEverySignThePriorAllows) {
    PlacementPrior prior;
    prior.enabled = true;
    int checked = 0;
    for (double pitch : {-0.3, -0.1, 0.0, 0.15, 0.35}) {
        const synthetic::Camera cam = levelVga(pitch);
        for (double above : {0.3, 0.8, 1.4, 2.0}) {
            for (double ahead : {1.5, 2.5, 4.0, 7.0, 10.0}) {
                for (double left : {0.0, 1.0}) {
                    const cv::Rect2d win = windowOnSign(cam, above, ahead, left);
                    if (win.y < 0 || win.y + win.height > 480) continue;  // out of frame at this pitch
                    const auto band = placementRowBand(prior, win.width, win.height, pitch, intrinsicsOf(cam));
                    EXPECT_LE(band.first, win.y) << "pitch " << pitch << " above " << above << " ahead " << ahead;
                    EXPECT_GE(band.second, win.y + win.height) << "pitch " << pitch << " above " << above << " ahead " << ahead;
                    ++checked;
                }
            }
        }
    }
    EXPECT_GT(checked, 100);
}

TEST(PlacementPrior, SignsFarOutsideThePriorFallOutsideTheBand) {
    PlacementPrior prior;
    prior.enabled = true;
    const synthetic::Camera cam = levelVga(0.05);
    for (double ahead : {3.0, 6.0, 9.0}) {
        // A sign 4 m above the camera (on a high ceiling) and one 1 m below it (a floor-level plate).
        for (double above : {4.0, -1.0}) {
            const cv::Rect2d win = windowOnSign(cam, above, ahead, 0.0);
            if (win.y < 0 || win.y + win.height > 480) continue;
            const auto band = placementRowBand(prior, win.width, win.height, cam.pitchRad, intrinsicsOf(cam));
            const bool overlaps = win.y + win.height > band.first && win.y < band.second;
            EXPECT_FALSE(overlaps) << "above " << above << " ahead " << ahead << ": band " << band.first << ".."
                                   << band.second << ", window " << win.y << ".." << win.y + win.height;
        }
    }
}

TEST(PlacementPrior, BandIsNarrowForSmallWindowsAndFollowsThePitch) {
    PlacementPrior prior;
    prior.enabled = true;
    const Intrinsics k{534, 534, 319.5, 239.5};
    const auto small = placementRowBand(prior, 24, 16, 0.0, k);
    const auto large = placementRowBand(prior, 96, 64, 0.0, k);
    // A 24-px window is a sign 6.7 .. 10.7 m away, seen 0.03 .. 0.29 rad up (+-0.05 margin): fy (tan 0.34 +
    // tan 0.02) + 16 = 218 rows, under half of the 480; a 96-px window is a near sign: a taller band.
    EXPECT_NEAR(small.second - small.first, 218, 4);
    EXPECT_GT(large.second - large.first, small.second - small.first);
    // Both lie mostly above the principal row (signs hang above the camera).
    EXPECT_LT(0.5 * (small.first + small.second), 239.5);
    // Looking up by 0.2 rad moves the band down by about fy tan(0.2).
    const auto up = placementRowBand(prior, 24, 16, 0.2, k);
    EXPECT_NEAR(up.first - small.first, 534 * std::tan(0.2), 15);
    // Extreme inputs stay finite and ordered.
    const auto steep = placementRowBand(prior, 600, 400, 1.4, k);
    EXPECT_LE(steep.first, steep.second);
    EXPECT_GE(steep.first, -1000000);
    EXPECT_LE(steep.second, 1000001);
}
