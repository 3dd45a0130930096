// Reading the legend of a room-number placard: the box a detector found is cut from the unrolled gray frame,
// enlarged, binarised (Otsu) with dark characters on light, and read as one line by tesseract's LSTM engine
// (Smith 2007, "An overview of the Tesseract OCR engine"; Debian's libtesseract 5 and its English model), limited
// to the characters room numbers use. On the iPhone the library is built without tesseract and the app reads the
// text with Vision's VNRecognizeTextRequest instead (App/iOS); the detector then reports placards with no text.
// Hand-written here: only the crop, the polarity and the clean-up; the recognition is tesseract's.
#pragma once

#include <opencv2/core.hpp>

#include <memory>
#include <string>

namespace wf::sign {

/// Options of the text reader.
struct TextReaderParams {
    /// Height the plate's crop is scaled to before recognition, pixels: a placard's 25 mm characters on a 0.15 m
    /// plate are then about 30 px tall, where tesseract reads best (its documentation: x-height >= 20 px).
    int plateHeightPx = 180;
    /// Below this mean character confidence (tesseract's 0-100) the text is not reported (55 let 10 of 72 rendered
    /// VGA placards through misread, 75 seven: a misread room number is matched to one wrong sign).
    int minConfidence = 75;
    /// Characters kept: what room numbers are made of.
    std::string alphabet = "0123456789ABCDEFGHJKLMNPRSTUVWXYZ-";
};

/// What one read gave.
struct TextRead {
    /// Letters, digits and '-' only; "" = nothing read with enough confidence.
    std::string text;
    /// Tesseract's mean confidence of the line, 0-100 (-1 = no recognition ran).
    int confidence = -1;
};

/// One tesseract engine (loaded once; about 30 MB and 0.1-0.3 s). Not thread-safe, like the detector handle that
/// owns it.
class TextReader {
public:
    TextReader();
    ~TextReader();
    TextReader(const TextReader&) = delete;
    TextReader& operator=(const TextReader&) = delete;

    /// True when the library was built with tesseract (WF_SIGN_DETECTOR_HAS_TEXT_READER).
    static bool compiledIn();

    /// Loads the English model from `tessdataDir` ("" = $TESSDATA_PREFIX or tesseract's built-in path, which is
    /// Debian's /usr/share/tesseract-ocr/5/tessdata). Returns false with `error` set when the model is missing or
    /// the library was built without tesseract.
    bool load(const std::string& tessdataDir, std::string* error);

    /// True after a successful load().
    bool loaded() const;

    /// Reads the text on the plate inside `plateBox` of `gray` (CV_8UC1; the box in its pixels, clipped to it).
    /// A box smaller than 8 x 8 px, or no model loaded, gives an empty read.
    TextRead read(const cv::Mat& gray, const cv::Rect& plateBox, const TextReaderParams& params = {});

private:
    struct Engine;
    std::unique_ptr<Engine> engine_;
};

/// The plate prepared for recognition (exposed for tests): `gray`'s crop scaled to params.plateHeightPx, Otsu
/// threshold, inverted when the plate is dark (light characters) so that characters are black on white, with a
/// white border of a tenth of the height.
cv::Mat preparePlateForReading(const cv::Mat& gray, const cv::Rect& plateBox, const TextReaderParams& params);

/// `raw` reduced to the characters of `alphabet` (after upper-casing; spaces and others dropped).
std::string cleanLegend(const std::string& raw, const std::string& alphabet);

}  // namespace wf::sign
