#include "bench_support.hpp"

#include "range_formula.hpp"
#include "unet_detector.hpp"

#include <opencv2/imgproc.hpp>

#include <fstream>
#include <sstream>

namespace wf::sign::bench {

bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

std::string productModelsDir() { return std::string(WF_REPO_ROOT) + "/SignDetector/models"; }
std::string referenceCascadePath() {
    return std::string(WF_SHARED_DIR) + "/data/skeri_inavigate/models/exit_sign_cascade.xml";
}
std::string tinyUnetPath() { return std::string(WF_REPO_ROOT) + "/Tests/SignDetector/data/tiny_red_unet.onnx"; }

bool readLabels(const std::string& dir, std::vector<LabelledFrame>* frames, std::string* error) {
    const std::string path = dir + "/labels.jsonl";
    std::ifstream in(path);
    if (!in) {
        *error = "cannot open " + path + " (render a test set with SignDetector/training/render_signs.py)";
        return false;
    }
    std::string line;
    int lineNumber = 0;
    frames->clear();
    while (std::getline(in, line)) {
        ++lineNumber;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        try {
            cv::FileStorage fs(line, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_JSON);
            LabelledFrame f;
            f.imagePath = dir + "/" + static_cast<std::string>(fs["image"]);
            const cv::FileNode k = fs["intrinsics"];
            f.fx = k["fx"].real();
            f.fy = k["fy"].real();
            f.cx = k["cx"].real();
            f.cy = k["cy"].real();
            f.width = static_cast<int>(k["width"].real());
            f.height = static_cast<int>(k["height"].real());
            f.pitchRad = fs["pitchRad"].real();
            f.rollRad = fs["rollRad"].real();
            for (const auto& s : fs["signs"]) {
                LabelledSign sign;
                sign.kind = s["kind"].empty() ? "exit" : static_cast<std::string>(s["kind"]);
                const cv::FileNode corners = s["cornersRaw"];
                if (corners.size() != 4) throw std::runtime_error("cornersRaw needs 4 corners");
                for (int i = 0; i < 4; ++i) sign.cornersRaw[i] = {corners[i][0].real(), corners[i][1].real()};
                sign.rangeMeters = s["rangeMeters"].real();
                sign.bearingRad = s["bearingRad"].real();
                if (!s["heightMeters"].empty()) sign.heightMeters = s["heightMeters"].real();
                if (!s["widthMeters"].empty()) sign.widthMeters = s["widthMeters"].real();
                if (!s["text"].empty()) sign.text = static_cast<std::string>(s["text"]);
                f.signs.push_back(sign);
            }
            if (f.width <= 0 || f.height <= 0 || f.fx <= 0) throw std::runtime_error("missing intrinsics");
            frames->push_back(std::move(f));
        } catch (const std::exception& e) {
            *error = path + ":" + std::to_string(lineNumber) + ": " + e.what();
            return false;
        }
    }
    return true;
}

std::unique_ptr<PreparedFrame> prepareFrame(const cv::Mat& bgr, const LabelledFrame& labels, cv::Size size, int shiftPx) {
    auto p = std::make_unique<PreparedFrame>();
    cv::Mat resized;
    if (bgr.size() == size) {
        resized = bgr;
    } else {
        cv::resize(bgr, resized, size, 0, 0, size.width < bgr.cols ? cv::INTER_AREA : cv::INTER_LINEAR);
    }
    cv::cvtColor(resized, p->rgb, cv::COLOR_BGR2RGB);
    // The labels describe the image as stored (bgr's size); scale them to the working size.
    const double sx = double(size.width) / bgr.cols, sy = double(size.height) / bgr.rows;
    const double lx = double(bgr.cols) / labels.width, ly = double(bgr.rows) / labels.height;
    p->labels = labels;
    LabelledFrame& l = p->labels;
    l.fx = labels.fx * lx * sx;
    l.fy = labels.fy * ly * sy;
    l.cx = ((labels.cx + 0.5) * lx) * sx - 0.5;
    l.cy = ((labels.cy + 0.5) * ly) * sy - 0.5;
    l.width = size.width;
    l.height = size.height;
    for (auto& s : l.signs) {
        for (auto& c : s.cornersRaw) c = {((c.x + 0.5) * lx) * sx - 0.5, ((c.y + 0.5) * ly) * sy - 0.5};
    }
    if (shiftPx > 0 && shiftPx < std::min(size.width, size.height)) {
        // Drop the first shiftPx columns and rows: the same scene on a scan grid moved by shiftPx pixels.
        p->rgb = p->rgb(cv::Rect(shiftPx, shiftPx, size.width - shiftPx, size.height - shiftPx)).clone();
        l.cx -= shiftPx;
        l.cy -= shiftPx;
        l.width = p->rgb.cols;
        l.height = p->rgb.rows;
        for (auto& s : l.signs) {
            for (auto& c : s.cornersRaw) c -= cv::Point2d(shiftPx, shiftPx);
        }
    }
    p->frame.image = wf_image{p->rgb.data, p->rgb.cols, p->rgb.rows, p->rgb.step, WF_PIXEL_RGB8, nullptr, 0};
    p->frame.intrinsics = wf_intrinsics{l.fx, l.fy, l.cx, l.cy};
    p->frame.pitch_rad = l.pitchRad;
    p->frame.roll_rad = l.rollRad;
    return p;
}

void convertPixelFormat(PreparedFrame* p, wf_pixel_format format) {
    const cv::Mat rgb = p->rgb;
    switch (format) {
        case WF_PIXEL_RGB8: return;
        case WF_PIXEL_GRAY8:
            cv::cvtColor(rgb, p->rgb, cv::COLOR_RGB2GRAY);
            p->frame.image = wf_image{p->rgb.data, p->rgb.cols, p->rgb.rows, p->rgb.step, WF_PIXEL_GRAY8, nullptr, 0};
            return;
        case WF_PIXEL_BGRA8:
            cv::cvtColor(rgb, p->rgb, cv::COLOR_RGB2BGRA);
            p->frame.image = wf_image{p->rgb.data, p->rgb.cols, p->rgb.rows, p->rgb.step, WF_PIXEL_BGRA8, nullptr, 0};
            return;
        case WF_PIXEL_NV12: {
            // Full-range BT.601: Y = 0.299 R + 0.587 G + 0.114 B, Cb = 128 + (B - Y) / 1.772, Cr = 128 + (R - Y) / 1.402.
            cv::Mat y(rgb.size(), CV_8UC1), cbcr(rgb.size(), CV_32FC2);
            for (int r = 0; r < rgb.rows; ++r) {
                const cv::Vec3b* in = rgb.ptr<cv::Vec3b>(r);
                uchar* outY = y.ptr<uchar>(r);
                cv::Vec2f* outC = cbcr.ptr<cv::Vec2f>(r);
                for (int c = 0; c < rgb.cols; ++c) {
                    const double luma = 0.299 * in[c][0] + 0.587 * in[c][1] + 0.114 * in[c][2];
                    outY[c] = cv::saturate_cast<uchar>(luma);
                    outC[c] = cv::Vec2f(float(128 + (in[c][2] - luma) / 1.772), float(128 + (in[c][0] - luma) / 1.402));
                }
            }
            cv::Mat half;
            cv::resize(cbcr, half, cv::Size((rgb.cols + 1) / 2, (rgb.rows + 1) / 2), 0, 0, cv::INTER_AREA);
            half.convertTo(p->chroma, CV_8UC2);
            p->rgb = y;
            p->frame.image = wf_image{p->rgb.data, p->rgb.cols, p->rgb.rows, p->rgb.step, WF_PIXEL_NV12,
                                      p->chroma.data, p->chroma.step};
            return;
        }
    }
}

std::unique_ptr<DetectorHandle> makeCascade(const std::string& path, int minWindowWidth, int minWindowHeight,
                                            double maxWindowFactor, double minElevationRad, bool fullSearch,
                                            CascadeSearch search, FaceEdgeOptions faceEdges, int searchMaxLongSidePx) {
    auto d = std::make_unique<DetectorHandle>();
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.kind = WF_DETECTOR_CASCADE;
    const char* paths[] = {path.c_str()};
    opts.cascade_paths = paths;
    opts.cascade_count = 1;
    opts.cascade_min_window_width = minWindowWidth;
    opts.cascade_min_window_height = minWindowHeight;
    opts.cascade_max_window_factor = maxWindowFactor;
    opts.cascade_full_search = fullSearch ? 1 : 0;
    opts.face_edge_refinement = faceEdges.refinement;
    opts.face_edge_transfer = faceEdges.transfer;
    opts.cascade_search_max_long_side_px = searchMaxLongSidePx;
    if (search != CascadeSearch::Defaults) {
        opts.cascade_gate_min_margin_px = 24;
        opts.cascade_gate_component_window_fraction = -1;
    }
    if (search == CascadeSearch::WideGateRegionsNoPrior) {
        opts.cascade_placement_prior = -1;
        opts.cascade_gate_crowded_contrast_factor = 1;
    }
    if (std::isnan(minElevationRad)) {
        opts.cascade_search_above_elevation = -1;  // the whole frame
    } else if (minElevationRad != 0) {
        opts.cascade_search_above_elevation = 1;
        opts.cascade_min_elevation_rad = minElevationRad;
    }
    if (wf_detector_create(&d->handle, &opts) != WF_STATUS_OK) d->error = wf_thread_last_error();
    return d;
}

std::unique_ptr<DetectorHandle> makeUnet(const std::string& path, double coarseMinElevationRad, FaceEdgeOptions faceEdges,
                                         const std::vector<CatalogueEntry>* catalogue, int transposedConvolution) {
    auto d = std::make_unique<DetectorHandle>();
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    std::vector<wf_sign_kind> entries;
    if (catalogue != nullptr) {
        for (const auto& e : *catalogue) entries.push_back(e.entry);
        opts.catalogue = entries.data();
        opts.catalogue_count = entries.size();
    }
    opts.kind = WF_DETECTOR_UNET;
    opts.unet_path = path.c_str();
    opts.unet_coarse_min_elevation_rad = coarseMinElevationRad;
    opts.face_edge_refinement = faceEdges.refinement;
    opts.face_edge_transfer = faceEdges.transfer;
    opts.unet_transposed_convolution = transposedConvolution;
    if (wf_detector_create(&d->handle, &opts) != WF_STATUS_OK) d->error = wf_thread_last_error();
    return d;
}

bool readUnetClasses(const std::string& modelPath, std::vector<std::string>* classes, std::string* error) {
    const size_t slash = modelPath.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : modelPath.substr(0, slash);
    return readClassList(dir + "/classes.json", classes, error);
}

int detect(DetectorHandle& detector, const PreparedFrame& frame, std::vector<wf_detector_observation>* observations) {
    observations->resize(64);
    size_t count = 0;
    const int status = wf_detector_detect(detector.handle, &frame.frame, observations->data(), observations->size(), &count);
    observations->resize(count);
    return status;
}

double observationRangeMeters(const wf_detector_observation& o, double signHeightMeters, double pitchRad) {
    return rangeFromApparentHeight(signHeightMeters, o.median_bottom_row_px, o.median_height_px, o.unrolled_fy,
                                   o.unrolled_cy, pitchRad);
}

bool matches(const wf_detector_observation& o, const LabelledSign& sign) {
    const double* m = o.unrolled_to_raw;
    cv::Matx23d toRaw(m[0], m[1], m[2], m[3], m[4], m[5]), toUnrolled;
    cv::invertAffineTransform(toRaw, toUnrolled);
    double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
    for (const auto& c : sign.cornersRaw) {
        const double x = toUnrolled(0, 0) * c.x + toUnrolled(0, 1) * c.y + toUnrolled(0, 2);
        const double y = toUnrolled(1, 0) * c.x + toUnrolled(1, 1) * c.y + toUnrolled(1, 2);
        minX = std::min(minX, x); maxX = std::max(maxX, x);
        minY = std::min(minY, y); maxY = std::max(maxY, y);
    }
    const double cxObs = o.box_x + 0.5 * o.box_width, cyObs = o.box_y + 0.5 * o.box_height;
    const double truthHeight = maxY - minY;
    return cxObs >= minX && cxObs <= maxX && cyObs >= minY && cyObs <= maxY && o.median_height_px > 0.5 * truthHeight &&
           o.median_height_px < 2.0 * truthHeight;
}

}  // namespace wf::sign::bench

