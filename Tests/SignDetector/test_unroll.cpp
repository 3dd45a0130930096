// Tests of src/unroll: exact raw <-> unrolled maps, agreement with cv::rotate, level horizon.
#include "unroll.hpp"
#include "synthetic_scene.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

using wf::sign::Intrinsics;
using wf::sign::Unrolling;

namespace {
constexpr double kPi = 3.14159265358979323846;
const Intrinsics kIphone{1602.0, 1598.0, 959.5, 719.5};  // fx != fy on purpose
const cv::Size kRaw(1920, 1440);

cv::Mat randomImage(cv::Size size, uint32_t seed) {
    cv::Mat m(size, CV_8UC1);
    cv::RNG rng(seed);
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
    return m;
}
}  // namespace

TEST(Unroll, RollZeroIsIdentityAndSharesPixels) {
    const Unrolling u = Unrolling::forRoll(0.0, kIphone, kRaw);
    EXPECT_EQ(u.quarterTurns(), 0);
    EXPECT_EQ(u.unrolledSize(), kRaw);
    EXPECT_DOUBLE_EQ(u.unrolledIntrinsics().cx, kIphone.cx);
    EXPECT_DOUBLE_EQ(u.unrolledIntrinsics().fy, kIphone.fy);
    const cv::Mat raw = randomImage(kRaw, 1);
    EXPECT_EQ(u.apply(raw).data, raw.data);
    EXPECT_EQ(u.rawToUnrolled({12, 34}), cv::Point2d(12, 34));
}

TEST(Unroll, PortraitIsClockwiseQuarterTurnWithSwappedFocalLengths) {
    const Unrolling u = Unrolling::forRoll(-kPi / 2, kIphone, kRaw);
    EXPECT_EQ(u.quarterTurns(), 1);
    EXPECT_EQ(u.unrolledSize(), cv::Size(1440, 1920));
    const Intrinsics& k = u.unrolledIntrinsics();
    EXPECT_DOUBLE_EQ(k.fx, kIphone.fy);
    EXPECT_DOUBLE_EQ(k.fy, kIphone.fx);
    EXPECT_DOUBLE_EQ(k.cx, kRaw.height - 1 - kIphone.cy);
    EXPECT_DOUBLE_EQ(k.cy, kIphone.cx);
    // Raw left edge (world up in portrait) becomes the unrolled top.
    EXPECT_EQ(u.rawToUnrolled({0, 719}), cv::Point2d(720, 0));
}

class QuarterTurn : public ::testing::TestWithParam<double> {};

