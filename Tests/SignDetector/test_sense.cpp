// Tests of wf_detector_sense (frame -> ranged sightings in one call) and of the sign-kind catalogue, and of bad
// input at that boundary: frames of the wrong size or stride, a NaN pose, empty or contradictory catalogues.
#include "detector.hpp"
#include "wf_range.h"
#include "wf_sign_detector.h"

#include "synthetic_scene.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

using namespace wf::sign;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The Exit sign of the synthetic renderer: 0.33 x 0.21 m (synthetic_scene.hpp SignPlacement).
const wf_sign_kind kExit{"exit", 0.21, 0.33, "red", "white", 0};

/// A U-Net detector (the tiny committed model, class "exit") with `catalogue`.
wf_detector* makeUnet(const std::vector<wf_sign_kind>& catalogue, int* status = nullptr) {
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.kind = WF_DETECTOR_UNET;
    const std::string path = wf::sign::testing::tinyUnetPath();
    opts.unet_path = path.c_str();
    opts.catalogue = catalogue.empty() ? nullptr : catalogue.data();
    opts.catalogue_count = catalogue.size();
    wf_detector* d = nullptr;
    const int s = wf_detector_create(&d, &opts);
    if (status) *status = s;
    return d;
}

/// A portrait 1920 x 1440 frame (RGB8) with a red sign at `rangeMeters`, bearing 0.15 rad, pitch 0.1 rad.
struct Scene {
    synthetic::Camera camera;
    synthetic::RenderedSign truth;
    cv::Mat rgb;
    wf_frame frame{};
};

Scene scene(double rangeMeters = 3.0) {
    Scene s;
    s.camera.pitchRad = 0.1;
    s.camera.rollRad = -kPi / 2;
    cv::Mat bgr = synthetic::renderBackground(s.camera, 21);
    synthetic::SignPlacement sign;
    sign.rangeMeters = rangeMeters;
    sign.bearingRad = 0.15;
    sign.style = synthetic::SignStyle::WhiteLettersOnRed;
    s.truth = synthetic::drawSign(bgr, s.camera, sign);
    cv::cvtColor(bgr, s.rgb, cv::COLOR_BGR2RGB);
    s.frame.image = wf_image{s.rgb.data, s.rgb.cols, s.rgb.rows, s.rgb.step, WF_PIXEL_RGB8, nullptr, 0,
                             s.rgb.step * size_t(s.rgb.rows), 0};
    s.frame.intrinsics = wf_intrinsics{s.camera.fx, s.camera.fy, s.camera.cx, s.camera.cy};
    s.frame.pitch_rad = s.camera.pitchRad;
    s.frame.roll_rad = s.camera.rollRad;
    return s;
}

/// wf_detector_sense's status on `frame`, with the count it wrote.
int sense(wf_detector* d, const wf_frame& frame, std::vector<wf_sign_sighting>* out) {
    out->assign(8, wf_sign_sighting{});
    size_t count = 99;
    const int status = wf_detector_sense(d, &frame, out->data(), out->size(), &count);
    out->resize(count);
    return status;
}

}  // namespace

