// Tests for the C ABI (include/wf_localizer.h): options, error codes, ownership, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "support/synthetic_world.hpp"
#include "wf_localizer.h"

TEST(CApi, OptionsInitMatchesMacro) {
    wf_localizer_options a;
    std::memset(&a, 0xab, sizeof a);
    ASSERT_EQ(wf_localizer_options_init(&a, WF_LOCALIZER_OPTIONS_VERSION), WF_LOC_OK);
    const wf_localizer_options b = WF_LOCALIZER_OPTIONS_INIT;
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    EXPECT_EQ(a.particle_count, 20000);
    EXPECT_NEAR(a.horizontal_fov_rad, 48 * M_PI / 180, 1e-12);
    EXPECT_EQ(a.max_sign_range_m, 12.0);
    EXPECT_EQ(wf_localizer_options_init(&a, 999), WF_LOC_ERR_VERSION);
    EXPECT_EQ(wf_localizer_options_init(nullptr, WF_LOCALIZER_OPTIONS_VERSION), WF_LOC_ERR_INVALID_ARGUMENT);
}

TEST(CApi, FreeNullAndNullArguments) {
    wf_localizer_free(nullptr);
    EXPECT_EQ(wf_localizer_particle_count(nullptr), 0u);
    wf_localizer *loc = reinterpret_cast<wf_localizer *>(0x1);
    EXPECT_EQ(wf_localizer_create(&loc, nullptr, nullptr, 1), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(loc, nullptr);  // *out cleared on failure
    EXPECT_EQ(wf_localizer_create(nullptr, nullptr, nullptr, 1), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_predict(nullptr, nullptr), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_note_vio_reset(nullptr), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_init_floor_only(nullptr, 0), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_STREQ(wf_localizer_status_string(WF_LOC_ERR_NOT_INITIALIZED), "filter not initialized");
    EXPECT_STREQ(wf_localizer_status_string(-1234), "unknown status");
}

TEST(CApi, CreateRejectsBadOptionsAndMaps) {
    auto world = wf::test::corridor_world();
    wf_localizer *loc = nullptr;
    wf_localizer_options o = WF_LOCALIZER_OPTIONS_INIT;
    o.version = 42;
    EXPECT_EQ(wf_localizer_create(&loc, &world.map(), &o, 1), WF_LOC_ERR_VERSION);
    o = WF_LOCALIZER_OPTIONS_INIT;
    o.bearing_sigma_rad = NAN;
    EXPECT_EQ(wf_localizer_create(&loc, &world.map(), &o, 1), WF_LOC_ERR_INVALID_ARGUMENT);
    o = WF_LOCALIZER_OPTIONS_INIT;
    o.min_particles = 50000;
    o.max_particles = 1000;
    EXPECT_EQ(wf_localizer_create(&loc, &world.map(), &o, 1), WF_LOC_ERR_INVALID_ARGUMENT);
    world.floors[0].walls[0][1] = INFINITY;
    EXPECT_EQ(wf_localizer_create(&loc, &world.map(), nullptr, 1), WF_LOC_ERR_INVALID_MAP);
    EXPECT_EQ(loc, nullptr);
}

TEST(CApi, LifecycleOnCorridor) {
    auto world = wf::test::corridor_world();
    wf_localizer *loc = nullptr;
    wf_localizer_options o = WF_LOCALIZER_OPTIONS_INIT;
    o.particle_count = 3000;
    o.min_particles = 1000;
    o.max_particles = 5000;
    ASSERT_EQ(wf_localizer_create(&loc, &world.map(), &o, 7), WF_LOC_OK);
    ASSERT_NE(loc, nullptr);
    // Before init: estimate is valid but empty; sign updates say "not initialized" with a message.
    wf_localizer_estimate e;
    ASSERT_EQ(wf_localizer_get_estimate(loc, &e), WF_LOC_OK);
    EXPECT_EQ(e.particle_count, 0);
    EXPECT_EQ(e.floor_index, -1);
    EXPECT_EQ(wf_localizer_update_signs(loc, nullptr, 0, 0.0), WF_LOC_ERR_NOT_INITIALIZED);
    EXPECT_NE(std::strlen(wf_localizer_last_error(loc)), 0u);
    EXPECT_EQ(wf_localizer_init_floor_only(loc, 5), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_localizer_last_error(loc)).find("floor index 5"), std::string::npos);

    ASSERT_EQ(wf_localizer_init_floor_only(loc, 0), WF_LOC_OK);
    EXPECT_STREQ(wf_localizer_last_error(loc), "");
    EXPECT_EQ(wf_localizer_particle_count(loc), 3000u);
    wf_vio_sample s = {0.0, 0.0, 0.0, 0.0, WF_VIO_TRACKING_NORMAL};
    EXPECT_EQ(wf_localizer_predict(loc, &s), WF_LOC_OK);
    s.t = 0.1;
    s.east_m = NAN;
    EXPECT_EQ(wf_localizer_predict(loc, &s), WF_LOC_ERR_NON_FINITE_INPUT);
    const wf_sign_observation z[] = {{0, 4.0, 0.05, 0.9}, {9, 2.0, 0.0, 0.9}};  // kind 9: not in the map
    EXPECT_EQ(wf_localizer_update_signs(loc, z, 2, 0.1), WF_LOC_OK);
    EXPECT_EQ(wf_localizer_update_signs(loc, nullptr, 1, 0.1), WF_LOC_ERR_INVALID_ARGUMENT);
    // A frame on which the detector did not look for some kinds: known ids are fine, unknown ones are reported
    // after the update (the message names them), a NULL list with a count is refused.
    const int32_t unsearched[] = {1};
    EXPECT_EQ(wf_localizer_update_signs_searched(loc, z, 2, 0.12, unsearched, 1), WF_LOC_OK);
    EXPECT_EQ(wf_localizer_update_signs_searched(loc, nullptr, 0, 0.13, nullptr, 0), WF_LOC_OK);
    const int32_t unknown[] = {1, 7, -1};
    EXPECT_EQ(wf_localizer_update_signs_searched(loc, nullptr, 0, 0.14, unknown, 3), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_localizer_last_error(loc)).find("2 unsearched kind id(s)"), std::string::npos)
        << wf_localizer_last_error(loc);
    EXPECT_EQ(wf_localizer_update_signs_searched(loc, nullptr, 0, 0.15, nullptr, 2), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_update_signs_searched(nullptr, nullptr, 0, 0.15, nullptr, 0), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_update_altitude(loc, 1.0, 0.2), WF_LOC_OK);
    EXPECT_EQ(wf_localizer_set_compass_prior(loc, 1.0, 0.2), WF_LOC_OK);
    ASSERT_EQ(wf_localizer_get_estimate(loc, &e), WF_LOC_OK);
    EXPECT_TRUE(std::isfinite(e.x) && std::isfinite(e.heading_rad));
    EXPECT_EQ(e.floor_index, 0);
    EXPECT_GT(e.particle_count, 0);

    // Particles: an even subsample when capacity is smaller; weights of all particles sum to 1.
    const size_t n = wf_localizer_particle_count(loc);
    std::vector<wf_localizer_particle> all(n + 10), few(100);
    size_t count = 0;
    ASSERT_EQ(wf_localizer_get_particles(loc, all.data(), all.size(), &count), WF_LOC_OK);
    EXPECT_EQ(count, n);
    double sum = 0;
    for (size_t i = 0; i < count; ++i) {
        sum += all[i].weight;
        ASSERT_GE(all[i].heading_rad, -3.1416f);
        ASSERT_LE(all[i].heading_rad, 3.1416f);
    }
    EXPECT_NEAR(sum, 1.0, 1e-3);
    ASSERT_EQ(wf_localizer_get_particles(loc, few.data(), few.size(), &count), WF_LOC_OK);
    EXPECT_EQ(count, 100u);
    EXPECT_EQ(wf_localizer_get_particles(loc, nullptr, 0, &count), WF_LOC_OK);
    EXPECT_EQ(count, 0u);
    EXPECT_EQ(wf_localizer_get_particles(loc, nullptr, 5, &count), WF_LOC_ERR_INVALID_ARGUMENT);
    wf_localizer_free(loc);
}

