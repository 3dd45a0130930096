import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore

/// The app flow's state machine, fed with the sample walk's frames as the phone would.
final class GuidanceSessionTests: XCTestCase {
    func testFlowFromBuildingToGuidance() throws {
        let building = try TestData.office()
        let session = GuidanceSession()
        XCTAssertEqual(session.state, .choosingBuilding)
        XCTAssertThrowsError(try session.start(), "cannot start before choosing")
        session.selectBuilding(building)
        XCTAssertEqual(session.state, .choosingStart)
        XCTAssertFalse(session.places!.items.isEmpty)
        session.selectStart(nil)
        XCTAssertEqual(session.state, .choosingDestination)
        session.selectDestination("no-such-place")
        XCTAssertEqual(session.state, .choosingDestination, "unknown destinations are ignored")
        let bundle = try TestData.sample()
        session.selectDestination(bundle.info.destination!)
        XCTAssertEqual(session.state, .ready)
        session.pipelineOptions.sightingSource = .recorded
        session.pipelineOptions.localizer.particleCount = 3000
        XCTAssertEqual(try session.start(), [.startSensors])
        XCTAssertEqual(session.state, .guiding)

        var spoken: [String] = []
        var obsByFrame: [Int: [ObservationRecord]] = [:]
        var j = 0
        for (i, f) in bundle.frames.enumerated() {
            while j < bundle.observations.count, bundle.observations[j].t <= f.t + 1e-6 {
                obsByFrame[i, default: []].append(bundle.observations[j]); j += 1
            }
        }
        for (i, f) in bundle.frames.enumerated() {
            let frame = PipelineFrame(record: f, imagesDirectory: nil, observations: obsByFrame[i] ?? [])
            for c in session.process(frame) { if case .speak(let text, _) = c { spoken.append(text) } }
        }
        XCTAssertTrue(spoken.first.map(ReplayTests.isUnsureGuidance) ?? false, "first: \(String(describing: spoken.first))")
        let stopped = session.stop()
        if session.state != .arrived {
            XCTAssertTrue(stopped.contains(.stopSensors))
            XCTAssertEqual(session.state, .ready)
        }
    }

    func testWhereAmIBeforeGuidanceSpeaksTheStatus() {
        let session = GuidanceSession()
        XCTAssertEqual(session.whereAmI(t: 0), [.speak("Choose a building", interrupt: true)])
    }
}
