#include "cascade_detector.hpp"

#include <fstream>

namespace wf::sign {

bool CascadeDetector::load(const std::vector<std::string>& paths, const std::vector<std::string>& kinds,
                           std::string* error) {
    kinds_.clear();
    cascades_.clear();
    if (paths.empty()) {
        *error = "no cascade path given";
        return false;
    }
    for (size_t i = 0; i < paths.size(); ++i) {
        if (!std::ifstream(paths[i]).good()) {
            *error = "cascade file not found or unreadable: " + paths[i];
            return false;
        }
        auto cascade = std::make_unique<cv::CascadeClassifier>();
        bool loaded = false;
        try {
            loaded = cascade->load(paths[i]);
        } catch (const cv::Exception& e) {
            *error = "cascade file " + paths[i] + " is not an OpenCV cascade: " + e.what();
            return false;
        }
        if (!loaded || cascade->empty()) {
            *error = "cascade file " + paths[i] + " is not an OpenCV cascade (cv::CascadeClassifier::load failed)";
            return false;
        }
        cascades_.push_back(std::move(cascade));
        kinds_.push_back(i < kinds.size() && !kinds[i].empty() ? kinds[i] : "exit");
    }
    return true;
}

cv::Size CascadeDetector::trainedWindow(size_t index) const {
    return index < cascades_.size() ? cascades_[index]->getOriginalWindowSize() : cv::Size();
}

std::vector<Detection> CascadeDetector::detect(const cv::Mat& grayUnrolled, const CascadeParams& params) {
    CV_Assert(grayUnrolled.type() == CV_8UC1);
    std::vector<Detection> detections;
    for (size_t i = 0; i < cascades_.size(); ++i) {
        std::vector<cv::Rect> boxes;
        std::vector<int> neighbours;
        cv::Size maxSize;
        if (params.maxWindowFactor > 0) {
            maxSize = cv::Size(static_cast<int>(params.minWindow.width * params.maxWindowFactor),
                               static_cast<int>(params.minWindow.height * params.maxWindowFactor));
        }
        cascades_[i]->detectMultiScale(grayUnrolled, boxes, neighbours, params.scaleFactor, params.minNeighbors, 0,
                                       params.minWindow, maxSize);
        for (size_t j = 0; j < boxes.size(); ++j) {
            Detection d;
            d.kind = kinds_[i];
            d.kindIndex = static_cast<int>(i);
            d.score = j < neighbours.size() ? neighbours[j] : params.minNeighbors;
            d.measurement = measureBox(boxes[j], params.slices);
            detections.push_back(std::move(d));
        }
    }
    return detections;
}

}  // namespace wf::sign