namespace wf::sign::bench {

std::string officeMapPath() { return std::string(WF_REPO_ROOT) + "/Maps/Buildings/wayfinder-office.json"; }

bool readMapCatalogue(const std::string& mapPath, std::vector<CatalogueEntry>* out, std::string* error) {
    out->clear();
    try {
        cv::FileStorage fs(mapPath, cv::FileStorage::READ | cv::FileStorage::FORMAT_JSON);
        if (!fs.isOpened()) {
            *error = mapPath + ": cannot open the map";
            return false;
        }
        const cv::FileNode kinds = fs["signKinds"];
        if (kinds.empty() || !kinds.isSeq()) {
            *error = mapPath + ": the map has no signKinds catalogue";
            return false;
        }
        out->reserve(kinds.size());
        for (const auto& k : kinds) {
            CatalogueEntry e;
            e.kind = static_cast<std::string>(k["kind"]);
            if (!k["faceColor"].empty()) e.faceColour = static_cast<std::string>(k["faceColor"]);
            if (!k["legendColor"].empty()) e.legendColour = static_cast<std::string>(k["legendColor"]);
            e.entry.face_height_m = k["heightMeters"].real();
            e.entry.face_width_m = k["widthMeters"].real();
            e.entry.double_sided = !k["doubleSided"].empty() && static_cast<int>(k["doubleSided"]) != 0;
            if (!k["maxRangeMeters"].empty()) e.entry.max_range_m = k["maxRangeMeters"].real();
            e.entry.reads_text = !k["readsText"].empty() && static_cast<int>(k["readsText"]) != 0;
            if (!k["mountingHeightMeters"].empty()) {
                const double centre = k["mountingHeightMeters"].real() + 0.5 * e.entry.face_height_m;
                e.entry.centre_above_camera_min_m = centre - 1.7 - 0.1;
                e.entry.centre_above_camera_max_m = centre - 1.0 + 0.1;
            }
            out->push_back(std::move(e));
        }
    } catch (const cv::Exception& e) {
        *error = mapPath + ": " + e.what();
        return false;
    }
    for (CatalogueEntry& e : *out) {
        e.entry.kind = e.kind.c_str();
        e.entry.face_colour = e.faceColour.empty() ? nullptr : e.faceColour.c_str();
        e.entry.legend_colour = e.legendColour.empty() ? nullptr : e.legendColour.c_str();
    }
    return true;
}

std::unique_ptr<DetectorHandle> makeWithCatalogue(const std::vector<std::string>& paths, const std::vector<std::string>& kinds,
                                                  const std::vector<CatalogueEntry>& catalogue, const std::string& unetPath,
                                                  int wallKindsPerFrame, int plateGate, int wallKindFramePeriod) {
    auto d = std::make_unique<DetectorHandle>();
    std::vector<const char*> p, k;
    for (const auto& s : paths) p.push_back(s.c_str());
    for (const auto& s : kinds) k.push_back(s.c_str());
    std::vector<wf_sign_kind> entries;
    for (const auto& e : catalogue) entries.push_back(e.entry);
    wf_detector_options opts = WF_DETECTOR_OPTIONS_INIT;
    opts.kind = unetPath.empty() ? WF_DETECTOR_CASCADE : WF_DETECTOR_UNET;
    if (!unetPath.empty()) opts.unet_path = unetPath.c_str();
    opts.cascade_paths = p.data();
    opts.cascade_kinds = k.data();
    opts.cascade_count = p.size();
    opts.catalogue = entries.data();
    opts.catalogue_count = entries.size();
    opts.cascade_wall_kinds_per_frame = wallKindsPerFrame;
    opts.cascade_plate_gate = plateGate;
    opts.cascade_wall_kind_frame_period = wallKindFramePeriod;
    if (wf_detector_create(&d->handle, &opts) != WF_STATUS_OK) d->error = wf_thread_last_error();
    return d;
}

}  // namespace wf::sign::bench
