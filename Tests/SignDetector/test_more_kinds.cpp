// Tests of the sign kinds beyond the Exit sign (issue 16 section 3; docs/sign-detection.md "More sign kinds"):
// the catalogue's placement, range and text fields, cascades of non-Exit kinds searched without the colour gate
// on their own placement band and range limit (at VGA whatever the frame's size), cascades beside the U-Net, and
// the text reader behind wf_detector_reads_text.
#include "detector.hpp"
#include "wf_sign_detector.h"

#include "synthetic_scene.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

using namespace wf::sign;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A portrait BGR frame (`size`, default 640 x 480) with the synthetic Exit-style sign (0.33 x 0.21 m, red letters on
/// white) 2.5 m ahead, its bottom edge 0.3 m above the camera: centre 0.405 m above it.
struct Frame {
    synthetic::Camera camera;
    synthetic::RenderedSign truth;
    cv::Mat bgr;
    wf_frame frame{};
};

Frame frameWithSign(cv::Size size = {640, 480}, double rollRad = -kPi / 2) {
    Frame f;
    f.camera.rollRad = rollRad;
    f.camera.pitchRad = 0.05;
    f.camera = f.camera.resized(size);
    f.bgr = synthetic::renderBackground(f.camera, 11);
    synthetic::SignPlacement sign;
    sign.rangeMeters = 2.5;
    sign.bottomAboveCameraMeters = 0.3;
    f.truth = synthetic::drawSign(f.bgr, f.camera, sign);
    cv::cvtColor(f.bgr, f.bgr, cv::COLOR_BGR2RGB);
    f.frame.image = wf_image{f.bgr.data, f.bgr.cols, f.bgr.rows, f.bgr.step, WF_PIXEL_RGB8, nullptr, 0};
    f.frame.intrinsics = wf_intrinsics{f.camera.fx, f.camera.fy, f.camera.cx, f.camera.cy};
    f.frame.pitch_rad = f.camera.pitchRad;
    f.frame.roll_rad = f.camera.rollRad;
    return f;
}

/// A pictogram-like kind ("restroom", white on blue: not Exit-like, so searched without the colour gate) with the
/// synthetic sign's size, placed `bandMin`..`bandMax` above the camera, recognised out to `maxRange` m.
wf_sign_kind restroomKind(double bandMin, double bandMax, double maxRange, int readsText = 0) {
    wf_sign_kind k{};
    k.kind = "restroom";
    k.face_height_m = 0.21;
    k.face_width_m = 0.33;
    k.face_colour = "blue";
    k.legend_colour = "white";
    k.centre_above_camera_min_m = bandMin;
    k.centre_above_camera_max_m = bandMax;
    k.max_range_m = maxRange;
    k.reads_text = readsText;
    return k;
}

/// Points `o` at `n` cascades (`paths`, registered as `kinds`, min neighbours 1) and a catalogue of `m` kinds.
void useCascades(wf_detector_options& o, const char* const* paths, const char* const* kinds, size_t n,
                 const wf_sign_kind* catalogue, size_t m) {
    o.cascade_paths = paths;
    o.cascade_kinds = kinds;
    o.cascade_count = n;
    o.cascade_min_neighbors = 1;
    o.catalogue = catalogue;
    o.catalogue_count = m;
}

/// Options of the tiny three-class U-Net with the reference cascade beside it as "restroom" (min neighbours 1), the
/// catalogue an Exit sign and restroomKind(0.1, 0.7, 0). Holds the strings the options point to: not copyable.
struct UnetWithRestroom {
    std::string unet = wf::sign::testing::tinyUnetPath(), cascade = wf::sign::testing::referenceCascadePath();
    const char* paths[1] = {cascade.c_str()};
    const char* kinds[1] = {"restroom"};
    wf_sign_kind catalogue[2] = {{"exit", 0.21, 0.33, "red", "white", 0, 0, 0, 0, 0}, restroomKind(0.1, 0.7, 0)};
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    UnetWithRestroom() {
        opts.kind = WF_DETECTOR_UNET;
        opts.unet_path = unet.c_str();
        useCascades(opts, paths, kinds, 1, catalogue, 2);
    }
    UnetWithRestroom(const UnetWithRestroom&) = delete;
    UnetWithRestroom& operator=(const UnetWithRestroom&) = delete;
};

/// A cascade detector (the reference Exit cascade, registered as `kind`) with `catalogue`; nullptr on failure.
wf_detector* cascadeDetector(const char* kind, const std::vector<wf_sign_kind>& catalogue) {
    static const std::string path = wf::sign::testing::referenceCascadePath();
    static const char* paths[] = {path.c_str()};
    const char* kinds[] = {kind};
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.cascade_paths = paths;
    opts.cascade_kinds = kinds;
    opts.cascade_count = 1;
    opts.cascade_min_neighbors = 1;
    opts.catalogue = catalogue.data();
    opts.catalogue_count = catalogue.size();
    opts.cascade_wall_kind_frame_period = 1;  // every frame: these tests look at what one frame finds
    wf_detector* d = nullptr;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    return d;
}

std::vector<wf_sign_sighting> sense(wf_detector* d, const wf_frame& frame) {
    std::vector<wf_sign_sighting> out(16);
    size_t count = 0;
    EXPECT_GE(wf_detector_sense(d, &frame, out.data(), out.size(), &count), 0) << wf_detector_last_error(d);
    out.resize(count);
    return out;
}

/// How many sightings a cascade detector of the one kind `kind` (the reference cascade) makes of `f`.
size_t sightingCount(const Frame& f, const wf_sign_kind& kind) {
    wf_detector* d = cascadeDetector(kind.kind, {kind});
    const size_t n = sense(d, f.frame).size();
    wf_detector_free(d);
    return n;
}

/// Checks a cascade sighting's corners against the drawn face of `f` (a portrait frame: the raw x axis runs along
/// the face's height, raw y along its width). The top and bottom edges are the face-edge refiner's: to a few VGA
/// pixels (12 raw px on a 1920 x 1440 frame). The side edges are the cascade window's, which covers about 1.1 x the
/// face or more (the plate gate searches fewer windows around the face than the whole band, so the grouped box can
/// sit to one side): to those 12 px plus a tenth of the face's width.
void expectCornersOnThePortraitFace(const wf_sign_sighting& s, const Frame& f) {
    const double faceWidthPx = std::abs(f.truth.cornersRaw[3].y - f.truth.cornersRaw[2].y) +
                               std::abs(f.truth.cornersRaw[0].y - f.truth.cornersRaw[1].y);  // both sides: 2 x width
    for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(s.corners_raw_px[2 * i], f.truth.cornersRaw[i].x, 12) << i;
        EXPECT_NEAR(s.corners_raw_px[2 * i + 1], f.truth.cornersRaw[i].y, 12 + 0.05 * faceWidthPx) << i;
    }
}

}  // namespace

