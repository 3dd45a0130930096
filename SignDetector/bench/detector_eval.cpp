// wf_detector_eval: the paper's Table 1 on a rendered test set, for every detector we have.
//
//   wf_detector_eval --testset DIR [--models DIR] [--reference CASCADE.xml] [--limit N] [--every K] [--rows a,b,...]
//
// DIR holds labels.jsonl and the images (SignDetector/training/render_signs.py --split test). Rows:
//   cascade-vga  our cascade (models/exit_sign_cascade.xml), frames resized to 640 x 480
//   cascade-hr   our cascade given 1920 x 1440 frames (searched at VGA, measured on the frame: the phone's input)
//   cascade-hr-native   the same frames searched at their own size (cascade_search_max_long_side_px = -1)
//   cascade-vga-full, cascade-hr-full   the same without the colour gate (whole-frame search)
//   unet         U-Net multi-scale (models/sign_unet.onnx) on 1920 x 1440 frames
//   unet-native  the same on each frame at its own size (e.g. 360 x 640 portrait frames, as the phone gives them)
//   unet-deconv  the same with OpenCV's own Deconvolution layer for the upsampling (the sub-pixel layer's baseline)
//   any row + "-rough": without face-edge refinement; + "-srgb": the refiner reads pixels as sRGB
//   reference    the reference app's cascade (../shared/.../exit_sign_cascade.xml) on 640 x 480, its settings
// A row whose model is missing is reported as skipped. Prints Markdown: median percent range error per
// true distance (2..9 m), missed signs per distance, precision / recall / false positives per 1000 sign-free
// frames, mean time per frame. Range uses the labelled face height and, in the root CMake build, the
// product's estimator (wf_range_apparent_height_slices, ray-elevation model: elevations of
// the sign's centre line at its column); a second table uses the paper's equation 3, which ignores the
// column (it gives about range x cos(bearing)) and is therefore biased short off-axis. Reference rows range
// the labelled corners with each formula: the floor that the formula alone leaves.
#include "bench_support.hpp"
#include "range_formula.hpp"
#include "wf_range.h"

#include "wf_range.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>

using namespace wf::sign::bench;

