// The example input of `wayfinder range` (Tests/Fixtures/range/observations.csv) is generated here by the
// synthetic projection of range_synthetic.hpp; this test checks the committed file is exactly what the
// generator writes. Regenerate with:
//   WF_RANGE_WRITE_FIXTURE=1 <gtest binary> --gtest_filter='RangeFixture.*'
#include <gtest/gtest.h>

#include "range_synthetic.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace wf::range::test {
namespace {

std::string fixturePath() {
    std::string here = __FILE__;  // .../Tests/SignDetector/range/test_range_fixture.cpp
    const std::size_t cut = here.rfind("/SignDetector/range/");
    return here.substr(0, cut) + "/Fixtures/range/observations.csv";
}

std::string format(const char *fmt, double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, fmt, value);
    return buffer;
}

/// The fixture's text: 12 sightings of a 0.33 x 0.21 m sign, portrait and landscape, 1.5 to 14 m; rows 1-8
/// exact (corners rounded to 0.001 px), rows 9-12 with 1.5 px of seeded corner noise; rows 11-12 give the
/// orientation as a camera_to_world column instead of pitch and roll.
std::string generateFixture() {
    std::ostringstream out;
    out << "image_width,image_height,fx,fy,cx,cy,pitch_rad,roll_rad,camera_to_world,u_tl,v_tl,u_tr,v_tr,u_br,"
           "v_br,u_bl,v_bl,sign_height_m,sign_width_m,camera_height_m,sign_center_height_m,true_range_m\n";
    struct Row {
        double rangeM, bearingDeg, pitchDeg, rollDeg, facingDeg, heightAboveCameraM;
    };
    const Row rows[] = {
        {1.5, 4, 20, -90, 10, 0.7},   {2.0, 3, 5, -90.5, 0, 0.17},  {3.0, -8, 8, -88, -20, 0.8},
        {4.0, 10, 6, -92, 25, 0.85},  {6.0, -5, 4, 0, 15, 0.9},     {8.0, 2, 3, -90, -30, 0.8},
        {10.0, -3, 2, 3, 5, 0.75},    {14.0, 1, 1, -89, 0, 0.9},    {3.5, 6, 10, -90, 12, 0.8},
        {7.0, -9, 4, -85, -10, 0.85}, {5.0, 0, 7, -91, 0, 0.8},     {12.0, 5, 2, -2, 20, 0.8},
    };
    std::mt19937_64 rng(42);
    std::normal_distribution<double> noise(0.0, 1.5);
    int index = 0;
    for (const Row &row : rows) {
        ++index;
        Scene s;
        s.yawRad = 0.3 * index;
        s.pitchRad = deg(row.pitchDeg);
        s.rollRad = deg(row.rollDeg);
        s.rangeM = row.rangeM;
        s.bearingRad = deg(row.bearingDeg);
        s.facingRad = deg(row.facingDeg);
        s.centerHeightAboveCameraM = row.heightAboveCameraM;
        s.signWidthM = 0.33;
        s.signHeightM = 0.21;
        auto corners = projectCorners(s);
        if (!corners) {
            ADD_FAILURE() << "fixture row " << index << " is not visible";
            continue;
        }
        if (index > 8)
            for (auto &p : *corners) {
                p.u += noise(rng);
                p.v += noise(rng);
            }
        const double cameraHeight = 1.40;
        out << "1920,1440,1602,1602,960,720,";
        if (index <= 10) {
            out << format("%.6f", s.pitchRad) << ',' << format("%.6f", s.rollRad) << ",,";
        } else {
            const auto m = columnMajor(rotation(s));
            out << ",,";
            for (std::size_t i = 0; i < 16; ++i) out << (i ? ";" : "") << format("%.9f", m[i]);
            out << ',';
        }
        for (const auto &p : *corners) out << format("%.3f", p.u) << ',' << format("%.3f", p.v) << ',';
        out << "0.21,0.33," << format("%.2f", cameraHeight) << ','
            << format("%.3f", cameraHeight + s.centerHeightAboveCameraM) << ',' << format("%.3f", s.rangeM)
            << '\n';
    }
    return out.str();
}

TEST(RangeFixture, CommittedFixtureIsTheSyntheticProjection) {
    const std::string expected = generateFixture();
    if (std::getenv("WF_RANGE_WRITE_FIXTURE")) {
        std::ofstream(fixturePath()) << expected;
        GTEST_SKIP() << "wrote " << fixturePath();
    }
    std::ifstream in(fixturePath());
    ASSERT_TRUE(in) << "missing " << fixturePath();
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str(), expected);
}

}  // namespace
}  // namespace wf::range::test
