// Motion model driven by ARKit VIO pose deltas (Fusco & Coughlan 2018: VIO "dead reckoning" between sign
// sightings). Two parts:
//  - VioDeltaTracker turns the stream of VIO samples into per-frame deltas and classifies them: an ordinary
//    move, a frame to skip (first sample, tracking not available), or a relocalization jump / origin reset
//    (implausible displacement or turn between consecutive frames, or tracking coming back after being
//    unavailable), which is skipped while the particles' uncertainty is inflated instead; after a tracking loss
//    part of the cloud walks on at the pre-loss velocity, part takes the yaw change as a turn, and when the VIO
//    displacement across the loss is a plausible walk, part takes it as measured (WalkOnParams).
//  - apply_motion moves every particle: the VIO displacement is rotated by the particle's yaw offset and
//    scaled by its scale factor; noise grows with distance walked and angle turned (the odometry model of
//    Probabilistic Robotics section 5.4 in spirit: error driven by motion, not by time), as a random walk
//    whose variance is proportional to distance and turn so the result is independent of the frame rate,
//    and a move that crosses a wall multiplies the particle's weight by `wall_crossing_weight`.
#pragma once

#include <cstdint>

#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"
#include "wf_localizer.h"

namespace wf::loc {

/// Noise parameters of the motion model (wf_localizer_options fields of the same names).
struct MotionNoise {
    /// Isotropic position std per sqrt(meter walked) (m/sqrt(m)) and per sqrt(radian turned) (m/sqrt(rad)).
    float position_per_sqrt_meter = 0.15f;
    float position_per_sqrt_rad = 0.03f;
    /// Yaw-offset random-walk std per sqrt(meter walked) (rad/sqrt(m)) and per sqrt(radian turned).
    float yaw_per_sqrt_meter = 0.02f;
    float yaw_per_sqrt_rad = 0.04f;
    /// Scale random-walk std per sqrt(meter walked) (1/sqrt(m)).
    float scale_per_sqrt_meter = 0.003f;
    float scale_min = 0.8f, scale_max = 1.25f;
    /// Weight factor of a particle whose move crosses a wall.
    float wall_crossing_weight = 1e-3f;

