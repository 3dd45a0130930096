// Tests of src/unet_detector with the tiny committed model (a red-pixel segmenter with the U-Net's
// interface): loading, softmax, coarse candidates, zoomed refinement, range accuracy through the slices.
#include "unet_detector.hpp"
#include "range_formula.hpp"
#include "synthetic_scene.hpp"
#include "test_paths.hpp"
#include "unroll.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

using namespace wf::sign;
using wf::sign::testing::tinyUnetPath;

namespace {

UnetDetector loadTiny() {
    UnetDetector d;
    std::string error;
    EXPECT_TRUE(d.load(tinyUnetPath(), {"background", "exit"}, 224, &error)) << error;
    return d;
}

struct Scene {
    synthetic::Camera camera;
    synthetic::RenderedSign truth;
    Unrolling unrolling;
    cv::Mat rgbRaw;
};

/// A portrait 1920 x 1440 frame with a red-plate Exit sign at `rangeMeters`, unrolled.
Scene portraitScene(double rangeMeters, double bearingRad, double pitchRad, uint32_t seed,
                    double bottomAboveCameraMeters = 0.8) {
    Scene s;
    s.camera.pitchRad = pitchRad;
    cv::Mat bgr = synthetic::renderBackground(s.camera, seed);
    synthetic::SignPlacement sign;
    sign.rangeMeters = rangeMeters;
    sign.bearingRad = bearingRad;
    sign.style = synthetic::SignStyle::WhiteLettersOnRed;
    sign.bottomAboveCameraMeters = bottomAboveCameraMeters;
    s.truth = synthetic::drawSign(bgr, s.camera, sign);
    s.unrolling = Unrolling::forRoll(s.camera.rollRad, {s.camera.fx, s.camera.fy, s.camera.cx, s.camera.cy}, bgr.size());
    cv::cvtColor(bgr, s.rgbRaw, cv::COLOR_BGR2RGB);
    return s;
}

}  // namespace

TEST(UnetDetector, LoadsTheModelAndItsClassList) {
    UnetDetector d;
    std::string error;
    ASSERT_TRUE(d.load(tinyUnetPath(), {}, 224, &error)) << error;
    EXPECT_EQ(d.classNames(), (std::vector<std::string>{"background", "class1"}));
    std::vector<std::string> classes;
    ASSERT_TRUE(readClassList(wf::sign::testing::testDataDir() + "/classes.json", &classes, &error)) << error;
    EXPECT_EQ(classes, (std::vector<std::string>{"background", "exit"}));
}

TEST(UnetDetector, LoadErrorsNameTheProblem) {
    UnetDetector d;
    std::string error;
    EXPECT_FALSE(d.load("/nonexistent/sign_unet.onnx", {}, 224, &error));
    EXPECT_NE(error.find("/nonexistent/sign_unet.onnx"), std::string::npos);
    EXPECT_FALSE(d.load(tinyUnetPath(), {"background", "exit", "restroom"}, 224, &error));
    EXPECT_NE(error.find("outputs 2 classes"), std::string::npos) << error;
    EXPECT_FALSE(d.load(wf::sign::testing::testDataDir() + "/classes.json", {}, 224, &error));
    std::vector<std::string> classes;
    EXPECT_FALSE(readClassList("/nonexistent/classes.json", &classes, &error));
}

TEST(UnetDetector, ProbabilitiesAreASoftmaxOverClasses) {
    UnetDetector d = loadTiny();
    cv::Mat rgb(224, 224, CV_8UC3, cv::Scalar(235, 235, 235));
    rgb(cv::Rect(100, 100, 20, 10)).setTo(cv::Scalar(220, 20, 20));  // red in RGB order
    const std::vector<cv::Mat> p = d.probabilities(rgb);
    ASSERT_EQ(p.size(), 2u);
    cv::Mat sum = p[0] + p[1];
    double lo, hi;
    cv::minMaxLoc(sum, &lo, &hi);
    EXPECT_NEAR(lo, 1.0, 1e-5);
    EXPECT_NEAR(hi, 1.0, 1e-5);
    EXPECT_GT(p[1].at<float>(105, 110), 0.99f);
    EXPECT_LT(p[1].at<float>(50, 50), 0.01f);
}