namespace {

struct Row {
    std::string id, title;
    cv::Size size;
    std::unique_ptr<DetectorHandle> detector;
    std::string skipped;
    // Results.
    std::map<int, std::vector<double>> errorsPercent;  // per distance bin
    std::map<int, std::vector<double>> signedErrorsPercent;  // 100 (e - a) / a: bias
    std::map<int, std::vector<double>> eq3ErrorsPercent;     // |e - a| / a with the paper's equation 3
    std::map<int, int> signs, missed;
    long truePositives = 0, falsePositives = 0, falseNegatives = 0;
    long signFreeFrames = 0, signFreeFalsePositives = 0;
    long frames = 0, rejected = 0;
    double seconds = 0;
};

double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string percent(double value) {
    if (std::isnan(value)) return "N/A";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", value);
    return buf;
}


/// Range (meters) from slice medians in the unrolled image (rows and columns in unrolled pixels, slopes
/// dv/du) by the product's estimator: the apparent-height method, ray-elevation model. NaN when
/// the estimator rejects the measurement.
double productRangeMeters(double bottomEdgePx, double heightPx, double centerColumnPx, double extentWidthPx,
                          double bottomSlope, double topSlope, double fxPx, double fyPx, double cxPx, double cyPx,
                          double signHeightMeters, double pitchRad) {
    const wf_range_unrolled_camera camera{fxPx, fyPx, cxPx, cyPx, pitchRad, 0.0};
    wf_range_slice_measurement m{};
    m.median_bottom_row_px = bottomEdgePx;
    m.median_height_px = heightPx;
    m.center_column_px = centerColumnPx;
    m.bottom_edge_slope = bottomSlope;
    m.top_edge_slope = topSlope;
    m.extent_width_px = extentWidthPx;
    wf_range_result result{};
    if (wf_range_apparent_height_slices(&result, &camera, &m, signHeightMeters, WF_RANGE_SLICE_MODEL_RAY_ELEVATION) != 0) {
        return std::nan("");
    }
    return result.range_m;
}

/// Range (meters) of a detector observation by the product's estimator (see productRangeMeters).
double observationProductRangeMeters(const wf_detector_observation& o, double signHeightMeters, double pitchRad) {
    return productRangeMeters(o.median_bottom_row_px, o.median_height_px, o.center_column_px, o.extent_width_px,
                              o.bottom_edge_slope, o.top_edge_slope, o.unrolled_fx, o.unrolled_fy, o.unrolled_cx,
                              o.unrolled_cy, signHeightMeters, pitchRad);
}

/// Ranges (meters) of a labelled sign from its exact corners (TL, TR, BR, BL raw pixels), unrolled with
/// the range library's map for the frame's intrinsics and roll: `eq3` by the paper's equation 3 at the
/// midpoints of the top and bottom edges, `product` by the product's estimator on the slice measurement an
/// exact mask would give (edge lines through the corners).
struct CornerRanges {
    double eq3 = std::nan(""), product = std::nan("");
};

CornerRanges cornerRanges(const LabelledFrame& frame, const LabelledSign& sign) {
    CornerRanges out;
    const wf_range_intrinsics raw{frame.fx, frame.fy, frame.cx, frame.cy};
    wf_range_unroll_map map{};
    if (wf_range_unroll_map_make(&map, &raw, frame.rollRad, frame.width, frame.height) != 0) return out;
    wf_range_point c[4];
    for (int i = 0; i < 4; ++i) {
        const wf_range_point p{sign.cornersRaw[i].x, sign.cornersRaw[i].y};
        if (wf_range_unroll_point(&c[i], &map, &p) != 0) return out;
    }
    const wf_range_intrinsics& u = map.unrolled;
    const double topV = 0.5 * (c[0].v + c[1].v), bottomV = 0.5 * (c[3].v + c[2].v);
    out.eq3 = wf::sign::rangeFromApparentHeight(sign.heightMeters, bottomV, bottomV - topV, u.fy, u.cy, frame.pitchRad);
    // An exact mask's slices: top edge = line TL-TR, bottom edge = line BL-BR, extent = corners' columns.
    const double minU = std::min({c[0].u, c[1].u, c[2].u, c[3].u}), maxU = std::max({c[0].u, c[1].u, c[2].u, c[3].u});
    const double midU = 0.5 * (minU + maxU);
    const double topSlope = (c[1].v - c[0].v) / (c[1].u - c[0].u), bottomSlope = (c[2].v - c[3].v) / (c[2].u - c[3].u);
    const double topAtMid = c[0].v + topSlope * (midU - c[0].u), bottomAtMid = c[3].v + bottomSlope * (midU - c[3].u);
    out.product = productRangeMeters(bottomAtMid, bottomAtMid - topAtMid, midU, maxU - minU, bottomSlope, topSlope, u.fx,
                                     u.fy, u.cx, u.cy, sign.heightMeters, frame.pitchRad);
    return out;
}

void usage() {
    std::cerr << "usage: wf_detector_eval --testset DIR [--models DIR] [--reference CASCADE.xml] [--limit N]\n"
                 "                        [--every K] [--rows cascade-vga,cascade-hr,unet,unet-deconv,reference,cascade-vga-full,cascade-hr-full,cascade-vga-v3,cascade-hr-v3,\n"
                 "                        cascade-vga-v4,cascade-hr-v4] [--threads N]\n"
                 "  rows take a suffix: -rough = without face-edge refinement (the box's or mask's own edges),\n"
                 "  -native = cascade rows search the frame at its own size, not shrunk to VGA; unet-native is given the\n"
                 "               frame at its own size, not resized to 1920 x 1440 (e.g. 360 x 640 portrait frames),\n"
                 "               -srgb = the refiner reads pixels as sRGB-encoded (e.g. cascade-vga-rough, unet-srgb)\n"
                 "  --every K   use every K-th frame (keeps the per-distance balance of a rendered test set)\n"
                 "  --limit N   use the first N frames (after --every)\n"
                 "  --shift K   drop the first K columns and rows of every resized frame (moves every scan grid by K px;\n"
                 "               compare search settings over several K: single far signs come and go with the grid)\n"
                 "  --min-elevation RAD  our cascade rows search only rows at least RAD above the horizon (default:\n"
                 "               the detector's -0.15 rad; nan = every row)\n"
                 "  --times FILE  write the detection time of every frame and row as CSV (row, frame, true distance or -1, ms)\n"
                 "  --dump FILE  write every observation as CSV (row, frame, true distance or -1, matched, score, box,\n"
                 "               median height and bottom edge, extent width, elevation of the box centre in rad, centre column,\n"
                 "               top and bottom edge slopes, the unrolled -> raw affine map a00..a12)\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::string testset, models = productModelsDir(), reference = referenceCascadePath();
    std::string rowsArg = "cascade-vga,cascade-hr,unet,reference";
    long limit = -1, every = 1;
    double minElevation = 0;  // the detector's default row limit (-0.15 rad); NaN = every row
    int threads = 1, shiftPx = 0;
    std::string dumpPath, timesPath;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                usage();
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--testset") testset = next();
        else if (a == "--models") models = next();
        else if (a == "--reference") reference = next();
        else if (a == "--limit") limit = std::stol(next());
        else if (a == "--rows") rowsArg = next();
        else if (a == "--every") every = std::max(1L, std::stol(next()));
        else if (a == "--min-elevation") minElevation = std::stod(next());
        else if (a == "--threads") threads = std::stoi(next());
        else if (a == "--shift") shiftPx = std::max(0, std::stoi(next()));
        else if (a == "--dump") dumpPath = next();
        else if (a == "--times") timesPath = next();
        else {
            usage();
            return 2;
        }
    }
    if (testset.empty()) {
        usage();
        return 2;
    }
    cv::setNumThreads(threads);
    std::vector<LabelledFrame> frames;
    std::string error;
    if (!readLabels(testset, &frames, &error)) {
        std::cerr << "wf_detector_eval: " << error << "\n";
        return 1;
    }
    if (every > 1) {
        std::vector<LabelledFrame> kept;
        for (size_t i = 0; i < frames.size(); i += static_cast<size_t>(every)) kept.push_back(frames[i]);
        frames.swap(kept);
    }
    if (limit >= 0 && static_cast<long>(frames.size()) > limit) frames.resize(limit);

