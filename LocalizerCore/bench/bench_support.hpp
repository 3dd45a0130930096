// Helpers shared by the localizer benchmarks (bench_localizer.cpp, bench_planes.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/fast_math.hpp"
#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"

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

}  // namespace wf::loc::bench
