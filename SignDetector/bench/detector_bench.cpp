// wf_detector_bench: per-frame cost of the whole detector pipeline through the C ABI (validation, unrolling,
// detection, slice measurement), one OpenCV thread (cv::setNumThreads(1)).
//
//   wf_detector_bench [--benchmark_filter=...]        (Google Benchmark flags)
//
// Frames: 8 synthetic portrait frames (bench/synthetic_scene: an Exit sign at 2..9 m, roll -1.58 rad as in a
// real recording), or 16 frames of a rendered test set when WF_BENCH_TESTSET=DIR is set: the first 16, or every
// k-th with WF_BENCH_STRIDE=k (20: two frames per distance 2..9 m of the fixed test set).
// Benchmarks (each iteration = one frame, frames cycled):
//   cascade_ours/VGA, cascade_ours/HR       SignDetector/models/exit_sign_cascade.xml (skipped if absent), with
//                                           the defaults: colour gate (search around red/green regions only, the
//                                           threshold raised in crowded frames), rows at elevation >= -0.15 rad
//                                           only, placement prior (per scale, only the rows a sign can hang in),
//                                           16-pixel gate margins, component-width windows in large components' tiles
//   cascade_ours_v4_search/VGA              the same with the earlier gate regions (24-pixel margins, every window
//                                           size in tiles; named options, CascadeSearch::WideGateRegions)
//   cascade_ours_v3_search/VGA              ... and without the placement prior and the crowded-frame gate
//                                           (CascadeSearch::WideGateRegionsNoPrior)
//   cascade_ours_full_search/VGA, .../HR    the same cascade searching the whole frame (no gate, no row limit,
//                                           no placement prior)
//   cascade_ours_gray/VGA                   GRAY8 frames: no colour, so the gate falls back to the full search (what
//                                           the phone sent before it sent colour)
//   cascade_ours_native/HR                  the HR frames searched at their own size (cascade_search_max_long_side_px
//                                           -1; the HR rows otherwise search the frame shrunk to VGA and measure on it)
//   cascade_phone_nv12/VGA, .../HR          the frames as ARKit delivers them: NV12 (Y plane + interleaved CbCr),
//                                           full-range BT.601, handed over without conversion
//   cascade_phone_bgra/VGA, .../HR          the frames as 32BGRA pixel buffers
//   cascade_phone_bgra_all_kinds/VGA        the same plus every other kind of the office's catalogue with a model
//                                           (models/<kind>_cascade.xml: pictograms, placards; their legends read),
//                                           one such kind a frame in rotation (the default)
//   ..._no_plate_gate/...                   the same with those kinds' plate gate off (their whole placement bands)
//   unet_coarse_zoom_all_kinds/HR           the U-Net with the office's catalogue and the cascades of the kinds it
//                                           has no class for beside it (none when its classes.json lists them all)
//   unet_coarse_zoom_all_kinds_every_frame_phone_bgra/HR   the same, every such kind on every frame
//   unet_coarse_zoom_exit_only_model/HR     $WF_BENCH_UNET_EXIT_ONLY (an Exit-only U-Net, classes.json beside it;
//                                           e.g. the model before the wall kinds, `git show 0930cf0:SignDetector/
//                                           models/sign_unet.onnx`) with the same catalogue: the baseline of the
//                                           extra classes' cost
//   cascade_reference/VGA, .../HR           the reference app's cascade, same frames, same settings
//   unet_coarse_zoom/HR                     $WF_BENCH_UNET, else SignDetector/models/sign_unet.onnx, else the
//                                           tiny test model (then it times only the pipeline around the net)
//   unet_coarse_zoom_whole_frame/HR         the same with the coarse pass over the whole frame (no elevation cut)
//   unet_coarse_zoom_opencv_deconvolution/HR  the same with OpenCV's own Deconvolution layer for the upsampling
//                                           (unet_transposed_convolution -1; the default is the sub-pixel layer)
//   detectMultiScale_only_reference/VGA     the cascade call alone on pre-unrolled frames (pipeline overhead =
//                                           cascade_reference/VGA minus this)
//   unet_forward/224                        one 224 x 224 forward pass + softmax of that model
//   unroll/VGA_roll-1.58, unroll/HR_roll-1.58, unroll/HR_portrait_exact   unrolling alone
// After the run, ratios of CPU times ours / reference are printed.
#include "bench_support.hpp"
#include "synthetic_scene.hpp"
#include "cascade_detector.hpp"
#include "unet_detector.hpp"
#include "unroll.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>

