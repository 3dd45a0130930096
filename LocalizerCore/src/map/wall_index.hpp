// Spatial index of wall segments: a uniform grid whose cells list the segments touching them (CSR layout).
// Queries visit only the cells a move or ray passes through, so their cost does not grow with the number of
// walls; moves inside wall-free cells return after one lookup. Used for traversability (a particle cannot
// walk through a wall), visibility (no sign seen through a wall) and wall clearance of walkable cells.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "map/floor_grid.hpp"

namespace wf::loc {

class WallIndex {
public:
    WallIndex() = default;
    /// Builds the index over `grid` (meters) for `count` segments given as 4 floats each (ax, ay, bx, by).
    WallIndex(const FloorGrid &grid, const float *segments, size_t count);

    /// True when the segment (x0,y0)->(x1,y1) intersects or touches a wall. A zero-length move never crosses.
    /// Inline fast path: both ends in one cell that lists no wall (the usual per-frame step).
    inline bool crosses(float x0, float y0, float x1, float y1) const {
        if (cell_segments_.empty()) return false;
        const int32_t ax = grid_.clamp_ix(x0), ay = grid_.clamp_iy(y0);
        if (ax == grid_.clamp_ix(x1) && ay == grid_.clamp_iy(y1)) {
            const int32_t c = ay * grid_.nx + ax;
            if (cell_start_[c] == cell_start_[c + 1]) return false;
        }
        return crosses_slow(x0, y0, x1, y1);
    }

    /// Distance from (x, y) to the nearest wall if it is below `max_distance_m`, else max_distance_m.
    float distance_to_nearest(float x, float y, float max_distance_m) const;

    size_t segment_count() const { return ax_.size(); }
    const FloorGrid &grid() const { return grid_; }
    /// True when the cell containing (x, y) lists no segment (fast path of `crosses`).
    bool cell_empty(float x, float y) const;

private:
    bool crosses_slow(float x0, float y0, float x1, float y1) const;
    bool test_cell(int32_t cell, float px, float py, float qx, float qy) const;

    FloorGrid grid_;
    std::vector<float> ax_, ay_, bx_, by_;
    std::vector<int32_t> cell_start_;  // size cells + 1
    std::vector<int32_t> cell_segments_;
};

/// Segment-segment intersection (touching counts; collinear overlap does not). Exposed for tests.
bool segments_intersect(float px, float py, float qx, float qy, float ax, float ay, float bx, float by);

}  // namespace wf::loc
