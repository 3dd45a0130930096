// Tests of the C ABI (src/wf_sign_detector.cpp): options, handle lifetime, status codes and messages,
// pixel formats end to end, capacity handling, image reading.
#include "detector.hpp"
#include "wf_sign_detector.h"

#include "synthetic_scene.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace wf::sign;

namespace {

constexpr double kPi = 3.14159265358979323846;

wf_detector* makeUnet(double coarseMinElevationRad = 0) {
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.kind = WF_DETECTOR_UNET;
    opts.unet_coarse_min_elevation_rad = coarseMinElevationRad;
    const std::string path = wf::sign::testing::tinyUnetPath();
    opts.unet_path = path.c_str();
    wf_detector* d = nullptr;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    return d;
}

/// A portrait 1920 x 1440 BGR frame with a red-plate sign 3 m ahead.
struct PortraitFrame {
    synthetic::Camera camera;
    synthetic::RenderedSign truth;
    cv::Mat bgr;
};

PortraitFrame portraitFrame(double bottomAboveCameraMeters = 0.8) {
    PortraitFrame f;
    f.camera.pitchRad = 0.1;
    f.camera.rollRad = -kPi / 2;
    f.bgr = synthetic::renderBackground(f.camera, 21);
    synthetic::SignPlacement sign;
    sign.rangeMeters = 3;
    sign.bearingRad = 0.15;
    sign.bottomAboveCameraMeters = bottomAboveCameraMeters;
    sign.style = synthetic::SignStyle::WhiteLettersOnRed;
    f.truth = synthetic::drawSign(f.bgr, f.camera, sign);
    return f;
}

wf_frame frameOf(const PortraitFrame& f, const wf_image& image) {
    wf_frame frame{};
    frame.image = image;
    frame.intrinsics = wf_intrinsics{f.camera.fx, f.camera.fy, f.camera.cx, f.camera.cy};
    frame.pitch_rad = f.camera.pitchRad;
    frame.roll_rad = f.camera.rollRad;
    return frame;
}

/// A portrait VGA GRAY8 frame with a red sign 2.5 m ahead, 0.3 m above the camera (about 0.12 rad of elevation
/// for a level camera): on its side in the raw image; unrolling stands it up for the cascade. `frame` points
/// into `gray`.
struct GrayPortraitFrame {
    synthetic::Camera camera;
    synthetic::RenderedSign truth;
    cv::Mat gray;
    wf_frame frame{};
};

GrayPortraitFrame grayPortraitFrame() {
    GrayPortraitFrame f;
    f.camera.rollRad = -kPi / 2;
    f.camera = f.camera.resized({640, 480});
    cv::Mat bgr = synthetic::renderBackground(f.camera, 11);
    synthetic::SignPlacement sign;
    sign.rangeMeters = 2.5;
    sign.bottomAboveCameraMeters = 0.3;
    f.truth = synthetic::drawSign(bgr, f.camera, sign);
    cv::cvtColor(bgr, f.gray, cv::COLOR_BGR2GRAY);
    f.frame.image = wf_image{f.gray.data, f.gray.cols, f.gray.rows, f.gray.step, WF_PIXEL_GRAY8, nullptr, 0};
    f.frame.intrinsics = wf_intrinsics{f.camera.fx, f.camera.fy, f.camera.cx, f.camera.cy};
    f.frame.roll_rad = f.camera.rollRad;
    return f;
}

/// Full-range BT.601 NV12 planes of a BGR image (the inverse of the detector's conversion).
void toNv12(const cv::Mat& bgr, std::vector<uint8_t>* y, std::vector<uint8_t>* uv) {
    const int w = bgr.cols, h = bgr.rows;
    y->resize(size_t(w) * h);
    uv->resize(size_t(w) * (h / 2));
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const cv::Vec3b p = bgr.at<cv::Vec3b>(r, c);
            (*y)[size_t(r) * w + c] = cv::saturate_cast<uchar>(0.299 * p[2] + 0.587 * p[1] + 0.114 * p[0]);
        }
    for (int r = 0; r < h / 2; ++r)
        for (int c = 0; c < w / 2; ++c) {
            const cv::Vec3b p = bgr.at<cv::Vec3b>(2 * r, 2 * c);
            const double luma = 0.299 * p[2] + 0.587 * p[1] + 0.114 * p[0];
            (*uv)[size_t(r) * w + 2 * c] = cv::saturate_cast<uchar>(128 + (p[0] - luma) / 1.772);
            (*uv)[size_t(r) * w + 2 * c + 1] = cv::saturate_cast<uchar>(128 + (p[2] - luma) / 1.402);
        }
}

