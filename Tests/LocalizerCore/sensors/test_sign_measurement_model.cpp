// Tests for sensors/sign_measurement_model.hpp: the likelihood peaks at the true pose, walls and the field
// of view gate the signs, unknown kinds and bad values are ignored, negative information on and off.
#include <gtest/gtest.h>

#include <cmath>

#include "sensors/sign_measurement_model.hpp"
#include "support/filter_fixtures.hpp"

using namespace wf::loc;

namespace {

ParticleSet one_particle(float x, float y, float heading) {
    ParticleSet p;
    p.resize(1);
    p.x[0] = x; p.y[0] = y; p.yaw_offset[0] = heading; p.scale[0] = 1; p.weight[0] = 1; p.floor[0] = 0;
    return p;
}

float ll_at(const LocalizerMap &map, const SignModelParams &m, float x, float y, float heading,
            const std::vector<PreparedSighting> &z) {
    const ParticleSet p = one_particle(x, y, heading);
    float ll;
    sign_log_likelihood(p, 0.0f, map, m, z.data(), z.size(), &ll);
    return ll;
}

SignModelParams no_negative(SignModelParams m) {
    m.negative_information = false;
    return m;
}

}  // namespace

// A walker at (14, 1.25) facing west sees the west-end exit 14 m... too far; at (8, 1.25) facing west it sees
// the exit on the west end wall at 8 m, bearing 0.
TEST(SignMeasurementModel, LikelihoodPeaksAtTruePose) {
    auto world = wf::test::l_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const SignModelParams m = no_negative(SignModelParams::from_options(o));
    const float tx = 6, ty = 1.25f, th = static_cast<float>(wf::test::kPi) - 0.1f;
    // Predicted sighting of sign 0 at (0, 1.25) from the true pose.
    const float r = std::hypot(0 - tx, 1.25f - ty);
    const float b = static_cast<float>(wf::test::wrap(std::atan2(1.25 - ty, 0 - tx) - th));
    const std::vector<PreparedSighting> z = {{wf::test::kExit, r, b, 0.1f}};
    const float at_truth = ll_at(map, m, tx, ty, th, z);
    float best = -1e30f, bx = 0, by = 0, bh = 0;
    for (float x = 2; x <= 12; x += 0.25f) {
        for (float y = 0.5f; y <= 2.0f; y += 0.25f) {
            for (float h = th - 0.3f; h <= th + 0.3f; h += 0.02f) {
                const float v = ll_at(map, m, x, y, h, z);
                if (v > best) { best = v; bx = x; by = y; bh = h; }
            }
        }
    }
    EXPECT_NEAR(best, at_truth, 0.05f);
    EXPECT_NEAR(bx, tx, 0.26f);
    EXPECT_NEAR(bh, th, 0.05f);
    // Moving 1 m towards the sign (range error 1 m, sigma 0.1 + 0.12 * 5 = 0.7 m) costs about 1 nat.
    EXPECT_LT(ll_at(map, m, tx - 1, ty, th, z), at_truth - 0.5f);
    // Facing the south wall: no exit sign in view (the restroom sign is another kind); clutter floor only.
    const float clutter = std::log(0.1f / (12.0f * static_cast<float>(o.horizontal_fov_rad)));
    EXPECT_NEAR(ll_at(map, m, tx, ty, -1.5708f, z), clutter, 1e-4f);
    (void)by;
}

TEST(SignMeasurementModel, WallBlocksVisibility) {
    auto world = wf::test::l_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const SignModelParams m = no_negative(SignModelParams::from_options(o));
    // Sign 3 at (30, 12) faces west. From (26, 12) (west of the corridor wall x = 27.5, outside the building)
    // looking east, the sign is 4 m ahead but the wall is in between.
    const std::vector<PreparedSighting> z = {{wf::test::kExit, 4.0f, 0.0f, 0.1f}};
    const float clutter = std::log(0.1f / (12.0f * static_cast<float>(o.horizontal_fov_rad)));
    EXPECT_NEAR(ll_at(map, m, 26, 12, 0, z), clutter, 1e-4f);
    EXPECT_GT(ll_at(map, m, 28.0f, 12, 0, z), clutter);  // inside the corridor at (28, 12)
}

