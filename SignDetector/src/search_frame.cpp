#include "search_frame.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace wf::sign {

SearchFrame::SearchFrame(const wf_image& image, const Intrinsics& k, int maxLongSidePx) : image_(image), k_(k) {
    int type = CV_8UC1;
    switch (image.format) {
        case WF_PIXEL_BGRA8: type = CV_8UC4; break;
        case WF_PIXEL_RGB8: type = CV_8UC3; break;
        default: type = CV_8UC1; break;  // GRAY8, and the Y plane of NV12
    }
    const cv::Mat src(image.height, image.width, type, const_cast<uint8_t*>(image.data), image.stride);
    if (!shrinkFrom(src, src.size(), maxLongSidePx)) return;
    if (image.format == WF_PIXEL_NV12 && image.data_uv != nullptr) {
        const cv::Mat uv((image.height + 1) / 2, (image.width + 1) / 2, CV_8UC2, const_cast<uint8_t*>(image.data_uv),
                         image.stride_uv);
        cv::resize(uv, chroma_, cv::Size((image_.width + 1) / 2, (image_.height + 1) / 2), 0, 0, cv::INTER_AREA);
        image_.data_uv = chroma_.data;
        image_.stride_uv = chroma_.step;
        image_.data_uv_bytes = 0;
    }
}

SearchFrame::SearchFrame(const cv::Mat& source, cv::Size frameSize, const Intrinsics& k, int maxLongSidePx) : k_(k) {
    CV_Assert(source.depth() == CV_8U && (source.channels() == 1 || source.channels() == 3 || source.channels() == 4));
    image_ = wf_image{source.data, source.cols, source.rows, source.step,
                      source.channels() == 1 ? WF_PIXEL_GRAY8 : source.channels() == 3 ? WF_PIXEL_RGB8 : WF_PIXEL_BGRA8,
                      nullptr, 0, 0, 0};
    if (!shrinkFrom(source, frameSize, maxLongSidePx)) CV_Assert(source.size() == frameSize);  // the frame itself
}

bool SearchFrame::shrinkFrom(const cv::Mat& source, cv::Size frameSize, int maxLongSidePx) {
    const int longSide = std::max(frameSize.width, frameSize.height);
    if (maxLongSidePx <= 0 || longSide <= maxLongSidePx) return false;
    const double s = double(maxLongSidePx) / longSide;
    const int w = std::max(1, int(std::lround(frameSize.width * s))), h = std::max(1, int(std::lround(frameSize.height * s)));
    CV_Assert(source.cols >= w && source.rows >= h);
    cv::resize(source, plane_, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    image_.data = plane_.data;
    image_.width = w;
    image_.height = h;
    image_.stride = plane_.step;
    image_.data_bytes = 0;
    sx_ = double(w) / frameSize.width;
    sy_ = double(h) / frameSize.height;
    k_ = Intrinsics{k_.fx * sx_, k_.fy * sy_, (k_.cx + 0.5) * sx_ - 0.5, (k_.cy + 0.5) * sy_ - 0.5};
    shrunk_ = true;
    return true;
}

std::vector<Detection> mapToFrame(std::vector<Detection> detections, const SearchFrame& search,
                                  const Unrolling& searchUnrolling, const Unrolling& frameUnrolling) {
    return mapToFrame(std::move(detections), search.scaleX(), search.scaleY(), searchUnrolling, frameUnrolling);
}

std::vector<Detection> mapToFrame(std::vector<Detection> detections, double searchScaleX, double searchScaleY,
                                  const Unrolling& searchUnrolling, const Unrolling& frameUnrolling) {
    // Search unrolled -> frame unrolled is a scale and a shift (both unrollings rotate by the same roll about
    // principal points that correspond): the image of the pixel-edge corner (-0.5, -0.5) and the scale.
    const auto toFrame = [&](cv::Point2d p) {
        const cv::Point2d raw = searchUnrolling.unrolledToRaw(p);
        return frameUnrolling.rawToUnrolled(
            cv::Point2d((raw.x + 0.5) / searchScaleX - 0.5, (raw.y + 0.5) / searchScaleY - 0.5));
    };
    const cv::Point2d origin = toFrame({-0.5, -0.5});
    const double scale = toFrame({99.5, -0.5}).x - origin.x;
    for (Detection& d : detections) d.measurement = d.measurement.mapped(scale / 100.0, origin);
    return detections;
}

}  // namespace wf::sign
