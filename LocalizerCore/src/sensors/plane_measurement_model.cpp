#include "sensors/plane_measurement_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/fast_math.hpp"
#include "common/simd_clones.hpp"

namespace wf::loc {

namespace {

/// Direction levels (pi / 128 each) per radian.
constexpr float kLevelsPerRad = static_cast<float>(WallField::kDirectionLevels) / kPi;

/// std::max(init, v[0], ..., v[n - 1]) folded in eight independent lanes, then the lanes (no chain of
/// dependent maxima through every particle). The same value as the sequential fold for values that hold no
/// negative zero (every log-likelihood here is +0 or a sum of negative terms): std::max keeps its first
/// argument against a NaN, so a NaN never enters either fold, and the maximum of the others does not depend on
/// the order.
/// Particles (runs) per block of the one-floor path, and plane points whose cells are computed together (the
/// cells of point q of a block at cell + q * kBlock).
constexpr size_t kBlock = 512;
constexpr int32_t kPointChunk = 4;

/// acc[i] += log_p of each of Q points of particle i (cells at cell[q * kBlock + i], plane direction level
/// level[i]), in point order.
template <int32_t Q>
inline void add_lookups(const uint16_t *code, const float *lp, const int32_t *cell, const int32_t *level, float *acc,
                        size_t m) {
    for (size_t i = 0; i < m; ++i) {
        float a = acc[i];
        const int32_t lv = level[i];
        for (int32_t q = 0; q < Q; ++q) {
            const int32_t cc = code[cell[static_cast<size_t>(q) * kBlock + i]];
            a += lp[(cc & ~127) | ((cc - lv) & 127)];
        }
        acc[i] = a;
    }
}

float max_of(const float *v, size_t n, float init) {
    constexpr size_t kLanes = 8;
    float lane[kLanes];
    for (float &l : lane) l = init;
    size_t i = 0;
    for (; i + kLanes <= n; i += kLanes) {
        for (size_t k = 0; k < kLanes; ++k) lane[k] = std::max(lane[k], v[i + k]);
    }
    float m = init;
    for (float l : lane) m = std::max(m, l);
    for (; i < n; ++i) m = std::max(m, v[i]);
    return m;
}

}  // namespace

WallField build_wall_field(const WallIndex &walls, float cell_m, float max_distance_m) {
    WallField f;
    f.cell_m = cell_m;
    f.inv_cell = 1.0f / cell_m;
    f.max_distance_m = max_distance_m;
    const size_t n = walls.segment_count();
    // Bounds: the segments' box plus the saturation distance and two cells on every side.
    float x0, y0, x1, y1;
    if (!walls.segment_bounds(x0, y0, x1, y1)) return f;
    const float margin = max_distance_m + 2 * cell_m;
    f.x0 = x0 - margin;
    f.y0 = y0 - margin;
    f.nx = std::max(1, static_cast<int32_t>(std::ceil((x1 - x0 + 2 * margin) * f.inv_cell)));
    f.ny = std::max(1, static_cast<int32_t>(std::ceil((y1 - y0 + 2 * margin) * f.inv_cell)));
    const size_t cells = static_cast<size_t>(f.nx) * static_cast<size_t>(f.ny);
    std::vector<float> best(cells, max_distance_m);
    std::vector<uint8_t> dir_level(cells, 0);
    for (size_t s = 0; s < n; ++s) {
        float ax, ay, bx, by;
        walls.segment(s, ax, ay, bx, by);
        const float ex = bx - ax, ey = by - ay;
        const float len2 = ex * ex + ey * ey;
        // Direction modulo pi in [0, pi).
        float dir = std::atan2(ey, ex);
        if (dir < 0) dir += kPi;
        if (dir >= kPi) dir -= kPi;
        const auto dq = static_cast<uint8_t>(std::min(127.0f, std::floor(dir * kLevelsPerRad)));
        const int32_t ix0 = std::max(0, static_cast<int32_t>((std::min(ax, bx) - max_distance_m - f.x0) * f.inv_cell));
        const int32_t iy0 = std::max(0, static_cast<int32_t>((std::min(ay, by) - max_distance_m - f.y0) * f.inv_cell));
        const int32_t ix1 = std::min(f.nx - 1, static_cast<int32_t>((std::max(ax, bx) + max_distance_m - f.x0) * f.inv_cell));
        const int32_t iy1 = std::min(f.ny - 1, static_cast<int32_t>((std::max(ay, by) + max_distance_m - f.y0) * f.inv_cell));
        for (int32_t iy = iy0; iy <= iy1; ++iy) {
            const float cy = f.y0 + (static_cast<float>(iy) + 0.5f) * cell_m;
            for (int32_t ix = ix0; ix <= ix1; ++ix) {
                const float cx = f.x0 + (static_cast<float>(ix) + 0.5f) * cell_m;
                float t = len2 > 0 ? ((cx - ax) * ex + (cy - ay) * ey) / len2 : 0.0f;
                t = std::clamp(t, 0.0f, 1.0f);
                const float dx = ax + t * ex - cx, dy = ay + t * ey - cy;
                const float d = std::sqrt(dx * dx + dy * dy);
                const size_t c = static_cast<size_t>(iy) * static_cast<size_t>(f.nx) + static_cast<size_t>(ix);
                if (d < best[c]) {
                    best[c] = d;
                    dir_level[c] = dq;
                }
            }
        }
    }
    f.code.resize(cells);
    const float top = static_cast<float>(WallField::kDistanceLevels - 1);
    const float q = top / max_distance_m;
    for (size_t c = 0; c < cells; ++c) {
        const auto level = static_cast<uint16_t>(std::min(top, std::round(best[c] * q)));
        f.code[c] = static_cast<uint16_t>(level << 7 | dir_level[c]);
    }
    return f;
}

bool PlaneGate::admit(uint64_t anchor_id, double t, double min_interval_s) {
    auto it = last_t_.find(anchor_id);
    if (it != last_t_.end() && t - it->second < min_interval_s && t >= it->second) return false;
    last_t_[anchor_id] = t;
    return true;
}

std::vector<PreparedPlane> prepare_planes(const wf_plane_observation *obs, size_t count, double cam_east_m,
                                          double cam_north_m, double t, const PlaneModelParams &m, PlaneGate *gate,
                                          PlanePrepareStats *stats) {
    PlanePrepareStats local;
    PlanePrepareStats &st = stats ? *stats : local;
    st = PlanePrepareStats{};
    std::vector<PreparedPlane> out;
    out.reserve(count);
    for (size_t k = 0; k < count; ++k) {
        const wf_plane_observation &o = obs[k];
        if (!std::isfinite(o.center_east_m) || !std::isfinite(o.center_north_m) || !std::isfinite(o.normal_yaw_rad) ||
            !std::isfinite(o.width_m)) {
            ++st.non_finite;
            continue;
        }
        if (!(o.width_m >= m.min_width_m)) {
            ++st.too_narrow;
            continue;
        }
        const double re = o.center_east_m - cam_east_m, rn = o.center_north_m - cam_north_m;
        if (re * re + rn * rn > static_cast<double>(m.max_range_m) * m.max_range_m) {
            ++st.too_far;
            continue;
        }
        if (gate && !gate->admit(o.anchor_id, t, m.min_interval_s)) {
            ++st.gated;
            continue;
        }
        PreparedPlane p;
        p.anchor_id = o.anchor_id;
        p.rel_east_m = static_cast<float>(re);
        p.rel_north_m = static_cast<float>(rn);
        const double tangent = wrap_angle(o.normal_yaw_rad + 0.5 * kPiD);
        p.tangent_yaw_rad = static_cast<float>(tangent);
        p.tangent_east = static_cast<float>(std::cos(tangent));
        p.tangent_north = static_cast<float>(std::sin(tangent));
        p.width_m = static_cast<float>(o.width_m);
        out.push_back(p);
    }
    return out;
}

PlaneLikelihoodTable build_plane_likelihood_table(const PlaneModelParams &m) {
    PlaneLikelihoodTable t;
    constexpr int32_t D = WallField::kDistanceLevels, A = WallField::kDirectionLevels;
    t.log_p.resize(static_cast<size_t>(D) * A);
    const double inv2sd = 1.0 / (2.0 * m.sigma_distance_m * m.sigma_distance_m);
    const double inv2sa = 1.0 / (2.0 * m.sigma_angle_rad * m.sigma_angle_rad);
    for (int32_t dq = 0; dq < D; ++dq) {
        const double d = dq * static_cast<double>(m.max_distance_m) / (D - 1);
        for (int32_t diff = 0; diff < A; ++diff) {
            const int32_t fold = diff <= A / 2 ? diff : A - diff;  // angle between the lines, [0, pi/2]
            const double a = fold * kPiD / A;
            // Saturated distance: no wall within max_distance_m, only the random share explains the point.
            const double hit = dq < D - 1 ? std::exp(-d * d * inv2sd - a * a * inv2sa) : 0.0;
            t.log_p[static_cast<size_t>(dq) * A + diff] = static_cast<float>(std::log(m.z_hit * hit + m.z_rand));
        }
    }
    return t;
}

WF_SIMD_CLONES float plane_log_likelihood(const ParticleSet &p, const std::vector<WallField> &fields,
                           const PlaneLikelihoodTable &table, const PlaneModelParams &m, const PreparedPlane *planes,
                           size_t count, float *log_likelihood) {
    const size_t n = p.size();
    float max_ll = -1e30f;
    if (n == 0) return 0.0f;
    if (count == 0 || table.empty()) {
        for (size_t i = 0; i < n; ++i) max_ll = std::max(max_ll, log_likelihood[i]);
        return max_ll;
    }
    // Per plane: the sample offsets along its width (VIO meters, camera-relative) and a per-point weight
    // weight / K, so a plane counts once whatever its width.
    constexpr int32_t kMaxPoints = 16;
    const int32_t cap = std::clamp(m.max_points, 2, kMaxPoints);
    struct PlanePoints {
        float pe[kMaxPoints], pn[kMaxPoints];
        int32_t k;
        float per_point;
        float tangent_levels;  // tangent yaw in direction levels (pi / 128)
    };
    std::vector<PlanePoints> pts(count);
    for (size_t j = 0; j < count; ++j) {
        const PreparedPlane &pl = planes[j];
        const int32_t k = std::clamp(static_cast<int32_t>(std::floor(pl.width_m / m.point_spacing_m)) + 1, 2, cap);
        PlanePoints &pp = pts[j];
        pp.k = k;
        pp.per_point = m.weight / static_cast<float>(k);
        pp.tangent_levels = pl.tangent_yaw_rad * kLevelsPerRad;
        // Points spread over the width, the outer ones half a step inside the ends.
        const float half = 0.5f * pl.width_m * (1.0f - 1.0f / static_cast<float>(k));
        for (int32_t q = 0; q < k; ++q) {
            const float u = -half + 2.0f * half * static_cast<float>(q) / static_cast<float>(k - 1);
            pp.pe[q] = pl.rel_east_m + u * pl.tangent_east;
            pp.pn[q] = pl.rel_north_m + u * pl.tangent_north;
        }
    }
    const float *lp = table.log_p.data();
    // Fast path, every particle on one floor (the usual case): blocks of particles, plane points outer, so
    // the coordinate arithmetic runs over contiguous arrays (vectorised) and only the field and table
    // lookups stay scalar.
    const int16_t floor0 = p.floor[0];
    bool one_floor = floor0 >= 0 && static_cast<size_t>(floor0) < fields.size() && !fields[floor0].empty();
    for (size_t i = 1; i < n && one_floor; ++i) one_floor = p.floor[i] == floor0;
    if (one_floor) {
        const WallField &f = fields[floor0];
        const uint16_t *code = f.code.data();
        const float fx_max = static_cast<float>(f.nx - 1), fy_max = static_cast<float>(f.ny - 1);
        const int32_t stride = f.nx;
        alignas(64) float cs[kBlock], ss[kBlock], gx[kBlock], gy[kBlock], yl[kBlock], acc[kBlock], ll[kBlock];
        alignas(64) int32_t cell[kPointChunk * kBlock], level[kBlock];
        // Resampling leaves identical copies of a particle next to each other (and the plane update often
        // follows a sign update's resampling before any motion): each run of identical particles is scored
        // once, with the same arithmetic, and its value given to every copy.
        thread_local std::vector<uint32_t> first_of_run, run_of;
        thread_local std::vector<uint8_t> starts_run;
        thread_local std::vector<float> run_ll;
        first_of_run.resize(n + 1);  // + 1: the branch-free scan writes one slot past the last run's start
        run_of.resize(n);
        starts_run.resize(n);
        const float *px = p.x.data(), *py = p.y.data(), *pyaw = p.yaw_offset.data(), *psc = p.scale.data();
        // Whether particle i starts a run: a pose that differs from the previous one's in its bits (vectorised:
        // integer compares; a copy is bit for bit its source, and a pose that is equal but for the sign of a
        // zero only starts a run of its own, scored with the same arithmetic), then the runs listed by a
        // branch-free compaction.
        {
            const auto bits = [](const float *v, size_t i) {
                uint32_t u;
                std::memcpy(&u, v + i, sizeof(u));
                return u;
            };
            uint8_t *starts = starts_run.data();
            for (size_t i = 1; i < n; ++i) {
                starts[i] = static_cast<uint8_t>((bits(px, i) != bits(px, i - 1)) | (bits(py, i) != bits(py, i - 1)) |
                                                 (bits(pyaw, i) != bits(pyaw, i - 1)) |
                                                 (bits(psc, i) != bits(psc, i - 1)));
            }
        }
        first_of_run[0] = 0;
        run_of[0] = 0;
        size_t runs = 1;
        const uint8_t *starts = starts_run.data();
        for (size_t i = 1; i < n; ++i) {
            first_of_run[runs] = static_cast<uint32_t>(i);
            runs += starts[i];
            run_of[i] = static_cast<uint32_t>(runs - 1);
        }
        run_ll.resize(runs);
        alignas(64) float yo[kBlock], scp[kBlock], xp[kBlock], ypp[kBlock];
        for (size_t b = 0; b < runs; b += kBlock) {
            const size_t m_n = std::min(kBlock, runs - b);
            for (size_t i = 0; i < m_n; ++i) {
                const uint32_t src = first_of_run[b + i];
                yo[i] = pyaw[src];
                scp[i] = psc[src];
                xp[i] = px[src];
                ypp[i] = py[src];
            }
            for (size_t i = 0; i < m_n; ++i) {
                float sn, cn;
                fast_sincos(yo[i], sn, cn);
                cs[i] = scp[i] * cn * f.inv_cell;
                ss[i] = scp[i] * sn * f.inv_cell;
                gx[i] = (xp[i] - f.x0) * f.inv_cell;
                gy[i] = (ypp[i] - f.y0) * f.inv_cell;
                yl[i] = yo[i] * kLevelsPerRad + 1024.0f;
                ll[i] = 0.0f;
            }
            for (size_t j = 0; j < count; ++j) {
                const PlanePoints &pp = pts[j];
                // The plane's direction level in the map is the same for all its points: once per particle.
                for (size_t i = 0; i < m_n; ++i) {
                    acc[i] = 0.0f;
                    level[i] = static_cast<int32_t>(pp.tangent_levels + yl[i]) & 127;
                }
                // Points in chunks of kPointChunk: the cells of each point (vectorised), then per particle the
                // chunk's lookups, added in point order into a register (the same sums as point by point, with
                // several independent lookups in flight per particle and one load and store of acc).
                for (int32_t q0 = 0; q0 < pp.k; q0 += kPointChunk) {
                    const int32_t qn = std::min(kPointChunk, pp.k - q0);
                    for (int32_t q = 0; q < qn; ++q) {
                        const float pe = pp.pe[q0 + q], pn = pp.pn[q0 + q];
                        int32_t *const cq = cell + static_cast<size_t>(q) * kBlock;
                        for (size_t i = 0; i < m_n; ++i) {
                            const float fx = std::min(std::max(gx[i] + cs[i] * pe - ss[i] * pn, 0.0f), fx_max);
                            const float fy = std::min(std::max(gy[i] + ss[i] * pe + cs[i] * pn, 0.0f), fy_max);
                            cq[i] = static_cast<int32_t>(fy) * stride + static_cast<int32_t>(fx);
                        }
                    }
                    switch (qn) {
                        case 4: add_lookups<4>(code, lp, cell, level, acc, m_n); break;
                        case 3: add_lookups<3>(code, lp, cell, level, acc, m_n); break;
                        case 2: add_lookups<2>(code, lp, cell, level, acc, m_n); break;
                        default: add_lookups<1>(code, lp, cell, level, acc, m_n); break;
                    }
                }
                for (size_t i = 0; i < m_n; ++i) ll[i] += pp.per_point * acc[i];
            }
            std::copy(ll, ll + m_n, run_ll.begin() + static_cast<std::ptrdiff_t>(b));
        }
        const uint32_t *run_index = run_of.data();
        for (size_t i = 0; i < n; ++i) log_likelihood[i] += run_ll[run_index[i]];
        return max_of(log_likelihood, n, max_ll);
    }
    for (size_t i = 0; i < n; ++i) {
        const int16_t fl = p.floor[i];
        if (fl < 0 || static_cast<size_t>(fl) >= fields.size() || fields[fl].empty()) {
            max_ll = std::max(max_ll, log_likelihood[i]);
            continue;
        }
        const WallField &f = fields[fl];
        const uint16_t *code = f.code.data();
        const float fx_max = static_cast<float>(f.nx - 1), fy_max = static_cast<float>(f.ny - 1);
        const size_t stride = static_cast<size_t>(f.nx);
        float s, c;
        fast_sincos(p.yaw_offset[i], s, c);
        const float sc = p.scale[i], px = p.x[i] - f.x0, py = p.y[i] - f.y0;
        const float yaw_levels = p.yaw_offset[i] * kLevelsPerRad;
        const float cs = sc * c * f.inv_cell, ss = sc * s * f.inv_cell;
        const float gx = px * f.inv_cell, gy = py * f.inv_cell;
        float ll = 0;
        for (size_t j = 0; j < count; ++j) {
            const PlanePoints &pp = pts[j];
            // Plane direction level in the map modulo pi (|value| < 1024 levels for wrapped angles).
            const int32_t plane_level = static_cast<int32_t>(pp.tangent_levels + yaw_levels + 1024.0f) & 127;
            float acc = 0;
            for (int32_t q = 0; q < pp.k; ++q) {
                // Grid coordinates, clamped onto the (saturated) border: no branch.
                const float fx = std::min(std::max(gx + cs * pp.pe[q] - ss * pp.pn[q], 0.0f), fx_max);
                const float fy = std::min(std::max(gy + ss * pp.pe[q] + cs * pp.pn[q], 0.0f), fy_max);
                const int32_t cell_code =
                    code[static_cast<size_t>(static_cast<int32_t>(fy)) * stride + static_cast<size_t>(static_cast<int32_t>(fx))];
                acc += lp[(cell_code & ~127) | ((cell_code - plane_level) & 127)];
            }
            ll += pp.per_point * acc;
        }
        log_likelihood[i] += ll;
        max_ll = std::max(max_ll, log_likelihood[i]);
    }
    return max_ll;
}

void PlaneModelState::ensure_fields(const LocalizerMap &map) {
    if (table.empty()) table = build_plane_likelihood_table(params);
    if (fields.size() == map.floors.size()) return;
    fields.clear();
    fields.reserve(map.floors.size());
    for (const FloorData &f : map.floors) {
        fields.push_back(build_wall_field(f.walls, params.field_cell_m, params.max_distance_m));
    }
}

}  // namespace wf::loc
