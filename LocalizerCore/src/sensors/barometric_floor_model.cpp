#include "sensors/barometric_floor_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/fast_math.hpp"

namespace wf::loc {

double BarometricFloorDetector::push(double relative_altitude_m, double t) {
    if (!has_altitude_) {
        has_altitude_ = true;
        settled_altitude_ = stable_ref_altitude_ = relative_altitude_m;
        stable_since_t_ = t;
        return 0;
    }
    if (std::fabs(relative_altitude_m - stable_ref_altitude_) > p_.settle_tolerance_m) {
        stable_ref_altitude_ = relative_altitude_m;
        stable_since_t_ = t;
    }
    const bool settled = t - stable_since_t_ >= p_.settle_s;
    const double delta = relative_altitude_m - settled_altitude_;
    if (settled && std::fabs(delta) > p_.storey_threshold_m) {
        settled_altitude_ = relative_altitude_m;
        return delta;
    }
    if (settled && std::fabs(delta) < p_.settle_tolerance_m) settled_altitude_ = relative_altitude_m;  // drift
    return 0;
}

std::vector<int16_t> floor_change_destinations(const LocalizerMap &map, double delta_m) {
    const size_t nf = map.floors.size();
    std::vector<int16_t> dest(nf, -1);
    for (size_t f = 0; f < nf; ++f) {
        const double target = map.floors[f].elevation_m + delta_m;
        double best = std::max(1.0, 0.5 * std::fabs(delta_m));
        for (size_t g = 0; g < nf; ++g) {
            const double e = std::fabs(map.floors[g].elevation_m - target);
            if (g != f && e < best) {
                best = e;
                dest[f] = static_cast<int16_t>(g);
            }
        }
    }
    return dest;
}

void link_offset(const LocalizerMap &map, int16_t f, int32_t link, int16_t g, float max_offset_m, float &dx,
                 float &dy) {
    dx = dy = 0;
    const FloorData &from = map.floors[f];
    const float ax = from.link_x[static_cast<size_t>(link)], ay = from.link_y[static_cast<size_t>(link)];
    const FloorData &to = map.floors[g];
    const int32_t b = to.nearest_link(ax, ay);
    if (b < 0) return;
    const float ox = to.link_x[static_cast<size_t>(b)] - ax, oy = to.link_y[static_cast<size_t>(b)] - ay;
    if (ox * ox + oy * oy > max_offset_m * max_offset_m) return;
    dx = ox;
    dy = oy;
}

double apply_floor_change(ParticleSet &p, const LocalizerMap &map, double delta_m, const BarometricFloorParams &params,
                          Rng &rng, const std::function<float()> &sample_yaw_offset) {
    const std::vector<int16_t> dest = floor_change_destinations(map, delta_m);
    const float radius = static_cast<float>(params.link_radius_m);
    const float far = static_cast<float>(params.far_from_link_weight);
    double sum = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        const int16_t f = p.floor[i];
        const int16_t g = dest[f];
        float link_distance = std::numeric_limits<float>::infinity();
        const int32_t link = g >= 0 ? map.floors[f].nearest_link(p.x[i], p.y[i], &link_distance) : -1;
        if (link >= 0 && link_distance <= radius) {
            float dx, dy;
            link_offset(map, f, link, g, static_cast<float>(params.shaft_offset_max_m), dx, dy);
            // Beside the same link on the new floor's plan; kept in place when the shifted pose is not walkable
            // there (the plan's cabin drawn smaller than the traveler's offset from it).
            if (map.floors[g].is_walkable(p.x[i] + dx, p.y[i] + dy)) {
                p.x[i] += dx;
                p.y[i] += dy;
            }
            p.floor[i] = g;
        } else if (g >= 0 && !map.floors[g].link_x.empty()) {
            // Cannot have ridden from here: re-drawn beside a vertical link of the destination floor, on
            // walkable ground within the link radius (a few tries; else at the link itself).
            const FloorData &fd = map.floors[g];
            const size_t k = rng.below(static_cast<uint32_t>(fd.link_x.size()));
            float x = fd.link_x[k], y = fd.link_y[k];
            for (int attempt = 0; attempt < 8; ++attempt) {
                const float r = radius * std::sqrt(rng.uniform_float());
                float s, c;
                fast_sincos(kTwoPi * rng.uniform_float(), s, c);
                const float qx = fd.link_x[k] + r * c, qy = fd.link_y[k] + r * s;
                if (fd.is_walkable(qx, qy) && !fd.walls.crosses(fd.link_x[k], fd.link_y[k], qx, qy)) {
                    x = qx;
                    y = qy;
                    break;
                }
            }
            p.x[i] = x;
            p.y[i] = y;
            p.floor[i] = g;
            p.yaw_offset[i] = sample_yaw_offset();
            p.weight[i] *= far;
        } else {
            p.weight[i] *= far;  // no floor at that elevation: cannot explain the change
        }
        sum += p.weight[i];
    }
    return sum;
}

}  // namespace wf::loc
