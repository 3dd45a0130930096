// Tests of src/colour_gate and CascadeDetector::detectInRegions: a red sign yields a region around it (landscape
// and portrait, RGB8 and NV12), frames without colour fall back to the full search, a colour frame with nothing
// red or green yields no region, and boxes found in a region map back to full-frame pixels exactly, within the
// region's window limits; hits grouped across overlapping regions count each window once.
#include "cascade_detector.hpp"
#include "colour_gate.hpp"
#include "synthetic_scene.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <vector>

using namespace wf::sign;
using wf::sign::testing::referenceCascadePath;

namespace {

struct SignFrame {
    cv::Mat rgb;  // owns the pixels of `image`
    wf_image image{};
    synthetic::Camera camera;
    synthetic::RenderedSign truth;
};

/// VGA RGB8 frame with a red-on-white Exit sign at `rangeMeters`, camera roll `rollRad`.
SignFrame redSignFrame(double rangeMeters, double rollRad, double bearingRad = 0.1) {
    SignFrame f;
    synthetic::Camera cam;
    cam.rollRad = rollRad;
    f.camera = cam.resized(rollRad == 0 ? cv::Size(640, 480) : cv::Size(480, 640));
    if (rollRad != 0) {  // portrait: the raw frame is 480 x 640 with the intrinsics of that size
        f.camera = synthetic::Camera{};
        f.camera.size = {480, 640};
        f.camera.fx = f.camera.fy = 534;
        f.camera.cx = 239.5;
        f.camera.cy = 319.5;
        f.camera.rollRad = rollRad;
    }
    cv::Mat bgr = synthetic::renderBackground(f.camera, 21);
    synthetic::SignPlacement sign;
    sign.rangeMeters = rangeMeters;
    sign.bearingRad = bearingRad;
    sign.bottomAboveCameraMeters = 0.5;
    f.truth = synthetic::drawSign(bgr, f.camera, sign);
    cv::cvtColor(bgr, f.rgb, cv::COLOR_BGR2RGB);
    f.image = wf_image{f.rgb.data, f.rgb.cols, f.rgb.rows, f.rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    return f;
}

Unrolling unrollingOf(const SignFrame& f) {
    const synthetic::Camera& c = f.camera;
    return Unrolling::forRoll(c.rollRad, Intrinsics{c.fx, c.fy, c.cx, c.cy}, c.size);
}

/// The sign's bounding box in the unrolled image (pixel edges).
cv::Rect2d unrolledSignBox(const SignFrame& f, const Unrolling& u) {
    std::vector<cv::Point2f> pts;
    for (const auto& c : f.truth.cornersRaw) {
        const cv::Point2d p = u.rawToUnrolled(c);
        pts.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
    }
    return cv::boundingRect(pts);
}

bool someRegionContains(const GateDecision& d, const cv::Rect2d& box) {
    for (const auto& r : d.regions) {
        const cv::Rect2d rr(r.unrolledRect.x - 0.5, r.unrolledRect.y - 0.5, r.unrolledRect.width, r.unrolledRect.height);
        if ((rr & box) == box) return true;
    }
    return false;
}

/// The reference cascade loaded as "exit", the gray VGA frame of a red sign 2.5 m ahead, and search parameters
/// that keep every raw hit (minNeighbors 1).
void loadOnGraySign(CascadeDetector* d, cv::Mat* gray, CascadeParams* params) {
    std::string error;
    ASSERT_TRUE(d->load({referenceCascadePath()}, {"exit"}, &error)) << error;
    const SignFrame f = redSignFrame(2.5, 0.0, 0.0);
    cv::cvtColor(f.rgb, *gray, cv::COLOR_RGB2GRAY);
    params->minNeighbors = 1;
}

}  // namespace

TEST(ColourGate, RedSignYieldsARegionAroundIt) {
    for (double range : {2.0, 4.0, 8.0}) {
        SignFrame f = redSignFrame(range, 0.0);
        ASSERT_TRUE(f.truth.visible);
        const ColourGateParams params;
        const ColourBlobs blobs = findColourBlobs(f.image, params);
        EXPECT_TRUE(blobs.colourAvailable);
        EXPECT_FALSE(blobs.rawBoxes.empty());
        const Unrolling u = unrollingOf(f);
        const GateDecision d = gateRegions(blobs, u, -1, params);
        EXPECT_FALSE(d.fullSearch) << "range " << range;
        EXPECT_TRUE(someRegionContains(d, unrolledSignBox(f, u))) << "range " << range;
        double area = 0;
        for (const auto& r : d.regions) area += r.unrolledRect.area();
        EXPECT_LT(area, 0.5 * u.unrolledSize().area()) << "the gate must cut the searched area";
    }
}

TEST(ColourGate, PortraitFrameRegionsAreInUnrolledPixels) {
    SignFrame f = redSignFrame(3.0, -1.58);
    ASSERT_TRUE(f.truth.visible);
    const ColourGateParams params;
    const Unrolling u = unrollingOf(f);
    const GateDecision d = gateRegions(findColourBlobs(f.image, params), u, -1, params);
    ASSERT_FALSE(d.fullSearch);
    EXPECT_TRUE(someRegionContains(d, unrolledSignBox(f, u)));
    for (const auto& r : d.regions) {
        EXPECT_EQ(r.unrolledRect & cv::Rect(cv::Point(), u.unrolledSize()), r.unrolledRect) << "clipped to the canvas";
    }
}

TEST(ColourGate, Nv12ChromaGivesTheSameRegion) {
    SignFrame f = redSignFrame(3.0, 0.0);
    // Full-range BT.601 NV12 of the frame: Y plane plus interleaved Cb, Cr at half resolution.
    cv::Mat ycrcb;
    cv::cvtColor(f.rgb, ycrcb, cv::COLOR_RGB2YCrCb);
    std::vector<cv::Mat> ch;
    cv::split(ycrcb, ch);
    cv::Mat cr, cb, uv;
    cv::resize(ch[1], cr, {f.rgb.cols / 2, f.rgb.rows / 2}, 0, 0, cv::INTER_AREA);
    cv::resize(ch[2], cb, {f.rgb.cols / 2, f.rgb.rows / 2}, 0, 0, cv::INTER_AREA);
    cv::merge(std::vector<cv::Mat>{cb, cr}, uv);
    const wf_image nv12{ch[0].data, ch[0].cols, ch[0].rows, ch[0].step, WF_PIXEL_NV12, uv.data, uv.step};
    const ColourGateParams params;
    const Unrolling u = unrollingOf(f);
    const GateDecision d = gateRegions(findColourBlobs(nv12, params), u, -1, params);
    ASSERT_FALSE(d.fullSearch);
    EXPECT_TRUE(someRegionContains(d, unrolledSignBox(f, u)));

    // Without its chroma plane the same frame is luma only: full search.
    const wf_image lumaOnly{ch[0].data, ch[0].cols, ch[0].rows, ch[0].step, WF_PIXEL_NV12, nullptr, 0};
    const ColourBlobs none = findColourBlobs(lumaOnly, params);
    EXPECT_FALSE(none.colourAvailable);
    EXPECT_TRUE(gateRegions(none, u, -1, params).fullSearch);
}

TEST(ColourGate, FramesWithoutColourFallBackToTheFullSearch) {
    SignFrame f = redSignFrame(3.0, 0.0);
    const ColourGateParams params;
    const Unrolling u = unrollingOf(f);
    // GRAY8.
    cv::Mat gray;
    cv::cvtColor(f.rgb, gray, cv::COLOR_RGB2GRAY);
    const wf_image grayImage{gray.data, gray.cols, gray.rows, gray.step, WF_PIXEL_GRAY8, nullptr, 0};
    EXPECT_FALSE(findColourBlobs(grayImage, params).colourAvailable);
    EXPECT_TRUE(gateRegions(findColourBlobs(grayImage, params), u, -1, params).fullSearch);
    // RGB8 whose three channels are equal (a gray image handed over as RGB): no usable colour either.
    cv::Mat grayRgb;
    cv::cvtColor(gray, grayRgb, cv::COLOR_GRAY2RGB);
    const wf_image grayAsRgb{grayRgb.data, grayRgb.cols, grayRgb.rows, grayRgb.step, WF_PIXEL_RGB8, nullptr, 0};
    EXPECT_FALSE(findColourBlobs(grayAsRgb, params).colourAvailable);
    EXPECT_TRUE(gateRegions(findColourBlobs(grayAsRgb, params), u, -1, params).fullSearch);
    // The gate switched off: full search even with colour.
    ColourGateParams off;
    off.enabled = false;
    EXPECT_TRUE(gateRegions(findColourBlobs(f.image, off), u, -1, off).fullSearch);
}

TEST(ColourGate, ColourFrameWithNothingRedOrGreenHasNoRegion) {
    // A teal-tinted wall (R - G = -20 everywhere: a colour cast, which the local mean cancels) with noise and a
    // blue door: colour, but no local red-green contrast.
    cv::Mat rgb(480, 640, CV_8UC3, cv::Scalar(110, 130, 140));
    cv::Mat noise(rgb.size(), CV_8UC1);
    cv::RNG(3).fill(noise, cv::RNG::UNIFORM, 0, 12);
    std::vector<cv::Mat> ch;
    cv::split(rgb, ch);
    for (auto& c : ch) c += noise;  // the same noise in R and G: texture without red-green contrast
    cv::merge(ch, rgb);
    cv::rectangle(rgb, cv::Rect(300, 150, 120, 300), cv::Scalar(40, 40, 160), cv::FILLED);
    const wf_image image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    const ColourGateParams params;
    const ColourBlobs blobs = findColourBlobs(image, params);
    EXPECT_TRUE(blobs.colourAvailable);
    const Unrolling u = Unrolling::forRoll(0.0, Intrinsics{534, 534, 319.5, 239.5}, rgb.size());
    const GateDecision d = gateRegions(blobs, u, -1, params);
    EXPECT_FALSE(d.fullSearch);
    EXPECT_TRUE(d.regions.empty());
}

TEST(ColourGate, RegionsAreClippedToTheSearchRows) {
    SignFrame f = redSignFrame(3.0, 0.0);
    const ColourGateParams params;
    const Unrolling u = unrollingOf(f);
    const ColourBlobs blobs = findColourBlobs(f.image, params);
    const int lastRow = 200;
    for (const auto& r : gateRegions(blobs, u, lastRow, params).regions) EXPECT_LE(r.unrolledRect.br().y, lastRow);
    EXPECT_TRUE(gateRegions(blobs, u, 0, params).regions.empty());
}

TEST(ColourGate, BoxesFoundInARegionMapBackExactly) {
    CascadeDetector d;
    cv::Mat gray;
    CascadeParams params;
    ASSERT_NO_FATAL_FAILURE(loadOnGraySign(&d, &gray, &params));
    const cv::Rect region(150, 60, 300, 220);
    const std::vector<Detection> inRegion = d.detectInRegions(gray, {SearchRegion{region, 0}}, params);
    const cv::Mat crop = gray(region).clone();
    const std::vector<Detection> onCrop = d.detect(crop, params);
    ASSERT_EQ(inRegion.size(), onCrop.size());
    ASSERT_FALSE(onCrop.empty()) << "the reference cascade finds the drawn sign (see test_cascade_detector)";
    for (size_t i = 0; i < onCrop.size(); ++i) {
        EXPECT_DOUBLE_EQ(inRegion[i].measurement.box.x, onCrop[i].measurement.box.x + region.x);
        EXPECT_DOUBLE_EQ(inRegion[i].measurement.box.y, onCrop[i].measurement.box.y + region.y);
        EXPECT_DOUBLE_EQ(inRegion[i].measurement.box.width, onCrop[i].measurement.box.width);
        EXPECT_DOUBLE_EQ(inRegion[i].measurement.box.height, onCrop[i].measurement.box.height);
        EXPECT_DOUBLE_EQ(inRegion[i].measurement.medianBottomEdgePx, onCrop[i].measurement.medianBottomEdgePx + region.y);
        EXPECT_DOUBLE_EQ(inRegion[i].measurement.centerColumnPx, onCrop[i].measurement.centerColumnPx + region.x);
    }
    // A region with a minimum window wider than the region itself searches nothing.
    EXPECT_TRUE(d.detectInRegions(gray, {SearchRegion{region, 400}}, params).empty());
    // A largest window narrower than the sign's box: no box that wide (the plate gate's regions).
    const int narrower = static_cast<int>(onCrop[0].measurement.box.width) - 1;
    for (const Detection& det : d.detectInRegions(gray, {SearchRegion{region, 0, narrower}}, params)) {
        EXPECT_LE(det.measurement.box.width, narrower);
    }
}

TEST(ColourGate, HitsGroupedAcrossOverlappingRegionsCountEachWindowOnce) {
    // The plate gate's grouping: the raw hits of all regions grouped together, a hit that repeats one of an earlier
    // region (same size, within half the scan's step) counted once. The same region twice then gives what it gives
    // once (neighbour counts included); grouped per region it gives every box twice.
    CascadeDetector d;
    cv::Mat gray;
    CascadeParams params;
    ASSERT_NO_FATAL_FAILURE(loadOnGraySign(&d, &gray, &params));
    const SearchRegion region{cv::Rect(150, 60, 300, 220), 0, 0};
    const std::vector<Detection> once = d.detectInRegions(gray, {region}, params, -1, nullptr, nullptr, true);
    const std::vector<Detection> twice = d.detectInRegions(gray, {region, region}, params, -1, nullptr, nullptr, true);
    ASSERT_FALSE(once.empty());
    ASSERT_EQ(twice.size(), once.size());
    for (size_t i = 0; i < once.size(); ++i) {
        EXPECT_EQ(twice[i].measurement.box, once[i].measurement.box);
        EXPECT_EQ(twice[i].score, once[i].score);
    }
    EXPECT_EQ(d.detectInRegions(gray, {region, region}, params).size(), 2 * once.size());
}

TEST(ColourGate, CrowdedFramesRaiseTheThresholdOnceAndKeepTheSign) {
    // The red sign on a wall covered with weakly red and green patches (contrast about 40 levels: above the
    // normal threshold of 25, below the raised 62.5): the regions at 25 cover most of the frame.
    SignFrame f = redSignFrame(3.0, 0.0);
    cv::RNG rng(5);
    const cv::Rect2d sign = cv::boundingRect(std::vector<cv::Point2f>(f.truth.cornersRaw.begin(), f.truth.cornersRaw.end()));
    for (int i = 0; i < 60; ++i) {
        const cv::Rect patch(rng.uniform(0, 600), rng.uniform(0, 440), rng.uniform(10, 40), rng.uniform(10, 40));
        if ((cv::Rect2d(patch) & sign).area() > 0) continue;
        const bool reddish = rng.uniform(0, 2) == 0;
        cv::Mat view = f.rgb(patch & cv::Rect(0, 0, f.rgb.cols, f.rgb.rows));
        view += reddish ? cv::Scalar(45, 0, 0) : cv::Scalar(0, 45, 0);
    }
    const Unrolling u = unrollingOf(f);
    ColourGateParams params;
    params.crowdedContrastFactor = 1.0;  // off: the regions at 25 levels
    const GateDecision plain = gateFrame(f.image, u, -1, params);
    EXPECT_DOUBLE_EQ(plain.minContrast, 25.0);
    double plainArea = 0;
    for (const auto& r : plain.regions) plainArea += r.unrolledRect.area();
    ASSERT_TRUE(plain.fullSearch || plainArea > 0.15 * 640 * 480) << "the clutter must crowd the frame";

    params.crowdedContrastFactor = 2.5;
    const GateDecision crowded = gateFrame(f.image, u, -1, params);
    EXPECT_DOUBLE_EQ(crowded.minContrast, 62.5);
    EXPECT_FALSE(crowded.fullSearch);
    double crowdedArea = 0;
    for (const auto& r : crowded.regions) crowdedArea += r.unrolledRect.area();
    EXPECT_LT(crowdedArea, 0.15 * 640 * 480);
    EXPECT_TRUE(someRegionContains(crowded, unrolledSignBox(f, u)));

    // An uncrowded frame keeps the normal threshold.
    SignFrame clean = redSignFrame(3.0, 0.0);
    const GateDecision normal = gateFrame(clean.image, unrollingOf(clean), -1, params);
    EXPECT_DOUBLE_EQ(normal.minContrast, 25.0);
    EXPECT_TRUE(someRegionContains(normal, unrolledSignBox(clean, unrollingOf(clean))));
}

TEST(ColourGate, TilesOfALargeComponentSearchOnlyWindowsNearItsWidth) {
    // A red stripe 400 x 12 px on a gray wall (VGA, level camera): one component far larger than a tile, so it is
    // cut into tiles; with componentWindowFraction f, every tile's region asks for windows of at least f x the
    // stripe's width (about 400 px), not of any size.
    cv::Mat rgb(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
    cv::rectangle(rgb, cv::Rect(100, 200, 400, 12), cv::Scalar(200, 30, 30), cv::FILLED);
    const wf_image image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    const Unrolling u = Unrolling::forRoll(0.0, Intrinsics{534, 534, 319.5, 239.5}, rgb.size());
    ColourGateParams params;
    const ColourBlobs blobs = findColourBlobs(image, params);
    ASSERT_EQ(blobs.componentRawBoxes.size(), blobs.rawBoxes.size());
    ASSERT_GT(blobs.rawBoxes.size(), 2u) << "the stripe is tiled";
    for (size_t i = 0; i < blobs.rawBoxes.size(); ++i) {
        EXPECT_FALSE(blobs.wholeComponent[i]);
        EXPECT_GT(blobs.componentRawBoxes[i].width, 400.0);  // the dilated stripe, not the tile
        EXPECT_LE(blobs.rawBoxes[i].width, 2.0 * params.tileSidePx + 1e-9);
    }
    params.componentWindowFraction = 0.4;
    GateDecision d = gateRegions(blobs, u, -1, params);
    ASSERT_FALSE(d.fullSearch);
    ASSERT_FALSE(d.regions.empty());
    for (const auto& r : d.regions) {
        EXPECT_GE(r.minWindowWidthPx, static_cast<int>(0.4 * 400));
        EXPECT_LE(r.minWindowWidthPx, static_cast<int>(0.4 * 410));
    }
    params.componentWindowFraction = 0;  // off (options before version 5): every window size in tiles
    d = gateRegions(blobs, u, -1, params);
    for (const auto& r : d.regions) EXPECT_EQ(r.minWindowWidthPx, 0);
}

TEST(ColourGate, MarginIsAtLeastMinMarginAroundASmallBlob) {
    // A 10 x 6 px red patch: its region is the patch plus the minimum margin on each side (0.5 x its size is less).
    cv::Mat rgb(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
    cv::rectangle(rgb, cv::Rect(300, 200, 10, 6), cv::Scalar(220, 20, 20), cv::FILLED);
    const wf_image image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    const Unrolling u = Unrolling::forRoll(0.0, Intrinsics{534, 534, 319.5, 239.5}, rgb.size());
    for (const int margin : {16, 24}) {
        ColourGateParams params;
        params.minMarginPx = margin;
        const GateDecision d = gateRegions(findColourBlobs(image, params), u, -1, params);
        ASSERT_EQ(d.regions.size(), 1u);
        const cv::Rect r = d.regions[0].unrolledRect;
        // The dilated blob at working resolution (2 px per working pixel) spans about 298..312 x 198..208.
        EXPECT_NEAR(r.x, 298 - margin, 3) << margin;
        EXPECT_NEAR(r.br().x, 312 + margin, 3) << margin;
        EXPECT_NEAR(r.y, 198 - margin, 3) << margin;
        EXPECT_NEAR(r.br().y, 208 + margin, 3) << margin;
    }
}

TEST(ColourGate, WorkingResolutionIsRoundedNotFloored) {
    // A 639 x 479 frame is gated at 319 x 239 like VGA (factor 2), not at its full size (factor 1); the shrink is
    // exactly 2 (its first 638 x 478 pixels), so working pixel j covers raw pixels 2j and 2j + 1.
    cv::Mat rgb(479, 639, CV_8UC3, cv::Scalar(128, 128, 128));
    cv::rectangle(rgb, cv::Rect(300, 200, 40, 14), cv::Scalar(220, 20, 20), cv::FILLED);
    const wf_image image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    const ColourContrast c = localColourContrast(image, ColourGateParams{});
    ASSERT_FALSE(c.contrast.empty());
    EXPECT_EQ(c.contrast.cols, 319);
    EXPECT_EQ(c.contrast.rows, 239);
    EXPECT_DOUBLE_EQ(c.rawPerWorkingPx.x, 2.0);
    EXPECT_DOUBLE_EQ(c.rawPerWorkingPx.y, 2.0);
    // The red patch (columns 300..339) is where the contrast is, at working columns 150..169.
    double peak = 0;
    cv::Point at;
    cv::minMaxLoc(c.contrast, nullptr, &peak, nullptr, &at);
    EXPECT_GE(at.x, 148);
    EXPECT_LE(at.x, 171);
}

TEST(ColourGate, TilesOfASignSizedComponentKeepTheNearSignMargin) {
    // A 44 x 20 px red block (a near sign's lettering: larger than a tile, so tiled) and a 400 x 12 px stripe (far
    // larger than any sign): the block's merged region reaches nearSignMarginPx beyond it, the stripe's only
    // minMarginPx.
    cv::Mat rgb(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
    cv::rectangle(rgb, cv::Rect(100, 100, 44, 20), cv::Scalar(220, 20, 20), cv::FILLED);
    cv::rectangle(rgb, cv::Rect(100, 350, 400, 12), cv::Scalar(220, 20, 20), cv::FILLED);
    const wf_image image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    const Unrolling u = Unrolling::forRoll(0.0, Intrinsics{534, 534, 319.5, 239.5}, rgb.size());
    ColourGateParams params;
    ASSERT_EQ(params.minMarginPx, 16);
    ASSERT_EQ(params.nearSignMarginPx, 24);
    const ColourBlobs blobs = findColourBlobs(image, params);
    const GateDecision d = gateRegions(blobs, u, -1, params);
    ASSERT_FALSE(d.fullSearch);
    // The two components' boxes (raw = unrolled pixels here: level camera, no roll). The mask reaches beyond the
    // painted shapes (the local mean spreads their colour), so margins are measured from the components.
    cv::Rect2d block, stripe;
    for (const cv::Rect2d& c : blobs.componentRawBoxes) (c.y < 250 ? block : stripe) = c;
    ASSERT_GT(block.width, 2.0 * params.tileSidePx);
    ASSERT_LE(std::max(block.width, block.height), params.nearSignComponentMaxPx);
    ASSERT_GT(stripe.width, params.nearSignComponentMaxPx);
    bool sawBlock = false, sawStripe = false;
    for (const auto& r : d.regions) {
        if (r.unrolledRect.y < 250) {  // the block's region (its tiles merged): 24 px beyond its rows
            sawBlock = true;
            EXPECT_LE(r.unrolledRect.y, block.y + 0.5 - 24 + 1);
            EXPECT_GE(r.unrolledRect.br().y, block.br().y - 0.5 + 24 - 1);
        } else {  // the stripe's: 16 px beyond its rows
            sawStripe = true;
            EXPECT_GE(r.unrolledRect.y, stripe.y + 0.5 - 16 - 1);
            EXPECT_LE(r.unrolledRect.br().y, stripe.br().y - 0.5 + 16 + 1);
        }
    }
    EXPECT_TRUE(sawBlock);
    EXPECT_TRUE(sawStripe);
}
