// wf_kinds_eval: the sign kinds beyond the Exit sign (restroom, elevator and stairs pictograms, room-number
// placards) on a rendered held-out set, through the product's one call per frame (wf_detector_sense).
//
//   wf_kinds_eval --testset DIR [--models DIR] [--map MAP.json] [--limit N] [--repeat K]
//                 [--unet MODEL.onnx [--unet-baseline MODEL.onnx]]
//   (WF_KINDS_ROTATION=N sets wf_detector_options.cascade_wall_kinds_per_frame: N wall kinds searched per searched
//    frame; WF_KINDS_PERIOD=P sets cascade_wall_kind_frame_period: one frame in P searched;
//    WF_KINDS_PLATE_GATE=G sets wf_detector_options.cascade_plate_gate: -1 = off, the search before the plate gate)
//
// DIR: SignDetector/training/render_signs.py --split test_kinds (VGA frames, labels.jsonl with "kind" and, for
// placards, "text"). The catalogue is the map's "signKinds" (default: the bundled office's, which has every
// kind), turned into wf_sign_kind as the Swift wrapper does. Two detectors, each frame run `--repeat` times:
//   exit-only   the Exit cascade alone (what the phone ran before)
//   all-kinds   the Exit cascade plus <kind>_cascade.xml for every other kind of the catalogue found in --models
// With --unet (the U-Net path; classes.json beside each model):
//   exit-only   the --unet-baseline U-Net (default --models/sign_unet.onnx) with no cascade beside it
//   all-kinds   the --unet U-Net with the cascades of the catalogue's kinds it has no class for beside it
// Prints Markdown: per kind and true distance, found / signs, median |range error| % and the signed median
// (bias); for placards how often the text was read right, read wrong, not read; false sightings per frame by
// kind (a sighting of a kind with no labelled sign of that kind under it; "confused" when it lies on a sign of
// another kind); the mean time per frame of both detectors, with the ratio (the issue's "extra sign classes
// add <= 20 %"), and the median, 95th percentile and largest time the extra kinds add to one frame.
#include "bench_support.hpp"
#include "text_reader.hpp"
#include "unroll.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace wf::sign::bench;

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// True when the sighting's corner centroid lies inside the sign's labelled corner box (raw pixels).
bool onSign(const wf_sign_sighting& s, const LabelledSign& sign) {
    double u = 0, v = 0;
    for (int i = 0; i < 4; ++i) {
        u += 0.25 * s.corners_raw_px[2 * i];
        v += 0.25 * s.corners_raw_px[2 * i + 1];
    }
    double u0 = 1e9, u1 = -1e9, v0 = 1e9, v1 = -1e9;
    for (const auto& c : sign.cornersRaw) {
        u0 = std::min(u0, c.x), u1 = std::max(u1, c.x), v0 = std::min(v0, c.y), v1 = std::max(v1, c.y);
    }
    return u >= u0 && u <= u1 && v >= v0 && v <= v1;
}

struct KindStats {
    std::map<int, int> signs, found;                       // per distance, decimetres (0.5 m bins)
    std::map<int, std::vector<double>> errors, signedErrors;  // percent
    int textRight = 0, textWrong = 0, textNone = 0;
    int falseSightings = 0, confused = 0;
};


}  // namespace

