import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore

/// The replay of the committed sample walk through the whole pipeline.
final class ReplayTests: XCTestCase {
    /// Before localization: only the exploratory guidance (issue: never a bare "Start walking").
    static func isUnsureGuidance(_ text: String) -> Bool {
        text.hasPrefix("Not sure where you are yet.") || text == "I'm not sure where you are yet; keep walking slowly."
    }

    func testSampleReplayGivesOnlyExploratoryGuidanceUntilLocalizedAndTracesEveryFrame() throws {
        let bundle = try TestData.sample()
        let building = try TestData.office()
        let options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: PipelineOptions()))
        let result = try Replay.run(bundle: bundle, building: building, options: options)
        XCTAssertEqual(result.trace.count, bundle.frames.count)
        XCTAssertTrue(result.announcements.first.map { Self.isUnsureGuidance($0.text) } ?? false,
                      "first: \(String(describing: result.announcements.first?.text))")
        XCTAssertTrue(result.trace.allSatisfy { $0.x.isFinite && $0.y.isFinite && $0.headingRad.isFinite && $0.confidence.isFinite })
        // No route guidance before the localizer is sure, and never a bare "Start walking".
        let firstLocalized = result.trace.first(where: \.localized)?.t ?? .infinity
        XCTAssertLessThan(firstLocalized, .infinity, "the sample walk localizes")
        for a in result.announcements where a.t < firstLocalized {
            XCTAssertTrue(Self.isUnsureGuidance(a.text), "spoke '\(a.text)' at \(a.t) s before being localized")
        }
        XCTAssertFalse(result.announcements.contains { $0.text == "Start walking." })
        XCTAssertTrue(result.trace.contains { $0.sightings > 0 }, "recorded observations reach the localizer")
    }

    func testReplayIsDeterministicForASeed() throws {
        let bundle = try TestData.sample()
        let building = try TestData.office()
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: PipelineOptions()))
        options.pipeline.localizer.particleCount = 3000
        let a = try Replay.run(bundle: bundle, building: building, options: options)
        let b = try Replay.run(bundle: bundle, building: building, options: options)
        XCTAssertEqual(a.trace, b.trace)
    }

    func testNonFinitePosesDegradeGracefully() throws {
        var bundle = try TestData.sample()
        let building = try TestData.office()
        for i in stride(from: 20, to: 40, by: 1) { bundle.frames[i].cameraToWorld[12] = .nan }
        bundle.frames[50].cameraToWorld = Array(repeating: .infinity, count: 16)
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: PipelineOptions()))
        options.pipeline.localizer.particleCount = 3000
        let result = try Replay.run(bundle: bundle, building: building, options: options)
        XCTAssertEqual(result.trace.count, bundle.frames.count)
        XCTAssertEqual(result.warnings.filter { $0.contains("not finite") }.count, 21)
        XCTAssertTrue(result.trace.allSatisfy { $0.x.isFinite && $0.y.isFinite })
    }

    func testUnknownPlacesAreClearErrors() throws {
        let building = try TestData.office()
        var o = PipelineOptions()
        o.destinationId = "no-such-room"
        XCTAssertThrowsError(try WayfinderPipeline(building: building, options: o))
        o = PipelineOptions()
        o.startPointOfInterestId = "nowhere"
        XCTAssertThrowsError(try WayfinderPipeline(building: building, options: o)) { error in
            XCTAssertTrue("\(error)".contains("nowhere"))
        }
        o = PipelineOptions()
        o.floorId = "99"
        XCTAssertThrowsError(try WayfinderPipeline(building: building, options: o)) { error in
            XCTAssertTrue("\(error)".contains("99"))
        }
    }

    // MARK: Issue 14: no silent wrong answer, no slow path

    /// Replay options for quick tests: few particles, fixed seed.
    private func quickOptions(_ bundle: SessionBundle, source: SightingSource = .automatic) -> Replay.Options {
        var o = PipelineOptions()
        o.sightingSource = source
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: o))
        options.pipeline.localizer.particleCount = 3000
        options.snapshotParticleCount = 0
        return options
    }

    /// Writes `bundle` (frames, observations, truth) to a fresh directory and reads it back, so observation
    /// line numbers are real.
    private func writtenCopy(_ bundle: SessionBundle, info: SessionInfo? = nil) throws -> SessionBundle {
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-replay-\(UUID().uuidString)")
        addTeardownBlock { try? FileManager.default.removeItem(at: dir) }
        let w = try BundleWriter(directory: dir, info: info ?? bundle.info)
        for f in bundle.frames { try w.append(f) }
        for o in bundle.observations { try w.append(o) }
        for t in bundle.truth { try w.append(t) }
        for p in bundle.planes { try w.append(p) }
        try w.close()
        return try SessionBundle.read(from: dir)
    }

    func testBundleOfAnotherBuildingIsWarnedFirst() throws {
        var bundle = try TestData.sample()
        bundle.frames = Array(bundle.frames.prefix(30))
        bundle.observations = bundle.observations.filter { $0.t <= bundle.frames[29].t }
        let building = try TestData.office()
        let same = try Replay.run(bundle: bundle, building: building, options: quickOptions(bundle))
        XCTAssertFalse(same.warnings.contains { $0.contains("mapId") }, "\(same.warnings)")
        bundle.info.mapId = "skeri-4"
        let other = try Replay.run(bundle: bundle, building: building, options: quickOptions(bundle))
        let w = try XCTUnwrap(other.warnings.first)
        XCTAssertTrue(w.contains("session.json") && w.contains("'skeri-4'") && w.contains("'\(building.id)'"), w)
    }

    func testObservationsOfSignKindsTheMapLacksAreIgnoredWithAWarningNamingFileAndLine() throws {
        let sample = try TestData.sample()
        let building = try TestData.office()
        var damaged = sample
        // A "vending-machine" sighting next to every fifth sighting: the office map has no such kind.
        var observations: [ObservationRecord] = []
        for (i, o) in sample.observations.enumerated() {
            observations.append(o)
            if i % 5 == 2 { observations.append(ObservationRecord(t: o.t, kind: "vending-machine", rangeMeters: 2, bearingRad: 0.1, score: 0.9)) }
        }
        damaged.observations = observations
        let bundle = try writtenCopy(damaged)
        let added = observations.count - sample.observations.count
        let firstLine = try XCTUnwrap(observations.firstIndex { $0.kind == "vending-machine" }) + 1
        let result = try Replay.run(bundle: bundle, building: building, options: quickOptions(bundle))
        let w = try XCTUnwrap(result.warnings.first { $0.contains("'vending-machine'") }, "\(result.warnings)")
        XCTAssertTrue(w.contains("observations.jsonl line \(firstLine):"), w)
        XCTAssertTrue(w.contains("\(added) observations of this kind ignored"), w)
        // Ignored means exactly that: the replay is the one without them.
        let clean = try Replay.run(bundle: sample, building: building, options: quickOptions(sample))
        XCTAssertEqual(result.trace, clean.trace)
    }

    func testObservationsPerFrameAreCappedKeepingTheHighestScores() throws {
        var bundle = try TestData.sample()
        bundle.frames = Array(bundle.frames.prefix(60))
        let t = bundle.frames[40].t
        var flood: [ObservationRecord] = []
        for k in 0..<5000 {
            flood.append(ObservationRecord(t: t, kind: "exit", rangeMeters: 3, bearingRad: 0, score: Double(k % 1000) / 1000))
        }
        bundle.observations = bundle.observations.filter { $0.t < t } + flood
        bundle.observationLineNumbers = []
        var warnings: [String] = []
        let byFrame = Replay.assignObservations(bundle: bundle, building: try TestData.office(), warnings: &warnings)
        XCTAssertEqual(byFrame[40].count, Replay.maximumObservationsPerFrame)
        XCTAssertEqual(Replay.maximumObservationsPerFrame, 64)
        // Scores 0.000...0.999, five of each: the 64 highest are five each of 0.999...0.988 and four of 0.987.
        XCTAssertEqual(byFrame[40].map(\.score).min(), 0.987)
        XCTAssertEqual(byFrame[40].filter { $0.score == 0.987 }.count, 4)
        let w = try XCTUnwrap(warnings.first { $0.contains("more than 64") }, "\(warnings)")
        XCTAssertTrue(w.contains("\(5000 - 64) observations dropped"), w)
        // The whole replay stays fast and uses at most the cap (it took over a minute with 200,000).
        bundle.observations = bundle.observations.filter { $0.t < t } + (0..<50_000).map { k in
            ObservationRecord(t: t, kind: "exit", rangeMeters: 3, bearingRad: 0, score: Double(k % 997) / 997)
        }
        let result = try Replay.run(bundle: bundle, building: try TestData.office(), options: quickOptions(bundle))
        XCTAssertEqual(result.trace[40].sightings, 64)
    }

    /// Issue 14: one frame naming a missing image switched `--detector auto` to image mode, dropping every
    /// recorded sighting: the walk never localized. Now auto uses images only when some are present.
    func testAutoDetectorWithOnlyMissingImagesReplaysTheRecordedObservations() throws {
        var bundle = try TestData.sample()
        bundle.frames[10].image = "missing.ppm"
        let building = try TestData.office()
        let auto = try Replay.run(bundle: bundle, building: building, options: quickOptions(bundle))
        let recorded = try Replay.run(bundle: bundle, building: building, options: quickOptions(bundle, source: .recorded))
        XCTAssertEqual(auto.trace, recorded.trace)
        XCTAssertGreaterThan(auto.trace.map(\.sightings).reduce(0, +), 0)
        XCTAssertTrue(auto.warnings.contains { $0.contains("--detector auto") && $0.contains("none is present") },
                      "\(auto.warnings)")
    }

    /// With some images present, auto runs the detector on them, and a frame whose image is missing uses
    /// its recorded observations instead of nothing.
    func testAutoDetectorFallsBackToRecordedObservationsForEachMissingImage() throws {
        let models = TestData.packageRoot.appendingPathComponent("SignDetector/models/sign_unet.onnx")
        guard FileManager.default.fileExists(atPath: models.path) else { throw XCTSkip("U-Net model not present") }
        var sample = try TestData.sample()
        sample.frames = Array(sample.frames.prefix(120))
        sample.observations = sample.observations.filter { $0.t <= sample.frames[119].t }
        var ignored: [String] = []
        let byFrame = Replay.assignObservations(bundle: sample, building: try TestData.office(), warnings: &ignored)
        let withObservations = sample.frames.indices.filter { !byFrame[$0].isEmpty }
        XCTAssertGreaterThanOrEqual(withObservations.count, 4, "the sample has observed frames early on")
        let present = Array(withObservations.prefix(2)), missing = Array(withObservations.dropFirst(2))
        for i in present + missing { sample.frames[i].image = "frame-\(i).ppm" }
        // The present images are 640 x 480: their frames get intrinsics of that resolution.
        for i in present { sample.frames[i].intrinsics = CameraIntrinsics(fx: 534, fy: 534, cx: 320, cy: 240, width: 640, height: 480) }
        let bundle = try writtenCopy(sample)
        // A plain grey 640 x 480 image: the detector finds no sign in it.
        var ppm = Data("P6\n640 480\n255\n".utf8)
        ppm.append(Data(repeating: 128, count: 640 * 480 * 3))
        try FileManager.default.createDirectory(at: bundle.imagesDirectory, withIntermediateDirectories: true)
        for i in present { try ppm.write(to: bundle.imagesDirectory.appendingPathComponent("frame-\(i).ppm")) }

        let result = try Replay.run(bundle: bundle, building: try TestData.office(), options: quickOptions(bundle))
        for i in present { XCTAssertEqual(result.trace[i].sightings, 0, "frame \(i): the detector, not the recording") }
        XCTAssertFalse(result.warnings.contains { $0.contains(".ppm") }, "the detector ran on both images: \(result.warnings)")
        for i in missing {
            XCTAssertEqual(result.trace[i].sightings, byFrame[i].count, "frame \(i): its image is missing, its observations replay")
        }
        XCTAssertTrue(result.warnings.contains { $0.contains("\(missing.count) of \(present.count + missing.count) frames")
            && $0.contains("use their recorded observations") }, "\(result.warnings)")
    }
}

