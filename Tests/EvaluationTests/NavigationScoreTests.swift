import XCTest
import Maps
import SessionFormat
import WayfinderCore
@testable import Evaluation

/// True turns from the truth track (not node proximity), what counts as a cue, and the truth-floor check.
/// Hand-made walks at 1 m/s sampled at 10 Hz on floor "1", meters in the map frame.
final class NavigationScoreTests: XCTestCase {
    /// Truth along the polyline `points` at 1 m/s, 10 Hz, starting at `t0` seconds.
    func walk(_ points: [Point2], t0: Double = 0) -> [TruthRecord] {
        var out = [TruthRecord(t: t0, x: points[0].x, y: points[0].y, floorId: "1", headingRad: 0)]
        var t = t0
        for (a, b) in zip(points, points.dropFirst()) {
            let length = hypot(b.x - a.x, b.y - a.y)
            let steps = max(1, Int((length / 0.1).rounded()))
            for k in 1...steps {
                let f = Double(k) / Double(steps)
                t += length / Double(steps)
                out.append(TruthRecord(t: t, x: a.x + f * (b.x - a.x), y: a.y + f * (b.y - a.y), floorId: "1",
                                       headingRad: atan2(b.y - a.y, b.x - a.x)))
            }
        }
        return out
    }

    /// A building with floor "1" and the graph polyline through `nodes` (ids n0, n1, ...).
    /// With `edges` (index pairs) instead of the polyline's when given.
    func building(_ nodes: [Point2], edges pairs: [(Int, Int)]? = nil) -> Building {
        let graphNodes = nodes.enumerated().map { GraphNode(id: "n\($0.offset)", kind: .control, floorId: "1", position: $0.element) }
        let edges = (pairs ?? (1..<nodes.count).map { ($0 - 1, $0) }).map { GraphEdge(from: "n\($0.0)", to: "n\($0.1)") }
        return Building(id: "test", name: "Test", floors: [Floor(id: "1", name: "F1", elevationMeters: 0, walls: [])],
                        graph: NavigationGraph(nodes: graphNodes, edges: edges))
    }

    func point(_ p: Point2, _ angleDeg: Double, _ d: Double) -> Point2 {
        Point2(p.x + d * cos(angleDeg * .pi / 180), p.y + d * sin(angleDeg * .pi / 180))
    }

    /// The issue's case: a 61-degree left turn whose corner is cut on the diagonal, passing `passMeters`
    /// from its node (the chord from d before to d after the corner is d sin(30.5 deg) from it).
    func cutCornerWalk(passMeters: Double) -> (truth: [TruthRecord], building: Building, cueT: Double) {
        let corner = Point2(20, 0)
        let d = passMeters / sin(30.5 * .pi / 180)
        let leave = Point2(20 - d, 0), rejoin = point(corner, 61, d)
        let truth = walk([Point2(0, 0), leave, rejoin, point(corner, 61, 15)])
        // "Turn left now" 1 s before the walker leaves the straight line.
        return (truth, building([Point2(0, 0), corner, point(corner, 61, 15)]), 20 - d - 1)
    }

    func testCutCornerTurnCountsHoweverFarFromItsNodeTheWalkerPasses() {
        for pass in [1.51, 2.0] {
            let w = cutCornerWalk(passMeters: pass)
            let track = TruthTrack(w.truth)
            let closest = w.truth.map { hypot($0.x - 20, $0.y) }.min()!
            XCTAssertEqual(closest, pass, accuracy: 0.02, "the walk passes the node this far")
            let turns = NavigationScore.trueTurns(truth: track, building: w.building)
            XCTAssertEqual(turns.count, 1, "pass \(pass) m: \(turns)")
            XCTAssertEqual(turns.first?.direction, "left")
            XCTAssertEqual(turns.first?.angleDeg ?? 0, 61, accuracy: 3)
            XCTAssertEqual(turns.first?.nodeId, "n1")
            let score = NavigationScore(announcements: [(w.cueT, "Turn left now.")], truth: track, building: w.building,
                                        destination: nil, convergenceT: 0)
            XCTAssertEqual(score.wrongInstructions, 0, "the correct cue is not wrong (pass \(pass) m)")
            XCTAssertEqual(score.missingInstructions, 0)
            XCTAssertEqual(score.cueDistancesBeforeMeters.count, 1)
        }
    }

    func testAWrongDirectionCueAtACutCornerIsStillWrong() {
        let w = cutCornerWalk(passMeters: 2.0)
        let score = NavigationScore(announcements: [(w.cueT, "Turn right now.")], truth: TruthTrack(w.truth),
                                    building: w.building, destination: nil, convergenceT: 0)
        XCTAssertEqual(score.wrongInstructions, 1)
        XCTAssertEqual(score.missingInstructions, 1)
        XCTAssertEqual(score.wrongCues.map(\.text), ["Turn right now."])
    }