int main(int argc, char** argv) {
    cv::setNumThreads(1);  // one core, as wf_detector_bench: the times are one core's
    std::string testset, models = productModelsDir(), map = officeMapPath();
    std::string unet, unetBaseline;
    int limit = 0, repeat = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
        if (a == "--testset") testset = next();
        else if (a == "--models") models = next();
        else if (a == "--map") map = next();
        else if (a == "--limit") limit = std::atoi(next().c_str());
        else if (a == "--repeat") repeat = std::max(1, std::atoi(next().c_str()));
        else if (a == "--unet") unet = next();
        else if (a == "--unet-baseline") unetBaseline = next();
        else {
            std::fprintf(stderr, "usage: wf_kinds_eval --testset DIR [--models DIR] [--map MAP.json] [--limit N] [--repeat K] "
                                 "[--unet MODEL.onnx [--unet-baseline MODEL.onnx]]\n");
            return 2;
        }
    }
    if (testset.empty()) {
        std::fprintf(stderr, "wf_kinds_eval: --testset DIR is required\n");
        return 2;
    }
    std::vector<LabelledFrame> frames;
    std::string error;
    if (!readLabels(testset, &frames, &error)) {
        std::fprintf(stderr, "wf_kinds_eval: %s\n", error.c_str());
        return 1;
    }
    if (limit > 0 && frames.size() > size_t(limit)) frames.resize(limit);
    std::vector<CatalogueEntry> catalogue;
    if (!readMapCatalogue(map, &catalogue, &error)) {
        std::fprintf(stderr, "wf_kinds_eval: %s\n", error.c_str());
        return 1;
    }
    // The U-Net's own classes (none on the cascade path): no cascade for those kinds.
    std::vector<std::string> unetClasses;
    if (!unet.empty()) {
        if (!readUnetClasses(unet, &unetClasses, &error)) {
            std::fprintf(stderr, "wf_kinds_eval: %s\n", error.c_str());
            return 1;
        }
        if (unetBaseline.empty()) unetBaseline = models + "/sign_unet.onnx";
    }
    std::vector<std::string> paths{models + "/exit_sign_cascade.xml"}, kinds{"exit"};
    for (const auto& e : catalogue) {
        if (e.kind == "exit") continue;
        if (std::find(unetClasses.begin(), unetClasses.end(), e.kind) != unetClasses.end()) continue;
        const std::string path = models + "/" + e.kind + "_cascade.xml";
        if (fileExists(path)) {
            paths.push_back(path);
            kinds.push_back(e.kind);
        } else {
            std::fprintf(stderr, "wf_kinds_eval: no model for kind '%s' (%s): not evaluated\n", e.kind.c_str(), path.c_str());
        }
    }
    const char* rotation = std::getenv("WF_KINDS_ROTATION");
    const int wallKindsPerFrame = rotation ? std::atoi(rotation) : 0;
    const char* plateGateSetting = std::getenv("WF_KINDS_PLATE_GATE");
    const int plateGate = plateGateSetting ? std::atoi(plateGateSetting) : 0;
    const char* periodSetting = std::getenv("WF_KINDS_PERIOD");
    const int period = periodSetting ? std::atoi(periodSetting) : 0;
    std::unique_ptr<DetectorHandle> exitOnly, all;
    if (unet.empty()) {
        exitOnly = makeWithCatalogue({paths[0]}, {"exit"}, catalogue, "", wallKindsPerFrame);
        all = makeWithCatalogue(paths, kinds, catalogue, "", wallKindsPerFrame, plateGate, period);
    } else {
        const std::vector<std::string> besidePaths(paths.begin() + 1, paths.end()), besideKinds(kinds.begin() + 1, kinds.end());
        exitOnly = makeWithCatalogue({}, {}, catalogue, unetBaseline, wallKindsPerFrame);
        all = makeWithCatalogue(besidePaths, besideKinds, catalogue, unet, wallKindsPerFrame, plateGate, period);
        std::printf("U-Net path: exit-only = %s; all kinds = %s with %zu cascade(s) beside it\n\n", unetBaseline.c_str(),
                    unet.c_str(), besidePaths.size());
    }
    for (auto* d : {exitOnly.get(), all.get()}) {
        if (!*d) {
            std::fprintf(stderr, "wf_kinds_eval: %s\n", d->error.c_str());
            return 1;
        }
    }
    std::printf("text reader: %s\n\n", wf_detector_reads_text(all->handle) ? "tesseract"
                                                                            : wf_detector_text_reader_problem(all->handle));
    // The text reader alone on every labelled placard (its exact box): what reading can do when detection is right.
    wf::sign::TextReader reader;
    std::string readerError;
    const bool readerLoaded = reader.load("", &readerError);
    std::map<int, std::array<int, 3>> labelledReads;  // per distance: right, wrong, not read
    std::map<std::string, KindStats> stats;
    double exitSeconds = 0, allSeconds = 0;
    std::vector<double> extraMs;  // per frame: all kinds minus exit-only, ms (mean over the repeats)
    long signFree = 0, signFreeFalse = 0;
    std::vector<wf_sign_sighting> out(64);
    for (const LabelledFrame& f : frames) {
        const cv::Mat bgr = cv::imread(f.imagePath, cv::IMREAD_COLOR);
        if (bgr.empty()) {
            std::fprintf(stderr, "wf_kinds_eval: cannot read %s\n", f.imagePath.c_str());
            return 1;
        }
        auto prepared = prepareFrame(bgr, f, bgr.size());
        convertPixelFormat(prepared.get(), WF_PIXEL_BGRA8);  // what the phone sends the cascade
        size_t count = 0;
        double frameSeconds[2] = {0, 0};
        int which = 0;
        for (auto [d, seconds] : {std::pair{exitOnly.get(), &exitSeconds}, std::pair{all.get(), &allSeconds}}) {
            for (int r = 0; r < repeat; ++r) {
                const auto t0 = std::chrono::steady_clock::now();
                wf_detector_sense(d->handle, &prepared->frame, out.data(), out.size(), &count);
                const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                *seconds += dt;
                frameSeconds[which] += dt;
            }
            ++which;
        }
        extraMs.push_back(1000.0 * (frameSeconds[1] - frameSeconds[0]) / repeat);
        if (readerLoaded) {
            cv::Mat gray;
            cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
            const wf::sign::Unrolling u = wf::sign::Unrolling::forRoll(f.rollRad, wf::sign::Intrinsics{f.fx, f.fy, f.cx, f.cy},
                                                                       gray.size());
            const cv::Mat unrolled = u.apply(gray);
            for (const LabelledSign& sign : f.signs) {
                if (sign.text.empty()) continue;
                std::vector<cv::Point2f> pts;
                for (const auto& c : sign.cornersRaw) pts.push_back(cv::Point2f(u.rawToUnrolled(c)));
                const wf::sign::TextRead r = reader.read(unrolled, cv::boundingRect(pts));
                auto& counts = labelledReads[int(std::lround(sign.rangeMeters * 2)) * 5];
                counts[r.text.empty() ? 2 : r.text == sign.text ? 0 : 1]++;
                if (!r.text.empty() && r.text != sign.text) {
                    std::fprintf(stderr, "misread %s as %s (%.1f m, confidence %d)\n", sign.text.c_str(), r.text.c_str(),
                                 sign.rangeMeters, r.confidence);
                }
            }
        }
        // `out` holds the all-kinds detector's sightings of this frame.
        std::vector<bool> used(count, false);
        for (const LabelledSign& sign : f.signs) {
            if (sign.kind == "exit") continue;
            KindStats& k = stats[sign.kind];
            const int bin = int(std::lround(sign.rangeMeters * 2)) * 5;  // decimetres, nearest 0.5 m
            k.signs[bin]++;
            int best = -1;
            for (size_t i = 0; i < count; ++i) {
                if (!used[i] && sign.kind == out[i].kind && onSign(out[i], sign)) {
                    best = int(i);
                    break;
                }
            }
            if (best < 0) continue;
            used[best] = true;
            k.found[bin]++;
            const double e = 100.0 * (out[best].range_m - sign.rangeMeters) / sign.rangeMeters;
            k.errors[bin].push_back(std::abs(e));
            k.signedErrors[bin].push_back(e);
            if (!sign.text.empty()) {
                const std::string read = out[best].text;
                (read.empty() ? k.textNone : read == sign.text ? k.textRight : k.textWrong)++;
            }
        }
        for (size_t i = 0; i < count; ++i) {
            if (used[i] || std::string(out[i].kind) == "exit") continue;
            KindStats& k = stats[out[i].kind];
            k.falseSightings++;
            for (const LabelledSign& sign : f.signs) {
                if (onSign(out[i], sign)) {
                    k.confused++;
                    break;
                }
            }
            if (f.signs.empty()) signFreeFalse++;
        }
        if (f.signs.empty()) signFree++;
    }
    std::printf("| kind | distance | found / signs | median range error | bias |\n|---|---|---|---|---|\n");
    for (auto& [kind, k] : stats) {
        int signs = 0, found = 0;
        for (auto& [bin, n] : k.signs) {
            signs += n;
            found += k.found[bin];
            std::printf("| %s | %.1f m | %d / %d | %.1f %% | %+.1f %% |\n", kind.c_str(), bin / 10.0, k.found[bin], n,
                        median(k.errors[bin]), median(k.signedErrors[bin]));
        }
        std::printf("| %s | all | %d / %d (recall %.3f) | | |\n", kind.c_str(), found, signs, signs ? double(found) / signs : 0.0);
    }
    std::printf("\n| kind | false sightings per frame | of them on a sign of another kind | text right / wrong / not read |\n"
                "|---|---|---|---|\n");
    for (auto& [kind, k] : stats) {
        std::printf("| %s | %.3f | %d | %d / %d / %d |\n", kind.c_str(), double(k.falseSightings) / frames.size(), k.confused,
                    k.textRight, k.textWrong, k.textNone);
    }
    if (!labelledReads.empty()) {
        std::printf("\nText reader on the labelled placard boxes (no detector): right / wrong / not read\n\n"
                    "| distance | right | wrong | not read |\n|---|---|---|---|\n");
        for (const auto& [bin, c] : labelledReads) std::printf("| %.1f m | %d | %d | %d |\n", bin / 10.0, c[0], c[1], c[2]);
    } else if (!readerLoaded) {
        std::printf("\ntext reader not loaded: %s\n", readerError.c_str());
    }
    const double perFrame = 1000.0 / (double(frames.size()) * repeat);
    std::printf("\n%zu frames (%ld sign-free: %ld false sightings of the new kinds on them), each run %d x.\n", frames.size(),
                signFree, signFreeFalse, repeat);
    std::printf("time per frame: exit-only %.2f ms, all kinds %.2f ms: ratio %.2f\n", exitSeconds * perFrame,
                allSeconds * perFrame, allSeconds / exitSeconds);
    // What the extra kinds add to one frame (a schedule spreads them: the searched frames pay more than the mean).
    std::sort(extraMs.begin(), extraMs.end());
    auto quantile = [&](double q) { return extraMs[std::min(extraMs.size() - 1, size_t(q * double(extraMs.size())))]; };
    if (!extraMs.empty()) {
        std::printf("added per frame: median %.2f ms, 95th percentile %.2f ms, max %.2f ms\n", quantile(0.5),
                    quantile(0.95), extraMs.back());
    }
    return 0;
}