TEST(UnetDetector, AlternatingInputShapesGiveTheSameProbabilities) {
    // One cached cv::dnn::Net per input shape (more shapes than the cache holds): results must not depend
    // on which shape ran before, and the returned maps must not alias the net's output buffer.
    UnetDetector d = loadTiny();
    cv::Mat a(192, 224, CV_8UC3, cv::Scalar(235, 235, 235));
    a(cv::Rect(100, 100, 20, 10)).setTo(cv::Scalar(220, 20, 20));
    const std::vector<cv::Mat> first = d.probabilities(a);
    const cv::Mat firstCopy = first[1].clone();
    for (int rows = 32; rows <= 256; rows += 32) {
        cv::Mat b(rows, 160, CV_8UC3, cv::Scalar(20, 200, 20));
        const std::vector<cv::Mat> p = d.probabilities(b);
        ASSERT_EQ(p[1].size(), b.size());
    }
    const std::vector<cv::Mat> again = d.probabilities(a);
    EXPECT_EQ(cv::norm(first[1], firstCopy, cv::NORM_INF), 0.0);
    EXPECT_LE(cv::norm(again[1], first[1], cv::NORM_INF), 1e-6);
    EXPECT_LE(cv::norm(again[0], first[0], cv::NORM_INF), 1e-6);
}

TEST(UnetDetector, CoarseCandidateMapsBackToTheSign) {
    UnetDetector d = loadTiny();
    const Scene s = portraitScene(4.0, 0.1, 0.05, 5);
    ASSERT_TRUE(s.truth.visible);
    RawPyramid raw(s.rgbRaw);
    const std::vector<UnetCandidate> c = d.coarseCandidates(raw, s.unrolling, UnetParams{}, std::nan(""));
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].classIndex, 1);
    // The truth box in unrolled pixels; the coarse box agrees within two network pixels (~17 px).
    double minX = 1e9, maxX = -1e9, minY = 1e9, maxY = -1e9;
    for (const auto& p : s.truth.cornersRaw) {
        const cv::Point2d q = s.unrolling.rawToUnrolled(p);
        minX = std::min(minX, q.x); maxX = std::max(maxX, q.x);
        minY = std::min(minY, q.y); maxY = std::max(maxY, q.y);
    }
    const cv::Rect2d truthBox(minX, minY, maxX - minX, maxY - minY);
    EXPECT_NEAR(c[0].boxInUnrolled.x, truthBox.x, 18);
    EXPECT_NEAR(c[0].boxInUnrolled.y + c[0].boxInUnrolled.height, truthBox.y + truthBox.height, 18);
}

TEST(UnetDetector, CoarsePassSkipsRowsBelowTheLowestSignElevation) {
    UnetDetector d = loadTiny();
    const double pitch = 0.05;
    // A sign above eye level (bottom 0.8 m above the camera at 4 m: elevation >= 0.2 rad) is found with the
    // cut at its default (-0.10 rad) exactly where the full pass finds it.
    const Scene high = portraitScene(4.0, 0.1, pitch, 5);
    ASSERT_TRUE(high.truth.visible);
    RawPyramid rawHigh(high.rgbRaw);
    const std::vector<UnetCandidate> full = d.coarseCandidates(rawHigh, high.unrolling, UnetParams{}, std::nan(""));
    const std::vector<UnetCandidate> cut = d.coarseCandidates(rawHigh, high.unrolling, UnetParams{}, pitch);
    ASSERT_EQ(full.size(), 1u);
    ASSERT_EQ(cut.size(), 1u);
    EXPECT_EQ(cut[0].boxInUnrolled, full[0].boxInUnrolled);
    EXPECT_NEAR(cut[0].meanProbability, full[0].meanProbability, 1e-6);
    // A plate 1.5 m below the camera at 4 m (elevation about -0.3 rad, e.g. a red poster near the floor) is
    // left out by the cut and found by the full pass: the rows really are skipped.
    const Scene low = portraitScene(4.0, 0.1, pitch, 5, -1.5);
    ASSERT_TRUE(low.truth.visible);
    RawPyramid rawLow(low.rgbRaw);
    EXPECT_EQ(d.coarseCandidates(rawLow, low.unrolling, UnetParams{}, std::nan("")).size(), 1u);
    EXPECT_TRUE(d.coarseCandidates(rawLow, low.unrolling, UnetParams{}, pitch).empty());
    UnetParams off;
    off.coarseMinElevationRad = std::nan("");
    EXPECT_EQ(d.coarseCandidates(rawLow, low.unrolling, off, pitch).size(), 1u);
    // Camera looking steeply down (pitch -1.2 rad): every row is below the cut, the pass is skipped.
    EXPECT_TRUE(d.coarseCandidates(rawLow, low.unrolling, UnetParams{}, -1.2).empty());
    EXPECT_EQ(d.coarseCandidates(rawLow, low.unrolling, off, -1.2).size(), 1u);
}

class UnetRange : public ::testing::TestWithParam<double> {};

