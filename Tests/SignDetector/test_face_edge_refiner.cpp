// Tests of src/face_edge_refiner: sub-pixel edges of a synthetic face (area-sampled, blurred, noisy, with letters
// and a halo), a too-tall and a too-short box fixed, wall texture and a ceiling line beside the face ignored,
// fallbacks, and the in-frame sampling through the unrolling (quarter turn and a tilted roll).
#include "face_edge_refiner.hpp"

#include "image_input.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

using namespace wf::sign;

namespace {

/// A face of colour `face` covering x in [left, right] and y in [top, bottom] (edge coordinates, pixel-centre
/// convention: pixel (i, j) covers [i - 0.5, i + 0.5] x [j - 0.5, j + 0.5]) on a wall of colour `wall`, area-sampled
/// (each pixel gets its exact covered fraction), then red letters (a bar) inside the face at 30-70 % of its height,
/// a Gaussian blur of `blurSigmaPx` and seeded noise of `noiseLevels` (8-bit levels, standard deviation).
cv::Mat syntheticFace(cv::Size size, double left, double right, double top, double bottom, cv::Vec3d wall, cv::Vec3d face,
                      double blurSigmaPx, double noiseLevels, uint32_t seed) {
    cv::Mat img(size, CV_32FC3);
    auto overlap = [](double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); };
    const double letterTop = top + 0.3 * (bottom - top), letterBottom = top + 0.7 * (bottom - top);
    const cv::Vec3d letter(200, 30, 30);
    for (int y = 0; y < size.height; ++y) {
        for (int x = 0; x < size.width; ++x) {
            const double fx = overlap(x - 0.5, x + 0.5, left, right);
            const double fFace = fx * overlap(y - 0.5, y + 0.5, top, bottom);
            const double fLetter = overlap(x - 0.5, x + 0.5, left + 4, right - 4) * overlap(y - 0.5, y + 0.5, letterTop, letterBottom);
            const cv::Vec3d c = wall * (1 - fFace) + face * (fFace - fLetter) + letter * fLetter;
            img.at<cv::Vec3f>(y, x) = cv::Vec3f(float(c[0]), float(c[1]), float(c[2]));
        }
    }
    if (blurSigmaPx > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), blurSigmaPx);
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, float(noiseLevels));
    for (int y = 0; y < size.height; ++y) {
        for (int x = 0; x < size.width; ++x) {
            cv::Vec3f& p = img.at<cv::Vec3f>(y, x);
            for (int c = 0; c < 3; ++c) p[c] += noise(rng);
        }
    }
    cv::Mat out;
    img.convertTo(out, CV_8UC3);
    return out;
}

/// A box measurement (measureBox) of integer columns/rows.
SliceMeasurement roughBox(int x, int y, int w, int h) { return measureBox(cv::Rect(x, y, w, h)); }

}  // namespace

TEST(FaceEdgeRefiner, FindsKnownEdgesOfABlurredNoisyFaceToSubPixelAccuracy) {
    // Face edges at 40.3 and 71.8 (height 31.5 px), white plate on a mid-gray wall, blur sigma 1.2 px, noise 2 levels;
    // the rough box is the face's box rounded outwards by 2 px.
    const double top = 40.3, bottom = 71.8;
    const cv::Mat img = syntheticFace({160, 120}, 30.5, 130.5, top, bottom, {110, 110, 110}, {235, 235, 230}, 1.2, 2.0, 7);
    const SliceMeasurement rough = roughBox(31, 38, 100, 36);
    const FaceEdgeResult r = refineFaceEdges(img, rough, SliceParams{}, FaceEdgeParams{});
    ASSERT_TRUE(r.refined);
    EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.15);
    EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.25);
    EXPECT_NEAR(r.measurement.bottomEdgeSlope, 0.0, 0.01);
    EXPECT_EQ(r.validSlices, r.searchedSlices);
    // Centre and extent stay the box's.
    EXPECT_DOUBLE_EQ(r.measurement.centerColumnPx, rough.centerColumnPx);
}

