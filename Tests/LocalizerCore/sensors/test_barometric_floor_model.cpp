// Barometric floor changes (sensors/barometric_floor_model): riding particles land beside the same link on the
// destination floor's plan, which may draw it at other map coordinates than the floor they left.
#include <gtest/gtest.h>

#include "sensors/barometric_floor_model.hpp"
#include "support/filter_fixtures.hpp"

namespace {

using wf::loc::apply_floor_change;
using wf::loc::BarometricFloorParams;
using wf::loc::link_offset;
using wf::loc::ParticleSet;
using wf::loc::Rng;

// Two 20 m x 20 m floors 3.5 m apart. The elevator is drawn at (10, 10) on the ground floor and at (10.5, 8.8)
// on the upper floor (plans not aligned: 1.3 m apart); the stairs' landings are (2, 2) and (2, 8) (a straight
// flight, 6 m of horizontal run, which the traveler walks and VIO measures).
wf::test::World two_floors() {
    wf::test::World w;
    wf::test::FloorSpec ground, upper;
    ground.box(0, 0, 20, 20).seed(5, 5).link(10, 10).link(2, 2);
    upper.box(0, 0, 20, 20).seed(5, 5).link(10.5f, 8.8f).link(2, 8);
    upper.elevation_m = 3.5;
    w.floors = {ground, upper};
    return w;
}

ParticleSet particles_at(const std::vector<std::array<float, 2>> &xy) {
    ParticleSet p;
    p.resize(xy.size());
    for (size_t i = 0; i < xy.size(); ++i) {
        p.x[i] = xy[i][0];
        p.y[i] = xy[i][1];
        p.yaw_offset[i] = 0.3f;
        p.scale[i] = 1;
        p.floor[i] = 0;
        p.weight[i] = 1.0f / static_cast<float>(xy.size());
    }
    return p;
}

TEST(BarometricFloorModel, TheSameShaftDrawnElsewhereOnTheNewPlanMovesTheRidersByTheOffset) {
    auto w = two_floors();
    const auto o = wf::test::default_options();
    const auto map = wf::test::build_map(w, o);
    float dx, dy;
    link_offset(map, 0, map.floors[0].nearest_link(9.0f, 10.5f), 1, 2.0f, dx, dy);
    EXPECT_NEAR(dx, 0.5f, 1e-6f);
    EXPECT_NEAR(dy, -1.2f, 1e-6f);
    // The staircase's landings are 6 m apart: no offset (the walk up the flight is VIO's to measure).
    link_offset(map, 0, map.floors[0].nearest_link(2.5f, 2.5f), 1, 2.0f, dx, dy);
    EXPECT_EQ(dx, 0.0f);
    EXPECT_EQ(dy, 0.0f);
    // Nor with a smaller allowance than the shaft's offset.
    link_offset(map, 0, map.floors[0].nearest_link(9.0f, 10.5f), 1, 1.0f, dx, dy);
    EXPECT_EQ(dx, 0.0f);
    EXPECT_EQ(dy, 0.0f);

    // A ride up: the particles in the cabin arrive beside the upper plan's elevator with their offsets from it
    // and headings kept; the one at the stairs changes floor where it is; the one far from any link is re-drawn
    // beside a link of the upper floor with a twentieth of its weight.
    ParticleSet p = particles_at({{10, 10}, {9.2f, 10.6f}, {2.5f, 2.5f}, {15, 16}});
    Rng rng(7);
    BarometricFloorParams params;
    apply_floor_change(p, map, 3.5, params, rng, [] { return 0.0f; });
    for (size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p.floor[i], 1) << i;
    EXPECT_NEAR(p.x[0], 10.5f, 1e-5f);
    EXPECT_NEAR(p.y[0], 8.8f, 1e-5f);
    EXPECT_NEAR(p.x[1], 9.7f, 1e-5f);
    EXPECT_NEAR(p.y[1], 9.4f, 1e-5f);
    EXPECT_FLOAT_EQ(p.yaw_offset[1], 0.3f);
    EXPECT_FLOAT_EQ(p.x[2], 2.5f);
    EXPECT_FLOAT_EQ(p.y[2], 2.5f);
    EXPECT_FLOAT_EQ(p.weight[2], 0.25f);
    EXPECT_FLOAT_EQ(p.weight[3], 0.25f * static_cast<float>(params.far_from_link_weight));

    // With the allowance at 0 (aligned plans assumed) the riders change floor where they are, as before.
    ParticleSet q = particles_at({{10, 10}});
    params.shaft_offset_max_m = 0;
    apply_floor_change(q, map, 3.5, params, rng, [] { return 0.0f; });
    EXPECT_FLOAT_EQ(q.x[0], 10.0f);
    EXPECT_FLOAT_EQ(q.y[0], 10.0f);
}

}  // namespace
