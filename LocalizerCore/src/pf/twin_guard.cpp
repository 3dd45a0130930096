#include "pf/twin_guard.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/fast_math.hpp"

namespace wf::loc {

namespace {

/// yaw + angle wrapped to [-pi, pi] (the project's branch-free wrap: the twin loop vectorises).
float turn(float yaw, float angle) { return wrap_angle_f(yaw + angle); }

}  // namespace

size_t TwinGuard::twin_arrays_for(const LocalizerMap &map) {
    size_t most = 0;
    for (const FloorData &f : map.floors) most = std::max(most, f.symmetries.size());
    return std::min(most, ParticleSet::kMaxTwins);
}

void TwinGuard::observe_dominant(int32_t floor, double x, double y, double yaw_offset_rad, double std_m) {
    if (!p_.enabled || floor < 0 || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw_offset_rad)) {
        has_dominant_ = false;
        return;
    }
    has_dominant_ = true;
    floor_ = floor;
    x_ = x;
    y_ = y;
    yaw_offset_ = yaw_offset_rad;
    const double s = std::isfinite(std_m) ? std_m : p_.region_max_radius_m;
    radius_m_ = std::clamp(p_.region_std_factor * s, p_.region_min_radius_m, p_.region_max_radius_m);
}

bool TwinGuard::is_twin_of_dominant(const LocalizerMap &map, int32_t floor, double x, double y,
                                    double yaw_offset_rad) const {
    if (!p_.enabled || !has_dominant_ || floor != floor_) return false;
    for (size_t k = 0; k < ParticleSet::kMaxTwins; ++k) {
        const FloorSymmetry *sym = symmetry_of(map, floor_, k);
        if (!sym) break;
        float tx, ty;
        sym->apply(static_cast<float>(x_), static_cast<float>(y_), tx, ty);
        if (near_pose(x, y, yaw_offset_rad, tx, ty, yaw_offset_ + sym->angle_rad)) return true;
    }
    return false;
}

bool TwinGuard::twin_poses(const ParticleSet &p, const LocalizerMap &map, size_t k, std::vector<float> &x,
                           std::vector<float> &y, std::vector<float> &yaw_offset) const {
    if (!p_.enabled || k >= p.twin_arrays) return false;
    bool any = false;
    for (const FloorData &f : map.floors) any = any || k < f.symmetries.size();
    if (!any) return false;
    const size_t n = p.size();
    x.resize(n);
    y.resize(n);
    yaw_offset.resize(n);
    const int16_t *fl = p.floor.data();
    size_t i = 0;
    while (i < n) {
        // Runs of one floor (usually the whole cloud): the transform is a vectorisable loop over the run.
        const int16_t f = fl[i];
        size_t end = i + 1;
        while (end < n && fl[end] == f) ++end;
        const float *__restrict px = p.x.data(), *__restrict py = p.y.data(), *__restrict pyaw = p.yaw_offset.data();
        float *__restrict ox = x.data(), *__restrict oy = y.data(), *__restrict oyaw = yaw_offset.data();
        const FloorSymmetry *sym = symmetry_of(map, f, k);
        if (sym) {
            const float cx = sym->cx, cy = sym->cy, c = sym->cos_a, s = sym->sin_a, angle = sym->angle_rad;
            for (size_t j = i; j < end; ++j) {
                const float dx = px[j] - cx, dy = py[j] - cy;
                ox[j] = cx + c * dx - s * dy;
                oy[j] = cy + s * dx + c * dy;
                oyaw[j] = turn(pyaw[j], angle);
            }
        } else {
            for (size_t j = i; j < end; ++j) {
                ox[j] = px[j];
                oy[j] = py[j];
                oyaw[j] = pyaw[j];
            }
        }
        i = end;
    }
    return true;
}

void TwinGuard::accumulate(ParticleSet &p, const LocalizerMap &map, size_t k, const float *ll, const float *twin_ll) const {
    if (k >= p.twin_arrays) return;
    float *r = p.twin_llr[k].data();
    const float cap = static_cast<float>(p_.max_step_nats);
    int32_t last_floor = -2;
    bool has = false;
    for (size_t i = 0; i < p.size(); ++i) {
        if (p.floor[i] != last_floor) {
            last_floor = p.floor[i];
            has = symmetry_of(map, last_floor, k) != nullptr;
        }
        if (!has) continue;
        const float d = ll[i] - twin_ll[i];
        // NaN (both -inf) adds nothing; +-inf and large steps are clamped.
        r[i] += std::isnan(d) ? 0.0f : std::clamp(d, -cap, cap);
    }
}

