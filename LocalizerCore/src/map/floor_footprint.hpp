// The footprint of a floor: where the traveler can be at all. Walls alone leave the outside of the building
// open wherever the map has an entrance without a door segment, and a particle that walks out through it
// finds no wall and no sign to refute it for as long as it stays out there (docs/localizer.md, "Map
// precomputation", Footprint).
//
// The footprint is the convex hull of the floor's walls, signs and navigation-graph nodes, grown by a
// margin: a polygon that every indoor position lies inside (convex, so the straight line between two indoor
// points never leaves it). Its edges go into the floor's wall index as boundary segments: a move across one
// is a wall crossing (vio_motion_model), the walkable flood fill stops at them, and the clearance grid counts
// them; the plane model's wall field, the symmetry search and wall distances see the walls only.
//
// Written here (Andrew's monotone chain, Andrew 1979, on the points grown into octagons): the hull of a few
// thousand points is a few lines, and no library in the build (Eigen) offers one.
#pragma once

#include <cstddef>
#include <vector>

namespace wf::loc {

/// Boundary segments (4 floats each: ax, ay, bx, by, meters, map frame, counter-clockwise) of the convex hull
/// of `wall_count` wall segments (4 floats each) and `point_count` points (2 floats each), every input point
/// grown into an octagon that contains the disc of radius `margin_m` around it. Non-finite coordinates are
/// skipped. Empty (no boundary) without walls, or when `margin_m` is not positive and finite.
std::vector<float> floor_footprint_boundary(const float *walls, size_t wall_count, const float *points,
                                            size_t point_count, float margin_m);

}  // namespace wf::loc
