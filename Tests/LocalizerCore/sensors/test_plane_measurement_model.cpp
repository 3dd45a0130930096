// Tests for sensors/plane_measurement_model.hpp and ParticleFilter::update_planes: the wall field against
// brute force, a plane along a true wall favours the true pose over shifted and rotated ones, non-finite and
// zero-extent planes are ignored, the per-anchor gate, and the filter step (weights stay finite, headings
// along the walls gain weight).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "pf/particle_filter.hpp"
#include "sensors/plane_measurement_model.hpp"
#include "support/filter_fixtures.hpp"

using namespace wf::loc;

namespace {

constexpr float kPiF = 3.14159265f;

ParticleSet particles(const std::vector<std::array<float, 3>> &poses) {
    ParticleSet p;
    p.resize(poses.size());
    for (size_t i = 0; i < poses.size(); ++i) {
        p.x[i] = poses[i][0]; p.y[i] = poses[i][1]; p.yaw_offset[i] = poses[i][2];
        p.scale[i] = 1; p.weight[i] = 1.0f / static_cast<float>(poses.size()); p.floor[i] = 0; p.evidence[i] = 0;
    }
    return p;
}

// A plane on the VIO plane; with yaw offset 0 and scale 1 the VIO frame is the map frame shifted so that the
// camera (VIO origin) sits at the particle.
wf_plane_observation plane(uint64_t id, double ce, double cn, double normal_yaw, double width) {
    return wf_plane_observation{id, ce, cn, normal_yaw, width};
}

std::vector<float> log_likelihoods(const LocalizerMap &map, const ParticleSet &p, const std::vector<wf_plane_observation> &obs,
                                   PlanePrepareStats *stats = nullptr) {
    PlaneModelState st;
    st.ensure_fields(map);
    const auto z = prepare_planes(obs.data(), obs.size(), 0, 0, 0, st.params, nullptr, stats);
    std::vector<float> ll(p.size(), 0.0f);
    plane_log_likelihood(p, st.fields, st.table, st.params, z.data(), z.size(), ll.data());
    return ll;
}

}  // namespace

