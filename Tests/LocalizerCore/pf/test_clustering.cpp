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
