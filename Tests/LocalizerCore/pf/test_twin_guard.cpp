// Tests for pf/twin_guard.hpp: the twin pose of each particle under a floor's symmetry, the per-particle log
// ratios, a cluster's Bayes factor against its twin, and reseeding that splits (never creates) the pair's mass.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "pf/twin_guard.hpp"
#include "support/filter_fixtures.hpp"

using namespace wf::loc;

namespace {

/// Two floors: floor 0 the 30 x 2 point-symmetric corridor (half turn about (15, 1)), floor 1 an L (none).
LocalizerMap two_floor_map() {
    auto w = wf::test::symmetric_world();
    wf::test::FloorSpec l;
    l.elevation_m = 4;
    l.polygon({{0, 0}, {30, 0}, {30, 25}, {27.5f, 25}, {27.5f, 2.5f}, {0, 2.5f}}).seed(1, 1.25f);
    w.floors.push_back(l);
    return wf::test::build_map(w, wf::test::default_options());
}

ParticleSet particles(size_t n, size_t twin_arrays) {
    ParticleSet p;
    p.twin_arrays = twin_arrays;
    p.resize(n);
    for (size_t i = 0; i < n; ++i) {
        p.x[i] = 5 + 0.01f * static_cast<float>(i % 50);
        p.y[i] = 0.8f;
        p.yaw_offset[i] = 0.3f;
        p.scale[i] = 1.02f;
        p.weight[i] = 1.0f / static_cast<float>(n);
        p.evidence[i] = -1;
        p.compass_ll[i] = 0;
        p.bias_s1[i] = 0.5f;
        p.bias_s0[i] = 2;
        p.floor[i] = 0;
        p.twin_llr[0][i] = 0;
    }
    return p;
}

}  // namespace

TEST(TwinGuard, ArraysFollowTheMostSymmetricFloor) {
    EXPECT_EQ(TwinGuard::twin_arrays_for(two_floor_map()), 1u);
    auto w = wf::test::l_world();
    EXPECT_EQ(TwinGuard::twin_arrays_for(wf::test::build_map(w, wf::test::default_options())), 0u);
}

// The twin is the half-turned particle (position about (15, 1), yaw offset + pi); particles on the floor
// without a symmetry keep their pose and their ratio is never touched.
TEST(TwinGuard, TwinsAreRotatedCopiesAndOnlySymmetricFloorsAccumulate) {
    const LocalizerMap map = two_floor_map();
    ParticleSet p = particles(4, 1);
    p.floor[3] = 1;
    TwinGuard g;
    std::vector<float> tx, ty, tyaw;
    ASSERT_TRUE(g.twin_poses(p, map, 0, tx, ty, tyaw));
    ASSERT_EQ(tx.size(), 4u);
    EXPECT_NEAR(tx[0], 30 - p.x[0], 1e-5);
    EXPECT_NEAR(ty[0], 2 - p.y[0], 1e-5);
    EXPECT_NEAR(std::fabs(std::remainder(tyaw[0] - p.yaw_offset[0], 2 * wf::test::kPi)), wf::test::kPi, 1e-5);
    EXPECT_LE(std::fabs(tyaw[0]), wf::test::kPi + 1e-6);
    EXPECT_EQ(tx[3], p.x[3]);  // floor 1: no symmetry
    EXPECT_EQ(tyaw[3], p.yaw_offset[3]);
    EXPECT_FALSE(g.twin_poses(p, map, 1, tx, ty, tyaw));  // no floor has a second symmetry

    const float ll[4] = {-1, -2, -3, -4};
    const float twin_ll[4] = {-2, -2, -1e30f, -1};
    g.accumulate(p, map, 0, ll, twin_ll);
    EXPECT_FLOAT_EQ(p.twin_llr[0][0], 1);
    EXPECT_FLOAT_EQ(p.twin_llr[0][1], 0);
    EXPECT_FLOAT_EQ(p.twin_llr[0][2], 20);  // clamped to max_step_nats
    EXPECT_FLOAT_EQ(p.twin_llr[0][3], 0);   // floor 1
}

// A cluster's Bayes factor against its twin: log(sum w) - log(sum w exp(-llr)); +infinity off or without symmetry.
TEST(TwinGuard, ClusterBayesFactor) {
    const LocalizerMap map = two_floor_map();
    ParticleSet p = particles(3, 1);
    p.weight = {0.5f, 0.25f, 0.25f};
    p.twin_llr[0] = {2, 4, -1};
    const uint32_t members[3] = {0, 1, 2};
    TwinGuard g;
    const double expect = std::log(1.0) - std::log(0.5 * std::exp(-2.0) + 0.25 * std::exp(-4.0) + 0.25 * std::exp(1.0));
    EXPECT_NEAR(g.log_ratio(p, map, members, 3), expect, 1e-6);
    p.floor = {1, 1, 1};
    EXPECT_TRUE(std::isinf(g.log_ratio(p, map, members, 3)));
    p.floor = {0, 0, 0};
    g.mutable_params().enabled = false;
    EXPECT_TRUE(std::isinf(g.log_ratio(p, map, members, 3)));
}

// With no evidence either way (ratios 0) and the twin region empty, reseeding moves half of the dominant
// hypothesis's mass onto the twin poses; the total is unchanged, the moved particles carry the negated ratio,
// and a second call moves nothing. A twin refuted by more than refuted_nats is never reseeded.
TEST(TwinGuard, ReseedingSplitsThePairsMass) {
    const LocalizerMap map = two_floor_map();
    ParticleSet p = particles(200, 1);
    // 100 other particles far from both regions (the rest of the cloud) keep their mass.
    for (size_t i = 100; i < 200; ++i) { p.x[i] = 15; p.yaw_offset[i] = 1.8f; }
    for (size_t i = 0; i < 100; ++i) p.twin_llr[0][i] = 0.5f;
    TwinGuard g;
    g.observe_dominant(0, 5.25, 0.8, 0.3, 0.2);
    const size_t moved = g.reseed(p, map);
    EXPECT_GT(moved, 0u);
    double total = 0, twin = 0, rest = 0;
    size_t negated = 0;
    for (size_t i = 0; i < 200; ++i) {
        total += p.weight[i];
        if (i >= 100) { rest += p.weight[i]; continue; }
        if (p.x[i] > 20) {
            twin += p.weight[i];
            negated += p.twin_llr[0][i] == -0.5f ? 1 : 0;
            EXPECT_NEAR(std::remainder(p.yaw_offset[i] - 0.3 - wf::test::kPi, 2 * wf::test::kPi), 0, 1e-5);
            EXPECT_FLOAT_EQ(p.evidence[i], -1.5f);  // lowered by the ratio
        }
    }
    EXPECT_NEAR(total, 1.0, 1e-5);
    EXPECT_NEAR(rest, 0.5, 1e-6);
    // twin : dominant = exp(-0.5) : 1 of the pair's 0.5.
    EXPECT_NEAR(twin, 0.5 * std::exp(-0.5) / (1 + std::exp(-0.5)), 0.011);
    EXPECT_EQ(negated, moved);
    EXPECT_EQ(g.reseed(p, map), 0u);

    ParticleSet refuted = particles(100, 1);
    for (size_t i = 0; i < 100; ++i) refuted.twin_llr[0][i] = 9;
    EXPECT_EQ(g.reseed(refuted, map), 0u);
}
