// Tests of src/image_input: pixel formats and bad-frame checks.
#include "image_input.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

using namespace wf::sign;

namespace {

struct OwnedFrame {
    std::vector<uint8_t> pixels;
    wf_frame frame{};
};

/// A VGA gray frame of constant luma with matching intrinsics, upright.
OwnedFrame grayFrame(uint8_t luma = 120, int width = 640, int height = 480) {
    OwnedFrame f;
    f.pixels.assign(size_t(width) * height, luma);
    f.frame.image = wf_image{f.pixels.data(), width, height, size_t(width), WF_PIXEL_GRAY8, nullptr, 0};
    f.frame.intrinsics = wf_intrinsics{534, 534, (width - 1) / 2.0, (height - 1) / 2.0};
    f.frame.pitch_rad = 0.05;
    f.frame.roll_rad = -1.5707963267948966;
    return f;
}

}  // namespace

TEST(FrameCheck, AcceptsAGoodFrame) {
    OwnedFrame f = grayFrame();
    EXPECT_TRUE(checkFrame(f.frame).ok()) << checkFrame(f.frame).message;
}

TEST(FrameCheck, RejectsEmptyFrames) {
    OwnedFrame f = grayFrame();
    f.frame.image.data = nullptr;
    FrameCheck c = checkFrame(f.frame);
    EXPECT_EQ(c.status, WF_STATUS_BAD_FRAME);
    EXPECT_NE(c.message.find("empty"), std::string::npos);
    f = grayFrame();
    f.frame.image.width = 0;
    EXPECT_EQ(checkFrame(f.frame).status, WF_STATUS_BAD_FRAME);
    f = grayFrame();
    f.frame.image.stride = 100;
    EXPECT_NE(checkFrame(f.frame).message.find("stride"), std::string::npos);
    f = grayFrame();
    const int bogus = 42;  // what a C caller may store in the enum field
    std::memcpy(&f.frame.image.format, &bogus, sizeof bogus);
    EXPECT_EQ(checkFrame(f.frame).status, WF_STATUS_INVALID_ARGUMENT);
}

TEST(FrameCheck, RejectsIntrinsicsOfAnotherResolution) {
    OwnedFrame f = grayFrame();
    f.frame.intrinsics = wf_intrinsics{1602, 1602, 959.5, 719.5};  // 1920 x 1440 intrinsics on a VGA image
    const FrameCheck c = checkFrame(f.frame);
    EXPECT_EQ(c.status, WF_STATUS_BAD_FRAME);
    EXPECT_NE(c.message.find("another resolution"), std::string::npos) << c.message;
}

TEST(FrameCheck, RejectsNonFiniteGeometry) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    OwnedFrame f = grayFrame();
    f.frame.intrinsics.fx = nan;
    EXPECT_NE(checkFrame(f.frame).message.find("non-finite intrinsics"), std::string::npos);
    f = grayFrame();
    f.frame.intrinsics.fy = -3;
    EXPECT_NE(checkFrame(f.frame).message.find("positive"), std::string::npos);
    f = grayFrame();
    f.frame.pitch_rad = nan;
    EXPECT_NE(checkFrame(f.frame).message.find("pitch"), std::string::npos);
    f = grayFrame();
    f.frame.pitch_rad = 2.0;
    EXPECT_EQ(checkFrame(f.frame).status, WF_STATUS_BAD_FRAME);
    f = grayFrame();
    f.frame.roll_rad = inf;
    EXPECT_NE(checkFrame(f.frame).message.find("roll"), std::string::npos);
}

TEST(FrameCheck, SkipsBlackFrames) {
    OwnedFrame f = grayFrame(1);
    EXPECT_EQ(checkBrightness(toGray(f.frame.image)).status, WF_STATUS_SKIPPED_DARK_FRAME);
    f = grayFrame(3);
    EXPECT_TRUE(checkBrightness(toGray(f.frame.image)).ok());
}

TEST(FrameCheck, BrightnessReadFromTheImageIsTheGrayFramesToTheBit) {
    // Dark frames (luma about 0-4, so the verdict's message carries the mean) of odd sizes, in every colour layout:
    // the check that samples the caller's image without converting it reports exactly the gray frame's mean.
    cv::RNG rng(7);
    for (const cv::Size size : {cv::Size(17, 9), cv::Size(640, 480), cv::Size(1921, 1443)}) {
        cv::Mat bgr(size, CV_8UC3);
        rng.fill(bgr, cv::RNG::UNIFORM, 0, 5);
        cv::Mat rgb, bgra;
        cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
        cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
        for (const wf_image image : {wf_image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0},
                                     wf_image{bgra.data, bgra.cols, bgra.rows, bgra.step, WF_PIXEL_BGRA8, nullptr, 0}}) {
            const FrameCheck fromGray = checkBrightness(toGray(image)), fromImage = checkBrightness(image);
            EXPECT_EQ(fromImage.status, fromGray.status) << size;
            EXPECT_EQ(fromImage.message, fromGray.message) << size;
        }
    }
    const OwnedFrame bright = grayFrame(3), dark = grayFrame(1);
    EXPECT_TRUE(checkBrightness(bright.frame.image).ok());
    EXPECT_EQ(checkBrightness(dark.frame.image).status, WF_STATUS_SKIPPED_DARK_FRAME);
}