TEST(MoreKindsCatalogue, PlacementRangeAndTextFieldsAreValidatedNamingTheField) {
    struct Case {
        wf_sign_kind kind;
        const char* field;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Case cases[] = {
        {restroomKind(0.6, 0.2, 0), "centre_above_camera_min_m"},
        {restroomKind(0.2, nan, 0), "centre_above_camera_min_m"},
        {restroomKind(0, 0, -1), "max_range_m"},
        {restroomKind(0, 0, nan), "max_range_m"},
        {restroomKind(0, 0, 0, 2), "reads_text"},
    };
    for (const Case& c : cases) {
        std::vector<SignKindSpec> out;
        std::string error;
        EXPECT_EQ(parseCatalogue(&c.kind, 1, &out, &error), WF_STATUS_INVALID_CATALOGUE) << c.field;
        EXPECT_NE(error.find(c.field), std::string::npos) << error;
        EXPECT_NE(error.find("restroom"), std::string::npos) << error;
    }
    // Two entries of one kind that disagree about where it hangs contradict each other.
    const wf_sign_kind two[] = {restroomKind(-0.4, 0.6, 6), restroomKind(-0.4, 0.7, 6)};
    std::vector<SignKindSpec> out;
    std::string error;
    EXPECT_EQ(parseCatalogue(two, 2, &out, &error), WF_STATUS_INVALID_CATALOGUE);
    // A good entry is copied whole.
    const wf_sign_kind good = restroomKind(-0.4, 0.6, 6, 1);
    ASSERT_EQ(parseCatalogue(&good, 1, &out, &error), WF_STATUS_OK) << error;
    EXPECT_EQ(out[0].centreAboveCameraMinMeters, -0.4);
    EXPECT_EQ(out[0].centreAboveCameraMaxMeters, 0.6);
    EXPECT_EQ(out[0].maxRangeMeters, 6);
    EXPECT_TRUE(out[0].readsText);
    EXPECT_FALSE(out[0].colourGated());
}

TEST(MoreKindsCatalogue, OnlyExitLikeKindsAreColourGated) {
    SignKindSpec s;
    EXPECT_TRUE(s.colourGated());  // colours unknown: searched like an Exit sign
    s.faceColour = "white";
    s.legendColour = "red";
    EXPECT_TRUE(s.colourGated());
    s.faceColour = "green";
    s.legendColour = "white";
    EXPECT_TRUE(s.colourGated());  // ISO running man
    s.faceColour = "blue";
    EXPECT_FALSE(s.colourGated());  // a restroom pictogram
    s.faceColour = "dark";
    EXPECT_FALSE(s.colourGated());  // a room-number placard
}

TEST(MoreKinds, APictogramKindIsFoundOnItsPlacementBandOnly) {
    const Frame f = frameWithSign();
    ASSERT_TRUE(f.truth.visible);
    // The sign's centre is 0.405 m above the camera: a band around it finds it, one 1.5-2.5 m up does not.
    wf_detector* d = cascadeDetector("restroom", {restroomKind(0.1, 0.7, 0)});
    const std::vector<wf_sign_sighting> seen = sense(d, f.frame);
    ASSERT_GE(seen.size(), 1u);
    EXPECT_STREQ(seen[0].kind, "restroom");
    EXPECT_NEAR(seen[0].range_m, 2.5, 0.25);
    EXPECT_NEAR(seen[0].center_height_above_camera_m, 0.405, 0.08);
    EXPECT_STREQ(seen[0].text, "");
    wf_detector_free(d);
    EXPECT_EQ(sightingCount(f, restroomKind(1.5, 2.5, 0)), 0u);
}

TEST(MoreKinds, APictogramKindIsNotSearchedBeyondItsRange) {
    const Frame f = frameWithSign();
    // Out to 4 m the 2.5 m sign is searched; out to 1.5 m its face (about 45 px) is below the smallest window.
    EXPECT_GE(sightingCount(f, restroomKind(0.1, 0.7, 4)), 1u);
    EXPECT_EQ(sightingCount(f, restroomKind(0.1, 0.7, 1.5)), 0u);
}

TEST(MoreKinds, ExitKindsIgnoreTheirCatalogueBandAndKeepTheGate) {
    // The same cascade as "exit" (Exit-like colours): searched through the colour gate with the detector's own
    // placement prior, whatever band its entry states.
    const Frame f = frameWithSign();
    wf_sign_kind exit = restroomKind(1.5, 2.5, 0);
    exit.kind = "exit";
    exit.face_colour = "red";
    wf_detector* d = cascadeDetector("exit", {exit});
    const std::vector<wf_sign_sighting> seen = sense(d, f.frame);
    ASSERT_GE(seen.size(), 1u);
    EXPECT_STREQ(seen[0].kind, "exit");
    wf_detector_free(d);
}

TEST(MoreKinds, HighResolutionFramesAreSearchedAtVgaAndBoxesMapBack) {
    const Frame vga = frameWithSign();
    const Frame hr = frameWithSign({1920, 1440});
    wf_detector* d = cascadeDetector("restroom", {restroomKind(0.1, 0.7, 0)});
    const std::vector<wf_sign_sighting> a = sense(d, vga.frame), b = sense(d, hr.frame);
    ASSERT_GE(a.size(), 1u);
    ASSERT_GE(b.size(), 1u);
    EXPECT_NEAR(b[0].range_m, 2.5, 0.2);
    // Corners land on the drawn face in the 1920 x 1440 frame.
    expectCornersOnThePortraitFace(b[0], hr);
    wf_detector_free(d);
}

TEST(MoreKinds, CascadesRunBesideTheUnetForKindsItHasNoClassFor) {
    UnetWithRestroom setup;
    wf_detector_options& opts = setup.opts;
    opts.cascade_wall_kind_frame_period = 1;  // the same frame detected several times below
    wf_detector* d = nullptr;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    ASSERT_EQ(wf_detector_kind_count(d), 2u);
    EXPECT_STREQ(wf_detector_kind_name(d, 0), "exit");
    EXPECT_STREQ(wf_detector_kind_name(d, 1), "restroom");
    const Frame hr = frameWithSign({1920, 1440});
    std::vector<wf_detector_observation> obs(16);
    size_t count = 0;
    ASSERT_GE(wf_detector_detect(d, &hr.frame, obs.data(), obs.size(), &count), 0) << wf_detector_last_error(d);
    bool restroomSeen = false;
    for (size_t i = 0; i < count; ++i) {
        if (std::string(obs[i].kind) == "restroom") {
            restroomSeen = true;
            EXPECT_EQ(obs[i].kind_index, 2);  // after the U-Net's background and exit classes
        }
    }
    EXPECT_TRUE(restroomSeen);
    // Searched on the frame shrunk to VGA and unrolled there, measured on the frame: the restroom sighting's range
    // and corners are those of the drawn face in the 1920 x 1440 frame (to a few VGA pixels, 3 x as many here).
    std::vector<wf_sign_sighting> sightings(16);
    ASSERT_GE(wf_detector_sense(d, &hr.frame, sightings.data(), sightings.size(), &count), 0) << wf_detector_last_error(d);
    sightings.resize(count);
    const auto restroomSighting = std::find_if(sightings.begin(), sightings.end(),
                                               [](const wf_sign_sighting& s) { return std::string(s.kind) == "restroom"; });
    ASSERT_NE(restroomSighting, sightings.end());
    EXPECT_NEAR(restroomSighting->range_m, 2.5, 0.2);
    expectCornersOnThePortraitFace(*restroomSighting, hr);
    // The phone's frame (BGRA, App/iOS/Sensors/PixelBufferTools.swift) reaches the U-Net without a whole-frame RGB
    // copy and the plain kinds through a gray copy: the same observations, to the bit, as the RGB frame gives.
    cv::Mat bgra;
    cv::cvtColor(hr.bgr, bgra, cv::COLOR_RGB2BGRA);
    wf_frame phone = hr.frame;
    phone.image = wf_image{bgra.data, bgra.cols, bgra.rows, bgra.step, WF_PIXEL_BGRA8, nullptr, 0};
    std::vector<wf_detector_observation> phoneObs(16);
    size_t phoneCount = 0;
    ASSERT_GE(wf_detector_detect(d, &hr.frame, obs.data(), obs.size(), &count), 0) << wf_detector_last_error(d);
    ASSERT_GE(wf_detector_detect(d, &phone, phoneObs.data(), phoneObs.size(), &phoneCount), 0) << wf_detector_last_error(d);
    ASSERT_EQ(phoneCount, count);
    for (size_t i = 0; i < count; ++i) {
        EXPECT_STREQ(phoneObs[i].kind, obs[i].kind) << i;
        EXPECT_EQ(phoneObs[i].score, obs[i].score) << i;
        EXPECT_EQ(phoneObs[i].median_height_px, obs[i].median_height_px) << i;
        EXPECT_EQ(phoneObs[i].median_bottom_row_px, obs[i].median_bottom_row_px) << i;
        EXPECT_EQ(phoneObs[i].center_column_px, obs[i].center_column_px) << i;
    }
    wf_detector_free(d);
    // The default schedule (wall kinds on every second frame): the U-Net's class is looked for on every frame, the
    // cascade beside it on one frame in two (its index after the U-Net's classes).
    opts.cascade_wall_kind_frame_period = 0;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    for (int frame = 0; frame < 3; ++frame) {
        ASSERT_GE(wf_detector_detect(d, &hr.frame, obs.data(), obs.size(), &count), 0) << wf_detector_last_error(d);
        EXPECT_EQ(wf_detector_kind_searched(d, 0), 1) << frame;
        EXPECT_EQ(wf_detector_kind_searched(d, 1), frame % 2 == 0 ? 1 : 0) << frame;
    }
    wf_detector_free(d);
    // A cascade of a kind the U-Net already has is refused, naming the kind.
    const char* exit[] = {"exit"};
    opts.cascade_kinds = exit;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_MODEL_LOAD);
    EXPECT_EQ(d, nullptr);
    EXPECT_NE(std::string(wf_thread_last_error()).find("'exit'"), std::string::npos) << wf_thread_last_error();
}