/// Default options (wf_detector_options_init) for one cascade at paths[0] (borrowed).
wf_detector_options cascadeOptions(const char* const* paths) {
    wf_detector_options opts;
    EXPECT_EQ(wf_detector_options_init(&opts), WF_STATUS_OK);
    opts.cascade_paths = paths;
    opts.cascade_count = 1;
    return opts;
}

/// wf_detector_create must refuse `bad` with WF_STATUS_INVALID_ARGUMENT, no handle, and an error naming `field`.
void expectRejected(const wf_detector_options& bad, const char* field) {
    wf_detector* d = nullptr;
    EXPECT_EQ(wf_detector_create(&d, &bad), WF_STATUS_INVALID_ARGUMENT) << field;
    EXPECT_EQ(d, nullptr);
    EXPECT_NE(std::string(wf_thread_last_error()).find(field), std::string::npos) << wf_thread_last_error();
}

}  // namespace

TEST(CApi, OptionsInitZeroesEveryField) {
    std::vector<unsigned char> bytes(sizeof(wf_detector_options), 0xAB);
    wf_detector_options* opts = reinterpret_cast<wf_detector_options*>(bytes.data());
    EXPECT_EQ(wf_detector_options_init(opts), WF_STATUS_OK);
    for (size_t i = 0; i < bytes.size(); ++i) ASSERT_EQ(bytes[i], 0) << "byte " << i;
    EXPECT_EQ(opts->kind, WF_DETECTOR_CASCADE);
    EXPECT_EQ(opts->catalogue_count, 0u);
    EXPECT_EQ(wf_detector_options_init(nullptr), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_STRNE(wf_sign_detector_version(), "");
}

TEST(CApi, UnetCoarseElevationCutIsValidatedAndCanBeTurnedOff) {
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.kind = WF_DETECTOR_UNET;
    const std::string path = wf::sign::testing::tinyUnetPath();
    opts.unet_path = path.c_str();
    opts.unet_coarse_min_elevation_rad = std::nan("");
    wf_detector* bad = nullptr;
    EXPECT_EQ(wf_detector_create(&bad, &opts), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_thread_last_error()).find("unet_coarse_min_elevation_rad"), std::string::npos);
    EXPECT_EQ(bad, nullptr);
    // A red plate 1.0 m below the camera at 3 m (elevation about -0.3 rad): skipped by the default cut, found
    // with the cut off. The sign above eye level is found either way.
    wf_detector* withCut = makeUnet();
    wf_detector* noCut = makeUnet(-2.0);
    ASSERT_NE(withCut, nullptr);
    ASSERT_NE(noCut, nullptr);
    for (const double bottomAboveCamera : {0.8, -1.0}) {
        const PortraitFrame f = portraitFrame(bottomAboveCamera);
        ASSERT_TRUE(f.truth.visible);
        cv::Mat rgb;
        cv::cvtColor(f.bgr, rgb, cv::COLOR_BGR2RGB);
        const wf_frame frame = frameOf(f, {rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0});
        wf_detector_observation obs[4];
        size_t count = 0;
        ASSERT_EQ(wf_detector_detect(noCut, &frame, obs, 4, &count), WF_STATUS_OK) << wf_detector_last_error(noCut);
        EXPECT_EQ(count, 1u) << "no cut, bottom " << bottomAboveCamera << " m above the camera";
        ASSERT_EQ(wf_detector_detect(withCut, &frame, obs, 4, &count), WF_STATUS_OK) << wf_detector_last_error(withCut);
        EXPECT_EQ(count, bottomAboveCamera > 0 ? 1u : 0u) << "cut, bottom " << bottomAboveCamera << " m above the camera";
    }
    wf_detector_free(withCut);
    wf_detector_free(noCut);
}

