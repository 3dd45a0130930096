// The filter's copy of the building, one FloorData per floor, with the precomputed structures the
// per-particle loops need:
//  - a wall index (uniform grid of segment lists) for traversability and ray casting;
//  - a walkable mask on a fine grid: cells reachable from the navigation-graph seeds by a flood fill that
//    never crosses a wall, and at least `wall_clearance_m` from every wall (floor-only initialisation and
//    recovery draw particles from it);
//  - a visibility bitset on the same grid: bit j of a cell says sign j is within the maximum range, faces the
//    cell, and no wall lies between the cell centre and the sign (ray cast against the wall index). This is
//    the "per-pixel sign visibility" of the reference app (iNavigate AnnotatedMap), one bit per sign per cell.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "map/floor_grid.hpp"
#include "map/floor_symmetry.hpp"
#include "map/wall_index.hpp"
#include "wf_localizer.h"

namespace wf::loc {

/// Signs of one floor, structure of arrays; index j is the sign's bit in the visibility words.
struct SignTable {
    std::vector<int32_t> kind;
    std::vector<float> x, y, facing_x, facing_y;
    std::vector<uint8_t> double_sided;
    /// Per sign, its own recognition limits from the map (wf_localizer_sign): farthest range, meters, and largest
    /// view angle from the face normal, radians; 0 = none, the options' limits apply. One entry per sign, like
    /// the other columns. compute_visibility uses the smaller of the sign's and the options'.
    std::vector<float> own_max_range_m, own_max_view_angle_rad;
    size_t size() const { return kind.size(); }
};

struct FloorData {
    double elevation_m = 0;
    FloorGrid grid;  // fine grid for walkable + visibility
    WallIndex walls;
    SignTable signs;
    /// 64-bit words of visibility bits per cell (0 when the floor has no sign).
    int32_t words_per_cell = 0;
    std::vector<uint64_t> visibility;  // cell * words_per_cell + word
    /// For each kind id: the bits of the signs of that kind (kind * words_per_cell + word).
    std::vector<uint64_t> kind_masks;
    std::vector<uint8_t> walkable;         // per cell
    std::vector<int32_t> walkable_cells;   // indices of walkable cells
    std::vector<float> link_x, link_y;     // vertical-link points
    /// Rotations that map the floor's walls onto themselves (map/floor_symmetry): the twins the filter must
    /// keep alive until the evidence tells them apart (pf/twin_guard).
    std::vector<FloorSymmetry> symmetries;

    /// Visibility words of the cell containing (x, y), or nullptr outside the grid / no signs.
    inline const uint64_t *visibility_at(float x, float y) const {
        if (words_per_cell == 0) return nullptr;
        const int32_t c = grid.index(x, y);
        return c < 0 ? nullptr : &visibility[static_cast<size_t>(c) * words_per_cell];
    }
    bool is_walkable(float x, float y) const {
        const int32_t c = grid.index(x, y);
        return c >= 0 && walkable[c] != 0;
    }
    /// Index of the vertical link point nearest (x, y), or -1 when the floor has none; its distance in meters in
    /// `*distance_m` when given (infinity when there is none).
    int32_t nearest_link(float x, float y, float *distance_m = nullptr) const;
    /// Distance to the nearest vertical link point, meters (infinity when there is none).
    float distance_to_link(float x, float y) const;
};

struct LocalizerMap {
    std::vector<FloorData> floors;
    int32_t kind_count = 0;
};

/// Validates and copies `map`, precomputing the grids with `opts`. Returns a wf_localizer_status and, on
/// failure, a message naming the floor and the problem in `error`.
int build_localizer_map(const wf_localizer_map &map, const wf_localizer_options &opts, LocalizerMap &out,
                        std::string &error);

/// Recomputes the visibility bits of one floor for the given range and view angle, each capped per sign by
/// the sign's own limits (SignTable::own_*) (used by build and by tests).
void compute_visibility(FloorData &floor, float max_range_m, float max_view_angle_from_normal_rad);

}  // namespace wf::loc
