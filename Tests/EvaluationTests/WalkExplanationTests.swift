import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore
@testable import Evaluation

/// `wayfinder eval --explain` (App/Evaluation/WalkExplanation.swift): an instruction unsafe from the true pose is
/// listed with the time, the free walk it leaves, where the traveler truly was and the phrases around it.
final class WalkExplanationTests: XCTestCase {
    func testAnInstructionUnsafeFromTheTruePoseIsListedWithTheTruthAndThePhrases() {
        // CorridorUnsureWalk: "walk ahead" said at 4 s into the end wall 1.5 m in front of the true pose.
        let building = CorridorUnsureWalk.building, truth = CorridorUnsureWalk.truth
        var trace = CorridorUnsureWalk.trace
        let said = "Not sure where you are yet. Walk straight ahead along the corridor."
        trace[40].announcements = [said]
        let result = ReplayResult(trace: trace, announcements: [(t: 4, text: said)], haptics: [], sightingRays: [],
                                  particleSnapshots: [], routePolyline: [], warnings: [])
        let track = TruthTrack(truth)
        let score = WalkScore(name: "corridor", localization: LocalizationScore(trace: trace, truth: track),
                              navigation: NavigationScore(announcements: result.announcements, truth: track, building: building,
                                                          destination: nil, convergenceT: nil),
                              frames: trace.count, durationSeconds: 10,
                              unsureGuidance: UnsureGuidanceScore(trace: trace, truth: track, building: building))
        let lines = WalkExplanation.lines(score: score, result: result, truth: truth, building: building)
        let unsafe = lines.filter { $0.contains("UNSAFE") }
        XCTAssertEqual(unsafe.count, 1, "\(lines)")
        let line = unsafe.first ?? ""
        XCTAssertTrue(line.contains("4.00 s 'ahead' (0.50 m free from the true pose)"), line)
        XCTAssertTrue(line.contains("truth (18.50, 1.00) floor 1"), line)
        XCTAssertTrue(line.contains("estimate (10.00, 1.00) floor 1, error 8.50 m, not localized"), line)
        XCTAssertTrue(lines.contains { $0.contains(said) }, "the phrase said then is listed: \(lines)")
    }
}
