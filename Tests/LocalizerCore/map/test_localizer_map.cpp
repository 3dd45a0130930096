// Tests for map/localizer_map.hpp: validation, visibility bits and walkable space.
#include <gtest/gtest.h>

#include <cmath>

#include "map/localizer_map.hpp"
#include "support/synthetic_world.hpp"

using namespace wf::loc;

namespace {
wf_localizer_options defaults() {
    wf_localizer_options o;
    wf_localizer_options_init(&o, WF_LOCALIZER_OPTIONS_VERSION);
    return o;
}
bool visible(const FloorData &f, float x, float y, size_t sign) {
    const uint64_t *v = f.visibility_at(x, y);
    return v && (v[sign / 64] >> (sign % 64)) & 1u;
}
}  // namespace

TEST(LocalizerMap, VisibilityBlockedByWallAndFacing) {
    wf::test::World w;
    wf::test::FloorSpec f;
    // Two rooms side by side sharing the wall x = 10 (no opening); a sign on the west room's west wall.
    f.box(0, 0, 20, 10).wall(10, 0, 10, 10).seed(5, 5).seed(15, 5);
    f.sign(wf::test::kExit, 0, 5, 1, 0);                       // 0: faces east, into the west room
    f.sign(wf::test::kExit, 5, 10, 0, -1, /*double_sided=*/true);  // 1: double-sided on the north wall
    w.floors.push_back(f);
    LocalizerMap m;
    std::string err;
    ASSERT_EQ(build_localizer_map(w.map(), defaults(), m, err), WF_LOC_OK) << err;
    const FloorData &fd = m.floors[0];
    EXPECT_TRUE(visible(fd, 5, 5, 0));
    EXPECT_FALSE(visible(fd, 12, 5, 0));    // 12 m away would still be in range... but behind the wall
    EXPECT_FALSE(visible(fd, -1, 5, 0));    // behind the sign (outside the building)
    EXPECT_TRUE(visible(fd, 9.5f, 1, 0));
    EXPECT_TRUE(visible(fd, 5, 5, 1));
    EXPECT_FALSE(visible(fd, 15, 5, 1));    // other room
}

// A sign is not predicted visible from where it would be seen more obliquely than
// max_view_angle_from_normal_rad (default 80 degrees): its face is a sliver there.
TEST(LocalizerMap, VisibilityViewAngleLimit) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 20, 10).wall(10, 0, 10, 10).seed(5, 5).seed(15, 5);
    f.sign(wf::test::kExit, 0, 5, 1, 0);                           // 0: faces east
    f.sign(wf::test::kExit, 5, 10, 0, -1, /*double_sided=*/true);  // 1: double-sided on the north wall
    w.floors.push_back(f);
    for (const double limit_deg : {80.0, 90.0}) {
        auto o = defaults();
        if (limit_deg == 90.0) o.max_view_angle_from_normal_rad = wf::test::kPi / 2;
        LocalizerMap m;
        std::string err;
        ASSERT_EQ(build_localizer_map(w.map(), o, m, err), WF_LOC_OK) << err;
        const FloorData &fd = m.floors[0];
        EXPECT_TRUE(visible(fd, 9.5f, 1, 0)) << limit_deg;   // 23 degrees off the normal
        EXPECT_TRUE(visible(fd, 1, 9.5f, 0)) << limit_deg;   // about 76 degrees
        EXPECT_EQ(visible(fd, 0.5f, 9.5f, 0), limit_deg == 90.0) << limit_deg;  // about 82 degrees
        EXPECT_TRUE(visible(fd, 5, 5, 1)) << limit_deg;
        EXPECT_EQ(visible(fd, 9.5f, 9.5f, 1), limit_deg == 90.0) << limit_deg;  // about 85 degrees
    }
}

TEST(LocalizerMap, VisibilityRangeLimit) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 40, 2).seed(1, 1).sign(wf::test::kExit, 0, 1, 1, 0);
    w.floors.push_back(f);
    auto o = defaults();
    o.max_sign_range_m = 12;
    LocalizerMap m;
    std::string err;
    ASSERT_EQ(build_localizer_map(w.map(), o, m, err), WF_LOC_OK);
    EXPECT_TRUE(visible(m.floors[0], 11.5f, 1, 0));
    EXPECT_FALSE(visible(m.floors[0], 12.6f, 1, 0));
}