    std::vector<Row> rows;
    std::vector<CatalogueEntry> officeCatalogue;  // read on first use (U-Net rows)
    std::string catalogueError;
    std::stringstream rowIds(rowsArg);
    for (std::string id; std::getline(rowIds, id, ',');) {
        Row r;
        r.id = id;
        std::string model;
        // Suffixes: -rough = without face-edge refinement (the box's or mask's own edges), -srgb = the refiner
        // reads the pixels as sRGB-encoded.
        FaceEdgeOptions faceEdges;
        std::string faceEdgeTitle;
        for (const auto& [tail, refinement, transfer, title] :
             {std::tuple<std::string, int, int, std::string>{"-rough", -1, 0, ", no edge refinement"},
              std::tuple<std::string, int, int, std::string>{"-srgb", 1, 2, ", edges refined (sRGB)"}}) {
            if (id.size() > tail.size() && id.compare(id.size() - tail.size(), tail.size(), tail) == 0) {
                id.resize(id.size() - tail.size());
                faceEdges = FaceEdgeOptions{refinement, transfer};
                faceEdgeTitle = title;
            }
        }
        // Suffix -native: cascade rows search the frame at its own size, not shrunk to VGA; the U-Net row is given the
        // frame at its own size, not resized to 1920 x 1440 (a 360 x 640 portrait frame as the phone gives it).
        bool native = false;
        if (id.size() > 7 && id.compare(id.size() - 7, 7, "-native") == 0) {
            id.resize(id.size() - 7);
            native = true;
        }
        if (id == "cascade-vga" || id == "cascade-hr" || id == "cascade-vga-full" || id == "cascade-hr-full" ||
            id == "cascade-vga-v3" || id == "cascade-hr-v3" || id == "cascade-vga-v4" || id == "cascade-hr-v4") {
            model = models + "/exit_sign_cascade.xml";
            const auto endsWith = [&](const std::string& tail) {
                return id.size() > tail.size() && id.compare(id.size() - tail.size(), tail.size(), tail) == 0;
            };
            const bool vga = id.rfind("cascade-vga", 0) == 0, full = endsWith("-full"), v3 = endsWith("-v3"),
                       v4 = endsWith("-v4");
            r.size = vga ? cv::Size(640, 480) : cv::Size(1920, 1440);
            r.title = vga ? "Cascade box, VGA 640x480" : "Cascade box, HR 1920x1440";
            r.title += native ? ", searched at its own size" : vga ? "" : ", searched at VGA";
            if (full) r.title += ", full search";
            if (v3) r.title += ", earliest gated search (24 px gate margins, every window in tiles, no placement prior, no crowded gate)";
            if (v4) r.title += ", earlier gate regions (24 px gate margins, every window in tiles)";
            // Full search: no gate and every row (the cascade before the gate and the row limit).
            const double rowLimit = full ? std::nan("") : minElevation;
            if (std::isnan(rowLimit) && !full) r.title += ", all rows";
            if (!std::isnan(rowLimit) && rowLimit != 0) r.title += ", rows above " + std::to_string(rowLimit).substr(0, 5) + " rad";
            if (fileExists(model)) r.detector = makeCascade(model, 0, 0, 0, rowLimit, full,
                                                                 full || v3 ? CascadeSearch::WideGateRegionsNoPrior
                                                                 : v4      ? CascadeSearch::WideGateRegions
                                                                           : CascadeSearch::Defaults,
                                                                 faceEdges, native ? -1 : 0);
        } else if (id == "unet" || id == "unet-deconv") {
            // unet-deconv: OpenCV's own Deconvolution layer for the upsampling (the baseline of the sub-pixel layer).
            const bool deconv = id == "unet-deconv";
            model = models + "/sign_unet.onnx";
            r.size = native ? cv::Size() : cv::Size(1920, 1440);
            r.title = std::string("U-Net multi-scale, ") + (native ? "frame at its own size" : "1920x1440") +
                      (deconv ? ", OpenCV's Deconvolution" : "");
            // The bundled office's sign kinds, as the product passes the map's (a class of the model for a kind
            // other than the Exit sign is verified with its face's limits and lifts the coarse elevation cut).
            if (officeCatalogue.empty() && !readMapCatalogue(officeMapPath(), &officeCatalogue, &catalogueError)) {
                std::cerr << "wf_detector_eval: " << catalogueError << "\n";
                return 1;
            }
            if (fileExists(model)) r.detector = makeUnet(model, 0, faceEdges, &officeCatalogue, deconv ? -1 : 0);
        } else if (id == "reference") {
            model = reference;
            r.size = cv::Size(640, 480);
            r.title = "Reference cascade (iNavigate), VGA";
            // All rows and no placement prior, as the app did.
            if (fileExists(model)) r.detector = makeCascade(model, 36, 24, 5.0, std::nan(""), false, CascadeSearch::WideGateRegionsNoPrior);
        } else {
            std::cerr << "wf_detector_eval: unknown row " << id << "\n";
            return 2;
        }
        r.title += faceEdgeTitle;
        if (!r.detector) r.skipped = "model not found: " + model;
        else if (!*r.detector) r.skipped = r.detector->error;
        rows.push_back(std::move(r));
    }