TEST(MoreKinds, AUnetClassOfAnEyeLevelKindIsSearchedBelowTheExitCutWithItsOwnLimits) {
    // The tiny three-class U-Net reports the drawn sign (a red plate) as "restroom". Its bottom edge 1 m below the
    // camera 2.5 m away, its centre at -0.34 rad elevation, it lies under the coarse pass's Exit-sign cut (-0.10 rad,
    // rounded down by up to 32 network rows: about 0.17 rad at this frame's scale).
    const std::string unet = wf::sign::testing::tinyKindsUnetPath();
    Frame f;
    f.camera.rollRad = -kPi / 2;
    f.camera.pitchRad = 0.05;
    f.camera = f.camera.resized({1920, 1440});
    f.bgr = synthetic::renderBackground(f.camera, 11);
    synthetic::SignPlacement placement;
    placement.rangeMeters = 2.5;
    placement.bottomAboveCameraMeters = -1.0;
    placement.style = synthetic::SignStyle::WhiteLettersOnRed;
    f.truth = synthetic::drawSign(f.bgr, f.camera, placement);
    ASSERT_TRUE(f.truth.visible);
    cv::cvtColor(f.bgr, f.bgr, cv::COLOR_BGR2RGB);
    f.frame.image = wf_image{f.bgr.data, f.bgr.cols, f.bgr.rows, f.bgr.step, WF_PIXEL_RGB8, nullptr, 0};
    f.frame.intrinsics = wf_intrinsics{f.camera.fx, f.camera.fy, f.camera.cx, f.camera.cy};
    f.frame.pitch_rad = f.camera.pitchRad;
    f.frame.roll_rad = f.camera.rollRad;
    auto restroomsFound = [&](const std::vector<wf_sign_kind>& catalogue, double cut) {
        wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
        opts.kind = WF_DETECTOR_UNET;
        opts.unet_path = unet.c_str();
        opts.catalogue = catalogue.data();
        opts.catalogue_count = catalogue.size();
        opts.unet_coarse_min_elevation_rad = cut;
        wf_detector* d = nullptr;
        EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
        if (d == nullptr) return -1;
        int n = 0;
        for (const wf_sign_sighting& s : sense(d, f.frame)) {
            if (std::string(s.kind) != "restroom") continue;
            ++n;
            EXPECT_NEAR(s.range_m, 2.5, 0.25);
        }
        wf_detector_free(d);
        return n;
    };
    const wf_sign_kind exitKind{"exit", 0.21, 0.33, "red", "white", 0, 0, 0, 0, 0};
    // The catalogue's restroom (white on blue: not Exit-like) lifts the cut: the sign is found and ranged.
    EXPECT_EQ(restroomsFound({exitKind, restroomKind(0, 0, 0)}, 0), 1);
    // A cut the caller sets stays: the sign is below it.
    EXPECT_EQ(restroomsFound({exitKind, restroomKind(0, 0, 0)}, -0.10), 0);
    // A restroom described as Exit-like (red) keeps the Exit limits and cut.
    wf_sign_kind redRestroom = restroomKind(0, 0, 0);
    redRestroom.face_colour = "red";
    EXPECT_EQ(restroomsFound({exitKind, redRestroom}, 0), 0);
    // The class's own limits apply: a restroom face said to be 0.21 m tall and 0.06 m wide (aspect 0.29: limits
    // 0.11-0.54) refuses the drawn 0.33 m wide face, which the Exit limits (0.8-3.0) would take.
    wf_sign_kind narrow = restroomKind(0, 0, 0);
    narrow.face_width_m = 0.06;
    EXPECT_EQ(restroomsFound({exitKind, narrow}, -1.5), 0);
    EXPECT_EQ(restroomsFound({exitKind, redRestroom}, -1.5), 1);
}