TEST(Sense, OneCallGivesTheRangeOfTheDetectionWithTheCatalogueHeight) {
    wf_detector* d = makeUnet({kExit});
    ASSERT_NE(d, nullptr) << wf_thread_last_error();
    const Scene s = scene(3.0);
    ASSERT_TRUE(s.truth.visible);
    std::vector<wf_sign_sighting> sightings;
    ASSERT_EQ(sense(d, s.frame, &sightings), WF_STATUS_OK) << wf_detector_last_error(d);
    ASSERT_EQ(sightings.size(), 1u);
    const wf_sign_sighting& g = sightings[0];
    EXPECT_STREQ(g.kind, "exit");
    EXPECT_NEAR(g.range_m, 3.0, 0.03 * 3.0);
    EXPECT_NEAR(g.bearing_rad, 0.15, 0.02);

    // Identical to the two-step path: detect, then range the observation with the same face height.
    wf_detector_observation obs[4];
    size_t count = 0;
    ASSERT_EQ(wf_detector_detect(d, &s.frame, obs, 4, &count), WF_STATUS_OK);
    ASSERT_EQ(count, 1u);
    const wf_range_unrolled_camera camera{obs[0].unrolled_fx, obs[0].unrolled_fy, obs[0].unrolled_cx,
                                          obs[0].unrolled_cy, s.frame.pitch_rad, obs[0].applied_roll_rad};
    const wf_range_slice_measurement m{obs[0].median_bottom_row_px, obs[0].median_height_px, obs[0].center_column_px,
                                       obs[0].bottom_edge_slope,    obs[0].top_edge_slope,   obs[0].extent_width_px};
    wf_range_result r{};
    ASSERT_EQ(wf_range_apparent_height_slices(&r, &camera, &m, kExit.face_height_m, WF_RANGE_SLICE_MODEL_RAY_ELEVATION),
              WF_STATUS_OK);
    EXPECT_EQ(g.range_m, r.range_m);
    EXPECT_EQ(g.bearing_rad, r.bearing_rad);
    EXPECT_EQ(g.score, obs[0].score);

    // The corners lie on the drawn sign's corners (raw pixels; the mask's edges within a few pixels).
    ASSERT_EQ(s.truth.cornersRaw.size(), 4u);
    for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(g.corners_raw_px[2 * i], s.truth.cornersRaw[i].x, 6.0) << "corner " << i << " u";
        EXPECT_NEAR(g.corners_raw_px[2 * i + 1], s.truth.cornersRaw[i].y, 6.0) << "corner " << i << " v";
    }
    wf_detector_free(d);
}

// A face measured under 13 px is detected but not ranged (ResolvedOptions::minRangingHeightPx): its range from
// apparent height is too coarse for the localizer. 36 m away the drawn face measures about 9 px on this
// 1920 x 1440 frame, 30 m away about 11 px (both detected, neither ranged); 25 m away, 13.6 px (ranged).
TEST(Sense, FacesTooSmallToRangeAreNotReported) {
    constexpr double kMinRangingHeightPx = 13;
    wf_detector* d = makeUnet({kExit});
    ASSERT_NE(d, nullptr) << wf_thread_last_error();
    for (const double range : {36.0, 30.0, 25.0}) {
        const Scene s = scene(range);
        wf_detector_observation obs[4];
        size_t count = 0;
        ASSERT_EQ(wf_detector_detect(d, &s.frame, obs, 4, &count), WF_STATUS_OK);
        ASSERT_EQ(count, 1u) << range;
        std::vector<wf_sign_sighting> sightings;
        ASSERT_EQ(sense(d, s.frame, &sightings), WF_STATUS_OK);
        const bool small = obs[0].median_height_px < kMinRangingHeightPx;
        EXPECT_EQ(sightings.size(), small ? 0u : 1u) << range << " m, " << obs[0].median_height_px << " px";
        EXPECT_EQ(small, range > 26.0) << range << " m, " << obs[0].median_height_px << " px";
    }
    wf_detector_free(d);
}

