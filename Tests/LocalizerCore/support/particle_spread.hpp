// A particle set spread over a map, for tests that compare two implementations of an update on the same input.
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "pf/particle_set.hpp"

namespace wf::test {

/// `n` particles over the walkable cells of the map's floors (floor i % floor count), uniform in each cell, any
/// yaw offset, equal weights, no evidence. Every `outside_every`-th particle is moved 5-15 m west of the map
/// (outside every grid) to exercise the out-of-grid paths. Scales are N(1, scale_sigma), or exactly 1 when
/// scale_sigma is 0. Deterministic for a seed.
inline wf::loc::ParticleSet spread_particles(const wf::loc::LocalizerMap &map, size_t n, uint64_t seed, size_t outside_every,
                                             float scale_sigma) {
    wf::loc::Rng r(seed);
    wf::loc::ParticleSet p;
    p.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const int16_t fl = static_cast<int16_t>(i % map.floors.size());
        const wf::loc::FloorData &f = map.floors[fl];
        const int32_t c = f.walkable_cells[r.below(static_cast<uint32_t>(f.walkable_cells.size()))];
        p.x[i] = f.grid.x0 + (static_cast<float>(c % f.grid.nx) + r.uniform_float()) * f.grid.cell_m;
        p.y[i] = f.grid.y0 + (static_cast<float>(c / f.grid.nx) + r.uniform_float()) * f.grid.cell_m;
        if (outside_every > 0 && i % outside_every == 0) p.x[i] = -5.0f - 10 * r.uniform_float();
        p.yaw_offset[i] = static_cast<float>(r.uniform(-3.2, 3.2));
        p.scale[i] = scale_sigma > 0 ? 1 + scale_sigma * r.normal() : 1.0f;
        p.weight[i] = 1.0f / static_cast<float>(n);
        p.floor[i] = fl;
        p.evidence[i] = 0;
    }
    return p;
}

}  // namespace wf::test
