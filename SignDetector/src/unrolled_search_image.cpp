#include "unrolled_search_image.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace wf::sign {

UnrolledSearchImage::UnrolledSearchImage(const cv::Mat& sourceGray, cv::Size frameSize, const Intrinsics& k,
                                         double rollRad, double snapToleranceRad, int maxLongSidePx) {
    CV_Assert(!sourceGray.empty() && sourceGray.type() == CV_8UC1 && maxLongSidePx > 0 && frameSize.width > 0 &&
              frameSize.height > 0);
    // The frame at scale s unrolls onto a canvas about s times the full-size one's; rounding the shrunk frame to
    // whole pixels can leave it a pixel over the limit, so the scale is lowered until it fits (two rounds at most in
    // practice; the bound only guards the loop).
    double s = std::min(1.0, double(maxLongSidePx) / std::max(frameSize.width, frameSize.height));
    for (int round = 0; round < 8; ++round) {
        const int w = std::max(1, int(std::lround(frameSize.width * s)));
        const int h = std::max(1, int(std::lround(frameSize.height * s)));
        sx_ = double(w) / frameSize.width;
        sy_ = double(h) / frameSize.height;
        const Intrinsics shrunk{k.fx * sx_, k.fy * sy_, (k.cx + 0.5) * sx_ - 0.5, (k.cy + 0.5) * sy_ - 0.5};
        unrolling_ = Unrolling::forRoll(rollRad, shrunk, cv::Size(w, h), snapToleranceRad);
        const cv::Size canvas = unrolling_.unrolledSize();
        const int longSide = std::max(canvas.width, canvas.height);
        if (longSide <= maxLongSidePx) break;
        s *= double(maxLongSidePx) / longSide * (round == 0 ? 1.0 : 0.999);
    }
    // Source pixel -> shrunk-frame pixel (pixel edges aligned): u_s = (u_src + 0.5) * (w / source width) - 0.5;
    // then the unrolling's affine map.
    const cv::Size shrunkSize = unrolling_.rawSize();
    const double ax = double(shrunkSize.width) / sourceGray.cols, ay = double(shrunkSize.height) / sourceGray.rows;
    const cv::Matx23d& a = unrolling_.rawToUnrolledMatrix();
    const double bx = 0.5 * ax - 0.5, by = 0.5 * ay - 0.5;
    const cv::Matx23d m(a(0, 0) * ax, a(0, 1) * ay, a(0, 0) * bx + a(0, 1) * by + a(0, 2),
                        a(1, 0) * ax, a(1, 1) * ay, a(1, 0) * bx + a(1, 1) * by + a(1, 2));
    cv::warpAffine(sourceGray, image_, cv::Mat(m), unrolling_.unrolledSize(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                   cv::Scalar::all(0));
}

}  // namespace wf::sign