    std::vector<wf_detector_observation> observations;
    std::ofstream dump;
    if (!dumpPath.empty()) {
        dump.open(dumpPath);
        dump << "row,frame,truth_m,matched,score,box_x,box_y,box_w,box_h,height_px,bottom_px,extent_px,elevation_rad,"
                "center_px,top_slope,bottom_slope,a00,a01,a02,a10,a11,a12\n";
    }
    std::ofstream times;
    if (!timesPath.empty()) {
        times.open(timesPath);
        times << "row,frame,truth_m,ms\n";
    }
    std::map<int, std::vector<double>> cornerProductErrors, cornerEq3Errors;  // reference rows, |e - a| / a %
    for (size_t fi = 0; fi < frames.size(); ++fi) {
        const LabelledFrame& labels = frames[fi];
        for (const LabelledSign& sign : labels.signs) {
            const int bin = static_cast<int>(std::lround(sign.rangeMeters));
            const CornerRanges z = cornerRanges(labels, sign);
            if (std::isfinite(z.product)) cornerProductErrors[bin].push_back(100.0 * std::abs(z.product - sign.rangeMeters) / sign.rangeMeters);
            if (std::isfinite(z.eq3)) cornerEq3Errors[bin].push_back(100.0 * std::abs(z.eq3 - sign.rangeMeters) / sign.rangeMeters);
        }
        const cv::Mat bgr = cv::imread(labels.imagePath, cv::IMREAD_COLOR);
        if (bgr.empty()) {
            std::cerr << "wf_detector_eval: cannot read " << labels.imagePath << "\n";
            return 1;
        }
        for (Row& r : rows) {
            if (!r.skipped.empty()) continue;
            const auto prepared = prepareFrame(bgr, labels, r.size.empty() ? bgr.size() : r.size, shiftPx);
            const auto t0 = std::chrono::steady_clock::now();
            const int status = detect(*r.detector, *prepared, &observations);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            r.seconds += seconds;
            if (times) {
                const int truth = labels.signs.empty() ? -1 : static_cast<int>(std::lround(labels.signs[0].rangeMeters));
                times << r.id << "," << fi << "," << truth << "," << 1e3 * seconds << "\n";
            }
            ++r.frames;
            if (status < 0) {
                ++r.rejected;
                std::cerr << "wf_detector_eval: " << labels.imagePath << ": " << wf_detector_last_error(r.detector->handle)
                          << "\n";
                continue;
            }
            // Greedy matching, best score first (observations come sorted by score).
            std::vector<bool> used(observations.size(), false);
            for (const LabelledSign& sign : prepared->labels.signs) {
                const int bin = static_cast<int>(std::lround(sign.rangeMeters));
                ++r.signs[bin];
                bool found = false;
                for (size_t k = 0; k < observations.size() && !found; ++k) {
                    if (used[k] || !matches(observations[k], sign)) continue;
                    used[k] = true;
                    found = true;
                    const double z = observationProductRangeMeters(observations[k], sign.heightMeters, labels.pitchRad);
                    if (std::isfinite(z)) {
                        r.errorsPercent[bin].push_back(100.0 * std::abs(z - sign.rangeMeters) / sign.rangeMeters);
                        r.signedErrorsPercent[bin].push_back(100.0 * (z - sign.rangeMeters) / sign.rangeMeters);
                    }
                    const double z3 = observationRangeMeters(observations[k], sign.heightMeters, labels.pitchRad);
                    if (std::isfinite(z3)) {
                        r.eq3ErrorsPercent[bin].push_back(100.0 * std::abs(z3 - sign.rangeMeters) / sign.rangeMeters);
                    }
                }
                if (found) ++r.truePositives;
                else {
                    ++r.falseNegatives;
                    ++r.missed[bin];
                }
            }
            if (dump) {
                for (size_t k = 0; k < observations.size(); ++k) {
                    const wf_detector_observation& o = observations[k];
                    const int truth = labels.signs.empty() ? -1 : static_cast<int>(std::lround(labels.signs[0].rangeMeters));
                    const double elevation =
                        labels.pitchRad + std::atan((o.unrolled_cy - (o.box_y + 0.5 * o.box_height)) / o.unrolled_fy);
                    dump << r.id << "," << fi << "," << truth << "," << int(used[k]) << "," << o.score << "," << o.box_x << ","
                         << o.box_y << "," << o.box_width << "," << o.box_height << "," << o.median_height_px << ","
                         << o.median_bottom_row_px << "," << o.extent_width_px << "," << elevation << ","
                         << o.center_column_px << "," << o.top_edge_slope << "," << o.bottom_edge_slope;
                    for (double a : o.unrolled_to_raw) dump << "," << a;
                    dump << "\n";
                }
            }
            const long unmatched = static_cast<long>(std::count(used.begin(), used.end(), false));
            r.falsePositives += unmatched;
            if (labels.signs.empty()) {
                ++r.signFreeFrames;
                r.signFreeFalsePositives += unmatched;
            }
        }
        if ((fi + 1) % 100 == 0) std::cerr << "evaluated " << (fi + 1) << "/" << frames.size() << " frames\n";
    }

