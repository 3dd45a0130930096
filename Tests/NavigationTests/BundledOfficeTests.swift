// Routes on the bundled two-floor "Wayfinder Office" (Maps/Buildings/wayfinder-office.json), walked end to
// end at 1.2 m/s with 10 Hz updates.
import Foundation
import Maps
import XCTest
@testable import Navigation

/// Walk steps that follow a route's polyline, riding between floors (3 s wait, then the traveler appears
/// at the landing of the next floor).
func walkSteps(along route: Route) -> [WalkStep] {
    var steps: [WalkStep] = []
    var floor = route.points.first?.floorId
    for p in route.points.dropFirst() {
        if p.floorId != floor {
            steps += [.wait(seconds: 3), .appear(at: p.position, floorId: p.floorId)]
            floor = p.floorId
        } else {
            steps.append(.walk(to: p.position))
        }
    }
    return steps
}

/// Walks `nav` from `start` along the route it adopts and checks the cue rules:
/// - every turn with a cue of its own gets exactly one, timed to END at least 0.5 m before its point at the
///   walking speed (1.2 m/s), and started at most a frame (0.12 m) later than that needs, or as soon as the
///   previous maneuver allows when it is closer;
/// - every ride gets its cue 0.5-1.5 m before its point (or, right after a landing closer than 0.5 m, on
///   arrival at the landing);
/// - a maneuver announced with the previous one ("Then turn left.") is said once, before its point;
/// - door cues rank as alerts and may be dropped when a turn or ride phrase occupies the speech channel,
///   but are never said more than 0.5 m past the door;
/// - turns and doors within the first 1.5 m are covered by the first instruction.
/// Returns the walker for further checks.
@discardableResult
func walkRouteCheckingCues(_ nav: Navigator, start: Point2, floorId: String, file: StaticString = #filePath,
                           line: UInt = #line) throws -> Walker {
    var w = Walker(start: start, floorId: floorId)
    w.run(nav, [.wait(seconds: 0.1)])
    let route = try XCTUnwrap(nav.currentRoute, file: file, line: line)
    w.run(nav, walkSteps(along: route))
    XCTAssertTrue(nav.hasArrived, "arrived", file: file, line: line)
    XCTAssertEqual(nav.routeCount, 1, "no re-route while on the route", file: file, line: line)
    let lookAhead = nav.options.lookAheadMeters
    for (k, m) in route.maneuvers.enumerated() {
        let isPoint = m.kind.isTurn || m.kind == .takeElevator || m.kind == .takeStairs
        guard isPoint || m.kind == .goThroughDoor else { continue }
        if m.kind != .takeElevator && m.kind != .takeStairs && m.distanceFromStartMeters < lookAhead { continue }
        let chained = m.announcedWithPrevious
        guard let text = chained ? nav.narrative.then(m) : nav.narrative.cue(m, floorName: "") else { continue }
        let previous = k > 0 ? route.maneuvers[k - 1].distanceFromStartMeters : 0
        // A turn cue may come before a door just ahead of the turn (the door's cue is then dropped), not
        // before the turn or ride before it.
        let previousTurnOrRide = route.maneuvers[..<k].last { $0.kind.isTurn || $0.kind == .takeElevator
            || $0.kind == .takeStairs || $0.kind == .continue }?.distanceFromStartMeters ?? 0
        let lo = chained ? previous - 1.5 : m.kind.isTurn ? max(previousTurnOrRide, m.distanceFromStartMeters - 4) - 1e-9
            : previous - 1e-9
        let said = w.records.filter { r in
            r.progressMeters >= lo && r.progressMeters <= m.distanceFromStartMeters + 0.5
                && r.events.contains { $0.spokenText == text }
        }
        let what = "\(m.kind) at \(m.distanceFromStartMeters) m\(chained ? " (chained)" : ""): \(w.spoken)"
        if m.kind == .goThroughDoor && !chained {
            XCTAssertLessThanOrEqual(said.count, 1, what, file: file, line: line)
        } else {
            XCTAssertEqual(said.count, 1, what, file: file, line: line)
        }
        for r in said {
            let before = m.distanceFromStartMeters - r.progressMeters
            if chained || m.kind == .goThroughDoor {
                XCTAssertGreaterThanOrEqual(before, chained ? 0 : -0.5, "said after the point: " + what, file: file, line: line)
            } else if m.kind.isTurn {
                let lead = nav.options.cueEndMarginMeters + nav.options.cueSchedulingSlackMeters
                    + 1.2 * nav.policy.estimatedDurationSeconds(text)
                let end = before - 1.2 * nav.policy.estimatedDurationSeconds(text)
                XCTAssertGreaterThanOrEqual(end, min(0.5, m.distanceFromStartMeters - previousTurnOrRide - 1.2
                    * nav.policy.estimatedDurationSeconds(text) - 1e-6), "ends late: " + what, file: file, line: line)
                XCTAssertLessThanOrEqual(before, lead + 0.12 + 1e-6, "early: " + what, file: file, line: line)
            } else {
                XCTAssertGreaterThanOrEqual(before, min(0.5, m.distanceFromStartMeters - previous - 1e-6), "late: " + what,
                                            file: file, line: line)
                XCTAssertLessThanOrEqual(before, 1.5, "early: " + what, file: file, line: line)
            }
        }
    }
    return w
}