TEST(SignMeasurementModel, OutsideFieldOfViewIsClutter) {
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const SignModelParams m = no_negative(SignModelParams::from_options(o));
    // Sign 2 at (8, 2) faces south; from (8, 1) facing east it is 90 deg to the left: outside the 48 deg FOV.
    const std::vector<PreparedSighting> z = {{wf::test::kExit, 1.0f, 1.5708f, 0.1f}};
    const float clutter = std::log(0.1f / (12.0f * static_cast<float>(o.horizontal_fov_rad)));
    // The east-end exit (12 m away, bearing 0) is in view but does not explain a 1 m / 90 deg sighting.
    EXPECT_NEAR(ll_at(map, m, 8, 1, 0, z), clutter, 0.01f);
    // Facing north the sign is straight ahead and explains a 1 m, bearing-0 sighting.
    const std::vector<PreparedSighting> ahead = {{wf::test::kExit, 1.0f, 0.0f, 0.1f}};
    EXPECT_GT(ll_at(map, m, 8, 1, 1.5708f, ahead), clutter + 3);
}

// clutter_only_log_likelihood (the localized flag's test of a frame explained only as false positives, pf/
// localized_hysteresis) is exactly the value the model gives a particle that sees no sign of the sighted kinds:
// here two sightings of different scores from a pose facing a blank wall.
TEST(SignMeasurementModel, ClutterOnlyLogLikelihoodIsTheValueOfAParticleSeeingNoSign) {
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const SignModelParams m = no_negative(SignModelParams::from_options(o));
    const std::vector<PreparedSighting> z = {{wf::test::kExit, 1.0f, 0.2f, 0.1f}, {wf::test::kExit, 4.0f, -0.1f, 0.6f}};
    const float expected = std::log(0.1f / (12.0f * static_cast<float>(o.horizontal_fov_rad))) +
                           std::log(0.6f / (12.0f * static_cast<float>(o.horizontal_fov_rad)));
    EXPECT_NEAR(clutter_only_log_likelihood(m, z.data(), z.size()), expected, 1e-5f);
    // From (8, 1) facing south (the wall 1 m away, no sign in view) the model gives exactly that value.
    EXPECT_EQ(ll_at(map, m, 8, 1, -1.5708f, z), clutter_only_log_likelihood(m, z.data(), z.size()));
}

TEST(SignMeasurementModel, PrepareSkipsBadValuesAndUnknownKinds) {
    const SignModelParams m;
    const wf_sign_observation obs[] = {
        {0, 3.0, 0.1, 1.0}, {0, NAN, 0.1, 1.0}, {0, 3.0, INFINITY, 1.0}, {5, 3.0, 0.0, 1.0}, {-1, 3, 0, 1},
        {1, 2.0, 0.0, 0.5}, {0, -1.0, 0.0, 1.0}};
    size_t bad = 0;
    const auto z = prepare_sightings(obs, 7, m, 2, &bad);
    EXPECT_EQ(bad, 3u);
    ASSERT_EQ(z.size(), 2u);
    EXPECT_EQ(z[0].kind, 0);
    EXPECT_NEAR(z[0].clutter_probability, 0.1f, 1e-6f);
    EXPECT_NEAR(z[1].clutter_probability, 1 - 0.9f * 0.5f, 1e-6f);  // low score: trusted less
}

TEST(SignMeasurementModel, NegativeInformationOnAndOff) {
    auto world = wf::test::corridor_world();
    auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    SignModelParams on = SignModelParams::from_options(o);
    on.negative_information = true;
    const SignModelParams off = no_negative(on);
    // At (17, 1) facing east, the east-end exit is 3 m ahead: plainly visible. An empty frame:
    const std::vector<PreparedSighting> none;
    EXPECT_NEAR(ll_at(map, on, 17, 1, 0, none), std::log(0.8f), 1e-5f);
    EXPECT_EQ(ll_at(map, off, 17, 1, 0, none), 0.0f);
    // Facing west, nothing plainly visible (the west exit is 17 m away): no penalty.
    EXPECT_EQ(ll_at(map, on, 17, 1, static_cast<float>(wf::test::kPi), none), 0.0f);
    // The sign detected where predicted: no penalty on top of the sighting's likelihood.
    const std::vector<PreparedSighting> seen = {{wf::test::kExit, 3.0f, 0.0f, 0.1f}};
    EXPECT_NEAR(ll_at(map, on, 17, 1, 0, seen), ll_at(map, off, 17, 1, 0, seen), 1e-6f);
    // A sign nearer than negative_info_min_range_m (2.5 m) hangs above the top of a portrait frame: its absence
    // from the frame carries no information.
    EXPECT_FLOAT_EQ(on.negative_info_min_range_m, 2.5f);
    EXPECT_EQ(ll_at(map, on, 18, 1, 0, none), 0.0f);  // 2 m: overhead, no penalty
    EXPECT_EQ(ll_at(map, on, 19, 1, 0, none), 0.0f);  // 1 m
    SignModelParams all = on;
    all.negative_info_min_range_m = 0;
    EXPECT_NEAR(ll_at(map, all, 18, 1, 0, none), std::log(0.8f), 1e-5f);  // the rule off: penalised
}

