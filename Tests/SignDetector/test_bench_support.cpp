// Tests of bench/bench_support and bench/range_formula: the test-set format read by wf_detector_eval,
// resolution scaling, matching, and the paper's range formula on exact geometry.
#include "bench_support.hpp"
#include "range_formula.hpp"
#include "synthetic_scene.hpp"
#include "unroll.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

using namespace wf::sign;
using namespace wf::sign::bench;

namespace {
std::string writeLabels(const std::string& name, const std::string& text) {
    const std::string dir = ::testing::TempDir() + name;
    std::remove((dir + "/labels.jsonl").c_str());
    std::string mk = "mkdir -p '" + dir + "'";
    EXPECT_EQ(std::system(mk.c_str()), 0);
    std::ofstream(dir + "/labels.jsonl") << text;
    return dir;
}
}  // namespace

TEST(BenchSupport, ReadsTheRendererLabelFormat) {
    const std::string dir = writeLabels("wf_labels_ok",
        R"({"image": "000001.jpg", "mask": "000001_mask.png", "intrinsics": {"fx": 1602.0, "fy": 1602.0, "cx": 960.0, "cy": 720.0, "width": 1920, "height": 1440}, "pitchRad": 0.22, "rollRad": -1.65, "yawRad": 0.9, "signs": [{"kind": "exit", "cornersRaw": [[238.2, 1428.0], [264.6, 1189.5], [402.5, 1188.1], [381.3, 1431.9]], "rangeMeters": 2.0, "bearingRad": 0.36, "heightMeters": 0.21, "widthMeters": 0.3, "style": {"letter": "green", "lit": false}}]})"
        "\n"
        R"({"image": "000002.jpg", "intrinsics": {"fx": 534.0, "fy": 534.0, "cx": 320.0, "cy": 240.0, "width": 640, "height": 480}, "pitchRad": 0.0, "rollRad": 0.0, "signs": []})"
        "\n");
    std::vector<LabelledFrame> frames;
    std::string error;
    ASSERT_TRUE(readLabels(dir, &frames, &error)) << error;
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].imagePath, dir + "/000001.jpg");
    EXPECT_DOUBLE_EQ(frames[0].fx, 1602.0);
    EXPECT_EQ(frames[0].width, 1920);
    EXPECT_DOUBLE_EQ(frames[0].rollRad, -1.65);
    ASSERT_EQ(frames[0].signs.size(), 1u);
    EXPECT_EQ(frames[0].signs[0].kind, "exit");
    EXPECT_DOUBLE_EQ(frames[0].signs[0].cornersRaw[2].x, 402.5);
    EXPECT_DOUBLE_EQ(frames[0].signs[0].rangeMeters, 2.0);
    EXPECT_DOUBLE_EQ(frames[0].signs[0].heightMeters, 0.21);
    EXPECT_TRUE(frames[1].signs.empty());
}

TEST(BenchSupport, BadLabelsNameTheFileAndLine) {
    const std::string dir = writeLabels("wf_labels_bad",
        R"({"image": "a.jpg", "intrinsics": {"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 4, "height": 4}, "pitchRad": 0, "rollRad": 0, "signs": []})"
        "\n"
        R"({"image": "b.jpg", "intrinsics": {"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 4, "height": 4}, "signs": [{"cornersRaw": [[0, 0]]}]})"
        "\n");
    std::vector<LabelledFrame> frames;
    std::string error;
    EXPECT_FALSE(readLabels(dir, &frames, &error));
    EXPECT_NE(error.find("labels.jsonl:2"), std::string::npos) << error;
    EXPECT_FALSE(readLabels("/nonexistent/testset", &frames, &error));
    EXPECT_NE(error.find("/nonexistent/testset/labels.jsonl"), std::string::npos);
}

TEST(BenchSupport, PreparedFramesScaleIntrinsicsAndCorners) {
    LabelledFrame labels;
    labels.fx = labels.fy = 1602;
    labels.cx = 959.5;
    labels.cy = 719.5;
    labels.width = 1920;
    labels.height = 1440;
    LabelledSign sign;
    sign.cornersRaw = {cv::Point2d(-0.5, -0.5), {1919.5, -0.5}, {1919.5, 1439.5}, {959.5, 719.5}};
    labels.signs.push_back(sign);
    const cv::Mat bgr(1440, 1920, CV_8UC3, cv::Scalar(10, 20, 30));
    const auto p = prepareFrame(bgr, labels, {640, 480});
    EXPECT_DOUBLE_EQ(p->frame.intrinsics.fx, 534);
    EXPECT_DOUBLE_EQ(p->frame.intrinsics.cx, 319.5);
    EXPECT_DOUBLE_EQ(p->frame.intrinsics.cy, 239.5);
    EXPECT_EQ(p->frame.image.width, 640);
    EXPECT_EQ(p->frame.image.format, WF_PIXEL_RGB8);
    EXPECT_EQ(p->rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));
    EXPECT_DOUBLE_EQ(p->labels.signs[0].cornersRaw[0].x, -0.5);
    EXPECT_DOUBLE_EQ(p->labels.signs[0].cornersRaw[2].x, 639.5);
    EXPECT_DOUBLE_EQ(p->labels.signs[0].cornersRaw[3].y, 239.5);
}

TEST(RangeFormula, IsExactForASignStraightAhead) {
    // Exact projection of a 0.21 m sign at 4 m, 0.8 m above the camera, pitch 0.1, portrait roll.
    synthetic::Camera cam;
    cam.pitchRad = 0.1;
    synthetic::SignPlacement s;
    s.rangeMeters = 4;
    cv::Point2d bottom, top;
    ASSERT_TRUE(synthetic::projectToRaw(cam, {0, s.bottomAboveCameraMeters, -s.rangeMeters}, &bottom));
    ASSERT_TRUE(synthetic::projectToRaw(cam, {0, s.bottomAboveCameraMeters + s.heightMeters, -s.rangeMeters}, &top));
    const Unrolling u = Unrolling::forRoll(cam.rollRad, {cam.fx, cam.fy, cam.cx, cam.cy}, cam.size);
    const double vb = u.rawToUnrolled(bottom).y, vt = u.rawToUnrolled(top).y;
    const Intrinsics& k = u.unrolledIntrinsics();
    EXPECT_NEAR(rangeFromApparentHeight(0.21, vb, vb - vt, k.fy, k.cy, cam.pitchRad), 4.0, 1e-9);
    EXPECT_TRUE(std::isnan(rangeFromApparentHeight(0.21, vb, 0.0, k.fy, k.cy, 0.1)));
}

TEST(BenchSupport, MatchingNeedsTheCentreInsideAndASimilarHeight) {
    LabelledSign sign;  // upright frame, sign covering u 100..160, v 50..90 (raw = unrolled)
    sign.cornersRaw = {cv::Point2d(100, 50), {160, 50}, {160, 90}, {100, 90}};
    wf_detector_observation o{};
    const double identity[6] = {1, 0, 0, 0, 1, 0};
    std::copy(identity, identity + 6, o.unrolled_to_raw);
    o.box_x = 105; o.box_y = 55; o.box_width = 50; o.box_height = 30; o.median_height_px = 30;
    EXPECT_TRUE(matches(o, sign));
    o.median_height_px = 10;  // too small
    EXPECT_FALSE(matches(o, sign));
    o.median_height_px = 30;
    o.box_x = 300;            // elsewhere
    EXPECT_FALSE(matches(o, sign));
}
