// Bad input at the C ABI: every failure is a negative status, the output is left untouched, nothing throws.
#include <gtest/gtest.h>

#include "range_synthetic.hpp"

#include <cstring>
#include <set>
#include <string>
#include <limits>

namespace wf::range::test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A valid observation: sign 4 m ahead, 10 deg left, portrait camera pitched 5 deg up.
wf_range_observation validObservation() {
    Scene s;
    s.pitchRad = deg(5);
    s.rollRad = -kPi / 2;
    s.rangeM = 4;
    s.bearingRad = deg(10);
    s.centerHeightAboveCameraM = 4 * std::tan(deg(8));
    return observation(s, *projectCorners(s));
}

/// A result filled with a sentinel, to check outputs are untouched on failure.
wf_range_result sentinel() { return {-123, -123, -123}; }

void expectUntouched(const wf_range_result &r) {
    EXPECT_EQ(r.range_m, -123);
    EXPECT_EQ(r.bearing_rad, -123);
    EXPECT_EQ(r.center_height_above_camera_m, -123);
}

int estimate(wf_range_method method, const wf_range_observation &o) {
    wf_range_result r = sentinel();
    const int status = wf_range_estimate(&r, method, &o);
    if (status != WF_STATUS_OK) expectUntouched(r);
    return status;
}

const wf_range_method kMethods[] = {WF_RANGE_METHOD_APPARENT_HEIGHT, WF_RANGE_METHOD_HORIZON, WF_RANGE_METHOD_PNP};

TEST(RangeErrors, ValidObservationWorksForEveryMethod) {
    const wf_range_observation o = validObservation();
    for (auto m : kMethods) {
        wf_range_result r{};
        ASSERT_EQ(wf_range_estimate(&r, m, &o), WF_STATUS_OK);
        EXPECT_NEAR(r.range_m, 4.0, 1e-6);
        EXPECT_NEAR(r.bearing_rad, deg(10), 1e-6);
    }
}

TEST(RangeErrors, NaNAnywhereIsNotFinite) {
    for (auto m : kMethods) {
        wf_range_observation o = validObservation();
        o.corners[2].v = kNaN;
        EXPECT_EQ(estimate(m, o), WF_STATUS_NON_FINITE_INPUT);
        o = validObservation();
        o.intrinsics.cx = kInf;
        EXPECT_EQ(estimate(m, o), WF_STATUS_NON_FINITE_INPUT);
        o = validObservation();
        o.camera_to_world[5] = kNaN;
        EXPECT_EQ(estimate(m, o), WF_STATUS_NON_FINITE_INPUT);
    }
    wf_range_observation o = validObservation();
    o.sign_height_m = kNaN;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_APPARENT_HEIGHT, o), WF_STATUS_NON_FINITE_INPUT);
    EXPECT_EQ(estimate(WF_RANGE_METHOD_PNP, o), WF_STATUS_NON_FINITE_INPUT);
    o = validObservation();
    o.camera_height_m = kInf;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_HORIZON, o), WF_STATUS_NON_FINITE_INPUT);

    double range = -1;
    EXPECT_EQ(wf_range_paper_equation3(&range, kNaN, 0.1, 0.05, 0.21), WF_STATUS_NON_FINITE_INPUT);
    EXPECT_EQ(range, -1);
    const wf_range_unrolled_camera cam{1602, 1602, 720, 960, 0.1, -kPi / 2};
    wf_range_slice_measurement m{900, 40, 700, 0, 0, 0};
    m.median_bottom_row_px = kNaN;
    wf_range_result r = sentinel();
    EXPECT_EQ(wf_range_apparent_height_slices(&r, &cam, &m, 0.21, WF_RANGE_SLICE_MODEL_RAY_ELEVATION),
              WF_STATUS_NON_FINITE_INPUT);
    expectUntouched(r);
    const double u[2] = {1, 2}, top[2] = {10, kNaN}, bottom[2] = {30, 31};
    EXPECT_EQ(wf_range_slice_measurement_from_columns(&m, u, top, bottom, 2), WF_STATUS_NON_FINITE_INPUT);
}

