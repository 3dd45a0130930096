#include "motion/vio_motion_model.hpp"

#include <algorithm>
#include <cmath>

#include "common/fast_math.hpp"

namespace wf::loc {

namespace {
// Physical limits that make a delta plausible at low frame rates: the jump thresholds grow by these rates
// times the frame interval (a 1 Hz caller may legitimately move 1.5 m + 2 m).
constexpr double kMaxWalkSpeedMps = 2.0;
constexpr double kMaxTurnRateRadps = 3.0;
// Cap on the position noise injected after tracking was unavailable for a long time, meters.
constexpr double kMaxLostPositionSigmaM = 5.0;
inline float sq(float v) { return v * v; }
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

VioDelta VioDeltaTracker::push(const wf_vio_sample &s) {
    VioDelta d;
    if (s.tracking == WF_VIO_TRACKING_NOT_AVAILABLE) {
        // The pose is meaningless until tracking returns; remember when it was lost.
        if (lost_since_ < 0) lost_since_ = has_last_ ? last_.t : s.t;
        return d;
    }
    if (!has_last_) {
        last_ = s;
        has_last_ = true;
        lost_since_ = -1;
        return d;
    }
    const double dt = s.t - last_.t;
    const double de = s.east_m - last_.east_m, dn = s.north_m - last_.north_m;
    const double dyaw = wrap_angle(s.yaw_rad - last_.yaw_rad);
    d.d_east = static_cast<float>(de);
    d.d_north = static_cast<float>(dn);
    d.d_yaw = static_cast<float>(dyaw);
    if (lost_since_ >= 0) {
        // notAvailable -> normal/limited: ARKit may have reset its origin. Skip the delta; the traveler kept
        // walking meanwhile, so the position noise grows with the time tracking was lost.
        const double lost_s = std::max(0.0, s.t - lost_since_);
        d.kind = DeltaKind::kJump;
        d.jump_position_sigma = static_cast<float>(
            std::min(kMaxLostPositionSigmaM, opts_.jump_position_sigma_m + opts_.lost_tracking_speed_mps * lost_s));
        d.jump_yaw_sigma = static_cast<float>(opts_.jump_yaw_sigma_rad);
        lost_since_ = -1;
        last_ = s;
        return d;
    }
    if (dt < 0) {
        // Time went backwards: a new session or a replay seam; treat as an origin reset.
        d.kind = DeltaKind::kJump;
        d.jump_position_sigma = static_cast<float>(opts_.jump_position_sigma_m);
        d.jump_yaw_sigma = static_cast<float>(opts_.jump_yaw_sigma_rad);
        last_ = s;
        return d;
    }
    const double dist = std::sqrt(de * de + dn * dn);
    const double max_dist = opts_.jump_distance_m + kMaxWalkSpeedMps * dt;
    const double max_turn = opts_.jump_yaw_rad + kMaxTurnRateRadps * dt;
    last_ = s;
    if (dist > max_dist || std::fabs(dyaw) > max_turn) {
        // Relocalization jump (ARKit snapped its map): the traveler did not move that much in one frame.
        d.kind = DeltaKind::kJump;
        d.jump_position_sigma = static_cast<float>(opts_.jump_position_sigma_m);
        d.jump_yaw_sigma = static_cast<float>(opts_.jump_yaw_sigma_rad);
        return d;
    }
    if (dist == 0.0 && dyaw == 0.0) return d;  // nothing moved
    d.kind = DeltaKind::kMove;
    d.noise_factor = s.tracking == WF_VIO_TRACKING_LIMITED ? static_cast<float>(opts_.limited_tracking_noise_factor)
                                                           : 1.0f;
    return d;
}

double apply_motion(ParticleSet &p, const VioDelta &delta, const MotionNoise &noise, const LocalizerMap &map,
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
        // VIO yaw jump; the displacement is dropped and replaced by inflated noise.
        const float sp = delta.jump_position_sigma, sy = delta.jump_yaw_sigma;
        for (size_t i = 0; i < n; ++i) {
            offs[i] = wrap_angle_f(offs[i] - delta.d_yaw + sy * rng.normal());
            const float nx = xs[i] + sp * rng.normal(), ny = ys[i] + sp * rng.normal();
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
    a.var_position += k2 * (sq(noise.position_per_sqrt_meter) * dist + sq(noise.position_per_sqrt_rad) * turn);
    a.var_yaw += k2 * (sq(noise.yaw_per_sqrt_meter) * dist + sq(noise.yaw_per_sqrt_rad) * turn);
    a.var_scale += k2 * sq(noise.scale_per_sqrt_meter) * dist;
    a.distance_m += dist;
    a.turn_rad += turn;
    ++a.frames;
    const bool inject = !acc || a.due();

    // Deterministic part: rotate by the yaw offset, scale, test the wall grid. With one floor (the common
    // case) the wall index is fixed for the whole loop, so its fields stay in registers.
    // Two passes over blocks of particles: the displacement (branch-free, so the compiler vectorises the
    // polynomial sincos), then the wall test on the block while it is still in L1.
    auto deterministic = [&](auto walls_of) {
        constexpr size_t kBlock = 1024;
        float dx[kBlock], dy[kBlock];
        double total = 0;
        for (size_t b = 0; b < n; b += kBlock) {
            const size_t m = std::min(kBlock, n - b);
            const float *const off = offs + b;
            const float *const sca = scales + b;
            for (size_t j = 0; j < m; ++j) {
                float s, c;
                fast_sincos(off[j], s, c);
                dx[j] = sca[j] * (c * de - s * dn);
                dy[j] = sca[j] * (s * de + c * dn);
            }
            float partial = 0;
            for (size_t j = 0; j < m; ++j) {
                const size_t i = b + j;
                const float x0 = xs[i], y0 = ys[i];
                const float x1 = x0 + dx[j], y1 = y0 + dy[j];
                float w = ws[i];
                if (walls_of(i).crosses(x0, y0, x1, y1)) w *= kill;
                ws[i] = w;
                xs[i] = x1;
                ys[i] = y1;
                partial += w;
            }
            total += partial;
        }
        return total;
    };
    if (map.floors.size() == 1) {
        const WallIndex &only = fl[0].walls;
        weight_sum = deterministic([&only](size_t) -> const WallIndex & { return only; });
    } else {
        weight_sum = deterministic([fl, floors](size_t i) -> const WallIndex & { return fl[floors[i]].walls; });
    }
    float wsum = 0;
    if (!inject) return weight_sum;

    // Stochastic part, every ~0.25 m: yaw offset, scale and position random walks (and their wall test).
    const float sigma_pos = static_cast<float>(std::sqrt(a.var_position));
    const float sigma_yaw = static_cast<float>(std::sqrt(a.var_yaw));
    const float sigma_scale = static_cast<float>(std::sqrt(a.var_scale));
    a.clear();
    const float smin = noise.scale_min, smax = noise.scale_max;
    weight_sum = 0;
    for (size_t i = 0; i < n; ++i) {
        if (sigma_yaw > 0) offs[i] = wrap_angle_f(offs[i] + sigma_yaw * rng.normal());
        if (sigma_scale > 0) scales[i] = std::min(smax, std::max(smin, scales[i] + sigma_scale * rng.normal()));
        float w = ws[i];
        if (sigma_pos > 0) {
            const float x0 = xs[i], y0 = ys[i];
            const float x1 = x0 + sigma_pos * rng.normal(), y1 = y0 + sigma_pos * rng.normal();
            if (fl[floors[i]].walls.crosses(x0, y0, x1, y1)) w *= kill;
            xs[i] = x1;
            ys[i] = y1;
        }
        ws[i] = w;
        wsum += w;
        if ((i & 1023) == 1023) {
            weight_sum += wsum;
            wsum = 0;
        }
    }
    return weight_sum + wsum;
}

}  // namespace wf::loc