TEST(MoreKinds, TheTextReaderLoadsOnlyForAReportedKindThatReadsText) {
    wf_detector* d = cascadeDetector("restroom", {restroomKind(0.1, 0.7, 0)});
    EXPECT_EQ(wf_detector_reads_text(d), 0);
    EXPECT_STREQ(wf_detector_text_reader_problem(d), "");
    wf_detector_free(d);
    d = cascadeDetector("restroom", {restroomKind(0.1, 0.7, 0, 1)});
    if (TextReader::compiledIn()) {
        EXPECT_EQ(wf_detector_reads_text(d), 1) << wf_detector_text_reader_problem(d);
    } else {
        EXPECT_EQ(wf_detector_reads_text(d), 0);
        EXPECT_NE(std::string(wf_detector_text_reader_problem(d)), "");
    }
    wf_detector_free(d);
    EXPECT_EQ(wf_detector_reads_text(nullptr), 0);
    EXPECT_STREQ(wf_detector_text_reader_problem(nullptr), "");
}

// Three wall kinds (restroom, stairs, elevator: not colour-gated, so searched in turn), each a cascade that finds the
// drawn sign of frameWithSign(), so the kinds sighted on a frame are the kinds it looked for. Not copyable: the options
// point into it.
struct ThreeWallKinds {
    const std::string path = wf::sign::testing::referenceCascadePath();
    const char* paths[3] = {path.c_str(), path.c_str(), path.c_str()};
    const char* kinds[3] = {"restroom", "stairs", "elevator"};
    wf_sign_kind catalogue[3] = {restroomKind(0.1, 0.7, 0), restroomKind(0.1, 0.7, 0), restroomKind(0.1, 0.7, 0)};
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    const Frame f = frameWithSign();
    ThreeWallKinds() {
        catalogue[1].kind = "stairs";
        catalogue[2].kind = "elevator";
        useCascades(opts, paths, kinds, 3, catalogue, 3);
    }
    ThreeWallKinds(const ThreeWallKinds&) = delete;
    ThreeWallKinds& operator=(const ThreeWallKinds&) = delete;
    using Kinds = std::set<std::string>;
    /// The kinds sighted on the frame by `d`, checked to be the kinds the detector says it looked for
    /// (wf_detector_kind_searched).
    Kinds seen(wf_detector* d) const {
        Kinds sighted, searched;
        for (const auto& s : sense(d, f.frame)) sighted.insert(s.kind);
        for (size_t i = 0; i < wf_detector_kind_count(d); ++i) {
            if (wf_detector_kind_searched(d, i) == 1) searched.insert(wf_detector_kind_name(d, i));
        }
        EXPECT_EQ(searched, sighted);
        return sighted;
    }
};

