#include "unroll.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace wf::sign {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

Unrolling Unrolling::forRoll(double rollRad, const Intrinsics& raw, cv::Size rawSize, double snapToleranceRad) {
    Unrolling u;
    u.rawSize_ = rawSize;
    // Nearest multiple of pi/2 and whether to snap to it.
    const double quarters = std::round(rollRad / (kPi / 2));
    const double residual = rollRad - quarters * (kPi / 2);
    const bool snap = std::abs(residual) <= std::max(snapToleranceRad, 1e-12);
    double c, s, fxU, fyU;
    if (snap) {
        // -roll in clockwise quarter turns: roll = -pi/2 -> one clockwise turn.
        int k = static_cast<int>(-quarters) % 4;
        if (k < 0) k += 4;
        u.quarterTurns_ = k;
        u.appliedRollRad_ = quarters * (kPi / 2);
        static const double cosTable[4] = {1, 0, -1, 0};
        static const double sinTable[4] = {0, -1, 0, 1};  // sin(r) for r = -k pi/2
        c = cosTable[k];
        s = sinTable[k];
        const bool odd = (k % 2) == 1;
        fxU = odd ? raw.fy : raw.fx;
        fyU = odd ? raw.fx : raw.fy;
    } else {
        u.quarterTurns_ = -1;
        u.appliedRollRad_ = rollRad;
        c = std::cos(rollRad);
        s = std::sin(rollRad);
        fxU = fyU = std::sqrt(raw.fx * raw.fy);
    }
    // Linear part (raw pixel offsets -> unrolled pixel offsets):
    // [du'; dv'] = diag(fx', fy') * [[c, s], [-s, c]] * diag(1/fx, 1/fy) * [du; dv].
    // Columns: the unrolled normalised images (camera_geometry.hpp) of the raw unit offsets along x and y.
    double x0, y0, x1, y1;
    wf::camera::unrollNormalised(c, s, 1.0, 0.0, &x0, &y0);
    wf::camera::unrollNormalised(c, s, 0.0, 1.0, &x1, &y1);
    const double a00 = fxU * x0 / raw.fx, a01 = fxU * x1 / raw.fy;
    const double a10 = fyU * y0 / raw.fx, a11 = fyU * y1 / raw.fy;
    // Bounding box of the raw frame's outer pixel edges after rotation about the principal point.
    const double w = rawSize.width, h = rawSize.height;
    const double cornersU[4] = {-0.5, w - 0.5, w - 0.5, -0.5};
    const double cornersV[4] = {-0.5, -0.5, h - 0.5, h - 0.5};
    double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
    for (int i = 0; i < 4; ++i) {
        const double du = cornersU[i] - raw.cx, dv = cornersV[i] - raw.cy;
        const double x = a00 * du + a01 * dv, y = a10 * du + a11 * dv;
        minX = std::min(minX, x); maxX = std::max(maxX, x);
        minY = std::min(minY, y); maxY = std::max(maxY, y);
    }
    const int outW = std::max(1, static_cast<int>(std::ceil(maxX - minX - 1e-9)));
    const int outH = std::max(1, static_cast<int>(std::ceil(maxY - minY - 1e-9)));
    u.unrolledSize_ = cv::Size(outW, outH);
    // The principal point lands where the rotated outer edge starts at -0.5 (centred in the canvas).
    const double cxU = -minX - 0.5 + 0.5 * (outW - (maxX - minX));
    const double cyU = -minY - 0.5 + 0.5 * (outH - (maxY - minY));
    u.unrolledK_ = Intrinsics{fxU, fyU, cxU, cyU};
    u.rawToUnrolled_ = cv::Matx23d(a00, a01, cxU - a00 * raw.cx - a01 * raw.cy,
                                   a10, a11, cyU - a10 * raw.cx - a11 * raw.cy);
    // Inverse of the 2x2 part (exact for quarter turns: entries are 0/+-1 times fy/fx ratios).
    const double det = a00 * a11 - a01 * a10;
    const double i00 = a11 / det, i01 = -a01 / det, i10 = -a10 / det, i11 = a00 / det;
    u.unrolledToRaw_ = cv::Matx23d(i00, i01, raw.cx - i00 * cxU - i01 * cyU,
                                   i10, i11, raw.cy - i10 * cxU - i11 * cyU);
    return u;
}

cv::Mat Unrolling::apply(const cv::Mat& raw, int interpolation) const {
    CV_Assert(raw.size() == rawSize_);
    cv::Mat out;
    switch (quarterTurns_) {
        case 0: return raw;
        case 1: cv::rotate(raw, out, cv::ROTATE_90_CLOCKWISE); return out;
        case 2: cv::rotate(raw, out, cv::ROTATE_180); return out;
        case 3: cv::rotate(raw, out, cv::ROTATE_90_COUNTERCLOCKWISE); return out;
        default:
            cv::warpAffine(raw, out, cv::Mat(rawToUnrolled_), unrolledSize_, interpolation, cv::BORDER_CONSTANT,
                           cv::Scalar::all(0));
            return out;
    }
}

void Unrolling::applyToRegion(const cv::Mat& raw, const cv::Rect& unrolledRoi, cv::Mat* canvas, int interpolation) const {
    CV_Assert(raw.size() == rawSize_ && canvas->size() == unrolledSize_ && canvas->type() == raw.type());
    const cv::Rect roi = unrolledRoi & cv::Rect(cv::Point(0, 0), unrolledSize_);
    if (roi.empty()) return;
    cv::Mat target = (*canvas)(roi);  // a view: writing it writes the canvas
    if (quarterTurns_ >= 0) {
        apply(raw, interpolation)(roi).copyTo(target);  // a pixel permutation: cheap for the whole frame
        return;
    }
    // The same affine map with the ROI's origin moved to (0, 0): destination pixel (x, y) of the ROI is
    // unrolled pixel (x + roi.x, y + roi.y).
    cv::Matx23d m = rawToUnrolled_;
    m(0, 2) -= roi.x;
    m(1, 2) -= roi.y;
    cv::warpAffine(raw, target, cv::Mat(m), roi.size(), interpolation, cv::BORDER_CONSTANT, cv::Scalar::all(0));
}

cv::Point2d Unrolling::rawToUnrolled(cv::Point2d p) const {
    const auto& m = rawToUnrolled_;
    return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)};
}

cv::Point2d Unrolling::unrolledToRaw(cv::Point2d p) const {
    const auto& m = unrolledToRaw_;
    return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)};
}

}  // namespace wf::sign
