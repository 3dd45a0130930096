#include "map/wall_index.hpp"

#include <algorithm>
#include <cmath>

namespace wf::loc {

bool segments_intersect(float px, float py, float qx, float qy, float ax, float ay, float bx, float by) {
    // Orientation tests (cross products): the segments intersect when each one's endpoints lie on
    // opposite sides of (or on) the other's line. Collinear pairs (sliding along a wall) do not count.
    const float ex = bx - ax, ey = by - ay;
    const float d1 = ex * (py - ay) - ey * (px - ax);
    const float d2 = ex * (qy - ay) - ey * (qx - ax);
    if ((d1 > 0 && d2 > 0) || (d1 < 0 && d2 < 0)) return false;
    if (d1 == 0 && d2 == 0) return false;
    const float mx = qx - px, my = qy - py;
    const float d3 = mx * (ay - py) - my * (ax - px);
    const float d4 = mx * (by - py) - my * (bx - px);
    if ((d3 > 0 && d4 > 0) || (d3 < 0 && d4 < 0)) return false;
    if (d3 == 0 && d4 == 0) return false;
    return true;
}

namespace {

// Does segment a-b touch the axis-aligned box [x0,x1]x[y0,y1]? (Liang-Barsky clipping.)
bool segment_touches_box(float ax, float ay, float bx, float by, float x0, float y0, float x1, float y1) {
    float t0 = 0.0f, t1 = 1.0f;
    const float dx = bx - ax, dy = by - ay;
    const float p[4] = {-dx, dx, -dy, dy};
    const float q[4] = {ax - x0, x1 - ax, ay - y0, y1 - ay};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0.0f) {
            if (q[i] < 0.0f) return false;
        } else {
            const float r = q[i] / p[i];
            if (p[i] < 0.0f) {
                if (r > t1) return false;
                t0 = std::max(t0, r);
            } else {
                if (r < t0) return false;
                t1 = std::min(t1, r);
            }
        }
    }
    return t0 <= t1;
}

namespace {
// Distance from (x, y) to segment a-b in the precision T (one formula for the float hot path and the double
// precomputation).
template <class T>
T point_segment_distance_t(T x, T y, T ax, T ay, T bx, T by) {
    const T ex = bx - ax, ey = by - ay;
    const T len2 = ex * ex + ey * ey;
    T t = len2 > T(0) ? ((x - ax) * ex + (y - ay) * ey) / len2 : T(0);
    t = std::clamp(t, T(0), T(1));
    const T dx = ax + t * ex - x, dy = ay + t * ey - y;
    return std::sqrt(dx * dx + dy * dy);
}
}  // namespace

float point_segment_distance(float x, float y, float ax, float ay, float bx, float by) {
    return point_segment_distance_t<float>(x, y, ax, ay, bx, by);
}

// Distance from point (x, y) to segment a-b, double precision.
double point_segment_distance_d(double x, double y, double ax, double ay, double bx, double by) {
    return point_segment_distance_t<double>(x, y, ax, ay, bx, by);
}

// Distance from point (x, y) to the box [x0,x1]x[y0,y1] (0 inside).
double point_box_distance(double x, double y, double x0, double y0, double x1, double y1) {
    const double dx = std::max({x0 - x, 0.0, x - x1}), dy = std::max({y0 - y, 0.0, y - y1});
    return std::sqrt(dx * dx + dy * dy);
}

// Distance between segment a-b and the box: 0 when they touch, else attained at a vertex of one of the two
// convex sets against the other (segment ends vs the box, box corners vs the segment).
double segment_box_distance(double ax, double ay, double bx, double by, double x0, double y0, double x1,
                            double y1) {
    if (segment_touches_box(static_cast<float>(ax), static_cast<float>(ay), static_cast<float>(bx),
                            static_cast<float>(by), static_cast<float>(x0), static_cast<float>(y0),
                            static_cast<float>(x1), static_cast<float>(y1))) {
        return 0.0;
    }
    double d = std::min(point_box_distance(ax, ay, x0, y0, x1, y1), point_box_distance(bx, by, x0, y0, x1, y1));
    d = std::min(d, point_segment_distance_d(x0, y0, ax, ay, bx, by));
    d = std::min(d, point_segment_distance_d(x1, y0, ax, ay, bx, by));
    d = std::min(d, point_segment_distance_d(x0, y1, ax, ay, bx, by));
    d = std::min(d, point_segment_distance_d(x1, y1, ax, ay, bx, by));
    return d;
}