// The map arrays belong to the caller and may be freed right after create.
TEST(CApi, MapIsCopiedAtCreate) {
    wf_localizer *loc = nullptr;
    {
        auto world = wf::test::corridor_world();
        ASSERT_EQ(wf_localizer_create(&loc, &world.map(), nullptr, 3), WF_LOC_OK);
    }  // world (and every array the map pointed to) destroyed here
    EXPECT_EQ(wf_localizer_init_start_point(loc, 0, 10, 1, 0.5), WF_LOC_OK);
    const wf_sign_observation z = {0, 10.0, 0.0, 1.0};
    EXPECT_EQ(wf_localizer_update_signs(loc, &z, 1, 0.0), WF_LOC_OK);
    wf_localizer_free(loc);
}

TEST(CApi, CreateFailureReasonIsKeptPerThread) {
    // wf_localizer_create has no handle when it fails: its reason is read with wf_localizer_last_error(NULL).
    wf_localizer *loc = nullptr;
    EXPECT_EQ(wf_localizer_create(&loc, nullptr, nullptr, 1), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_STREQ(wf_localizer_last_error(nullptr), "map is NULL");
    wf::test::World w;
    wf::test::FloorSpec f;
    f.box(0, 0, 10, 4).seed(5, 2);
    f.wall(-60000, 0, 60000, 0);  // 120 km across
    w.floors.push_back(f);
    EXPECT_EQ(wf_localizer_create(&loc, &w.map(), nullptr, 1), WF_LOC_ERR_INVALID_MAP);
    EXPECT_EQ(loc, nullptr);
    const std::string reason = wf_localizer_last_error(nullptr);
    EXPECT_EQ(reason.rfind("floor 0: extent 120000.0 m x 4.0 m", 0), 0u) << reason;
    EXPECT_NE(reason.find("larger than 100 km"), std::string::npos) << reason;
    wf_localizer_options o = WF_LOCALIZER_OPTIONS_INIT;
    o.min_particles = 50000;
    o.max_particles = 1000;
    EXPECT_EQ(wf_localizer_create(&loc, &w.map(), &o, 1), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_STREQ(wf_localizer_last_error(nullptr), "options: option min_particles is larger than max_particles");
    // 99.999 km across (the map validator's limit is 100 km, unpadded): builds, and the reason is cleared.
    wf::test::World ok;
    wf::test::FloorSpec g;
    g.box(0, 0, 10, 4).seed(5, 2);
    g.wall(99998, 0, 99999, 0);
    ok.floors.push_back(g);
    wf_localizer_options small = WF_LOCALIZER_OPTIONS_INIT;
    small.particle_count = 500;
    ASSERT_EQ(wf_localizer_create(&loc, &ok.map(), &small, 1), WF_LOC_OK) << wf_localizer_last_error(nullptr);
    EXPECT_STREQ(wf_localizer_last_error(nullptr), "");
    wf_localizer_free(loc);
}

TEST(CApi, ZeroAreaFloorHasNoWalkableSpace) {
    wf::test::World w;
    wf::test::FloorSpec f;
    f.wall(0, 0, 0, 0).wall(1, 1, 1, 1);
    f.seed(100, 100);  // the only seed is far away from anything: the floor grid is empty of walkable cells
    w.floors.push_back(f);
    wf::test::FloorSpec g;
    g.box(0, 0, 0.3f, 0.3f).seed(0.15f, 0.15f);  // a closet narrower than twice the wall clearance
    w.floors.push_back(g);
    wf_localizer *loc = nullptr;
    ASSERT_EQ(wf_localizer_create(&loc, &w.map(), nullptr, 1), WF_LOC_OK);
    EXPECT_EQ(wf_localizer_init_floor_only(loc, 1), WF_LOC_ERR_NO_WALKABLE_SPACE);
    EXPECT_NE(std::string(wf_localizer_last_error(loc)).find("floor 1"), std::string::npos);
    wf_localizer_estimate e;
    ASSERT_EQ(wf_localizer_get_estimate(loc, &e), WF_LOC_OK);
    EXPECT_EQ(e.localized, 0);
    wf_localizer_free(loc);
}

// The symmetric corridor (30 x 2 m) is mapped onto itself by a half turn about (15, 1); the L-shaped floor is not.
TEST(CApi, FloorSymmetries) {
    auto sym = wf::test::symmetric_world();
    wf_localizer *loc = nullptr;
    ASSERT_EQ(wf_localizer_create(&loc, &sym.map(), nullptr, 1), WF_LOC_OK);
    wf_localizer_floor_symmetry out[3];
    size_t count = 99;
    ASSERT_EQ(wf_localizer_get_floor_symmetries(loc, 0, out, 3, &count), WF_LOC_OK);
    ASSERT_EQ(count, 1u);
    EXPECT_NEAR(out[0].angle_rad, M_PI, 1e-6);
    EXPECT_NEAR(out[0].center_x_m, 15, 1e-6);
    EXPECT_NEAR(out[0].center_y_m, 1, 1e-6);
    EXPECT_GT(out[0].matched_fraction, 0.99);
    EXPECT_EQ(wf_localizer_get_floor_symmetries(loc, 0, out, 0, &count), WF_LOC_OK);  // capacity 0: none copied
    EXPECT_EQ(count, 0u);
    EXPECT_EQ(wf_localizer_get_floor_symmetries(loc, 1, out, 3, &count), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(count, 0u);
    EXPECT_EQ(wf_localizer_get_floor_symmetries(loc, 0, nullptr, 3, &count), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_get_floor_symmetries(loc, 0, out, 3, nullptr), WF_LOC_ERR_INVALID_ARGUMENT);
    EXPECT_EQ(wf_localizer_get_floor_symmetries(nullptr, 0, out, 3, &count), WF_LOC_ERR_INVALID_ARGUMENT);
    wf_localizer_free(loc);

    auto l = wf::test::l_world();
    ASSERT_EQ(wf_localizer_create(&loc, &l.map(), nullptr, 1), WF_LOC_OK);
    ASSERT_EQ(wf_localizer_get_floor_symmetries(loc, 0, out, 3, &count), WF_LOC_OK);
    EXPECT_EQ(count, 0u);
    wf_localizer_free(loc);
}
