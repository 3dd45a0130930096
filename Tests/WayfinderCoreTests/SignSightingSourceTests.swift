import Foundation
import Localizer
import Maps
import SessionFormat
import SignDetection
import XCTest
@testable import WayfinderCore

/// SignSightingSource ranges detections with the map's sign-kind catalogue in one `SignDetector.sense` call per
/// frame (the tiny red-pixel U-Net, Tests/SignDetector/data, standing in for the product model).
final class SignSightingSourceTests: XCTestCase {
    private var modelsDirectory: URL!

    override func setUpWithError() throws {
        // A models folder holding the tiny test model under the product's file names.
        modelsDirectory = FileManager.default.temporaryDirectory.appendingPathComponent("wf-sighting-models-\(UUID().uuidString)")
        try FileManager.default.createDirectory(at: modelsDirectory, withIntermediateDirectories: true)
        let data = TestData.packageRoot.appendingPathComponent("Tests/SignDetector/data")
        try FileManager.default.copyItem(at: data.appendingPathComponent("tiny_red_unet.onnx"),
                                         to: modelsDirectory.appendingPathComponent(DetectorConfiguration.unetFileName))
        try FileManager.default.copyItem(at: data.appendingPathComponent("classes.json"),
                                         to: modelsDirectory.appendingPathComponent(DetectorConfiguration.classListFileName))
    }

    override func tearDownWithError() throws {
        try? FileManager.default.removeItem(at: modelsDirectory)
    }

    /// A 640 x 480 portrait frame: gray wall, a red plate over raw columns 300..339 (40 px: the upright sign's
    /// height) and rows 200..259.
    private func frame() -> (PipelineFrame, CameraPose) {
        let width = 640, height = 480
        var pixels = [UInt8](repeating: 120, count: width * height * 3)
        for v in 200..<260 {
            for u in 300..<340 {
                let i = (v * width + u) * 3
                pixels[i] = 220; pixels[i + 1] = 25; pixels[i + 2] = 25
            }
        }
        let image = ImageBuffer(width: width, height: height, bytesPerRow: width * 3, pixelFormat: .rgb8, data: pixels)
        let pose = CameraPose(positionInWorld: (0, 1.4, 0), yawRad: 0, pitchRad: 0.05, rollRad: -Double.pi / 2)
        let f = PipelineFrame(t: 0, cameraPose: pose, tracking: .normal,
                              intrinsics: CameraIntrinsics(fx: 534, fy: 530, cx: 319.5, cy: 239.5, width: width, height: height),
                              image: image)
        return (f, pose)
    }

    private func sightings(options: PipelineOptions, building: Building) throws -> [SignSighting] {
        let source = try SignSightingSource(options: options, catalogue: building.signCatalogue, imagesAvailable: true)
        let (f, pose) = frame()
        return try XCTUnwrap(try source.sightings(for: f, pose: pose).get()).sightings
    }

    /// A kind that reads text gets the platform's reading (Vision on the iPhone) when the detector read none: the
    /// red plate has no legend for tesseract, so the reader given in the options supplies it, cleaned; a kind that
    /// reads no text never asks it.
    func testTheLegendReaderFillsTheTextOfKindsThatReadText() throws {
        var options = PipelineOptions()
        options.sightingSource = .unet
        options.modelsDirectory = modelsDirectory.path
        let calls = LockedCounter()
        options.legendReader = { image, corners in
            calls.increment()
            return corners.count == 4 && image.width == 640 ? "2o4-" : nil
        }
        var exit = SignKindSpec.defaultExit
        exit.readsText = true
        options.signCatalogue = SignCatalogue(kinds: [exit])
        let office = try TestData.office()
        let read = try sightings(options: options, building: office)
        XCTAssertEqual(read.first?.text, "204", "O read as 0, the trailing '-' dropped")
        XCTAssertEqual(calls.value, read.count)
        options.signCatalogue = SignCatalogue(kinds: [.defaultExit])
        let plain = try sightings(options: options, building: office)
        XCTAssertFalse(plain.isEmpty)
        XCTAssertNil(plain.first?.text)
        XCTAssertEqual(calls.value, read.count, "not asked for a kind without text")
        XCTAssertNil(SignSightingSource.cleanLegend("--"))
        XCTAssertEqual(SignSightingSource.cleanLegend(" b-12 "), "B-12")
    }

    func testTheMapsCatalogueSetsTheRange() throws {
        var options = PipelineOptions()
        options.sightingSource = .unet
        options.modelsDirectory = modelsDirectory.path
        let office = try TestData.office()
        XCTAssertEqual(office.signCatalogue.heightMeters(kind: "exit"), 0.21)
        let base = try sightings(options: options, building: office)
        XCTAssertEqual(base.count, 1)
        let exit = try XCTUnwrap(base.first)
        XCTAssertEqual(exit.kind, "exit")
        XCTAssertEqual(exit.rangeMeters, 0.21 * 534 / 40, accuracy: 0.1)  // 40 px of a 0.21 m face at f = 534 px

        // A map whose Exit signs are twice as tall: twice the range, with no other setting.
        var tall = office
        tall.signKinds = [SignKindSpec(kind: "exit", heightMeters: 0.42, widthMeters: 0.6)]
        let far = try XCTUnwrap(try sightings(options: options, building: tall).first)
        XCTAssertEqual(far.rangeMeters / exit.rangeMeters, 2, accuracy: 1e-9)
        XCTAssertEqual(far.bearingRad, exit.bearingRad, accuracy: 1e-12)

        // The pipeline option overrides the map's catalogue.
        options.signCatalogue = SignCatalogue(kinds: [SignKindSpec(kind: "exit", heightMeters: 0.42, widthMeters: 0.6)])
        let overridden = try XCTUnwrap(try sightings(options: options, building: office).first)
        XCTAssertEqual(overridden.rangeMeters, far.rangeMeters)
    }