TEST(FaceEdgeRefiner, FixesATooTallAndATooShortBox) {
    // A far sign at VGA: 14.6 px tall, blur sigma 0.8 px. A cascade box 30 % too tall reads the range 23 % short;
    // one 15 % too short reads it 18 % long. Both refine to the face within 0.3 px (2 %).
    const double top = 20.4, bottom = 35.0;
    const cv::Mat img = syntheticFace({80, 60}, 20.5, 42.5, top, bottom, {90, 100, 95}, {225, 220, 220}, 0.8, 1.5, 11);
    for (const SliceMeasurement& rough : {roughBox(20, 18, 24, 19), roughBox(21, 22, 22, 12)}) {
        const FaceEdgeResult r = refineFaceEdges(img, rough, SliceParams{}, FaceEdgeParams{});
        ASSERT_TRUE(r.refined) << rough.medianHeightPx;
        EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.3) << rough.medianHeightPx;
        EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.2) << rough.medianHeightPx;
    }
}

TEST(FaceEdgeRefiner, DarkFaceOnALightWallAndGrayImages) {
    // The distance from the wall's colour works for a face darker than the wall, and on one channel.
    const double top = 30.7, bottom = 55.2;
    const cv::Mat img = syntheticFace({120, 90}, 20.5, 90.5, top, bottom, {200, 205, 210}, {35, 30, 30}, 1.0, 2.0, 3);
    cv::Mat gray;
    cv::cvtColor(img, gray, cv::COLOR_RGB2GRAY);
    for (const cv::Mat& image : {img, gray}) {
        const FaceEdgeResult r = refineFaceEdges(image, roughBox(21, 27, 70, 32), SliceParams{}, FaceEdgeParams{});
        ASSERT_TRUE(r.refined) << image.channels();
        EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.3) << image.channels();
        EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.2) << image.channels();
    }
}

TEST(FaceEdgeRefiner, IgnoresAThinLineOnTheWallAndAHalo) {
    // A 1-px dark tile joint 3 px above the face (persistence rejects it) and a broad additive halo around the
    // face (levels taken at the foot and top of the rise cancel it).
    const double top = 40.5, bottom = 70.0;
    cv::Mat img = syntheticFace({160, 120}, 30.5, 130.5, top, bottom, {120, 120, 120}, {240, 240, 240}, 1.0, 1.0, 5);
    cv::line(img, {0, 37}, {159, 37}, cv::Scalar(70, 70, 70), 1);
    cv::Mat halo = cv::Mat::zeros(img.size(), CV_8UC3);
    cv::rectangle(halo, cv::Point(31, 41), cv::Point(130, 69), cv::Scalar(40, 40, 40), cv::FILLED);
    cv::GaussianBlur(halo, halo, cv::Size(0, 0), 6.0);
    img += halo;
    const FaceEdgeResult r = refineFaceEdges(img, roughBox(31, 33, 100, 42), SliceParams{}, FaceEdgeParams{});
    ASSERT_TRUE(r.refined);
    EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.5);
    EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.4);
}

TEST(FaceEdgeRefiner, SkipsABackgroundLineThatRunsOnBesideTheFace) {
    // A far sign at VGA (15.5 px tall) mounted 3 px below a ceiling line: above the line the ceiling (lighter) spans
    // the whole image. The cascade box is 35 % too tall, so the search starts on the ceiling; the ceiling-to-wall
    // change is a significant, persistent rise from the ceiling's colour, but the wall beside the face shows the
    // same change at the same rows, so it is the background's: the search restarts on the wall and finds the face.
    const double top = 22.5, bottom = 38.0;
    cv::Mat img = syntheticFace({90, 60}, 25.5, 48.5, top, bottom, {95, 110, 100}, {230, 225, 220}, 0.8, 1.5, 13);
    img.rowRange(0, 20).setTo(cv::Scalar(200, 205, 210));
    const SliceMeasurement rough = roughBox(25, 17, 24, 23);
    const FaceEdgeResult r = refineFaceEdges(img, rough, SliceParams{}, FaceEdgeParams{});
    ASSERT_TRUE(r.refined);
    EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.4);
    EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.3);
    // Without the look beside the face, the ceiling line is taken for the face's top edge (2-3 px too high).
    FaceEdgeParams noSide;
    noSide.sideSameChangeFraction = 0;
    const FaceEdgeResult without = refineFaceEdges(img, rough, SliceParams{}, noSide);
    ASSERT_TRUE(without.refined);
    EXPECT_GT(without.measurement.medianHeightPx, bottom - top + 1.5);
    // The side columns outside the image (the face at the image's left edge): the check uses the other side.
    const cv::Mat shifted = img.colRange(20, 90).clone();
    const FaceEdgeResult edge = refineFaceEdges(shifted, roughBox(5, 17, 24, 23), SliceParams{}, FaceEdgeParams{});
    ASSERT_TRUE(edge.refined);
    EXPECT_NEAR(edge.measurement.medianHeightPx, bottom - top, 0.4);
}

