// Tests of src/slice_measurement: boxes, clean masks, ragged noisy masks, mapping between pixel frames.
#include "slice_measurement.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <random>

using namespace wf::sign;

TEST(SliceMeasurement, BoxGivesItsHeightBottomEdgeAndCentre) {
    const SliceMeasurement m = measureBox(cv::Rect(10, 20, 30, 12));
    ASSERT_TRUE(m.valid);
    EXPECT_DOUBLE_EQ(m.medianHeightPx, 12);
    EXPECT_DOUBLE_EQ(m.medianBottomEdgePx, 31.5);  // last row 31, bottom edge 31.5
    EXPECT_DOUBLE_EQ(m.centerColumnPx, 24.5);      // columns 10..39
    EXPECT_EQ(m.box, cv::Rect2d(9.5, 19.5, 30, 12));
    EXPECT_EQ(m.sliceCount, 18);                   // middle 60 % of 30 columns
    EXPECT_DOUBLE_EQ(m.extentWidthPx, 29);
    EXPECT_DOUBLE_EQ(m.bottomEdgeSlope, 0);
    EXPECT_FALSE(measureBox(cv::Rect(0, 0, 0, 5)).valid);
}

TEST(SliceMeasurement, FilledMaskEqualsItsBox) {
    cv::Mat mask = cv::Mat::zeros(100, 120, CV_8UC1);
    const cv::Rect r(30, 40, 50, 21);
    mask(r).setTo(255);
    const SliceMeasurement a = measureMask(mask), b = measureBox(r);
    ASSERT_TRUE(a.valid);
    EXPECT_DOUBLE_EQ(a.medianHeightPx, b.medianHeightPx);
    EXPECT_DOUBLE_EQ(a.medianBottomEdgePx, b.medianBottomEdgePx);
    EXPECT_DOUBLE_EQ(a.centerColumnPx, b.centerColumnPx);
    EXPECT_EQ(a.box, b.box);
    EXPECT_EQ(a.sliceCount, 30);
}

TEST(SliceMeasurement, FixedSliceCountSamplesEvenlyInTheBand) {
    cv::Mat mask = cv::Mat::zeros(50, 100, CV_8UC1);
    mask(cv::Rect(0, 10, 100, 20)).setTo(1);
    SliceParams p;
    p.sliceCount = 5;
    const SliceMeasurement m = measureMask(mask, p);
    EXPECT_EQ(m.sliceCount, 5);
    EXPECT_DOUBLE_EQ(m.medianHeightPx, 20);
}

TEST(SliceMeasurement, EmptyMaskIsInvalid) {
    EXPECT_FALSE(measureMask(cv::Mat::zeros(10, 10, CV_8UC1)).valid);
}

TEST(SliceMeasurement, RaggedNoisyMaskGivesRobustMedians) {
    // A 80 x 24 sign whose top and bottom edges jitter by up to +-2 px per column (seeded), with 10 % of
    // the columns missing, holes inside (letters) and a few spikes of 8 px: medians stay within 1 px.
    std::mt19937 rng(2024);
    std::uniform_int_distribution<int> jitter(-2, 2), coin(0, 9), spike(0, 19);
    cv::Mat mask = cv::Mat::zeros(120, 160, CV_8UC1);
    const int left = 40, width = 80, top = 50, height = 24;
    for (int c = left; c < left + width; ++c) {
        if (coin(rng) == 0) continue;                      // missing column
        int t = top + jitter(rng), b = top + height - 1 + jitter(rng);
        if (spike(rng) == 0) t -= 8;                        // spike up
        if (spike(rng) == 0) b += 8;                        // spike down
        mask(cv::Range(t, b + 1), cv::Range(c, c + 1)).setTo(255);
        if (c % 7 == 0) mask(cv::Range(top + 8, top + 14), cv::Range(c, c + 1)).setTo(0);  // hole
    }
    const SliceMeasurement m = measureMask(mask);
    ASSERT_TRUE(m.valid);
    EXPECT_NEAR(m.medianHeightPx, height, 1.0);
    EXPECT_NEAR(m.medianBottomEdgePx, top + height - 0.5, 1.0);
    EXPECT_NEAR(m.centerColumnPx, left + 0.5 * (width - 1), 1.0);
    EXPECT_GT(m.sliceCount, 35);
}

TEST(SliceMeasurement, ShearedSignMeasuresVerticalExtentPerColumn) {
    // A parallelogram (a sign seen with a small residual roll): every column spans 20 rows.
    cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
    for (int c = 20; c < 80; ++c) {
        const int t = 30 + (c - 20) / 6;
        mask(cv::Range(t, t + 20), cv::Range(c, c + 1)).setTo(255);
    }
    const SliceMeasurement m = measureMask(mask);
    EXPECT_DOUBLE_EQ(m.medianHeightPx, 20);
    EXPECT_NEAR(m.medianBottomEdgePx, 30 + 5 + 19.5, 1.0);  // bottom near the centre column
    EXPECT_NEAR(m.bottomEdgeSlope, 1.0 / 6, 0.03);
    EXPECT_NEAR(m.topEdgeSlope, 1.0 / 6, 0.03);
    EXPECT_DOUBLE_EQ(m.extentWidthPx, 59);
}

TEST(SliceMeasurement, MappedScalesAndShiftsBetweenPixelFrames) {
    // Mask pixels are 2 unrolled pixels; the mask's top-left edge sits at unrolled (99.5, 49.5),
    // i.e. mask pixel (0, 0) covers unrolled pixels 100..101 x 50..51.
    const SliceMeasurement m = measureBox(cv::Rect(0, 0, 10, 5)).mapped(2.0, {99.5, 49.5});
    EXPECT_EQ(m.box, cv::Rect2d(99.5, 49.5, 20, 10));
    EXPECT_DOUBLE_EQ(m.medianHeightPx, 10);
    EXPECT_DOUBLE_EQ(m.medianBottomEdgePx, 59.5);  // rows 50..59
    EXPECT_DOUBLE_EQ(m.centerColumnPx, 109.5);     // columns 100..119
    EXPECT_DOUBLE_EQ(m.extentWidthPx, 18);         // 9 mask columns apart
}