// A kind the detector did not look for on a frame (its wall kinds in turn): a plainly visible sign of that kind
// costs nothing by its absence; the other kinds' absence still does, and a sighting of the kind counts as searched.
TEST(SignMeasurementModel, NoNegativeInformationForAKindNotSearched) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 20, 2).seed(1, 1).seed(10, 1);
    f.sign(wf::test::kRestroom, 20, 1, -1, 0).sign(wf::test::kExit, 20, 1.5f, -1, 0);
    w.floors.push_back(f);
    auto o = wf::test::default_options();
    const auto map = wf::test::build_map(w, o);
    SignModelParams m = SignModelParams::from_options(o);
    m.negative_information = true;
    const ParticleSet p = one_particle(17, 1, 0);  // both signs 3 m ahead: plainly visible
    auto ll = [&](const std::vector<PreparedSighting> &z, const uint8_t *unsearched) {
        float v;
        sign_log_likelihood(p, 0.0f, map, m, z.data(), z.size(), &v, nullptr, nullptr, unsearched);
        return v;
    };
    const std::vector<PreparedSighting> none;
    const float miss = std::log(0.8f);
    EXPECT_NEAR(ll(none, nullptr), 2 * miss, 1e-5f);  // both searched, both missed
    const uint8_t restroomUnsearched[2] = {0, 1};
    EXPECT_NEAR(ll(none, restroomUnsearched), miss, 1e-5f);  // only the Exit sign's miss
    const uint8_t neither[2] = {1, 1};
    EXPECT_EQ(ll(none, neither), 0.0f);
    const uint8_t all[2] = {0, 0};
    EXPECT_EQ(ll(none, all), ll(none, nullptr));
    // A restroom sighting where predicted: the kind was searched after all, and the sighting scores as usual.
    const float r = std::hypot(3.0f, 0.0f);
    const std::vector<PreparedSighting> seen = {{wf::test::kRestroom, r, 0.0f, 0.1f}};
    EXPECT_EQ(ll(seen, restroomUnsearched), ll(seen, nullptr));
}

// With two visible signs of the same kind, one sighting is explained by either (data association mixture):
// the likelihood is the average of the two single-sign likelihoods plus clutter.
TEST(SignMeasurementModel, MixtureOverVisibleSigns) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 20, 20).seed(10, 10);
    f.sign(wf::test::kExit, 10, 20, 0, -1).sign(wf::test::kExit, 14, 20, 0, -1);
    w.floors.push_back(f);
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(w, o);
    SignModelParams m = no_negative(SignModelParams::from_options(o));
    m.range_bias_sigma = 0;  // the mixture alone (the bias term: RangeBias* below)
    const float h = static_cast<float>(wf::test::kPi / 2) - 0.25f;  // both in view
    const std::vector<PreparedSighting> z = {{wf::test::kExit, 10.0f, 0.25f, 0.1f}};  // sign 0 exactly
    const float ll = ll_at(map, m, 10, 10, h, z);
    const float sr0 = 0.1f + 0.12f * 10;
    const float r1 = std::hypot(4.0f, 10.0f);
    const float b1 = std::atan2(10.0f, 4.0f) - h;
    const float sr1 = 0.1f + 0.12f * r1;
    const float sb = static_cast<float>(o.bearing_sigma_rad);
    const float g0 = 1 / (2 * static_cast<float>(wf::test::kPi) * sr0 * sb);
    const float e1 = (10 - r1) / sr1, eb1 = (0.25f - b1) / sb;
    const float g1 = std::exp(-0.5f * (e1 * e1 + eb1 * eb1)) / (2 * static_cast<float>(wf::test::kPi) * sr1 * sb);
    const float expected = 0.1f / (12 * static_cast<float>(o.horizontal_fov_rad)) + 0.9f * 0.5f * (g0 + g1);
    EXPECT_NEAR(ll, std::log(expected), 1e-3f);
}

namespace {

/// One exit 10 m north of a particle at (10, 10) facing it (a 20 m box): the range-bias tests' world.
struct OneSignAhead {
    LocalizerMap map;
    SignModelParams m;
    float heading = static_cast<float>(wf::test::kPi / 2);
};

OneSignAhead one_sign_ahead() {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 20, 20).seed(10, 10);
    f.sign(wf::test::kExit, 10, 20, 0, -1);
    w.floors.push_back(f);
    const auto o = wf::test::default_options();
    OneSignAhead s{wf::test::build_map(w, o), no_negative(SignModelParams::from_options(o))};
    return s;
}