// A sign's own limits (its kind's, from the map's catalogue) cap the options': a room-number placard read
// from at most 2.5 m and 50 degrees off its normal, beside an Exit sign with none of its own.
TEST(LocalizerMap, PerSignRangeAndViewAngleLimits) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 40, 6).seed(1, 3);
    f.sign(wf::test::kExit, 0, 3, 1, 0);   // 0: Exit sign, options' limits (12 m, 80 degrees)
    f.signs.push_back({wf::test::kExit, 0, 1, 1, 0, false, 2.5f, static_cast<float>(50 * wf::test::kPi / 180)});  // 1
    w.floors.push_back(f);
    auto o = defaults();
    o.max_sign_range_m = 12;
    LocalizerMap m;
    std::string err;
    ASSERT_EQ(build_localizer_map(w.map(), o, m, err), WF_LOC_OK) << err;
    const FloorData &fd = m.floors[0];
    EXPECT_TRUE(visible(fd, 2, 1, 1));      // 2 m, square on
    EXPECT_FALSE(visible(fd, 3, 1, 1));     // 3 m: beyond the placard's 2.5 m
    EXPECT_TRUE(visible(fd, 3, 1, 0));      // the Exit sign is
    EXPECT_TRUE(visible(fd, 1.2f, 2.2f, 1));   // 45 degrees off the normal, 1.7 m
    EXPECT_FALSE(visible(fd, 0.8f, 2.6f, 1));  // 63 degrees
    EXPECT_TRUE(visible(fd, 0.8f, 4.6f, 0));   // 63 degrees: within the Exit sign's 80
    EXPECT_TRUE(visible(fd, 11.5f, 3, 0));
    // A negative or non-finite limit is refused with the sign named.
    w.floors[0].signs[1].max_range_m = -1;
    EXPECT_EQ(build_localizer_map(w.map(), o, m, err), WF_LOC_ERR_INVALID_MAP);
    EXPECT_NE(err.find("sign 1"), std::string::npos) << err;
}

TEST(LocalizerMap, WalkableFloodFillStaysInsideAndKeepsClearance) {
    wf::test::World w;
    wf::test::FloorSpec f;
    // A room with a closed closet (not reachable from the seed).
    f.box(0, 0, 10, 10).box(2, 2, 4, 4).seed(8, 8);
    w.floors.push_back(f);
    LocalizerMap m;
    std::string err;
    ASSERT_EQ(build_localizer_map(w.map(), defaults(), m, err), WF_LOC_OK);
    const FloorData &fd = m.floors[0];
    EXPECT_TRUE(fd.is_walkable(8, 8));
    EXPECT_TRUE(fd.is_walkable(1, 1));
    EXPECT_FALSE(fd.is_walkable(3, 3));     // closet: walls all around
    EXPECT_FALSE(fd.is_walkable(-1, 5));    // outside the building
    EXPECT_FALSE(fd.is_walkable(11, 5));
    EXPECT_FALSE(fd.is_walkable(5, 0.1f));  // within 0.2 m of the wall
    // Area: 100 m^2 minus the 4 m^2 closet minus the clearance bands (~0.25 m grid): 75..96 m^2.
    const double area = fd.walkable_cells.size() * fd.grid.cell_m * fd.grid.cell_m;
    EXPECT_GT(area, 75);
    EXPECT_LT(area, 96);
}

TEST(LocalizerMap, RejectsBadMaps) {
    LocalizerMap m;
    std::string err;
    {
        wf::test::World w;
        wf::test::FloorSpec f;
        f.wall(0, 0, NAN, 1);
        w.floors.push_back(f);
        EXPECT_EQ(build_localizer_map(w.map(), defaults(), m, err), WF_LOC_ERR_INVALID_MAP);
        EXPECT_NE(err.find("floor 0"), std::string::npos) << err;
        EXPECT_NE(err.find("wall 0"), std::string::npos) << err;
    }
    {
        wf::test::World w;
        wf::test::FloorSpec f;
        f.sign(7, 0, 0, 1, 0);
        w.floors.push_back(f);
        EXPECT_EQ(build_localizer_map(w.map(), defaults(), m, err), WF_LOC_ERR_INVALID_MAP);
        EXPECT_NE(err.find("kind 7"), std::string::npos) << err;
    }
    {
        wf::test::World w;
        wf_localizer_map cm = w.map();
        EXPECT_EQ(build_localizer_map(cm, defaults(), m, err), WF_LOC_ERR_INVALID_MAP);  // no floors
        cm.version = 99;
        EXPECT_EQ(build_localizer_map(cm, defaults(), m, err), WF_LOC_ERR_VERSION);
    }
}

TEST(LocalizerMap, EmptyFloorBuildsWithoutWalkableSpaceIssues) {
    wf::test::World w;
    w.floors.emplace_back();  // nothing at all: a small grid, every cell "walkable" (no seed, no wall)
    wf::test::FloorSpec g;
    g.wall(3, 3, 3, 3);       // zero-length wall only, seed on top of it
    g.seed(3, 3);
    w.floors.push_back(g);
    LocalizerMap m;
    std::string err;
    ASSERT_EQ(build_localizer_map(w.map(), defaults(), m, err), WF_LOC_OK) << err;
    EXPECT_EQ(m.floors[0].words_per_cell, 0);
    EXPECT_EQ(m.floors[0].visibility_at(0, 0), nullptr);
    EXPECT_TRUE(std::isinf(m.floors[0].distance_to_link(0, 0)));
}
