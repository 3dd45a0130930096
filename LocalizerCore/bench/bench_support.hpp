// Helpers shared by the localizer benchmarks (bench_localizer.cpp, bench_planes.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/fast_math.hpp"
#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"
#include "sensors/plane_measurement_model.hpp"
#include "wf_localizer.h"

namespace wf::loc::bench {

/// `n` particles spread uniformly over the walkable cells of `floor` (floor index 0), uniform yaw offsets,
/// scale ~ N(1, 0.03), equal weights: the spread-out cloud of a floor-only start (the costly case).
inline ParticleSet spread_particles(const FloorData &floor, size_t n, uint64_t seed) {
    Rng rng(seed);
    ParticleSet p;
    p.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const int32_t c = floor.walkable_cells[rng.below(static_cast<uint32_t>(floor.walkable_cells.size()))];
        p.x[i] = floor.grid.x0 + (static_cast<float>(c % floor.grid.nx) + rng.uniform_float()) * floor.grid.cell_m;
        p.y[i] = floor.grid.y0 + (static_cast<float>(c / floor.grid.nx) + rng.uniform_float()) * floor.grid.cell_m;
        p.yaw_offset[i] = static_cast<float>(rng.uniform(-kPiD, kPiD));
        p.scale[i] = 1.0f + 0.03f * rng.normal();
        p.weight[i] = 1.0f / static_cast<float>(n);
        p.floor[i] = 0;
        p.evidence[i] = 0;
        p.compass_ll[i] = 0;
    }
    return p;
}

/// The plane model of sensors/plane_measurement_model written plainly, for one particle (map pose x, y in
/// meters, yaw offset in radians, VIO scale): WallIndex::distance_to_nearest per point (segment lists of the
/// grid cells around it), the nearest wall's direction by a scan of the floor's segments, std::exp / std::log
/// per point, std::cos / std::sin per particle. Planes relative to the camera at the VIO origin. Returns the
/// particle's plane log-likelihood (nats). The baseline of bench_planes.cpp and of the full filter step.
inline double baseline_plane_log_likelihood(double x, double y, double yaw_offset, double scale,
                                            const std::vector<wf_plane_observation> &obs, const WallIndex &walls,
                                            const PlaneModelParams &prm) {
    const double c = std::cos(yaw_offset), s = std::sin(yaw_offset);
    double total = 0;
    for (const wf_plane_observation &o : obs) {
        const double tx = std::cos(o.normal_yaw_rad + kPiD / 2), ty = std::sin(o.normal_yaw_rad + kPiD / 2);
        const int k = std::clamp(static_cast<int>(std::floor(o.width_m / prm.point_spacing_m)) + 1, 2, prm.max_points);
        double acc = 0;
        for (int q = 0; q < k; ++q) {
            const double u = (q / double(k - 1) - 0.5) * o.width_m * (1 - 1.0 / k);
            const double ve = o.center_east_m + u * tx, vn = o.center_north_m + u * ty;
            const float mx = static_cast<float>(x + scale * (c * ve - s * vn));
            const float my = static_cast<float>(y + scale * (s * ve + c * vn));
            const float d = walls.distance_to_nearest(mx, my, prm.max_distance_m);
            double hit = 0;
            if (d < prm.max_distance_m) {
                // Direction of the nearest wall: scan the segments.
                double best = 1e9, dir = 0;
                for (size_t w = 0; w < walls.segment_count(); ++w) {
                    float ax, ay, bx, by;
                    walls.segment(w, ax, ay, bx, by);
                    const double ex = bx - ax, ey = by - ay;
                    double t = ((mx - ax) * ex + (my - ay) * ey) / (ex * ex + ey * ey);
                    t = std::clamp(t, 0.0, 1.0);
                    const double dd = std::hypot(ax + t * ex - mx, ay + t * ey - my);
                    if (dd < best) {
                        best = dd;
                        dir = std::atan2(ey, ex);
                    }
                }
                const double delta = std::fabs(wrap_angle(2 * (o.normal_yaw_rad + kPiD / 2 + yaw_offset - dir))) / 2;
                hit = std::exp(-d * d / (2.0 * prm.sigma_distance_m * prm.sigma_distance_m) -
                               delta * delta / (2.0 * prm.sigma_angle_rad * prm.sigma_angle_rad));
            }
            acc += std::log(prm.z_hit * hit + prm.z_rand);
        }
        total += prm.weight * acc / k;
    }
    return total;
}

}  // namespace wf::loc::bench
