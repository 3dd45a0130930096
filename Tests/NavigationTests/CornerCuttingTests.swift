// Guidance for travelers who walk as people do: cutting corners, localized just before a turn, and routes
// whose graph bends slightly right before a turn. Walks at 1.2 m/s with 10 Hz updates.
import Foundation
import Maps
import XCTest
@testable import Navigation

final class CornerCuttingTests: XCTestCase {
    func building(_ points: [(String, Point2)]) -> Building {
        let nodes = points.map { GraphNode(id: $0.0, kind: .control, floorId: "1", position: $0.1) }
        let edges = (1..<points.count).map { GraphEdge(from: points[$0 - 1].0, to: points[$0].0) }
        return Building(id: "b", name: "B", floors: [Floor(id: "1", name: "F1", elevationMeters: 0, walls: [])],
                        graph: NavigationGraph(nodes: nodes, edges: edges))
    }

    func testCueComesBeforeTheCornerForATravelerWhoCutsIt() throws {
        // East to b (20, 0), then north. The traveler leaves the corridor's line 3 m before b and walks the
        // diagonal to 3 m past it: they are nearest the route's corner at (18.5, 1.5), where their
        // projection jumps from the incoming to the outgoing segment.
        let b = building([("a", Point2(x: 0, y: 0)), ("b", Point2(x: 20, y: 0)), ("c", Point2(x: 20, y: 15))])
        let nav = try Navigator(building: b, destinationId: "c")
        var w = Walker(start: Point2(x: 2, y: 0), floorId: "1")
        w.run(nav, [.walk(to: Point2(x: 17, y: 0)), .walk(to: Point2(x: 20, y: 3)), .walk(to: Point2(x: 20, y: 14.5))])
        let cue = try XCTUnwrap(w.records.first { $0.events.contains { $0.spokenText == "Turn left now." } }, "\(w.spoken)")
        // Before the point of the diagonal nearest the corner (x = 18.5), by at least 0.3 m of walking.
        XCTAssertLessThan(cue.input.positionInMap.x, 18.5 - 0.3 / 2.0.squareRoot(), "cue at \(cue.input.positionInMap)")
        // Not before the traveler leaves the corridor's line at x = 17 (on the line the cue is due at 17.8).
        XCTAssertGreaterThan(cue.input.positionInMap.x, 17.0, "not earlier than the cut's reach")
        XCTAssertEqual(w.spoken.filter { $0.contains("now") }, ["Turn left now."])
    }

    func testTravelerOnTheCentreLineGetsTheCueTimedToEndHalfAMeterBeforeTheTurn() throws {
        let b = building([("a", Point2(x: 0, y: 0)), ("b", Point2(x: 20, y: 0)), ("c", Point2(x: 20, y: 15))])
        let nav = try Navigator(building: b, destinationId: "c")
        var w = Walker(start: Point2(x: 2, y: 0), floorId: "1")
        w.run(nav, [.walk(to: Point2(x: 20, y: 0)), .walk(to: Point2(x: 20, y: 14.5))])
        let cue = try XCTUnwrap(w.records.first { $0.events.contains { $0.spokenText == "Turn left now." } })
        // Ends 0.5 m (+ 0.5 m slack) before the corner at 1.2 m/s: starts 1.0 + 1.2 x 1.15 s = 2.38 m before.
        let lead = nav.options.cueEndMarginMeters + nav.options.cueSchedulingSlackMeters
            + 1.2 * nav.policy.estimatedDurationSeconds("Turn left now.")
        XCTAssertEqual(cue.input.positionInMap.x, 20 - lead, accuracy: 0.13)
    }

    func testStraightAheadDepartureDoesNotSwallowATurnJustAhead() throws {
        // Localized 1.2 m before a left turn, facing along the corridor: the point 1.5 m ahead on the route
        // (0.3 m past the corner) is within the "ahead" sector, so the first phrase says "Go straight
        // ahead"; the turn must still get its cue.
        let b = building([("a", Point2(x: 0, y: 0)), ("b", Point2(x: 10, y: 0)), ("c", Point2(x: 10, y: 8))])
        let nav = try Navigator(building: b, destinationId: "c")
        var w = Walker(start: Point2(x: 8.8, y: 0), floorId: "1")
        w.run(nav, [.wait(seconds: 0.1), .walk(to: Point2(x: 10, y: 0)), .walk(to: Point2(x: 10, y: 7.5))])
        // 1.2 m before the turn its cue is due at once (it must end 0.5 m before the corner): the cue is
        // the first instruction, with no "Go straight ahead, 1 meter." around it.
        XCTAssertEqual(w.spoken.first, "Turn left now.", "\(w.spoken)")
        XCTAssertFalse(w.spoken.contains { $0.hasPrefix("Go straight ahead") }, "\(w.spoken)")
        // Facing the new corridor already (the turn is behind the first phrase's direction): no cue.
        let nav2 = try Navigator(building: b, destinationId: "c")
        var w2 = Walker(start: Point2(x: 9.7, y: 0), floorId: "1", headingRad: .pi / 2)
        w2.run(nav2, [.wait(seconds: 0.1), .walk(to: Point2(x: 10, y: 0.5)), .walk(to: Point2(x: 10, y: 7.5))])
        XCTAssertFalse(w2.spoken.contains("Turn left now."), "\(w2.spoken)")
    }