TEST_P(UnetRange, ZoomedMaskGivesRangeWithinThreePercent) {
    const double rangeMeters = GetParam();
    const double pitch = 0.08;
    UnetDetector d = loadTiny();
    const Scene s = portraitScene(rangeMeters, 0.0, pitch, 17);
    ASSERT_TRUE(s.truth.visible);
    const std::vector<Detection> found = d.detect(s.rgbRaw, s.unrolling, UnetParams{});
    ASSERT_EQ(found.size(), 1u) << "range " << rangeMeters;
    const Detection& det = found[0];
    EXPECT_EQ(det.kind, "exit");
    EXPECT_GT(det.score, 0.8);
    const Intrinsics& k = s.unrolling.unrolledIntrinsics();
    // Truth: the sign straight ahead, so its centre column is the principal column.
    EXPECT_NEAR(det.measurement.centerColumnPx, k.cx, 2.0);
    const double z = rangeFromApparentHeight(0.21, det.measurement.medianBottomEdgePx, det.measurement.medianHeightPx,
                                             k.fy, k.cy, pitch);
    EXPECT_NEAR(z, rangeMeters, 0.03 * rangeMeters) << "height " << det.measurement.medianHeightPx;
}

INSTANTIATE_TEST_SUITE_P(Ranges, UnetRange, ::testing::Values(2.0, 4.0, 6.0, 9.0));

TEST(UnetDetector, SignFreeFrameGivesNothing) {
    UnetDetector d = loadTiny();
    synthetic::Camera cam;
    cv::Mat rgb;
    cv::cvtColor(synthetic::renderBackground(cam, 3), rgb, cv::COLOR_BGR2RGB);
    const Unrolling u = Unrolling::forRoll(cam.rollRad, {cam.fx, cam.fy, cam.cx, cam.cy}, rgb.size());
    EXPECT_TRUE(d.detect(rgb, u, UnetParams{}).empty());
}

TEST(UnetDetector, TwoSignsGiveTwoDetections) {
    UnetDetector d = loadTiny();
    synthetic::Camera cam;
    cam.rollRad = 0;
    cv::Mat bgr = synthetic::renderBackground(cam, 9);
    synthetic::SignPlacement a, b;
    a.style = b.style = synthetic::SignStyle::WhiteLettersOnRed;
    a.rangeMeters = 3;
    a.bearingRad = 0.3;
    b.rangeMeters = 5;
    b.bearingRad = -0.3;
    ASSERT_TRUE(synthetic::drawSign(bgr, cam, a).visible);
    ASSERT_TRUE(synthetic::drawSign(bgr, cam, b).visible);
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    const Unrolling upright = Unrolling::forRoll(0.0, {cam.fx, cam.fy, cam.cx, cam.cy}, rgb.size());
    const std::vector<Detection> found = d.detect(rgb, upright, UnetParams{});
    ASSERT_EQ(found.size(), 2u);
    // The nearer sign (left, bearing +0.3 => smaller u) is the taller one.
    const Detection& left = found[0].measurement.centerColumnPx < found[1].measurement.centerColumnPx ? found[0] : found[1];
    const Detection& right = &left == &found[0] ? found[1] : found[0];
    EXPECT_GT(left.measurement.medianHeightPx, right.measurement.medianHeightPx * 1.5);
}

TEST(UnetDetector, SamplingFromRawEqualsUnrollingThenCropping) {
    // A smooth raw image; a 224 x 224 sample of the unrolled region starting at unrolled pixel (100, 200),
    // one unrolled pixel per network pixel, equals the explicitly unrolled image's crop (bilinear, +-2).
    cv::Mat raw(480, 640, CV_8UC3);
    for (int v = 0; v < raw.rows; ++v)
        for (int c = 0; c < raw.cols; ++c)
            raw.at<cv::Vec3b>(v, c) = cv::Vec3b(cv::saturate_cast<uchar>(128 + 100 * std::sin(c / 25.0)),
                                                cv::saturate_cast<uchar>(128 + 100 * std::cos(v / 30.0)), 60);
    for (double roll : {-1.5707963267948966, 0.4}) {
        const Unrolling u = Unrolling::forRoll(roll, {500, 500, 319.5, 239.5}, raw.size());
        const cv::Mat unrolled = u.apply(raw);
        RawPyramid pyramid(raw);
        const cv::Mat sample = sampleUnrolled(pyramid, u, {99.5, 199.5}, 1.0, 1.0, 224);
        cv::Mat diff;
        cv::absdiff(sample(cv::Rect(2, 2, 220, 220)), unrolled(cv::Rect(102, 202, 220, 220)), diff);
        double maxDiff;
        cv::minMaxLoc(diff.reshape(1), nullptr, &maxDiff);
        EXPECT_LE(maxDiff, 2.0) << "roll " << roll;
    }
}

