import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore

/// The replay of the committed sample walk through the whole pipeline.
final class ReplayTests: XCTestCase {
    func testSampleReplaySaysStartWalkingFirstAndTracesEveryFrame() throws {
        let bundle = try TestData.sample()
        let building = try TestData.office()
        let options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: PipelineOptions()))
        let result = try Replay.run(bundle: bundle, building: building, options: options)
        XCTAssertEqual(result.trace.count, bundle.frames.count)
        XCTAssertEqual(result.announcements.first?.text, "Start walking.")
        XCTAssertTrue(result.trace.allSatisfy { $0.x.isFinite && $0.y.isFinite && $0.headingRad.isFinite && $0.confidence.isFinite })
        // No guidance other than "Start walking" before the localizer is sure.
        let firstLocalized = result.trace.first(where: \.localized)?.t ?? .infinity
        for a in result.announcements where a.t < firstLocalized {
            XCTAssertEqual(a.text, "Start walking.", "spoke '\(a.text)' at \(a.t) s before being localized")
        }
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
}
