// Tests for map/floor_symmetry.hpp: which rotations map a floor's walls onto themselves.
#include <gtest/gtest.h>

#include <cmath>

#include "map/localizer_map.hpp"
#include "support/filter_fixtures.hpp"

using namespace wf::loc;

namespace {
std::vector<FloorSymmetry> symmetries_of(wf::test::FloorSpec f) {
    wf::test::World w;
    w.floors.push_back(f);
    const LocalizerMap m = wf::test::build_map(w, wf::test::default_options());
    return m.floors.empty() ? std::vector<FloorSymmetry>{} : m.floors[0].symmetries;
}
}  // namespace

// An office like the bundled one: a 40 x 24 m box, two corridors, rooms whose doors sit point-symmetrically.
// The half turn about the box's centre maps it onto itself; a quarter turn cannot (the box is not square).
TEST(FloorSymmetry, HalfTurnOfAPointSymmetricOffice) {
    wf::test::FloorSpec f;
    f.box(0, 0, 40, 24);
    f.wall(0, 6, 7.5f, 6).wall(8.5f, 6, 31.5f, 6).wall(32.5f, 6, 40, 6);     // south rooms, doors at 8 and 32
    f.wall(0, 18, 7.5f, 18).wall(8.5f, 18, 31.5f, 18).wall(32.5f, 18, 40, 18);  // north rooms, doors at 32 and 8
    f.wall(8, 8, 32, 8).wall(8, 16, 32, 16);                                    // the central block
    const auto s = symmetries_of(f.seed(20, 7));
    ASSERT_EQ(s.size(), 1u);
    EXPECT_FLOAT_EQ(s[0].angle_rad, static_cast<float>(wf::test::kPi));
    EXPECT_FLOAT_EQ(s[0].cx, 20);
    EXPECT_FLOAT_EQ(s[0].cy, 12);
    EXPECT_GT(s[0].matched_fraction, 0.99f);
    EXPECT_TRUE(s[0].is_half_turn());
    float x, y;
    s[0].apply(8, 7, x, y);
    EXPECT_NEAR(x, 32, 1e-5);
    EXPECT_NEAR(y, 17, 1e-5);
}

// A square plan with a centred cross of corridors is symmetric under every quarter turn.
TEST(FloorSymmetry, QuarterTurnsOfASquarePlan) {
    wf::test::FloorSpec f;
    f.box(0, 0, 30, 30).wall(14, 0, 14, 10).wall(16, 20, 16, 30).wall(0, 16, 10, 16).wall(20, 14, 30, 14);
    const auto s = symmetries_of(f.seed(15, 15));
    ASSERT_EQ(s.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(s[k].angle_rad, (k + 1) * wf::test::kPi / 2, 1e-6);
        EXPECT_GT(s[k].matched_fraction, 0.99f);
    }
    EXPECT_FALSE(s[0].is_half_turn());
    EXPECT_TRUE(s[1].is_half_turn());
}

// An L-shaped floor, and the office with its doors moved off the symmetric places (more than a tenth of the
// wall length no longer lands on a wall), have none; nor has a floor with too little wall to judge.
TEST(FloorSymmetry, AsymmetricPlansHaveNone) {
    wf::test::FloorSpec l;
    l.polygon({{0, 0}, {30, 0}, {30, 25}, {27.5f, 25}, {27.5f, 2.5f}, {0, 2.5f}});
    EXPECT_TRUE(symmetries_of(l.seed(1, 1.25f)).empty());

    wf::test::FloorSpec f;
    f.box(0, 0, 40, 24);
    f.wall(0, 6, 30, 6).wall(8, 8, 20, 8).wall(8, 16, 32, 16).wall(22, 8, 40, 8);
    EXPECT_TRUE(symmetries_of(f.seed(20, 7)).empty());

    wf::test::FloorSpec tiny;
    tiny.box(0, 0, 4, 4);
    EXPECT_TRUE(symmetries_of(tiny.seed(2, 2)).empty());
}
