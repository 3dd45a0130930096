// The core of a cluster (pf/cluster_core): robust to a light tail far away, still wide when the cluster is.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "pf/cluster_core.hpp"

using wf::loc::cluster_core;
using wf::loc::cluster_core_around;
using wf::loc::ClusterCore;
using wf::loc::ParticleSet;
using wf::loc::sighted_members;
using wf::loc::sighted_weight_per_cluster;

namespace {

void add(ParticleSet &p, float x, float y, float yaw, float w, float bias_s0 = 0) {
    p.x.push_back(x);
    p.y.push_back(y);
    p.yaw_offset.push_back(yaw);
    p.scale.push_back(1);
    p.weight.push_back(w);
    p.evidence.push_back(0);
    p.compass_ll.push_back(0);
    p.bias_s1.push_back(0);
    p.bias_s0.push_back(bias_s0);
    p.floor.push_back(0);
}

std::vector<uint32_t> all_of(const ParticleSet &p) {
    std::vector<uint32_t> m(p.size());
    for (size_t i = 0; i < m.size(); ++i) m[i] = static_cast<uint32_t>(i);
    return m;
}

/// A locked blob of `blob_count` particles (std `blob_std_m` in x and y around (bx, by), yaw offset `blob_yaw`)
/// and a swath of `swath_count` particles spread evenly at random over x in [x0, x1] along y = by (with the
/// blob's y noise when `swath_y_noise`), yaw offset 0; every weight 0.001. Drawn in that order from `seed`.
ParticleSet blob_and_swath(unsigned seed, float bx, float by, float blob_std_m, float blob_yaw, int blob_count,
                           float x0, float x1, int swath_count, bool swath_y_noise) {
    std::mt19937 gen(seed);
    std::normal_distribution<float> n(0, blob_std_m);
    std::uniform_real_distribution<float> u(x0, x1);
    ParticleSet p;
    for (int i = 0; i < blob_count; ++i) add(p, bx + n(gen), by + n(gen), blob_yaw, 0.001f);
    for (int i = 0; i < swath_count; ++i) add(p, u(gen), swath_y_noise ? by + n(gen) : by, 0.0f, 0.001f);
    return p;
}

}  // namespace

TEST(ClusterCore, ATailOfInjectedParticlesMovesNeitherTheMeanNorTheSpread) {
    // A locked blob (0.25 m std at (10, 1.2), heading offset 0.3 rad) holding 93 % of the weight, and 7 %
    // scattered 6-25 m along the same corridor (what recovery injection adds to the cluster).
    const ParticleSet p = blob_and_swath(3, 10, 1.2f, 0.25f, 0.3f, 930, 16, 35, 70, false);
    std::vector<double> scratch;
    const ClusterCore core = cluster_core(p, all_of(p), 6.0, scratch);
    EXPECT_EQ(core.count, 930u);
    EXPECT_NEAR(core.weight, 0.93, 1e-4);
    EXPECT_NEAR(core.x, 10, 0.05);
    EXPECT_NEAR(core.y, 1.2, 0.05);
    EXPECT_NEAR(core.position_std_m(), 0.25, 0.05);
    EXPECT_NEAR(std::atan2(core.yaw_sin_sum, core.yaw_cos_sum), 0.3, 1e-5);
    // The whole cluster's figures, for contrast (what the lock read before): std about 4 m.
    const ClusterCore whole = cluster_core(p, all_of(p), 1e4, scratch);
    EXPECT_GT(whole.position_std_m(), 3.0);
    EXPECT_GT(std::fabs(whole.x - 10), 0.8);
}

TEST(ClusterCore, AClusterThatReallySpreadsStaysWide) {
    // A Gaussian of 2.1 m std in both directions (a long tracking loss in an open hall): the 6 m core keeps
    // most of it, and its std stays above the lock's 2 m limit.
    std::mt19937 gen(4);
    std::normal_distribution<float> n(0, 2.1f);
    ParticleSet p;
    for (int i = 0; i < 4000; ++i) add(p, 20 + n(gen), 10 + n(gen), 0, 1.0f / 4000);
    std::vector<double> scratch;
    const ClusterCore core = cluster_core(p, all_of(p), 6.0, scratch);
    EXPECT_GT(core.position_std_m(), 2.0);
    EXPECT_GT(core.weight, 0.9);
}