    /// Replayed observations carry the kinds their detector did not look for (`FrameRecord.unsearchedSignKinds`), so
    /// the localizer takes no negative information for them; an older bundle's frame (no list) searched every kind.
    /// The same with `.automatic` on a frame without an image.
    func testRecordedObservationsPassOnTheKindsTheirDetectorDidNotLookFor() throws {
        let pose = CameraPose(positionInWorld: (0, 1.4, 0), yawRad: 0, pitchRad: 0.05, rollRad: -Double.pi / 2)
        var record = FrameRecord(t: 1, cameraToWorld: pose.columnMajor, intrinsics: .iPhone8Full,
                                 unsearchedSignKinds: ["placard", "stairs"])
        let exit = ObservationRecord(t: 1, kind: "exit", rangeMeters: 4, bearingRad: 0.1, score: 0.9)
        let catalogue = try TestData.office().signCatalogue
        for source in [SightingSource.recorded, .automatic] {
            var options = PipelineOptions()
            options.sightingSource = source
            options.modelsDirectory = modelsDirectory.path
            let sightingSource = try SignSightingSource(options: options, catalogue: catalogue, imagesAvailable: source == .automatic)
            let frame = PipelineFrame(record: record, imagesDirectory: nil, observations: [exit])
            let found = try XCTUnwrap(try sightingSource.sightings(for: frame, pose: pose).get())
            XCTAssertEqual(found.sightings.map(\.kind), ["exit"], "\(source)")
            XCTAssertEqual(found.unsearchedKinds, ["placard", "stairs"], "\(source)")
        }
        record.unsearchedSignKinds = nil
        let older = PipelineFrame(record: record, imagesDirectory: nil, observations: [exit])
        let recorded = try SignSightingSource(options: PipelineOptions(), catalogue: catalogue, imagesAvailable: false)
        XCTAssertEqual(try XCTUnwrap(try recorded.sightings(for: older, pose: pose).get()).unsearchedKinds, [])
    }

    /// With `scheduleRecordedSightings` (the study of the phone's budget on simulated walks) replayed observations go
    /// through the wall-kind schedule: a recorded sighting of a wall kind the frame does not look for is left out (the
    /// phone's detector would not have found it) and that kind is unsearched; the Exit sign (the U-Net's class) is
    /// always looked for. Without it they are the recording detector's, used whole. The office's wall kinds are its
    /// pictograms and placards.
    func testRecordedSightingsOfAWallKindTheFrameDoesNotLookForAreLeftOut() throws {
        let pose = CameraPose(positionInWorld: (0, 1.4, 0), yawRad: 0, pitchRad: 0.05, rollRad: -Double.pi / 2)
        let record = FrameRecord(t: 1, cameraToWorld: pose.columnMajor, intrinsics: .iPhone8Full,
                                 unsearchedSignKinds: ["stairs"])
        let seen = ["exit", "restroom", "placard"].map {
            ObservationRecord(t: 1, kind: $0, rangeMeters: 2, bearingRad: 0, score: 0.9)
        }
        var options = PipelineOptions()
        options.scheduleRecordedSightings = true
        let catalogue = try TestData.office().signCatalogue
        let source = try SignSightingSource(options: options, catalogue: catalogue, imagesAvailable: false)
        XCTAssertEqual(source.wallKinds, ["restroom", "elevator", "stairs", "placard"])
        XCTAssertTrue(source.schedulesWallKinds)
        let frame = PipelineFrame(record: record, imagesDirectory: nil, observations: seen)
        let found = try XCTUnwrap(try source.sightings(for: frame, pose: pose, searchedWallKinds: ["restroom"]).get())
        XCTAssertEqual(found.sightings.map(\.kind), ["exit", "restroom"])
        XCTAssertEqual(found.unsearchedKinds, ["elevator", "stairs", "placard"])
        // No schedule (nil): every recorded sighting, the frame's own unsearched kinds only.
        let all = try XCTUnwrap(try source.sightings(for: frame, pose: pose).get())
        XCTAssertEqual(all.sightings.map(\.kind), ["exit", "restroom", "placard"])
        XCTAssertEqual(all.unsearchedKinds, ["stairs"])
        // The default: recorded observations whole, whatever the schedule would choose.
        let plain = try SignSightingSource(options: PipelineOptions(), catalogue: catalogue, imagesAvailable: false)
        XCTAssertFalse(plain.schedulesWallKinds)
        let whole = try XCTUnwrap(try plain.sightings(for: frame, pose: pose, searchedWallKinds: ["restroom"]).get())
        XCTAssertEqual(whole.sightings.map(\.kind), ["exit", "restroom", "placard"])
        XCTAssertEqual(whole.unsearchedKinds, ["stairs"])
    }

    func testAFrameOfTheWrongSizeIsAFrameErrorNotACrash() throws {
        var options = PipelineOptions()
        options.sightingSource = .unet
        options.modelsDirectory = modelsDirectory.path
        let source = try SignSightingSource(options: options, catalogue: try TestData.office().signCatalogue, imagesAvailable: true)
        var (f, pose) = frame()
        f.image?.data.removeLast(100)
        guard case .failure(let error) = source.sightings(for: f, pose: pose) else { return XCTFail("expected a frame error") }
        XCTAssertTrue("\(error)".contains("image data has"), "\(error)")
    }
}

/// A thread-safe call counter for @Sendable closures.
final class LockedCounter: @unchecked Sendable {
    private let lock = NSLock()
    private var count = 0
    func increment() { lock.lock(); count += 1; lock.unlock() }
    var value: Int { lock.lock(); defer { lock.unlock() }; return count }
}
