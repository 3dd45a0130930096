// Rotational symmetries of a floor plan: rotations by a quarter, half or three-quarter turn about a point that
// map the walls onto themselves. In such a building a walk and its rotated twin (every position rotated about
// the point, every heading turned by the same angle) see the same walls and, where the signs are laid out
// symmetrically too, the same signs: VIO, planes and Exit sightings cannot tell them apart, and a particle
// filter keeps whichever twin Monte Carlo noise happened to favour (docs/localizer.md, "Symmetric twins").
// Mirror images (reflections) are not twins: a reflected walk turns left where the real one turns right, and
// VIO tells them apart by itself.
//
// Detection (written here: no library finds the self-similarities of a wall set): the fixed point of a rotation
// that maps a wall set onto itself is the centre of the set's bounding box (the box maps onto itself). Each wall
// is sampled every `sample_step_m`; a rotation is a symmetry when at least `min_matched_fraction` of the sampled
// wall length lands within `tolerance_m` of some wall (WallIndex::distance_to_nearest).
#pragma once

#include <cstdint>
#include <vector>

#include "map/wall_index.hpp"

namespace wf::loc {

/// One rotation of a floor onto itself: p' = c + R(angle) (p - c), heading' = heading + angle.
struct FloorSymmetry {
    /// Rotation angle, radians: pi / 2, pi or 3 pi / 2.
    float angle_rad = 0;
    /// Fixed point, meters, map frame.
    float cx = 0, cy = 0;
    /// cos and sin of angle_rad.
    float cos_a = 1, sin_a = 0;
    /// Share of the floor's wall length that the rotation lands on a wall (0..1).
    float matched_fraction = 0;

    /// Rotates a map point (meters) about the fixed point.
    void apply(float x, float y, float &out_x, float &out_y) const {
        const float dx = x - cx, dy = y - cy;
        out_x = cx + cos_a * dx - sin_a * dy;
        out_y = cy + sin_a * dx + cos_a * dy;
    }
    /// True for the half turn (its own inverse).
    bool is_half_turn() const { return sin_a * sin_a < 0.5f; }
};

/// Detection thresholds.
struct FloorSymmetryParams {
    /// Spacing of the wall samples, meters.
    float sample_step_m = 0.25f;
    /// A rotated sample within this distance of a wall is matched, meters.
    float tolerance_m = 0.2f;
    /// Share of the wall length that must match (0..1).
    float min_matched_fraction = 0.9f;
    /// Floors with less wall than this are not examined, meters (an empty or tiny plan is trivially symmetric).
    float min_wall_length_m = 20.0f;
};

/// The rotations (quarter, half, three-quarter turn about the walls' bounding-box centre) that map the floor's
/// walls onto themselves, in angle order; empty for an asymmetric floor.
std::vector<FloorSymmetry> find_floor_symmetries(const WallIndex &walls, const FloorSymmetryParams &params = {});

}  // namespace wf::loc
