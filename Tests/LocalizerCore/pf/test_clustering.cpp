// Tests for pf/clustering.hpp: separate blobs become separate hypotheses, means and covariances are right,
// headings average circularly across +-pi.
#include <gtest/gtest.h>

#include <cmath>

#include "common/rng.hpp"
#include "pf/clustering.hpp"

using namespace wf::loc;

namespace {
void add_blob(ParticleSet &p, Rng &rng, size_t n, float x, float y, float heading, float sigma, float weight_each) {
    const size_t s = p.size();
    p.resize(s + n);
    for (size_t i = s; i < s + n; ++i) {
        p.x[i] = x + sigma * rng.normal();
        p.y[i] = y + sigma * rng.normal();
        p.yaw_offset[i] = heading + 0.05f * rng.normal();
        p.scale[i] = 1;
        p.floor[i] = 0;
        p.weight[i] = weight_each;
    }
}
}  // namespace

TEST(Clustering, TwoBlobsTwoHypotheses) {
    Rng rng(4);
    ParticleSet p;
    add_blob(p, rng, 3000, 5, 1, 0.0f, 0.3f, 0.7f / 3000);
    add_blob(p, rng, 2000, 25, 1, 3.14159f, 0.3f, 0.3f / 2000);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_GE(cl.size(), 2u);
    EXPECT_NEAR(cl[0].weight, 0.7, 0.01);
    EXPECT_NEAR(cl[1].weight, 0.3, 0.01);
    EXPECT_NEAR(cl[0].x, 5, 0.03);    // 3 standard errors of 0.3/sqrt(3000)
    EXPECT_NEAR(cl[1].x, 25, 0.03);
    EXPECT_NEAR(std::sqrt(cl[0].cov_xx), 0.3, 0.02);
    EXPECT_NEAR(std::sqrt(cl[0].cov_yy), 0.3, 0.02);
    EXPECT_NEAR(cl[0].cov_xy, 0.0, 0.01);
    EXPECT_NEAR(std::fabs(cl[1].heading), 3.14159, 0.01);
}

TEST(Clustering, CircularMeanAcrossPi) {
    Rng rng(5);
    ParticleSet p;
    add_blob(p, rng, 1000, 0, 0, 3.1f, 0.2f, 0.5f / 1000);
    add_blob(p, rng, 1000, 0, 0, -3.1f, 0.2f, 0.5f / 1000);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 1u);  // adjacent heading bins wrap around
    EXPECT_NEAR(std::fabs(cl[0].heading), 3.14159, 0.01);
    EXPECT_LT(cl[0].heading_std, 0.1);
}

TEST(Clustering, HeadingUsesVioYawPlusOffset) {
    Rng rng(6);
    ParticleSet p;
    add_blob(p, rng, 500, 0, 0, 0.5f, 0.1f, 1.0f / 500);
    ParticleClusterer c;
    const auto &cl = c.run(p, 1.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 1u);
    EXPECT_NEAR(cl[0].heading, 1.5, 0.01);
    EXPECT_NEAR(cl[0].yaw_offset, 0.5, 0.01);
}

namespace {
// Runs the clustering with dense bins and with the hash table and expects the very same result (the dense
// path numbers cells and clusters in the same order and sums in the same order).
void expect_same_clusters(const ParticleSet &p, float vio_yaw) {
    ClusterParams dense_params, hash_params;
    hash_params.dense_bins = false;
    ParticleClusterer dense, hash;
    const std::vector<ClusterSummary> a = dense.run(p, vio_yaw, dense_params);
    const std::vector<ClusterSummary> b = hash.run(p, vio_yaw, hash_params);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].weight, b[k].weight) << "cluster " << k;
        EXPECT_EQ(a[k].x, b[k].x) << "cluster " << k;
        EXPECT_EQ(a[k].y, b[k].y) << "cluster " << k;
        EXPECT_EQ(a[k].cov_xx, b[k].cov_xx) << "cluster " << k;
        EXPECT_EQ(a[k].cov_xy, b[k].cov_xy) << "cluster " << k;
        EXPECT_EQ(a[k].heading, b[k].heading) << "cluster " << k;
        EXPECT_EQ(a[k].floor, b[k].floor) << "cluster " << k;
        EXPECT_EQ(a[k].particle_count, b[k].particle_count) << "cluster " << k;
    }
    EXPECT_EQ(dense.particle_clusters(), hash.particle_clusters());
}
}  // namespace

// Dense bins (the fast path) and the hash table give identical clusters: a spread-out cloud over a floor
// (the costly case: thousands of bins near the weight threshold), blobs on two floors at negative
// coordinates, headings across +-pi.
TEST(Clustering, DenseBinsMatchHashTable) {
    Rng rng(11);
    ParticleSet spread;
    spread.resize(20000);
    for (size_t i = 0; i < spread.size(); ++i) {
        spread.x[i] = 40 * rng.uniform_float();
        spread.y[i] = 30 * rng.uniform_float();
        spread.yaw_offset[i] = static_cast<float>(rng.uniform(-3.14159, 3.14159));
        spread.scale[i] = 1;
        spread.floor[i] = 0;
        spread.weight[i] = (0.5f + rng.uniform_float()) / 20000.0f;
    }
    expect_same_clusters(spread, 0.7f);

    ParticleSet blobs;
    add_blob(blobs, rng, 3000, -12.5f, -3.2f, 3.1f, 0.4f, 0.5f / 3000);
    add_blob(blobs, rng, 2000, 7.0f, -20.0f, -3.1f, 0.6f, 0.3f / 2000);
    const size_t first_upper = blobs.size();
    add_blob(blobs, rng, 2000, -12.5f, -3.2f, 0.0f, 0.4f, 0.2f / 2000);
    for (size_t i = first_upper; i < blobs.size(); ++i) blobs.floor[i] = 2;
    expect_same_clusters(blobs, -2.0f);
}

// Particles too far apart for a small box of bins (two hypotheses 3 km apart) take the hash table path and
// still give both clusters.
TEST(Clustering, FarApartFallsBackToHashTable) {
    Rng rng(12);
    ParticleSet p;
    add_blob(p, rng, 500, 0, 0, 0.0f, 0.2f, 0.6f / 500);
    add_blob(p, rng, 500, 3000, 2000, 1.0f, 0.2f, 0.4f / 500);
    expect_same_clusters(p, 0.0f);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 2u);
    EXPECT_NEAR(cl[1].x, 3000, 0.05);
}

// The covariance comes from moments about the origin: a tight blob far from the origin (5 km, 5 cm spread)
// keeps its covariance.
TEST(Clustering, CovarianceFarFromOrigin) {
    Rng rng(13);
    ParticleSet p;
    add_blob(p, rng, 4000, 5000, -4000, 0.3f, 0.05f, 1.0f / 4000);
    ParticleClusterer c;
    const auto &cl = c.run(p, 0.0f, ClusterParams{});
    ASSERT_EQ(cl.size(), 1u);
    EXPECT_NEAR(std::sqrt(cl[0].cov_xx), 0.05, 0.004);
    EXPECT_NEAR(std::sqrt(cl[0].cov_yy), 0.05, 0.004);
    EXPECT_NEAR(cl[0].cov_xy, 0.0, 2e-4);
}