using namespace wf::sign;
using namespace wf::sign::bench;

namespace {

/// Source frames (BGR) with labels, at their stored resolution.
struct Source {
    cv::Mat bgr;
    LabelledFrame labels;
};

std::vector<Source> loadSources(std::string* description) {
    std::vector<Source> sources;
    if (const char* dir = std::getenv("WF_BENCH_TESTSET")) {
        std::vector<LabelledFrame> frames;
        std::string error;
        if (!readLabels(dir, &frames, &error)) {
            std::cerr << "wf_detector_bench: " << error << "\n";
            std::exit(1);
        }
        // Every k-th frame (WF_BENCH_STRIDE, default 1): a rendered test set stores 40 frames per distance
        // 2, 3, ..., 9 m and then the sign-free ones, so stride 20 gives 2 frames per distance.
        const char* strideText = std::getenv("WF_BENCH_STRIDE");
        const size_t stride = strideText ? std::max(1, std::atoi(strideText)) : 1;
        for (size_t i = 0; i < frames.size() && sources.size() < 16; i += stride) {
            Source s{cv::imread(frames[i].imagePath, cv::IMREAD_COLOR), frames[i]};
            if (!s.bgr.empty()) sources.push_back(std::move(s));
        }
        *description = std::to_string(sources.size()) + " frames (every " + std::to_string(stride) + ") of " + dir;
        return sources;
    }
    for (int i = 0; i < 8; ++i) {
        synthetic::Camera cam;
        cam.rollRad = -1.58;
        cam.pitchRad = 0.1;
        cv::Mat bgr = synthetic::renderBackground(cam, 100 + i);
        synthetic::SignPlacement sign;
        sign.rangeMeters = 2 + i;
        sign.bearingRad = 0.2 * ((i % 3) - 1);
        sign.style = i % 2 ? synthetic::SignStyle::WhiteLettersOnRed : synthetic::SignStyle::RedLettersOnWhite;
        const synthetic::RenderedSign truth = synthetic::drawSign(bgr, cam, sign);
        LabelledFrame l;
        l.fx = cam.fx;
        l.fy = cam.fy;
        l.cx = cam.cx;
        l.cy = cam.cy;
        l.width = cam.size.width;
        l.height = cam.size.height;
        l.pitchRad = cam.pitchRad;
        l.rollRad = cam.rollRad;
        sources.push_back({bgr, l});
        (void)truth;
    }
    *description = "8 synthetic 1920x1440 portrait frames (roll -1.58 rad), signs at 2..9 m";
    return sources;
}

std::vector<std::unique_ptr<PreparedFrame>> prepareAll(const std::vector<Source>& sources, cv::Size size) {
    std::vector<std::unique_ptr<PreparedFrame>> out;
    for (const auto& s : sources) out.push_back(prepareFrame(s.bgr, s.labels, size));
    return out;
}

/// The frames in a phone's pixel format (bench_support convertPixelFormat): GRAY8 (luma only, as the app sent
/// before: no colour for the gate), BGRA8, or NV12 (ARKit's capturedImage as it comes, Y + CbCr planes).
std::vector<std::unique_ptr<PreparedFrame>> prepareAllAs(const std::vector<Source>& sources, cv::Size size,
                                                         wf_pixel_format format) {
    std::vector<std::unique_ptr<PreparedFrame>> out = prepareAll(sources, size);
    for (auto& p : out) convertPixelFormat(p.get(), format);
    return out;
}

void runPipeline(benchmark::State& state, DetectorHandle* detector, const std::vector<std::unique_ptr<PreparedFrame>>* frames) {
    std::vector<wf_detector_observation> observations;
    size_t i = 0, found = 0;
    for (auto _ : state) {
        // Each pass over the frames starts one frame later, so a detector with a schedule across frames (wall kinds
        // in rotation, one frame in two) meets every frame at every phase of it over the passes; in the same order
        // every pass, a frame would always get the same kinds or never be searched.
        const size_t n = frames->size();
        const int status = detect(*detector, *(*frames)[(i + i / n) % n], &observations);
        if (status < 0) {
            state.SkipWithError(wf_detector_last_error(detector->handle));
            return;
        }
        found += observations.size();
        benchmark::DoNotOptimize(observations.data());
        ++i;
    }
    state.counters["signs_per_frame"] = benchmark::Counter(double(found) / double(std::max<size_t>(1, i)));
}

/// detectMultiScale alone on pre-unrolled gray frames: the pipeline's overhead is the difference.
void runCascadeOnly(benchmark::State& state, const std::string* path, const std::vector<std::unique_ptr<PreparedFrame>>* frames) {
    CascadeDetector cascade;
    std::string error;
    if (!cascade.load({*path}, {"exit"}, &error)) {
        state.SkipWithError(error.c_str());
        return;
    }
    std::vector<cv::Mat> unrolled;
    for (const auto& f : *frames) {
        cv::Mat gray;
        cv::cvtColor(f->rgb, gray, cv::COLOR_RGB2GRAY);
        const Intrinsics k{f->labels.fx, f->labels.fy, f->labels.cx, f->labels.cy};
        unrolled.push_back(Unrolling::forRoll(f->labels.rollRad, k, gray.size()).apply(gray).clone());
    }
    CascadeParams params;  // the reference app's settings, as in cascade_reference/*
    params.minWindow = cv::Size(36, 24);
    params.maxWindowFactor = 5.0;
    size_t i = 0;
    for (auto _ : state) {
        auto d = cascade.detect(unrolled[i++ % unrolled.size()], params);
        benchmark::DoNotOptimize(d.data());
    }
}

void runForward(benchmark::State& state, const std::string* modelPath) {
    UnetDetector net;
    std::string error;
    if (!net.load(*modelPath, {}, 224, &error)) {
        state.SkipWithError(error.c_str());
        return;
    }
    cv::Mat rgb(224, 224, CV_8UC3);
    cv::RNG(5).fill(rgb, cv::RNG::UNIFORM, 0, 256);
    for (auto _ : state) {
        std::vector<cv::Mat> p = net.probabilities(rgb);
        benchmark::DoNotOptimize(p.data());
    }
}

void runUnroll(benchmark::State& state, const std::vector<std::unique_ptr<PreparedFrame>>* frames, double roll) {
    const PreparedFrame& f = *(*frames)[0];
    cv::Mat gray;
    cv::cvtColor(f.rgb, gray, cv::COLOR_RGB2GRAY);
    const Intrinsics k{f.labels.fx, f.labels.fy, f.labels.cx, f.labels.cy};
    for (auto _ : state) {
        const Unrolling u = Unrolling::forRoll(roll, k, gray.size());
        cv::Mat out = u.apply(gray);
        benchmark::DoNotOptimize(out.data);
    }
}

/// Console output plus, at the end, time ratios of our detectors to the reference cascade.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const auto& r : runs) {
            if (!r.error_occurred && r.run_type == Run::RT_Iteration) times_[r.benchmark_name()] = r.GetAdjustedCPUTime();  // CPU: robust on a shared machine
        }
        ConsoleReporter::ReportRuns(runs);
    }
    void Finalize() override {
        ConsoleReporter::Finalize();
        auto ratio = [&](const std::string& a, const std::string& b) {
            const auto ia = find(a), ib = find(b);
            if (ia < 0 || ib < 0) return;
            std::printf("ratio %-28s / %-28s = %.2f\n", a.c_str(), b.c_str(), ia / ib);
        };
        std::printf("\n");
        ratio("cascade_ours/VGA", "cascade_reference/VGA");
        ratio("cascade_ours/HR", "cascade_reference/HR");
        ratio("cascade_ours_full_search/VGA", "cascade_reference/VGA");
        ratio("cascade_ours_full_search/HR", "cascade_reference/HR");
        ratio("cascade_phone_nv12/VGA", "cascade_ours_gray/VGA");
        ratio("cascade_phone_bgra/VGA", "cascade_ours_gray/VGA");
        ratio("cascade_phone_nv12/VGA", "cascade_ours/VGA");
        ratio("cascade_ours/VGA", "cascade_ours_v4_search/VGA");
        ratio("cascade_ours/VGA", "cascade_ours_v3_search/VGA");
        ratio("cascade_ours/VGA", "cascade_ours_full_search/VGA");
        ratio("cascade_ours/HR", "cascade_ours_full_search/HR");
        // A full-size frame searched at VGA and measured at full size, against the same frame searched at full size
        // and against the VGA frame the phone sends (search_frame.hpp).
        ratio("cascade_ours/HR", "cascade_ours_native/HR");
        ratio("cascade_phone_bgra/HR", "cascade_phone_bgra/VGA");
        ratio("cascade_phone_nv12/HR", "cascade_phone_nv12/VGA");
        ratio("unet_coarse_zoom/HR", "cascade_reference/VGA");
        ratio("unet_coarse_zoom/HR", "cascade_ours/VGA");
        ratio("unet_coarse_zoom/HR", "unet_coarse_zoom_whole_frame/HR");
        ratio("unet_coarse_zoom/HR", "unet_coarse_zoom_opencv_deconvolution/HR");
        ratio("cascade_phone_bgra/VGA", "cascade_phone_bgra_no_edge_refinement/VGA");
        ratio("cascade_phone_nv12/VGA", "cascade_phone_nv12_no_edge_refinement/VGA");
        ratio("unet_coarse_zoom/HR", "unet_coarse_zoom_no_edge_refinement/HR");
        // Issue 16: "extra sign classes add <= 20 %" (pictogram and placard cascades beside the Exit detector).
        ratio("cascade_phone_bgra_all_kinds/VGA", "cascade_phone_bgra/VGA");
        ratio("unet_coarse_zoom_all_kinds/HR", "unet_coarse_zoom/HR");
        ratio("unet_coarse_zoom_all_kinds_phone_bgra/HR", "unet_coarse_zoom_phone_bgra/HR");
        ratio("unet_coarse_zoom_all_kinds_phone_bgra_no_plate_gate/HR", "unet_coarse_zoom_phone_bgra/HR");
        ratio("unet_coarse_zoom_all_kinds_every_frame_phone_bgra/HR", "unet_coarse_zoom_phone_bgra/HR");
        ratio("unet_coarse_zoom_all_kinds_one_per_frame_phone_bgra/HR", "unet_coarse_zoom_phone_bgra/HR");
        ratio("cascade_phone_bgra_all_kinds_no_plate_gate/VGA", "cascade_phone_bgra/VGA");
        ratio("cascade_phone_bgra_all_kinds_one_per_frame/VGA", "cascade_phone_bgra/VGA");
        ratio("unet_coarse_zoom_phone_bgra/HR", "cascade_reference/VGA");
        ratio("unet_coarse_zoom_phone_bgra/HR", "unet_coarse_zoom/HR");
        ratio("unet_coarse_zoom_all_kinds/HR", "unet_coarse_zoom_exit_only_model/HR");
    }