TEST(ImageInput, TheNetworksColourLayoutWrapsThePhonesFrames) {
    cv::Mat bgra(2, 3, CV_8UC4, cv::Scalar(10, 20, 30, 255)), rgb(2, 3, CV_8UC3, cv::Scalar(30, 20, 10));
    const wf_image bgraImage{bgra.data, 3, 2, bgra.step, WF_PIXEL_BGRA8, nullptr, 0};
    const wf_image rgbImage{rgb.data, 3, 2, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    EXPECT_EQ(toNetworkColour(bgraImage).data, bgra.data);  // wrapped, not converted
    EXPECT_EQ(toNetworkColour(bgraImage).type(), CV_8UC4);
    EXPECT_EQ(toNetworkColour(rgbImage).data, rgb.data);
    std::vector<uint8_t> y(6, 50);
    const wf_image gray{y.data(), 3, 2, 3, WF_PIXEL_GRAY8, nullptr, 0};
    EXPECT_EQ(toNetworkColour(gray).type(), CV_8UC3);  // other layouts become RGB
    EXPECT_EQ(toNetworkColour(gray).at<cv::Vec3b>(1, 2), cv::Vec3b(50, 50, 50));
    const wf_image view = grayImageView(cv::Mat(2, 3, CV_8UC1, y.data()));
    EXPECT_EQ(view.format, WF_PIXEL_GRAY8);
    EXPECT_EQ(view.data, y.data());
    EXPECT_EQ(view.stride, 3u);
}

TEST(ImageInput, ConvertsEveryPixelFormat) {
    // A 4 x 2 BGR image: red, green, blue, white / black, gray, yellow, cyan.
    const cv::Mat bgr = (cv::Mat_<cv::Vec3b>(2, 4) << cv::Vec3b(0, 0, 255), cv::Vec3b(0, 255, 0), cv::Vec3b(255, 0, 0),
                         cv::Vec3b(255, 255, 255), cv::Vec3b(0, 0, 0), cv::Vec3b(128, 128, 128),
                         cv::Vec3b(0, 255, 255), cv::Vec3b(255, 255, 0));
    cv::Mat expectedGray, rgb, bgra;
    cv::cvtColor(bgr, expectedGray, cv::COLOR_BGR2GRAY);
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);

    const wf_image bgraImage{bgra.data, 4, 2, bgra.step, WF_PIXEL_BGRA8, nullptr, 0};
    EXPECT_EQ(cv::norm(toGray(bgraImage), expectedGray, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(toRgb(bgraImage), rgb, cv::NORM_INF), 0);
    const wf_image rgbImage{rgb.data, 4, 2, rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    EXPECT_EQ(cv::norm(toGray(rgbImage), expectedGray, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(toRgb(rgbImage), rgb, cv::NORM_INF), 0);
}

TEST(ImageInput, Nv12UsesTheLumaPlaneAndFullRangeChroma) {
    // 4 x 2 luma 100; chroma pairs (Cb, Cr): neutral, then strong red (Cr = 228).
    std::vector<uint8_t> y(8, 100);
    std::vector<uint8_t> uv = {128, 128, 128, 228};
    const wf_image nv12{y.data(), 4, 2, 4, WF_PIXEL_NV12, uv.data(), 4};
    const cv::Mat gray = toGray(nv12);
    EXPECT_EQ(gray.data, y.data());  // wrapped, not copied
    const cv::Mat rgb = toRgb(nv12);
    EXPECT_EQ(rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(100, 100, 100));
    const cv::Vec3b red = rgb.at<cv::Vec3b>(1, 3);
    EXPECT_EQ(red[0], 240);                    // 100 + 1.402 * 100 = 240.2
    EXPECT_EQ(red[1], 29);                     // 100 - 0.714136 * 100 = 28.6
    EXPECT_EQ(red[2], 100);
    const wf_image lumaOnly{y.data(), 4, 2, 4, WF_PIXEL_NV12, nullptr, 0};
    EXPECT_EQ(toRgb(lumaOnly).at<cv::Vec3b>(1, 1), cv::Vec3b(100, 100, 100));
}