    /// A corridor n0 (0, 0) - n1 (10, 0) - n2 (20, 0) with a branch from n1 to the room at (10, -5): walking east,
    /// the room is a right turn at n1. The walker goes straight past it (a wrong turn on purpose).
    func walkPastTheTurn() -> (truth: TruthTrack, building: Building) {
        let nodes = [GraphNode(id: "n0", kind: .control, floorId: "1", position: Point2(0, 0)),
                     GraphNode(id: "n1", kind: .control, floorId: "1", position: Point2(10, 0)),
                     GraphNode(id: "n2", kind: .control, floorId: "1", position: Point2(20, 0)),
                     GraphNode(id: "room", kind: .pointOfInterest, floorId: "1", position: Point2(10, -5), label: "Room",
                               pointOfInterestId: "room")]
        let edges = [GraphEdge(from: "n0", to: "n1"), GraphEdge(from: "n1", to: "n2"), GraphEdge(from: "n1", to: "room")]
        let room = PointOfInterest(id: "room", name: "Room", category: "office", position: Point2(10, -5), behindDoor: false)
        let b = Building(id: "test", name: "Test",
                         floors: [Floor(id: "1", name: "F1", elevationMeters: 0, walls: [], doors: [], signs: [], pointsOfInterest: [room])],
                         graph: NavigationGraph(nodes: nodes, edges: edges))
        return (TruthTrack(walk([Point2(0, 0), Point2(20, 0)])), b)
    }

    func testACueRightUnderTheTruePoseIsNotWrongWhenTheTravelerWalksPastTheTurn() {
        let w = walkPastTheTurn()
        // "Turn right now." 2 m before n1: the route from the true position turns right there.
        let followedNot = NavigationScore(announcements: [(8, "Turn right now.")], truth: w.truth, building: w.building,
                                          destination: "room", convergenceT: 0)
        XCTAssertEqual(followedNot.wrongInstructions, 0, "\(followedNot.wrongCues)")
        // The other way, or without a destination to route to, or with the turn too far ahead, it is wrong.
        for (t, text, destination) in [(8.0, "Turn left now.", "room"), (8.0, "Turn right now.", nil), (2.0, "Turn right now.", "room")] {
            let score = NavigationScore(announcements: [(t, text)], truth: w.truth, building: w.building,
                                        destination: destination, convergenceT: 0)
            XCTAssertEqual(score.wrongInstructions, 1, "\(text) at \(t) s to \(destination ?? "nil")")
        }
    }

    func testAChangeOfDirectionFarFromEveryControlPointIsNotATurn() {
        // The same 90-degree turn, but the graph's only corner is 10 m away.
        let truth = walk([Point2(0, 0), Point2(20, 0), Point2(20, 15)])
        let far = building([Point2(0, -10), Point2(30, -10), Point2(30, 5)])
        XCTAssertTrue(NavigationScore.trueTurns(truth: TruthTrack(truth), building: far).isEmpty)
        let near = building([Point2(0, 0), Point2(20, 0), Point2(20, 15)])
        XCTAssertEqual(NavigationScore.trueTurns(truth: TruthTrack(truth), building: near).map(\.direction), ["left"])
    }

    func testTurnAroundIsNoTurnButTheTurnsIntoAndOutOfTheBranchAre() {
        // Junction n1 at (20, 0) with a branch north (n3): the walker turns into it (left), goes 4 m,
        // turns around in place, comes back and turns left again to go on east.
        let j = Point2(20, 0)
        var truth = walk([Point2(0, 0), j, Point2(20, 4)])
        let back = walk([Point2(20, 4), j, Point2(35, 0)], t0: truth.last!.t + 2)
        truth += back.dropFirst()
        let b = building([Point2(0, 0), j, Point2(35, 0), Point2(20, 6)], edges: [(0, 1), (1, 2), (1, 3)])
        let turns = NavigationScore.trueTurns(truth: TruthTrack(truth), building: b)
        XCTAssertEqual(turns.map(\.direction), ["left", "left"], "\(turns)")
        XCTAssertTrue(turns.allSatisfy { $0.nodeId == "n1" && abs($0.angleDeg) < 150 })
    }