// Clearance grid: at most this many cells per floor (bytes); larger floors get coarser clearance cells.
constexpr double kMaxClearanceCells = 4.0e6;

}  // namespace

WallIndex::WallIndex(const FloorGrid &grid, const float *segments, size_t wall_count, const float *boundary,
                     size_t boundary_count)
    : grid_(grid), wall_count_(wall_count) {
    if (!boundary) boundary_count = 0;
    const size_t count = wall_count + boundary_count;
    ax_.reserve(count);
    ay_.reserve(count);
    bx_.reserve(count);
    by_.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        const float *s = i < wall_count ? segments + 4 * i : boundary + 4 * (i - wall_count);
        ax_.push_back(s[0]);
        ay_.push_back(s[1]);
        bx_.push_back(s[2]);
        by_.push_back(s[3]);
    }
    const int64_t cells = grid_.cell_count();
    std::vector<std::vector<int32_t>> lists(static_cast<size_t>(cells));
    const float margin = 1e-4f;
    for (size_t s = 0; s < count; ++s) {
        const int32_t ix0 = grid_.clamp_ix(std::min(ax_[s], bx_[s]) - margin);
        const int32_t ix1 = grid_.clamp_ix(std::max(ax_[s], bx_[s]) + margin);
        const int32_t iy0 = grid_.clamp_iy(std::min(ay_[s], by_[s]) - margin);
        const int32_t iy1 = grid_.clamp_iy(std::max(ay_[s], by_[s]) + margin);
        for (int32_t iy = iy0; iy <= iy1; ++iy) {
            for (int32_t ix = ix0; ix <= ix1; ++ix) {
                const float cx0 = grid_.x0 + static_cast<float>(ix) * grid_.cell_m - margin;
                const float cy0 = grid_.y0 + static_cast<float>(iy) * grid_.cell_m - margin;
                if (segment_touches_box(ax_[s], ay_[s], bx_[s], by_[s], cx0, cy0, cx0 + grid_.cell_m + 2 * margin,
                                        cy0 + grid_.cell_m + 2 * margin)) {
                    lists[static_cast<size_t>(iy) * grid_.nx + ix].push_back(static_cast<int32_t>(s));
                }
            }
        }
    }
    cell_start_.assign(static_cast<size_t>(cells) + 1, 0);
    for (int64_t c = 0; c < cells; ++c) {
        cell_start_[c + 1] = cell_start_[c] + static_cast<int32_t>(lists[c].size());
    }
    cell_segments_.reserve(static_cast<size_t>(cell_start_.back()));
    for (const auto &l : lists) cell_segments_.insert(cell_segments_.end(), l.begin(), l.end());
    build_clearance();
}