    static MotionNoise from_options(const wf_localizer_options &o);
};

enum class DeltaKind {
    /// Nothing to apply (first sample, tracking not available, duplicate timestamp).
    kNone,
    /// An ordinary frame-to-frame move.
    kMove,
    /// A relocalization jump / VIO origin reset: skip the displacement, keep the map heading, inflate noise.
    kJump,
};

/// One classified VIO delta.
struct VioDelta {
    DeltaKind kind = DeltaKind::kNone;
    /// Displacement on the VIO plane, meters, and VIO yaw change, radians (wrapped).
    float d_east = 0, d_north = 0, d_yaw = 0;
    /// Noise multiplier (limited tracking).
    float noise_factor = 1;
    /// For kJump: extra position and yaw-offset std to add, meters / radians.
    float jump_position_sigma = 0, jump_yaw_sigma = 0;
    /// For kJump: tracking was lost (notAvailable) before this sample, so the traveler moved unobserved.
    bool after_tracking_loss = false;
    /// For kJump after a tracking loss: where the traveler would be had they walked on at the velocity
    /// VIO measured just before the loss (displacement on the pre-loss VIO plane, meters; 0 = no walk-on
    /// hypothesis), and the share of particles that take it (WalkOnParams).
    float walk_on_east = 0, walk_on_north = 0, walk_on_share = 0;
    /// Along-track std of the walk-on displacement per meter of it, and its cross-track std, meters.
    float walk_on_along_sigma_per_m = 0, walk_on_cross_sigma_m = 0;
    /// For kJump after a tracking loss: the share of particles for which the VIO yaw change across the loss is
    /// the traveler's own turn (ARKit kept its world frame: the orientation was tracked by the IMU meanwhile, or
    /// tracking relocalized into the old map) rather than a new origin; their yaw offsets keep their values.
    float frame_kept_share = 0;
    /// For kJump after a tracking loss whose VIO displacement (d_east, d_north) is a plausible walk: the share
    /// of particles that take it as measured (ARKit relocalized into its old map), and its position std, meters.
    float measured_share = 0, measured_sigma_m = 0;
};

/// The walk-on prior after a tracking loss (ours; the pedestrian's constant-velocity prior of pedestrian dead
/// reckoning, e.g. Harle 2013, "A survey of indoor inertial positioning systems for pedestrians"): a traveler
/// walking when ARKit lost tracking most likely walked on at about the same speed and along the same line. On
/// tracking's return a share of the particles is moved by the pre-loss VIO velocity times the time lost
/// (rotated by each particle's yaw offset, scaled by its scale), with an along-track spread for the unknown
/// speed and a small cross-track one; the others take the isotropic lost-tracking noise as before (the
/// traveler stopped or turned). Walls still weigh every move. Named parameters "motion.walk_on_*".
struct WalkOnParams {
    /// Share of the particles that walk on (0 = off: every particle takes the isotropic noise).
    double share = 0.5;
    /// Pre-loss window over which the velocity is measured, seconds (needs at least half of it tracked).
    double window_s = 1.5;
    /// Walking speeds, m/s: below min the traveler is taken as standing (no walk-on); above max the window held
    /// a snap, not a walk.
    double min_speed_mps = 0.3, max_speed_mps = 2.0;
    /// Longest loss the walk-on covers, seconds: after longer ones a turn is as likely as not.
    double max_lost_s = 10.0;
    /// Along-track std per meter of walk-on (speed unknown within about a quarter) and cross-track std, meters.
    double along_sigma_per_m = 0.25, cross_sigma_m = 0.3;
    /// Share of the particles that take the VIO yaw change across the loss as a turn (VioDelta::frame_kept_share).
    double frame_kept_share = 0.5;
    /// Share of the particles that take the VIO displacement across the loss as measured, when it is a plausible
    /// walk: at least min_measured_m (a smaller one is the isotropic share's "stood still") and at most
    /// jump_position_sigma_m + max_speed_mps x the time lost. Drawn before the walk-on split; its position std
    /// is measured_sigma_m + measured_sigma_per_m x the displacement (drift through the relocalization).
    double measured_share = 0.4;
    double min_measured_m = 0.5;
    double measured_sigma_m = 0.2, measured_sigma_per_m = 0.1;
};

class VioDeltaTracker {
public:
    explicit VioDeltaTracker(const wf_localizer_options &o) : opts_(o) {}

    /// Classifies `s` against the previous usable sample. Non-finite samples must be rejected before.
    VioDelta push(const wf_vio_sample &s);

    bool has_yaw() const { return has_last_; }
    /// Last usable VIO yaw, radians.
    double last_yaw() const { return last_.yaw_rad; }
    /// Last usable VIO camera position on the VIO plane, meters (valid when has_yaw()).
    double last_east() const { return last_.east_m; }
    double last_north() const { return last_.north_m; }
    /// Time tracking was lost (the last usable sample's time), seconds; negative while tracking is available.
    double lost_since() const { return lost_since_; }
    /// Seconds ARKit has reported limited tracking without a break (from the first limited sample of the spell to
    /// the last usable sample); negative while tracking is normal or lost.
    double tracking_limited_s() const {
        return has_last_ && lost_since_ < 0 && last_.tracking == WF_VIO_TRACKING_LIMITED && limited_since_ >= 0
                   ? last_.t - limited_since_
                   : -1;
    }
    void reset() {
        has_last_ = false;
        lost_since_ = -1;
        recent_count_ = 0;
        origin_reset_ = false;
        limited_since_ = -1;
    }
    /// The VIO origin was reset: the next usable sample's delta is a snap (jump noise, the yaw change absorbed by
    /// the offsets), with none of a tracking loss's shares that assume the old frame kept (WalkOnParams: the
    /// frame-kept turn, the measured displacement); the walk-on share stays when tracking was lost meanwhile.
    void note_origin_reset() { origin_reset_ = true; }
    /// The walk-on prior's parameters (named parameters "motion.walk_on_*").
    WalkOnParams &mutable_walk_on() { return walk_on_; }
    const WalkOnParams &walk_on() const { return walk_on_; }

private:
    /// Fills the walk-on fields of `d`, a jump after `lost_s` seconds lost.
    void add_walk_on(VioDelta &d, double lost_s) const;
    /// VIO velocity on the VIO plane (m/s) over the last window_s of remembered samples; false when they span
    /// less than half the window (too few usable samples since the last seam).
    bool pre_loss_velocity(double &v_east, double &v_north) const;
    /// Remembers a usable sample for the pre-loss velocity (a ring of the last kRecent).
    void remember(const wf_vio_sample &s);
    /// Forgets the remembered samples and remembers `s` alone: a seam (first sample, a tracking return, a
    /// relocalization snap) that no velocity may span.
    void restart_recent(const wf_vio_sample &s);