    func testTwoTurnsOfAUShapedRouteAreTwoTurns() {
        // West, right (north) for 1.9 m, right (east) for 1 m: the end of the walk to an elevator's buttons.
        // Together the two corners turn 180 degrees; each is a turn the navigator cues ("Turn right now.",
        // "Then turn right.").
        let truth = walk([Point2(20, 0), Point2(10, 0), Point2(10, 1.9), Point2(11, 1.9)])
        let b = building([Point2(20, 0), Point2(10, 0), Point2(10, 1.9), Point2(11, 1.9)])
        let turns = NavigationScore.trueTurns(truth: TruthTrack(truth), building: b)
        XCTAssertEqual(turns.map(\.direction), ["right", "right"], "\(turns)")
        XCTAssertEqual(turns.map(\.nodeId), ["n1", "n2"])
        let score = NavigationScore(announcements: [(8.5, "Turn right now."), (9.5, "Then turn right.")],
                                    truth: TruthTrack(truth), building: b, destination: nil, convergenceT: 0)
        XCTAssertEqual(score.wrongInstructions, 0, "\(score.wrongCues)")
        XCTAssertEqual(score.missingInstructions, 0)
    }

    func testAJogIsOneSlightTurnAndABendsCueIsNotWrong() {
        // A jog: right 1.3 m then left again (the navigator collapses it into "Bear right now."), then a
        // 25-degree bend to the left ("Bear left now.", below the 35-degree true-turn threshold).
        let pts = [Point2(0, 0), Point2(10, 0), Point2(10, -1.3), Point2(20, -1.3)]
        let bendEnd = point(pts[3], 25, 12)
        let truth = walk(pts + [bendEnd])
        let b = building(pts + [bendEnd])
        let score = NavigationScore(announcements: [(9.0, "Bear right now."), (19.3, "Bear left now.")],
                                    truth: TruthTrack(truth), building: b, destination: nil, convergenceT: 0)
        XCTAssertFalse(score.expectedTurns.contains { $0.secondHalfOfJog }, "the jog's second half is not expected")
        XCTAssertTrue(NavigationScore.trueTurns(truth: TruthTrack(truth), building: b, minimumAngleDeg: 20)
            .contains { $0.secondHalfOfJog && $0.direction == "left" }, "the jog is found")
        XCTAssertEqual(score.missingInstructions, 0)
        XCTAssertEqual(score.wrongInstructions, 0, "\(score.wrongCues)")
    }

    func testDepartureThatStartsWithATurnIsItsCueAndTurnsBegunBeforeConvergenceAreNotExpected() {
        let truth = walk([Point2(0, 0), Point2(20, 0), Point2(20, -15)])
        let b = building([Point2(0, 0), Point2(20, 0), Point2(20, -15)])
        // Localized 1 s before the corner (the turn's stretch began about 1.7 m before it).
        let late = NavigationScore(announcements: [(19.0, "Go straight ahead, 15 meters.")], truth: TruthTrack(truth),
                                   building: b, destination: nil, convergenceT: 19.0)
        XCTAssertEqual(late.missingInstructions, 0, "a turn under way at convergence is not the navigator's")
        // Localized 0.5 s before it began: the departure phrase "Turn right, then go ..." is its cue.
        let early = NavigationScore(announcements: [(17.8, "Turn right, then go 15 meters.")], truth: TruthTrack(truth),
                                    building: b, destination: nil, convergenceT: 17.8)
        XCTAssertEqual(early.expectedTurns.count, 1)
        XCTAssertEqual(early.missingInstructions, 0)
        XCTAssertEqual(early.wrongInstructions, 0)
    }

    func testCuePhrases() {
        XCTAssertEqual(NavigationScore.cueDirection("Turn left now."), "left")
        XCTAssertEqual(NavigationScore.cueDirection("Bear right now."), "right")
        XCTAssertEqual(NavigationScore.cueDirection("Then turn right."), "right")
        XCTAssertEqual(NavigationScore.cueDirection("Turn right, then go 10 meters."), "right")
        XCTAssertNil(NavigationScore.cueDirection("In 8 meters, turn left."))
        XCTAssertNil(NavigationScore.cueDirection("Go straight ahead, 2 meters."))
        XCTAssertNil(NavigationScore.cueDirection("Arrived. Room 101 is on your left."))
        XCTAssertNil(NavigationScore.cueDirection("Now on Floor 2. Continue 10 meters."))
        XCTAssertNil(NavigationScore.cueDirection("Wrong way, turn around."))
        XCTAssertNil(NavigationScore.cueDirection("Near Knowledge Center, between Left Wing and Lobby."))
    }

