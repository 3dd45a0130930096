// Tests for motion/vio_motion_model.hpp: exact zero-noise geometry, wall kills, jump handling, and the
// statistics of the noise over many particles (fixed seeds, tolerances stated per check).
#include <gtest/gtest.h>

#include <cmath>

#include "motion/vio_motion_model.hpp"
#include "support/filter_fixtures.hpp"

using namespace wf::loc;

namespace {

ParticleSet make_particles(size_t n, float x, float y, float off, float scale) {
    ParticleSet p;
    p.resize(n);
    for (size_t i = 0; i < n; ++i) {
        p.x[i] = x; p.y[i] = y; p.yaw_offset[i] = off; p.scale[i] = scale; p.weight[i] = 1.0f / n; p.floor[i] = 0;
    }
    return p;
}

MotionNoise zero_noise() {
    MotionNoise m;
    m.position_per_sqrt_meter = m.position_per_sqrt_rad = m.yaw_per_sqrt_meter = m.yaw_per_sqrt_rad = m.scale_per_sqrt_meter = 0;
    return m;
}

/// A return from a tracking loss without the jump's own noise: only the splits move the particles.
VioDelta noiseless_loss_return() {
    VioDelta d;
    d.kind = DeltaKind::kJump;
    d.after_tracking_loss = true;
    d.jump_position_sigma = 0;
    d.jump_yaw_sigma = 0;
    return d;
}

VioDelta move(float de, float dn, float dyaw = 0) {
    VioDelta d;
    d.kind = DeltaKind::kMove;
    d.d_east = de; d.d_north = dn; d.d_yaw = dyaw;
    return d;
}

}  // namespace

TEST(VioMotionModel, ZeroNoiseRotatesAndScalesDisplacement) {
    auto world = wf::test::corridor_world();
    const auto map = wf::test::build_map(world, wf::test::default_options());
    ParticleSet p = make_particles(3, 5, 1, static_cast<float>(wf::test::kPi / 2), 1.1f);
    Rng rng(1);
    // VIO moves 1 m "north"; the particle's yaw offset is +90 deg, so in the map it moves 1.1 m west.
    apply_motion(p, move(0, 1), zero_noise(), map, rng);
    EXPECT_NEAR(p.x[0], 5 - 1.1f, 1e-5f);
    EXPECT_NEAR(p.y[0], 1, 1e-5f);
    EXPECT_FLOAT_EQ(p.weight[0], 1.0f / 3);
}

TEST(VioMotionModel, MoveThroughWallKillsMoveInCorridorDoesNot) {
    auto world = wf::test::corridor_world();
    const auto map = wf::test::build_map(world, wf::test::default_options());
    ParticleSet p = make_particles(2, 5, 1.5f, 0, 1);
    p.y[1] = 1.0f;
    Rng rng(1);
    const double sum = apply_motion(p, move(0, 0.8f), zero_noise(), map, rng);  // north by 0.8 m
    EXPECT_NEAR(p.weight[0], 0.5f * 1e-3f, 1e-9f);  // crossed y = 2
    EXPECT_FLOAT_EQ(p.weight[1], 0.5f);              // stayed inside
    EXPECT_NEAR(sum, 0.5 + 0.5e-3, 1e-6);
}