TEST(CApi, CreateErrorsLeaveNoHandleAndAMessage) {
    wf_detector* d = reinterpret_cast<wf_detector*>(0x1);
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    EXPECT_EQ(wf_detector_create(&d, nullptr), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(d, nullptr);
    EXPECT_EQ(wf_detector_create(nullptr, &opts), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_MODEL_LOAD);  // cascade with no path
    const char* missing = "/nonexistent/exit.xml";
    opts.cascade_paths = &missing;
    opts.cascade_count = 1;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_MODEL_LOAD);
    EXPECT_NE(std::string(wf_thread_last_error()).find(missing), std::string::npos);
    EXPECT_EQ(d, nullptr);
    opts.kind = WF_DETECTOR_UNET;
    opts.unet_path = "/nonexistent/sign_unet.onnx";
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_MODEL_LOAD);
    EXPECT_NE(std::string(wf_detector_last_error(nullptr)).find("sign_unet.onnx"), std::string::npos);
    wf_detector_free(nullptr);  // no-op
    wf_detector_options halfWindow = WF_DETECTOR_OPTIONS_INIT;
    halfWindow.cascade_min_window_width = 36;  // height left 0
    EXPECT_EQ(wf_detector_create(&d, &halfWindow), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_thread_last_error()).find("both"), std::string::npos);
    wf_detector_options badKind = WF_DETECTOR_OPTIONS_INIT;
    int bogus = 9;
    std::memcpy(&badKind.kind, &bogus, sizeof bogus);  // what a C caller may store
    EXPECT_EQ(wf_detector_create(&d, &badKind), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_thread_last_error()).find("unknown detector kind 9"), std::string::npos);
}

TEST(CApi, CascadeHandleReportsItsKinds) {
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    const std::string path = wf::sign::testing::referenceCascadePath();
    const char* paths[] = {path.c_str(), path.c_str()};
    const char* kinds[] = {"exit", "restroom"};
    opts.cascade_paths = paths;
    opts.cascade_kinds = kinds;
    opts.cascade_count = 2;
    wf_detector* d = nullptr;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    EXPECT_EQ(wf_detector_kind_count(d), 2u);
    EXPECT_STREQ(wf_detector_kind_name(d, 1), "restroom");
    EXPECT_EQ(wf_detector_kind_name(d, 2), nullptr);
    wf_detector_free(d);
}

TEST(CApi, UnetReadsClassesJsonNextToTheModel) {
    wf_detector* d = makeUnet();
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(wf_detector_kind_count(d), 1u);
    EXPECT_STREQ(wf_detector_kind_name(d, 0), "exit");
    wf_detector_free(d);
}

TEST(CApi, BadFramesAreRejectedWithAMessage) {
    wf_detector* d = makeUnet();
    ASSERT_NE(d, nullptr);
    std::vector<uint8_t> pixels(640 * 480, 100);
    wf_frame good{};
    good.image = wf_image{pixels.data(), 640, 480, 640, WF_PIXEL_GRAY8, nullptr, 0};
    good.intrinsics = wf_intrinsics{534, 534, 319.5, 239.5};
    good.roll_rad = -kPi / 2;
    wf_detector_observation obs[4];
    size_t count = 99;
    EXPECT_EQ(wf_detector_detect(d, &good, obs, 4, &count), WF_STATUS_OK) << wf_detector_last_error(d);
    EXPECT_EQ(count, 0u);

    const double nan = std::numeric_limits<double>::quiet_NaN();
    struct Case {
        const char* name;
        void (*mutate)(wf_frame&);
        int status;
        const char* fragment;
    };
    const Case cases[] = {
        {"empty", [](wf_frame& f) { f.image.data = nullptr; }, WF_STATUS_BAD_FRAME, "empty"},
        {"zero size", [](wf_frame& f) { f.image.height = 0; }, WF_STATUS_BAD_FRAME, "empty"},
        {"wrong size", [](wf_frame& f) { f.intrinsics = {1602, 1602, 959.5, 719.5}; }, WF_STATUS_BAD_FRAME, "resolution"},
        {"nan fx", [](wf_frame& f) { f.intrinsics.fx = std::numeric_limits<double>::quiet_NaN(); }, WF_STATUS_BAD_FRAME, "intrinsics"},
        {"nan pitch", [](wf_frame& f) { f.pitch_rad = std::numeric_limits<double>::quiet_NaN(); }, WF_STATUS_BAD_FRAME, "pitch"},
        {"nan roll", [](wf_frame& f) { f.roll_rad = std::numeric_limits<double>::quiet_NaN(); }, WF_STATUS_BAD_FRAME, "roll"},
    };
    (void)nan;
    for (const Case& c : cases) {
        wf_frame f = good;
        c.mutate(f);
        count = 99;
        EXPECT_EQ(wf_detector_detect(d, &f, obs, 4, &count), c.status) << c.name;
        EXPECT_EQ(count, 0u) << c.name;
        EXPECT_NE(std::string(wf_detector_last_error(d)).find(c.fragment), std::string::npos)
            << c.name << ": " << wf_detector_last_error(d);
    }
    std::vector<uint8_t> black(640 * 480, 0);
    wf_frame dark = good;
    dark.image.data = black.data();
    EXPECT_EQ(wf_detector_detect(d, &dark, obs, 4, &count), WF_STATUS_SKIPPED_DARK_FRAME);
    EXPECT_NE(std::string(wf_detector_last_error(d)).find("mean luma"), std::string::npos);
    EXPECT_EQ(wf_detector_detect(d, nullptr, obs, 4, &count), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_detector_detect(d, &good, nullptr, 4, &count), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_detector_detect(d, &good, obs, 4, nullptr), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_detector_detect(nullptr, &good, obs, 4, &count), WF_STATUS_INVALID_ARGUMENT);
    wf_detector_free(d);
}

