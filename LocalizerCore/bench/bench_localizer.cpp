// Google Benchmark of the particle filter's per-frame work, with a straightforward baseline in the same
// binary so the ratios come from the same run (docs/benchmarks.md, "LocalizerCore particle filter").
//
// Floor: a synthetic 40 m x 30 m office (outer walls, a central corridor, 12 rooms with door gaps: 64 wall
// segments) with 10 exit signs. Particles spread uniformly over the walkable space, any heading.
//  - Motion: one VIO frame (4 cm step, 0.6 deg turn) through apply_motion (blocks of particles: vectorised
//    fast sincos, wall-clearance byte lookup before the exact wall grid test, batched xoshiro + Ziggurat
//    normals every 0.25 m). Baseline: array of structs, std::mt19937 +
//    std::normal_distribution (2 samples), std::cos/std::sin, and a wall test by marching a 5 cm raster.
//  - Signs: one frame with 2 sightings (kind exit) plus negative information through sign_log_likelihood
//    (blocks: vectorised sincos, cell lookup and sign-by-sign "nearly in view" mask) and the weight update. Baseline: array of structs, double, per-sign byte visibility rasters, std::atan2 /
//    std::exp / std::log per candidate sign.
//  - Filter: the public ParticleFilter::predict / update_signs (including normalisation, ESS test,
//    clustering for the estimate, resampling when due), fixed particle count.
// Counters: ns_per_particle (per update), bytes_per_particle (state arrays incl. the resampling copy).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "bench_support.hpp"
#include "common/fast_math.hpp"
#include "common/rng.hpp"
#include "map/localizer_map.hpp"
#include "motion/vio_motion_model.hpp"
#include "pf/particle_filter.hpp"
#include "sensors/sign_measurement_model.hpp"
#include "wf_localizer.h"

using namespace wf::loc;

namespace {

struct Office {
    std::vector<float> walls;  // 4 floats per segment
    std::vector<wf_localizer_sign> signs;
    std::vector<float> seeds;
    wf_localizer_floor floor{};
    wf_localizer_map map{};