TEST(FaceEdgeRefiner, KeepsTheRoughMeasurementWithoutAnEdgeOrWhenOff) {
    // A flat wall: no rise, the box stays. Disabled: the box stays.
    cv::Mat flat(100, 100, CV_8UC3, cv::Scalar(128, 128, 128));
    const SliceMeasurement rough = roughBox(20, 30, 60, 30);
    const FaceEdgeResult none = refineFaceEdges(flat, rough, SliceParams{}, FaceEdgeParams{});
    EXPECT_FALSE(none.refined);
    EXPECT_DOUBLE_EQ(none.measurement.medianHeightPx, rough.medianHeightPx);
    const cv::Mat img = syntheticFace({100, 100}, 20.5, 79.5, 34.2, 55.0, {100, 100, 100}, {230, 230, 230}, 1.0, 1.0, 9);
    FaceEdgeParams off;
    off.enabled = false;
    EXPECT_FALSE(refineFaceEdges(img, rough, SliceParams{}, off).refined);
    EXPECT_FALSE(refineFaceEdges(img, SliceMeasurement{}, SliceParams{}, FaceEdgeParams{}).refined);
    // A box at the image border whose search would leave the image: kept, no crash.
    EXPECT_FALSE(refineFaceEdges(img, roughBox(0, 0, 30, 10), SliceParams{}, FaceEdgeParams{}).refined);
    // Boxes partly or wholly outside the image, a degenerate one, a tiny image: kept, no out-of-bounds read.
    for (const cv::Rect& r : {cv::Rect(10, -20, 30, 25), cv::Rect(40, 90, 30, 40), cv::Rect(-50, 30, 40, 20),
                              cv::Rect(200, 200, 20, 10), cv::Rect(20, 30, 1, 1)}) {
        EXPECT_FALSE(refineFaceEdges(img, measureBox(r), SliceParams{}, FaceEdgeParams{}).refined) << r;
    }
    EXPECT_FALSE(refineFaceEdges(cv::Mat(3, 3, CV_8UC3, cv::Scalar::all(9)), rough, SliceParams{}, FaceEdgeParams{}).refined);
}

TEST(FaceEdgeRefiner, SrgbTransferDecodesBeforeTakingTheMidpoint) {
    // The same blurred edge written in sRGB code values: read as sRGB the midpoint is the true edge; read as
    // linear it lies outside the bright face (the face reads taller).
    const double top = 40.3, bottom = 71.8;
    const cv::Mat linear = syntheticFace({160, 120}, 30.5, 130.5, top, bottom, {20, 20, 20}, {230, 230, 230}, 2.0, 0.0, 1);
    cv::Mat encoded(linear.size(), CV_8UC3);
    for (int y = 0; y < linear.rows; ++y) {
        for (int x = 0; x < linear.cols * 3; ++x) {
            const double l = linear.ptr<uchar>(y)[x] / 255.0;
            const double e = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
            encoded.ptr<uchar>(y)[x] = cv::saturate_cast<uchar>(255 * e);
        }
    }
    const SliceMeasurement rough = roughBox(31, 37, 100, 38);
    FaceEdgeParams srgb;
    srgb.transfer = PixelTransfer::kSrgb;
    const FaceEdgeResult asSrgb = refineFaceEdges(encoded, rough, SliceParams{}, srgb);
    const FaceEdgeResult asLinear = refineFaceEdges(encoded, rough, SliceParams{}, FaceEdgeParams{});
    ASSERT_TRUE(asSrgb.refined);
    ASSERT_TRUE(asLinear.refined);
    EXPECT_NEAR(asSrgb.measurement.medianHeightPx, bottom - top, 0.35);
    EXPECT_GT(asLinear.measurement.medianHeightPx, bottom - top + 1.0);
}

