#include "motion/vio_motion_model.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"
#include "common/simd_clones.hpp"

namespace wf::loc {

namespace {
// Physical limits that make a delta plausible at low frame rates: the jump thresholds grow by these rates
// times the frame interval (a 1 Hz caller may legitimately move 1.5 m + 2 m).
constexpr double kMaxWalkSpeedMps = 2.0;
constexpr double kMaxTurnRateRadps = 3.0;
// Cap on the position noise injected after tracking was unavailable for a long time, meters.
constexpr double kMaxLostPositionSigmaM = 5.0;
// Samples closer than this to the last used one are merged into the next (the motion model's noise, driven by
// the summed path length and turn, was calibrated at 30 Hz: ARKit's per-frame jitter adds to those sums at every
// frame, so a 60 Hz stream injected about twice the noise and converged later: the convergence study within 20 m
// 97 -> 90 %, eleventh stop). 30 Hz with up to 4 ms of timestamp jitter is never merged.
constexpr double kMinSampleIntervalS = 1.0 / 30.0 - 0.004;
}  // namespace

MotionNoise MotionNoise::from_options(const wf_localizer_options &o) {
    MotionNoise n;
    n.position_per_sqrt_meter = static_cast<float>(o.position_noise_per_sqrt_meter);
    n.position_per_sqrt_rad = static_cast<float>(o.position_noise_per_sqrt_rad);
    n.yaw_per_sqrt_meter = static_cast<float>(o.yaw_noise_per_sqrt_meter);
    n.yaw_per_sqrt_rad = static_cast<float>(o.yaw_noise_per_sqrt_rad);
    n.scale_per_sqrt_meter = static_cast<float>(o.scale_noise_per_sqrt_meter);
    n.scale_min = static_cast<float>(o.scale_min);
    n.scale_max = static_cast<float>(o.scale_max);
    n.wall_crossing_weight = static_cast<float>(o.wall_crossing_weight);
    return n;
}

void VioDeltaTracker::remember(const wf_vio_sample &s) {
    recent_t_[recent_head_] = s.t;
    recent_e_[recent_head_] = s.east_m;
    recent_n_[recent_head_] = s.north_m;
    recent_head_ = (recent_head_ + 1) % kRecent;
    recent_count_ = std::min(recent_count_ + 1, kRecent);
}

void VioDeltaTracker::restart_recent(const wf_vio_sample &s) {
    recent_count_ = 0;
    remember(s);
}

bool VioDeltaTracker::pre_loss_velocity(double &v_east, double &v_north) const {
    if (recent_count_ < 2) return false;
    const int newest = (recent_head_ + kRecent - 1) % kRecent;
    int oldest = newest;
    for (int k = 1; k < recent_count_; ++k) {
        const int i = (newest + kRecent - k) % kRecent;
        if (recent_t_[newest] - recent_t_[i] > walk_on_.window_s) break;
        oldest = i;
    }
    const double span = recent_t_[newest] - recent_t_[oldest];
    if (span < 0.5 * walk_on_.window_s) return false;
    v_east = (recent_e_[newest] - recent_e_[oldest]) / span;
    v_north = (recent_n_[newest] - recent_n_[oldest]) / span;
    return true;
}

void VioDeltaTracker::add_walk_on(VioDelta &d, double lost_s) const {
    double v_east = 0, v_north = 0;
    if (walk_on_.share <= 0 || lost_s > walk_on_.max_lost_s || !pre_loss_velocity(v_east, v_north)) return;
    const double speed = std::hypot(v_east, v_north);
    if (!(speed >= walk_on_.min_speed_mps && speed <= walk_on_.max_speed_mps)) return;
    d.walk_on_east = static_cast<float>(v_east * lost_s);
    d.walk_on_north = static_cast<float>(v_north * lost_s);
    d.walk_on_share = static_cast<float>(walk_on_.share);
    d.walk_on_along_sigma_per_m = static_cast<float>(walk_on_.along_sigma_per_m);
    d.walk_on_cross_sigma_m = static_cast<float>(walk_on_.cross_sigma_m);
}

VioDelta VioDeltaTracker::push(const wf_vio_sample &s) {
    VioDelta d;
    // The current limited spell: from its first limited sample; a normal or lost sample ends it.
    if (s.tracking != WF_VIO_TRACKING_LIMITED) {
        limited_since_ = -1;
    } else if (limited_since_ < 0) {
        limited_since_ = s.t;
    }
    if (s.tracking == WF_VIO_TRACKING_NOT_AVAILABLE) {
        // The pose is meaningless until tracking returns; remember when it was lost. The recent samples stay
        // as they were: on the return they give the pre-loss velocity.
        if (lost_since_ < 0) lost_since_ = has_last_ ? last_.t : s.t;
        return d;
    }
    if (!has_last_) {
        last_ = s;
        has_last_ = true;
        lost_since_ = -1;
        origin_reset_ = false;  // nothing to skip: this sample starts the first frame
        restart_recent(s);
        return d;
    }
    const double dt = s.t - last_.t;
    const double de = s.east_m - last_.east_m, dn = s.north_m - last_.north_m;
    const double dyaw = wrap_angle(s.yaw_rad - last_.yaw_rad);
    d.d_east = static_cast<float>(de);
    d.d_north = static_cast<float>(dn);
    d.d_yaw = static_cast<float>(dyaw);
    if (origin_reset_ || lost_since_ >= 0) {
        // A seam: tracking returns after notAvailable (ARKit may have kept its frame or reset its origin), or the
        // caller said the VIO frame is new (note_origin_reset: world tracking restarted). Skip the delta; the
        // traveler kept walking meanwhile, so the position noise grows with the time tracking was lost. The shares
        // that take the yaw change as a turn or the displacement as walked assume the old frame kept: a return
        // from a loss only, never a new frame.
        const bool new_frame = origin_reset_;
        const bool after_loss = lost_since_ >= 0;
        const double lost_s = after_loss ? std::max(0.0, s.t - lost_since_) : 0.0;
        d.kind = DeltaKind::kJump;
        d.jump_position_sigma = static_cast<float>(
            std::min(kMaxLostPositionSigmaM, opts_.jump_position_sigma_m + opts_.lost_tracking_speed_mps * lost_s));
        d.jump_yaw_sigma = static_cast<float>(opts_.jump_yaw_sigma_rad);
        if (after_loss) {
            d.after_tracking_loss = true;
            add_walk_on(d, lost_s);
        }
        if (after_loss && !new_frame) {
            d.frame_kept_share = static_cast<float>(walk_on_.frame_kept_share);
            const double moved = std::sqrt(de * de + dn * dn);
            if (walk_on_.measured_share > 0 && moved >= walk_on_.min_measured_m &&
                moved <= opts_.jump_position_sigma_m + walk_on_.max_speed_mps * lost_s) {
                d.measured_share = static_cast<float>(walk_on_.measured_share);
                d.measured_sigma_m = static_cast<float>(walk_on_.measured_sigma_m + walk_on_.measured_sigma_per_m * moved);
            }
        }
        origin_reset_ = false;
        lost_since_ = -1;
        last_ = s;
        restart_recent(s);  // a new VIO frame may start here: no velocity across the seam
        return d;
    }
    if (dt < 0) {
        // Time went backwards: a new session or a replay seam; treat as an origin reset.
        d.kind = DeltaKind::kJump;
        d.jump_position_sigma = static_cast<float>(opts_.jump_position_sigma_m);
        d.jump_yaw_sigma = static_cast<float>(opts_.jump_yaw_sigma_rad);
        last_ = s;
        restart_recent(s);
        return d;
    }
    if (dt < kMinSampleIntervalS) return VioDelta{};  // merged: the next sample's delta spans this one
    const double dist = std::sqrt(de * de + dn * dn);
    const double max_dist = opts_.jump_distance_m + kMaxWalkSpeedMps * dt;
    const double max_turn = opts_.jump_yaw_rad + kMaxTurnRateRadps * dt;
    last_ = s;
    if (dist > max_dist || std::fabs(dyaw) > max_turn) {
        // Relocalization jump (ARKit snapped its map): the traveler did not move that much in one frame.
        d.kind = DeltaKind::kJump;
        d.jump_position_sigma = static_cast<float>(opts_.jump_position_sigma_m);
        d.jump_yaw_sigma = static_cast<float>(opts_.jump_yaw_sigma_rad);
        restart_recent(s);  // the snap is not walking
        return d;
    }
    remember(s);
    if (dist == 0.0 && dyaw == 0.0) return d;  // nothing moved
    d.kind = DeltaKind::kMove;
    d.noise_factor = s.tracking == WF_VIO_TRACKING_LIMITED ? static_cast<float>(opts_.limited_tracking_noise_factor)
                                                           : 1.0f;
    return d;
}

WF_SIMD_CLONES double apply_motion(ParticleSet &p, const VioDelta &delta, const MotionNoise &noise, const LocalizerMap &map,
                    Rng &rng, MotionNoiseAccumulator *acc) {
    const size_t n = p.size();
    float *const xs = p.x.data();
    float *const ys = p.y.data();
    float *const offs = p.yaw_offset.data();
    float *const scales = p.scale.data();
    float *const ws = p.weight.data();
    const int16_t *const floors = p.floor.data();
    const FloorData *const fl = map.floors.data();
    const float kill = noise.wall_crossing_weight;
    double weight_sum = 0;

    if (delta.kind == DeltaKind::kJump) {
        // The VIO frame jumped: the camera's true map heading did not change, so the yaw offset absorbs the
        // VIO yaw jump; the displacement is dropped and replaced by inflated noise. After a tracking loss the
        // particles split (WalkOnParams): some take the yaw change as the traveler's turn, some walk on.
        const float sp = delta.jump_position_sigma, sy = delta.jump_yaw_sigma;
        // Walk-on share (after a tracking loss): the pre-loss VIO displacement, in the pre-loss VIO frame, so
        // rotated by the offset before this jump's yaw change; along- and cross-track spreads.
        const float we = delta.walk_on_east, wn = delta.walk_on_north;
        const float walk_len = std::sqrt(we * we + wn * wn);
        const bool walk_on = delta.walk_on_share > 0 && walk_len > 0;
        const float along_sigma = delta.walk_on_along_sigma_per_m, cross_sigma = delta.walk_on_cross_sigma_m;
        const bool kept_frame = delta.frame_kept_share > 0;
        const bool measured = delta.measured_share > 0;
        for (size_t i = 0; i < n; ++i) {
            float nx, ny;
            // A particle that takes the yaw change as a turn keeps its offset (the same draw of yaw noise).
            const float d_yaw = kept_frame && rng.uniform(0.0, 1.0) < delta.frame_kept_share ? 0.0f : delta.d_yaw;
            if (measured && rng.uniform(0.0, 1.0) < delta.measured_share) {
                // The displacement as VIO measured it, in the pre-loss frame (rotated by the offset before the
                // yaw change), as an ordinary move, with the drift of the relocalization around it.
                float sn, cs;
                fast_sincos(offs[i], sn, cs);
                const float sm = delta.measured_sigma_m;
                nx = xs[i] + scales[i] * (cs * delta.d_east - sn * delta.d_north) + sm * rng.normal();
                ny = ys[i] + scales[i] * (sn * delta.d_east + cs * delta.d_north) + sm * rng.normal();
                offs[i] = wrap_angle_f(offs[i] - d_yaw + sy * rng.normal());
            } else if (walk_on && rng.uniform(0.0, 1.0) < delta.walk_on_share) {
                float sn, cs;
                fast_sincos(offs[i], sn, cs);
                const float ue = (cs * we - sn * wn) / walk_len, un = (sn * we + cs * wn) / walk_len;
                const float along = scales[i] * walk_len * (1.0f + along_sigma * rng.normal());
                const float cross = cross_sigma * rng.normal();
                nx = xs[i] + along * ue - cross * un;
                ny = ys[i] + along * un + cross * ue;
                offs[i] = wrap_angle_f(offs[i] - d_yaw + sy * rng.normal());
            } else {
                offs[i] = wrap_angle_f(offs[i] - d_yaw + sy * rng.normal());
                nx = xs[i] + sp * rng.normal();
                ny = ys[i] + sp * rng.normal();
            }
            if (fl[floors[i]].walls.crosses(xs[i], ys[i], nx, ny)) ws[i] *= kill;
            xs[i] = nx;
            ys[i] = ny;
            weight_sum += ws[i];
        }
        return weight_sum;
    }
    if (delta.kind != DeltaKind::kMove) {
        for (size_t i = 0; i < n; ++i) weight_sum += ws[i];
        return weight_sum;
    }
    const float de = delta.d_east, dn = delta.d_north;
    const float dist = std::sqrt(de * de + dn * dn);
    const float turn = std::fabs(delta.d_yaw);
    const float k2 = delta.noise_factor * delta.noise_factor;
    // Random-walk noise: variances add over frames (std = k * sqrt(distance or turn) per frame).
    MotionNoiseAccumulator local;
    MotionNoiseAccumulator &a = acc ? *acc : local;
    a.add_frame(noise, dist, turn, k2);
    const bool inject = !acc || a.due();

    // Particles are processed in blocks of kBlock that stay in L1. Each block takes two passes: a branch-free
    // pass the compiler vectorises (the polynomial sincos, the new positions, the squared move length and the
    // clearance-grid cell of the start point), then a scalar pass doing the wall test, where a move shorter
    // than its start cell's guaranteed wall clearance skips the exact test (most particles, most frames).
    // The arithmetic and the order of the weight sums are those of a plain per-particle loop, so the result
    // is bit-identical to it.
    constexpr size_t kBlock = 512;  // 24 KB of stack buffers below
    const bool one_floor = map.floors.size() == 1;
    const WallIndex &walls0 = fl[0].walls;
    const WallClearanceGrid &clear0 = walls0.clearance();
    const bool use_clear0 = one_floor && !clear0.units.empty();
    float nx_b[kBlock], ny_b[kBlock], len2_b[kBlock];
    int32_t cell_b[kBlock];
    // Weight sum as the plain loop forms it: in float over each run of 1024 particles, added to a double.
    constexpr size_t kSumRun = 1024;
    static_assert(kSumRun % kBlock == 0, "blocks must tile the summation runs");
    float partial = 0;
    auto flush_partial = [&](size_t end) {
        if (end % kSumRun == 0 || end == n) {
            weight_sum += partial;
            partial = 0;
        }
    };
    // Scalar pass over one block: wall test on the moves (x, y) -> (nx_b, ny_b), weights, positions, and the
    // float weight sum (accumulated in particle order).
    auto wall_pass = [&](size_t b, size_t m) {
        if (use_clear0) {
            for (size_t j = 0; j < m; ++j) {
                const size_t i = b + j;
                const float cl = clear0.clearance_m(cell_b[j]);
                float w = ws[i];
                if (!(len2_b[j] < cl * cl) && walls0.crosses_grid(xs[i], ys[i], nx_b[j], ny_b[j])) w *= kill;
                ws[i] = w;
                xs[i] = nx_b[j];
                ys[i] = ny_b[j];
                partial += w;
            }
        } else {
            for (size_t j = 0; j < m; ++j) {
                const size_t i = b + j;
                float w = ws[i];
                if (fl[floors[i]].walls.crosses(xs[i], ys[i], nx_b[j], ny_b[j])) w *= kill;
                ws[i] = w;
                xs[i] = nx_b[j];
                ys[i] = ny_b[j];
                partial += w;
            }
        }
        flush_partial(b + m);
    };
    // Vectorisable tail of the first pass: squared move length and clearance cell of the start point.
    auto clearance_prepass = [&](size_t b, size_t m) {
        if (!use_clear0) return;
        for (size_t j = 0; j < m; ++j) {
            const float dx = nx_b[j] - xs[b + j], dy = ny_b[j] - ys[b + j];
            len2_b[j] = dx * dx + dy * dy;
            cell_b[j] = clear0.cell(xs[b + j], ys[b + j]);
        }
    };

    // Deterministic part: rotate by the yaw offset, scale, test the walls.
    for (size_t b = 0; b < n; b += kBlock) {
        const size_t m = std::min(kBlock, n - b);
        const float *const off = offs + b;
        const float *const sca = scales + b;
        const float *const x0 = xs + b;
        const float *const y0 = ys + b;
        for (size_t j = 0; j < m; ++j) {
            float s, c;
            fast_sincos(off[j], s, c);
            // Two statements, as in the plain loop (no contraction of the sum into an FMA on ARM).
            const float dx = sca[j] * (c * de - s * dn);
            const float dy = sca[j] * (s * de + c * dn);
            nx_b[j] = x0[j] + dx;
            ny_b[j] = y0[j] + dy;
        }
        clearance_prepass(b, m);
        wall_pass(b, m);
    }
    if (!inject) return weight_sum;

    // Stochastic part, every ~0.25 m: yaw offset, scale and position random walks (and their wall test).
    // The normals are drawn per particle in the order yaw, scale, x, y (skipping zero sigmas), as a plain
    // loop would, into per-block buffers; the arithmetic on them is then vectorised.
    const float sigma_pos = static_cast<float>(std::sqrt(a.var_position));
    const float sigma_yaw = static_cast<float>(std::sqrt(a.var_yaw));
    const float sigma_scale = static_cast<float>(std::sqrt(a.var_scale));
    a.clear();
    const float smin = noise.scale_min, smax = noise.scale_max;
    const bool draw_yaw = sigma_yaw > 0, draw_scale = sigma_scale > 0, draw_pos = sigma_pos > 0;
    const size_t per_particle = (draw_yaw ? 1 : 0) + (draw_scale ? 1 : 0) + (draw_pos ? 2 : 0);
    float n_yaw[kBlock], n_scale[kBlock], n_x[kBlock], n_y[kBlock], draws[4 * kBlock];
    weight_sum = 0;
    for (size_t b = 0; b < n; b += kBlock) {
        const size_t m = std::min(kBlock, n - b);
        // One batch from the generator (the same values as per-particle calls), split per variable.
        rng.fill_normal(draws, per_particle * m);
        for (size_t j = 0, k = 0; j < m; ++j) {
            if (draw_yaw) n_yaw[j] = draws[k++];
            if (draw_scale) n_scale[j] = draws[k++];
            if (draw_pos) {
                n_x[j] = draws[k++];
                n_y[j] = draws[k++];
            }
        }
        float *const off = offs + b;
        float *const sca = scales + b;
        if (draw_yaw) {
            for (size_t j = 0; j < m; ++j) off[j] = wrap_angle_f(off[j] + sigma_yaw * n_yaw[j]);
        }
        if (draw_scale) {
            for (size_t j = 0; j < m; ++j) sca[j] = std::min(smax, std::max(smin, sca[j] + sigma_scale * n_scale[j]));
        }
        if (draw_pos) {
            const float *const x0 = xs + b;
            const float *const y0 = ys + b;
            for (size_t j = 0; j < m; ++j) {
                nx_b[j] = x0[j] + sigma_pos * n_x[j];
                ny_b[j] = y0[j] + sigma_pos * n_y[j];
            }
            clearance_prepass(b, m);
            wall_pass(b, m);
        } else {
            for (size_t j = 0; j < m; ++j) partial += ws[b + j];
            flush_partial(b + m);
        }
    }
    return weight_sum;
}

}  // namespace wf::loc