TEST(MoreKinds, WallKindsAreSearchedInRotationOnTheirFramesUnlessAllAreAsked) {
    ThreeWallKinds three;
    wf_detector_options& opts = three.opts;
    using Kinds = ThreeWallKinds::Kinds;
    auto kindsSeen = [&](wf_detector* d) { return three.seen(d); };
    // Default: two kinds on every second frame, the first frame searched (each kind on two frames in three here).
    wf_detector* d = nullptr;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    EXPECT_EQ(wf_detector_kind_searched(d, 0), 0);  // before any frame
    EXPECT_EQ(wf_detector_kind_searched(d, 3), -1);
    EXPECT_EQ(wf_detector_kind_searched(nullptr, 0), -1);
    EXPECT_EQ(kindsSeen(d), (Kinds{"restroom", "stairs"}));
    EXPECT_EQ(kindsSeen(d), Kinds{});
    EXPECT_EQ(kindsSeen(d), (Kinds{"elevator", "restroom"}));
    EXPECT_EQ(kindsSeen(d), Kinds{});
    EXPECT_EQ(kindsSeen(d), (Kinds{"stairs", "elevator"}));
    wf_detector_free(d);
    // A count alone: that many kinds on every frame (the behaviour before the period), unless a period is given.
    opts.cascade_wall_kinds_per_frame = 1;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    EXPECT_EQ(kindsSeen(d), Kinds{"restroom"});
    EXPECT_EQ(kindsSeen(d), Kinds{"stairs"});
    EXPECT_EQ(kindsSeen(d), Kinds{"elevator"});
    wf_detector_free(d);
    opts.cascade_wall_kind_frame_period = 3;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    EXPECT_EQ(kindsSeen(d), Kinds{"restroom"});
    EXPECT_EQ(kindsSeen(d), Kinds{});
    EXPECT_EQ(kindsSeen(d), Kinds{});
    EXPECT_EQ(kindsSeen(d), Kinds{"stairs"});
    wf_detector_free(d);
    opts.cascade_wall_kind_frame_period = 0;
    opts.cascade_wall_kinds_per_frame = -1;
    ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
    EXPECT_EQ(kindsSeen(d), (Kinds{"restroom", "stairs", "elevator"}));
    EXPECT_EQ(kindsSeen(d), (Kinds{"restroom", "stairs", "elevator"}));
    wf_detector_free(d);
    // Bad values name the field.
    opts.cascade_wall_kinds_per_frame = -2;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_thread_last_error()).find("cascade_wall_kinds_per_frame"), std::string::npos);
    opts.cascade_wall_kinds_per_frame = 0;
    opts.cascade_wall_kind_frame_period = -1;
    EXPECT_EQ(wf_detector_create(&d, &opts), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_thread_last_error()).find("cascade_wall_kind_frame_period"), std::string::npos);
}

