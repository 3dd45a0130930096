#include "synthetic_scene.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

namespace wf::sign::synthetic {

Camera Camera::resized(cv::Size newSize) const {
    Camera c = *this;
    const double sx = double(newSize.width) / size.width, sy = double(newSize.height) / size.height;
    c.size = newSize;
    c.fx = fx * sx;
    c.fy = fy * sy;
    c.cx = (cx + 0.5) * sx - 0.5;
    c.cy = (cy + 0.5) * sy - 0.5;
    return c;
}

bool projectToRaw(const Camera& camera, const cv::Vec3d& p, cv::Point2d* pixel) {
    // Camera-to-world R = Rx(pitch) * Rz(roll) (yaw fixed so that forward is world -z); camera coords = R^T p.
    const double cp = std::cos(camera.pitchRad), sp = std::sin(camera.pitchRad);
    const double cr = std::cos(camera.rollRad), sr = std::sin(camera.rollRad);
    const cv::Matx33d rx(1, 0, 0, 0, cp, -sp, 0, sp, cp);
    const cv::Matx33d rz(cr, -sr, 0, sr, cr, 0, 0, 0, 1);
    const cv::Vec3d c = (rx * rz).t() * p;
    if (c[2] >= -1e-6) return false;
    pixel->x = camera.cx + camera.fx * (c[0] / -c[2]);
    pixel->y = camera.cy - camera.fy * (c[1] / -c[2]);
    return true;
}

cv::Mat renderBackground(const Camera& camera, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> gray(90, 150);
    cv::Mat bgr(camera.size, CV_8UC3, cv::Scalar::all(gray(rng)));
    // Door- and poster-like rectangles.
    std::uniform_int_distribution<int> x(0, camera.size.width - 1), y(0, camera.size.height - 1);
    for (int i = 0; i < 6; ++i) {
        const cv::Point a(x(rng), y(rng)), b(x(rng), y(rng));
        const int g = gray(rng);
        cv::rectangle(bgr, a, b, cv::Scalar(g - 10, g, g + 10), cv::FILLED);
    }
    cv::Mat noise(camera.size, CV_16SC3);
    cv::RNG noiseRng(seed);
    noiseRng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(6));
    cv::Mat noisy;
    cv::add(bgr, noise, noisy, cv::noArray(), CV_8UC3);
    return noisy;
}

cv::Mat renderSignFace(const SignPlacement& sign, int heightPx) {
    const int h = std::max(8, heightPx);
    const int w = std::max(8, static_cast<int>(std::lround(h * sign.widthMeters / sign.heightMeters)));
    if (sign.style == SignStyle::PlacardLightOnDark) {
        cv::Mat face(h, w, CV_8UC3, cv::Scalar(40, 35, 30));
        const int thickness = std::max(1, h / 40);
        int baseline = 0;
        const cv::Size unit = cv::getTextSize(sign.legend, cv::FONT_HERSHEY_SIMPLEX, 1.0, thickness, &baseline);
        const double scale = std::min(h / 6.0 / unit.height, 0.8 * w / unit.width);
        const cv::Size fitted = cv::getTextSize(sign.legend, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
        cv::putText(face, sign.legend, cv::Point((w - fitted.width) / 2, (h + fitted.height) / 2), cv::FONT_HERSHEY_SIMPLEX,
                    scale, cv::Scalar(235, 235, 235), thickness, cv::LINE_AA);
        return face;
    }
    const bool redPlate = sign.style == SignStyle::WhiteLettersOnRed;
    const cv::Scalar red(30, 30, 210), white(235, 240, 240);
    cv::Mat face(h, w, CV_8UC3, redPlate ? red : white);
    const double fontScale = h / 40.0;
    const int thickness = std::max(1, h / 14);
    int baseline = 0;
    const cv::Size text = cv::getTextSize("EXIT", cv::FONT_HERSHEY_SIMPLEX, fontScale, thickness, &baseline);
    const double fit = std::min(0.85 * w / text.width, 0.6 * h / text.height);
    const double scale = fontScale * fit;
    const cv::Size fitted = cv::getTextSize("EXIT", cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
    cv::putText(face, "EXIT", cv::Point((w - fitted.width) / 2, (h + fitted.height) / 2), cv::FONT_HERSHEY_SIMPLEX,
                scale, redPlate ? white : red, thickness, cv::LINE_AA);
    if (!redPlate) cv::rectangle(face, cv::Rect(0, 0, w, h), cv::Scalar(60, 60, 60), std::max(1, h / 30));
    return face;
}

RenderedSign drawSign(cv::Mat& bgr, const Camera& camera, const SignPlacement& sign) {
    RenderedSign truth;
    truth.placement = sign;
    const double sb = std::sin(sign.bearingRad), cb = std::cos(sign.bearingRad);
    const cv::Vec3d centre(-sign.rangeMeters * sb, 0, -sign.rangeMeters * cb);
    const cv::Vec3d right(cb, 0, -sb), up(0, 1, 0);
    const double hw = 0.5 * sign.widthMeters, bottom = sign.bottomAboveCameraMeters, top = bottom + sign.heightMeters;
    const cv::Vec3d world[4] = {centre - hw * right + top * up, centre + hw * right + top * up,
                                centre + hw * right + bottom * up, centre - hw * right + bottom * up};
    truth.cornersRaw.resize(4);
    for (int i = 0; i < 4; ++i) {
        if (!projectToRaw(camera, world[i], &truth.cornersRaw[i])) return truth;
    }
    const double apparentHeight = cv::norm(truth.cornersRaw[0] - truth.cornersRaw[3]);
    const cv::Mat face = renderSignFace(sign, static_cast<int>(std::max(16.0, 2 * apparentHeight)));
    // Face pixel edges (-0.5 .. size-0.5) -> projected corners.
    const cv::Point2f src[4] = {{-0.5f, -0.5f}, {face.cols - 0.5f, -0.5f}, {face.cols - 0.5f, face.rows - 0.5f},
                                {-0.5f, face.rows - 0.5f}};
    cv::Point2f dst[4];
    for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(float(truth.cornersRaw[i].x), float(truth.cornersRaw[i].y));
    const cv::Mat h = cv::getPerspectiveTransform(src, dst);
    cv::Mat warped, coverage;
    cv::warpPerspective(face, warped, h, bgr.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    cv::warpPerspective(cv::Mat(face.size(), CV_32F, cv::Scalar(1)), coverage, h, bgr.size(), cv::INTER_LINEAR,
                        cv::BORDER_CONSTANT);
    // Alpha blend by coverage (anti-aliased edges).
    for (int r = 0; r < bgr.rows; ++r) {
        const float* a = coverage.ptr<float>(r);
        const cv::Vec3b* s = warped.ptr<cv::Vec3b>(r);
        cv::Vec3b* d = bgr.ptr<cv::Vec3b>(r);
        for (int c = 0; c < bgr.cols; ++c) {
            if (a[c] <= 0) continue;
            const float t = std::min(1.0f, a[c]);
            for (int k = 0; k < 3; ++k) d[c][k] = cv::saturate_cast<uchar>(t * s[c][k] + (1 - t) * d[c][k]);
        }
    }
    truth.visible = true;
    for (const auto& p : truth.cornersRaw) {
        if (p.x < -0.5 || p.y < -0.5 || p.x > bgr.cols - 0.5 || p.y > bgr.rows - 0.5) truth.visible = false;
    }
    return truth;
}

}  // namespace wf::sign::synthetic
