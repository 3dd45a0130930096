// Tests of src/plate_gate (the wall kinds' search regions): a dark plate with a light legend on a textured wall
// gives a candidate around the plate, a wall without plates gives none, the size range and aspect filter
// candidates, and each region holds its box with the margin and window range, near-duplicates merged, a crowded
// frame falling back to the whole search.
#include "plate_gate.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <vector>

using namespace wf::sign;

namespace {

/// A 640 x 480 gray wall (level 170, Gaussian noise sd 4: below every edge threshold).
cv::Mat wall(int seed = 3) {
    cv::Mat g(480, 640, CV_8UC1, cv::Scalar(170));
    cv::Mat noise(g.size(), CV_16SC1);
    cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0, 4);
    cv::Mat out;
    cv::add(g, noise, out, cv::noArray(), CV_8UC1);
    return out;
}

/// Draws a dark plate (level 40) of `plate` with a light legend (two bars and a dot, level 235) on `gray`.
void drawPlate(cv::Mat& gray, const cv::Rect& plate) {
    cv::rectangle(gray, plate, cv::Scalar(40), cv::FILLED);
    const int w = plate.width, h = plate.height;
    cv::rectangle(gray, cv::Rect(plate.x + w / 4, plate.y + h / 3, w / 8, h / 2), cv::Scalar(235), cv::FILLED);
    cv::rectangle(gray, cv::Rect(plate.x + 5 * w / 8, plate.y + h / 3, w / 8, h / 2), cv::Scalar(235), cv::FILLED);
    cv::circle(gray, {plate.x + w / 2, plate.y + h / 5}, std::max(2, w / 12), cv::Scalar(235), cv::FILLED);
}

/// Whether some candidate's edges lie within `tolerancePx` of `plate`'s.
bool someCandidateOutlines(const std::vector<cv::Rect>& candidates, const cv::Rect& plate, int tolerancePx) {
    for (const cv::Rect& c : candidates) {
        if (std::abs(c.x - plate.x) <= tolerancePx && std::abs(c.y - plate.y) <= tolerancePx &&
            std::abs(c.br().x - plate.br().x) <= tolerancePx && std::abs(c.br().y - plate.br().y) <= tolerancePx) {
            return true;
        }
    }
    return false;
}

}  // namespace

TEST(PlateGate, ADarkPlateWithALightLegendGivesACandidateAroundIt) {
    cv::Mat g = wall();
    const cv::Rect near(300, 150, 60, 60), far(100, 220, 22, 22);  // a pictogram plate at about 2 m and 6 m (VGA)
    drawPlate(g, near);
    drawPlate(g, far);
    const std::vector<cv::Rect> c = plateCandidates(g, 0, g.rows, 10, 240, PlateGateParams{});
    // Found on the image shrunk 2 x: edges to 2 working pixels, 4 px here.
    EXPECT_TRUE(someCandidateOutlines(c, near, 4));
    EXPECT_TRUE(someCandidateOutlines(c, far, 4));
    // At full resolution the outline is found to a pixel or two.
    PlateGateParams fine;
    fine.shrinkFactor = 1;
    EXPECT_TRUE(someCandidateOutlines(plateCandidates(g, 0, g.rows, 10, 240, fine), near, 2));
}

TEST(PlateGate, AWallWithoutPlatesGivesNoCandidate) {
    EXPECT_TRUE(plateCandidates(wall(), 0, 480, 10, 240, PlateGateParams{}).empty());
}

TEST(PlateGate, SizeRowsAndAspectFilterTheCandidates) {
    cv::Mat g = wall();
    const cv::Rect plate(300, 150, 60, 60);
    drawPlate(g, plate);
    EXPECT_FALSE(plateCandidates(g, 0, g.rows, 10, 240, PlateGateParams{}).empty());
    // Smallest side above the plate's (and its legend's), or rows that miss it: nothing.
    EXPECT_TRUE(plateCandidates(g, 0, g.rows, 80, 240, PlateGateParams{}).empty());
    EXPECT_TRUE(plateCandidates(g, 300, g.rows, 10, 240, PlateGateParams{}).empty());
    // Rows that hold it: found, in the image's own row coordinates.
    EXPECT_TRUE(someCandidateOutlines(plateCandidates(g, 100, 260, 10, 240, PlateGateParams{}), plate, 4));
    // A long bar (a door frame's lintel, 6:1) is not a plate.
    cv::Mat bar = wall();
    cv::rectangle(bar, cv::Rect(100, 100, 240, 40), cv::Scalar(40), cv::FILLED);
    for (const cv::Rect& c : plateCandidates(bar, 0, bar.rows, 10, 240, PlateGateParams{})) {
        const double aspect = double(c.width) / c.height;
        EXPECT_GE(aspect, 0.4);
        EXPECT_LE(aspect, 2.5);
    }
}

TEST(PlateGate, EachRegionHoldsItsBoxWithTheMarginAndWindowRange) {
    const cv::Rect searched(0, 0, 640, 480);
    const PlateGateParams params;
    const GateDecision one = plateRegions({cv::Rect(300, 150, 40, 30)}, searched, params);
    ASSERT_FALSE(one.fullSearch);
    ASSERT_EQ(one.regions.size(), 1u);
    // Margin 0.45 x 40 = 18 px each side; windows 0.7-1.9 x 40 px wide.
    EXPECT_EQ(one.regions[0].unrolledRect, cv::Rect(282, 132, 76, 66));
    EXPECT_EQ(one.regions[0].minWindowWidthPx, 28);
    EXPECT_EQ(one.regions[0].maxWindowWidthPx, 76);
    // Clipped to the searched image; near-duplicates (intersection over union >= 0.9) are one region.
    const GateDecision edge = plateRegions({cv::Rect(0, 0, 40, 40), cv::Rect(0, 0, 40, 41)}, searched, params);
    ASSERT_EQ(edge.regions.size(), 1u);
    EXPECT_EQ(edge.regions[0].unrolledRect.tl(), cv::Point(0, 0));
    // Overlapping but distinct boxes (a plate and its legend) keep their own window ranges.
    EXPECT_EQ(plateRegions({cv::Rect(300, 150, 40, 40), cv::Rect(310, 160, 20, 20)}, searched, params).regions.size(), 2u);
    // No candidate: nothing to search. Too many: the whole bands. Gate off: the whole bands.
    const GateDecision none = plateRegions({}, searched, params);
    EXPECT_FALSE(none.fullSearch);
    EXPECT_TRUE(none.regions.empty());
    std::vector<cv::Rect> crowd;
    for (int i = 0; i <= params.maxRegions; ++i) crowd.emplace_back((i % 20) * 30, (i / 20) * 30, 20, 20);
    EXPECT_TRUE(plateRegions(crowd, searched, params).fullSearch);
    PlateGateParams off;
    off.enabled = false;
    EXPECT_TRUE(plateRegions({cv::Rect(300, 150, 40, 30)}, searched, off).fullSearch);
}