TEST(UnetDetector, SamplingABgraFrameGivesTheRgbFramesBytes) {
    // The phone's BGRA frame is sampled as it is and only the small network input is converted: every pyramid
    // level the samples are drawn from (upscaled, 1:1, halved twice) gives the same bytes as the RGB frame.
    cv::Mat rgb(480, 640, CV_8UC3);
    cv::RNG rng(3);
    rng.fill(rgb, cv::RNG::UNIFORM, 0, 256);
    cv::GaussianBlur(rgb, rgb, cv::Size(5, 5), 1.5);
    cv::Mat bgra;
    cv::cvtColor(rgb, bgra, cv::COLOR_RGB2BGRA);
    const Unrolling u = Unrolling::forRoll(0.4, {500, 500, 319.5, 239.5}, rgb.size());
    RawPyramid fromRgb(rgb), fromBgra(bgra);
    EXPECT_FALSE(fromRgb.bgra());
    EXPECT_TRUE(fromBgra.bgra());
    for (double scale : {0.5, 1.0, 2.5, 4.5}) {
        const cv::Mat a = sampleUnrolled(fromRgb, u, {20.5, 10.5}, scale, scale, 96);
        const cv::Mat b = sampleUnrolled(fromBgra, u, {20.5, 10.5}, scale, scale, 96);
        ASSERT_EQ(b.type(), CV_8UC3) << scale;
        EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0) << "scale " << scale;
    }
}

TEST(UnetVerification, TinyBlobFarFromSignAspectIsRejected) {
    UnetParams params;
    const double fy = 1602;
    SliceMeasurement m;
    m.valid = true;
    // A 3 px tall sliver, 1 px wide: not an Exit sign at any plausible range.
    m.medianHeightPx = 3;
    m.extentWidthPx = 1;
    EXPECT_EQ(verifyZoomedSign(m, 0.99, fy, params), UnetVerdict::kImplausibleAspect);
    // Sign-like aspect but only 3 px tall: a 0.12 m face would be beyond 20 m.
    m.extentWidthPx = 4.5;
    EXPECT_EQ(verifyZoomedSign(m, 0.99, fy, params), UnetVerdict::kImplausibleHeight);
    // Taller than a 0.5 m face at 0.5 m.
    m.medianHeightPx = 2000;
    m.extentWidthPx = 3000;
    EXPECT_EQ(verifyZoomedSign(m, 0.99, fy, params), UnetVerdict::kImplausibleHeight);
    // A plausible shape with a weak mask.
    m.medianHeightPx = 40;
    m.extentWidthPx = 62;
    EXPECT_EQ(verifyZoomedSign(m, 0.7, fy, params), UnetVerdict::kLowProbability);
}

TEST(UnetVerification, FarSmallSignIsAccepted) {
    UnetParams params;
    const double fy = 1602;
    SliceMeasurement m;
    m.valid = true;
    // A 0.21 x 0.33 m Exit sign at 15 m: 22.4 x 35 px; turned 50 degrees: 22.4 x 23 px.
    m.medianHeightPx = fy * 0.21 / 15;
    m.extentWidthPx = fy * 0.33 / 15;
    EXPECT_EQ(verifyZoomedSign(m, 0.95, fy, params), UnetVerdict::kAccepted);
    m.extentWidthPx = fy * 0.33 * std::cos(50 * CV_PI / 180) / 15;
    EXPECT_EQ(verifyZoomedSign(m, 0.95, fy, params), UnetVerdict::kAccepted);
}

