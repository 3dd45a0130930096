// Compass measurement model (sensors/compass_model): the mixture's shape, the cap, accuracy widening and the
// distance gate.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sensors/compass_model.hpp"

using wf::loc::CompassModel;
using wf::loc::CompassModelParams;
using wf::loc::ParticleSet;

namespace {

constexpr double kPi = 3.14159265358979323846;

ParticleSet particles_with_headings(const std::vector<float> &yaw_offsets) {
    ParticleSet p;
    p.resize(yaw_offsets.size());
    for (size_t i = 0; i < yaw_offsets.size(); ++i) {
        p.yaw_offset[i] = yaw_offsets[i];
        p.weight[i] = 1.0f / static_cast<float>(yaw_offsets.size());
    }
    return p;
}

}  // namespace

TEST(CompassModel, DensityIsNormalisedAndRobust) {
    // The mixture integrates to 1 over the circle (trapezoid rule, 3600 steps).
    for (double kappa : {0.5, 11.4, 60.0}) {
        double integral = 0;
        const int n = 3600;
        for (int k = 0; k < n; ++k) {
            integral += std::exp(CompassModel::log_density(-kPi + 2 * kPi * k / n, kappa, 0.15)) * 2 * kPi / n;
        }
        EXPECT_NEAR(integral, 1.0, 1e-4) << "kappa " << kappa;
    }
    // The outlier share bounds how unlikely any heading can be: u / (2 pi).
    EXPECT_NEAR(std::exp(CompassModel::log_density(kPi, 60.0, 0.15)), 0.15 / (2 * kPi), 1e-6);
}

TEST(CompassModel, RelativeLogLikelihoodPeaksAtTheReadingAndIsCapped) {
    CompassModelParams params;
    params.max_nats = 2.5;
    CompassModel m(params);
    // vio_yaw 0.3: headings 0.3 + offsets = reading, reading + 20 deg, + 90 deg, + 180 deg.
    const double reading = 1.0;
    const float base = static_cast<float>(reading - 0.3);
    const float d20 = static_cast<float>(20 * kPi / 180);
    ParticleSet p = particles_with_headings({base, base + d20, base + static_cast<float>(kPi / 2), base + static_cast<float>(kPi)});
    std::vector<float> ll(p.size());
    m.log_likelihood(p, 0.3f, reading, 0.0, ll.data());
    EXPECT_NEAR(ll[0], 0.0f, 1e-5);
    EXPECT_LT(ll[1], 0.0f);
    EXPECT_GT(ll[1], -2.5f);
    // The uncapped ratio at 90 and 180 degrees is about log((1-u) peak / (u/2pi)) ~ 5 nats for u = 0.05, kappa 10:
    // the cap (2.5) holds.
    EXPECT_FLOAT_EQ(ll[2], -2.5f);
    EXPECT_FLOAT_EQ(ll[3], -2.5f);
    // Uncapped, the same comparison follows the density.
    m.mutable_params().max_nats = 50;
    m.log_likelihood(p, 0.3f, reading, 0.0, ll.data());
    const double expect20 = CompassModel::log_density(d20, params.kappa, params.outlier_share) -
                            CompassModel::log_density(0, params.kappa, params.outlier_share);
    EXPECT_NEAR(ll[1], expect20, 1e-3);
}

TEST(CompassModel, KnownAccuracyWidensTheCore) {
    CompassModel m;
    const float off = static_cast<float>(30 * kPi / 180);
    ParticleSet p = particles_with_headings({0.0f, off});
    std::vector<float> sharp(2), wide(2);
    m.log_likelihood(p, 0.0f, 0.0, 0.0, sharp.data());
    m.log_likelihood(p, 0.0f, 0.0, 25 * kPi / 180, wide.data());
    EXPECT_LT(sharp[1], wide[1]);  // a 30-degree error costs less when the reading says it is +-25 degrees
}

TEST(CompassModel, AppliedOncePerDistanceWalked) {
    CompassModelParams params;
    params.min_distance_m = 4.0;
    CompassModel m(params);
    EXPECT_TRUE(m.due());  // the first reading is applied at once
    m.mark_applied();
    EXPECT_FALSE(m.due());
    m.add_distance(3.9);
    EXPECT_FALSE(m.due());  // standing still or a short step: the same disturbance, no new evidence
    m.add_distance(0.2);
    EXPECT_TRUE(m.due());
    m.mutable_params().enabled = false;
    EXPECT_FALSE(m.due());
}