void WallIndex::build_clearance() {
    clearance_ = WallClearanceGrid{};
    if (cell_segments_.empty()) return;
    WallClearanceGrid &g = clearance_;
    // Quarter of the index's cell (0.125 m by default), doubled until the grid is small enough.
    const double width = static_cast<double>(grid_.nx) * grid_.cell_m;
    const double height = static_cast<double>(grid_.ny) * grid_.cell_m;
    double cell = grid_.cell_m / 4.0;
    while ((width / cell) * (height / cell) > kMaxClearanceCells) cell *= 2.0;
    g.x0 = grid_.x0;
    g.y0 = grid_.y0;
    g.inv_cell = static_cast<float>(1.0 / cell);
    g.nx = std::max(1, static_cast<int32_t>(std::ceil(width / cell)));
    g.ny = std::max(1, static_cast<int32_t>(std::ceil(height / cell)));
    const double cap_m = 255.0 * g.unit_m;
    // Margin for float rounding: a point is binned with float arithmetic and may sit a few ulps outside its
    // cell's box (float inverse cell side: about 1e-7 of the extent), and the exact crossing test itself
    // rounds (about 1e-7 of the coordinates); both are far below 1 mm + 1e-6 of the coordinates and extent.
    const double gx0 = grid_.x0, gy0 = grid_.y0;
    const double magnitude = std::max({std::fabs(gx0), std::fabs(gy0), std::fabs(gx0 + width), std::fabs(gy0 + height)});
    const double margin_m = 1e-3 + 1e-6 * (magnitude + width + height);
    std::vector<double> dist(static_cast<size_t>(g.nx) * g.ny, cap_m + margin_m);
    // Per segment, every clearance cell within cap_m of its bounding box: min of the box-segment distances.
    for (size_t s = 0; s < ax_.size(); ++s) {
        const double ax = ax_[s], ay = ay_[s], bx = bx_[s], by = by_[s];
        const double reach = cap_m + margin_m + cell;
        const auto col = [&](double x) {
            return std::clamp(static_cast<int64_t>(std::floor((x - gx0) / cell)), int64_t{0}, int64_t{g.nx - 1});
        };
        const auto row = [&](double y) {
            return std::clamp(static_cast<int64_t>(std::floor((y - gy0) / cell)), int64_t{0}, int64_t{g.ny - 1});
        };
        const int64_t ix0 = col(std::min(ax, bx) - reach), ix1 = col(std::max(ax, bx) + reach);
        const int64_t iy0 = row(std::min(ay, by) - reach), iy1 = row(std::max(ay, by) + reach);
        for (int64_t iy = iy0; iy <= iy1; ++iy) {
            const double cy0 = gy0 + static_cast<double>(iy) * cell;
            for (int64_t ix = ix0; ix <= ix1; ++ix) {
                const double cx0 = gx0 + static_cast<double>(ix) * cell;
                double &d = dist[static_cast<size_t>(iy * g.nx + ix)];
                d = std::min(d, segment_box_distance(ax, ay, bx, by, cx0, cy0, cx0 + cell, cy0 + cell));
            }
        }
    }
    g.units.resize(dist.size() + 1);
    for (size_t c = 0; c < dist.size(); ++c) {
        const double units = std::floor((dist[c] - margin_m) / g.unit_m);
        g.units[c] = static_cast<uint8_t>(std::clamp(units, 0.0, 255.0));
    }
    g.units.back() = 0;  // sentinel
    g.sentinel = static_cast<int32_t>(dist.size());
}

bool WallIndex::cell_empty(float x, float y) const {
    if (cell_start_.empty()) return true;
    const int32_t c = grid_.clamp_iy(y) * grid_.nx + grid_.clamp_ix(x);
    return cell_start_[c] == cell_start_[c + 1];
}

bool WallIndex::test_cell(int32_t cell, float px, float py, float qx, float qy) const {
    const int32_t end = cell_start_[cell + 1];
    for (int32_t k = cell_start_[cell]; k < end; ++k) {
        const int32_t s = cell_segments_[k];
        if (segments_intersect(px, py, qx, qy, ax_[s], ay_[s], bx_[s], by_[s])) return true;
    }
    return false;
}

