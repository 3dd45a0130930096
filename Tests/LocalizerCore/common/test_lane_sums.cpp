// Tests for common/lane_sums.hpp: the lane sums against a sequential long-double reference, for lengths that
// leave every possible tail, and the documented lane assignment.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/lane_sums.hpp"
#include "common/rng.hpp"

using namespace wf::loc;

TEST(LaneSums, MatchSequentialSums) {
    Rng rng(3);
    for (size_t n : {0, 1, 7, 8, 9, 15, 16, 17, 1000, 100'003}) {
        std::vector<float> v(n);
        for (float &x : v) x = rng.uniform_float() * rng.uniform_float() * 1e-3f;
        long double ref = 0, ref2 = 0;
        for (float x : v) {
            ref += x;
            ref2 += static_cast<long double>(x) * x;
        }
        double s = -1, s2 = -1;
        lane_sum_and_squares(v.data(), n, s, s2);
        EXPECT_EQ(s, lane_sum(v.data(), n)) << n;
        // Double rounding over n additions: well within n * 2^-53 of the sum (no cancellation: all terms >= 0).
        EXPECT_NEAR(s, static_cast<double>(ref), 1e-16 * static_cast<double>(n) * static_cast<double>(ref)) << n;
        EXPECT_NEAR(s2, static_cast<double>(ref2), 1e-16 * static_cast<double>(n) * static_cast<double>(ref2)) << n;
    }
}

TEST(LaneSums, ElementsGoToLaneIndexModuloLanes) {
    // One large value in lane 3 and tiny ones elsewhere: folding the lanes in the documented order gives the
    // documented value (fold_lanes is a fixed, not a data-dependent, order).
    std::vector<float> v(19, 1.0f);
    v[3] = 1e8f;
    double lane[kSumLanes] = {};
    for (size_t i = 0; i < v.size(); ++i) lane[i % kSumLanes] += v[i];
    EXPECT_EQ(lane_sum(v.data(), v.size()), fold_lanes(lane));
    EXPECT_EQ(lane_sum(v.data(), v.size()), 1e8 + 18.0);
}
