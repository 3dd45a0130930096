import XCTest
import Maps
import SessionFormat
import WayfinderCore
@testable import Evaluation

/// Guidance while not localized, checked against the true pose (App/Evaluation/UnsureGuidanceScore.swift).
final class UnsureGuidanceScoreTests: XCTestCase {
    /// A corridor x 0...20, y 0...2, closed at both ends.
    private let building: Building = {
        let walls = [Wall(from: Point2(0, 0), to: Point2(20, 0)), Wall(from: Point2(0, 2), to: Point2(20, 2)),
                     Wall(from: Point2(0, 0), to: Point2(0, 2)), Wall(from: Point2(20, 0), to: Point2(20, 2))]
        return Building(id: "c", name: "Corridor", floors: [Floor(id: "1", name: "F", elevationMeters: 0, walls: walls)],
                        graph: NavigationGraph(nodes: [GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(1, 1))],
                                               edges: []))
    }()

    func testDirectedShareAndInstructionsUnsafeUnderTheTruePose() {
        // The true walker stands at x 18.5 facing east (the end wall 1.5 m ahead) for 10 s, at 10 Hz.
        let truth = stride(from: 0.0, through: 10, by: 0.1).map { TruthRecord(t: $0, x: 18.5, y: 1, floorId: "1", headingRad: 0) }
        var trace = truth.map { r in
            TraceRecord(t: r.t, x: 10, y: 1, floorId: "1", headingRad: 0, confidence: 0.2, localized: false, hypotheses: 2,
                        sightings: 0, announcements: [], haptics: [])
        }
        // 0-4 s "unsure", then "ahead" in force; "ahead" spoken at 4 s (into the wall: unsafe), "turnAround" at 8 s.
        for i in trace.indices { trace[i].advice = trace[i].t < 4 - 1e-9 ? "unsure" : "ahead" }
        trace[40].spokenAdvice = "ahead"
        trace[80].advice = "turnAround"
        trace[80].spokenAdvice = "turnAround"
        let score = UnsureGuidanceScore(trace: trace, truth: TruthTrack(truth), building: building)
        XCTAssertEqual(score.unsureSeconds, 10, accuracy: 1e-6)
        XCTAssertEqual(score.directedSeconds, 6, accuracy: 1e-6)
        XCTAssertEqual(score.spokenInstructions, 2)
        XCTAssertEqual(score.unsafeInstructions, 1)  // "ahead" from the true pose walks into the end wall
        XCTAssertEqual(score.unsafeMoments.map(\.action), ["ahead"])
        XCTAssertEqual(score.unsafeMoments.first?.t ?? -1, 4, accuracy: 1e-9)
        XCTAssertLessThan(score.unsafeMoments.first?.freeWalkMeters ?? 9, 1.5 + 1e-6)  // the end wall 1.5 m ahead
    }
}