TEST(RangeErrors, ZeroOrNegativeSizesAreRejected) {
    for (double h : {0.0, -0.21}) {
        wf_range_observation o = validObservation();
        o.sign_height_m = h;
        EXPECT_EQ(estimate(WF_RANGE_METHOD_APPARENT_HEIGHT, o), WF_STATUS_NONPOSITIVE_SIZE);
        EXPECT_EQ(estimate(WF_RANGE_METHOD_PNP, o), WF_STATUS_NONPOSITIVE_SIZE);
        double range = -1;
        EXPECT_EQ(wf_range_paper_equation3(&range, 0.1, 0.1, 0.05, h), WF_STATUS_NONPOSITIVE_SIZE);
    }
    wf_range_observation o = validObservation();
    o.sign_width_m = 0;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_PNP, o), WF_STATUS_NONPOSITIVE_SIZE);
    o = validObservation();
    o.intrinsics.fx = 0;
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_NONPOSITIVE_SIZE);

    // Zero pixel height of the slices, zero columns, zero image size.
    const wf_range_unrolled_camera cam{1602, 1602, 720, 960, 0.1, -kPi / 2};
    const wf_range_slice_measurement flat{900, 0, 700, 0, 0, 0};
    wf_range_result r = sentinel();
    EXPECT_EQ(wf_range_apparent_height_slices(&r, &cam, &flat, 0.21, WF_RANGE_SLICE_MODEL_RAY_ELEVATION),
              WF_STATUS_NONPOSITIVE_SIZE);
    expectUntouched(r);
    wf_range_slice_measurement m{};
    const double u[1] = {5}, top[1] = {20}, bottom[1] = {20};
    EXPECT_EQ(wf_range_slice_measurement_from_columns(&m, u, top, bottom, 0), WF_STATUS_NONPOSITIVE_SIZE);
    EXPECT_EQ(wf_range_slice_measurement_from_columns(&m, u, top, bottom, 1), WF_STATUS_NONPOSITIVE_SIZE);
    const wf_range_intrinsics k = iphone8();
    wf_range_unroll_map map{};
    EXPECT_EQ(wf_range_unroll_map_make(&map, &k, 0.0, 0.0, 1440), WF_STATUS_NONPOSITIVE_SIZE);
}

TEST(RangeErrors, DegenerateCornersAreRejected) {
    const wf_range_observation valid = validObservation();
    // Repeated corner.
    wf_range_observation o = valid;
    o.corners[1] = o.corners[0];
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_DEGENERATE_CORNERS);
    // All four on a line.
    o = valid;
    for (int i = 0; i < 4; ++i) o.corners[i] = {100.0 + 10 * i, 200.0 + 5 * i};
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_DEGENERATE_CORNERS);
    // Counter-clockwise order (TL, BL, BR, TR): a mirrored sign.
    o = valid;
    std::swap(o.corners[1], o.corners[3]);
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_DEGENERATE_CORNERS);
    // Self-intersecting (bow tie).
    o = valid;
    std::swap(o.corners[2], o.corners[3]);
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_DEGENERATE_CORNERS);
    // Non-convex (one corner pushed inside).
    o = valid;
    o.corners[2] = {0.5 * (o.corners[1].u + o.corners[3].u), 0.5 * (o.corners[1].v + o.corners[3].v)};
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_DEGENERATE_CORNERS);
}