/// While ARKit's tracking is lost the traveler walks on unseen: no exploratory instruction is planned from the
/// hypotheses, which stand where tracking was lost (docs/navigation.md "Guidance while not localized").
final class TrackingLossGuidanceTests: XCTestCase {
    func testNoDirectionalAdviceWhileTrackingIsLost() throws {
        var bundle = try TestData.sample()
        let building = try TestData.office()
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: PipelineOptions()))
        options.pipeline.localizer.particleCount = 3000
        // With this small cloud, filter seed 2 gives exploratory advice on the sample walk (16 frames; seed 1 none
        // since the thirty-fifth stop's floor footprint: it localizes late or not at all).
        options.pipeline.seed = 2
        options.snapshotParticleCount = 0
        // The sample gives exploratory advice before it localizes: lose tracking over most of that time.
        let reference = try Replay.run(bundle: bundle, building: building, options: options)
        let directed = reference.trace.filter { ($0.advice ?? "unsure") != "unsure" }
        XCTAssertFalse(directed.isEmpty, "the sample walk gives directional advice while unsure")
        let lost = Set(bundle.frames.indices.filter { i in directed.contains { abs($0.t - bundle.frames[i].t) < 1e-9 } })
        for i in lost { bundle.frames[i].tracking = .notAvailable }
        let result = try Replay.run(bundle: bundle, building: building, options: options)
        var lostFrames = 0
        for (i, r) in result.trace.enumerated() where lost.contains(i) {
            lostFrames += 1
            XCTAssertEqual(r.advice ?? "unsure", "unsure", "t=\(r.t)")
            XCTAssertNil(r.spokenAdvice, "t=\(r.t)")
            // Nor a bare "Start walking": the hypotheses are withheld while tracking is lost, not unknown.
            XCTAssertFalse(r.announcements.contains("Start walking."), "t=\(r.t)")
        }
        XCTAssertEqual(lostFrames, lost.count)
    }
}