TEST(ClusterCore, AroundAGivenCentreTheDiscStaysOnTheLockWhenTheMedianFlips) {
    // A lock of 0.45 of the weight at (35, 11) and a merged swath of 0.55 spread 12-30 m along the same corridor
    // (recovery injection joined to the cluster): the members' median falls in the swath, 11 m from the lock.
    // The disc around the last full estimate's centre keeps reading the lock (between full estimates).
    const ParticleSet p = blob_and_swath(7, 35, 11, 0.3f, 0.1f, 450, 12, 30, 550, true);
    std::vector<double> scratch;
    const ClusterCore by_median = cluster_core(p, all_of(p), 6.0, scratch);
    EXPECT_LT(by_median.centre_x, 29.0);
    EXPECT_GT(std::fabs(by_median.x - 35), 5.0);
    const ClusterCore around = cluster_core_around(p, all_of(p), 35.0, 11.0, 6.0);
    EXPECT_EQ(around.centre_x, 35.0);
    EXPECT_EQ(around.centre_y, 11.0);
    EXPECT_NEAR(around.x, 35, 0.6);  // the lock and the swath's particles within 6 m of it (29-30 m)
    EXPECT_NEAR(around.y, 11, 0.05);
    EXPECT_GT(around.weight, 0.45);
    EXPECT_LT(around.weight, 0.45 + 0.55 * 2.0 / 18.0);
    // The median path reports the centre it used.
    const ClusterCore tight = cluster_core(p, std::vector<uint32_t>{0, 1, 2}, 6.0, scratch);
    EXPECT_NEAR(tight.centre_x, 35, 1.0);
}

TEST(ClusterCore, EmptyOrWeightlessMembersGiveAnEmptyCore) {
    ParticleSet p;
    std::vector<double> scratch;
    EXPECT_EQ(cluster_core(p, {}, 5.0, scratch).weight, 0.0);
    add(p, 1, 1, 0, 0);
    const ClusterCore c = cluster_core(p, all_of(p), 5.0, scratch);
    EXPECT_EQ(c.weight, 0.0);
    EXPECT_EQ(c.count, 0u);
}

namespace {

// Five particles: 1, 2 and 3 with range-bias statistics (they explained sightings), 0 and 4 without (4 a fresh
// injected one).
ParticleSet sighted_and_fresh() {
    ParticleSet p;
    add(p, 1, 1, 0, 0.1f, 0.0f);
    add(p, 1, 2, 0, 0.2f, 3.5f);
    add(p, 2, 1, 0, 0.3f, 0.7f);
    add(p, 9, 9, 0, 0.15f, 1.0f);
    add(p, 5, 5, 0, 0.25f, 0.0f);
    return p;
}

}  // namespace

TEST(ClusterCore, SightedMembersAreThoseWhoseHistoryExplainsASighting) {
    // Members 0-2 of a cluster; particle 3 is not a member but is sighted too.
    const ParticleSet p = sighted_and_fresh();
    std::vector<uint32_t> out{7};
    const double total = sighted_members(p, {0, 1, 2}, out);
    EXPECT_EQ(out, (std::vector<uint32_t>{1, 2}));
    EXPECT_NEAR(total, 0.2 + 0.3 + 0.15, 1e-6);
    // The sighted core of the members: particles 1 and 2 only.
    std::vector<double> scratch;
    const ClusterCore c = cluster_core(p, out, 6.0, scratch);
    EXPECT_EQ(c.count, 2u);
    EXPECT_NEAR(c.weight, 0.5, 1e-6);
    EXPECT_NEAR(c.x, (0.2 * 1 + 0.3 * 2) / 0.5, 1e-6);
}

TEST(ClusterCore, SightedWeightPerClusterSumsOnlyTheParticlesThatExplainedASighting) {
    // Cluster 0: particles 0 (not sighted) and 1 (sighted); cluster 1: particle 2 (sighted); particle 3 in no
    // cluster (a light bin) though sighted; cluster 2: particle 4, fresh from an injection.
    const ParticleSet p = sighted_and_fresh();
    std::vector<double> out{42.0};
    sighted_weight_per_cluster(p, {0, 0, 1, -1, 2}, 3, out);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_NEAR(out[0], 0.2, 1e-7);
    EXPECT_NEAR(out[1], 0.3, 1e-7);
    EXPECT_DOUBLE_EQ(out[2], 0.0);  // the injected cluster has no sighting behind it
}
