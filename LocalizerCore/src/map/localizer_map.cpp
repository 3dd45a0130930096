#include "map/localizer_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "map/floor_footprint.hpp"

namespace wf::loc {

namespace {

bool finite2(float a, float b) { return std::isfinite(a) && std::isfinite(b); }

// Largest fine grid per floor; bigger floors get coarser cells (a 0.25 m grid over 500 m x 500 m would be
// 4 M cells: still fine; beyond that the cell grows).
constexpr int64_t kMaxGridCells = 4'000'000;

// Largest east-west or north-south extent of one floor (walls, signs, link and seed points), meters. The Swift
// map validator checks the same limit first (MapValidator.maximumFloorExtentMeters). Coordinates arrive as
// floats, whose rounding near 100 km is under 4 mm per coordinate: the check allows 1 cm more, so that a floor
// the validator accepts (extent <= 100 km in doubles) is never refused here.
constexpr double kMaxFloorExtentM = 100'000.0;
// Margin of the floor footprint around its walls, signs and graph nodes, meters (below the grid's 2 m pad).
constexpr float kFootprintMarginM = 1.0f;
constexpr double kFloatRoundingSlackM = 0.01;

std::string meters(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

}  // namespace

int32_t FloorData::nearest_link(float x, float y, float *distance_m) const {
    int32_t best = -1;
    float best_d = std::numeric_limits<float>::infinity();
    for (size_t i = 0; i < link_x.size(); ++i) {
        const float dx = link_x[i] - x, dy = link_y[i] - y;
        const float d = std::sqrt(dx * dx + dy * dy);
        if (d < best_d) best_d = d, best = static_cast<int32_t>(i);
    }
    if (distance_m) *distance_m = best_d;
    return best;
}

float FloorData::distance_to_link(float x, float y) const {
    float d;
    nearest_link(x, y, &d);
    return d;
}

void compute_visibility(FloorData &f, float max_range_all_m, float max_view_angle_from_normal_rad) {
    const size_t n = f.signs.size();
    f.words_per_cell = static_cast<int32_t>((n + 63) / 64);
    f.visibility.assign(static_cast<size_t>(f.grid.cell_count()) * f.words_per_cell, 0);
    if (n == 0) return;
    const FloorGrid &g = f.grid;
    // A sign hangs on a wall: cast the ray to a point 5 cm in front of the face so the sign's own wall
    // does not hide it, and stop 1 cm short.
    constexpr float kFaceOffset = 0.05f;
    // Seen more obliquely than max_view_angle_from_normal_rad (wf_localizer.h), a sign is not predicted visible.
    for (size_t j = 0; j < n; ++j) {
        // The sign's own limits (its kind's: a placard is read from closer and more squarely), when it has them.
        const float own_r = f.signs.own_max_range_m[j], own_a = f.signs.own_max_view_angle_rad[j];
        const float max_range_m = own_r > 0.0f ? std::min(own_r, max_range_all_m) : max_range_all_m;
        const float cos_max_view = std::cos(own_a > 0.0f ? std::min(own_a, max_view_angle_from_normal_rad)
                                                         : max_view_angle_from_normal_rad);
        const float sx = f.signs.x[j], sy = f.signs.y[j];
        const float fx = f.signs.facing_x[j], fy = f.signs.facing_y[j];
        const bool both = f.signs.double_sided[j] != 0;
        const int32_t ix0 = g.clamp_ix(sx - max_range_m), ix1 = g.clamp_ix(sx + max_range_m);
        const int32_t iy0 = g.clamp_iy(sy - max_range_m), iy1 = g.clamp_iy(sy + max_range_m);
        const size_t word = j / 64;
        const uint64_t bit = uint64_t{1} << (j % 64);
        for (int32_t iy = iy0; iy <= iy1; ++iy) {
            const float cy = g.center_y(iy);
            for (int32_t ix = ix0; ix <= ix1; ++ix) {
                const float cx = g.center_x(ix);
                const float dx = cx - sx, dy = cy - sy;  // sign -> cell
                const float d2 = dx * dx + dy * dy;
                if (d2 > max_range_m * max_range_m || d2 < 1e-6f) continue;
                const float side = fx * dx + fy * dy;     // > 0: cell in front of the face
                const float len = std::sqrt(d2);
                // In front of the face and not too oblique: cos(view angle) = side / len (facing is unit).
                if (both ? std::fabs(side) <= cos_max_view * len : side <= cos_max_view * len) continue;
                const float s = side >= 0.0f ? 1.0f : -1.0f;
                const float tx = sx + s * kFaceOffset * fx, ty = sy + s * kFaceOffset * fy;
                const float shrink = std::max(0.0f, 1.0f - 0.01f / len);
                const float ex = cx + (tx - cx) * shrink, ey = cy + (ty - cy) * shrink;
                if (f.walls.crosses(cx, cy, ex, ey)) continue;
                f.visibility[(static_cast<size_t>(iy) * g.nx + ix) * f.words_per_cell + word] |= bit;
            }
        }
    }
}

namespace {

void compute_walkable(FloorData &f, const float *seeds, size_t seed_count, float clearance_m) {
    const FloorGrid &g = f.grid;
    const int64_t cells = g.cell_count();
    f.walkable.assign(static_cast<size_t>(cells), 0);
    std::vector<uint8_t> reached(static_cast<size_t>(cells), 0);
    if (seed_count == 0) {
        std::fill(reached.begin(), reached.end(), 1);
    } else {
        // Flood fill (4-neighbour BFS) from the seed cells; a step between two cell centres that crosses a
        // wall is not taken, so the fill stays inside the building and its rooms connected by openings.
        std::vector<int32_t> queue;
        queue.reserve(static_cast<size_t>(cells));
        for (size_t i = 0; i < seed_count; ++i) {
            const int32_t c = g.index(seeds[2 * i], seeds[2 * i + 1]);
            if (c >= 0 && !reached[c]) {
                reached[c] = 1;
                queue.push_back(c);
            }
        }
        for (size_t head = 0; head < queue.size(); ++head) {
            const int32_t c = queue[head];
            const int32_t ix = c % g.nx, iy = c / g.nx;
            const float cx = g.center_x(ix), cy = g.center_y(iy);
            const int32_t nbx[4] = {ix + 1, ix - 1, ix, ix};
            const int32_t nby[4] = {iy, iy, iy + 1, iy - 1};
            for (int k = 0; k < 4; ++k) {
                if (nbx[k] < 0 || nby[k] < 0 || nbx[k] >= g.nx || nby[k] >= g.ny) continue;
                const int32_t n = nby[k] * g.nx + nbx[k];
                if (reached[n]) continue;
                if (f.walls.crosses(cx, cy, g.center_x(nbx[k]), g.center_y(nby[k]))) continue;
                reached[n] = 1;
                queue.push_back(n);
            }
        }
    }
    f.walkable_cells.clear();
    for (int32_t iy = 0; iy < g.ny; ++iy) {
        for (int32_t ix = 0; ix < g.nx; ++ix) {
            const int32_t c = iy * g.nx + ix;
            if (!reached[c]) continue;
            if (f.walls.distance_to_nearest(g.center_x(ix), g.center_y(iy), clearance_m) < clearance_m) continue;
            f.walkable[c] = 1;
            f.walkable_cells.push_back(c);
        }
    }
}

}  // namespace

int build_localizer_map(const wf_localizer_map &map, const wf_localizer_options &opts, LocalizerMap &out,
                        std::string &error) {
    if (map.version != WF_LOCALIZER_MAP_VERSION) {
        error = "map version " + std::to_string(map.version) + " is not supported (expected " +
                std::to_string(WF_LOCALIZER_MAP_VERSION) + ")";
        return WF_LOC_ERR_VERSION;
    }
    if (map.floor_count == 0 || map.floors == nullptr) {
        error = "map has no floor";
        return WF_LOC_ERR_INVALID_MAP;
    }
    if (map.floor_count > 32767) {
        error = "map has too many floors (" + std::to_string(map.floor_count) + ", at most 32767)";
        return WF_LOC_ERR_INVALID_MAP;
    }
    if (map.kind_count < 0 || map.kind_count > 4096) {
        error = "map kind_count " + std::to_string(map.kind_count) + " is outside [0, 4096]";
        return WF_LOC_ERR_INVALID_MAP;
    }
    out.floors.clear();
    out.floors.resize(map.floor_count);
    out.kind_count = map.kind_count;
    for (size_t fi = 0; fi < map.floor_count; ++fi) {
        const wf_localizer_floor &src = map.floors[fi];
        const std::string where = "floor " + std::to_string(fi) + ": ";
        if ((src.wall_count && !src.walls) || (src.sign_count && !src.signs) ||
            (src.link_point_count && !src.link_points) || (src.seed_point_count && !src.seed_points)) {
            error = where + "an array is NULL but its count is not 0";
            return WF_LOC_ERR_INVALID_MAP;
        }
        if (!std::isfinite(src.elevation_m)) {
            error = where + "elevation is not finite";
            return WF_LOC_ERR_INVALID_MAP;
        }
        FloorData &f = out.floors[fi];
        f.elevation_m = src.elevation_m;
        // Bounding box of everything on the floor.
        float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
        auto grow = [&](float x, float y) {
            x0 = std::min(x0, x); y0 = std::min(y0, y); x1 = std::max(x1, x); y1 = std::max(y1, y);
        };
        for (size_t i = 0; i < src.wall_count; ++i) {
            const float *w = src.walls + 4 * i;
            if (!finite2(w[0], w[1]) || !finite2(w[2], w[3])) {
                error = where + "wall " + std::to_string(i) + " has a non-finite coordinate";
                return WF_LOC_ERR_INVALID_MAP;
            }
            grow(w[0], w[1]);
            grow(w[2], w[3]);
        }
        for (size_t i = 0; i < src.sign_count; ++i) {
            const wf_localizer_sign &s = src.signs[i];
            if (!finite2(s.x, s.y) || !finite2(s.facing_x, s.facing_y)) {
                error = where + "sign " + std::to_string(i) + " has a non-finite coordinate";
                return WF_LOC_ERR_INVALID_MAP;
            }
            if (s.kind < 0 || s.kind >= map.kind_count) {
                error = where + "sign " + std::to_string(i) + " has kind " + std::to_string(s.kind) +
                        " outside [0, kind_count=" + std::to_string(map.kind_count) + ")";
                return WF_LOC_ERR_INVALID_MAP;
            }
            if (!std::isfinite(s.max_range_m) || s.max_range_m < 0 || !std::isfinite(s.max_view_angle_rad) ||
                s.max_view_angle_rad < 0) {
                error = where + "sign " + std::to_string(i) + " has a negative or non-finite max range or view angle";
                return WF_LOC_ERR_INVALID_MAP;
            }
            grow(s.x, s.y);
        }
        for (size_t i = 0; i < src.link_point_count; ++i) {
            const float *p = src.link_points + 2 * i;
            if (!finite2(p[0], p[1])) {
                error = where + "link point " + std::to_string(i) + " is not finite";
                return WF_LOC_ERR_INVALID_MAP;
            }
            grow(p[0], p[1]);
            f.link_x.push_back(p[0]);
            f.link_y.push_back(p[1]);
        }
        for (size_t i = 0; i < src.seed_point_count; ++i) {
            const float *p = src.seed_points + 2 * i;
            if (!finite2(p[0], p[1])) {
                error = where + "seed point " + std::to_string(i) + " is not finite";
                return WF_LOC_ERR_INVALID_MAP;
            }
            grow(p[0], p[1]);
        }
        if (!(x0 <= x1)) { x0 = y0 = 0; x1 = y1 = 0; }  // empty floor: a small grid around the origin
        const double width = static_cast<double>(x1) - x0, height = static_cast<double>(y1) - y0;
        if (width > kMaxFloorExtentM + kFloatRoundingSlackM || height > kMaxFloorExtentM + kFloatRoundingSlackM) {
            error = where + "extent " + meters(width) + " m x " + meters(height) + " m (x from " + meters(x0) +
                    " to " + meters(x1) + ", y from " + meters(y0) + " to " + meters(y1) +
                    ", over walls, signs and graph nodes) is larger than 100 km (100000 m) on one axis";
            return WF_LOC_ERR_INVALID_MAP;
        }
        const float pad = 2.0f;
        x0 -= pad; y0 -= pad; x1 += pad; y1 += pad;
        float cell = static_cast<float>(opts.grid_cell_m);
        while (static_cast<double>((x1 - x0) / cell) * static_cast<double>((y1 - y0) / cell) > kMaxGridCells) cell *= 2;
        f.grid = FloorGrid(x0, y0, x1, y1, cell);
        const float wcell = std::max(static_cast<float>(opts.wall_index_cell_m), cell);
        const FloorGrid wgrid(x0, y0, x1, y1, wcell);
        {
            // The footprint (map/floor_footprint): the hull of the walls, signs and graph nodes, grown by
            // kFootprintMarginM (inside the grid's 2 m pad).
            std::vector<float> points(src.seed_points, src.seed_points + 2 * src.seed_point_count);
            for (size_t i = 0; i < src.sign_count; ++i) points.insert(points.end(), {src.signs[i].x, src.signs[i].y});
            const std::vector<float> boundary = floor_footprint_boundary(src.walls, src.wall_count, points.data(),
                                                                         points.size() / 2, kFootprintMarginM);
            f.walls = WallIndex(wgrid, src.walls, src.wall_count, boundary.data(), boundary.size() / 4);
        }
        f.symmetries = find_floor_symmetries(f.walls);
        for (size_t i = 0; i < src.sign_count; ++i) {
            const wf_localizer_sign &s = src.signs[i];
            float nx = s.facing_x, ny = s.facing_y;
            const float len = std::sqrt(nx * nx + ny * ny);
            const bool both = s.double_sided != 0 || len < 1e-6f;  // no normal: readable from anywhere
            if (len >= 1e-6f) { nx /= len; ny /= len; } else { nx = 1; ny = 0; }
            f.signs.kind.push_back(s.kind);
            f.signs.x.push_back(s.x);
            f.signs.y.push_back(s.y);
            f.signs.facing_x.push_back(nx);
            f.signs.facing_y.push_back(ny);
            f.signs.double_sided.push_back(both ? 1 : 0);
            f.signs.own_max_range_m.push_back(s.max_range_m);
            f.signs.own_max_view_angle_rad.push_back(s.max_view_angle_rad);
        }
        compute_visibility(f, static_cast<float>(opts.max_sign_range_m), static_cast<float>(opts.max_view_angle_from_normal_rad));
        f.kind_masks.assign(static_cast<size_t>(map.kind_count) * f.words_per_cell, 0);
        for (size_t j = 0; j < f.signs.size(); ++j) {
            f.kind_masks[static_cast<size_t>(f.signs.kind[j]) * f.words_per_cell + j / 64] |= uint64_t{1} << (j % 64);
        }
        compute_walkable(f, src.seed_points, src.seed_point_count, static_cast<float>(opts.wall_clearance_m));
    }
    return WF_LOC_OK;
}

}  // namespace wf::loc
