// Google Benchmark of the vertical-plane update (sensors/plane_measurement_model, ParticleFilter::update_planes)
// at 100k particles spread over a 40 m x 30 m office floor (outer walls, a corridor, 10 rooms with door gaps),
// any heading. Four planes per update (what a walker typically has in view after the per-anchor gate).
//  - PlaneLikelihood: plane_log_likelihood alone (wall field lookup + the 256 x 129 log table).
//  - PlaneLikelihoodBaseline: the same model written plainly: WallIndex::distance_to_nearest per point (segment
//    lists of the grid cells around it), the nearest wall's direction by a scan of the floor's segments,
//    std::exp / std::log per point, std::cos / std::sin per particle.
//  - PlaneUpdateFilter: the public ParticleFilter::update_planes (likelihood, evidence, tempering,
//    normalisation, resampling when due), fixed particle count, new anchors every iteration.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "common/fast_math.hpp"
#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "pf/particle_filter.hpp"
#include "sensors/plane_measurement_model.hpp"
#include "wf_localizer.h"

using namespace wf::loc;

namespace {

struct PlaneOffice {
    std::vector<float> walls, seeds;
    wf_localizer_floor floor{};
    wf_localizer_map map{};
    PlaneOffice() {
        auto add = [&](float ax, float ay, float bx, float by) { walls.insert(walls.end(), {ax, ay, bx, by}); };
        add(0, 0, 40, 0); add(40, 0, 40, 30); add(40, 30, 0, 30); add(0, 30, 0, 0);
        for (int i = 0; i < 5; ++i) {
            const float x0 = 8.0f * i, x1 = x0 + 8.0f, door = x0 + 3.0f;
            add(x0, 12, door, 12); add(door + 1, 12, x1, 12);   // corridor south wall, one door per room
            add(x0, 18, door, 18); add(door + 1, 18, x1, 18);   // corridor north wall
            if (i > 0) { add(x0, 0, x0, 12); add(x0, 18, x0, 30); }
        }
        for (float x = 1; x < 40; x += 2) seeds.insert(seeds.end(), {x, 15, x, 6, x, 24});
        floor.walls = walls.data();
        floor.wall_count = walls.size() / 4;
        floor.seed_points = seeds.data();
        floor.seed_point_count = seeds.size() / 2;
        map.version = WF_LOCALIZER_MAP_VERSION;
        map.floors = &floor;
        map.floor_count = 1;
        map.kind_count = 1;
    }
};

wf_localizer_options options(size_t n) {
    wf_localizer_options o;
    wf_localizer_options_init(&o, WF_LOCALIZER_OPTIONS_VERSION);
    o.particle_count = static_cast<int32_t>(n);
    o.max_particles = static_cast<int32_t>(n);
    o.min_particles = 1000;
    o.adaptive_particle_count = 0;
    return o;
}

LocalizerMap build(size_t n) {
    PlaneOffice office;
    LocalizerMap m;
    std::string err;
    build_localizer_map(office.map, options(n), m, err);
    return m;
}

ParticleSet spread(const LocalizerMap &m, size_t n) {
    return bench::spread_particles(m.floors[0], n, 11);
}

// Four planes around a camera at the VIO origin: walls 1.5 m left and right, one 3 m ahead, one oblique.
std::vector<wf_plane_observation> planes(uint64_t first_id) {
    return {{first_id, 0.5, 1.5, -kPiD / 2, 3.0}, {first_id + 1, 1.0, -1.5, kPiD / 2, 2.5},
            {first_id + 2, 3.0, 0.2, kPiD, 1.5}, {first_id + 3, 2.0, 2.0, -2.3, 1.0}};
}

void counters(benchmark::State &state, size_t n) {
    state.counters["ns_per_particle"] = benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(n),
                                                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_PlaneLikelihood(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    const LocalizerMap m = build(n);
    const ParticleSet p = spread(m, n);
    PlaneModelState st;
    st.ensure_fields(m);
    const auto obs = planes(1);
    const auto z = prepare_planes(obs.data(), obs.size(), 0, 0, 0, st.params, nullptr, nullptr);
    std::vector<float> ll(n);
    for (auto _ : state) {
        std::fill(ll.begin(), ll.end(), 0.0f);
        benchmark::DoNotOptimize(plane_log_likelihood(p, st.fields, st.table, st.params, z.data(), z.size(), ll.data()));
    }
    counters(state, n);
}

void BM_PlaneLikelihoodBaseline(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    const LocalizerMap m = build(n);
    const ParticleSet p = spread(m, n);
    const PlaneModelParams prm;
    const WallIndex &walls = m.floors[0].walls;
    const auto obs = planes(1);
    std::vector<float> ll(n);
    for (auto _ : state) {
        for (size_t i = 0; i < n; ++i) {
            ll[i] = static_cast<float>(
                bench::baseline_plane_log_likelihood(p.x[i], p.y[i], p.yaw_offset[i], p.scale[i], obs, walls, prm));
        }
        benchmark::DoNotOptimize(ll.data());
    }
    counters(state, n);
}

void BM_PlaneUpdateFilter(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    ParticleFilter pf(build(n), options(n), 5);
    pf.init_floor_only(0);
    wf_vio_sample s{0, 0, 0, 0, WF_VIO_TRACKING_NORMAL};
    pf.predict(s);
    uint64_t id = 1;
    double t = 0;
    std::vector<wf_plane_observation> obs = planes(id);
    pf.update_planes(obs.data(), obs.size(), t);  // builds the wall field (once per filter)
    for (auto _ : state) {
        id += 4;
        t += 0.1;
        obs = planes(id);
        benchmark::DoNotOptimize(pf.update_planes(obs.data(), obs.size(), t));
        state.PauseTiming();
        if (pf.resample_count() > 0 || pf.particles().size() != n) {  // keep the cloud spread out
            pf.init_floor_only(0);
            pf.predict(s);
        }
        state.ResumeTiming();
    }
    counters(state, n);
}

}  // namespace

BENCHMARK(BM_PlaneLikelihood)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlaneLikelihoodBaseline)->Arg(100000)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_PlaneUpdateFilter)->Arg(100000)->Unit(benchmark::kMillisecond);
