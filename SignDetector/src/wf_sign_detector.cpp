// C ABI over wf::sign::Detector. Every entry point catches all exceptions: none crosses the boundary.
#include "wf_sign_detector.h"

#include "detector.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <cstddef>
#include <cstring>
#include <new>
#include <string>

struct wf_detector {
    wf::sign::Detector detector;
    std::string lastError;
};

namespace {

thread_local std::string threadLastError;

int fail(int status, const std::string& message) {
    threadLastError = message;
    return status;
}

}  // namespace

extern "C" {

const char* wf_thread_last_error(void) { return threadLastError.c_str(); }

const char* wf_sign_detector_version(void) { return "1.0.0"; }

int wf_detector_options_init(wf_detector_options* opts) {
    if (opts == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_detector_options_init: opts is NULL");
    std::memset(opts, 0, sizeof *opts);
    return WF_STATUS_OK;
}

int wf_detector_create(wf_detector** out, const wf_detector_options* opts) {
    if (out == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_detector_create: out is NULL");
    *out = nullptr;
    if (opts == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_detector_create: opts is NULL");
    try {
        wf::sign::ResolvedOptions resolved;
        std::string error;
        int status = wf::sign::ResolvedOptions::fromOptions(*opts, &resolved, &error);
        if (status != WF_STATUS_OK) return fail(status, error);
        auto* handle = new (std::nothrow) wf_detector();
        if (handle == nullptr) return fail(WF_STATUS_INTERNAL, "wf_detector_create: out of memory");
        status = handle->detector.load(resolved, &error);
        if (status != WF_STATUS_OK) {
            delete handle;
            return fail(status, error);
        }
        *out = handle;
        threadLastError.clear();
        return WF_STATUS_OK;
    } catch (const std::exception& e) {
        return fail(WF_STATUS_INTERNAL, std::string("wf_detector_create: ") + e.what());
    } catch (...) {
        return fail(WF_STATUS_INTERNAL, "wf_detector_create: unknown exception");
    }
}

void wf_detector_free(wf_detector* detector) { delete detector; }

int wf_detector_detect(wf_detector* detector, const wf_frame* frame, wf_detector_observation* out, size_t capacity,
                       size_t* count_out) {
    if (count_out) *count_out = 0;
    if (detector == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_detector_detect: detector is NULL");
    auto reject = [&](int status, std::string message) {
        detector->lastError = std::move(message);
        return status;
    };
    if (frame == nullptr) return reject(WF_STATUS_INVALID_ARGUMENT, "wf_detector_detect: frame is NULL");
    if (count_out == nullptr) return reject(WF_STATUS_INVALID_ARGUMENT, "wf_detector_detect: count_out is NULL");
    if (out == nullptr && capacity > 0) {
        return reject(WF_STATUS_INVALID_ARGUMENT, "wf_detector_detect: out is NULL but capacity > 0");
    }
    try {
        wf::sign::FrameResult result = detector->detector.detect(*frame);
        if (result.status != WF_STATUS_OK) return reject(result.status, result.message);
        const size_t n = std::min(capacity, result.observations.size());
        for (size_t i = 0; i < n; ++i) out[i] = result.observations[i];
        *count_out = n;
        if (n < result.observations.size()) {
            return reject(WF_STATUS_TRUNCATED, "found " + std::to_string(result.observations.size()) +
                                            " signs; capacity " + std::to_string(capacity));
        }
        detector->lastError.clear();
        return WF_STATUS_OK;
    } catch (const std::exception& e) {
        return reject(WF_STATUS_INTERNAL, std::string("wf_detector_detect: ") + e.what());
    } catch (...) {
        return reject(WF_STATUS_INTERNAL, "wf_detector_detect: unknown exception");
    }
}

int wf_detector_sense(wf_detector* detector, const wf_frame* frame, wf_sign_sighting* out, size_t capacity,
                      size_t* count_out) {
    if (count_out) *count_out = 0;
    if (detector == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_detector_sense: detector is NULL");
    auto reject = [&](int status, std::string message) {
        detector->lastError = std::move(message);
        return status;
    };
    if (frame == nullptr) return reject(WF_STATUS_INVALID_ARGUMENT, "wf_detector_sense: frame is NULL");
    if (count_out == nullptr) return reject(WF_STATUS_INVALID_ARGUMENT, "wf_detector_sense: count_out is NULL");
    if (out == nullptr && capacity > 0) {
        return reject(WF_STATUS_INVALID_ARGUMENT, "wf_detector_sense: out is NULL but capacity > 0");
    }
    try {
        wf::sign::FrameSightings result = detector->detector.sense(*frame);
        if (result.status != WF_STATUS_OK) return reject(result.status, result.message);
        const size_t n = std::min(capacity, result.sightings.size());
        for (size_t i = 0; i < n; ++i) out[i] = result.sightings[i];
        *count_out = n;
        if (n < result.sightings.size()) {
            return reject(WF_STATUS_TRUNCATED, "found " + std::to_string(result.sightings.size()) +
                                                   " signs; capacity " + std::to_string(capacity));
        }
        detector->lastError.clear();
        return WF_STATUS_OK;
    } catch (const std::exception& e) {
        return reject(WF_STATUS_INTERNAL, std::string("wf_detector_sense: ") + e.what());
    } catch (...) {
        return reject(WF_STATUS_INTERNAL, "wf_detector_sense: unknown exception");
    }
}

const char* wf_detector_last_error(const wf_detector* detector) {
    return detector ? detector->lastError.c_str() : wf_thread_last_error();
}

size_t wf_detector_kind_count(const wf_detector* detector) {
    return detector ? detector->detector.kinds().size() : 0;
}

const char* wf_detector_kind_name(const wf_detector* detector, size_t index) {
    if (detector == nullptr || index >= detector->detector.kinds().size()) return nullptr;
    return detector->detector.kinds()[index].c_str();
}

int wf_detector_kind_searched(const wf_detector* detector, size_t index) {
    if (detector == nullptr || index >= detector->detector.kinds().size()) return -1;
    return detector->detector.searchedLastFrame(index) ? 1 : 0;
}

int wf_detector_is_wall_kind(const wf_detector* detector, size_t index) {
    if (detector == nullptr || index >= detector->detector.kinds().size()) return -1;
    return detector->detector.isWallKind(index) ? 1 : 0;
}

int wf_detector_request_wall_kinds(wf_detector* detector, const size_t* kind_indices, size_t count) {
    if (detector == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_detector_request_wall_kinds: detector is NULL");
    auto reject = [&](const std::string& message) {
        detector->lastError = "wf_detector_request_wall_kinds: " + message;
        return fail(WF_STATUS_INVALID_ARGUMENT, detector->lastError);
    };
    if (kind_indices == nullptr && count > 0) return reject("kind_indices is NULL but count > 0");
    std::string error;
    const std::vector<size_t> indices(kind_indices, kind_indices + count);
    if (!detector->detector.requestWallKinds(indices, &error)) return reject(error);
    detector->lastError.clear();
    return WF_STATUS_OK;
}

int wf_detector_reads_text(const wf_detector* detector) {
    return detector != nullptr && detector->detector.readsText() ? 1 : 0;
}

const char* wf_detector_text_reader_problem(const wf_detector* detector) {
    return detector == nullptr ? "" : detector->detector.textReaderProblem().c_str();
}

int wf_image_read(wf_owned_image* out, const char* path, wf_pixel_format format) {
    if (out == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_image_read: out is NULL");
    std::memset(out, 0, sizeof *out);
    if (path == nullptr) return fail(WF_STATUS_INVALID_ARGUMENT, "wf_image_read: path is NULL");
    int conversion;
    int channels;
    switch (wf::sign::enumValue(format)) {
        case WF_PIXEL_GRAY8: conversion = -1; channels = 1; break;
        case WF_PIXEL_RGB8: conversion = cv::COLOR_BGR2RGB; channels = 3; break;
        case WF_PIXEL_BGRA8: conversion = cv::COLOR_BGR2BGRA; channels = 4; break;
        default: return fail(WF_STATUS_INVALID_ARGUMENT, "wf_image_read: format must be GRAY8, RGB8 or BGRA8");
    }
    try {
        cv::Mat decoded = cv::imread(path, channels == 1 ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR);
        if (decoded.empty()) {
            return fail(WF_STATUS_IMAGE_READ, std::string("cannot read or decode image file ") + path);
        }
        cv::Mat converted;
        if (conversion >= 0) {
            cv::cvtColor(decoded, converted, conversion);
        } else {
            converted = decoded;
        }
        const size_t stride = static_cast<size_t>(converted.cols) * channels;
        auto* pixels = static_cast<uint8_t*>(std::malloc(stride * converted.rows));
        if (pixels == nullptr) return fail(WF_STATUS_INTERNAL, "wf_image_read: out of memory");
        for (int r = 0; r < converted.rows; ++r) std::memcpy(pixels + r * stride, converted.ptr(r), stride);
        out->data = pixels;
        out->width = converted.cols;
        out->height = converted.rows;
        out->stride = stride;
        out->format = format;
        return WF_STATUS_OK;
    } catch (const std::exception& e) {
        return fail(WF_STATUS_IMAGE_READ, std::string("wf_image_read ") + path + ": " + e.what());
    }
}

void wf_owned_image_free(wf_owned_image* image) {
    if (image == nullptr) return;
    std::free(image->data);
    std::memset(image, 0, sizeof *image);
}

}  // extern "C"