TEST(CApi, EveryPixelFormatFindsThePortraitSign) {
    wf_detector* d = makeUnet();
    ASSERT_NE(d, nullptr);
    const PortraitFrame f = portraitFrame();
    ASSERT_TRUE(f.truth.visible);
    cv::Mat rgb, bgra;
    cv::cvtColor(f.bgr, rgb, cv::COLOR_BGR2RGB);
    cv::cvtColor(f.bgr, bgra, cv::COLOR_BGR2BGRA);
    std::vector<uint8_t> y, uv;
    toNv12(f.bgr, &y, &uv);
    const wf_image images[] = {
        {rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0},
        {bgra.data, bgra.cols, bgra.rows, bgra.step, WF_PIXEL_BGRA8, nullptr, 0},
        {y.data(), f.bgr.cols, f.bgr.rows, size_t(f.bgr.cols), WF_PIXEL_NV12, uv.data(), size_t(f.bgr.cols)},
    };
    cv::Point2d truthCentre(0, 0);
    for (const auto& p : f.truth.cornersRaw) truthCentre += 0.25 * p;
    for (const wf_image& image : images) {
        const wf_frame frame = frameOf(f, image);
        wf_detector_observation obs[4];
        size_t count = 0;
        ASSERT_EQ(wf_detector_detect(d, &frame, obs, 4, &count), WF_STATUS_OK) << wf_detector_last_error(d);
        ASSERT_EQ(count, 1u) << "format " << image.format;
        const wf_detector_observation& o = obs[0];
        EXPECT_STREQ(o.kind, "exit");
        EXPECT_EQ(o.kind_index, 1);
        EXPECT_EQ(o.unrolled_width, 1440);
        EXPECT_EQ(o.unrolled_height, 1920);
        EXPECT_DOUBLE_EQ(o.unrolled_fx, f.camera.fy);
        EXPECT_DOUBLE_EQ(o.unrolled_cx, 1440 - 1 - f.camera.cy);
        EXPECT_DOUBLE_EQ(o.unrolled_cy, f.camera.cx);
        EXPECT_DOUBLE_EQ(o.applied_roll_rad, -kPi / 2);
        // The observation's centre mapped back to raw pixels lands on the drawn sign's centre.
        const double uc = o.center_column_px, vc = o.median_bottom_row_px - 0.5 * o.median_height_px;
        const double* m = o.unrolled_to_raw;
        EXPECT_NEAR(m[0] * uc + m[1] * vc + m[2], truthCentre.x, 3.0);
        EXPECT_NEAR(m[3] * uc + m[4] * vc + m[5], truthCentre.y, 3.0);
        // Apparent height: the drawn sign's left and right edges (raw pixels; a quarter turn keeps lengths).
        const double truthHeight = 0.5 * (cv::norm(f.truth.cornersRaw[3] - f.truth.cornersRaw[0]) +
                                          cv::norm(f.truth.cornersRaw[2] - f.truth.cornersRaw[1]));
        EXPECT_NEAR(o.median_height_px, truthHeight, 3.0);
        EXPECT_GT(o.slice_count, 30);  // slices are network-mask columns of the zoomed crop
    }
    wf_detector_free(d);
}