/// Log-likelihood of a sighting at `range_m` (bearing 0) for the particle of `world` holding range-bias
/// statistics (s1, s0); the statistics after the sighting are written to *after (s1, s0).
float ll_with_bias(const OneSignAhead &world, float s1, float s0, float range_m, float *after = nullptr) {
    ParticleSet p = one_particle(10, 10, world.heading);
    p.bias_s1[0] = s1;
    p.bias_s0[0] = s0;
    const std::vector<PreparedSighting> z = {{wf::test::kExit, range_m, 0.0f, 0.1f}};
    float ll;
    sign_log_likelihood(p, 0.0f, world.map, world.m, z.data(), z.size(), &ll, p.bias_s1.data(), p.bias_s0.data());
    if (after) {
        after[0] = p.bias_s1[0];
        after[1] = p.bias_s0[0];
    }
    return ll;
}

}  // namespace

// Without history the predicted range is the distance, its std grown by the prior: sqrt(s_r^2 + r^2 sigma_b^2).
TEST(SignMeasurementModel, RangeBiasPriorWidensThePrediction) {
    const OneSignAhead w = one_sign_ahead();
    const float r = 10, sb = w.m.bearing_sigma_rad, sigma_b = w.m.range_bias_sigma;
    ASSERT_GT(sigma_b, 0.0f);
    const float sr0 = w.m.range_sigma_base_m + w.m.range_sigma_per_meter * r;
    const float sr = std::sqrt(sr0 * sr0 + r * r * sigma_b * sigma_b);
    const float u = 1 / (w.m.max_range_m * 2 * w.m.half_fov_rad);
    for (const float z : {10.0f, 8.5f}) {
        const float e = (z - r) / sr;
        const float expected = 0.1f * u + 0.9f * std::exp(-0.5f * e * e) / (2 * static_cast<float>(wf::test::kPi) * sr * sb);
        EXPECT_NEAR(ll_with_bias(w, 0, 0, z), std::log(expected), 1e-4f) << z;
    }
}

// A history that established b = log(0.8) (a detector reading 20 % short) predicts 8 m for a sign 10 m away:
// a sighting at 8 m now scores higher than one at the true distance; with no history the order is reversed.
TEST(SignMeasurementModel, RangeBiasHistoryMovesThePrediction) {
    const OneSignAhead w = one_sign_ahead();
    const float s0 = 900, s1 = s0 * std::log(0.8f);  // posterior mean log(0.8) * 900 / (900 + 1 / sigma_b^2)
    EXPECT_GT(ll_with_bias(w, s1, s0, 8.0f), ll_with_bias(w, s1, s0, 10.0f));
    EXPECT_LT(ll_with_bias(w, 0, 0, 8.0f), ll_with_bias(w, 0, 0, 10.0f));
}

// A sighting the sign explains adds its log range ratio with the model's precision at that distance; clutter
// (a sighting no sign explains) adds nothing; above the precision cap both sums shrink together.
TEST(SignMeasurementModel, RangeBiasStatisticsUpdate) {
    const OneSignAhead w = one_sign_ahead();
    const float r = 10, rel = (w.m.range_sigma_base_m + w.m.range_sigma_per_meter * r) / r;
    float after[2];
    ll_with_bias(w, 0.5f, 20, 9.0f, after);
    EXPECT_NEAR(after[1], 20 + 1 / (rel * rel), 1e-3f);
    EXPECT_NEAR(after[0], 0.5f + std::log(0.9f) / (rel * rel), 1e-4f);
    ll_with_bias(w, 0.5f, 20, 3.0f, after);  // 7 m short: clutter
    EXPECT_EQ(after[0], 0.5f);
    EXPECT_EQ(after[1], 20.0f);
    const float cap = w.m.range_bias_max_precision;
    ll_with_bias(w, -0.1f * cap, cap, 9.0f, after);
    EXPECT_NEAR(after[1], cap, 1e-2f);
    EXPECT_LT(after[0] / after[1], -0.1f + 1e-6f);  // the mean moved towards log(0.9) = -0.105
    EXPECT_GT(after[0] / after[1], -0.11f);
    // sigma_b = 0: the model without the term reads and writes nothing.
    OneSignAhead off = one_sign_ahead();
    off.m.range_bias_sigma = 0;
    ll_with_bias(off, 0.5f, 20, 9.0f, after);
    EXPECT_EQ(after[0], 0.5f);
    EXPECT_EQ(after[1], 20.0f);
}