    static constexpr int kRecent = 64;
    wf_localizer_options opts_;
    WalkOnParams walk_on_;
    /// Recent usable samples (t, east, north), oldest first from recent_head_ - recent_count_.
    double recent_t_[kRecent] = {}, recent_e_[kRecent] = {}, recent_n_[kRecent] = {};
    int recent_head_ = 0, recent_count_ = 0;
    wf_vio_sample last_{};
    bool has_last_ = false;
    /// Time tracking became unavailable (-1 while available).
    double lost_since_ = -1;
    /// note_origin_reset() was called and no usable sample has come since.
    bool origin_reset_ = false;
    /// Time of the first sample of the current limited spell (-1 outside one).
    double limited_since_ = -1;
};

/// Motion noise not yet applied. The noise is a random walk, so the variances of consecutive frames add up:
/// instead of drawing four normals per particle at every 30 Hz frame, the variance is accumulated and
/// injected in one draw once 0.25 m or 0.25 rad of motion (or 10 frames) has built up. The distribution
/// after each injection is the same; between injections it lags by at most that much motion.
struct MotionNoiseAccumulator {
    double var_position = 0, var_yaw = 0, var_scale = 0;
    double distance_m = 0, turn_rad = 0;
    int frames = 0;
    bool due() const { return distance_m >= 0.25 - 1e-9 || turn_rad >= 0.25 - 1e-9 || frames >= 10; }
    /// Adds one frame's random-walk noise variances (std = k * sqrt(distance or turn) per frame, so variances
    /// add): `dist_m` walked, `turn_rad` turned, `k2` the squared noise multiplier (limited tracking).
    void add_frame(const MotionNoise &noise, float dist_m, float turn, float k2) {
        auto sq = [](float v) { return v * v; };
        var_position += k2 * (sq(noise.position_per_sqrt_meter) * dist_m + sq(noise.position_per_sqrt_rad) * turn);
        var_yaw += k2 * (sq(noise.yaw_per_sqrt_meter) * dist_m + sq(noise.yaw_per_sqrt_rad) * turn);
        var_scale += k2 * sq(noise.scale_per_sqrt_meter) * dist_m;
        distance_m += dist_m;
        turn_rad += turn;
        ++frames;
    }
    void clear() { *this = MotionNoiseAccumulator{}; }
};

/// Moves all particles by `delta` (kMove or kJump), sampling noise from `rng`, and down-weights particles
/// whose move crosses a wall of their floor. `acc` carries noise not yet injected (nullptr: inject every
/// frame). Returns the sum of the weights afterwards (not normalised).
double apply_motion(ParticleSet &p, const VioDelta &delta, const MotionNoise &noise, const LocalizerMap &map,
                    Rng &rng, MotionNoiseAccumulator *acc = nullptr);

}  // namespace wf::loc