TEST(CApi, ReferenceCascadeFindsADrawnSignInAPortraitFrame) {
    const GrayPortraitFrame g = grayPortraitFrame();
    const synthetic::RenderedSign& truth = g.truth;
    ASSERT_TRUE(truth.visible);
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    const std::string path = wf::sign::testing::referenceCascadePath();
    const char* paths[] = {path.c_str()};
    opts.cascade_paths = paths;
    opts.cascade_count = 1;
    opts.cascade_min_neighbors = 1;
    wf_detector* d = nullptr;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    const wf_frame frame = g.frame;
    wf_detector_observation obs[8];
    size_t count = 0;
    ASSERT_EQ(wf_detector_detect(d, &frame, obs, 8, &count), WF_STATUS_OK) << wf_detector_last_error(d);
    ASSERT_GE(count, 1u);
    // The best box, mapped back to raw pixels, covers the drawn sign's centre.
    cv::Point2d centre(0, 0);
    for (const auto& p : truth.cornersRaw) centre += 0.25 * p;
    const double* m = obs[0].unrolled_to_raw;
    const double uc = obs[0].box_x + 0.5 * obs[0].box_width, vc = obs[0].box_y + 0.5 * obs[0].box_height;
    EXPECT_NEAR(m[0] * uc + m[1] * vc + m[2], centre.x, 0.5 * obs[0].box_height);
    EXPECT_NEAR(m[3] * uc + m[4] * vc + m[5], centre.y, 0.5 * obs[0].box_width);
    EXPECT_STREQ(obs[0].kind, "exit");
    // Face-edge refinement (default): the slices measure the drawn face (unrolled v = raw u for this portrait
    // frame), not the box; without it every slice has the box's height and no slope.
    const double faceHeight = 0.5 * ((truth.cornersRaw[3].x - truth.cornersRaw[0].x) + (truth.cornersRaw[2].x - truth.cornersRaw[1].x));
    const double refinedHeight = obs[0].median_height_px;
    EXPECT_NEAR(refinedHeight, faceHeight, 0.03 * faceHeight) << "box height " << obs[0].box_height;
    wf_detector_free(d);
    wf_detector_options rough = opts;
    rough.face_edge_refinement = -1;
    ASSERT_EQ(wf_detector_create(&d, &rough), WF_STATUS_OK) << wf_thread_last_error();
    ASSERT_EQ(wf_detector_detect(d, &frame, obs, 8, &count), WF_STATUS_OK) << wf_detector_last_error(d);
    ASSERT_GE(count, 1u);
    EXPECT_EQ(obs[0].bottom_edge_slope, 0.0);
    EXPECT_EQ(obs[0].median_height_px, obs[0].box_height);
    EXPECT_LT(std::abs(refinedHeight - faceHeight), std::abs(obs[0].median_height_px - faceHeight));
    wf_detector_free(d);

    // Searching only above -0.15 rad of elevation keeps the sign (0.3 m above the camera at 2.5 m).
    opts.cascade_search_above_elevation = 1;
    opts.cascade_min_elevation_rad = -0.15;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    size_t restricted = 0;
    ASSERT_EQ(wf_detector_detect(d, &frame, obs, 8, &restricted), WF_STATUS_OK);
    EXPECT_GE(restricted, 1u);
    EXPECT_LE(restricted, count);
    // ... and 0.3 rad above the horizon (the sign is at about 0.12 rad) loses it.
    wf_detector_free(d);
    opts.cascade_min_elevation_rad = 0.3;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK);
    ASSERT_EQ(wf_detector_detect(d, &frame, obs, 8, &restricted), WF_STATUS_OK);
    EXPECT_EQ(restricted, 0u);
    wf_detector_free(d);
    opts.cascade_min_elevation_rad = 2.0;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_INVALID_ARGUMENT);
}