// A face cut by the frame's edge is detected but not ranged (ResolvedOptions::frameEdgeMarginPx): its apparent
// height is the visible part's. The frame is a crop about the image centre (so the principal point stays
// central) whose edge cuts the sign, on the axis where the sign is farther from the centre.
TEST(Sense, FacesCutByTheFrameEdgeAreNotReported) {
    wf_detector* d = makeUnet({kExit});
    ASSERT_NE(d, nullptr) << wf_thread_last_error();
    Scene s = scene(3.0);
    std::vector<wf_sign_sighting> whole;
    ASSERT_EQ(sense(d, s.frame, &whole), WF_STATUS_OK);
    ASSERT_EQ(whole.size(), 1u);
    EXPECT_FALSE(faceTouchesFrameEdge(whole[0], s.rgb.cols, s.rgb.rows, 2.0));

    double su = 0, sv = 0, minU = 1e9, maxU = -1e9, minV = 1e9, maxV = -1e9;
    for (const auto& c : s.truth.cornersRaw) {
        su += 0.25 * c.x;
        sv += 0.25 * c.y;
        minU = std::min(minU, double(c.x));
        maxU = std::max(maxU, double(c.x));
        minV = std::min(minV, double(c.y));
        maxV = std::max(maxV, double(c.y));
    }
    const double cu = 0.5 * (s.rgb.cols - 1), cv = 0.5 * (s.rgb.rows - 1);
    const bool alongU = std::abs(su - cu) / s.rgb.cols >= std::abs(sv - cv) / s.rgb.rows;
    const double off = alongU ? std::abs(su - cu) : std::abs(sv - cv);
    ASSERT_GT(off, 40.0) << "the sign is too near the centre to cut it this way";
    // The crop's edge runs a fifth of the sign's extent past its centre: 70 % of the face stays in view.
    const int half = int(std::lround(off + 0.2 * (alongU ? maxU - minU : maxV - minV)));
    cv::Rect roi = alongU ? cv::Rect(int(cu) - half, 0, 2 * half, s.rgb.rows) : cv::Rect(0, int(cv) - half, s.rgb.cols, 2 * half);
    cv::Mat crop = s.rgb(roi).clone();
    wf_frame cut = s.frame;
    cut.image = wf_image{crop.data, crop.cols, crop.rows, crop.step, WF_PIXEL_RGB8, nullptr, 0,
                         crop.step * size_t(crop.rows), 0};
    cut.intrinsics.cx -= roi.x;
    cut.intrinsics.cy -= roi.y;
    wf_detector_observation obs[4];
    size_t count = 0;
    ASSERT_EQ(wf_detector_detect(d, &cut, obs, 4, &count), WF_STATUS_OK) << wf_detector_last_error(d);
    ASSERT_GE(count, 1u) << "the half sign is still detected";
    std::vector<wf_sign_sighting> sightings;
    ASSERT_EQ(sense(d, cut, &sightings), WF_STATUS_OK);
    EXPECT_TRUE(sightings.empty()) << sightings.size() << " sighting(s), first at " << sightings[0].range_m << " m";
    wf_detector_free(d);
}

TEST(Sense, FaceEdgeTestCoversEveryCornerAndNaN) {
    wf_sign_sighting g{};
    const double inside[8] = {10, 10, 50, 10, 50, 40, 10, 40};
    std::copy(inside, inside + 8, g.corners_raw_px);
    EXPECT_FALSE(faceTouchesFrameEdge(g, 100, 80, 2.0));
    for (int k = 0; k < 8; ++k) {
        wf_sign_sighting h = g;
        h.corners_raw_px[k] = (k % 2 == 0) ? 98.5 : 78.5;  // within 2 px of the right or bottom edge
        EXPECT_TRUE(faceTouchesFrameEdge(h, 100, 80, 2.0)) << k;
        h.corners_raw_px[k] = 1.0;  // within 2 px of the left or top edge
        EXPECT_TRUE(faceTouchesFrameEdge(h, 100, 80, 2.0)) << k;
        h.corners_raw_px[k] = std::numeric_limits<double>::quiet_NaN();
        EXPECT_TRUE(faceTouchesFrameEdge(h, 100, 80, 2.0)) << k;
    }
}

TEST(Sense, RangeScalesWithTheCatalogueFaceHeight) {
    // The same detection ranged as a sign twice as tall is twice as far: the size comes from the catalogue only.
    wf_sign_kind tall = kExit;
    tall.face_height_m = 2 * kExit.face_height_m;
    wf_detector* a = makeUnet({kExit});
    wf_detector* b = makeUnet({tall});
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    const Scene s = scene(4.0);
    std::vector<wf_sign_sighting> ga, gb;
    ASSERT_EQ(sense(a, s.frame, &ga), WF_STATUS_OK);
    ASSERT_EQ(sense(b, s.frame, &gb), WF_STATUS_OK);
    ASSERT_EQ(ga.size(), 1u);
    ASSERT_EQ(gb.size(), 1u);
    EXPECT_NEAR(gb[0].range_m / ga[0].range_m, 2.0, 1e-9);
    wf_detector_free(a);
    wf_detector_free(b);
}

