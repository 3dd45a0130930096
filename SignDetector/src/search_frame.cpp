#include "search_frame.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace wf::sign {

SearchFrame::SearchFrame(const wf_image& image, const Intrinsics& k, int maxLongSidePx) : image_(image), k_(k) {
    const int longSide = std::max(image.width, image.height);
    if (maxLongSidePx <= 0 || longSide <= maxLongSidePx) return;
    const double s = double(maxLongSidePx) / longSide;
    const int w = std::max(1, int(std::lround(image.width * s))), h = std::max(1, int(std::lround(image.height * s)));
    int type = CV_8UC1;
    switch (image.format) {
        case WF_PIXEL_BGRA8: type = CV_8UC4; break;
        case WF_PIXEL_RGB8: type = CV_8UC3; break;
        default: type = CV_8UC1; break;  // GRAY8, and the Y plane of NV12
    }
    const cv::Mat src(image.height, image.width, type, const_cast<uint8_t*>(image.data), image.stride);
    cv::resize(src, plane_, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    image_.data = plane_.data;
    image_.width = w;
    image_.height = h;
    image_.stride = plane_.step;
    image_.data_bytes = 0;
    if (image.format == WF_PIXEL_NV12 && image.data_uv != nullptr) {
        const cv::Mat uv((image.height + 1) / 2, (image.width + 1) / 2, CV_8UC2, const_cast<uint8_t*>(image.data_uv),
                         image.stride_uv);
        cv::resize(uv, chroma_, cv::Size((w + 1) / 2, (h + 1) / 2), 0, 0, cv::INTER_AREA);
        image_.data_uv = chroma_.data;
        image_.stride_uv = chroma_.step;
        image_.data_uv_bytes = 0;
    }
    sx_ = double(w) / image.width;
    sy_ = double(h) / image.height;
    k_ = Intrinsics{k.fx * sx_, k.fy * sy_, (k.cx + 0.5) * sx_ - 0.5, (k.cy + 0.5) * sy_ - 0.5};
    shrunk_ = true;
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
