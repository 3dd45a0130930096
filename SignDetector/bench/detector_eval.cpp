// wf_detector_eval: the paper's Table 1 on a rendered test set, for every detector we have.
//
//   wf_detector_eval --testset DIR [--models DIR] [--reference CASCADE.xml] [--limit N] [--every K] [--rows a,b,...]
//
// DIR holds labels.jsonl and the images (SignDetector/training/render_signs.py --split test). Rows:
//   cascade-vga  our cascade (models/exit_sign_cascade.xml), frames resized to 640 x 480
//   cascade-hr   our cascade on 1920 x 1440 frames
//   unet         U-Net multi-scale (models/sign_unet.onnx) on 1920 x 1440 frames
//   reference    the reference app's cascade (../shared/.../exit_sign_cascade.xml) on 640 x 480, its settings
// A row whose model is missing is reported as skipped. Prints Markdown: median percent range error per
// true distance (2..9 m; range from the paper's equation 3 with the labelled face height), missed signs per
// distance, precision / recall / false positives per 1000 sign-free frames, mean time per frame.
#include "bench_support.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <sstream>

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

void usage() {
    std::cerr << "usage: wf_detector_eval --testset DIR [--models DIR] [--reference CASCADE.xml] [--limit N]\n"
                 "                        [--every K] [--rows cascade-vga,cascade-hr,unet,reference] [--threads N]\n"
                 "  --every K   use every K-th frame (keeps the per-distance balance of a rendered test set)\n"
                 "  --limit N   use the first N frames (after --every)\n"
                 "  --min-elevation RAD  our cascade rows search only rows at least RAD above the horizon\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::string testset, models = productModelsDir(), reference = referenceCascadePath();
    std::string rowsArg = "cascade-vga,cascade-hr,unet,reference";
    long limit = -1, every = 1;
    double minElevation = std::nan("");
    int threads = 1;
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
    std::stringstream rowIds(rowsArg);
    for (std::string id; std::getline(rowIds, id, ',');) {
        Row r;
        r.id = id;
        std::string model;
        if (id == "cascade-vga" || id == "cascade-hr") {
            model = models + "/exit_sign_cascade.xml";
            r.size = id == "cascade-vga" ? cv::Size(640, 480) : cv::Size(1920, 1440);
            r.title = id == "cascade-vga" ? "Cascade box, VGA 640x480" : "Cascade box, HR 1920x1440";
            if (!std::isnan(minElevation)) r.title += ", rows above " + std::to_string(minElevation).substr(0, 5) + " rad";
            if (fileExists(model)) r.detector = makeCascade(model, 0, 0, 0, minElevation);
        } else if (id == "unet") {
            model = models + "/sign_unet.onnx";
            r.size = cv::Size(1920, 1440);
            r.title = "U-Net multi-scale, 1920x1440";
            if (fileExists(model)) r.detector = makeUnet(model);
        } else if (id == "reference") {
            model = reference;
            r.size = cv::Size(640, 480);
            r.title = "Reference cascade (iNavigate), VGA";
            if (fileExists(model)) r.detector = makeCascade(model, 36, 24, 5.0);
        } else {
            std::cerr << "wf_detector_eval: unknown row " << id << "\n";
            return 2;
        }
        if (!r.detector) r.skipped = "model not found: " + model;
        else if (!*r.detector) r.skipped = r.detector->error;
        rows.push_back(std::move(r));
    }

    std::vector<wf_detector_observation> observations;
    for (size_t fi = 0; fi < frames.size(); ++fi) {
        const LabelledFrame& labels = frames[fi];
        const cv::Mat bgr = cv::imread(labels.imagePath, cv::IMREAD_COLOR);
        if (bgr.empty()) {
            std::cerr << "wf_detector_eval: cannot read " << labels.imagePath << "\n";
            return 1;
        }
        for (Row& r : rows) {
            if (!r.skipped.empty()) continue;
            const auto prepared = prepareFrame(bgr, labels, r.size);
            const auto t0 = std::chrono::steady_clock::now();
            const int status = detect(*r.detector, *prepared, &observations);
            r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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
                    const double z = observationRangeMeters(observations[k], sign.heightMeters, labels.pitchRad);
                    if (std::isfinite(z)) {
                        r.errorsPercent[bin].push_back(100.0 * std::abs(z - sign.rangeMeters) / sign.rangeMeters);
                        r.signedErrorsPercent[bin].push_back(100.0 * (z - sign.rangeMeters) / sign.rangeMeters);
                    }
                }
                if (found) ++r.truePositives;
                else {
                    ++r.falseNegatives;
                    ++r.missed[bin];
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
    std::cout << "Median percent range error |e - a| / a per true distance (matched signs only)\n\n";
    std::cout << "| Method |";
    for (int b : bins) std::cout << " " << b << " m |";
    std::cout << "\n|---|";
    for (size_t i = 0; i < std::size(bins); ++i) std::cout << "---|";
    std::cout << "\n";
    for (const Row& r : rows) {
        std::cout << "| " << r.title << " |";
        for (int b : bins) std::cout << " " << (r.skipped.empty() ? percent(median(r.errorsPercent.count(b) ? r.errorsPercent.at(b) : std::vector<double>{})) : "-") << " |";
        std::cout << "\n";
    }
    std::cout << "\nMedian signed range error (e - a) / a per true distance (bias; negative = estimated too near)\n\n"
                 "| Method |";
    for (int b : bins) std::cout << " " << b << " m |";
    std::cout << "\n|---|";
    for (size_t i = 0; i < std::size(bins); ++i) std::cout << "---|";
    std::cout << "\n";
    for (const Row& r : rows) {
        std::cout << "| " << r.title << " |";
        for (int b : bins) {
            const auto it = r.signedErrorsPercent.find(b);
            std::cout << " " << (r.skipped.empty() ? percent(median(it != r.signedErrorsPercent.end() ? it->second : std::vector<double>{})) : "-") << " |";
        }
        std::cout << "\n";
    }
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
