// Tests for common/fast_math.hpp's fast_exp (fast_sincos and fast_atan2 are tested in test_rng.cpp): relative
// error against double std::exp over the whole float range it serves, and its edge values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "common/fast_math.hpp"

TEST(FastMath, ExpMatchesStdOverItsRange) {
    // Every 601st float of [-87, 88], stepped on the bit patterns of each sign's magnitudes (about 3 million
    // values of both signs and all magnitudes, down to the smallest subnormal).
    double worst = 0;
    int checked = 0;
    for (const float sign : {-1.0f, 1.0f}) {
        const float top = sign < 0 ? 87.0f : 88.0f;
        uint32_t top_bits;
        std::memcpy(&top_bits, &top, sizeof(top_bits));
        for (uint32_t b = 0; b <= top_bits; b += 601) {
            float magnitude;
            std::memcpy(&magnitude, &b, sizeof(magnitude));
            const float x = sign * magnitude;
            const double ref = std::exp(static_cast<double>(x));
            worst = std::max(worst, std::fabs(wf::loc::fast_exp(x) - ref) / ref);
            ++checked;
        }
    }
    EXPECT_GT(checked, 3'000'000);
    EXPECT_LT(worst, 3e-7);  // about 2 float ulps
}

TEST(FastMath, ExpEdgeValues) {
    using wf::loc::fast_exp;
    EXPECT_EQ(fast_exp(0.0f), 1.0f);   // the best particle keeps its weight exactly
    EXPECT_EQ(fast_exp(-0.0f), 1.0f);
    EXPECT_EQ(fast_exp(-87.4f), 0.0f);  // no subnormal results
    EXPECT_EQ(fast_exp(-1e30f), 0.0f);
    EXPECT_EQ(fast_exp(-std::numeric_limits<float>::infinity()), 0.0f);
    EXPECT_EQ(fast_exp(std::numeric_limits<float>::quiet_NaN()), 0.0f);
    EXPECT_EQ(fast_exp(-std::numeric_limits<float>::quiet_NaN()), 0.0f);
    const float top = fast_exp(88.0f);
    EXPECT_TRUE(std::isfinite(top));
    EXPECT_EQ(fast_exp(1e30f), top);  // clamped at 88
    EXPECT_EQ(fast_exp(std::numeric_limits<float>::infinity()), top);
    EXPECT_NEAR(fast_exp(-87.3f) / std::exp(static_cast<double>(-87.3f)), 1.0, 3e-7);  // still normal just above the cut
}