double TwinGuard::log_ratio(const ParticleSet &p, const LocalizerMap &map, const uint32_t *members, size_t count) const {
    double best = std::numeric_limits<double>::infinity();
    if (!p_.enabled || p.twin_arrays == 0 || count == 0) return best;
    const int32_t f = p.floor[members[0]];
    for (size_t k = 0; k < p.twin_arrays && symmetry_of(map, f, k); ++k) {
        double w = 0, wt = 0;
        const float *r = p.twin_llr[k].data();
        // Copies of a particle (next to each other after a resampling) share their ratio: its exponential is
        // computed once per run of equal ratios (the same value as computing it again).
        float last_r = std::numeric_limits<float>::quiet_NaN();
        double last_exp = 0;
        for (size_t j = 0; j < count; ++j) {
            const uint32_t i = members[j];
            w += p.weight[i];
            if (!(r[i] == last_r)) {
                last_r = r[i];
                last_exp = std::exp(-static_cast<double>(last_r));
            }
            wt += static_cast<double>(p.weight[i]) * last_exp;
        }
        if (!(w > 0)) continue;
        best = std::min(best, std::log(w) - std::log(std::max(wt, 1e-300)));
    }
    return best;
}

bool TwinGuard::near_pose(double x, double y, double yaw_offset_rad, double cx, double cy, double cyaw) const {
    const double dx = x - cx, dy = y - cy;
    return dx * dx + dy * dy <= radius_m_ * radius_m_ && std::fabs(wrap_angle(yaw_offset_rad - cyaw)) <= p_.region_yaw_rad;
}

bool TwinGuard::in_region(const ParticleSet &p, size_t i, double cx, double cy, double yaw) const {
    return p.floor[i] == floor_ && near_pose(p.x[i], p.y[i], p.yaw_offset[i], cx, cy, yaw);
}

size_t TwinGuard::reseed(ParticleSet &p, const LocalizerMap &map) {
    if (!p_.enabled || !has_dominant_ || p.size() == 0 || p.twin_arrays == 0) return 0;
    size_t moved = 0;
    for (size_t k = 0; k < p.twin_arrays; ++k) {
        const FloorSymmetry *sym = symmetry_of(map, floor_, k);
        if (!sym) continue;
        const FloorData &fd = map.floors[static_cast<size_t>(floor_)];
        float tx, ty;
        sym->apply(static_cast<float>(x_), static_cast<float>(y_), tx, ty);
        const double tyaw = yaw_offset_ + sym->angle_rad;  // near_pose wraps the difference
        double w_dom = 0, w_twin = 0, target = 0;
        region_.clear();
        const float *r = p.twin_llr[k].data();
        for (size_t i = 0; i < p.size(); ++i) {
            if (in_region(p, i, x_, y_, yaw_offset_)) {
                region_.push_back(static_cast<uint32_t>(i));
                w_dom += p.weight[i];
                target += static_cast<double>(p.weight[i]) * std::exp(-static_cast<double>(r[i]));
            } else if (in_region(p, i, tx, ty, tyaw)) {
                w_twin += p.weight[i];
            }
        }
        if (!(w_dom > 0) || !(target > 0)) continue;
        const double log_bayes = std::log(w_dom) - std::log(target);  // the dominant against its twin, nats
        if (log_bayes > p_.refuted_nats) continue;                       // the twin is refuted
        // The pair's mass is split by the evidence (twin : dominant = target : w_dom), never created: other
        // hypotheses keep their share. Reseed only when the twin holds less than reseed_fraction of its share.
        const double pair = w_dom + w_twin;
        const double twin_share = pair * target / (w_dom + target);
        if (w_twin >= p_.reseed_fraction * twin_share) continue;
        const double q = std::clamp((twin_share - w_twin) / w_dom, 0.0, 0.9);  // share of the dominant's mass to move
        const size_t stride = std::max<size_t>(1, static_cast<size_t>(std::lround(1.0 / std::max(q, 1e-3))));
        double to_move = q * w_dom;
        // Every stride-th member first (spread over the region's copies), then the others, until moved.
        for (size_t pass = 0; pass < stride && to_move > 0; ++pass) {
            for (size_t j = pass; j < region_.size() && to_move > 0; j += stride) {
                const uint32_t i = region_[j];
                float nx, ny;
                sym->apply(p.x[i], p.y[i], nx, ny);
                if (!fd.is_walkable(nx, ny)) continue;
                const double llr = r[i];
                p.x[i] = nx;
                p.y[i] = ny;
                p.yaw_offset[i] = turn(p.yaw_offset[i], sym->angle_rad);
                p.evidence[i] -= static_cast<float>(std::max(0.0, llr));
                for (size_t m = 0; m < p.twin_arrays; ++m) p.twin_llr[m][i] = m == k ? static_cast<float>(-llr) : 0.0f;
                p.clear_tracks(i);  // the twin pose has not been scored against the tracked objects: even odds
                to_move -= p.weight[i];
                ++moved;
            }
        }
    }
    return moved;
}

}  // namespace wf::loc