TEST(Sense, KindsOutsideTheCatalogueAreLeftOut) {
    const wf_sign_kind restroom{"restroom", 0.2, 0.2, nullptr, nullptr, 0};
    wf_detector* d = makeUnet({restroom});
    ASSERT_NE(d, nullptr) << wf_thread_last_error();
    std::vector<wf_sign_sighting> sightings;
    EXPECT_EQ(sense(d, scene().frame, &sightings), WF_STATUS_OK);
    EXPECT_TRUE(sightings.empty());
    wf_detector_free(d);
}

TEST(Sense, WithoutACatalogueIsAClearError) {
    wf_detector* d = makeUnet({});
    ASSERT_NE(d, nullptr) << wf_thread_last_error();  // detect alone needs no sizes
    std::vector<wf_sign_sighting> sightings;
    EXPECT_EQ(sense(d, scene().frame, &sightings), WF_STATUS_INVALID_CATALOGUE);
    EXPECT_TRUE(sightings.empty());
    EXPECT_NE(std::string(wf_detector_last_error(d)).find("catalogue is empty"), std::string::npos);
    wf_detector_free(d);
}

TEST(Catalogue, BadEntriesAreRejectedAtCreationNamingTheEntry) {
    struct Case {
        std::vector<wf_sign_kind> entries;
        const char* expected;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<Case> cases = {
        {{{nullptr, 0.21, 0.3, nullptr, nullptr, 0}}, "entry 0: kind name"},
        {{{"", 0.21, 0.3, nullptr, nullptr, 0}}, "entry 0: kind name"},
        {{{"a-kind-name-that-is-far-too-long-for-it", 0.21, 0.3, nullptr, nullptr, 0}}, "entry 0: kind name"},
        {{kExit, {"exit", nan, 0.3, nullptr, nullptr, 0}}, "entry 1 ('exit'): face_height_m nan"},
        {{{"exit", 0.21, -0.3, nullptr, nullptr, 0}}, "face_width_m -0.3"},
        {{{"exit", 0.0, 0.3, nullptr, nullptr, 0}}, "face_height_m 0"},
        {{kExit, {"exit", 0.25, 0.33, nullptr, nullptr, 0}}, "entry 1 ('exit') contradicts an earlier entry"},
        {{kExit, {"exit", 0.21, 0.33, nullptr, nullptr, 1}}, "contradicts"},
    };
    for (const Case& c : cases) {
        int status = 0;
        wf_detector* d = makeUnet(c.entries, &status);
        EXPECT_EQ(d, nullptr) << c.expected;
        EXPECT_EQ(status, WF_STATUS_INVALID_CATALOGUE) << c.expected;
        EXPECT_NE(std::string(wf_thread_last_error()).find(c.expected), std::string::npos)
            << "expected '" << c.expected << "' in: " << wf_thread_last_error();
        wf_detector_free(d);
    }
    // A NULL array with a count is an argument error; an identical repeat is harmless.
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.catalogue_count = 2;
    wf_detector* d = nullptr;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(d, nullptr);
    int status = 0;
    d = makeUnet({kExit, kExit}, &status);
    EXPECT_EQ(status, WF_STATUS_OK) << wf_thread_last_error();
    wf_detector_free(d);
}

TEST(Catalogue, ParseCopiesEveryField) {
    std::vector<SignKindSpec> out;
    std::string error;
    const wf_sign_kind entries[] = {kExit, {"restroom", 0.2, 0.15, nullptr, "white", 1}};
    ASSERT_EQ(parseCatalogue(entries, 2, &out, &error), WF_STATUS_OK) << error;
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].kind, "exit");
    EXPECT_EQ(out[0].faceHeightMeters, 0.21);
    EXPECT_EQ(out[0].faceWidthMeters, 0.33);
    EXPECT_EQ(out[0].faceColour, "red");
    EXPECT_EQ(out[1].faceColour, "");
    EXPECT_EQ(out[1].legendColour, "white");
    EXPECT_TRUE(out[1].doubleSided);
    EXPECT_EQ(findKind(out, "restroom"), &out[1]);
    EXPECT_EQ(findKind(out, "stairs"), nullptr);
}

