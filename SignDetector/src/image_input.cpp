#include "image_input.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace wf::sign {

int bytesPerPixel(int format) {
    switch (format) {
        case WF_PIXEL_GRAY8: return 1;
        case WF_PIXEL_BGRA8: return 4;
        case WF_PIXEL_RGB8: return 3;
        case WF_PIXEL_NV12: return 1;
    }
    return 0;
}

FrameCheck checkImage(const wf_image& image) {
    std::ostringstream msg;
    const int format = enumValue(image.format);
    const int bpp = bytesPerPixel(format);
    if (bpp == 0) {
        msg << "unknown pixel format " << format;
        return {WF_STATUS_INVALID_ARGUMENT, msg.str()};
    }
    if (image.data == nullptr || image.width <= 0 || image.height <= 0) {
        msg << "empty frame: data " << (image.data ? "set" : "NULL") << ", size " << image.width << "x"
            << image.height;
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    if (image.stride < static_cast<size_t>(image.width) * bpp) {
        msg << "row stride " << image.stride << " bytes is smaller than width " << image.width << " x " << bpp
            << " bytes per pixel";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    const size_t rowBytes = static_cast<size_t>(image.width) * bpp;
    const size_t needed = image.stride * static_cast<size_t>(image.height - 1) + rowBytes;
    if (image.data_bytes != 0 && image.data_bytes < needed) {
        msg << "pixel buffer of " << image.data_bytes << " bytes is shorter than the " << image.width << "x"
            << image.height << " frame it describes (" << needed << " bytes at stride " << image.stride
            << "): wrong size or stride";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    if (format == WF_PIXEL_NV12 && image.data_uv != nullptr) {
        const size_t need = 2 * static_cast<size_t>((image.width + 1) / 2);
        if (image.stride_uv < need) {
            msg << "NV12 chroma stride " << image.stride_uv << " bytes is smaller than " << need;
            return {WF_STATUS_BAD_FRAME, msg.str()};
        }
        const size_t chromaRows = static_cast<size_t>((image.height + 1) / 2);
        const size_t neededUv = image.stride_uv * (chromaRows - 1) + need;
        if (image.data_uv_bytes != 0 && image.data_uv_bytes < neededUv) {
            msg << "NV12 chroma buffer of " << image.data_uv_bytes << " bytes is shorter than the " << neededUv
                << " bytes of " << chromaRows << " rows at stride " << image.stride_uv << ": wrong size or stride";
            return {WF_STATUS_BAD_FRAME, msg.str()};
        }
    }
    return {};
}

FrameCheck checkFrame(const wf_frame& frame) {
    FrameCheck imageCheck = checkImage(frame.image);
    if (!imageCheck.ok()) return imageCheck;
    const wf_intrinsics& k = frame.intrinsics;
    std::ostringstream msg;
    if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
        msg << "non-finite intrinsics (fx " << k.fx << ", fy " << k.fy << ", cx " << k.cx << ", cy " << k.cy << ")";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    if (k.fx <= 0 || k.fy <= 0) {
        msg << "focal lengths must be positive (fx " << k.fx << ", fy " << k.fy << ")";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    const double w = frame.image.width, h = frame.image.height;
    if (std::abs(k.cx - 0.5 * (w - 1)) > 0.25 * w || std::abs(k.cy - 0.5 * (h - 1)) > 0.25 * h) {
        msg << "principal point (" << k.cx << ", " << k.cy << ") is far from the centre of the "
            << frame.image.width << "x" << frame.image.height
            << " image: the intrinsics belong to another resolution (scale them with the image)";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    if (!std::isfinite(frame.pitch_rad) || std::abs(frame.pitch_rad) >= 1.5707963267948966) {
        msg << "pitch " << frame.pitch_rad << " rad is not finite or not in (-pi/2, pi/2)";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    if (!std::isfinite(frame.roll_rad)) {
        msg << "roll " << frame.roll_rad << " rad is not finite";
        return {WF_STATUS_BAD_FRAME, msg.str()};
    }
    return {};
}

namespace {
/// The verdict on a frame's sampled mean luma.
FrameCheck darkFrameCheck(double meanLuma) {
    if (meanLuma < kDarkFrameMeanLuma) {
        std::ostringstream msg;
        msg << "frame skipped: mean luma " << meanLuma << " < " << kDarkFrameMeanLuma << " (lens covered or dark)";
        return {WF_STATUS_SKIPPED_DARK_FRAME, msg.str()};
    }
    return {};
}
}  // namespace

FrameCheck checkBrightness(const cv::Mat& gray) {
    CV_Assert(gray.type() == CV_8UC1);
    uint64_t sum = 0, n = 0;
    for (int r = 0; r < gray.rows; r += 4) {
        const uchar* row = gray.ptr<uchar>(r);
        for (int c = 0; c < gray.cols; c += 4) {
            sum += row[c];
            ++n;
        }
    }
    return darkFrameCheck(n ? double(sum) / double(n) : 0.0);
}

namespace {
cv::Mat wrap(const wf_image& image, int type) {
    return cv::Mat(image.height, image.width, type, const_cast<uint8_t*>(image.data), image.stride);
}
}  // namespace

FrameCheck checkBrightness(const wf_image& image) {
    const int channels = bytesPerPixel(enumValue(image.format));  // 8-bit channels of the first plane
    if (channels != 3 && channels != 4) return checkBrightness(wrap(image, CV_8UC1));  // GRAY8, NV12's Y plane
    // Every 4th pixel of every 4th row, in the image's own layout, then one small conversion.
    const int rows = (image.height + 3) / 4, cols = (image.width + 3) / 4;
    cv::Mat samples(rows, cols, CV_8UC(channels));
    for (int r = 0; r < rows; ++r) {
        const uint8_t* src = image.data + size_t(4 * r) * image.stride;
        uint8_t* dst = samples.ptr<uint8_t>(r);
        for (int c = 0; c < cols; ++c) std::memcpy(dst + c * channels, src + size_t(4 * c) * channels, channels);
    }
    cv::Mat gray;
    cv::cvtColor(samples, gray, channels == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_RGB2GRAY);
    uint64_t sum = 0;
    for (int r = 0; r < gray.rows; ++r) {
        const uchar* row = gray.ptr<uchar>(r);
        for (int c = 0; c < gray.cols; ++c) sum += row[c];
    }
    return darkFrameCheck(gray.total() ? double(sum) / double(gray.total()) : 0.0);
}

namespace {
inline uint8_t clamp8(double v) { return static_cast<uint8_t>(std::min(255.0, std::max(0.0, v + 0.5))); }
}  // namespace

cv::Mat toGray(const wf_image& image) {
    cv::Mat gray;
    switch (enumValue(image.format)) {
        case WF_PIXEL_GRAY8:
        case WF_PIXEL_NV12: return wrap(image, CV_8UC1);
        case WF_PIXEL_BGRA8: cv::cvtColor(wrap(image, CV_8UC4), gray, cv::COLOR_BGRA2GRAY); return gray;
        case WF_PIXEL_RGB8: cv::cvtColor(wrap(image, CV_8UC3), gray, cv::COLOR_RGB2GRAY); return gray;
    }
    CV_Error(cv::Error::StsBadArg, "unknown pixel format");
}

wf_image grayImageView(const cv::Mat& gray) {
    CV_Assert(gray.type() == CV_8UC1);
    wf_image view{};
    view.data = gray.data;
    view.width = gray.cols;
    view.height = gray.rows;
    view.stride = gray.step;
    view.format = WF_PIXEL_GRAY8;
    return view;
}

cv::Mat toNetworkColour(const wf_image& image) {
    switch (enumValue(image.format)) {
        case WF_PIXEL_BGRA8: return wrap(image, CV_8UC4);
        case WF_PIXEL_RGB8: return wrap(image, CV_8UC3);
        default: return toRgb(image);
    }
}

cv::Mat toRgb(const wf_image& image) {
    cv::Mat rgb;
    switch (enumValue(image.format)) {
        case WF_PIXEL_GRAY8: cv::cvtColor(wrap(image, CV_8UC1), rgb, cv::COLOR_GRAY2RGB); return rgb;
        case WF_PIXEL_BGRA8: cv::cvtColor(wrap(image, CV_8UC4), rgb, cv::COLOR_BGRA2RGB); return rgb;
        case WF_PIXEL_RGB8: return wrap(image, CV_8UC3);  // read-only use: no copy
        case WF_PIXEL_NV12: {
            if (image.data_uv == nullptr) {
                cv::cvtColor(wrap(image, CV_8UC1), rgb, cv::COLOR_GRAY2RGB);
                return rgb;
            }
            // Full-range BT.601: R = Y + 1.402 Cr', G = Y - 0.344136 Cb' - 0.714136 Cr', B = Y + 1.772 Cb'.
            rgb.create(image.height, image.width, CV_8UC3);
            for (int r = 0; r < image.height; ++r) {
                const uint8_t* y = image.data + r * image.stride;
                const uint8_t* uv = image.data_uv + (r / 2) * image.stride_uv;
                uint8_t* out = rgb.ptr<uint8_t>(r);
                for (int c = 0; c < image.width; ++c) {
                    const double cb = uv[2 * (c / 2)] - 128.0, cr = uv[2 * (c / 2) + 1] - 128.0;
                    const double luma = y[c];
                    out[3 * c + 0] = clamp8(luma + 1.402 * cr);
                    out[3 * c + 1] = clamp8(luma - 0.344136 * cb - 0.714136 * cr);
                    out[3 * c + 2] = clamp8(luma + 1.772 * cb);
                }
            }
            return rgb;
        }
    }
    CV_Error(cv::Error::StsBadArg, "unknown pixel format");
}

}  // namespace wf::sign