    const int bins[] = {2, 3, 4, 5, 6, 7, 8, 9};
    std::cout << "Test set: " << testset << " (" << frames.size() << " frames)\n\n";
    // One per-distance table of medians over `errors`; with `cornerErrors`, a reference row on the labelled
    // corners follows (product-estimator builds only).
    auto errorTable = [&](const char* heading, std::map<int, std::vector<double>> Row::*errors,
                          const std::map<int, std::vector<double>>* cornerErrors, const char* cornerTitle) {
        std::cout << heading << "\n\n| Method |";
        for (int b : bins) std::cout << " " << b << " m |";
        std::cout << "\n|---|";
        for (size_t i = 0; i < std::size(bins); ++i) std::cout << "---|";
        std::cout << "\n";
        for (const Row& r : rows) {
            std::cout << "| " << r.title << " |";
            for (int b : bins) {
                const auto it = (r.*errors).find(b);
                std::cout << " " << (r.skipped.empty() ? percent(median(it != (r.*errors).end() ? it->second : std::vector<double>{})) : "-") << " |";
            }
            std::cout << "\n";
        }
        if (cornerErrors != nullptr) {
            std::cout << "| " << cornerTitle << " |";
            for (int b : bins) {
                const auto it = cornerErrors->find(b);
                std::cout << " " << percent(median(it != cornerErrors->end() ? it->second : std::vector<double>{})) << " |";
            }
            std::cout << "\n";
        }
    };
    errorTable("Median percent range error |e - a| / a per true distance (matched signs only; product estimator: "
               "wf_range_apparent_height_slices, ray-elevation model)",
               &Row::errorsPercent, &cornerProductErrors, "(reference) labelled corners, product estimator");
    std::cout << "\n";
    errorTable("Median percent range error with the paper's equation 3 (column ignored: biased short off-axis)",
               &Row::eq3ErrorsPercent, &cornerEq3Errors, "(reference) labelled corners, paper eq. 3");
    std::cout << "\n";
    errorTable("Median signed range error (e - a) / a per true distance (bias; negative = estimated too near)",
               &Row::signedErrorsPercent, nullptr, nullptr);
    std::cout << "\nMissed signs per true distance (missed / labelled)\n\n| Method |";
    for (int b : bins) std::cout << " " << b << " m |";
    std::cout << "\n|---|";
    for (size_t i = 0; i < std::size(bins); ++i) std::cout << "---|";
    std::cout << "\n";
    for (const Row& r : rows) {
        std::cout << "| " << r.title << " |";
        for (int b : bins) {
            if (!r.skipped.empty()) {
                std::cout << " - |";
                continue;
            }
            const int n = r.signs.count(b) ? r.signs.at(b) : 0;
            const int m = r.missed.count(b) ? r.missed.at(b) : 0;
            std::cout << " " << m << "/" << n << " |";
        }
        std::cout << "\n";
    }
    std::cout << "\nOperating point (detector defaults)\n\n"
                 "| Method | precision | recall | FP / 1000 sign-free frames | mean ms / frame | rejected frames |\n"
                 "|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
        if (!r.skipped.empty()) {
            std::cout << "| " << r.title << " | skipped: " << r.skipped << " | | | | |\n";
            continue;
        }
        char line[512];
        const double precision = r.truePositives + r.falsePositives
                                     ? double(r.truePositives) / double(r.truePositives + r.falsePositives) : std::nan("");
        const double recall = r.truePositives + r.falseNegatives
                                  ? double(r.truePositives) / double(r.truePositives + r.falseNegatives) : std::nan("");
        const double fpPerThousand = r.signFreeFrames ? 1000.0 * double(r.signFreeFalsePositives) / double(r.signFreeFrames)
                                                      : std::nan("");
        char fp[64];
        if (r.signFreeFrames) std::snprintf(fp, sizeof fp, "%.0f (%ld frames)", fpPerThousand, r.signFreeFrames);
        else std::snprintf(fp, sizeof fp, "n/a (no sign-free frames)");
        std::snprintf(line, sizeof line, "| %s | %.3f | %.3f | %s | %.1f | %ld |\n", r.title.c_str(), precision, recall, fp,
                      r.frames ? 1000.0 * r.seconds / r.frames : 0.0, r.rejected);
        std::cout << line;
    }
    return 0;
}
