// ParticleFilter::draw_corroboration_rivals: the lock must be earned against the other places that explain the
// same sightings.
//
// A named start, or a lock that the evidence just broke, leaves the cloud in one place. The first sighting that
// place explains proves little when another place explains it as well: Exit signs look alike and corridors
// repeat (Tests/Recovery: a start named 10 m up a parallel corridor sees "its" sign 1.2 m ahead-left exactly as
// the true place sees another one). Waiting for "a sighting" alone locks there at once and stays wrong for 20 m.
//
// So at the first frame with sightings of such a phase, a share of the particles is replaced by poses drawn
// from those sightings anywhere on the floor (sensor resetting, Lenser and Veloso 2000, the same draw as the
// recovery injection). They hold that share of the weight and the best evidence present (they explain the
// current sightings by construction; their past is unknown, so it is neither held for nor against them). The
// ambiguity guard then keeps the flag off until walls, compass, planes and later sightings refute them by the
// refutation margin (pf/localized_hysteresis), or one of them wins and the filter follows it. Drawn once per
// phase: drawing again at every sighting would hand each new sign fresh, untested rivals and never lock.
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/fast_math.hpp"
#include "pf/particle_filter.hpp"

namespace wf::loc {

bool ParticleFilter::sample_rival_pose(int16_t floor, float &x, float &y, float &yaw_offset) {
    if (last_sightings_.empty()) return false;
    const FloorData &f = map_.floors[floor];
    for (int attempt = 0; attempt < 16; ++attempt) {
        const PreparedSighting &z = last_sightings_[rng_.below(static_cast<uint32_t>(last_sightings_.size()))];
        const int32_t chosen = random_sign_of_kind(f, z.kind);
        if (chosen < 0) return false;
        // The heading from the compass prior (a uniform share when the field may be disturbed, see
        // sample_yaw_offset); the camera then stands where the sign appears at the sighting's bearing and range:
        // direction sign -> camera phi = heading + bearing - pi.
        const float yaw = sample_yaw_offset();
        const double heading = vio_yaw_ + yaw;
        const double phi = heading + z.bearing_rad - kPiD;
        const double facing = std::atan2(f.signs.facing_y[chosen], f.signs.facing_x[chosen]);
        if (!f.signs.double_sided[chosen] && std::abs(wrap_angle(phi - facing)) > 1.396) continue;
        const double r = z.range_m * (1.0 + 0.1 * rng_.normal());
        const float cx = static_cast<float>(f.signs.x[chosen] + r * std::cos(phi));
        const float cy = static_cast<float>(f.signs.y[chosen] + r * std::sin(phi));
        if (!f.is_walkable(cx, cy)) continue;
        const uint64_t *vis = f.visibility_at(cx, cy);
        if (!vis || !((vis[chosen / 64] >> (chosen % 64)) & 1u)) continue;
        x = cx;
        y = cy;
        yaw_offset = yaw;
        return true;
    }
    return false;
}

void ParticleFilter::draw_corroboration_rivals(double fraction) {
    corroboration_candidates_drawn_ = true;
    clusterer_.forget_carried_bins();  // rivals replace particles
    const size_t n = p_.size();
    if (n == 0 || last_sightings_.empty() || !(fraction > 0)) return;
    fraction = std::min(fraction, 0.5);
    const int16_t floor = estimate_.floor_index >= 0 ? static_cast<int16_t>(estimate_.floor_index) : init_floor_;
    if (floor < 0 || static_cast<size_t>(floor) >= map_.floors.size()) return;
    const size_t m = std::max<size_t>(1, static_cast<size_t>(std::lround(fraction * static_cast<double>(n))));
    float best_evidence = -std::numeric_limits<float>::infinity();
    for (float e : p_.evidence) best_evidence = std::max(best_evidence, e);
    if (!std::isfinite(best_evidence)) best_evidence = 0;
    // The kept particles give up `fraction` of the weight; the rivals share it equally.
    const float keep = static_cast<float>(1.0 - fraction);
    for (float &w : p_.weight) w *= keep;
    const float rival_w = static_cast<float>(fraction / static_cast<double>(m));
    // Replace an even stride of the array (particle order carries no meaning after resampling; a stride keeps
    // the draw deterministic for a seed and spreads it over every group).
    const double stride = static_cast<double>(n) / static_cast<double>(m);
    size_t drawn = 0;
    for (size_t k = 0; k < m; ++k) {
        const size_t i = std::min(n - 1, static_cast<size_t>(static_cast<double>(k) * stride));
        float x, y, yaw;
        if (!sample_rival_pose(floor, x, y, yaw)) continue;
        p_.x[i] = x;
        p_.y[i] = y;
        p_.yaw_offset[i] = yaw;
        p_.scale[i] = std::clamp(1.0f + static_cast<float>(opts_.initial_scale_sigma) * rng_.normal(), motion_.scale_min,
                                 motion_.scale_max);
        p_.floor[i] = floor;
        p_.weight[i] = rival_w;
        p_.evidence[i] = best_evidence;
        p_.compass_ll[i] = 0;
        p_.bias_s1[i] = 0;
        p_.bias_s0[i] = 0;
        p_.clear_twins(i);  // a fresh pose: no twin evidence either way
        p_.clear_tracks(i);
        ++drawn;
    }
    double sum = 0;
    for (float w : p_.weight) sum += w;
    normalize(sum);
    injected_count_ += drawn;
    estimate_dirty_ = true;
    dominant_members_valid_ = false;
}

}  // namespace wf::loc