// The caller chooses the next frame's wall kinds (wf_detector_request_wall_kinds: the app's pipeline asks for the
// kinds the localizer expects in view): exactly those are searched, on that frame only, even on a frame the schedule
// would have skipped; the schedule's rotation does not advance on it. Bad requests are refused, requesting nothing.
TEST(MoreKinds, TheCallerMayChooseTheNextFramesWallKinds) {
    ThreeWallKinds three;
    using Kinds = ThreeWallKinds::Kinds;
    wf_detector* d = nullptr;
    ASSERT_EQ(wf_detector_create(&d, &three.opts), WF_STATUS_OK) << wf_thread_last_error();
    ASSERT_EQ(wf_detector_kind_count(d), 3u);
    for (size_t i = 0; i < 3; ++i) EXPECT_EQ(wf_detector_is_wall_kind(d, i), 1) << i;
    EXPECT_EQ(wf_detector_is_wall_kind(d, 3), -1);
    EXPECT_EQ(wf_detector_is_wall_kind(nullptr, 0), -1);
    const size_t elevator = 2, stairs = 1;
    EXPECT_EQ(wf_detector_request_wall_kinds(d, &elevator, 1), WF_STATUS_OK);
    EXPECT_EQ(three.seen(d), Kinds{"elevator"});
    // The schedule resumes where it was: its first frame (restroom and stairs), then a frame it skips.
    EXPECT_EQ(three.seen(d), (Kinds{"restroom", "stairs"}));
    const size_t both[] = {stairs, elevator};
    EXPECT_EQ(wf_detector_request_wall_kinds(d, both, 2), WF_STATUS_OK);
    EXPECT_EQ(three.seen(d), (Kinds{"stairs", "elevator"}));
    EXPECT_EQ(wf_detector_request_wall_kinds(d, nullptr, 0), WF_STATUS_OK);
    EXPECT_EQ(three.seen(d), Kinds{});
    EXPECT_EQ(three.seen(d), Kinds{});  // the schedule's second frame: skipped
    EXPECT_EQ(three.seen(d), (Kinds{"elevator", "restroom"}));
    // Refused: an index out of range, a repeated kind, NULL with a count; the next frame follows the schedule.
    const size_t bad[] = {stairs, 7};
    EXPECT_EQ(wf_detector_request_wall_kinds(d, bad, 2), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_detector_last_error(d)).find("out of range"), std::string::npos) << wf_detector_last_error(d);
    const size_t twice[] = {stairs, stairs};
    EXPECT_EQ(wf_detector_request_wall_kinds(d, twice, 2), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_detector_last_error(d)).find("twice"), std::string::npos) << wf_detector_last_error(d);
    EXPECT_EQ(wf_detector_request_wall_kinds(d, nullptr, 1), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(wf_detector_request_wall_kinds(nullptr, both, 2), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(three.seen(d), Kinds{});
    wf_detector_free(d);
}

// The U-Net's classes are searched on every frame: only the cascades beside it can be requested.
TEST(MoreKinds, TheUnetsClassesAreNoWallKinds) {
    UnetWithRestroom u;
    wf_detector* d = nullptr;
    ASSERT_EQ(wf_detector_create(&d, &u.opts), WF_STATUS_OK) << wf_thread_last_error();
    size_t exitIndex = SIZE_MAX, restroomIndex = SIZE_MAX;
    for (size_t i = 0; i < wf_detector_kind_count(d); ++i) {
        if (std::string(wf_detector_kind_name(d, i)) == "exit") exitIndex = i;
        if (std::string(wf_detector_kind_name(d, i)) == "restroom") restroomIndex = i;
    }
    ASSERT_NE(exitIndex, SIZE_MAX);
    ASSERT_NE(restroomIndex, SIZE_MAX);
    EXPECT_EQ(wf_detector_is_wall_kind(d, exitIndex), 0);
    EXPECT_EQ(wf_detector_is_wall_kind(d, restroomIndex), 1);
    EXPECT_EQ(wf_detector_request_wall_kinds(d, &exitIndex, 1), WF_STATUS_INVALID_ARGUMENT);
    EXPECT_NE(std::string(wf_detector_last_error(d)).find("every frame"), std::string::npos) << wf_detector_last_error(d);
    EXPECT_EQ(wf_detector_request_wall_kinds(d, &restroomIndex, 1), WF_STATUS_OK);
    wf_detector_free(d);
}

// A phone held 8.6 degrees off upright: the unrolled frame is larger than the search size, so the wall kinds are
// searched on a canvas unrolled and shrunk in one resampling (unrolled_search_image.hpp), from the VGA frame on the
// cascade path and from the U-Net's half-size level on a 1920 x 1440 frame; the sign is found, ranged and its
// corners land on the drawn face either way.
TEST(MoreKinds, AnObliqueFrameIsSearchedOnACanvasOfTheSearchSize) {
    const double roll = -kPi / 2 + 0.15;
    auto expectOnTheFace = [](const wf_sign_sighting& s, const Frame& f) {
        const double faceWidthPx = cv::norm(f.truth.cornersRaw[3] - f.truth.cornersRaw[2]);
        for (int i = 0; i < 4; ++i) {
            EXPECT_LT(std::hypot(s.corners_raw_px[2 * i] - f.truth.cornersRaw[i].x,
                                 s.corners_raw_px[2 * i + 1] - f.truth.cornersRaw[i].y),
                      12 + 0.1 * faceWidthPx)
                << i;
        }
    };
    auto restroomOf = [](const std::vector<wf_sign_sighting>& all) {
        const auto it = std::find_if(all.begin(), all.end(), [](const wf_sign_sighting& s) { return std::string(s.kind) == "restroom"; });
        return it == all.end() ? nullptr : &*it;
    };
    const Frame vga = frameWithSign({640, 480}, roll);
    wf_detector* d = cascadeDetector("restroom", {restroomKind(0.1, 0.7, 0)});
    const std::vector<wf_sign_sighting> onVga = sense(d, vga.frame);
    const wf_sign_sighting* a = restroomOf(onVga);
    ASSERT_NE(a, nullptr);
    EXPECT_NEAR(a->range_m, 2.5, 0.2);
    expectOnTheFace(*a, vga);
    wf_detector_free(d);

    const UnetWithRestroom beside;
    ASSERT_EQ(wf_detector_create(&d, &beside.opts), WF_STATUS_OK) << wf_thread_last_error();
    const Frame hr = frameWithSign({1920, 1440}, roll);
    cv::Mat bgra;
    cv::cvtColor(hr.bgr, bgra, cv::COLOR_RGB2BGRA);  // as the phone sends it
    wf_frame phone = hr.frame;
    phone.image = wf_image{bgra.data, bgra.cols, bgra.rows, bgra.step, WF_PIXEL_BGRA8, nullptr, 0};
    const std::vector<wf_sign_sighting> onHr = sense(d, phone);
    const wf_sign_sighting* b = restroomOf(onHr);
    ASSERT_NE(b, nullptr);
    EXPECT_NEAR(b->range_m, 2.5, 0.2);
    expectOnTheFace(*b, hr);
    wf_detector_free(d);
}

TEST(MoreKinds, APlateOnAnUntexturedWallIsFoundThroughThePlateGate) {
    // The Swift wrapper's test frame (MoreSignKindsTests): an upright 480 x 640 RGB frame of a flat mid-gray wall with
    // a white 0.33 x 0.21 m face and four red blocks, 2.5 m ahead, centre 0.15 m above the camera. Its outline is the
    // plate gate's candidate; the kind's band (mounting height for a phone 1.0-1.7 m up) holds it.
    const int width = 480, height = 640;
    const double f = 534.0;
    cv::Mat rgb(height, width, CV_8UC3, cv::Scalar(128, 128, 128));
    const int faceW = int(std::lround(0.33 * f / 2.5)), faceH = int(std::lround(0.21 * f / 2.5));
    const int u0 = width / 2 - faceW / 2, v0 = int(std::lround(319.5 - 0.15 * f / 2.5)) - faceH / 2;
    for (int v = v0; v < v0 + faceH; ++v) {
        for (int u = u0; u < u0 + faceW; ++u) {
            const double x = double(u - u0) / faceW, y = double(v - v0) / faceH;
            const bool letter = y > 0.25 && y < 0.75 && x > 0.08 && x < 0.92 && int((x - 0.08) / 0.21 * 2) % 2 == 0;
            rgb.at<cv::Vec3b>(v, u) = letter ? cv::Vec3b(210, 30, 30) : cv::Vec3b(240, 240, 240);
        }
    }
    wf_frame frame{};
    frame.image = wf_image{rgb.data, rgb.cols, rgb.rows, rgb.step, WF_PIXEL_RGB8, nullptr, 0, 0, 0};
    frame.intrinsics = wf_intrinsics{f, f, 239.5, 319.5};
    const double centre = 1.5 - 0.105 + 0.105;  // mounting height + half the face
    const wf_sign_kind kind = restroomKind(centre - 1.8, centre - 0.9, 0);
    for (int gate : {-1, 0}) {
        static const std::string path = wf::sign::testing::referenceCascadePath();
        static const char* paths[] = {path.c_str()};
        const char* kinds[] = {"restroom"};
        wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
        opts.cascade_paths = paths;
        opts.cascade_kinds = kinds;
        opts.cascade_count = 1;
        opts.cascade_min_neighbors = 1;
        opts.catalogue = &kind;
        opts.catalogue_count = 1;
        opts.cascade_plate_gate = gate;
        wf_detector* d = nullptr;
        ASSERT_EQ(wf_detector_create(&d, &opts), WF_STATUS_OK) << wf_thread_last_error();
        const std::vector<wf_sign_sighting> seen = sense(d, frame);
        ASSERT_GE(seen.size(), 1u) << "gate " << gate;
        EXPECT_NEAR(seen[0].range_m, 2.5, 0.3) << "gate " << gate;
        wf_detector_free(d);
    }
}
