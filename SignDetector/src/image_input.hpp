// Conversion of caller-owned frames (wf_image: GRAY8, BGRA8, RGB8, NV12) into OpenCV matrices, and the
// checks that reject bad frames before any processing.
#pragma once

#include "wf_sign_detector.h"

#include <opencv2/core.hpp>

#include <cstring>
#include <string>

namespace wf::sign {

/// Outcome of a frame check: a wf status code (WF_STATUS_OK, WF_STATUS_SKIPPED_DARK_FRAME or WF_STATUS_BAD_FRAME /
/// WF_STATUS_INVALID_ARGUMENT) and a message naming the problem.
struct FrameCheck {
    int status = WF_STATUS_OK;
    std::string message;
    bool ok() const { return status == WF_STATUS_OK; }
};

/// Checks the image description alone: non-NULL data, positive size, stride large enough, known format,
/// NV12 chroma stride. Does not read pixels.
FrameCheck checkImage(const wf_image& image);

/// Checks a whole frame: the image (checkImage), finite positive focal lengths, finite principal point
/// inside the central half of the image in each axis (otherwise the intrinsics belong to another
/// resolution), finite pitch with |pitch| < pi/2, finite roll.
FrameCheck checkFrame(const wf_frame& frame);

/// Mean luma under which a frame is skipped as dark (lens covered, phone in a pocket).
constexpr double kDarkFrameMeanLuma = 2.0;

/// Checks the gray image's mean (sampled every 4th pixel): WF_STATUS_SKIPPED_DARK_FRAME when below
/// kDarkFrameMeanLuma.
FrameCheck checkBrightness(const cv::Mat& gray);

/// The same check read straight from the caller's image: the pixels it samples (every 4th row and column from
/// the first) are converted to gray as toGray converts them, so the mean is exactly that of
/// checkBrightness(toGray(image)) without converting the whole frame (1.9 ms per 1920 x 1440 BGRA frame here).
FrameCheck checkBrightness(const wf_image& image);

/// Wraps (no copy) or converts the image to 8-bit gray: GRAY8 and NV12 (Y plane) are wrapped; BGRA8 and
/// RGB8 are converted (ITU-R BT.601 luma, cv::cvtColor).
cv::Mat toGray(const wf_image& image);

/// The image as 8-bit RGB: RGB8 is wrapped (no copy; treat as read-only), other formats converted. NV12 uses full-range BT.601 (JPEG) coefficients, as ARKit
/// delivers; NV12 without chroma and GRAY8 give R = G = B = luma.
cv::Mat toRgb(const wf_image& image);

/// The image in a colour layout the U-Net's sampler reads (RawPyramid): BGRA8 wrapped as CV_8UC4 (B, G, R, A;
/// no copy), RGB8 wrapped as CV_8UC3; other formats converted to RGB (toRgb). Read-only.
cv::Mat toNetworkColour(const wf_image& image);

/// A GRAY8 wf_image viewing `gray` (CV_8UC1, continuous or not; borrowed: keep `gray` alive while it is used).
wf_image grayImageView(const cv::Mat& gray);

/// Bytes per pixel of the first plane of `format` (a wf_pixel_format value), or 0 if unknown.
int bytesPerPixel(int format);

/// The integer a C caller stored in an enum-typed field or argument. C allows any int there; reading an
/// out-of-range value through the C++ enum type is undefined behaviour, so values from the C side are read
/// as int before they are checked.
template <class E>
int enumValue(const E& e) {
    static_assert(sizeof(E) == sizeof(int), "C enums are int-sized on supported ABIs");
    int v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

}  // namespace wf::sign