TEST(FaceEdgeRefiner, InFrameSamplingThroughTheUnrolling) {
    // A landscape frame (roll 0), the same frame turned to portrait (roll -pi/2: the unrolled image is the
    // landscape one), and a tilted roll: the refined edges are the face's in unrolled pixels.
    const double top = 40.3, bottom = 71.8;
    const cv::Mat rgb = syntheticFace({200, 150}, 50.5, 150.5, top, bottom, {110, 110, 110}, {235, 235, 230}, 1.0, 1.0, 13);
    const Intrinsics k{200, 200, 99.5, 74.5};
    const SliceMeasurement rough = roughBox(51, 37, 100, 39);
    {
        const Unrolling u = Unrolling::forRoll(0.0, k, rgb.size());
        const wf_image image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0, 0, 0};
        const FaceEdgeResult r = refineFaceEdgesInFrame(image, u, rough, SliceParams{}, FaceEdgeParams{});
        ASSERT_TRUE(r.refined);
        EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.3);
        EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.2);
    }
    {
        // Portrait raw frame: the landscape image turned counter-clockwise; unrolling turns it back.
        cv::Mat portrait;
        cv::rotate(rgb, portrait, cv::ROTATE_90_COUNTERCLOCKWISE);
        cv::Mat bgra;
        cv::cvtColor(portrait, bgra, cv::COLOR_RGB2BGRA);
        const Intrinsics kp{200, 200, 74.5, 199 - 99.5};
        const Unrolling u = Unrolling::forRoll(-M_PI / 2, kp, portrait.size());
        ASSERT_EQ(u.unrolledSize(), rgb.size());
        const wf_image image{bgra.data, bgra.cols, bgra.rows, bgra.step, WF_PIXEL_BGRA8, nullptr, 0, 0, 0};
        const FaceEdgeResult r = refineFaceEdgesInFrame(image, u, rough, SliceParams{}, FaceEdgeParams{});
        ASSERT_TRUE(r.refined);
        EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.3);
        EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom, 0.2);
    }
    {
        // Tilted roll: the raw frame is the unrolled image rotated; build it with the unrolling's own map.
        const double roll = 0.2;
        const Unrolling u = Unrolling::forRoll(roll, k, rgb.size());
        // Raw = unrolled image warped by the unrolled -> raw map (the canvas is larger: embed the face image).
        cv::Mat canvas(u.unrolledSize(), CV_8UC3, cv::Scalar(110, 110, 110));
        const int ox = (canvas.cols - rgb.cols) / 2, oy = (canvas.rows - rgb.rows) / 2;
        rgb.copyTo(canvas(cv::Rect(ox, oy, rgb.cols, rgb.rows)));
        cv::Mat raw;
        cv::warpAffine(canvas, raw, cv::Mat(u.rawToUnrolledMatrix()), rgb.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                       cv::BORDER_REPLICATE);
        const wf_image image{raw.data, raw.cols, raw.rows, raw.step, WF_PIXEL_RGB8, nullptr, 0, 0, 0};
        const SliceMeasurement shifted = roughBox(51 + ox, 37 + oy, 100, 39);
        const FaceEdgeResult r = refineFaceEdgesInFrame(image, u, shifted, SliceParams{}, FaceEdgeParams{});
        ASSERT_TRUE(r.refined);
        EXPECT_NEAR(r.measurement.medianHeightPx, bottom - top, 0.5);
        EXPECT_NEAR(r.measurement.medianBottomEdgePx, bottom + oy, 0.5);
    }
}
