// Tests for map/wall_index.hpp: exact crossing tests and agreement with a brute-force check.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "map/wall_index.hpp"
#include "support/synthetic_world.hpp"

using wf::loc::FloorGrid;
using wf::loc::WallIndex;

namespace {
std::vector<float> flatten(const std::vector<std::array<float, 4>> &walls) {
    std::vector<float> v;
    for (const auto &w : walls) v.insert(v.end(), w.begin(), w.end());
    return v;
}
/// `count` random walls in a 40 m square, each up to 4 m long in x and y (draws from `gen`, in order).
std::vector<std::array<float, 4>> random_maze(std::mt19937& gen, int count) {
    std::uniform_real_distribution<float> u(0, 40);
    std::vector<std::array<float, 4>> walls;
    for (int i = 0; i < count; ++i) {
        const float x = u(gen), y = u(gen);
        walls.push_back({x, y, x + (u(gen) - 20) / 5, y + (u(gen) - 20) / 5});
    }
    return walls;
}
}  // namespace

TEST(WallIndex, MoveThroughWallCrossesMoveInCorridorDoesNot) {
    const auto world = wf::test::corridor_world();
    const auto flat = flatten(world.floors[0].walls);
    // Grid origin at -2.5 so that the cells around y = 1 ([0.5, 1.5)) touch neither long wall.
    const WallIndex idx(FloorGrid(-2.5f, -2.5f, 22, 4, 1.0f), flat.data(), world.floors[0].walls.size());
    EXPECT_TRUE(idx.crosses(5, 1.9f, 5, 2.1f));    // through the north wall
    EXPECT_TRUE(idx.crosses(19.9f, 1, 20.2f, 1));  // through the east end wall
    EXPECT_FALSE(idx.crosses(5, 1, 5.1f, 1.05f));  // along the corridor
    EXPECT_FALSE(idx.crosses(1, 1, 19, 1.5f));     // long move inside
    EXPECT_FALSE(idx.crosses(5, 1, 5, 1));         // zero-length
    EXPECT_FALSE(idx.crosses(5, 3, 15, 3.5f));     // outside, parallel
    EXPECT_TRUE(idx.cell_empty(10.5f, 1.0f));      // interior cell, fast path
    EXPECT_FALSE(idx.cell_empty(10.5f, 2.0f));
}

TEST(WallIndex, SegmentsIntersectCases) {
    using wf::loc::segments_intersect;
    EXPECT_TRUE(segments_intersect(0, -1, 0, 1, -1, 0, 1, 0));    // X
    EXPECT_FALSE(segments_intersect(0, 0.1f, 0, 1, -1, 0, 1, 0)); // above
    EXPECT_TRUE(segments_intersect(0, 0, 0, 1, -1, 0, 1, 0));     // touching at an end counts
    EXPECT_FALSE(segments_intersect(-2, 0, -1.5f, 0, -1, 0, 1, 0));  // collinear, disjoint
    EXPECT_FALSE(segments_intersect(0, -1, 0, 1, 2, 2, 2, 2));    // zero-length wall never blocks
}

// Random rays and moves against a random maze: the grid query must agree with testing every wall.
TEST(WallIndex, AgreesWithBruteForce) {
    std::mt19937 gen(11);
    std::uniform_real_distribution<float> u(0, 40);
    const std::vector<std::array<float, 4>> walls = random_maze(gen, 150);
    const auto flat = flatten(walls);
    for (float cell : {0.5f, 1.0f, 3.0f}) {
        const WallIndex idx(FloorGrid(-5, -5, 45, 45, cell), flat.data(), walls.size());
        int mismatches = 0;
        for (int k = 0; k < 5000; ++k) {
            const float x0 = u(gen), y0 = u(gen);
            const float len = k % 2 ? 0.3f : 15.0f;
            const float x1 = x0 + len * (u(gen) - 20) / 20, y1 = y0 + len * (u(gen) - 20) / 20;
            mismatches += idx.crosses(x0, y0, x1, y1) != wf::test::brute_crosses(walls, x0, y0, x1, y1);
        }
        EXPECT_EQ(mismatches, 0) << "cell " << cell;
    }
}

TEST(WallIndex, DistanceToNearest) {
    const auto world = wf::test::corridor_world();
    const auto flat = flatten(world.floors[0].walls);
    const WallIndex idx(FloorGrid(-2, -2, 22, 4, 1.0f), flat.data(), world.floors[0].walls.size());
    EXPECT_NEAR(idx.distance_to_nearest(5, 1, 5), 1.0f, 1e-6f);
    EXPECT_NEAR(idx.distance_to_nearest(5, 0.15f, 5), 0.15f, 1e-6f);
    EXPECT_NEAR(idx.distance_to_nearest(5, 1, 0.5f), 0.5f, 1e-6f);  // capped
}

// The clearance grid (fast path of crosses) must be conservative: at random points, the clearance of the
// point's cell is at most the true distance to the nearest wall, a move shorter than it never crosses a
// wall (brute force), and points outside the grid or non-finite get no clearance.
TEST(WallIndex, ClearanceGridIsConservative) {
    std::mt19937 gen(5);
    std::uniform_real_distribution<float> u(0, 40);
    std::vector<std::array<float, 4>> walls = random_maze(gen, 120);
    walls.push_back({10, 10, 10, 10});  // a zero-length wall
    const auto flat = flatten(walls);
    for (float cell : {0.5f, 1.0f}) {
        const WallIndex idx(FloorGrid(-5, -5, 45, 45, cell), flat.data(), walls.size());
        const wf::loc::WallClearanceGrid &g = idx.clearance();
        ASSERT_FALSE(g.units.empty());
        int clear_moves = 0;
        for (int k = 0; k < 20000; ++k) {
            const float x = u(gen), y = u(gen);
            const float cl = g.clearance_m(g.cell(x, y));
            double nearest = 1e9;
            for (const auto &w : walls) {
                const double ex = w[2] - w[0], ey = w[3] - w[1], len2 = ex * ex + ey * ey;
                const double t = len2 > 0 ? std::clamp(((x - w[0]) * ex + (y - w[1]) * ey) / len2, 0.0, 1.0) : 0.0;
                nearest = std::min(nearest, std::hypot(w[0] + t * ex - x, w[1] + t * ey - y));
            }
            ASSERT_LE(cl, nearest) << x << ", " << y;
            // A move just shorter than the clearance, in a random direction.
            const float a = u(gen) * 0.157f, len = 0.999f * cl;
            const float x1 = x + len * std::cos(a), y1 = y + len * std::sin(a);
            if (g.move_is_clear(x, y, (x1 - x) * (x1 - x) + (y1 - y) * (y1 - y))) {
                ++clear_moves;
                ASSERT_FALSE(wf::test::brute_crosses(walls, x, y, x1, y1)) << x << ", " << y;
            }
        }
        EXPECT_GT(clear_moves, 10000) << "cell " << cell;  // the fast path is taken for most points
        EXPECT_EQ(g.clearance_m(g.cell(-100, 3)), 0.0f);
        EXPECT_EQ(g.clearance_m(g.cell(3, 1e9f)), 0.0f);
        EXPECT_EQ(g.clearance_m(g.cell(std::nanf(""), 3)), 0.0f);
    }
}
