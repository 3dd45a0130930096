// Tests for map/floor_footprint.hpp and its use in the floor's wall index (map/localizer_map): the hull grown by
// the margin, and a building whose entrance has no door segment no longer lets moves or walkable space out.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "map/floor_footprint.hpp"
#include "map/localizer_map.hpp"
#include "map/wall_index.hpp"
#include "support/synthetic_world.hpp"

using namespace wf::loc;

namespace {

/// True when (x, y) lies inside or on the counter-clockwise polygon given as boundary segments.
bool inside(const std::vector<float> &b, float x, float y) {
    for (size_t s = 0; s + 3 < b.size(); s += 4) {
        const float cross = (b[s + 2] - b[s]) * (y - b[s + 1]) - (b[s + 3] - b[s + 1]) * (x - b[s]);
        if (cross < -1e-4f) return false;
    }
    return true;
}

/// Distance from (x, y) to the nearest boundary segment, up to 5 m: the boundary indexed as walls of a WallIndex.
float distance_to_boundary(const std::vector<float> &b, float x, float y) {
    const WallIndex index(FloorGrid(-10, -10, 40, 30, 0.5f), b.data(), b.size() / 4);
    return index.distance_to_nearest(x, y, 5.0f);
}

wf_localizer_options defaults() {
    wf_localizer_options o;
    wf_localizer_options_init(&o, WF_LOCALIZER_OPTIONS_VERSION);
    return o;
}

}  // namespace

TEST(FloorFootprint, HullOfTheWallsGrownByTheMargin) {
    // An L of walls (two sides of a 20 m x 10 m box): the hull is a triangle, grown by 1 m.
    const std::vector<float> walls = {0, 0, 20, 0, 0, 0, 0, 10};
    const std::vector<float> b = floor_footprint_boundary(walls.data(), 2, nullptr, 0, 1.0f);
    ASSERT_GE(b.size(), 4u * 3);
    // Every wall end point lies inside, at least the margin from the boundary and within the octagon's reach
    // (1 / cos(pi / 8) = 1.082 m).
    for (size_t k = 0; k + 1 < walls.size(); k += 2) {
        EXPECT_TRUE(inside(b, walls[k], walls[k + 1]));
        const float d = distance_to_boundary(b, walls[k], walls[k + 1]);
        EXPECT_GE(d, 1.0f - 1e-4f) << k;
        EXPECT_LE(d, 1.0825f) << k;
    }
    EXPECT_TRUE(inside(b, 5, 2));       // inside the L's hull
    EXPECT_TRUE(inside(b, -0.9f, 5));   // within the margin, outside the walls
    EXPECT_FALSE(inside(b, -1.2f, 5));  // beyond the margin
    EXPECT_FALSE(inside(b, 15, 8));     // beyond the hull's diagonal edge (20, 0) - (0, 10), grown by 1 m
}

TEST(FloorFootprint, GraphNodesAndSignsWidenTheHull) {
    const std::vector<float> walls = {0, 0, 10, 0, 10, 0, 10, 10};
    const std::vector<float> points = {-5, 5, std::numeric_limits<float>::quiet_NaN(), 0};
    const std::vector<float> b = floor_footprint_boundary(walls.data(), 2, points.data(), 2, 1.0f);
    EXPECT_TRUE(inside(b, -5.9f, 5));  // the node at (-5, 5) and its margin
    EXPECT_FALSE(inside(b, -6.5f, 5));
    for (float v : b) EXPECT_TRUE(std::isfinite(v));  // the NaN point is skipped
}

TEST(FloorFootprint, NoBoundaryWithoutWallsOrMargin) {
    const std::vector<float> walls = {0, 0, 10, 0};
    const std::vector<float> points = {5, 5};
    EXPECT_TRUE(floor_footprint_boundary(walls.data(), 0, points.data(), 1, 1.0f).empty());
    EXPECT_TRUE(floor_footprint_boundary(walls.data(), 1, points.data(), 1, 0.0f).empty());
    EXPECT_TRUE(floor_footprint_boundary(walls.data(), 1, points.data(), 1, std::nanf("")).empty());
    // One wall: the grown hull is a proper polygon around it.
    const std::vector<float> b = floor_footprint_boundary(walls.data(), 1, nullptr, 0, 0.5f);
    EXPECT_GE(b.size(), 4u * 3);
    EXPECT_TRUE(inside(b, 5, 0.4f));
    EXPECT_FALSE(inside(b, 5, 0.7f));
}

// A 20 m x 10 m building whose west entrance (y in [4, 6]) has no door segment: a traveler stepping into the
// doorway is inside the footprint, one walking 3 m out is not.
TEST(FloorFootprint, TheFloorsWallIndexStopsMovesOutOfTheBuilding) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.wall(0, 0, 20, 0).wall(20, 0, 20, 10).wall(20, 10, 0, 10).wall(0, 10, 0, 6).wall(0, 4, 0, 0).seed(5, 5);
    w.floors.push_back(f);
    LocalizerMap m;
    std::string err;
    ASSERT_EQ(build_localizer_map(w.map(), defaults(), m, err), WF_LOC_OK) << err;
    const FloorData &fd = m.floors[0];
    EXPECT_EQ(fd.walls.segment_count(), 5u);  // the walls; the boundary is apart
    EXPECT_GE(fd.walls.boundary_count(), 4u);
    EXPECT_FALSE(fd.walls.crosses(5, 5, -0.5f, 5));  // into the doorway and just out
    EXPECT_TRUE(fd.walls.crosses(5, 5, -3.0f, 5));   // out of the building: across the footprint
    EXPECT_TRUE(fd.walls.crosses(-0.5f, 5, -1.5f, 5));
    // The walkable space (floor-only starts and recovery draw from it) stops at the footprint too.
    EXPECT_TRUE(fd.is_walkable(-0.5f, 5));
    EXPECT_FALSE(fd.is_walkable(-1.6f, 5));
    EXPECT_FALSE(fd.is_walkable(-1.6f, 1));
    // Wall distances see the walls only: the nearest wall end is 1.35 m away, the boundary about 0.1 m.
    EXPECT_NEAR(fd.walls.distance_to_nearest(-0.9f, 5, 5.0f), std::hypot(0.9f, 1.0f), 1e-4f);
    float x0, y0, x1, y1;
    ASSERT_TRUE(fd.walls.segment_bounds(x0, y0, x1, y1));
    EXPECT_EQ(x0, 0.0f);
    EXPECT_EQ(x1, 20.0f);
}