TEST_P(QuarterTurn, MapIsExactPixelPermutationMatchingCvRotate) {
    const double roll = GetParam();
    const cv::Size size(64, 48);
    const Intrinsics k{60, 58, 31.5, 23.5};
    const Unrolling u = Unrolling::forRoll(roll, k, size);
    ASSERT_GE(u.quarterTurns(), 0);
    const cv::Mat raw = randomImage(size, 7);
    const cv::Mat unrolled = u.apply(raw);
    ASSERT_EQ(unrolled.size(), u.unrolledSize());
    for (int v = 0; v < size.height; ++v) {
        for (int c = 0; c < size.width; ++c) {
            const cv::Point2d p = u.rawToUnrolled({double(c), double(v)});
            // Exact integers, inside the canvas, same pixel value, exact round trip.
            ASSERT_EQ(p.x, std::round(p.x));
            ASSERT_EQ(p.y, std::round(p.y));
            ASSERT_EQ(unrolled.at<uchar>(int(p.y), int(p.x)), raw.at<uchar>(v, c)) << "roll " << roll;
            ASSERT_EQ(u.unrolledToRaw(p), cv::Point2d(c, v));
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Rolls, QuarterTurn, ::testing::Values(0.0, -kPi / 2, kPi / 2, kPi, -kPi));

class RoundTrip : public ::testing::TestWithParam<double> {};

TEST_P(RoundTrip, RawToUnrolledToRawIsIdentity) {
    const Unrolling u = Unrolling::forRoll(GetParam(), kIphone, kRaw);
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> x(-0.5, kRaw.width - 0.5), y(-0.5, kRaw.height - 0.5);
    for (int i = 0; i < 1000; ++i) {
        const cv::Point2d p(x(rng), y(rng));
        const cv::Point2d q = u.unrolledToRaw(u.rawToUnrolled(p));
        EXPECT_NEAR(q.x, p.x, 1e-9);
        EXPECT_NEAR(q.y, p.y, 1e-9);
        // Every raw pixel lands on the canvas.
        const cv::Point2d r = u.rawToUnrolled(p);
        EXPECT_GE(r.x, -0.5 - 1e-9);
        EXPECT_GE(r.y, -0.5 - 1e-9);
        EXPECT_LE(r.x, u.unrolledSize().width - 0.5 + 1e-9);
        EXPECT_LE(r.y, u.unrolledSize().height - 0.5 + 1e-9);
    }
    // The principal point maps to the unrolled principal point.
    const cv::Point2d c = u.rawToUnrolled({kIphone.cx, kIphone.cy});
    EXPECT_NEAR(c.x, u.unrolledIntrinsics().cx, 1e-9);
    EXPECT_NEAR(c.y, u.unrolledIntrinsics().cy, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Rolls, RoundTrip,
                         ::testing::Values(0.0, -kPi / 2, kPi / 2, kPi / 6, -kPi / 6, -1.580, 2.5));

TEST(Unroll, ThirtyDegreesMakesTheHorizonLevel) {
    using namespace wf::sign::synthetic;
    Camera cam;
    cam.fx = cam.fy = 1602;
    cam.pitchRad = 0;
    cam.rollRad = kPi / 6;
    const Unrolling u = Unrolling::forRoll(cam.rollRad, {cam.fx, cam.fy, cam.cx, cam.cy}, cam.size);
    EXPECT_EQ(u.quarterTurns(), -1);
    // Far points on the horizon (y = 0) at several bearings: one unrolled row, the principal row.
    for (double bearing = -0.5; bearing <= 0.5; bearing += 0.1) {
        cv::Point2d raw;
        ASSERT_TRUE(projectToRaw(cam, {-100 * std::sin(bearing), 0, -100 * std::cos(bearing)}, &raw));
        const cv::Point2d p = u.rawToUnrolled(raw);
        EXPECT_NEAR(p.y, u.unrolledIntrinsics().cy, 1e-6) << "bearing " << bearing;
    }
    // A point 1 m up at 4 m, straight ahead: elevation atan(1/4) from the unrolled principal row.
    cv::Point2d raw;
    ASSERT_TRUE(projectToRaw(cam, {0, 1, -4}, &raw));
    const cv::Point2d p = u.rawToUnrolled(raw);
    EXPECT_NEAR(std::atan((u.unrolledIntrinsics().cy - p.y) / u.unrolledIntrinsics().fy), std::atan(0.25), 1e-9);
    EXPECT_NEAR(p.x, u.unrolledIntrinsics().cx, 1e-6);
}

TEST(Unroll, WarpedPixelsMatchTheMapAtThirtyDegrees) {
    const cv::Size size(320, 240);
    const Intrinsics k{300, 300, 159.5, 119.5};
    // Smooth image so that bilinear sampling is close to the analytic value.
    cv::Mat raw(size, CV_8UC1);
    for (int v = 0; v < size.height; ++v)
        for (int c = 0; c < size.width; ++c) raw.at<uchar>(v, c) = cv::saturate_cast<uchar>(128 + 100 * std::sin(c / 20.0) * std::cos(v / 15.0));
    const Unrolling u = Unrolling::forRoll(kPi / 6, k, size);
    const cv::Mat unrolled = u.apply(raw);
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> x(2, size.width - 3), y(2, size.height - 3);
    for (int i = 0; i < 200; ++i) {
        const int c = x(rng), v = y(rng);
        const cv::Point2d p = u.rawToUnrolled({double(c), double(v)});
        const int pu = int(std::lround(p.x)), pv = int(std::lround(p.y));
        // Value at the nearest unrolled pixel, compared with the raw image sampled at its exact preimage.
        const cv::Point2d back = u.unrolledToRaw({double(pu), double(pv)});
        const double expected = 128 + 100 * std::sin(back.x / 20.0) * std::cos(back.y / 15.0);
        EXPECT_NEAR(unrolled.at<uchar>(pv, pu), expected, 3.0);
    }
}

TEST(Unroll, SnapsNearQuarterTurnsOnlyWithinTolerance) {
    const Unrolling exact = Unrolling::forRoll(-1.580, kIphone, kRaw);
    EXPECT_EQ(exact.quarterTurns(), -1);
    EXPECT_DOUBLE_EQ(exact.appliedRollRad(), -1.580);
    const Unrolling snapped = Unrolling::forRoll(-1.580, kIphone, kRaw, 0.02);
    EXPECT_EQ(snapped.quarterTurns(), 1);
    EXPECT_DOUBLE_EQ(snapped.appliedRollRad(), -kPi / 2);
    EXPECT_EQ(Unrolling::forRoll(-1.580, kIphone, kRaw, 0.005).quarterTurns(), -1);
}

TEST(Unroll, GeneralAngleKeepsFocalLengthGeometricMean) {
    const Unrolling u = Unrolling::forRoll(0.3, kIphone, kRaw);
    EXPECT_NEAR(u.unrolledIntrinsics().fx, std::sqrt(kIphone.fx * kIphone.fy), 1e-9);
    EXPECT_NEAR(u.unrolledIntrinsics().fy, std::sqrt(kIphone.fx * kIphone.fy), 1e-9);
}

TEST(Unroll, RowAtElevationFollowsThePinholeModelAndStaysFinite) {
    const Intrinsics k{534, 530, 319.5, 239.5};
    EXPECT_DOUBLE_EQ(unrolledRowAtElevation(k, 0.0, 0.0), 239.5);   // the horizon through the principal point
    EXPECT_DOUBLE_EQ(unrolledRowAtElevation(k, 0.2, 0.2), 239.5);   // the optical axis at the pitch
    EXPECT_NEAR(unrolledRowAtElevation(k, 0.1, 0.0), 239.5 - 530 * std::tan(0.1), 1e-9);  // above: smaller v
    EXPECT_GT(unrolledRowAtElevation(k, -0.1, 0.0), 239.5);
    // Rays beside or behind the camera: clamped to +-1.5 rad, far outside the image but finite.
    EXPECT_TRUE(std::isfinite(unrolledRowAtElevation(k, 2.0, -1.0)));
    EXPECT_LT(unrolledRowAtElevation(k, 2.0, -1.0), -5000);
    EXPECT_GT(unrolledRowAtElevation(k, -2.0, 1.0), 5000);
}

TEST(Unroll, RegionWarpWritesOnlyTheRegionWithApplysPixels) {
    const cv::Size size(320, 240);
    const Intrinsics k{300, 300, 159.5, 119.5};
    cv::Mat raw(size, CV_8UC1);
    cv::randu(raw, 0, 256);
    for (double roll : {0.35, -kPi / 2}) {  // a general angle (warpAffine) and a quarter turn (pixel permutation)
        const Unrolling u = Unrolling::forRoll(roll, k, size);
        const cv::Mat whole = u.apply(raw);
        cv::Mat canvas(u.unrolledSize(), CV_8UC1, cv::Scalar(7));
        const cv::Rect region(40, 30, 90, 70);
        u.applyToRegion(raw, region, &canvas);
        // Inside: apply()'s pixels, up to warpAffine's fixed-point rounding of the sample position (1/32 px: a
        // level or two on random pixels); quarter turns exactly.
        cv::Mat diff;
        cv::absdiff(canvas(region), whole(region), diff);
        double maxDiff = 0;
        cv::minMaxLoc(diff, nullptr, &maxDiff);
        EXPECT_LE(maxDiff, roll == 0.35 ? 8.0 : 0.0) << "roll " << roll;
        EXPECT_LT(cv::mean(diff)[0], roll == 0.35 ? 0.5 : 1e-9) << "roll " << roll;
        // Outside: untouched.
        cv::Mat outside = canvas.clone();
        outside(region).setTo(7);
        EXPECT_EQ(cv::countNonZero(outside != 7), 0) << "roll " << roll;
        // A region partly outside the image is clipped; one wholly outside writes nothing.
        const cv::Mat before = canvas.clone();
        u.applyToRegion(raw, cv::Rect(5000, 5000, 10, 10), &canvas);
        EXPECT_EQ(cv::countNonZero(canvas != before), 0) << "roll " << roll;
        u.applyToRegion(raw, cv::Rect(-20, -20, 30, 30), &canvas);
        cv::absdiff(canvas(cv::Rect(0, 0, 10, 10)), whole(cv::Rect(0, 0, 10, 10)), diff);
        cv::minMaxLoc(diff, nullptr, &maxDiff);
        EXPECT_LE(maxDiff, roll == 0.35 ? 8.0 : 0.0) << "roll " << roll;
    }
}
