// Branch-light float approximations used in the per-particle loops (std::sin/cos/atan2 cost 15-40 ns each
// and do not vectorise). Accuracy is stated per function and checked in Tests/LocalizerCore/common.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

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

/// e^x for float x, branch-free so that loops over particles vectorise (std::exp is a library call per
/// element). Cephes expf (S. L. Moshier, Cephes Math Library 2.x, "expf.c"): n = round(x / ln 2), the rest r
/// reduced with a two-constant split of ln 2, e^r by a degree-7 polynomial, times 2^n built in the exponent
/// bits. Relative error below 3e-7 (about 2 float ulps) on [-87, 88]; exactly 1 at x = 0; 0 below -87.33 (no
/// subnormal results), for -infinity and for NaN; e^88 above 88 (no infinity).
inline float fast_exp(float x) {
    // x clamped to [-100, 88] on its bits (integer masks: GCC leaves a loop scalar for a float min / max
    // here). As unsigned, negative floats below -100 (-infinity and negative NaNs too) are above -100's bits;
    // positive floats above 88 (+infinity and positive NaNs too) lie between 88's bits and the sign bit.
    constexpr uint32_t kMinus100 = 0xc2c80000u, kPlus88 = 0x42b00000u, kSign = 0x80000000u;
    uint32_t xb;
    std::memcpy(&xb, &x, sizeof(xb));
    const uint32_t below = 0u - static_cast<uint32_t>(xb > kMinus100);
    xb = (xb & ~below) | (kMinus100 & below);
    const uint32_t above = 0u - (static_cast<uint32_t>(xb > kPlus88) & static_cast<uint32_t>(xb < kSign));
    xb = (xb & ~above) | (kPlus88 & above);
    float xc;
    std::memcpy(&xc, &xb, sizeof(xc));
    const float t = xc * 1.44269504088896341f;  // x / ln 2
    const int32_t n = static_cast<int32_t>(t + std::copysign(0.5f, t));  // round half away from zero
    const float nf = static_cast<float>(n);
    float r = xc - nf * 0.693359375f;
    r = r - nf * -2.12194440e-4f;
    const float r2 = r * r;
    const float poly = ((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r + 4.1665795894e-2f) *
                            r + 1.6666665459e-1f) * r + 5.0000001201e-1f;
    const float er = poly * r2 + r + 1.0f;
    // 2^n as float bits, n kept in [-126, 127] (below, the mask zeroes the result anyway).
    const int32_t nc = std::max(n, -126);
    const uint32_t bits = static_cast<uint32_t>(nc + 127) << 23;
    float scale;
    std::memcpy(&scale, &bits, sizeof(scale));
    // Below -87.33654 (and for NaN, which fails the comparison) the result is 0: a bit mask, not a branch.
    const uint32_t keep = 0u - static_cast<uint32_t>(x >= -87.33654f);
    const float y = er * scale;
    uint32_t ybits;
    std::memcpy(&ybits, &y, sizeof(ybits));
    ybits &= keep;
    float out;
    std::memcpy(&out, &ybits, sizeof(out));
    return out;
}

}  // namespace wf::loc