    func testLockedWhileTurningACornerIsNotToldToTurnBackAgainstIt() throws {
        // Localized 1.2 m before a left turn (the estimate lags a traveler who cuts the corner), already turned
        // 48 degrees left: the look-ahead point, 0.3 m past the corner, lies 34 degrees to the right of the
        // heading. "Turn right" would send them back against the turn they are making.
        let b = building([("a", Point2(x: 0, y: 0)), ("b", Point2(x: 10, y: 0)), ("c", Point2(x: 10, y: 8))])
        let nav = try Navigator(building: b, destinationId: "c")
        var w = Walker(start: Point2(x: 8.8, y: 0), floorId: "1", headingRad: 48 * Double.pi / 180)
        w.run(nav, [.wait(seconds: 0.1), .walk(to: Point2(x: 10, y: 1.2)), .walk(to: Point2(x: 10, y: 7.5))])
        XCTAssertFalse(w.spoken.contains { $0.contains("right") }, "\(w.spoken)")
        XCTAssertTrue(w.spoken.first?.hasPrefix("Go straight ahead") ?? false, "\(w.spoken)")
        // Turned 20 degrees only (nearer the incoming leg): the turn keeps its cue.
        let nav2 = try Navigator(building: b, destinationId: "c")
        var w2 = Walker(start: Point2(x: 8.8, y: 0), floorId: "1", headingRad: 20 * Double.pi / 180)
        w2.run(nav2, [.wait(seconds: 0.1), .walk(to: Point2(x: 10, y: 0.4)), .walk(to: Point2(x: 10, y: 7.5))])
        XCTAssertFalse(w2.spoken.contains { $0.contains("right") }, "\(w2.spoken)")
        XCTAssertTrue(w2.spoken.contains { $0.hasPrefix("Turn left") }, "\(w2.spoken)")
        // Facing back along the incoming leg (not turning the corner): the first instruction still says which
        // way the route goes.
        let nav3 = try Navigator(building: b, destinationId: "c")
        var w3 = Walker(start: Point2(x: 8.8, y: 0), floorId: "1", headingRad: -100 * Double.pi / 180)
        w3.run(nav3, [.wait(seconds: 0.1)])
        XCTAssertTrue(w3.spoken.first?.hasPrefix("Turn left") ?? false, "\(w3.spoken)")
    }

    func testLockedAStepFromTheDestinationTheArrivalIsNotPrecededByAContraryInstruction() throws {
        // Localized 1.5 m before the destination c, walking toward it: "Go straight ahead, 2 meters." would still
        // be playing when the arrival comes 0.5 m later (found behind survey-rough: "Turn right, then go 1 meter."
        // then 0.17 s later "Arrived. Room 107 is ahead"). The arrival is the first and only instruction.
        let b = building([("a", Point2(x: 0, y: 0)), ("b", Point2(x: 10, y: 0)), ("c", Point2(x: 10, y: 8))])
        let nav = try Navigator(building: b, destinationId: "c")
        var w = Walker(start: Point2(x: 10, y: 6.5), floorId: "1", headingRad: Double.pi / 2)
        w.run(nav, [.walk(to: Point2(x: 10, y: 7.6))])
        XCTAssertEqual(w.spoken.count, 1, "\(w.spoken)")
        XCTAssertTrue(w.spoken.first?.hasPrefix("Arrived") ?? false, "\(w.spoken)")
        // Standing there, the first instruction comes after the hold (2 s), and nothing else.
        let nav2 = try Navigator(building: b, destinationId: "c")
        var w2 = Walker(start: Point2(x: 10, y: 6.5), floorId: "1", headingRad: Double.pi / 2)
        w2.run(nav2, [.wait(seconds: 4)])
        XCTAssertEqual(w2.spoken.count, 1, "\(w2.spoken)")
        XCTAssertTrue(w2.spoken.first?.hasPrefix("Go straight ahead") ?? false, "\(w2.spoken)")
        let said = try XCTUnwrap(w2.records.first { !$0.events.filter { $0.spokenText != nil }.isEmpty })
        XCTAssertEqual(said.input.t - w2.startT, Navigator.departureHoldSeconds, accuracy: 0.15)
        // Farther away (5 m: the instruction ends before the arrival), it is said at once as before.
        let nav3 = try Navigator(building: b, destinationId: "c")
        var w3 = Walker(start: Point2(x: 10, y: 3), floorId: "1", headingRad: Double.pi / 2)
        w3.run(nav3, [.wait(seconds: 0.1)])
        XCTAssertTrue(w3.spoken.first?.hasPrefix("Go straight ahead") ?? false, "\(w3.spoken)")
    }

    func testSlightBendJustBeforeAnOppositeTurnIsOneTurn() throws {
        // A 25-degree bend right at b, 1 m before a 90-degree left at c: one left turn of 65 degrees.
        let c = Point2(x: 10 + cos(-25 * Double.pi / 180), y: sin(-25 * Double.pi / 180))
        let d = Point2(x: c.x + 10 * cos(65 * Double.pi / 180), y: c.y + 10 * sin(65 * Double.pi / 180))
        let b = building([("a", Point2(x: 0, y: 0)), ("b", Point2(x: 10, y: 0)), ("c", c), ("d", d)])
        let nav = try Navigator(building: b, destinationId: "d")
        var w = Walker(start: Point2(x: 2, y: 0), floorId: "1")
        w.run(nav, [.walk(to: Point2(x: 10, y: 0)), .walk(to: c), .walk(to: Point2(x: (c.x + d.x) / 2, y: (c.y + d.y) / 2))])
        XCTAssertEqual(kindsList(nav.lastManeuvers), "depart,turnLeft,arrive")
        XCTAssertEqual(nav.lastManeuvers[1].turnAngleDeg ?? 0, 65, accuracy: 0.5)
        XCTAssertEqual(nav.lastManeuvers[1].nodeId, "c")
        XCTAssertTrue(w.spoken.contains("Turn left now."), "\(w.spoken)")
        XCTAssertFalse(w.spoken.contains { $0.lowercased().contains("bear") }, "\(w.spoken)")
    }
}
