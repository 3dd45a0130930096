// Tests for common/rng.hpp and common/fast_math.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/fast_math.hpp"
#include "common/rng.hpp"

using wf::loc::Rng;

TEST(Rng, SameSeedSameSequenceDifferentSeedDifferent) {
    Rng a(42), b(42), c(43);
    int differ = 0;
    for (int i = 0; i < 1000; ++i) {
        const uint64_t va = a.next_u64();
        EXPECT_EQ(va, b.next_u64());
        differ += va != c.next_u64();
    }
    EXPECT_GT(differ, 990);
}

TEST(Rng, UniformMomentsAndRange) {
    Rng r(1);
    const int n = 200000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
        const double u = r.uniform_float();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        s += u;
        s2 += u * u;
    }
    EXPECT_NEAR(s / n, 0.5, 0.003);                       // std of mean ~0.00065
    EXPECT_NEAR(s2 / n - (s / n) * (s / n), 1.0 / 12, 0.002);
}

TEST(Rng, BelowIsInRangeAndCoversAll) {
    Rng r(5);
    std::vector<int> hist(7, 0);
    for (int i = 0; i < 70000; ++i) {
        const uint32_t v = r.below(7);
        ASSERT_LT(v, 7u);
        ++hist[v];
    }
    for (int h : hist) EXPECT_NEAR(h, 10000, 400);  // ~4 sigma
}

// Ziggurat normal: mean 0, std 1, and the tail mass beyond 3 sigma (0.0027) and 4 sigma (6.3e-5).
TEST(Rng, NormalMomentsAndTails) {
    Rng r(2024);
    const int n = 1000000;
    double s = 0, s2 = 0, s4 = 0;
    int beyond3 = 0, beyond4 = 0;
    for (int i = 0; i < n; ++i) {
        const double z = r.normal();
        ASSERT_TRUE(std::isfinite(z));
        s += z;
        s2 += z * z;
        s4 += z * z * z * z;
        beyond3 += std::fabs(z) > 3;
        beyond4 += std::fabs(z) > 4;
    }
    EXPECT_NEAR(s / n, 0.0, 0.005);          // 5 standard errors
    EXPECT_NEAR(s2 / n, 1.0, 0.007);
    EXPECT_NEAR(s4 / n, 3.0, 0.05);          // kurtosis of a Gaussian
    EXPECT_NEAR(beyond3 / double(n), 0.0027, 0.0003);
    EXPECT_NEAR(beyond4 / double(n), 6.33e-5, 3e-5);
}

TEST(FastMath, SinCosMatchesStd) {
    float worst = 0;
    for (float x = -60.0f; x <= 60.0f; x += 0.0137f) {
        float s, c;
        wf::loc::fast_sincos(x, s, c);
        worst = std::max(worst, std::fabs(s - std::sin(x)));
        worst = std::max(worst, std::fabs(c - std::cos(x)));
    }
    EXPECT_LT(worst, 2e-6f);
}

TEST(FastMath, Atan2MatchesStd) {
    float worst = 0;
    for (float a = -3.14f; a <= 3.14f; a += 0.001f) {
        for (float r : {0.01f, 1.0f, 50.0f}) {
            const float y = r * std::sin(a), x = r * std::cos(a);
            worst = std::max(worst, std::fabs(wf::loc::fast_atan2(y, x) - std::atan2(y, x)));
        }
    }
    EXPECT_LT(worst, 2e-5f);
    EXPECT_EQ(wf::loc::fast_atan2(0.0f, 0.0f), 0.0f);
}

TEST(FastMath, WrapAngle) {
    EXPECT_NEAR(wf::loc::wrap_angle(3 * wf::loc::kPiD), -wf::loc::kPiD, 1e-12);
    EXPECT_NEAR(wf::loc::wrap_angle(-0.5), -0.5, 1e-15);
    EXPECT_NEAR(wf::loc::wrap_angle(7.0), 7.0 - 2 * wf::loc::kPiD, 1e-12);
    EXPECT_EQ(wf::loc::wrap_angle(NAN), 0.0);
    EXPECT_NEAR(wf::loc::wrap_angle_f(4.0f), 4.0f - 2 * wf::loc::kPi, 1e-6f);
}

// fill_normal is a batched normal(): same values, same order, same generator state afterwards, whatever the
// batch sizes (odd sizes leave a spare 32-bit half) and including the Ziggurat slow paths (~1.2 % of draws).
TEST(Rng, FillNormalMatchesRepeatedNormal) {
    Rng one(77), batch(77);
    std::vector<float> a, b;
    const size_t sizes[] = {1, 2, 3, 7, 1000, 4093, 1, 20000, 5};
    for (size_t n : sizes) {
        for (size_t i = 0; i < n; ++i) a.push_back(one.normal());
        const size_t start = b.size();
        b.resize(start + n);
        batch.fill_normal(b.data() + start, n);
        if (n == 7) {  // interleave other draws: the shared spare half must be handled the same way
            a.push_back(static_cast<float>(one.next_u32()));
            b.push_back(static_cast<float>(batch.next_u32()));
        }
    }
    ASSERT_EQ(a.size(), b.size());
    size_t tail = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i], b[i]) << "draw " << i;
        tail += std::fabs(a[i]) > 3.442619855899f;
    }
    EXPECT_GT(tail, 0u);  // the tail branch of the slow path was exercised
    EXPECT_EQ(one.next_u64(), batch.next_u64());
}