TEST(VioDeltaTracker, ClassifiesMovesJumpsAndTrackingLoss) {
    auto o = wf::test::default_options();
    VioDeltaTracker tr(o);
    EXPECT_EQ(tr.push({0.0, 0, 0, 0, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kNone);  // first sample
    auto d = tr.push({0.1, 0.1, 0, 0.05, WF_VIO_TRACKING_NORMAL});
    EXPECT_EQ(d.kind, DeltaKind::kMove);
    EXPECT_FLOAT_EQ(d.noise_factor, 1.0f);
    d = tr.push({0.2, 0.2, 0, 0.05, WF_VIO_TRACKING_LIMITED});
    EXPECT_EQ(d.kind, DeltaKind::kMove);
    EXPECT_FLOAT_EQ(d.noise_factor, 3.0f);
    d = tr.push({0.3, 2.5, 0, 0.05, WF_VIO_TRACKING_NORMAL});  // 2.3 m in 0.1 s
    EXPECT_EQ(d.kind, DeltaKind::kJump);
    d = tr.push({0.4, 2.5, 0, 0.05 + 1.2, WF_VIO_TRACKING_NORMAL});  // 69 deg in 0.1 s
    EXPECT_EQ(d.kind, DeltaKind::kJump);
    EXPECT_NEAR(d.d_yaw, 1.2f, 1e-6f);
    EXPECT_EQ(tr.push({0.5, 2.6, 0, 1.25, WF_VIO_TRACKING_NOT_AVAILABLE}).kind, DeltaKind::kNone);
    EXPECT_EQ(tr.push({1.5, 9.0, 0, 1.25, WF_VIO_TRACKING_NOT_AVAILABLE}).kind, DeltaKind::kNone);
    d = tr.push({2.5, 0.0, 0.0, 1.25, WF_VIO_TRACKING_NORMAL});  // back, origin reset
    EXPECT_EQ(d.kind, DeltaKind::kJump);
    // Lost for 2.1 s (since the last good sample at 0.4 s) at 0.7 m/s on top of 0.5 m.
    EXPECT_NEAR(d.jump_position_sigma, 0.5f + 0.7f * 2.1f, 1e-4f);
    EXPECT_EQ(tr.push({2.6, 0.1, 0.0, 1.25, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kMove);
}

// ARKit's relocalization snaps the world origin by 0.2-1.5 m within one frame (stress profile vio-rough,
// docs/benchmarks.md "Eleventh stop": a 1.13 m snap taken as a step left a lock 3.4 m off). At 30 Hz a snap
// of 0.6 m or more is a jump; a lanyard camera's fastest real frame step (0.25 m) and a slow caller's walk
// (1 m in 0.5 s) are moves.
TEST(VioDeltaTracker, ASnapNoWalkingCameraMakesInOneFrameIsAJump) {
    auto o = wf::test::default_options();
    VioDeltaTracker tr(o);
    const double dt = 1.0 / 30.0;
    tr.push({0.0, 0, 0, 0, WF_VIO_TRACKING_NORMAL});
    EXPECT_EQ(tr.push({dt, 0.25, 0, 0, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kMove);
    EXPECT_EQ(tr.push({2 * dt, 0.25 + 0.6, 0, 0, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kJump);
    EXPECT_EQ(tr.push({3 * dt, 0.85, 1.13, 0, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kJump);
    EXPECT_EQ(tr.push({3 * dt + 0.5, 0.85, 2.13, 0, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kMove);
}

// World tracking restarted (ARKit initializing again: a new VIO origin and yaw): the next sample's delta is a snap
// whatever its size, with the yaw change absorbed by every particle (no frame-kept turn, no measured walk: the old
// frame is gone); through a tracking loss the position noise still grows with the time lost and the walk-on share
// stays. Only the next usable sample is affected.
TEST(VioDeltaTracker, ANewVioFrameIsASnapWithoutTheShareThatKeepsTheOldFrame) {
    auto o = wf::test::default_options();
    const double dt = 1.0 / 30.0;
    VioDeltaTracker tr(o);
    tr.push({0.0, 0, 0, 0, WF_VIO_TRACKING_NORMAL});
    tr.note_origin_reset();
    // 5 cm and 0.3 rad: a move without the note.
    VioDelta d = tr.push({dt, 0.05, 0, 0.3, WF_VIO_TRACKING_LIMITED});
    ASSERT_EQ(d.kind, DeltaKind::kJump);
    EXPECT_FALSE(d.after_tracking_loss);
    EXPECT_NEAR(d.d_yaw, 0.3f, 1e-6f);
    EXPECT_EQ(d.frame_kept_share, 0.0f);
    EXPECT_EQ(d.measured_share, 0.0f);
    EXPECT_NEAR(d.jump_position_sigma, 0.5f, 1e-6f);
    EXPECT_EQ(tr.push({2 * dt, 0.10, 0, 0.3, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kMove);

    // Walking 1.2 m/s, lost for 2 s, then a new frame.
    VioDeltaTracker lost(o);
    double t = 0;
    for (int k = 0; k <= 60; ++k, t += dt) lost.push({t, 1.2 * t, 0, 0.1, WF_VIO_TRACKING_NORMAL});
    const double t_lost = t - dt;
    for (; t < t_lost + 2.0; t += dt) lost.push({t, 0, 0, 0, WF_VIO_TRACKING_NOT_AVAILABLE});
    lost.note_origin_reset();
    d = lost.push({t_lost + 2.0, 0.2, 0.1, -2.0, WF_VIO_TRACKING_LIMITED});
    ASSERT_EQ(d.kind, DeltaKind::kJump);
    EXPECT_TRUE(d.after_tracking_loss);
    EXPECT_NEAR(d.jump_position_sigma, 0.5f + 0.7f * 2.0f, 1e-4f);
    EXPECT_FLOAT_EQ(d.walk_on_share, 0.5f);
    EXPECT_EQ(d.frame_kept_share, 0.0f);
    EXPECT_EQ(d.measured_share, 0.0f);

    // A note before the first sample has nothing to skip.
    VioDeltaTracker fresh(o);
    fresh.note_origin_reset();
    EXPECT_EQ(fresh.push({0.0, 3, 4, 1, WF_VIO_TRACKING_LIMITED}).kind, DeltaKind::kNone);
    EXPECT_EQ(fresh.push({dt, 3.05, 4, 1, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kMove);
}

// How long the current limited spell has lasted (the lock rule's input): from its first limited sample; a normal
// or lost sample ends it.
TEST(VioDeltaTracker, MeasuresTheCurrentLimitedSpell) {
    auto o = wf::test::default_options();
    VioDeltaTracker tr(o);
    EXPECT_LT(tr.tracking_limited_s(), 0.0);
    tr.push({0.0, 0, 0, 0, WF_VIO_TRACKING_LIMITED});
    EXPECT_DOUBLE_EQ(tr.tracking_limited_s(), 0.0);
    tr.push({0.5, 0.1, 0, 0, WF_VIO_TRACKING_LIMITED});
    EXPECT_DOUBLE_EQ(tr.tracking_limited_s(), 0.5);
    tr.push({1.0, 0.2, 0, 0, WF_VIO_TRACKING_NORMAL});
    EXPECT_LT(tr.tracking_limited_s(), 0.0);
    tr.push({1.5, 0.3, 0, 0, WF_VIO_TRACKING_LIMITED});
    tr.push({2.5, 0.4, 0, 0, WF_VIO_TRACKING_LIMITED});
    EXPECT_DOUBLE_EQ(tr.tracking_limited_s(), 1.0);
    tr.push({3.0, 0.4, 0, 0, WF_VIO_TRACKING_NOT_AVAILABLE});
    EXPECT_LT(tr.tracking_limited_s(), 0.0);
    tr.push({4.0, 0.5, 0, 0, WF_VIO_TRACKING_LIMITED});  // a new spell after the loss
    EXPECT_DOUBLE_EQ(tr.tracking_limited_s(), 0.0);
}

// A 60 Hz stream moves the cloud as the same walk at 30 Hz does: every other sample is merged into the next,
// whose delta spans both (the motion noise is calibrated on 30 Hz sums of per-frame steps).
TEST(VioDeltaTracker, SamplesFasterThanThirtyHertzAreMergedIntoTheNext) {
    auto o = wf::test::default_options();
    VioDeltaTracker tr(o);
    tr.push({0.0, 0, 0, 0, WF_VIO_TRACKING_NORMAL});
    EXPECT_EQ(tr.push({1.0 / 60, 0.02, 0, 0.01, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kNone);
    EXPECT_DOUBLE_EQ(tr.last_east(), 0.0);  // the merged sample is not the reference
    auto d = tr.push({2.0 / 60, 0.045, 0, 0.02, WF_VIO_TRACKING_NORMAL});
    EXPECT_EQ(d.kind, DeltaKind::kMove);
    EXPECT_NEAR(d.d_east, 0.045f, 1e-6f);
    EXPECT_NEAR(d.d_yaw, 0.02f, 1e-6f);
    // 30 Hz with 3 ms of timestamp jitter is never merged.
    EXPECT_EQ(tr.push({2.0 / 60 + 1.0 / 30 - 0.003, 0.09, 0, 0.02, WF_VIO_TRACKING_NORMAL}).kind, DeltaKind::kMove);
}

// The walk-on prior (WalkOnParams): a traveler walking 1.2 m/s east when tracking is lost for 3 s would be
// 3.6 m further east on its return. The velocity comes from the last 1.5 s of usable samples; a traveler
// standing still, a loss longer than max_lost_s, or a window cut short by a snap gives no walk-on hypothesis.
TEST(VioDeltaTracker, ATrackingLossWhileWalkingCarriesThePreLossVelocity) {
    auto o = wf::test::default_options();
    const double dt = 1.0 / 30.0;
    auto walk_then_lose = [&](VioDeltaTracker &tr, double speed_mps, double lost_s) {
        double t = 0;
        for (int k = 0; k <= 60; ++k, t += dt) tr.push({t, speed_mps * t, 0, 0.1, WF_VIO_TRACKING_NORMAL});
        const double t_lost = t - dt;
        for (; t < t_lost + lost_s; t += dt) tr.push({t, 0, 0, 0, WF_VIO_TRACKING_NOT_AVAILABLE});
        return tr.push({t_lost + lost_s, speed_mps * t_lost, 0, 0.9, WF_VIO_TRACKING_NORMAL});
    };
    VioDeltaTracker walking(o);
    VioDelta d = walk_then_lose(walking, 1.2, 3.0);
    ASSERT_EQ(d.kind, DeltaKind::kJump);
    EXPECT_TRUE(d.after_tracking_loss);
    EXPECT_NEAR(d.walk_on_east, 1.2f * 3.0f, 1e-3f);
    EXPECT_NEAR(d.walk_on_north, 0.0f, 1e-6f);
    EXPECT_FLOAT_EQ(d.walk_on_share, 0.5f);
    EXPECT_FLOAT_EQ(d.frame_kept_share, 0.5f);
    EXPECT_NEAR(d.d_yaw, 0.8f, 1e-6f);  // the VIO yaw change across the loss is reported as it is
    EXPECT_EQ(d.measured_share, 0.0f);  // the pose resumed where it stopped: nothing measured to trust

    VioDeltaTracker standing(o);
    d = walk_then_lose(standing, 0.1, 3.0);  // below min_speed_mps
    EXPECT_EQ(d.kind, DeltaKind::kJump);
    EXPECT_EQ(d.walk_on_share, 0.0f);
    EXPECT_EQ(d.walk_on_east, 0.0f);

    VioDeltaTracker long_loss(o);
    d = walk_then_lose(long_loss, 1.2, 12.0);  // beyond max_lost_s (10 s)
    EXPECT_EQ(d.walk_on_share, 0.0f);

    // A snap just before the loss: the window after it is too short to measure a walk.
    VioDeltaTracker snapped(o);
    snapped.push({0.0, 0, 0, 0, WF_VIO_TRACKING_NORMAL});
    snapped.push({dt, 0.04, 0, 0, WF_VIO_TRACKING_NORMAL});
    snapped.push({2 * dt, 1.5, 0, 0, WF_VIO_TRACKING_NORMAL});  // a jump
    snapped.push({3 * dt, 1.54, 0, 0, WF_VIO_TRACKING_NORMAL});
    snapped.push({4 * dt, 0, 0, 0, WF_VIO_TRACKING_NOT_AVAILABLE});
    d = snapped.push({4 * dt + 2.0, 1.6, 0, 0, WF_VIO_TRACKING_NORMAL});
    EXPECT_EQ(d.kind, DeltaKind::kJump);
    EXPECT_EQ(d.walk_on_share, 0.0f);

    // The pose followed the walk through the loss (ARKit relocalized into its old map): 3.6 m is a plausible
    // walk in 3 s, so a share takes it as measured, with 0.2 m + 10 % of it as std; 30 m in 3 s is not.
    auto walk_then_return_at = [&](VioDeltaTracker &tr, double east_m) {
        double t = 0;
        for (int k = 0; k <= 60; ++k, t += dt) tr.push({t, 1.2 * t, 0, 0.1, WF_VIO_TRACKING_NORMAL});
        const double t_lost = t - dt;
        for (; t < t_lost + 3.0; t += dt) tr.push({t, 0, 0, 0, WF_VIO_TRACKING_NOT_AVAILABLE});
        return tr.push({t_lost + 3.0, 1.2 * t_lost + east_m, 0, 0.1, WF_VIO_TRACKING_NORMAL});
    };
    VioDeltaTracker relocalized(o);
    d = walk_then_return_at(relocalized, 3.6);
    EXPECT_FLOAT_EQ(d.measured_share, 0.4f);
    EXPECT_NEAR(d.measured_sigma_m, 0.2f + 0.1f * 3.6f, 1e-4f);
    EXPECT_NEAR(d.d_east, 3.6f, 1e-4f);
    VioDeltaTracker reset_far(o);
    d = walk_then_return_at(reset_far, 30.0);
    EXPECT_EQ(d.measured_share, 0.0f);

    // Switched off by its share.
    VioDeltaTracker off(o);
    off.mutable_walk_on().share = 0;
    off.mutable_walk_on().frame_kept_share = 0;
    off.mutable_walk_on().measured_share = 0;
    d = walk_then_return_at(off, 3.6);
    EXPECT_EQ(d.walk_on_share, 0.0f);
    EXPECT_EQ(d.frame_kept_share, 0.0f);
    EXPECT_EQ(d.measured_share, 0.0f);
}

/// 20k particles at (5, 1) in the 20 m corridor, heading offset 0, scale 1.1: the cloud a tracking return splits.
class TrackingReturn : public ::testing::Test {
protected:
    static constexpr size_t n = 20000;
    wf::test::World world = wf::test::corridor_world();
    LocalizerMap map = wf::test::build_map(world, wf::test::default_options());
    ParticleSet p = make_particles(n, 5, 1, 0.0f, 1.1f);
};

// The measured share: 40 % of 20k particles take the VIO displacement across the loss as an ordinary move (4 m
// east rotated by the offset, 0 here, times the scale 1.1), the rest stay for the isotropic noise (zero here);
// share within 0.02 (binomial standard error 0.0035).
TEST_F(TrackingReturn, TakesAPlausibleMeasuredWalkForAShare) {
    Rng rng(12);
    VioDelta d = noiseless_loss_return();
    d.d_east = 4.0f;
    d.measured_share = 0.4f;
    d.measured_sigma_m = 0;
    apply_motion(p, d, zero_noise(), map, rng);
    size_t moved = 0;
    for (size_t i = 0; i < n; ++i) {
        if (p.x[i] != 5.0f) {
            ++moved;
            EXPECT_NEAR(p.x[i], 5.0f + 1.1f * 4.0f, 1e-5f);
            EXPECT_FLOAT_EQ(p.y[i], 1.0f);
        }
    }
    EXPECT_NEAR(static_cast<double>(moved) / n, 0.4, 0.02);
}

// On tracking's return, half the particles walk on by the pre-loss displacement (rotated by their yaw offset,
// scaled, spread 25 % along track and 0.3 m across), the others stay for the isotropic noise (zero here); and
// half take the VIO yaw change as the traveler's turn (offset kept), the others as a new origin (offset
// absorbs it). 20k particles, fixed seed; shares within 0.02 (binomial standard error 0.0035), the walk-on
// mean within 0.05 m (standard error 0.006 m) and its along-track spread within 10 %.
TEST_F(TrackingReturn, SplitsTheCloudIntoWalkOnAndTurnHypotheses) {
    Rng rng(11);
    VioDelta d = noiseless_loss_return();
    d.d_yaw = 1.0f;
    d.walk_on_east = 4.0f; d.walk_on_north = 0; d.walk_on_share = 0.5f;
    d.walk_on_along_sigma_per_m = 0.25f; d.walk_on_cross_sigma_m = 0.3f;
    d.frame_kept_share = 0.5f;
    apply_motion(p, d, zero_noise(), map, rng);
    size_t stayed = 0, walked = 0, kept = 0;
    double sum_x = 0, sum_x2 = 0;
    for (size_t i = 0; i < n; ++i) {
        if (p.x[i] == 5.0f && p.y[i] == 1.0f) {
            ++stayed;
        } else {
            ++walked;
            sum_x += p.x[i];
            sum_x2 += static_cast<double>(p.x[i]) * p.x[i];
        }
        kept += std::fabs(p.yaw_offset[i]) < 1e-6f ? 1 : 0;
        if (std::fabs(p.yaw_offset[i]) >= 1e-6f) EXPECT_NEAR(p.yaw_offset[i], -1.0f, 1e-6f);
    }
    EXPECT_NEAR(static_cast<double>(stayed) / n, 0.5, 0.02);
    EXPECT_NEAR(static_cast<double>(kept) / n, 0.5, 0.02);
    const double mean = sum_x / walked, sd = std::sqrt(sum_x2 / walked - mean * mean);
    EXPECT_NEAR(mean, 5.0 + 1.1 * 4.0, 0.05);           // scale 1.1 times the 4 m walk-on
    EXPECT_NEAR(sd, 0.25 * 1.1 * 4.0, 0.1 * 0.25 * 1.1 * 4.0);
}

// A relocalization jump keeps every particle's map heading and does not apply the displacement.
TEST(VioMotionModel, JumpKeepsMapHeadingAndSkipsDisplacement) {
    auto world = wf::test::corridor_world();
    const auto map = wf::test::build_map(world, wf::test::default_options());
    ParticleSet p = make_particles(1000, 10, 1, 0.3f, 1);
    Rng rng(3);
    VioDelta d;
    d.kind = DeltaKind::kJump;
    d.d_east = 5; d.d_north = 3; d.d_yaw = 1.0f;   // VIO heading jumped by 1 rad
    d.jump_position_sigma = 0; d.jump_yaw_sigma = 0;
    apply_motion(p, d, zero_noise(), map, rng);
    // heading = vio_yaw + offset: the VIO yaw grew by 1, the offset must shrink by 1.
    EXPECT_NEAR(p.yaw_offset[0], 0.3f - 1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(p.x[0], 10);
    EXPECT_FLOAT_EQ(p.y[0], 1);
}

// Statistics of the noise: 20k particles moved 1 m east with heading noise off, position noise 0.04 m/sqrt(m):
// mean displacement 1 m (standard error 0.0003 m), spread 0.04 m (+-5 %).
TEST(VioMotionModel, NoiseMeanAndSpread) {
    wf::test::World world;
    world.floors.emplace_back();
    world.floors[0].seed(0, 0);
    const auto map = wf::test::build_map(world, wf::test::default_options());
    const size_t n = 20000;
    MotionNoise m = zero_noise();
    m.position_per_sqrt_meter = 0.04f;
    ParticleSet p = make_particles(n, 0, 0, 0, 1);
    Rng rng(99);
    apply_motion(p, move(1, 0), m, map, rng);
    double sx = 0, sy = 0, sxx = 0, syy = 0;
    for (size_t i = 0; i < n; ++i) {
        sx += p.x[i]; sy += p.y[i]; sxx += p.x[i] * p.x[i]; syy += p.y[i] * p.y[i];
    }
    const double mx = sx / n, my = sy / n;
    EXPECT_NEAR(mx, 1.0, 0.0015);
    EXPECT_NEAR(my, 0.0, 0.0015);
    EXPECT_NEAR(std::sqrt(sxx / n - mx * mx), 0.04, 0.002);
    EXPECT_NEAR(std::sqrt(syy / n - my * my), 0.04, 0.002);

    // Yaw-offset noise alone: a 1 m move with 0.1 rad/sqrt(m) spreads the offset by 0.1 rad (+-5 %) and the
    // endpoint laterally by about sin(0.1) ~ 0.1 m.
    MotionNoise y = zero_noise();
    y.yaw_per_sqrt_meter = 0.1f;
    ParticleSet q = make_particles(n, 0, 0, 0, 1);
    apply_motion(q, move(1, 0), y, map, rng);
    double so = 0, soo = 0;
    for (size_t i = 0; i < n; ++i) { so += q.yaw_offset[i]; soo += q.yaw_offset[i] * q.yaw_offset[i]; }
    EXPECT_NEAR(so / n, 0.0, 0.003);
    EXPECT_NEAR(std::sqrt(soo / n), 0.1, 0.005);

    // Limited tracking triples the spread.
    ParticleSet r = make_particles(n, 0, 0, 0, 1);
    VioDelta lim = move(1, 0);
    lim.noise_factor = 3;
    apply_motion(r, lim, m, map, rng);
    double ryy = 0;
    for (size_t i = 0; i < n; ++i) ryy += r.y[i] * r.y[i];
    EXPECT_NEAR(std::sqrt(ryy / n), 0.12, 0.006);
}

// Noise grows with the turn even without translation (turning in place blurs the yaw offset).
// Random walk: 100 steps of 1 cm spread as much as one step of 1 m (frame-rate independence).
TEST(VioMotionModel, SpreadIndependentOfStepCount) {
    wf::test::World world;
    world.floors.emplace_back();
    const auto map = wf::test::build_map(world, wf::test::default_options());
    MotionNoise m = zero_noise();
    m.position_per_sqrt_meter = 0.05f;
    ParticleSet p = make_particles(20000, 0, 0, 0, 1);
    Rng rng(21);
    for (int k = 0; k < 100; ++k) apply_motion(p, move(0.01f, 0), m, map, rng);
    double syy = 0;
    for (size_t i = 0; i < p.size(); ++i) syy += p.y[i] * p.y[i];
    EXPECT_NEAR(std::sqrt(syy / p.size()), 0.05, 0.0025);
}

TEST(VioMotionModel, TurnInPlaceAddsYawNoiseOnly) {
    wf::test::World world;
    world.floors.emplace_back();
    const auto map = wf::test::build_map(world, wf::test::default_options());
    MotionNoise m = zero_noise();
    m.yaw_per_sqrt_rad = 0.05f;
    ParticleSet p = make_particles(20000, 0, 0, 0, 1);
    Rng rng(5);
    apply_motion(p, move(0, 0, 2.0f), m, map, rng);  // turn 2 rad: std 0.05 * sqrt(2)
    double soo = 0;
    for (size_t i = 0; i < p.size(); ++i) soo += p.yaw_offset[i] * p.yaw_offset[i];
    EXPECT_NEAR(std::sqrt(soo / p.size()), 0.0707, 0.0035);
    EXPECT_FLOAT_EQ(p.x[0], 0);
}