    Office() {
        auto wall = [&](float ax, float ay, float bx, float by) { walls.insert(walls.end(), {ax, ay, bx, by}); };
        // Outer box.
        wall(0, 0, 40, 0); wall(40, 0, 40, 30); wall(40, 30, 0, 30); wall(0, 30, 0, 0);
        // Central east-west corridor y in [13, 17]; rooms of 6.67 m above and below with 1 m door gaps.
        for (int i = 0; i < 6; ++i) {
            const float x0 = i * 40.0f / 6, x1 = (i + 1) * 40.0f / 6;
            const float d0 = x0 + 2.5f, d1 = d0 + 1.0f;  // door gap
            wall(x0, 13, d0, 13); wall(d1, 13, x1, 13);
            wall(x0, 17, d0, 17); wall(d1, 17, x1, 17);
            if (i > 0) { wall(x0, 0, x0, 13); wall(x0, 17, x0, 30); }
        }
        // Some furniture-like segments inside rooms.
        for (int i = 0; i < 6; ++i) {
            const float cx = i * 40.0f / 6 + 3.3f;
            wall(cx - 1, 6, cx + 1, 6); wall(cx - 1, 24, cx + 1, 24);
            wall(cx - 1.5f, 9, cx - 1.5f, 10); wall(cx + 1.5f, 20, cx + 1.5f, 21);
        }
        const float sx[10] = {0, 40, 10, 20, 30, 5, 15, 25, 35, 20};
        const float sy[10] = {15, 15, 17, 13, 17, 30, 0, 30, 0, 17};
        const float fx[10] = {1, -1, 0, 0, 0, 0, 0, 0, 0, 0};
        const float fy[10] = {0, 0, -1, 1, -1, -1, 1, -1, 1, -1};
        for (int j = 0; j < 10; ++j) signs.push_back({0, sx[j], sy[j], fx[j], fy[j], 0});
        for (float x = 1; x < 40; x += 2) {
            seeds.insert(seeds.end(), {x, 15.0f, x, 5.0f, x, 25.0f});
        }
        floor.elevation_m = 0;
        floor.walls = walls.data();
        floor.wall_count = walls.size() / 4;
        floor.signs = signs.data();
        floor.sign_count = signs.size();
        floor.seed_points = seeds.data();
        floor.seed_point_count = seeds.size() / 2;
        map.version = WF_LOCALIZER_MAP_VERSION;
        map.floors = &floor;
        map.floor_count = 1;
        map.kind_count = 1;
    }
};

wf_localizer_options bench_options() {
    wf_localizer_options o;
    wf_localizer_options_init(&o, WF_LOCALIZER_OPTIONS_VERSION);
    return o;
}

const LocalizerMap &office_map() {
    static const LocalizerMap m = [] {
        Office office;
        LocalizerMap lm;
        std::string err;
        build_localizer_map(office.map, bench_options(), lm, err);
        return lm;
    }();
    return m;
}

ParticleSet uniform_particles(size_t n, uint64_t seed) {
    return bench::spread_particles(office_map().floors[0], n, seed);
}

void set_counters(benchmark::State &state, size_t n, size_t bytes_per_particle) {
    state.counters["ns_per_particle"] = benchmark::Counter(
        static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["ns_per_particle"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * static_cast<double>(n),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["bytes_per_particle"] = static_cast<double>(bytes_per_particle);
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(n));
}

// ---------------------------------------------------------------------------------------------- optimised

void BM_MotionUpdate(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    ParticleSet p = uniform_particles(n, 1);
    MotionNoise noise = MotionNoise::from_options(bench_options());
    noise.wall_crossing_weight = 1.0f;  // keep weights normal-range over millions of iterations (no denormals)
    Rng rng(2);
    MotionNoiseAccumulator acc;
    VioDelta d;
    d.kind = DeltaKind::kMove;
    d.d_yaw = 0.01f;
    float sign = 1;
    for (auto _ : state) {
        d.d_east = 0.04f * sign;  // back and forth so particles stay in the building
        sign = -sign;
        benchmark::DoNotOptimize(apply_motion(p, d, noise, office_map(), rng, &acc));
    }
    set_counters(state, n, 2 * ParticleSet::kBytesPerParticle);
}

void BM_SignUpdate(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    ParticleSet p = uniform_particles(n, 3);
    const SignModelParams m = SignModelParams::from_options(bench_options());
    const std::vector<PreparedSighting> z = {{0, 6.0f, 0.1f, 0.1f}, {0, 9.5f, -0.2f, 0.1f}};
    std::vector<float> ll(n);
    const std::vector<float> w0 = p.weight;
    for (auto _ : state) {
        const float mx = sign_log_likelihood(p, 0.3f, office_map(), m, z.data(), z.size(), ll.data());
        double s = 0;
        for (size_t i = 0; i < n; ++i) {
            p.weight[i] = w0[i] * std::exp(ll[i] - mx);
            s += p.weight[i];
        }
        benchmark::DoNotOptimize(s);
    }
    set_counters(state, n, 2 * ParticleSet::kBytesPerParticle + sizeof(float));
}

std::unique_ptr<ParticleFilter> make_filter(size_t n) {
    auto o = bench_options();
    o.adaptive_particle_count = 0;
    o.particle_count = static_cast<int32_t>(n);
    o.recovery = 0;
    LocalizerMap copy = office_map();
    auto pf = std::make_unique<ParticleFilter>(std::move(copy), o, 5);
    pf->init_floor_only(0);
    return pf;
}

void BM_FilterPredict(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    auto pf = make_filter(n);
    double t = 0, e = 0;
    float sign = 1;
    pf->predict({t, e, 0, 0, WF_VIO_TRACKING_NORMAL});
    for (auto _ : state) {
        t += 1.0 / 30;
        e += 0.04 * sign;
        sign = -sign;
        benchmark::DoNotOptimize(pf->predict({t, e, 0, 0.01 * sign, WF_VIO_TRACKING_NORMAL}));
    }
    set_counters(state, n, 2 * ParticleSet::kBytesPerParticle + sizeof(float) + sizeof(uint32_t));
}

void BM_FilterUpdateSigns(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    auto pf = make_filter(n);
    pf->predict({0, 0, 0, 0.3, WF_VIO_TRACKING_NORMAL});
    const wf_sign_observation z[2] = {{0, 6.0, 0.1, 0.9}, {0, 9.5, -0.2, 0.9}};
    double t = 0;
    for (auto _ : state) {
        state.PauseTiming();
        pf = make_filter(n);  // every update starts from the spread-out cloud (the costly case)
        pf->predict({0, 0, 0, 0.3, WF_VIO_TRACKING_NORMAL});
        state.ResumeTiming();
        t += 0.1;
        benchmark::DoNotOptimize(pf->update_signs(z, 2, t));
    }
    set_counters(state, n, 2 * ParticleSet::kBytesPerParticle + sizeof(float) + sizeof(uint32_t));
}

// Clustering of the spread-out cloud (the estimate and the hypothesis-preserving resampling each run it).
void BM_ClusterSpread(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    const ParticleSet p = uniform_particles(n, 7);
    ClusterParams cp;
    cp.dense_bins = state.range(1) != 0;
    ParticleClusterer c;
    for (auto _ : state) benchmark::DoNotOptimize(c.run(p, 0.3f, cp).size());
    set_counters(state, n, 0);
}

/// Shipped defaults (App/Core/PipelineOptions: 100k particles, KLD-sampling up to 100k, recovery on).
wf_localizer_options full_step_options(size_t n) {
    auto o = bench_options();
    o.particle_count = static_cast<int32_t>(n);
    o.max_particles = static_cast<int32_t>(n);
    return o;
}

/// Four ARKit planes around the camera at the VIO origin, in the office's corridor geometry: walls 2 m left
/// and right, one 3 m ahead, one oblique (anchor ids from first_id).
std::vector<wf_plane_observation> full_step_planes(uint64_t first_id) {
    return {{first_id, 0.5, 2.0, -kPiD / 2, 3.0}, {first_id + 1, 1.0, -2.0, kPiD / 2, 2.5},
            {first_id + 2, 3.0, 0.2, kPiD, 1.5}, {first_id + 3, 2.0, 2.0, -2.3, 1.0}};
}

/// A filter right after a floor-only start (spread-out cloud), one VIO sample seen and the wall fields of the
/// plane model built, so the measured step does only per-frame work.
std::unique_ptr<ParticleFilter> full_step_prototype(size_t n, bool twins = true) {
    auto pf = std::make_unique<ParticleFilter>(office_map(), full_step_options(n), 5);
    // The synthetic office is symmetric under a half turn (map/floor_symmetry: its doors are 0.67 m off the
    // turned ones), so the shipped filter scores every particle's twin too (pf/twin_guard).
    pf->set_parameter("twin.enabled", twins ? 1 : 0);
    pf->init_floor_only(0);
    pf->predict({0, 0, 0, 0.3, WF_VIO_TRACKING_NORMAL});
    const wf_plane_observation narrow{1, 0.5, 2.0, -kPiD / 2, 0.01};  // too narrow: builds the fields only
    pf->update_planes(&narrow, 1, 0);
    return pf;
}

/// Which frame the timed step is: the first after a floor-only start, or a frame after one with the same two
/// sightings (the cloud resampled once), untracked or of tracked objects.
enum class StepFrame { kFirst, kSecond, kSecondTracked };

// One full frame of the filter on the spread-out cloud: predict (4 cm, 0.6 deg), update_signs (2 sightings,
// with resampling), update_planes (4 planes, resampling when due) and the estimate read (clustering).
// BM_FilterFullStep: the shipped filter on this (symmetric) floor, twins scored; BM_FilterFullStepWithoutTwins:
// the same with `twin.enabled` 0, what a floor without symmetry costs.
void full_step(benchmark::State &state, bool twins, StepFrame frame = StepFrame::kFirst) {
    const size_t n = static_cast<size_t>(state.range(0));
    const auto proto = full_step_prototype(n, twins);
    wf_sign_observation z[2] = {{0, 6.0, 0.1, 0.9}, {0, 9.5, -0.2, 0.9}};
    if (frame == StepFrame::kSecondTracked) {
        // Both sightings are of tracked objects (the pipeline's tracks) seen in the prototype's frame, so the timed
        // step takes the object-level update and gathers two ratio arrays.
        for (uint32_t k = 0; k < 2; ++k) {
            z[k].track_id = k + 1;
            z[k].track_range_m = z[k].range_m + 0.04;
            z[k].track_bearing_rad = z[k].bearing_rad;
        }
    }
    if (frame != StepFrame::kFirst) {
        proto->predict({1.0 / 30, 0.04, 0, 0.31, WF_VIO_TRACKING_NORMAL});
        proto->update_signs(z, 2, 1.0 / 30);
    }
    auto pf = std::make_unique<ParticleFilter>(*proto);
    const auto planes = full_step_planes(100);
    size_t resamplings = 0, iterations = 0;
    for (auto _ : state) {
        state.PauseTiming();
        *pf = *proto;  // every step starts from the spread-out cloud (the costly case)
        state.ResumeTiming();
        pf->predict({1.0 / 30, 0.04, 0, 0.31, WF_VIO_TRACKING_NORMAL});
        pf->update_signs(z, 2, 1.0 / 30);
        pf->update_planes(planes.data(), planes.size(), 1.0 / 30);
        benchmark::DoNotOptimize(pf->estimate());
        resamplings += pf->resample_count();
        ++iterations;
    }
    state.counters["resamplings"] = static_cast<double>(resamplings) / static_cast<double>(std::max<size_t>(1, iterations));
    set_counters(state, n, 2 * ParticleSet::kBytesPerParticle + sizeof(float) + sizeof(uint32_t));
}
void BM_FilterFullStep(benchmark::State &state) { full_step(state, true); }
void BM_FilterFullStepWithoutTwins(benchmark::State &state) { full_step(state, false); }
// The frame after one with the same sightings (the cloud resampled once), untracked and of tracked objects
// (pf/track_evidence, on by default): what tracking costs once the pipeline has seen the objects before.
void BM_FilterFullStepSecondFrameWithoutTwins(benchmark::State &state) { full_step(state, false, StepFrame::kSecond); }
void BM_FilterFullStepSecondFrameTrackedWithoutTwins(benchmark::State &state) {
    full_step(state, false, StepFrame::kSecondTracked);
}

// ---------------------------------------------------------------------------------------------- baseline

struct AosParticle {
    double x, y, yaw_offset, scale, weight;
    int floor;
};

/// 5 cm occupancy raster of the office walls.
struct Raster {
    float x0, y0, cell = 0.05f;
    int nx, ny;
    std::vector<uint8_t> occ;
    Raster() {
        const FloorData &f = office_map().floors[0];
        x0 = f.grid.x0;
        y0 = f.grid.y0;
        nx = static_cast<int>(f.grid.nx * f.grid.cell_m / cell);
        ny = static_cast<int>(f.grid.ny * f.grid.cell_m / cell);
        occ.assign(static_cast<size_t>(nx) * ny, 0);
        Office office;
        for (size_t s = 0; s < office.walls.size() / 4; ++s) {
            const float *w = &office.walls[4 * s];
            const float len = std::hypot(w[2] - w[0], w[3] - w[1]);
            const int steps = static_cast<int>(len / (cell * 0.5f)) + 1;
            for (int k = 0; k <= steps; ++k) {
                const float t = static_cast<float>(k) / steps;
                set(w[0] + t * (w[2] - w[0]), w[1] + t * (w[3] - w[1]));
            }
        }
    }
    void set(float x, float y) {
        const int ix = static_cast<int>((x - x0) / cell), iy = static_cast<int>((y - y0) / cell);
        if (ix >= 0 && iy >= 0 && ix < nx && iy < ny) occ[static_cast<size_t>(iy) * nx + ix] = 1;
    }
    bool blocked(double ax, double ay, double bx, double by) const {
        const double len = std::hypot(bx - ax, by - ay);
        const int steps = static_cast<int>(len / cell) + 1;
        for (int k = 0; k <= steps; ++k) {
            const double t = static_cast<double>(k) / steps;
            const int ix = static_cast<int>((ax + t * (bx - ax) - x0) / cell);
            const int iy = static_cast<int>((ay + t * (by - ay) - y0) / cell);
            if (ix < 0 || iy < 0 || ix >= nx || iy >= ny) continue;
            if (occ[static_cast<size_t>(iy) * nx + ix]) return true;
        }
        return false;
    }
};

std::vector<AosParticle> aos_particles(size_t n, uint64_t seed) {
    const ParticleSet p = uniform_particles(n, seed);
    std::vector<AosParticle> a(n);
    for (size_t i = 0; i < n; ++i) a[i] = {p.x[i], p.y[i], p.yaw_offset[i], p.scale[i], p.weight[i], 0};
    return a;
}

/// The straightforward motion update: array of structs, std::mt19937 + std::normal_distribution (2 samples),
/// std::cos / std::sin, a wall test by marching a 5 cm raster.
struct BaselineMotion {
    std::mt19937 gen{2};
    std::normal_distribution<double> noise_x{0.0, 0.15 * std::sqrt(0.04)}, noise_y{0.0, 0.15 * std::sqrt(0.04)};
    void step(std::vector<AosParticle> &p, const Raster &raster, double de, double dn) {
        for (AosParticle &q : p) {
            const double c = std::cos(q.yaw_offset), s = std::sin(q.yaw_offset);
            const double nx = q.x + q.scale * (c * de - s * dn) + noise_x(gen);
            const double ny = q.y + q.scale * (s * de + c * dn) + noise_y(gen);
            if (raster.blocked(q.x, q.y, nx, ny)) q.weight *= 1.0;  // same no-denormal rule as BM_MotionUpdate
            q.x = nx;
            q.y = ny;
        }
    }
};

const Raster &baseline_raster() {
    static const Raster raster;
    return raster;
}

void BM_BaselineMotionUpdate(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    std::vector<AosParticle> p = aos_particles(n, 1);
    BaselineMotion motion;
    double sign = 1;
    for (auto _ : state) {
        motion.step(p, baseline_raster(), 0.04 * sign, 0);
        sign = -sign;
        benchmark::DoNotOptimize(p.data());
    }
    set_counters(state, n, sizeof(AosParticle));
}

/// One byte per sign per cell (what a straightforward implementation stores).
const std::vector<std::vector<uint8_t>> &baseline_visibility() {
    static const std::vector<std::vector<uint8_t>> vis = [] {
        const FloorData &f = office_map().floors[0];
        std::vector<std::vector<uint8_t>> v(f.signs.size(), std::vector<uint8_t>(static_cast<size_t>(f.grid.cell_count())));
        for (size_t j = 0; j < f.signs.size(); ++j) {
            for (int64_t c = 0; c < f.grid.cell_count(); ++c) v[j][c] = (f.visibility[c * f.words_per_cell] >> j) & 1u;
        }
        return v;
    }();
    return vis;
}

/// The straightforward sign update (2 sightings, kind exit): array of structs, double, per-sign byte
/// visibility rasters, std::atan2 / std::exp / std::log per candidate sign; weights multiplied by L.
void baseline_sign_update(std::vector<AosParticle> &p, double vio_yaw) {
    const FloorData &f = office_map().floors[0];
    const std::vector<std::vector<uint8_t>> &vis = baseline_visibility();
    const double obs_r[2] = {6.0, 9.5}, obs_b[2] = {0.1, -0.2};
    const double half_fov = 0.5 * 48 * kPiD / 180, sb = 3 * kPiD / 180, pc = 0.1;
    const double u = 1.0 / (12.0 * 2 * half_fov);
    for (AosParticle &q : p) {
        const int c = f.grid.index(static_cast<float>(q.x), static_cast<float>(q.y));
        double ll = 0;
        for (int o = 0; o < 2; ++o) {
            double mix = 0;
            int nvis = 0;
            for (size_t j = 0; j < f.signs.size(); ++j) {
                if (c < 0 || !vis[j][c]) continue;
                const double dx = f.signs.x[j] - q.x, dy = f.signs.y[j] - q.y;
                const double b = std::remainder(std::atan2(dy, dx) - (vio_yaw + q.yaw_offset), 2 * kPiD);
                if (std::fabs(b) > half_fov) continue;
                const double r = std::sqrt(dx * dx + dy * dy);
                const double sr = 0.1 + 0.12 * r;
                const double er = (obs_r[o] - r) / sr, eb = std::remainder(obs_b[o] - b, 2 * kPiD) / sb;
                mix += std::exp(-0.5 * (er * er + eb * eb)) / (2 * kPiD * sr * sb);
                ++nvis;
            }
            ll += std::log(pc * u + (nvis ? (1 - pc) * mix / nvis : 0.0));
        }
        q.weight *= std::exp(ll);
    }
}

void BM_BaselineSignUpdate(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    std::vector<AosParticle> p = aos_particles(n, 3);
    for (auto _ : state) {
        baseline_sign_update(p, 0.3);
        benchmark::DoNotOptimize(p.data());
    }
    set_counters(state, n, sizeof(AosParticle));
}

/// A cluster of the straightforward clustering: member particles and weighted statistics.
struct BaselineCluster {
    std::vector<size_t> members;
    double weight = 0, x = 0, y = 0, cov_xx = 0, cov_xy = 0, cov_yy = 0, heading = 0;
};

/// The straightforward clustering: particles binned (1 m, 45 deg) in a std::map of member lists, bins with
/// >= 1e-4 of the weight flood-filled over their 26 neighbours (breadth-first, std::set of visited bins),
/// then two passes per cluster for the weighted mean, covariance and circular mean heading (std::atan2,
/// std::cos / std::sin). Sorted heaviest first.
std::vector<BaselineCluster> baseline_cluster(const std::vector<AosParticle> &p, double vio_yaw) {
    using Key = std::tuple<int, int, int, int>;
    std::map<Key, std::vector<size_t>> bins;
    for (size_t i = 0; i < p.size(); ++i) {
        const double h = std::remainder(vio_yaw + p[i].yaw_offset, 2 * kPiD) + kPiD;
        const int ih = std::min(7, static_cast<int>(h / (2 * kPiD / 8)));
        bins[Key{p[i].floor, static_cast<int>(std::floor(p[i].x)), static_cast<int>(std::floor(p[i].y)), ih}].push_back(i);
    }
    auto bin_weight = [&](const std::vector<size_t> &m) {
        double w = 0;
        for (size_t i : m) w += p[i].weight;
        return w;
    };
    std::set<Key> visited;
    std::vector<BaselineCluster> clusters;
    for (const auto &entry : bins) {
        if (visited.count(entry.first) || bin_weight(entry.second) < 1e-4) continue;
        BaselineCluster c;
        std::deque<Key> queue{entry.first};
        visited.insert(entry.first);
        while (!queue.empty()) {
            const Key k = queue.front();
            queue.pop_front();
            const std::vector<size_t> &m = bins.at(k);
            c.members.insert(c.members.end(), m.begin(), m.end());
            for (int dx = -1; dx <= 1; ++dx) {
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dh = -1; dh <= 1; ++dh) {
                        const Key nk{std::get<0>(k), std::get<1>(k) + dx, std::get<2>(k) + dy, (std::get<3>(k) + dh + 8) % 8};
                        auto it = bins.find(nk);
                        if (it == bins.end() || visited.count(nk) || bin_weight(it->second) < 1e-4) continue;
                        visited.insert(nk);
                        queue.push_back(nk);
                    }
                }
            }
        }
        double sx = 0, sy = 0, hc = 0, hs = 0;
        for (size_t i : c.members) {
            c.weight += p[i].weight;
            sx += p[i].weight * p[i].x;
            sy += p[i].weight * p[i].y;
            hc += p[i].weight * std::cos(vio_yaw + p[i].yaw_offset);
            hs += p[i].weight * std::sin(vio_yaw + p[i].yaw_offset);
        }
        if (c.weight > 0) {
            c.x = sx / c.weight;
            c.y = sy / c.weight;
            c.heading = std::atan2(hs, hc);
            for (size_t i : c.members) {
                const double w = p[i].weight / c.weight, dx = p[i].x - c.x, dy = p[i].y - c.y;
                c.cov_xx += w * dx * dx;
                c.cov_xy += w * dx * dy;
                c.cov_yy += w * dy * dy;
            }
        }
        clusters.push_back(std::move(c));
    }
    std::sort(clusters.begin(), clusters.end(), [](const BaselineCluster &a, const BaselineCluster &b) { return a.weight > b.weight; });
    return clusters;
}