bool WallIndex::crosses_slow(float x0, float y0, float x1, float y1) const {
    if (x0 == x1 && y0 == y1) return false;
    {
        // Both ends in the same cell (which lists walls): test that cell only.
        const int32_t ax = grid_.clamp_ix(x0), ay = grid_.clamp_iy(y0);
        if (ax == grid_.clamp_ix(x1) && ay == grid_.clamp_iy(y1)) {
            return test_cell(ay * grid_.nx + ax, x0, y0, x1, y1);
        }
    }
    const int32_t ix0 = grid_.clamp_ix(std::min(x0, x1)), ix1 = grid_.clamp_ix(std::max(x0, x1));
    const int32_t iy0 = grid_.clamp_iy(std::min(y0, y1)), iy1 = grid_.clamp_iy(std::max(y0, y1));
    const int32_t span = (ix1 - ix0 + 1) * (iy1 - iy0 + 1);
    if (span <= 4) {
        // Short move (the usual per-frame step): the cells of its bounding box.
        for (int32_t iy = iy0; iy <= iy1; ++iy) {
            for (int32_t ix = ix0; ix <= ix1; ++ix) {
                const int32_t c = iy * grid_.nx + ix;
                if (cell_start_[c] != cell_start_[c + 1] && test_cell(c, x0, y0, x1, y1)) return true;
            }
        }
        return false;
    }
    // Long ray: walk the cells it passes through (Amanatides & Woo 1987 grid traversal), each cell
    // inflated by one neighbour column/row through the 3-cell cross test below to stay conservative at
    // corners where the ray passes exactly through a grid vertex.
    const float dx = x1 - x0, dy = y1 - y0;
    int32_t ix = grid_.clamp_ix(x0), iy = grid_.clamp_iy(y0);
    const int32_t ex = grid_.clamp_ix(x1), ey = grid_.clamp_iy(y1);
    const int32_t step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
    const float inf = 1e30f;
    const float cell = grid_.cell_m;
    const float next_x = grid_.x0 + static_cast<float>(ix + (step_x > 0 ? 1 : 0)) * cell;
    const float next_y = grid_.y0 + static_cast<float>(iy + (step_y > 0 ? 1 : 0)) * cell;
    float t_max_x = dx != 0 ? (next_x - x0) / dx : inf;
    float t_max_y = dy != 0 ? (next_y - y0) / dy : inf;
    const float t_delta_x = dx != 0 ? cell / std::fabs(dx) : inf;
    const float t_delta_y = dy != 0 ? cell / std::fabs(dy) : inf;
    const int32_t max_steps = grid_.nx + grid_.ny + 4;
    int32_t last_cell = -1;
    for (int32_t n = 0; n < max_steps; ++n) {
        const int32_t c = iy * grid_.nx + ix;
        if (c != last_cell && cell_start_[c] != cell_start_[c + 1] && test_cell(c, x0, y0, x1, y1)) return true;
        last_cell = c;
        if (ix == ex && iy == ey) break;
        if (t_max_x < t_max_y) {
            // Also look at the cell diagonally reached when both boundaries are crossed almost together.
            if (t_max_y - t_max_x < 1e-6f) {
                const int32_t iyn = std::clamp(iy + step_y, 0, grid_.ny - 1);
                const int32_t c2 = iyn * grid_.nx + ix;
                if (cell_start_[c2] != cell_start_[c2 + 1] && test_cell(c2, x0, y0, x1, y1)) return true;
            }
            t_max_x += t_delta_x;
            ix = std::clamp(ix + step_x, 0, grid_.nx - 1);
        } else {
            if (t_max_x - t_max_y < 1e-6f) {
                const int32_t ixn = std::clamp(ix + step_x, 0, grid_.nx - 1);
                const int32_t c2 = iy * grid_.nx + ixn;
                if (cell_start_[c2] != cell_start_[c2 + 1] && test_cell(c2, x0, y0, x1, y1)) return true;
            }
            t_max_y += t_delta_y;
            iy = std::clamp(iy + step_y, 0, grid_.ny - 1);
        }
    }
    return false;
}

bool WallIndex::segment_bounds(float &x0, float &y0, float &x1, float &y1) const {
    if (wall_count_ == 0) return false;
    x0 = y0 = 1e30f;
    x1 = y1 = -1e30f;
    for (size_t s = 0; s < wall_count_; ++s) {
        x0 = std::min({x0, ax_[s], bx_[s]});
        y0 = std::min({y0, ay_[s], by_[s]});
        x1 = std::max({x1, ax_[s], bx_[s]});
        y1 = std::max({y1, ay_[s], by_[s]});
    }
    return true;
}

float WallIndex::distance_to_nearest(float x, float y, float max_distance_m) const {
    float best = max_distance_m;
    if (cell_segments_.empty()) return best;
    const int32_t ix0 = grid_.clamp_ix(x - max_distance_m), ix1 = grid_.clamp_ix(x + max_distance_m);
    const int32_t iy0 = grid_.clamp_iy(y - max_distance_m), iy1 = grid_.clamp_iy(y + max_distance_m);
    for (int32_t iy = iy0; iy <= iy1; ++iy) {
        for (int32_t ix = ix0; ix <= ix1; ++ix) {
            const int32_t c = iy * grid_.nx + ix;
            for (int32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
                const auto s = static_cast<size_t>(cell_segments_[k]);
                if (s >= wall_count_) continue;  // a footprint boundary segment
                best = std::min(best, point_segment_distance(x, y, ax_[s], ay_[s], bx_[s], by_[s]));
            }
        }
    }
    return best;
}

}  // namespace wf::loc