TEST(PlaneMeasurementModel, WallFieldMatchesBruteForceDistanceAndDirection) {
    auto world = wf::test::l_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const WallField f = build_wall_field(map.floors[0].walls, 0.1f, 1.0f);
    ASSERT_FALSE(f.empty());
    const auto &walls = world.floors[0].walls;
    int checked = 0;
    for (int iy = 0; iy < f.ny; iy += 7) {
        for (int ix = 0; ix < f.nx; ix += 7) {
            const double cx = f.x0 + (ix + 0.5) * f.cell_m, cy = f.y0 + (iy + 0.5) * f.cell_m;
            double best = 1e9, best_dir = 0;
            for (const auto &w : walls) {
                const double ex = w[2] - w[0], ey = w[3] - w[1];
                double t = ((cx - w[0]) * ex + (cy - w[1]) * ey) / (ex * ex + ey * ey);
                t = std::clamp(t, 0.0, 1.0);
                const double d = std::hypot(w[0] + t * ex - cx, w[1] + t * ey - cy);
                if (d < best) { best = d; best_dir = std::fmod(std::atan2(ey, ex) + wf::test::kPi, wf::test::kPi); }
            }
            const size_t c = static_cast<size_t>(iy) * f.nx + ix;
            const double d = f.distance_m(c);
            if (best >= 1.0) {
                EXPECT_EQ(f.distance_level(c), WallField::kDistanceLevels - 1) << "cell " << ix << "," << iy;
            } else {
                EXPECT_NEAR(d, best, 0.5 / 63 + 1e-4) << "cell " << ix << "," << iy;
                // The direction is that of the nearest wall (skip cells equidistant from two walls: corners).
                double second = 1e9;
                for (const auto &w : walls) {
                    const double ex = w[2] - w[0], ey = w[3] - w[1];
                    double t = std::clamp(((cx - w[0]) * ex + (cy - w[1]) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
                    const double dd = std::hypot(w[0] + t * ex - cx, w[1] + t * ey - cy);
                    if (dd > best + 1e-6) second = std::min(second, dd);
                }
                if (second - best > 0.05) {
                    const double dir = f.direction_rad(c);
                    const double diff = std::fabs(wf::test::wrap(2 * (dir - best_dir))) / 2;
                    EXPECT_LT(diff, 0.5 * wf::test::kPi / 128 + 1e-4) << "cell " << ix << "," << iy;
                }
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 100);
}

// Corridor 20 m x 2 m; the camera at (10, 1) sees the north wall y = 2 as a 3 m plane 1 m to its north
// (normal pointing south). The true pose must score best; shifted by 0.4 m or rotated by 20 degrees less.
TEST(PlaneMeasurementModel, PlaneAlongTrueWallFavoursTruePose) {
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const ParticleSet p = particles({{10, 1, 0}, {10, 1.4f, 0}, {10.0f, 0.6f, 0}, {10, 1, 0.35f}, {10, 1, -0.35f}, {10, 1, kPiF}});
    const auto ll = log_likelihoods(map, p, {plane(1, 0, 1, -kPiF / 2, 3)});
    EXPECT_GT(ll[0], ll[1] + 0.1f);
    EXPECT_GT(ll[0], ll[2] + 0.1f);
    EXPECT_GT(ll[0], ll[3] + 0.1f);
    EXPECT_GT(ll[0], ll[4] + 0.1f);
    // Turned by 180 degrees the plane lands on the south wall, as well placed: the model cannot tell (the
    // corridor is symmetric), and must not pretend to.
    EXPECT_NEAR(ll[0], ll[5], 0.05f);
    // A true-pose plane scores the best possible value, log(z_hit + z_rand) * weight = 0.
    EXPECT_NEAR(ll[0], 0.0f, 0.02f);
}

// Particles spread over two floors take the per-particle path; it must agree with the one-floor block path.
TEST(PlaneMeasurementModel, MixedFloorsAgreeWithTheOneFloorPath) {
    auto world = wf::test::corridor_world();
    world.floors.push_back(world.floors[0]);
    world.floors[1].elevation_m = 4;
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const std::vector<std::array<float, 3>> poses = {{10, 1, 0}, {10, 1.4f, 0.1f}, {4, 0.7f, 1.2f}, {15, 1.2f, kPiF}};
    ParticleSet one = particles(poses), mixed = particles(poses);
    mixed.floor[1] = 1;
    mixed.floor[3] = 1;
    const std::vector<wf_plane_observation> obs = {plane(1, 0, 1, -kPiF / 2, 3), plane(2, 1, -1, kPiF / 2, 1.2)};
    const auto a = log_likelihoods(map, one, obs), b = log_likelihoods(map, mixed, obs);
    for (size_t i = 0; i < poses.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-5f) << i;
    EXPECT_GT(a[0], a[1]);
}

// Runs of identical particles (resampling copies) are scored once: every copy gets exactly the value the
// particle gets on its own, and runs broken by one differing field are scored apart.
TEST(PlaneMeasurementModel, IdenticalCopiesScoreExactlyAsAlone) {
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const std::vector<std::array<float, 3>> poses = {{10, 1, 0}, {10, 1.4f, 0.1f}, {4, 0.7f, 1.2f}, {15, 1.2f, kPiF}};
    std::vector<std::array<float, 3>> copies;
    for (size_t k = 0; k < poses.size(); ++k) {
        for (size_t c = 0; c <= k; ++c) copies.push_back(poses[k]);  // runs of 1, 2, 3 and 4 copies
    }
    copies.push_back(poses[0]);  // the first pose again, after a different one: a run of its own
    ParticleSet p = particles(copies);
    p.scale[2] = 1.3f;  // breaks the second run into two (the scale differs)
    const std::vector<wf_plane_observation> obs = {plane(1, 0, 1, -kPiF / 2, 3), plane(2, 1, -1, kPiF / 2, 1.2)};
    const auto all = log_likelihoods(map, p, obs);
    for (size_t i = 0; i < copies.size(); ++i) {
        ParticleSet alone = particles({copies[i]});
        alone.scale[0] = p.scale[i];
        EXPECT_EQ(all[i], log_likelihoods(map, alone, obs)[0]) << "particle " << i;
    }
    EXPECT_NE(all[1], all[2]);  // the scale matters, so the broken run really was scored twice
}

// The run scan compares the poses' bits: a pose one float step from its neighbour starts a run, and one equal
// to it but for the sign of a zero yaw offset starts a run too, scored as it is alone (the same value as the
// neighbour's: the sign of a zero does not change the points).
TEST(PlaneMeasurementModel, NearCopiesAndSignedZerosScoreAsAlone) {
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const float x1 = std::nextafter(10.0f, 11.0f);
    const std::vector<std::array<float, 3>> poses = {{10, 1, 0},  {10, 1, 0},  {x1, 1, 0}, {x1, 1, 0},
                                                     {10, 1, -0.0f}, {10, 1, 0}, {10, 1, -0.0f}};
    ParticleSet p = particles(poses);
    const std::vector<wf_plane_observation> obs = {plane(1, 0, 1, -kPiF / 2, 3), plane(2, 1, -1, kPiF / 2, 1.2)};
    const auto all = log_likelihoods(map, p, obs);
    for (size_t i = 0; i < poses.size(); ++i) {
        EXPECT_EQ(all[i], log_likelihoods(map, particles({poses[i]}), obs)[0]) << "particle " << i;
    }
    EXPECT_EQ(all[4], all[0]);
}

TEST(PlaneMeasurementModel, ScaleAndYawOffsetMapThePlane) {
    // VIO is rotated by +90 degrees from the map (yaw offset -pi/2) and 10 % short (scale 1.1): a plane that
    // lies 0.909 m to the VIO west is 1 m to the map north, on the wall.
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    ParticleSet p = particles({{10, 1, -kPiF / 2}, {10, 1, 0}});
    p.scale[0] = 1.1f;
    p.scale[1] = 1.1f;
    const auto ll = log_likelihoods(map, p, {plane(1, -1 / 1.1, 0, 0, 3)});
    EXPECT_NEAR(ll[0], 0.0f, 0.03f);
    EXPECT_LT(ll[1], ll[0] - 0.3f);
}

TEST(PlaneMeasurementModel, NonFiniteAndZeroExtentPlanesAreIgnored) {
    auto world = wf::test::corridor_world();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(world, o);
    const ParticleSet p = particles({{10, 1, 0}, {10, 1.4f, 0.3f}});
    const double nan = std::numeric_limits<double>::quiet_NaN();
    PlanePrepareStats stats;
    const auto ll = log_likelihoods(map, p,
                                    {plane(1, nan, 1, -kPiF / 2, 3), plane(2, 0, 1, nan, 3), plane(3, 0, 1, -kPiF / 2, nan),
                                     plane(4, 0, 1, -kPiF / 2, 0), plane(5, 0, 1, -kPiF / 2, 0.05),
                                     plane(6, 0, 1, -kPiF / 2, -1), plane(7, 30, 1, -kPiF / 2, 3)},
                                    &stats);
    EXPECT_EQ(stats.non_finite, 3u);
    EXPECT_EQ(stats.too_narrow, 3u);
    EXPECT_EQ(stats.too_far, 1u);
    EXPECT_EQ(ll[0], 0.0f);
    EXPECT_EQ(ll[1], 0.0f);
}

TEST(PlaneMeasurementModel, GateAdmitsAnAnchorOncePerInterval) {
    PlaneGate gate;
    EXPECT_TRUE(gate.admit(7, 10.0, 1.0));
    EXPECT_FALSE(gate.admit(7, 10.5, 1.0));
    EXPECT_TRUE(gate.admit(8, 10.5, 1.0));  // another anchor
    EXPECT_TRUE(gate.admit(7, 11.0, 1.0));
    EXPECT_TRUE(gate.admit(7, 3.0, 1.0));  // time went back (a new session): admitted
}

namespace {

wf_localizer_options filter_options() {
    auto o = wf::test::default_options();
    o.particle_count = 20000;
    o.min_particles = 2000;
    o.max_particles = 40000;
    o.adaptive_particle_count = 0;
    return o;
}

// Share of the weight on poses that explain the two walls: on the corridor's centre line (|y - 1| <= 0.2 m)
// with a heading along the corridor (either way, within half_width rad).
double weight_along_axis(const ParticleFilter &pf, double half_width) {
    const auto &p = pf.particles();
    double near = 0, all = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        all += p.weight[i];
        const double h = pf.vio_yaw() + p.yaw_offset[i];
        if (std::fabs(wf::test::wrap(2 * h)) / 2 <= half_width && std::fabs(p.y[i] - 1.0) <= 0.2) near += p.weight[i];
    }
    return near / all;
}

bool weights_finite(const ParticleFilter &pf) {
    double s = 0;
    for (float w : pf.particles().weight) {
        if (!std::isfinite(w) || w < 0) return false;
        s += w;
    }
    return std::fabs(s - 1) < 1e-3;
}

}  // namespace

// Standing in the corridor facing VIO east with unknown heading, the two long walls seen as planes leave the
// weight on headings along the corridor (either way), and never produce NaN.
TEST(ParticleFilterPlanes, WallPlanesConcentrateWeightOnHeadingsAlongTheCorridor) {
    auto world = wf::test::corridor_world();
    const auto o = filter_options();
    auto map = wf::test::build_map(world, o);
    ParticleFilter pf(std::move(map), o, 42);
    ASSERT_EQ(pf.init_floor_only(0), WF_LOC_OK);
    wf_vio_sample s{0.0, 0.0, 0.0, 0.0, WF_VIO_TRACKING_NORMAL};
    ASSERT_EQ(pf.predict(s), WF_LOC_OK);
    const double before = weight_along_axis(pf, 0.2);
    // True pose: (10, 1) heading map east, VIO = map shifted by (-10, -1): north wall 1 m north, south wall
    // 1 m south.
    const std::vector<wf_plane_observation> obs = {plane(1, 0, 1, -kPiF / 2, 3), plane(2, 0.5, -1, kPiF / 2, 2.5)};
    ASSERT_EQ(pf.update_planes(obs.data(), obs.size(), 0.1), WF_LOC_OK);
    EXPECT_EQ(pf.plane_model().last_applied, 2u);
    EXPECT_TRUE(weights_finite(pf));
    const double after_one = weight_along_axis(pf, 0.2);
    // Two more reports of the same walls, each after the per-anchor interval.
    ASSERT_EQ(pf.update_planes(obs.data(), obs.size(), 1.2), WF_LOC_OK);
    ASSERT_EQ(pf.update_planes(obs.data(), obs.size(), 2.3), WF_LOC_OK);
    EXPECT_TRUE(weights_finite(pf));
    const double after = weight_along_axis(pf, 0.2);
    EXPECT_LT(before, 0.06);
    EXPECT_GT(after_one, 1.5 * before);
    EXPECT_GT(after, 3 * before);
    // The same anchors again within the interval are gated: the weights do not move.
    const std::vector<float> w0 = pf.particles().weight;
    ASSERT_EQ(pf.update_planes(obs.data(), obs.size(), 2.8), WF_LOC_OK);
    EXPECT_EQ(pf.plane_model().last_applied, 0u);
    EXPECT_EQ(pf.plane_model().last_stats.gated, 2u);
    EXPECT_EQ(pf.particles().weight, w0);
}

// The named parameters plane.weight and plane.min_interval_s reach the update: weight 0 makes planes carry no
// information; a shorter interval admits an anchor again sooner.
TEST(ParticleFilterPlanes, PlaneWeightAndIntervalAreNamedParameters) {
    auto world = wf::test::corridor_world();
    const auto o = filter_options();
    const std::vector<wf_plane_observation> obs = {plane(1, 0, 1, -kPiF / 2, 3), plane(2, 0.5, -1, kPiF / 2, 2.5)};
    auto along_after_planes = [&](double weight) {
        ParticleFilter pf(wf::test::build_map(world, o), o, 42);
        EXPECT_EQ(pf.set_parameter("plane.weight", weight), WF_LOC_OK);
        EXPECT_EQ(pf.init_floor_only(0), WF_LOC_OK);
        wf_vio_sample s{0.0, 0.0, 0.0, 0.0, WF_VIO_TRACKING_NORMAL};
        EXPECT_EQ(pf.predict(s), WF_LOC_OK);
        const double before = weight_along_axis(pf, 0.2);
        EXPECT_EQ(pf.update_planes(obs.data(), obs.size(), 0.1), WF_LOC_OK);
        return weight_along_axis(pf, 0.2) / before;
    };
    EXPECT_NEAR(along_after_planes(0.0), 1.0, 1e-3);
    EXPECT_GT(along_after_planes(0.5), 1.5);
    EXPECT_GT(along_after_planes(1.0), along_after_planes(0.5));

    ParticleFilter pf(wf::test::build_map(world, o), o, 42);
    double v = 0;
    ASSERT_EQ(pf.get_parameter("plane.min_interval_s", v), WF_LOC_OK);
    EXPECT_DOUBLE_EQ(v, 1.0);
    ASSERT_EQ(pf.set_parameter("plane.min_interval_s", 0.2), WF_LOC_OK);
    EXPECT_EQ(pf.set_parameter("plane.weight", -1.0), WF_LOC_ERR_INVALID_ARGUMENT);
    ASSERT_EQ(pf.init_floor_only(0), WF_LOC_OK);
    wf_vio_sample s{0.0, 0.0, 0.0, 0.0, WF_VIO_TRACKING_NORMAL};
    ASSERT_EQ(pf.predict(s), WF_LOC_OK);
    ASSERT_EQ(pf.update_planes(obs.data(), obs.size(), 0.1), WF_LOC_OK);
    ASSERT_EQ(pf.update_planes(obs.data(), obs.size(), 0.4), WF_LOC_OK);  // 0.3 s later: admitted at 0.2 s
    EXPECT_EQ(pf.plane_model().last_applied, 2u);
}

TEST(ParticleFilterPlanes, BadPlanesLeaveTheFilterUnchanged) {
    auto world = wf::test::corridor_world();
    const auto o = filter_options();
    auto map = wf::test::build_map(world, o);
    ParticleFilter pf(std::move(map), o, 7);
    const wf_plane_observation good = plane(1, 0, 1, -kPiF / 2, 3);
    EXPECT_EQ(pf.update_planes(&good, 1, 0.0), WF_LOC_ERR_NOT_INITIALIZED);
    ASSERT_EQ(pf.init_floor_only(0), WF_LOC_OK);
    wf_vio_sample s{0.0, 0.0, 0.0, 0.0, WF_VIO_TRACKING_NORMAL};
    ASSERT_EQ(pf.predict(s), WF_LOC_OK);
    const std::vector<float> w0 = pf.particles().weight;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const wf_plane_observation bad_pose = plane(2, nan, 1, -kPiF / 2, 3);
    EXPECT_EQ(pf.update_planes(&bad_pose, 1, 0.1), WF_LOC_ERR_NON_FINITE_INPUT);
    EXPECT_NE(pf.error().find("non-finite"), std::string::npos);
    EXPECT_EQ(pf.particles().weight, w0);
    const wf_plane_observation zero_extent = plane(3, 0, 1, -kPiF / 2, 0);
    EXPECT_EQ(pf.update_planes(&zero_extent, 1, 0.2), WF_LOC_OK);
    EXPECT_EQ(pf.particles().weight, w0);
    EXPECT_EQ(pf.update_planes(nullptr, 1, 0.3), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(pf.update_planes(&good, 1, nan), WF_LOC_ERR_NON_FINITE_INPUT);
    // A plane no particle can explain (far from every wall for all of them) keeps the weights finite.
    const wf_plane_observation nowhere = plane(4, 0.2, 0.1, 0.3, 3);
    EXPECT_EQ(pf.update_planes(&nowhere, 1, 0.4), WF_LOC_OK);
    EXPECT_TRUE(weights_finite(pf));
}

TEST(ParticleFilterPlanes, CApiUpdatesPlanes) {
    auto world = wf::test::corridor_world();
    wf_localizer *loc = nullptr;
    const auto o = filter_options();
    ASSERT_EQ(wf_localizer_create(&loc, &world.map(), &o, 3), WF_LOC_OK);
    const wf_plane_observation good = plane(1, 0, 1, -kPiF / 2, 3);
    EXPECT_EQ(wf_localizer_update_planes(nullptr, &good, 1, 0), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_update_planes(loc, &good, 1, 0), WF_LOC_ERR_NOT_INITIALIZED);
    ASSERT_EQ(wf_localizer_init_floor_only(loc, 0), WF_LOC_OK);
    wf_vio_sample s{0.0, 0.0, 0.0, 0.0, WF_VIO_TRACKING_NORMAL};
    ASSERT_EQ(wf_localizer_predict(loc, &s), WF_LOC_OK);
    EXPECT_EQ(wf_localizer_update_planes(loc, &good, 1, 0.1), WF_LOC_OK);
    EXPECT_EQ(wf_localizer_update_planes(loc, nullptr, 0, 0.2), WF_LOC_OK);
    const wf_plane_observation bad = plane(2, 0, 1, std::numeric_limits<double>::infinity(), 3);
    EXPECT_EQ(wf_localizer_update_planes(loc, &bad, 1, 0.3), WF_LOC_ERR_NON_FINITE_INPUT);
    EXPECT_NE(std::string(wf_localizer_last_error(loc)).find("plane"), std::string::npos);
    wf_localizer_estimate e{};
    ASSERT_EQ(wf_localizer_get_estimate(loc, &e), WF_LOC_OK);
    EXPECT_TRUE(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.heading_rad));
    wf_localizer_free(loc);
}