/// Normalises the weights; returns the effective sample size.
double baseline_normalize(std::vector<AosParticle> &p) {
    double s = 0;
    for (const AosParticle &q : p) s += q.weight;
    double s2 = 0;
    for (AosParticle &q : p) {
        q.weight = s > 0 ? q.weight / s : 1.0 / p.size();
        s2 += q.weight * q.weight;
    }
    return 1.0 / s2;
}

/// The straightforward hypothesis-preserving resampling: cluster, then a systematic draw within each
/// cluster holding >= 1 % of the weight (half the particles shared equally, half by weight) and one for the
/// rest, into a new array of structs.
void baseline_resample(std::vector<AosParticle> &p, double vio_yaw, std::mt19937 &gen) {
    const std::vector<BaselineCluster> clusters = baseline_cluster(p, vio_yaw);
    std::vector<std::vector<size_t>> groups;
    std::vector<char> grouped(p.size(), 0);
    for (const BaselineCluster &c : clusters) {
        if (c.weight < 0.01) break;
        groups.push_back(c.members);
        for (size_t i : c.members) grouped[i] = 1;
    }
    groups.emplace_back();
    for (size_t i = 0; i < p.size(); ++i) {
        if (!grouped[i]) groups.back().push_back(i);
    }
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<AosParticle> out;
    out.reserve(p.size());
    const size_t n = p.size();
    for (size_t g = 0; g < groups.size(); ++g) {
        double wg = 0;
        for (size_t i : groups[g]) wg += p[i].weight;
        if (!(wg > 0)) continue;
        size_t ng = static_cast<size_t>(std::lround(n * (0.5 * wg + 0.5 / groups.size())));
        if (g + 1 == groups.size() || out.size() + ng > n) ng = n - out.size();
        const double step = wg / std::max<size_t>(1, ng);
        double target = uni(gen) * step, cum = 0;
        size_t k = 0;
        for (size_t d = 0; d < ng; ++d) {
            while (k + 1 < groups[g].size() && cum + p[groups[g][k]].weight < target) cum += p[groups[g][k++]].weight;
            AosParticle q = p[groups[g][k]];
            q.weight = wg / ng;
            out.push_back(q);
            target += step;
        }
    }
    p.swap(out);
}