    func testTruthOnAFloorTheMapLacksIsAnErrorNamingTheFileAndField() throws {
        let office = try BundledMaps.office()
        var truth = walk([Point2(5, 7), Point2(10, 7)])
        truth[3].floorId = "9"
        XCTAssertThrowsError(try WalkEvaluator.checkTruthFloors(truth, building: office)) {
            let m = "\($0)"
            XCTAssertTrue(m.contains("truth.jsonl") && m.contains("record 4") && m.contains("floorId '9'")
                          && m.contains("'\(office.id)'"), m)
        }
        // Through the evaluator: refused before any replay.
        let bundle = SessionBundle(url: URL(fileURLWithPath: "/tmp/walk"), info: SessionInfo(device: "test", appVersion: "0"),
                                   frames: [], truth: truth)
        XCTAssertThrowsError(try WalkEvaluator.evaluate(name: "walk", bundle: bundle, building: office)) {
            guard case .truthFloorNotInMap(let n, _, let floorId, _, _)? = $0 as? EvaluationError else { return XCTFail("\($0)") }
            XCTAssertEqual(n, 4); XCTAssertEqual(floorId, "9")
        }
        XCTAssertNoThrow(try WalkEvaluator.checkTruthFloors(walk([Point2(5, 7), Point2(10, 7)]), building: office))
    }
}

/// The cue-timing figure of issue 17: does a "now" cue end 0.5 m before its control point?
final class NowCueTimingTests: XCTestCase {
    /// A 90-degree left at (20, 0) walked at 1 m/s from (0, 0), cue "Turn left now." said `cueMetersBefore`
    /// before the corner (t = 20 - that).
    func score(cueMetersBefore: Double, text: String = "Turn left now.") -> NavigationScore {
        // Truth at 1 m/s, 10 Hz, along the two legs.
        var truth: [TruthRecord] = []
        for i in 0...350 {
            let s = Double(i) / 10
            truth.append(TruthRecord(t: s, x: min(s, 20), y: max(0, s - 20), floorId: "1", headingRad: s < 20 ? 0 : .pi / 2))
        }
        let nodes = [Point2(0, 0), Point2(20, 0), Point2(20, 15)].enumerated().map {
            GraphNode(id: "n\($0.offset)", kind: .control, floorId: "1", position: $0.element)
        }
        let building = Building(id: "test", name: "Test", floors: [Floor(id: "1", name: "F1", elevationMeters: 0, walls: [])],
                                graph: NavigationGraph(nodes: nodes, edges: [GraphEdge(from: "n0", to: "n1"),
                                                                            GraphEdge(from: "n1", to: "n2")]))
        return NavigationScore(announcements: [(t: 20 - cueMetersBefore, text: text)], truth: TruthTrack(truth),
                               building: building, destination: nil, convergenceT: 0)
    }

    func testEndOfTheCueIsMeasuredWithTheDurationModel() throws {
        let lasts = NavigationScore.speechTiming.durationSeconds("Turn left now.")  // 1.15 s = 1.15 m at 1 m/s
        XCTAssertEqual(lasts, 1.15, accuracy: 0.01)
        // The paper's 0.75 m: the cue ends 0.4 m after the corner.
        let late = score(cueMetersBefore: 0.75)
        XCTAssertEqual(late.cueDistancesBeforeMeters.count, 1)
        XCTAssertEqual(try XCTUnwrap(late.nowCueEndBeforeMeters?.first), 0.75 - lasts, accuracy: 0.12)
        XCTAssertEqual(AggregateScore([walkScore(late)]).nowCuesEndingInTimeShare, 0)
        // Timed to end 0.8 m before: counted in time.
        let early = score(cueMetersBefore: 0.8 + lasts)
        XCTAssertEqual(try XCTUnwrap(early.nowCueEndBeforeMeters?.first), 0.8, accuracy: 0.12)
        XCTAssertEqual(AggregateScore([walkScore(early), walkScore(late)]).nowCuesEndingInTimeShare, 0.5)
        XCTAssertEqual(AggregateScore([walkScore(early), walkScore(late)]).nowCues, 2)
        // A chained "Then turn left." is a cue but not a "now" cue: not in the figure.
        XCTAssertEqual(score(cueMetersBefore: 2, text: "Then turn left.").nowCueEndBeforeMeters, [])
    }

    func testMergedRouteStartIsACueForItsFirstTurnOnly() {
        XCTAssertEqual(NavigationScore.cueDirection("Turn left, then go 10 meters. Then turn right."), "left")
        XCTAssertNil(NavigationScore.cueDirection("Go straight ahead, 10 meters. Then turn left."))
        XCTAssertTrue(NavigationScore.isNowCue("Turn right now, toward 3 o'clock."))
        XCTAssertFalse(NavigationScore.isNowCue("Then turn right."))
    }

    private func walkScore(_ n: NavigationScore) -> WalkScore {
        WalkScore(name: "w", localization: LocalizationScore(trace: [], truth: TruthTrack([])), navigation: n, frames: 0,
                  durationSeconds: 0, unsureGuidance: nil)
    }
}