private:
    double find(const std::string& prefix) const {
        for (const auto& [name, t] : times_) {
            if (name.rfind(prefix, 0) == 0) return t;
        }
        return -1;
    }
    std::map<std::string, double> times_;
};

}  // namespace

int main(int argc, char** argv) {
    cv::setNumThreads(1);
    benchmark::Initialize(&argc, argv);
    std::string description;
    static const std::vector<Source> sources = loadSources(&description);
    static const auto vga = prepareAll(sources, {640, 480});
    static const auto hr = prepareAll(sources, {1920, 1440});
    static const auto vgaGray = prepareAllAs(sources, {640, 480}, WF_PIXEL_GRAY8);
    static const auto vgaNv12 = prepareAllAs(sources, {640, 480}, WF_PIXEL_NV12);
    static const auto vgaBgra = prepareAllAs(sources, {640, 480}, WF_PIXEL_BGRA8);
    static const auto hrNv12 = prepareAllAs(sources, {1920, 1440}, WF_PIXEL_NV12);
    static const auto hrBgra = prepareAllAs(sources, {1920, 1440}, WF_PIXEL_BGRA8);

    const std::string ours = productModelsDir() + "/exit_sign_cascade.xml";
    // Every kind of the bundled office's catalogue with a model: the Exit detector plus <kind>_cascade.xml.
    static std::vector<CatalogueEntry> catalogue;
    static std::vector<std::string> kindPaths, kindNames;
    std::string catalogueError;
    if (readMapCatalogue(officeMapPath(), &catalogue, &catalogueError)) {
        for (const auto& e : catalogue) {
            const std::string path = productModelsDir() + "/" + e.kind + "_cascade.xml";
            if (e.kind != "exit" && fileExists(path)) {
                kindPaths.push_back(path);
                kindNames.push_back(e.kind);
            }
        }
    } else {
        std::fprintf(stderr, "no extra kinds: %s\n", catalogueError.c_str());
    }
    static std::unique_ptr<DetectorHandle> oursCascade, oursRough, oursNative, oursV4, oursV3, oursFull, refCascade, unet, unetRough,
        unetWholeFrame, unetOpencvDeconvolution;
    if (fileExists(ours)) {
        oursCascade = makeCascade(ours);
        // The same search without face-edge refinement (the box's own height in every slice).
        oursRough = makeCascade(ours, 0, 0, 0, 0, false, CascadeSearch::Defaults, FaceEdgeOptions{-1, 0});
        oursNative = makeCascade(ours, 0, 0, 0, 0, false, CascadeSearch::Defaults, FaceEdgeOptions{}, -1);
        oursV4 = makeCascade(ours, 0, 0, 0, 0, /*fullSearch=*/false, CascadeSearch::WideGateRegions);
        oursV3 = makeCascade(ours, 0, 0, 0, 0, /*fullSearch=*/false, CascadeSearch::WideGateRegionsNoPrior);
        oursFull = makeCascade(ours, 0, 0, 0, std::nan(""), /*fullSearch=*/true, CascadeSearch::WideGateRegionsNoPrior);
    }
    // The reference app searched all rows, with no placement prior.
    refCascade = makeCascade(referenceCascadePath(), 36, 24, 5.0, std::nan(""), false,
                             CascadeSearch::WideGateRegionsNoPrior);
    const char* unetOverride = std::getenv("WF_BENCH_UNET");
    const std::string unetModel = unetOverride ? std::string(unetOverride)
                                  : fileExists(productModelsDir() + "/sign_unet.onnx") ? productModelsDir() + "/sign_unet.onnx"
                                                                                       : tinyUnetPath();
    unet = makeUnet(unetModel);
    unetRough = makeUnet(unetModel, 0, FaceEdgeOptions{-1, 0});
    unetWholeFrame = makeUnet(unetModel, -2.0);
    unetOpencvDeconvolution = makeUnet(unetModel, 0, FaceEdgeOptions{}, nullptr, -1);

    std::printf("frames: %s\nour cascade: %s\nreference cascade: %s\nU-Net: %s\nOpenCV threads: %d\n\n",
                description.c_str(), oursCascade && *oursCascade ? ours.c_str() : "(absent: SignDetector/models/exit_sign_cascade.xml)",
                refCascade && *refCascade ? referenceCascadePath().c_str() : refCascade->error.c_str(), unetModel.c_str(),
                cv::getNumThreads());

    // Every pipeline benchmark runs each frame the same number of times (4 passes over the set), so its mean is
    // the mean over the frames; a time-based iteration count would stop part-way through a set whose frames
    // differ 50-fold in cost (sign-free clutter vs a near sign).
    auto pipeline = [](const char* name, DetectorHandle* handle, const std::vector<std::unique_ptr<PreparedFrame>>* frames) {
        benchmark::RegisterBenchmark(name, runPipeline, handle, frames)
            ->Unit(benchmark::kMillisecond)
            ->Iterations(static_cast<benchmark::IterationCount>(4 * frames->size()));
    };
    if (oursCascade && *oursCascade) {
        pipeline("cascade_ours/VGA", oursCascade.get(), &vga);
        pipeline("cascade_ours/HR", oursCascade.get(), &hr);
        pipeline("cascade_ours_native/HR", oursNative.get(), &hr);
        pipeline("cascade_ours_v4_search/VGA", oursV4.get(), &vga);
        pipeline("cascade_ours_v3_search/VGA", oursV3.get(), &vga);
        pipeline("cascade_ours_full_search/VGA", oursFull.get(), &vga);
        pipeline("cascade_ours_full_search/HR", oursFull.get(), &hr);
        pipeline("cascade_ours_gray/VGA", oursCascade.get(), &vgaGray);
        pipeline("cascade_phone_nv12/VGA", oursCascade.get(), &vgaNv12);
        pipeline("cascade_phone_bgra/VGA", oursCascade.get(), &vgaBgra);
        pipeline("cascade_phone_bgra_no_edge_refinement/VGA", oursRough.get(), &vgaBgra);
        pipeline("cascade_phone_nv12_no_edge_refinement/VGA", oursRough.get(), &vgaNv12);
        pipeline("cascade_phone_nv12/HR", oursCascade.get(), &hrNv12);
        pipeline("cascade_phone_bgra/HR", oursCascade.get(), &hrBgra);
        if (!kindPaths.empty()) {
            std::vector<std::string> paths{ours}, names{"exit"};
            paths.insert(paths.end(), kindPaths.begin(), kindPaths.end());
            names.insert(names.end(), kindNames.begin(), kindNames.end());
            static auto allKinds = makeWithCatalogue(paths, names, catalogue);
            static auto allKindsUngated = makeWithCatalogue(paths, names, catalogue, "", 0, -1);
            static auto allKindsOnePerFrame = makeWithCatalogue(paths, names, catalogue, "", 1);
            if (*allKinds && *allKindsUngated && *allKindsOnePerFrame) {
                pipeline("cascade_phone_bgra_all_kinds/VGA", allKinds.get(), &vgaBgra);
                pipeline("cascade_phone_bgra_all_kinds_no_plate_gate/VGA", allKindsUngated.get(), &vgaBgra);
                pipeline("cascade_phone_bgra_all_kinds_one_per_frame/VGA", allKindsOnePerFrame.get(), &vgaBgra);
            } else {
                std::fprintf(stderr, "all-kinds cascade not benchmarked: %s%s\n", allKinds->error.c_str(),
                             allKindsUngated->error.c_str());
            }
        }
    }
    if (refCascade && *refCascade) {
        pipeline("cascade_reference/VGA", refCascade.get(), &vga);
        pipeline("cascade_reference/HR", refCascade.get(), &hr);
        static const std::string refPath = referenceCascadePath();
        benchmark::RegisterBenchmark("detectMultiScale_only_reference/VGA", runCascadeOnly, &refPath, &vga)
            ->Unit(benchmark::kMillisecond);
    }
    static const std::string unetModelPath = unetModel;
    if (unet && *unet) {
        pipeline("unet_coarse_zoom/HR", unet.get(), &hr);
        // What the phone sends the U-Net: a BGRA frame at capture size (App/iOS/Sensors/PixelBufferTools.swift).
        pipeline("unet_coarse_zoom_phone_bgra/HR", unet.get(), &hrBgra);
        pipeline("unet_coarse_zoom_no_edge_refinement/HR", unetRough.get(), &hr);
        pipeline("unet_coarse_zoom_whole_frame/HR", unetWholeFrame.get(), &hr);
        pipeline("unet_coarse_zoom_opencv_deconvolution/HR", unetOpencvDeconvolution.get(), &hr);
        benchmark::RegisterBenchmark("unet_forward/224", runForward, &unetModelPath)->Unit(benchmark::kMillisecond);
        if (!catalogue.empty()) {
            // Cascades beside the U-Net only for the kinds it has no class for.
            std::vector<std::string> classes, besidePaths, besideNames;
            std::string classError;
            readUnetClasses(unetModel, &classes, &classError);
            for (size_t i = 0; i < kindNames.size(); ++i) {
                if (std::find(classes.begin(), classes.end(), kindNames[i]) != classes.end()) continue;
                besidePaths.push_back(kindPaths[i]);
                besideNames.push_back(kindNames[i]);
            }
            static auto unetKinds = makeWithCatalogue(besidePaths, besideNames, catalogue, unetModel);
            static auto unetKindsUngated = makeWithCatalogue(besidePaths, besideNames, catalogue, unetModel, 0, -1);
            static auto unetKindsEveryFrame = makeWithCatalogue(besidePaths, besideNames, catalogue, unetModel, -1);
            // The schedule before the twenty-first stop: one kind on every frame (the same rate per kind).
            static auto unetKindsOnePerFrame = makeWithCatalogue(besidePaths, besideNames, catalogue, unetModel, 1);
            if (*unetKinds && *unetKindsUngated && *unetKindsEveryFrame && *unetKindsOnePerFrame) {
                pipeline("unet_coarse_zoom_all_kinds/HR", unetKinds.get(), &hr);
                pipeline("unet_coarse_zoom_all_kinds_phone_bgra/HR", unetKinds.get(), &hrBgra);
                pipeline("unet_coarse_zoom_all_kinds_phone_bgra_no_plate_gate/HR", unetKindsUngated.get(), &hrBgra);
                pipeline("unet_coarse_zoom_all_kinds_every_frame_phone_bgra/HR", unetKindsEveryFrame.get(), &hrBgra);
                pipeline("unet_coarse_zoom_all_kinds_one_per_frame_phone_bgra/HR", unetKindsOnePerFrame.get(), &hrBgra);
            } else {
                std::fprintf(stderr, "all-kinds U-Net not benchmarked: %s%s%s%s\n", unetKinds->error.c_str(),
                             unetKindsUngated->error.c_str(), unetKindsEveryFrame->error.c_str(),
                             unetKindsOnePerFrame->error.c_str());
            }
            if (const char* exitOnly = std::getenv("WF_BENCH_UNET_EXIT_ONLY")) {
                static auto unetExitOnly = makeUnet(exitOnly, 0, FaceEdgeOptions{}, &catalogue);
                if (*unetExitOnly) pipeline("unet_coarse_zoom_exit_only_model/HR", unetExitOnly.get(), &hr);
                else std::fprintf(stderr, "Exit-only U-Net not benchmarked: %s\n", unetExitOnly->error.c_str());
            }
        }
    } else {
        std::fprintf(stderr, "U-Net not benchmarked: %s\n", unet->error.c_str());
    }
    benchmark::RegisterBenchmark("unroll/VGA_roll-1.58", runUnroll, &vga, -1.58)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("unroll/HR_roll-1.58", runUnroll, &hr, -1.58)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("unroll/HR_portrait_exact", runUnroll, &hr, -1.5707963267948966)->Unit(benchmark::kMillisecond);

    RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}
