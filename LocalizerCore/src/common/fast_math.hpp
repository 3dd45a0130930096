// Branch-light float approximations used in the per-particle loops (std::sin/cos/atan2 cost 15-40 ns each
// and do not vectorise). Accuracy is stated per function and checked in Tests/LocalizerCore/common.
#pragma once

#include <cmath>
#include <cstdint>

namespace wf::loc {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kTwoPi = 6.28318530717958647692f;
constexpr double kPiD = 3.14159265358979323846;

/// Wraps an angle to [-pi, pi), radians (double).
inline double wrap_angle(double a) {
    if (!std::isfinite(a)) return 0.0;
    a = std::fmod(a + kPiD, 2.0 * kPiD);
    if (a < 0) a += 2.0 * kPiD;
    return a - kPiD;
}

/// Wraps an angle to about [-pi, pi], radians (float; one rounding step, exact enough for |a| < 1e4).
inline float wrap_angle_f(float a) {
    const float t = a * (1.0f / kTwoPi);
    const float k = static_cast<float>(static_cast<int32_t>(t + (t >= 0.0f ? 0.5f : -0.5f)));  // no libm call
    return a - kTwoPi * k;
}

/// sin and cos of x (radians, |x| < 1e5), max abs error ~2e-7 for |x| < 100: quadrant reduction by
/// pi/2 (Cody-Waite two-constant split) and Taylor polynomials of degree 7/8 on [-pi/4, pi/4].
inline void fast_sincos(float x, float &s, float &c) {
    const float t = x * 0.63661977236758134f;  // x * 2/pi
    const int32_t qi = static_cast<int32_t>(t + (t >= 0.0f ? 0.5f : -0.5f));  // round half away from zero
    const float q = static_cast<float>(qi);
    float r = x - q * 1.5707963705062866f;
    r = r - q * -4.37113900018624e-08f;
    const float r2 = r * r;
    const float sp = r * (1.0f + r2 * (-1.6666667e-1f + r2 * (8.3333338e-3f + r2 * -1.9841270e-4f)));
    const float cp = 1.0f + r2 * (-0.5f + r2 * (4.1666668e-2f + r2 * (-1.3888889e-3f + r2 * 2.4801587e-5f)));
    // Quadrant rotation: (sin, cos) of r + q*pi/2.
    const int32_t k = qi & 3;
    const float s0 = (k & 1) ? cp : sp;
    const float c0 = (k & 1) ? sp : cp;
    s = (k & 2) ? -s0 : s0;
    c = ((k + 1) & 2) ? -c0 : c0;
}

/// atan2(y, x) in radians, max abs error ~1e-5 rad: octant reduction and an odd minimax polynomial for
/// atan on [0, 1]. Returns 0 for (0, 0).
inline float fast_atan2(float y, float x) {
    const float ax = std::fabs(x);
    const float ay = std::fabs(y);
    const float mx = ax > ay ? ax : ay;
    const float mn = ax > ay ? ay : ax;
    const float a = mx > 0.0f ? mn / mx : 0.0f;
    const float s = a * a;
    float r = a * (0.99997726f + s * (-0.33262347f + s * (0.19354346f + s * (-0.11643287f +
                   s * (0.05265332f + s * -0.01172120f)))));
    if (ay > ax) r = 1.57079637f - r;
    if (x < 0.0f) r = kPi - r;
    return y < 0.0f ? -r : r;
}

}  // namespace wf::loc
