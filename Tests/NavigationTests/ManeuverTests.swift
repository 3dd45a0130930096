// Maneuver tables on ASCII fixtures, OSRM-feature style: each row routes from a node to a destination and
// lists the expected maneuver kinds.
import Foundation
import Maps
import XCTest
@testable import Navigation

/// Routes from node `from` (standing on it, facing east) to `to` and returns the maneuver kinds.
func routeKinds(_ building: Building, from: String, to: String, options: NavigatorOptions = NavigatorOptions()) throws -> String {
    let nav = try Navigator(building: building, destinationId: to, options: options)
    let start = building.nodePosition(from)
    let floor = building.graph.nodes.first { $0.id == from }!.floorId
    _ = nav.update(NavigationInput(t: 0, positionInMap: start, floorId: floor, headingRad: 0, isLocalized: true))
    return kindsList(nav.lastManeuvers)
}

func assertTable(_ building: Building, _ rows: [(String, String, String)], options: NavigatorOptions = NavigatorOptions(),
                 file: StaticString = #filePath, line: UInt = #line) throws {
    for (from, to, expected) in rows {
        let got = try routeKinds(building, from: from, to: to, options: options)
        XCTAssertEqual(got, expected, "route \(from) -> \(to)", file: file, line: line)
    }
}

final class ManeuverTests: XCTestCase {
    func testTurnClassifierThresholdsAndSign() {
        XCTAssertNil(TurnClassifier.classify(signedAngleDeg: 0))
        XCTAssertNil(TurnClassifier.classify(signedAngleDeg: 19.9))
        XCTAssertNil(TurnClassifier.classify(signedAngleDeg: -19.9))
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: 20), .slightLeft)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: -30), .slightRight)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: 45), .turnLeft)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: -90), .turnRight)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: 134.9), .turnLeft)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: 135), .sharpLeft)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: -170), .sharpRight)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: 170.1), .uTurn)
        XCTAssertEqual(TurnClassifier.classify(signedAngleDeg: -180), .uTurn)
        // Positive = left: east then north is a left turn.
        let a = signedTurnAngleRad(from: Vec2(1, 0), to: Vec2(0, 1)) * 180 / .pi
        XCTAssertEqual(a, 90, accuracy: 1e-9)
    }

    func testTJunction() throws {
        let b = FloorPlanFixture(gridMeters: 2).floor("1", map: """
            a---b---c
                |
                d
            """).build()
        try assertTable(b, [
            ("a", "d", "depart,turnRight,arrive"),
            ("c", "d", "depart,turnLeft,arrive"),
            ("d", "a", "depart,turnLeft,arrive"),
            ("d", "c", "depart,turnRight,arrive"),
            ("a", "c", "depart,arrive"),
            ("c", "a", "depart,arrive"),
        ])
    }

    func testCrossing() throws {
        let b = FloorPlanFixture(gridMeters: 2).floor("1", map: """
                c
                |
            a---b---e
                |
                d
            """).build()
        try assertTable(b, [
            ("a", "c", "depart,turnLeft,arrive"),
            ("a", "d", "depart,turnRight,arrive"),
            ("a", "e", "depart,arrive"),
            ("c", "e", "depart,turnLeft,arrive"),
            ("c", "a", "depart,turnRight,arrive"),
            ("c", "d", "depart,arrive"),
            ("e", "d", "depart,turnLeft,arrive"),
        ])
    }

    func testOffsetCorridorShortJogIsOneSlightTurn() throws {
        let map = """
            a---b
                |
                c---d
            """
        // 0.5 m grid: a 1 m jog, collapsed into one slight turn toward the jog.
        let small = FloorPlanFixture(gridMeters: 0.5).floor("1", map: map).build()
        try assertTable(small, [("a", "d", "depart,slightRight,arrive"), ("d", "a", "depart,slightRight,arrive")])
        // 2 m grid: a 4 m offset is two real turns.
        let large = FloorPlanFixture(gridMeters: 2).floor("1", map: map).build()
        try assertTable(large, [("a", "d", "depart,turnRight,turnLeft,arrive"), ("d", "a", "depart,turnRight,turnLeft,arrive")])
    }

    func testASlightBendBesideAnOppositeTurnIsOneTurnByTheNetAngle() throws {
        // b: a 90-degree right (east to south); c, one grid row further: a bend left onto the diagonal c -> d
        // (1 east, 2 south: 26.6 deg left of south). Net 63.4 deg right.
        let map = """
            a---b
                |
                c

                 d
            """
        // 0.5 m grid: b and c are 1 m apart, one turn by the net angle at the larger turn's point (b), both
        // ways (d -> a: the bend right at c comes first, the left at b after it).
        let small = FloorPlanFixture(gridMeters: 0.5).floor("1", map: map).way("cd").build()
        try assertTable(small, [("a", "d", "depart,turnRight,arrive"), ("d", "a", "depart,turnLeft,arrive")])
        for (from, to, angle) in [("a", "d", -63.43), ("d", "a", 63.43)] {
            let route = try XCTUnwrap(try Navigator(building: small, destinationId: to)
                .routeFrom(small.nodePosition(from), floorId: "1"))
            let turn = route.maneuvers[1]
            XCTAssertEqual(turn.turnAngleDeg!, angle, accuracy: 0.01, "\(from) -> \(to)")
            XCTAssertEqual(turn.nodeId, "b", "\(from) -> \(to): the merged turn sits at the larger turn's control point")
        }
        // 1 m grid: 2 m apart, two maneuvers (the second chained to the first's cue).
        let large = FloorPlanFixture(gridMeters: 1).floor("1", map: map).way("cd").build()
        try assertTable(large, [("a", "d", "depart,turnRight,slightLeft,arrive"), ("d", "a", "depart,slightRight,turnLeft,arrive")])
    }

    func testSlightSharpAndUTurnFromDiagonalWays() throws {
        // b -> c goes 4 right, 2 down: -26.6 deg, slight right.
        let slight = FloorPlanFixture(gridMeters: 1).floor("1", map: """
            a---b

                    c
            """).way("bc").build()
        try assertTable(slight, [("a", "c", "depart,slightRight,arrive"), ("c", "a", "depart,slightLeft,arrive")])
        // b -> c goes 3 left, 1 up: +161.6 deg, sharp left.
        let sharp = FloorPlanFixture(gridMeters: 1).floor("1", map: """
             c
            a---b
            """).way("bc").build()
        try assertTable(sharp, [("a", "c", "depart,sharpLeft,arrive")])
        // b -> c goes 8 left, 1 up: +172.9 deg, U-turn.
        let uturn = FloorPlanFixture(gridMeters: 1).floor("1", map: """
            c
            a-------b
            """).way("bc").build()
        try assertTable(uturn, [("a", "c", "depart,uTurn,arrive")])
        let m = try XCTUnwrap(try Navigator(building: uturn, destinationId: "c").routeFrom(uturn.nodePosition("a"), floorId: "1"))
        XCTAssertEqual(m.maneuvers[1].turnAngleDeg!, 172.87, accuracy: 0.01)
    }

    func testDoorsAndDoorFoldedIntoArrival() throws {
        let map = """
            a---b--D--c
            """
        let plain = FloorPlanFixture(gridMeters: 1).floor("1", map: map).build()
        try assertTable(plain, [("a", "c", "depart,goThroughDoor,arrive"), ("c", "a", "depart,goThroughDoor,arrive")])
        let route = try XCTUnwrap(try Navigator(building: plain, destinationId: "c").routeFrom(plain.nodePosition("a"), floorId: "1"))
        let door = route.maneuvers[1]
        XCTAssertEqual(door.position.x, 7, accuracy: 1e-9, "the door maneuver sits at the drawn door")
        XCTAssertEqual(door.distanceFromStartMeters, 7, accuracy: 1e-9)
        // The same door on the last edge to a room behind a door: said on arrival instead.
        let room = FloorPlanFixture(gridMeters: 1).floor("1", map: map)
            .pointOfInterest(node: "c", id: "r312", name: "Room 312", behindDoor: true).build()
        try assertTable(room, [("a", "r312", "depart,arrive")])
    }

    func testElevatorAndStairsBetweenTwoFloors() throws {
        let b = FloorPlanFixture(gridMeters: 2)
            .floor("1", map: "S---a---E")
            .floor("2", map: "S---b---E")
            .build()
        // Stairs 5 + 4 x 4 m rise = 21 m beat the elevator's 20 + 4 = 24 m at equal walking.
        try assertTable(b, [("a", "b", "depart,takeStairs,continue,arrive")])
        var noStairs = NavigatorOptions()
        noStairs.avoidStairs = true
        try assertTable(b, [("a", "b", "depart,takeElevator,continue,arrive")], options: noStairs)
        let nav = try Navigator(building: b, destinationId: "b", options: noStairs)
        let r = try XCTUnwrap(nav.routeFrom(b.nodePosition("a"), floorId: "1"))
        XCTAssertEqual(r.maneuvers[1].toFloorId, "2")
        XCTAssertEqual(r.maneuvers[1].toFloorName, "Floor 2")
        XCTAssertEqual(r.nodeIds, ["a", "E1", "E2", "b"])
        XCTAssertEqual(r.lengthMeters, 16, accuracy: 1e-9, "rides count no horizontal length")
        var neither = noStairs
        neither.avoidElevators = true
        let blocked = try Navigator(building: b, destinationId: "b", options: neither)
        XCTAssertNil(blocked.routeFrom(b.nodePosition("a"), floorId: "1"))
        let blockedWalk = try Navigator(building: b, destinationId: "b", options: neither)
        var w = Walker(start: b.nodePosition("a"), floorId: "1")
        w.run(blockedWalk, [.wait(seconds: 12)])
        XCTAssertEqual(w.spoken, ["No route to b."], "said once, not on every update")
    }

    func testThreeFloorRideIsOneManeuverAndPaysOnePenalty() throws {
        let b = FloorPlanFixture(gridMeters: 2)
            .floor("1", map: "S---a---E")
            .floor("2", map: "S       E")
            .floor("3", map: "S---b---E")
            .build()
        // Two floors up (8 m rise): elevator 20 + 8 = 28 m, stairs 5 + 32 = 37 m, each paid once per ride
        // (per floor the stairs would win: 2 x 21 = 42 < 2 x 24 = 48).
        try assertTable(b, [("a", "b", "depart,takeElevator,continue,arrive")])
        let nav = try Navigator(building: b, destinationId: "b")
        let r = try XCTUnwrap(nav.routeFrom(b.nodePosition("a"), floorId: "1"))
        XCTAssertEqual(r.maneuvers[1].toFloorId, "3")
        XCTAssertEqual(r.nodeIds, ["a", "E1", "E2", "E3", "b"])
        XCTAssertEqual(r.costMeters, 8 + 28 + 8, accuracy: 1e-9)
        // One floor up: stairs 21 m beat the elevator's 24 m.
        let one = FloorPlanFixture(gridMeters: 2)
            .floor("1", map: "S---a---E")
            .floor("2", map: "S---b---E")
            .build()
        try assertTable(one, [("a", "b", "depart,takeStairs,continue,arrive")])
    }

    func testManeuverDistances() throws {
        let b = FloorPlanFixture(gridMeters: 2).floor("1", map: """
            a-----b
                  |
                  |
                  c-----d
            """).build()
        let r = try XCTUnwrap(try Navigator(building: b, destinationId: "d").routeFrom(b.nodePosition("a"), floorId: "1"))
        XCTAssertEqual(kindsList(r.maneuvers), "depart,turnRight,turnLeft,arrive")
        XCTAssertEqual(r.maneuvers.map(\.distanceFromStartMeters), [0, 12, 18, 30])
        XCTAssertEqual(r.maneuvers.map(\.distanceToNextMeters), [12, 6, 12, 0])
        XCTAssertEqual(r.maneuvers[1].nodeId, "b")
        XCTAssertEqual(r.maneuvers[1].turnAngleDeg!, -90, accuracy: 1e-9)
    }
}

extension Navigator {
    /// Test helper: the route this navigator would adopt from a position (one localized update).
    func routeFrom(_ p: Point2, floorId: String, headingRad: Double = 0) -> Route? {
        _ = update(NavigationInput(t: 0, positionInMap: p, floorId: floorId, headingRad: headingRad, isLocalized: true))
        return currentRoute
    }
}