TEST(RangeErrors, NoPositiveTangentDifferenceIsDegenerateGeometry) {
    const wf_range_observation o = validObservation();
    wf_range_point c{}, top{}, bottom{};
    ASSERT_EQ(wf_range_sign_center_points(&c, &top, &bottom, o.corners), WF_STATUS_OK);
    wf_range_result r = sentinel();
    // Top and bottom swapped: tan(top) - tan(bottom) < 0.
    EXPECT_EQ(wf_range_apparent_height_exact(&r, &bottom, &top, &o.intrinsics, o.camera_to_world, 0.21),
              WF_STATUS_DEGENERATE_GEOMETRY);
    // Same point: difference 0.
    EXPECT_EQ(wf_range_apparent_height_exact(&r, &top, &top, &o.intrinsics, o.camera_to_world, 0.21),
              WF_STATUS_DEGENERATE_GEOMETRY);
    expectUntouched(r);
    double range = -1;
    EXPECT_EQ(wf_range_paper_equation3(&range, 0.1, 0.1, -0.02, 0.21), WF_STATUS_DEGENERATE_GEOMETRY);
    EXPECT_EQ(wf_range_paper_equation3(&range, 0.1, 0.1, 0.0, 0.21), WF_STATUS_DEGENERATE_GEOMETRY);
    // Angles at or beyond 90 degrees: tan blows up.
    EXPECT_EQ(wf_range_paper_equation3(&range, 1.5, 0.1, 0.05, 0.21), WF_STATUS_DEGENERATE_GEOMETRY);
    EXPECT_EQ(wf_range_paper_equation3(&range, -1.6, 0.0, 0.05, 0.21), WF_STATUS_DEGENERATE_GEOMETRY);
    EXPECT_EQ(range, -1);
    // Slices with a pitch of 90 degrees.
    const wf_range_unrolled_camera up{1602, 1602, 720, 960, kPi / 2, 0};
    const wf_range_slice_measurement m{900, 40, 700, 0, 0, 0};
    EXPECT_EQ(wf_range_apparent_height_slices(&r, &up, &m, 0.21, WF_RANGE_SLICE_MODEL_PAPER_PLANAR),
              WF_STATUS_DEGENERATE_GEOMETRY);
    // Camera looking straight down: no horizontal forward direction, no bearing.
    double down[16];
    ASSERT_EQ(wf_range_camera_to_world_from_pitch_roll(down, -kPi / 2, 0), WF_STATUS_OK);
    EXPECT_EQ(wf_range_apparent_height_exact(&r, &top, &bottom, &o.intrinsics, down, 0.21),
              WF_STATUS_DEGENERATE_GEOMETRY);
    expectUntouched(r);
}

TEST(RangeErrors, HorizonMethodRefusesSignsAtCameraHeightOrOnTheWrongSide) {
    wf_range_observation o = validObservation();  // sign centre above the horizon
    o.sign_center_height_m = o.camera_height_m;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_HORIZON, o), WF_STATUS_DEGENERATE_GEOMETRY);
    o.sign_center_height_m = o.camera_height_m - 0.3;  // heights say below, the image says above
    EXPECT_EQ(estimate(WF_RANGE_METHOD_HORIZON, o), WF_STATUS_DEGENERATE_GEOMETRY);
    o = validObservation();
    o.camera_height_m = kNaN;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_HORIZON, o), WF_STATUS_MISSING_INPUT);
    o = validObservation();
    o.sign_center_height_m = kNaN;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_HORIZON, o), WF_STATUS_MISSING_INPUT);
    // A sign exactly on the horizon line: the elevation's tangent is 0.
    Scene s;
    s.rangeM = 5;
    s.centerHeightAboveCameraM = 0;
    o = observation(s, *projectCorners(s));
    EXPECT_EQ(estimate(WF_RANGE_METHOD_HORIZON, o), WF_STATUS_DEGENERATE_GEOMETRY);
    // ...where the apparent-height method still works.
    wf_range_result r{};
    EXPECT_EQ(wf_range_estimate(&r, WF_RANGE_METHOD_APPARENT_HEIGHT, &o), WF_STATUS_OK);
    EXPECT_NEAR(r.range_m, 5, 1e-6);
}

TEST(RangeErrors, MissingWidthVersionRotationAndEnums) {
    wf_range_observation o = validObservation();
    o.sign_width_m = kNaN;
    EXPECT_EQ(estimate(WF_RANGE_METHOD_PNP, o), WF_STATUS_MISSING_INPUT);
    EXPECT_EQ(estimate(WF_RANGE_METHOD_APPARENT_HEIGHT, o), WF_STATUS_OK);  // width not needed
    o = validObservation();
    o.version = 2;
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_VERSION);
    o = validObservation();
    o.camera_to_world[1] *= 2;  // scaled column: not a rotation
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_NOT_A_ROTATION);
    o = validObservation();
    for (int i : {0, 1, 2}) o.camera_to_world[i] = -o.camera_to_world[i];  // reflection: det = -1
    for (auto m : kMethods) EXPECT_EQ(estimate(m, o), WF_STATUS_NOT_A_ROTATION);
    o = validObservation();
    EXPECT_EQ(estimate(static_cast<wf_range_method>(7), o), WF_STATUS_MISSING_INPUT);
    const wf_range_unrolled_camera cam{1602, 1602, 720, 960, 0.1, -kPi / 2};
    const wf_range_slice_measurement m{900, 40, 700, 0, 0, 0};
    wf_range_result r = sentinel();
    EXPECT_EQ(wf_range_apparent_height_slices(&r, &cam, &m, 0.21, static_cast<wf_range_slice_model>(5)),
              WF_STATUS_MISSING_INPUT);
    expectUntouched(r);
}

