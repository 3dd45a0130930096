// Spatial index of wall segments: a uniform grid whose cells list the segments touching them (CSR layout).
// Queries visit only the cells a move or ray passes through, so their cost does not grow with the number of
// walls. A finer clearance grid (a conservative distance transform: for each cell, a lower bound on the
// distance from any point of the cell to the nearest wall) lets a short move far enough from every wall
// return after one byte lookup, without visiting the segment lists. Used for traversability (a particle
// cannot walk through a wall), visibility (no sign seen through a wall) and wall clearance of walkable cells.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "map/floor_grid.hpp"

namespace wf::loc {

/// Conservative wall clearance on a uniform grid (a distance transform with cells as units): byte q of a
/// cell means that every point of the cell is at least q * unit_m meters from every wall segment (rounded
/// down, minus a float-rounding margin; capped at 255 units). Cell `sentinel` (outside the grid, or a
/// non-finite point) has clearance 0. A move from (x, y) of length L with L < clearance_m(cell(x, y))
/// cannot touch a wall, so WallIndex::crosses would return false for it. Built per wall segment over the
/// cells within the cap: the exact distance between the segment and the cell's box (0 when they touch, else
/// the smallest of segment-end-to-box and box-corner-to-segment distances, where the minimum distance
/// between two disjoint convex polygons is attained).
struct WallClearanceGrid {
    /// South-west corner (m), inverse cell side (1/m), size in cells.
    float x0 = 0, y0 = 0, inv_cell = 1;
    int32_t nx = 0, ny = 0;
    /// Meters per clearance unit (5 mm).
    float unit_m = 0.005f;
    /// cell_count() + 1 bytes; the last is the sentinel (0).
    std::vector<uint8_t> units;
    /// Index of the sentinel byte (cell_count()).
    int32_t sentinel = 0;

    /// Cell index of (x, y), or `sentinel` outside the grid / non-finite. Branch-free (vectorisable).
    inline int32_t cell(float x, float y) const {
        const float fx = (x - x0) * inv_cell, fy = (y - y0) * inv_cell;
        // The comparisons also reject NaN; the selects keep the int conversion in range (no UB).
        const bool in = (fx >= 0.0f) & (fy >= 0.0f) & (fx < static_cast<float>(nx)) & (fy < static_cast<float>(ny));
        const float cx = in ? fx : 0.0f, cy = in ? fy : 0.0f;
        const int32_t c = static_cast<int32_t>(cy) * nx + static_cast<int32_t>(cx);
        return in ? c : sentinel;
    }
    /// Guaranteed clearance of cell `c`, meters (0 for the sentinel or an empty grid).
    inline float clearance_m(int32_t c) const { return static_cast<float>(units[static_cast<size_t>(c)]) * unit_m; }
    /// True when a move from (x, y) whose squared length is `move_len2_m2` (m^2) certainly crosses no wall.
    inline bool move_is_clear(float x, float y, float move_len2_m2) const {
        if (units.empty()) return false;
        const float cl = clearance_m(cell(x, y));
        return move_len2_m2 < cl * cl;
    }
};

class WallIndex {
public:
    WallIndex() = default;
    /// Builds the index over `grid` (meters) for `count` segments given as 4 floats each (ax, ay, bx, by), and
    /// `boundary_count` boundary segments (the floor's footprint, map/floor_footprint) in the same layout: they
    /// block moves (`crosses`) and count in the clearance grid like walls, but `segment_count`, `segment`,
    /// `segment_bounds` and `distance_to_nearest` see the walls only.
    WallIndex(const FloorGrid &grid, const float *segments, size_t count, const float *boundary = nullptr,
              size_t boundary_count = 0);

    /// True when the segment (x0,y0)->(x1,y1) intersects or touches a wall. A zero-length move never crosses.
    /// Inline fast paths: the move is shorter than the clearance of its start cell (one byte lookup), or both
    /// ends lie in one wall-index cell that lists no wall.
    inline bool crosses(float x0, float y0, float x1, float y1) const {
        if (cell_segments_.empty()) return false;
        const float dx = x1 - x0, dy = y1 - y0;
        if (clearance_.move_is_clear(x0, y0, dx * dx + dy * dy)) return false;
        return crosses_grid(x0, y0, x1, y1);
    }
    /// `crosses` without the clearance fast path, for callers that already tested the clearance.
    inline bool crosses_grid(float x0, float y0, float x1, float y1) const {
        if (cell_segments_.empty()) return false;
        const int32_t ax = grid_.clamp_ix(x0), ay = grid_.clamp_iy(y0);
        if (ax == grid_.clamp_ix(x1) && ay == grid_.clamp_iy(y1)) {
            const int32_t c = ay * grid_.nx + ax;
            if (cell_start_[c] == cell_start_[c + 1]) return false;
        }
        return crosses_slow(x0, y0, x1, y1);
    }

    /// Distance from (x, y) to the nearest wall (not boundary) if it is below `max_distance_m`, else
    /// max_distance_m.
    float distance_to_nearest(float x, float y, float max_distance_m) const;

    /// Number of walls (boundary segments not counted).
    size_t segment_count() const { return wall_count_; }
    /// Number of footprint boundary segments.
    size_t boundary_count() const { return ax_.size() - wall_count_; }
    /// End points of segment i (meters, map frame), i < segment_count() (used by the plane model's wall field).
    void segment(size_t i, float &ax, float &ay, float &bx, float &by) const {
        ax = ax_[i]; ay = ay_[i]; bx = bx_[i]; by = by_[i];
    }
    /// Bounding box of the segments' end points, meters, map frame; false (outputs untouched) without segments.
    bool segment_bounds(float &x0, float &y0, float &x1, float &y1) const;
    const FloorGrid &grid() const { return grid_; }
    /// True when the cell containing (x, y) lists no segment (fast path of `crosses`).
    bool cell_empty(float x, float y) const;
    /// Clearance grid (cells of a quarter of the index's cell, coarser for very large floors); empty
    /// (`units` empty) when there is no wall.
    const WallClearanceGrid &clearance() const { return clearance_; }

private:
    bool crosses_slow(float x0, float y0, float x1, float y1) const;
    bool test_cell(int32_t cell, float px, float py, float qx, float qy) const;
    void build_clearance();

    FloorGrid grid_;
    std::vector<float> ax_, ay_, bx_, by_;  // walls, then boundary segments
    size_t wall_count_ = 0;
    std::vector<int32_t> cell_start_;  // size cells + 1
    std::vector<int32_t> cell_segments_;
    WallClearanceGrid clearance_;
};

/// Segment-segment intersection (touching counts; collinear overlap does not). Exposed for tests.
bool segments_intersect(float px, float py, float qx, float qy, float ax, float ay, float bx, float by);

}  // namespace wf::loc
