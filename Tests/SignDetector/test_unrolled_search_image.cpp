// Tests of src/unrolled_search_image.hpp (the wall kinds' search image in one resampling): the canvas fits the
// search size at every roll and is not needlessly small, pixels land where its geometry says, the result matches
// the three-step shrink-unroll-shrink it replaces, detections map back to the frame's unrolled pixels, bad input.
#include "search_frame.hpp"
#include "unrolled_search_image.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace wf::sign;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Intrinsics kFrameK{1602, 1604, 959.5, 719.5};  // iPhone-like, 1920 x 1440
const cv::Size kFrameSize(1920, 1440);

/// A frame's half-size copy with its pixel edges aligned (what the U-Net's pyramid holds).
cv::Mat halfOf(const cv::Mat& frame) {
    cv::Mat half;
    cv::resize(frame, half, cv::Size(frame.cols / 2, frame.rows / 2), 0, 0, cv::INTER_AREA);
    return half;
}

/// Search-image position of a frame raw pixel position: frame -> shrunk frame (pixel centres aligned) -> unrolled.
cv::Point2d toSearch(const UnrolledSearchImage& s, cv::Point2d frameRaw) {
    return s.unrolling().rawToUnrolled(
        cv::Point2d((frameRaw.x + 0.5) * s.scaleX() - 0.5, (frameRaw.y + 0.5) * s.scaleY() - 0.5));
}

}  // namespace

TEST(UnrolledSearchImage, CanvasFitsTheSearchSizeAtEveryRoll) {
    const cv::Mat half(720, 960, CV_8UC1, cv::Scalar(90));
    for (double roll : {0.0, -kPi / 2, -kPi / 2 + 0.09, 0.5, -2.5, kPi, 1.2}) {
        const UnrolledSearchImage s(half, kFrameSize, kFrameK, roll, 0.0, 640);
        const cv::Size canvas = s.image().size();
        EXPECT_EQ(canvas, s.unrolling().unrolledSize()) << roll;
        EXPECT_LE(std::max(canvas.width, canvas.height), 640) << roll;
        EXPECT_GE(std::max(canvas.width, canvas.height), 636) << roll;  // not needlessly small
        EXPECT_NEAR(s.scaleX(), s.scaleY(), 1e-3) << roll;
        EXPECT_EQ(s.image().type(), CV_8UC1);
    }
    // A quarter turn: the frame at VGA, turned (480 x 640); roll 0: VGA itself.
    const UnrolledSearchImage portrait(half, kFrameSize, kFrameK, -kPi / 2, 0.0, 640);
    EXPECT_EQ(portrait.image().size(), cv::Size(480, 640));
    EXPECT_EQ(UnrolledSearchImage(half, kFrameSize, kFrameK, 0.0, 0.0, 640).image().size(), cv::Size(640, 480));
    // 0.09 rad off upright: the whole rotated frame (534 x 680 at VGA scale) shrunk into 640 rows.
    const UnrolledSearchImage tilted(half, kFrameSize, kFrameK, -kPi / 2 + 0.09, 0.0, 640);
    EXPECT_EQ(tilted.image().rows, 640);
    EXPECT_LT(tilted.scaleX(), 640.0 / 1920.0);
}

TEST(UnrolledSearchImage, PixelsLandWhereItsGeometrySays) {
    // A bright 90 x 60 px plate on a dark frame; its centre and a point well outside it, mapped to the search image.
    cv::Mat frame(kFrameSize, CV_8UC1, cv::Scalar(20));
    const cv::Rect plate(1210, 400, 90, 60);
    frame(plate).setTo(230);
    const cv::Mat half = halfOf(frame);
    for (double roll : {0.0, -kPi / 2 + 0.09, 0.7}) {
        const UnrolledSearchImage s(half, kFrameSize, kFrameK, roll, 0.0, 640);
        const cv::Point2d centre = toSearch(s, cv::Point2d(plate.x + 0.5 * plate.width - 0.5, plate.y + 0.5 * plate.height - 0.5));
        ASSERT_TRUE(cv::Rect(0, 0, s.image().cols, s.image().rows).contains(cv::Point(centre)));
        EXPECT_GT(s.image().at<uint8_t>(cv::Point(int(std::lround(centre.x)), int(std::lround(centre.y)))), 220) << roll;
        const cv::Point2d outside = toSearch(s, cv::Point2d(plate.x - 60, plate.y + 30));
        EXPECT_LT(s.image().at<uint8_t>(cv::Point(int(std::lround(outside.x)), int(std::lround(outside.y)))), 30) << roll;
        // The plate's light above the background is centred on its mapped centre (to a tenth of a search pixel:
        // area averaging and the bilinear kernel are symmetric, so they keep the centroid).
        cv::Mat light;
        cv::subtract(s.image(), cv::Scalar(20), light);
        const cv::Moments m = cv::moments(light, false);
        ASSERT_GT(m.m00, 0);
        EXPECT_NEAR(m.m10 / m.m00, centre.x, 0.15) << roll;
        EXPECT_NEAR(m.m01 / m.m00, centre.y, 0.15) << roll;
    }
}

