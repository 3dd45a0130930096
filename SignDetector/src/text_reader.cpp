#include "text_reader.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <vector>

#if defined(WF_SIGN_DETECTOR_HAS_TEXT_READER)
#include <tesseract/baseapi.h>
#endif

namespace wf::sign {

struct TextReader::Engine {
#if defined(WF_SIGN_DETECTOR_HAS_TEXT_READER)
    tesseract::TessBaseAPI api;
#endif
    bool loaded = false;
};

TextReader::TextReader() : engine_(std::make_unique<Engine>()) {}

TextReader::~TextReader() {
#if defined(WF_SIGN_DETECTOR_HAS_TEXT_READER)
    if (engine_ && engine_->loaded) engine_->api.End();
#endif
}

bool TextReader::compiledIn() {
#if defined(WF_SIGN_DETECTOR_HAS_TEXT_READER)
    return true;
#else
    return false;
#endif
}

bool TextReader::loaded() const { return engine_->loaded; }

bool TextReader::load(const std::string& tessdataDir, std::string* error) {
#if defined(WF_SIGN_DETECTOR_HAS_TEXT_READER)
    if (engine_->loaded) return true;
    const char* path = tessdataDir.empty() ? nullptr : tessdataDir.c_str();
    if (engine_->api.Init(path, "eng", tesseract::OEM_LSTM_ONLY) != 0) {
        const char* env = std::getenv("TESSDATA_PREFIX");
        *error = "tesseract could not load its English model (eng.traineddata) from " +
                 (path ? std::string(path) : env ? std::string(env) + " (TESSDATA_PREFIX)" : std::string("its default tessdata path")) +
                 "; install Debian's tesseract-ocr-eng";
        return false;
    }
    engine_->api.SetPageSegMode(tesseract::PSM_SINGLE_LINE);
    engine_->api.SetVariable("debug_file", "/dev/null");
    engine_->loaded = true;
    return true;
#else
    (void)tessdataDir;
    *error = "this build of the sign detector has no text reader (built without tesseract)";
    return false;
#endif
}

cv::Mat preparePlateForReading(const cv::Mat& gray, const cv::Rect& plateBox, const TextReaderParams& params) {
    const cv::Rect box = plateBox & cv::Rect(0, 0, gray.cols, gray.rows);
    if (box.width < 8 || box.height < 8) return cv::Mat();
    cv::Mat scaled;
    const double s = double(params.plateHeightPx) / box.height;
    cv::resize(gray(box), scaled, cv::Size(), s, s, s > 1 ? cv::INTER_CUBIC : cv::INTER_AREA);
    cv::Mat binary;
    cv::threshold(scaled, binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
    // Polarity from the plate's middle half (the border and the wall around the plate left out): characters are
    // the minority there, so a mostly dark middle is a dark plate with light characters.
    const cv::Rect middle(binary.cols / 4, binary.rows / 4, std::max(1, binary.cols / 2), std::max(1, binary.rows / 2));
    if (cv::mean(binary(middle))[0] < 127.5) cv::bitwise_not(binary, binary);
    // Whatever touches the crop's edge is wall or plate border, not a character: flood it white.
    for (int x = 0; x < binary.cols; ++x) {
        for (int y : {0, binary.rows - 1}) {
            if (binary.at<uint8_t>(y, x) == 0) cv::floodFill(binary, cv::Point(x, y), 255);
        }
    }
    for (int y = 0; y < binary.rows; ++y) {
        for (int x : {0, binary.cols - 1}) {
            if (binary.at<uint8_t>(y, x) == 0) cv::floodFill(binary, cv::Point(x, y), 255);
        }
    }
    // Keep only what is shaped like a character: a plate's border line or frame (as wide or tall as most of the
    // crop) and specks or Braille dots (a few percent of its height) are wiped white.
    cv::Mat ink = 255 - binary, labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(ink, labels, stats, centroids, 8, CV_32S);
    std::vector<uint8_t> keep(n, 0);
    for (int i = 1; i < n; ++i) {
        const int w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
        const bool dash = w >= 2 * h && w >= 0.04 * binary.cols;  // "B-12"
        keep[i] = w < 0.6 * binary.cols && h < 0.6 * binary.rows && (h >= 0.08 * binary.rows || dash);
    }
    for (int y = 0; y < binary.rows; ++y) {
        const int* l = labels.ptr<int>(y);
        uint8_t* b = binary.ptr<uint8_t>(y);
        for (int x = 0; x < binary.cols; ++x) {
            if (l[x] > 0 && !keep[l[x]]) b[x] = 255;
        }
    }
    const int pad = std::max(4, params.plateHeightPx / 10);
    cv::copyMakeBorder(binary, binary, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(255));
    return binary;
}

std::string cleanLegend(const std::string& raw, const std::string& alphabet) {
    std::string out;
    for (char c : raw) {
        const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (alphabet.find(u) != std::string::npos) out.push_back(u);
    }
    // A '-' is kept only between characters ("B-12"), never at the ends.
    while (!out.empty() && out.front() == '-') out.erase(out.begin());
    while (!out.empty() && out.back() == '-') out.pop_back();
    return out;
}

TextRead TextReader::read(const cv::Mat& gray, const cv::Rect& plateBox, const TextReaderParams& params) {
    TextRead result;
#if defined(WF_SIGN_DETECTOR_HAS_TEXT_READER)
    if (!engine_->loaded || gray.empty() || gray.type() != CV_8UC1) return result;
    const cv::Mat plate = preparePlateForReading(gray, plateBox, params);
    if (plate.empty()) return result;
    tesseract::TessBaseAPI& api = engine_->api;
    api.SetVariable("tessedit_char_whitelist", params.alphabet.c_str());
    api.SetImage(plate.data, plate.cols, plate.rows, 1, static_cast<int>(plate.step));
    api.SetSourceResolution(300);
    char* text = api.GetUTF8Text();
    const int confidence = api.MeanTextConf();
    const std::string raw = text ? text : "";
    delete[] text;
    api.Clear();
    result.confidence = confidence;
    const std::string clean = cleanLegend(raw, params.alphabet);
    if (confidence >= params.minConfidence && !clean.empty() && clean.size() < 16) result.text = clean;
#else
    (void)gray;
    (void)plateBox;
    (void)params;
#endif
    return result;
}

}  // namespace wf::sign