final class BundledOfficeTests: XCTestCase {
    func testRoomToRoomAcrossFloors() throws {
        let office = try BundledMaps.office()
        let nav = try Navigator(building: office, destinationId: "room-215")
        let startNode = try XCTUnwrap(office.graph.nodes.first { $0.pointOfInterestId == "room-101" })
        let w = try walkRouteCheckingCues(nav, start: startNode.position, floorId: startNode.floorId)
        let kinds = kindsList(nav.lastManeuvers)
        XCTAssertTrue(kinds.hasPrefix("depart,goThroughDoor"), kinds)  // out of Room 101
        XCTAssertTrue(kinds.contains("takeStairs") || kinds.contains("takeElevator"), kinds)
        XCTAssertTrue(kinds.hasSuffix("continue") == false && kinds.hasSuffix("arrive"), kinds)
        let arrival = try XCTUnwrap(w.spoken.last)
        XCTAssertTrue(arrival.hasPrefix("Arrived. Room 215 is "), arrival)
        XCTAssertTrue(arrival.hasSuffix(", behind a door."), arrival)
    }

    func testAvoidStairsTakesTheElevator() throws {
        let office = try BundledMaps.office()
        var options = NavigatorOptions()
        options.avoidStairs = true
        let nav = try Navigator(building: office, destinationId: "room-215", options: options)
        let startNode = try XCTUnwrap(office.graph.nodes.first { $0.pointOfInterestId == "room-101" })
        try walkRouteCheckingCues(nav, start: startNode.position, floorId: startNode.floorId)
        let kinds = kindsList(nav.lastManeuvers)
        XCTAssertTrue(kinds.contains("takeElevator"), kinds)
        XCTAssertFalse(kinds.contains("takeStairs"), kinds)
    }

    func testEveryPointOfInterestIsReachableFromTheMainEntrance() throws {
        let office = try BundledMaps.office()
        let start = try XCTUnwrap(office.graph.nodes.first { $0.pointOfInterestId == "exit-main-entrance" })
        for floor in office.floors {
            for poi in floor.pointsOfInterest where poi.id != "exit-main-entrance" {
                let nav = try Navigator(building: office, destinationId: poi.id)
                let route = nav.routeFrom(start.position, floorId: start.floorId)
                XCTAssertNotNil(route, poi.id)
                XCTAssertEqual(route?.maneuvers.first?.kind, .depart, poi.id)
                XCTAssertEqual(route?.maneuvers.last?.kind, .arrive, poi.id)
            }
        }
    }
}
