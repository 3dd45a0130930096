// Tests of the placard text reader (src/text_reader.cpp): plate preparation (polarity, border), the legend
// clean-up, and tesseract reading room numbers from drawn plates at the sizes a phone sees them.
#include "text_reader.hpp"

#include "synthetic_scene.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <string>

using namespace wf::sign;

namespace {

/// A gray wall with one placard `plateHeightPx` tall (0.15 m square plate, legend a sixth of its height) at
/// (40, 30); `plate` receives the plate's box.
cv::Mat wallWithPlacard(const std::string& legend, int plateHeightPx, bool darkPlate, cv::Rect* plate) {
    cv::Mat wall(plateHeightPx + 60, plateHeightPx + 80, CV_8UC1, cv::Scalar(170));
    synthetic::SignPlacement sign;
    sign.heightMeters = sign.widthMeters = 0.15;
    sign.style = synthetic::SignStyle::PlacardLightOnDark;
    sign.legend = legend;
    cv::Mat face;
    cv::cvtColor(synthetic::renderSignFace(sign, plateHeightPx), face, cv::COLOR_BGR2GRAY);
    if (!darkPlate) cv::bitwise_not(face, face);
    *plate = cv::Rect(40, 30, face.cols, face.rows);
    face.copyTo(wall(*plate));
    return wall;
}

}  // namespace

TEST(TextReader, CleanLegendKeepsRoomNumberCharactersOnly) {
    const std::string alphabet = TextReaderParams{}.alphabet;
    EXPECT_EQ(cleanLegend(" 214\n", alphabet), "214");
    EXPECT_EQ(cleanLegend("4o2a.", alphabet), "42A");  // 'O' is not a room-number character (read as 0 or dropped)
    EXPECT_EQ(cleanLegend("-B-12-", alphabet), "B-12");
    EXPECT_EQ(cleanLegend("...", alphabet), "");
}

TEST(TextReader, PreparedPlateHasDarkCharactersOnWhiteWhateverThePolarity) {
    for (bool dark : {true, false}) {
        cv::Rect plate;
        const cv::Mat wall = wallWithPlacard("214", 60, dark, &plate);
        const TextReaderParams params;
        const cv::Mat prepared = preparePlateForReading(wall, plate, params);
        ASSERT_FALSE(prepared.empty());
        const int pad = params.plateHeightPx / 10;
        EXPECT_EQ(prepared.rows, params.plateHeightPx + 2 * pad);
        // Mostly white (the characters are a minority), and some black (the characters survive).
        const double white = cv::countNonZero(prepared) / double(prepared.total());
        EXPECT_GT(white, 0.8) << "dark plate " << dark;
        EXPECT_LT(white, 0.995) << "dark plate " << dark;
    }
    cv::Rect plate;
    const cv::Mat wall = wallWithPlacard("214", 60, true, &plate);
    EXPECT_TRUE(preparePlateForReading(wall, cv::Rect(0, 0, 5, 5), TextReaderParams{}).empty());
}

TEST(TextReader, ReadsRoomNumbersOffDrawnPlates) {
    TextReader reader;
    std::string error;
    if (!TextReader::compiledIn()) {
        EXPECT_FALSE(reader.load("", &error));
        EXPECT_NE(error.find("without tesseract"), std::string::npos) << error;
        GTEST_SKIP() << "built without tesseract: " << error;
    }
    ASSERT_TRUE(reader.load("", &error)) << error;
    // Plates 40-120 px tall: a 0.15 m placard 2.0-0.67 m away on a VGA frame (fy 534), characters 7-20 px.
    int read = 0, total = 0;
    for (const std::string legend : {"214", "402A", "1107", "B-12"}) {
        for (int heightPx : {40, 60, 120}) {
            for (bool dark : {true, false}) {
                cv::Rect plate;
                const cv::Mat wall = wallWithPlacard(legend, heightPx, dark, &plate);
                const TextRead r = reader.read(wall, plate);
                ++total;
                if (r.text == legend) ++read;
                // Never a wrong legend with confidence: empty or right (a 3 % misread rate would break locks).
                EXPECT_TRUE(r.text.empty() || r.text == legend)
                    << legend << " " << heightPx << " px dark " << dark << ": read '" << r.text << "' conf " << r.confidence;
            }
        }
    }
    EXPECT_GE(read, total - 2) << read << " of " << total;
}

TEST(TextReader, BlankPlateAndBlankWallGiveNoText) {
    TextReader reader;
    std::string error;
    if (!TextReader::compiledIn() || !reader.load("", &error)) GTEST_SKIP() << error;
    cv::Mat blank(120, 160, CV_8UC1, cv::Scalar(40));
    EXPECT_EQ(reader.read(blank, cv::Rect(20, 20, 100, 80)).text, "");
    cv::Mat noise(120, 160, CV_8UC1);
    cv::randn(noise, 128, 10);
    EXPECT_EQ(reader.read(noise, cv::Rect(20, 20, 100, 80)).text, "");
}

TEST(TextReader, UnloadedReaderReadsNothing) {
    TextReader reader;
    cv::Rect plate;
    const cv::Mat wall = wallWithPlacard("214", 60, true, &plate);
    EXPECT_FALSE(reader.loaded());
    EXPECT_EQ(reader.read(wall, plate).text, "");
    EXPECT_EQ(reader.read(wall, plate).confidence, -1);
}