TEST(RangeErrors, NullPointersAreRejected) {
    const wf_range_observation o = validObservation();
    wf_range_result r{};
    EXPECT_EQ(wf_range_estimate(nullptr, WF_RANGE_METHOD_PNP, &o), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_estimate(&r, WF_RANGE_METHOD_PNP, nullptr), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_pnp(&r, nullptr, &o.intrinsics, o.camera_to_world, 0.4, 0.21), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_horizon(&r, &o.corners[0], nullptr, o.camera_to_world, 1, 2), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_apparent_height_exact(&r, &o.corners[0], &o.corners[1], &o.intrinsics, nullptr, 0.2),
              WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_apparent_height_slices(&r, nullptr, nullptr, 0.21, WF_RANGE_SLICE_MODEL_RAY_ELEVATION),
              WF_STATUS_INVALID_ARGUMENT);
    wf_range_slice_measurement m{};
    EXPECT_EQ(wf_range_slice_measurement_from_columns(&m, nullptr, nullptr, nullptr, 3), WF_STATUS_INVALID_ARGUMENT);
    double p = 0;
    EXPECT_EQ(wf_range_pitch_roll_from_camera_to_world(&p, nullptr, o.camera_to_world), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_camera_to_world_from_pitch_roll(nullptr, 0, 0), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_unroll_map_make(nullptr, &o.intrinsics, 0, 10, 10), WF_STATUS_INVALID_ARGUMENT);
    wf_range_point a{}, b{}, c{};
    EXPECT_EQ(wf_range_sign_center_points(&a, &b, &c, nullptr), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_range_paper_equation3(nullptr, 0, 0, 0, 1), WF_STATUS_INVALID_ARGUMENT);
}

TEST(RangeErrors, EveryStatusHasADescription) {
    // Every code of the shared vocabulary (wf_status.h) has its own text; unknown codes share one.
    const int codes[] = {WF_STATUS_OK, WF_STATUS_SKIPPED_DARK_FRAME, WF_STATUS_TRUNCATED, WF_STATUS_INVALID_ARGUMENT,
                         WF_STATUS_OUT_OF_MEMORY, WF_STATUS_VERSION, WF_STATUS_NON_FINITE_INPUT, WF_STATUS_INTERNAL,
                         WF_STATUS_INVALID_MAP, WF_STATUS_NO_WALKABLE_SPACE, WF_STATUS_NOT_INITIALIZED,
                         WF_STATUS_MODEL_LOAD, WF_STATUS_BAD_FRAME, WF_STATUS_IMAGE_READ, WF_STATUS_INVALID_CATALOGUE,
                         WF_STATUS_NONPOSITIVE_SIZE, WF_STATUS_DEGENERATE_CORNERS, WF_STATUS_DEGENERATE_GEOMETRY,
                         WF_STATUS_NOT_A_ROTATION, WF_STATUS_PNP_FAILED, WF_STATUS_MISSING_INPUT};
    std::set<std::string> texts;
    for (int s : codes) {
        const char *text = wf_status_string(s);
        ASSERT_NE(text, nullptr);
        EXPECT_STRNE(text, "unknown status") << "code " << s;
        texts.insert(text);
    }
    EXPECT_EQ(texts.size(), sizeof codes / sizeof codes[0]) << "two codes share a description";
    EXPECT_STREQ(wf_status_string(-1000), "unknown status");
}

}  // namespace
}  // namespace wf::range::test