TEST(CApi, CascadeSearchesAboveMinus015RadByDefault) {
    // The sign is about 0.12 rad above the horizon for a level camera; handed over with a pitch of -0.5 rad, its
    // rows lie at about -0.38 rad, below the default limit.
    const GrayPortraitFrame g = grayPortraitFrame();
    ASSERT_TRUE(g.truth.visible);
    const wf_frame frame = g.frame;
    const std::string path = wf::sign::testing::referenceCascadePath();
    const char* paths[] = {path.c_str()};
    auto found = [&](int searchAbove, double pitch) {
        wf_detector_options opts;
        EXPECT_EQ(wf_detector_options_init(&opts), WF_STATUS_OK);
        opts.cascade_paths = paths;
        opts.cascade_count = 1;
        opts.cascade_min_neighbors = 1;
        opts.cascade_search_above_elevation = searchAbove;
        opts.cascade_placement_prior = -1;  // off: this test isolates the row limit
        wf_detector* d = nullptr;
        EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
        if (d == nullptr) return size_t(99);
        wf_frame f = frame;
        f.pitch_rad = pitch;
        wf_detector_observation obs[8];
        size_t count = 0;
        EXPECT_EQ(wf_detector_detect(d, &f, obs, 8, &count), WF_STATUS_OK) << wf_detector_last_error(d);
        wf_detector_free(d);
        return count;
    };
    EXPECT_GE(found(0, 0.0), 1u);          // level camera: the sign is above the default limit
    EXPECT_EQ(found(0, -0.5), 0u);         // default: rows below -0.15 rad are not searched
    EXPECT_GE(found(-1, -0.5), 1u);        // -1: the whole frame
    wf_detector_options bad;
    ASSERT_EQ(wf_detector_options_init(&bad), WF_STATUS_OK);
    bad.cascade_paths = paths;
    bad.cascade_count = 1;
    bad.cascade_search_above_elevation = 2;
    wf_detector* d = nullptr;
    EXPECT_EQ(wf_detector_create(&d, &bad), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_thread_last_error()).find("cascade_search_above_elevation"), std::string::npos);
}

TEST(CApi, PlacementPriorAndCrowdedGateAreDefaultsAndValidated) {
    // The drawn sign's centre is about 0.4 m above the camera: inside the default prior (0.3 .. 2.0 m), outside a
    // prior for signs hung 1.5 .. 2.0 m above it.
    const GrayPortraitFrame g = grayPortraitFrame();
    ASSERT_TRUE(g.truth.visible);
    const std::string path = wf::sign::testing::referenceCascadePath();
    const char* paths[] = {path.c_str()};
    auto options = [&]() {
        wf_detector_options opts = cascadeOptions(paths);
        opts.cascade_min_neighbors = 1;
        return opts;
    };
    auto found = [&](const wf_detector_options& opts) {
        wf_detector* d = nullptr;
        EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
        if (d == nullptr) return size_t(99);
        const wf_frame frame = g.frame;
        wf_detector_observation obs[8];
        size_t count = 0;
        EXPECT_EQ(wf_detector_detect(d, &frame, obs, 8, &count), WF_STATUS_OK) << wf_detector_last_error(d);
        wf_detector_free(d);
        return count;
    };
    wf_detector_options opts = options();
    EXPECT_GE(found(opts), 1u);  // defaults: prior on, sign inside it
    opts.cascade_sign_above_camera_min_m = 1.5;
    EXPECT_EQ(found(opts), 0u);  // the sign hangs below this prior's band
    opts.cascade_placement_prior = -1;
    EXPECT_GE(found(opts), 1u);  // prior off: every row

    wf_detector_options bad = options();
    bad.cascade_placement_prior = 2;
    expectRejected(bad, "cascade_placement_prior");
    bad = options();
    bad.cascade_sign_above_camera_min_m = 2.5;  // above the default maximum of 2.0
    expectRejected(bad, "cascade_sign_above_camera_min_m");
    bad = options();
    bad.cascade_sign_above_camera_max_m = std::nan("");
    expectRejected(bad, "cascade_sign_above_camera_min_m and _max_m");
    bad = options();
    bad.cascade_gate_crowded_contrast_factor = 0.5;
    expectRejected(bad, "cascade_gate_crowded_contrast_factor");
    bad.cascade_gate_crowded_contrast_factor = 1.0;  // off is valid
    EXPECT_GE(found(bad), 1u);
}