// The straightforward full frame: BaselineMotion, baseline_sign_update, normalisation and the clustered
// resampling when the ESS is below N/2, the plain plane likelihood (bench_support.hpp), normalisation and
// resampling when due, and the estimate's clustering.
void BM_BaselineFullStep(benchmark::State &state) {
    const size_t n = static_cast<size_t>(state.range(0));
    const std::vector<AosParticle> proto = aos_particles(n, 5);
    const auto planes = full_step_planes(100);
    const PlaneModelParams prm;
    const WallIndex &walls = office_map().floors[0].walls;
    std::vector<AosParticle> p;
    for (auto _ : state) {
        state.PauseTiming();
        p = proto;
        BaselineMotion motion;
        std::mt19937 gen(9);
        state.ResumeTiming();
        motion.step(p, baseline_raster(), 0.04, 0);
        baseline_sign_update(p, 0.31);
        if (baseline_normalize(p) < 0.5 * n) baseline_resample(p, 0.31, gen);
        for (AosParticle &q : p) {
            q.weight *= std::exp(bench::baseline_plane_log_likelihood(q.x, q.y, q.yaw_offset, q.scale, planes, walls, prm));
        }
        if (baseline_normalize(p) < 0.5 * n) baseline_resample(p, 0.31, gen);
        benchmark::DoNotOptimize(baseline_cluster(p, 0.31).size());
    }
    set_counters(state, n, sizeof(AosParticle));
}

}  // namespace

BENCHMARK(BM_MotionUpdate)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BaselineMotionUpdate)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SignUpdate)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BaselineSignUpdate)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FilterPredict)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FilterUpdateSigns)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond)->Iterations(20);

BENCHMARK(BM_ClusterSpread)->Args({100000, 1})->Args({100000, 0})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FilterFullStep)->Arg(100000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_FilterFullStepWithoutTwins)->Arg(100000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_FilterFullStepSecondFrameWithoutTwins)->Arg(100000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_FilterFullStepSecondFrameTrackedWithoutTwins)->Arg(100000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_BaselineFullStep)->Arg(100000)->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK_MAIN();