TEST(SenseBadInput, WrongSizeStrideOrPoseIsAClearErrorNeverACrash) {
    wf_detector* d = makeUnet({kExit});
    ASSERT_NE(d, nullptr);
    const Scene s = scene();
    std::vector<wf_sign_sighting> sightings;
    auto expectBadFrame = [&](const wf_frame& f, const char* expected) {
        EXPECT_EQ(sense(d, f, &sightings), WF_STATUS_BAD_FRAME) << expected;
        EXPECT_TRUE(sightings.empty()) << expected;
        EXPECT_NE(std::string(wf_detector_last_error(d)).find(expected), std::string::npos)
            << "expected '" << expected << "' in: " << wf_detector_last_error(d);
    };
    wf_frame f = s.frame;
    f.image.data_bytes = s.rgb.step * size_t(s.rgb.rows) - 1;  // one byte short: a buffer of another size
    expectBadFrame(f, "shorter than the 1920x1440 frame");
    f = s.frame;
    f.image.height = s.rgb.rows + 1;  // a taller frame than the buffer holds
    expectBadFrame(f, "wrong size or stride");
    f = s.frame;
    f.image.stride = s.rgb.step + 64;  // a stride from another buffer: the rows run past the end
    expectBadFrame(f, "wrong size or stride");
    f = s.frame;
    f.image.stride = 3 * 1920 - 1;  // a stride shorter than a row
    expectBadFrame(f, "row stride");
    f = s.frame;
    f.image.width = 640;  // the intrinsics belong to another resolution
    f.image.height = 480;
    expectBadFrame(f, "another resolution");
    f = s.frame;
    f.pitch_rad = std::nan("");
    expectBadFrame(f, "pitch nan");
    f = s.frame;
    f.roll_rad = std::numeric_limits<double>::infinity();
    expectBadFrame(f, "roll inf");
    f = s.frame;
    f.intrinsics.fx = std::nan("");
    expectBadFrame(f, "non-finite intrinsics");

    // NV12: a chroma plane shorter than the frame needs.
    cv::Mat y(480, 640, CV_8UC1, cv::Scalar(100)), uv(240, 320, CV_8UC2, cv::Scalar(128, 128));
    wf_frame nv12{};
    nv12.image = wf_image{y.data, 640, 480, y.step, WF_PIXEL_NV12, uv.data, uv.step, y.step * 480, uv.step * 239};
    nv12.intrinsics = wf_intrinsics{534, 534, 319.5, 239.5};
    nv12.roll_rad = -kPi / 2;
    expectBadFrame(nv12, "NV12 chroma buffer");
    nv12.image.data_uv_bytes = uv.step * 240;
    EXPECT_EQ(sense(d, nv12, &sightings), WF_STATUS_OK) << wf_detector_last_error(d);  // the right sizes pass
    EXPECT_EQ(wf_detector_sense(d, nullptr, nullptr, 0, nullptr), WF_STATUS_INVALID_ARGUMENT);
    size_t count = 5;
    EXPECT_EQ(wf_detector_sense(d, &s.frame, nullptr, 4, &count), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(count, 0u);
    EXPECT_EQ(wf_detector_sense(nullptr, &s.frame, nullptr, 0, &count), WF_STATUS_INVALID_ARGUMENT);
    wf_detector_free(d);
}

TEST(Sense, CapacityTooSmallTruncatesToTheBest) {
    wf_detector* d = makeUnet({kExit});
    ASSERT_NE(d, nullptr);
    const Scene s = scene();
    size_t count = 7;
    EXPECT_EQ(wf_detector_sense(d, &s.frame, nullptr, 0, &count), WF_STATUS_TRUNCATED);
    EXPECT_EQ(count, 0u);
    wf_detector_free(d);
}

TEST(Sense, FaceEdgeRefinementIsOnByDefaultSwitchableAndValidated) {
    // The U-Net path on a 3 m sign: with the refiner (default) and without it (the mask's own edges) the range is
    // within 3 %; the refined slices come from the image (heights differ from the mask's). Bad values are errors
    // naming the option. (The refiner's accuracy and the too-tall box: test_face_edge_refiner.cpp.)
    const Scene s = scene(3.0);
    ASSERT_TRUE(s.truth.visible);
    auto make = [&](int refinement, int transfer, int* status) {
        wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
        opts.kind = WF_DETECTOR_UNET;
        const std::string path = wf::sign::testing::tinyUnetPath();
        opts.unet_path = path.c_str();
        opts.catalogue = &kExit;
        opts.catalogue_count = 1;
        opts.face_edge_refinement = refinement;
        opts.face_edge_transfer = transfer;
        wf_detector* d = nullptr;
        *status = wf_detector_create(&d, &opts);
        return d;
    };
    double heights[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
        int status = 0;
        wf_detector* d = make(i == 0 ? 0 : -1, 0, &status);
        ASSERT_NE(d, nullptr) << wf_thread_last_error();
        std::vector<wf_sign_sighting> sightings;
        ASSERT_EQ(sense(d, s.frame, &sightings), WF_STATUS_OK) << wf_detector_last_error(d);
        ASSERT_EQ(sightings.size(), 1u);
        EXPECT_NEAR(sightings[0].range_m, 3.0, 0.03 * 3.0) << (i == 0 ? "refined" : "mask");
        wf_detector_observation obs[4];
        size_t count = 0;
        ASSERT_EQ(wf_detector_detect(d, &s.frame, obs, 4, &count), WF_STATUS_OK);
        ASSERT_EQ(count, 1u);
        heights[i] = obs[0].median_height_px;
        wf_detector_free(d);
    }
    EXPECT_NE(heights[0], heights[1]);
    for (const auto& [refinement, transfer, field] :
         {std::tuple<int, int, const char*>{2, 0, "face_edge_refinement"}, {-2, 0, "face_edge_refinement"},
          {0, 3, "face_edge_transfer"}, {0, -1, "face_edge_transfer"}}) {
        int status = 0;
        EXPECT_EQ(make(refinement, transfer, &status), nullptr) << field;
        EXPECT_EQ(status, WF_STATUS_INVALID_ARGUMENT) << field;
        EXPECT_NE(std::string(wf_thread_last_error()).find(field), std::string::npos) << wf_thread_last_error();
    }
    int status = 0;
    wf_detector* srgb = make(1, 2, &status);
    EXPECT_EQ(status, WF_STATUS_OK) << wf_thread_last_error();
    wf_detector_free(srgb);
    // The U-Net's upsampling option (-1 OpenCV's layer, 0/1 sub-pixel): other values are errors naming it.
    for (const int value : {-1, 0, 1, 2, -2}) {
        wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
        opts.kind = WF_DETECTOR_UNET;
        const std::string path = wf::sign::testing::tinyUnetPath();
        opts.unet_path = path.c_str();
        opts.unet_transposed_convolution = value;
        wf_detector* d = nullptr;
        const int created = wf_detector_create(&d, &opts);
        if (value >= -1 && value <= 1) {
            EXPECT_EQ(created, WF_STATUS_OK) << value << ": " << wf_thread_last_error();
        } else {
            EXPECT_EQ(created, WF_STATUS_INVALID_ARGUMENT) << value;
            EXPECT_NE(std::string(wf_thread_last_error()).find("unet_transposed_convolution"), std::string::npos);
        }
        wf_detector_free(d);
    }
}