TEST(CApi, GateMarginAndComponentWindowAreDefaultsAndValidated) {
    const std::string path = wf::sign::testing::referenceCascadePath();
    const char* paths[] = {path.c_str()};
    auto options = [&]() { return cascadeOptions(paths); };
    auto resolved = [](const wf_detector_options& opts) {
        wf::sign::ResolvedOptions r;
        std::string error;
        EXPECT_EQ(wf::sign::ResolvedOptions::fromOptions(opts, &r, &error), WF_STATUS_OK) << error;
        return r.cascade.colourGate;
    };
    // Defaults: 16-pixel margins, windows of at least 0.4 x a large component's width in its tiles, the
    // crowded-frame gate at 2.5 x the contrast, the placement prior on.
    const wf::sign::ColourGateParams defaults = resolved(options());
    EXPECT_EQ(defaults.minMarginPx, 16);
    EXPECT_DOUBLE_EQ(defaults.componentWindowFraction, 0.4);
    EXPECT_DOUBLE_EQ(defaults.crowdedContrastFactor, 2.5);
    EXPECT_TRUE(defaults.enabled);
    wf_detector_options set = options();
    set.cascade_gate_min_margin_px = 30;
    set.cascade_gate_component_window_fraction = -1;  // off
    EXPECT_EQ(resolved(set).minMarginPx, 30);
    EXPECT_DOUBLE_EQ(resolved(set).componentWindowFraction, 0.0);
    set.cascade_gate_component_window_fraction = 0.7;
    EXPECT_DOUBLE_EQ(resolved(set).componentWindowFraction, 0.7);

    wf_detector_options bad = options();
    bad.cascade_gate_min_margin_px = -1;
    expectRejected(bad, "cascade_gate_min_margin_px");
    for (const double fraction : {1.5, -0.5, std::nan("")}) {
        bad = options();
        bad.cascade_gate_component_window_fraction = fraction;
        expectRejected(bad, "cascade_gate_component_window_fraction");
    }
}

TEST(CApi, CapacityTooSmallTruncates) {
    wf_detector* d = makeUnet();
    ASSERT_NE(d, nullptr);
    const PortraitFrame f = portraitFrame();
    cv::Mat rgb;
    cv::cvtColor(f.bgr, rgb, cv::COLOR_BGR2RGB);
    const wf_frame frame = frameOf(f, {rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0});
    size_t count = 5;
    EXPECT_EQ(wf_detector_detect(d, &frame, nullptr, 0, &count), WF_STATUS_TRUNCATED);
    EXPECT_EQ(count, 0u);
    EXPECT_NE(std::string(wf_detector_last_error(d)).find("capacity"), std::string::npos);
    wf_detector_free(d);
}

TEST(CApi, ImageReadDecodesFilesAndNamesMissingOnes) {
    const std::string path = ::testing::TempDir() + "wf_image_read_test.png";
    cv::Mat bgr(3, 5, CV_8UC3, cv::Scalar(10, 20, 30));
    ASSERT_TRUE(cv::imwrite(path, bgr));
    wf_owned_image image;
    ASSERT_EQ(wf_image_read(&image, path.c_str(), WF_PIXEL_RGB8), WF_STATUS_OK) << wf_thread_last_error();
    EXPECT_EQ(image.width, 5);
    EXPECT_EQ(image.height, 3);
    EXPECT_EQ(image.stride, 15u);
    EXPECT_EQ(image.data[0], 30);  // R first
    EXPECT_EQ(image.data[2], 10);
    wf_owned_image_free(&image);
    EXPECT_EQ(image.data, nullptr);
    wf_owned_image_free(nullptr);
    ASSERT_EQ(wf_image_read(&image, path.c_str(), WF_PIXEL_GRAY8), WF_STATUS_OK);
    EXPECT_EQ(image.stride, 5u);
    wf_owned_image_free(&image);
    EXPECT_EQ(wf_image_read(&image, "/nonexistent/frame.png", WF_PIXEL_RGB8), WF_STATUS_IMAGE_READ);
    EXPECT_NE(std::string(wf_thread_last_error()).find("/nonexistent/frame.png"), std::string::npos);
    EXPECT_EQ(wf_image_read(&image, path.c_str(), WF_PIXEL_NV12), WF_STATUS_INVALID_ARGUMENT);
    std::remove(path.c_str());
}