TEST(UnrolledSearchImage, MatchesShrinkingThenUnrollingThenShrinkingAgain) {
    // The three resamplings it replaces, on a smooth frame: the same image up to interpolation (a level or two).
    cv::Mat frame(kFrameSize, CV_8UC1);
    for (int r = 0; r < frame.rows; ++r)
        for (int c = 0; c < frame.cols; ++c)
            frame.at<uint8_t>(r, c) = uint8_t(128 + 60 * std::sin(c / 97.0) + 50 * std::cos(r / 71.0));
    const double roll = 0.4;
    const UnrolledSearchImage s(halfOf(frame), kFrameSize, kFrameK, roll, 0.0, 640);
    // Step by step: the frame at VGA, unrolled, its canvas shrunk to the fused image's size.
    const SearchFrame vga(wf_image{frame.data, frame.cols, frame.rows, frame.step, WF_PIXEL_GRAY8, nullptr, 0, 0, 0},
                          kFrameK, 640);
    const cv::Mat small(vga.image().height, vga.image().width, CV_8UC1, const_cast<uint8_t*>(vga.image().data),
                        vga.image().stride);
    const Unrolling u = Unrolling::forRoll(roll, vga.intrinsics(), small.size());
    cv::Mat stepwise;
    cv::resize(u.apply(small), stepwise, s.image().size(), 0, 0, cv::INTER_AREA);
    // Away from the canvas' black corners (the two canvases' edges differ by up to a pixel).
    cv::Mat inside;
    cv::threshold(stepwise, inside, 5, 255, cv::THRESH_BINARY);
    cv::erode(inside, inside, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(7, 7)));
    cv::Mat difference;
    cv::absdiff(s.image(), stepwise, difference);
    EXPECT_GT(cv::countNonZero(inside), s.image().total() / 2);
    EXPECT_LT(cv::mean(difference, inside)[0], 1.5);
    double maxDifference = 0;
    cv::minMaxLoc(difference, nullptr, &maxDifference, nullptr, nullptr, inside);
    EXPECT_LE(maxDifference, 6);
}

TEST(UnrolledSearchImage, DetectionsMapBackToTheFramesUnrolledPixels) {
    // A box found in the search image, mapped to the frame's unrolled pixels, lies on the same rays.
    const cv::Mat half(720, 960, CV_8UC1, cv::Scalar(0));
    for (double roll : {-kPi / 2, -kPi / 2 + 0.09, 0.7}) {
        const UnrolledSearchImage s(half, kFrameSize, kFrameK, roll, 0.0, 640);
        const Unrolling frameU = Unrolling::forRoll(roll, kFrameK, kFrameSize);
        Detection d;
        d.kind = "restroom";
        d.measurement = measureBox(cv::Rect(100, 50, 30, 20));
        const std::vector<Detection> mapped = mapToFrame({d}, s.scaleX(), s.scaleY(), s.unrolling(), frameU);
        ASSERT_EQ(mapped.size(), 1u);
        EXPECT_EQ(mapped[0].kind, "restroom");
        // The box's corner through the raw images: compare in frame raw pixels.
        const cv::Point2d searchRaw = s.unrolling().unrolledToRaw({d.measurement.box.x, d.measurement.box.y});
        const cv::Point2d frameRaw = frameU.unrolledToRaw({mapped[0].measurement.box.x, mapped[0].measurement.box.y});
        EXPECT_NEAR(frameRaw.x, (searchRaw.x + 0.5) / s.scaleX() - 0.5, 1e-6) << roll;
        EXPECT_NEAR(frameRaw.y, (searchRaw.y + 0.5) / s.scaleY() - 0.5, 1e-6) << roll;
        // Sizes scale by the frame's unrolled focal length over the search image's.
        const double scale = frameU.unrolledIntrinsics().fy / s.unrolling().unrolledIntrinsics().fy;
        EXPECT_NEAR(mapped[0].measurement.medianHeightPx, 20.0 * scale, 1e-3 * scale) << roll;
    }
}

TEST(UnrolledSearchImage, BadInputThrows) {
    const cv::Mat colour(720, 960, CV_8UC3, cv::Scalar::all(0));
    EXPECT_THROW(UnrolledSearchImage(colour, kFrameSize, kFrameK, 0.0, 0.0, 640), cv::Exception);
    EXPECT_THROW(UnrolledSearchImage(cv::Mat(), kFrameSize, kFrameK, 0.0, 0.0, 640), cv::Exception);
    const cv::Mat gray(720, 960, CV_8UC1, cv::Scalar(0));
    EXPECT_THROW(UnrolledSearchImage(gray, kFrameSize, kFrameK, 0.0, 0.0, 0), cv::Exception);
}
