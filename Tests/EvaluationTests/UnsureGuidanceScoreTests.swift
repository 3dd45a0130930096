import XCTest
import Maps
import SessionFormat
import WayfinderCore
@testable import Evaluation

/// Guidance while not localized, checked against the true pose (App/Evaluation/UnsureGuidanceScore.swift).
final class UnsureGuidanceScoreTests: XCTestCase {
    func testDirectedShareAndInstructionsUnsafeUnderTheTruePose() {
        // CorridorUnsureWalk: "ahead" spoken at 4 s walks into the end wall from the true pose; "turnAround" at 8 s.
        var trace = CorridorUnsureWalk.trace
        trace[80].advice = "turnAround"
        trace[80].spokenAdvice = "turnAround"
        let score = UnsureGuidanceScore(trace: trace, truth: TruthTrack(CorridorUnsureWalk.truth),
                                        building: CorridorUnsureWalk.building)
        XCTAssertEqual(score.unsureSeconds, 10, accuracy: 1e-6)
        XCTAssertEqual(score.directedSeconds, 6, accuracy: 1e-6)
        XCTAssertEqual(score.spokenInstructions, 2)
        XCTAssertEqual(score.unsafeInstructions, 1)  // "ahead" from the true pose walks into the end wall
        XCTAssertEqual(score.unsafeMoments.map(\.action), ["ahead"])
        XCTAssertEqual(score.unsafeMoments.first?.t ?? -1, 4, accuracy: 1e-9)
        XCTAssertLessThan(score.unsafeMoments.first?.freeWalkMeters ?? 9, 1.5 + 1e-6)  // the end wall 1.5 m ahead
    }
}