TEST(UnetVerification, AClassCheckReplacesTheExitLimitsForItsClassOnly) {
    // A white-on-dark square pictogram (0.23 m) 3 m away, turned 55 degrees: aspect 0.57, no chroma.
    UnetParams params;
    params.classLimits.resize(3);
    UnetSignLimits square;
    square.minAspect = 0.4;
    square.maxAspect = 1.9;
    square.minSignHeightM = 0.13;
    square.maxSignHeightM = 0.55;
    square.minColourFraction = 0;
    params.classLimits[2] = square;
    const double fy = 1602;
    SliceMeasurement m;
    m.valid = true;
    m.medianHeightPx = fy * 0.23 / 3;
    m.extentWidthPx = m.medianHeightPx * std::cos(55 * CV_PI / 180);
    const double colourless = 0.0;
    // The Exit sign's limits (class 1, and class 0 / out-of-range indices) refuse it twice over.
    for (int c : {0, 1, 5, -1}) {
        const UnetParams p = params.forClass(c);
        EXPECT_DOUBLE_EQ(p.limits.minAspect, 0.8) << c;
        EXPECT_EQ(verifyZoomedSign(m, 0.95, fy, p, colourless), UnetVerdict::kColourless) << c;
        EXPECT_EQ(verifyZoomedSign(m, 0.95, fy, p), UnetVerdict::kImplausibleAspect) << c;
    }
    // Its own class's limits accept it; the probability threshold and range limits still apply.
    const UnetParams own = params.forClass(2);
    EXPECT_EQ(verifyZoomedSign(m, 0.95, fy, own, colourless), UnetVerdict::kAccepted);
    EXPECT_EQ(verifyZoomedSign(m, 0.7, fy, own, colourless), UnetVerdict::kLowProbability);
    SliceMeasurement far = m;
    far.medianHeightPx = fy * 0.23 / 40;  // a 0.13 m face would be beyond 20 m
    far.extentWidthPx = far.medianHeightPx;
    EXPECT_EQ(verifyZoomedSign(far, 0.95, fy, own, colourless), UnetVerdict::kImplausibleHeight);
    // An unset entry keeps the Exit limits.
    params.classLimits[2].reset();
    EXPECT_EQ(verifyZoomedSign(m, 0.95, fy, params.forClass(2)), UnetVerdict::kImplausibleAspect);
}

TEST(UnetDetector, FarBandPassFindsAFarSignAndNeedsThePitch) {
    UnetDetector d = loadTiny();
    const double pitch = 0.05;
    const Scene s = portraitScene(9.0, 0.1, pitch, 23);
    ASSERT_TRUE(s.truth.visible);
    RawPyramid raw(s.rgbRaw);
    UnetParams params;
    const std::vector<UnetCandidate> band = d.farBandCandidates(raw, s.unrolling, params, pitch);
    ASSERT_EQ(band.size(), 1u);
    double minX = 1e9, maxX = -1e9;
    for (const auto& p : s.truth.cornersRaw) {
        const cv::Point2d q = s.unrolling.rawToUnrolled(p);
        minX = std::min(minX, q.x);
        maxX = std::max(maxX, q.x);
    }
    // Twice the coarse resolution: the blob's left edge within ~2 band pixels (~9 unrolled px).
    EXPECT_NEAR(band[0].boxInUnrolled.x, minX, 10);
    EXPECT_TRUE(d.farBandCandidates(raw, s.unrolling, params, std::nan("")).empty());
    params.farBand = false;
    EXPECT_TRUE(d.farBandCandidates(raw, s.unrolling, params, pitch).empty());
    // The full pipeline with the pitch reports the sign once (coarse and band blobs merged).
    EXPECT_EQ(d.detect(s.rgbRaw, s.unrolling, UnetParams{}, pitch).size(), 1u);
}

// The colour check: a grey ceiling light the network took for a sign has no chroma under its mask, a red sign
// face has plenty; an empty mask counts as colourless.
TEST(UnetVerification, ColourlessMaskIsRejected) {
    cv::Mat rgb(40, 80, CV_8UC3, cv::Scalar(200, 200, 200));
    cv::rectangle(rgb, cv::Rect(0, 0, 40, 40), cv::Scalar(220, 30, 30), cv::FILLED);  // left half red (RGB)
    cv::Mat mask = cv::Mat::zeros(40, 80, CV_8UC1);
    cv::Mat left = mask.clone(), right = mask.clone();
    left(cv::Rect(0, 0, 40, 40)).setTo(255);
    right(cv::Rect(40, 0, 40, 40)).setTo(255);
    EXPECT_DOUBLE_EQ(colourfulFraction(rgb, left, 20), 1.0);
    EXPECT_DOUBLE_EQ(colourfulFraction(rgb, right, 20), 0.0);
    EXPECT_DOUBLE_EQ(colourfulFraction(rgb, mask, 20), 0.0);
    UnetParams params;
    SliceMeasurement m;
    m.valid = true;
    m.medianHeightPx = 40;
    m.extentWidthPx = 62;
    EXPECT_EQ(verifyZoomedSign(m, 0.99, 1602, params, colourfulFraction(rgb, right, params.colourChromaLevels)),
              UnetVerdict::kColourless);
    EXPECT_EQ(verifyZoomedSign(m, 0.99, 1602, params, colourfulFraction(rgb, left, params.colourChromaLevels)),
              UnetVerdict::kAccepted);
}
