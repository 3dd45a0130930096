import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore
@testable import Evaluation

/// `wayfinder eval --explain` (App/Evaluation/WalkExplanation.swift): an instruction unsafe from the true pose is
/// listed with the time, the free walk it leaves, where the traveler truly was and the phrases around it.
final class WalkExplanationTests: XCTestCase {
    func testAnInstructionUnsafeFromTheTruePoseIsListedWithTheTruthAndThePhrases() {
        // A corridor x 0...20, y 0...2, closed at both ends; the traveler stands at x 18.5 facing the east end
        // wall (1.5 m away) for 10 s while the estimate puts them at x 10: "walk ahead" said at 4 s is unsafe.
        let walls = [Wall(from: Point2(0, 0), to: Point2(20, 0)), Wall(from: Point2(0, 2), to: Point2(20, 2)),
                     Wall(from: Point2(0, 0), to: Point2(0, 2)), Wall(from: Point2(20, 0), to: Point2(20, 2))]
        let building = Building(id: "c", name: "Corridor",
                                floors: [Floor(id: "1", name: "F", elevationMeters: 0, walls: walls)],
                                graph: NavigationGraph(nodes: [GraphNode(id: "a", kind: .control, floorId: "1",
                                                                         position: Point2(1, 1))], edges: []))
        let truth = stride(from: 0.0, through: 10, by: 0.1).map { TruthRecord(t: $0, x: 18.5, y: 1, floorId: "1", headingRad: 0) }
        var trace = truth.map { r in
            TraceRecord(t: r.t, x: 10, y: 1, floorId: "1", headingRad: 0, confidence: 0.2, localized: false, hypotheses: 2,
                        sightings: 0, announcements: [], haptics: [])
        }
        for i in trace.indices { trace[i].advice = trace[i].t < 4 - 1e-9 ? "unsure" : "ahead" }
        trace[40].spokenAdvice = "ahead"
        let said = "Not sure where you are yet. Walk straight ahead along the corridor."
        trace[40].announcements = [said]
        var result = ReplayResult(trace: trace, announcements: [(t: 4, text: said)], haptics: [], sightingRays: [],
                                  particleSnapshots: [], routePolyline: [], warnings: [])
        result.trackingPrompts = []
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
