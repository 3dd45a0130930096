import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// Ground truth: routes, speeds, walls, wrong turns, floor changes.
final class WalkerTests: XCTestCase {
    /// Independent brute-force wall check (no grid).
    private func crossesAnyWall(_ a: Point2, _ b: Point2, floor: Floor) -> Bool {
        floor.crossesWall(from: a, to: b)
    }

    private let wallScenarios: [SimulationScenario] = [
        SimulationScenario(name: "a", from: "room-101", to: "room-111", seed: 1),
        SimulationScenario(name: "b", from: "room-118", to: "room-107", seed: 2, carry: .lanyard),
        SimulationScenario(name: "c", from: "kitchen-1f", to: "restroom-1f-men", seed: 3, wrongTurn: true),
        SimulationScenario(name: "d", from: "room-105", to: "room-214", seed: 4),
        SimulationScenario(name: "e", from: "room-116", to: "room-103", seed: 5, wrongTurn: true),
        SimulationScenario(name: "f", from: "exit-main-entrance", to: "exit-rear", seed: 6, orientation: .landscape),
    ]

    func testNoTruthStepCrossesAWall() throws {
        let floors = Dictionary(uniqueKeysWithValues: Fixtures.office.floors.map { ($0.id, $0) })
        var steps = 0
        for s in wallScenarios {
            for seed in [s.seed, s.seed + 100] {
                var sc = s; sc.seed = seed
                let w = try Fixtures.walk(sc)
                for k in 1..<w.truth.count where w.truth[k].floorId == w.truth[k - 1].floorId {
                    let a = Point2(w.truth[k - 1].x, w.truth[k - 1].y), b = Point2(w.truth[k].x, w.truth[k].y)
                    if a == b { continue }
                    steps += 1
                    XCTAssertFalse(crossesAnyWall(a, b, floor: floors[w.truth[k].floorId]!),
                                   "\(sc.name) seed \(seed): step at t=\(w.truth[k].t) crosses a wall")
                }
            }
        }
        XCTAssertGreaterThan(steps, 10_000)
    }

    func testWalkerKeepsClearOfWallsWhileOffTheCentreLine() throws {
        // Off the graph (more than 2 cm from it) the camera keeps 0.25 m from every wall.
        let w = try Fixtures.walk(SimulationScenario(name: "clear", from: "room-118", to: "room-107", seed: 11))
        let geo = FloorGeometry(walls: Fixtures.office.floor(id: "1")!.walls)
        let minClear = w.truth.map { geo.clearance(at: Point2($0.x, $0.y)) }.min()!
        // Doors are 0.9 m wide or more: the centre of a door gap is >= 0.45 m from its jambs; corridors are wider.
        XCTAssertGreaterThan(minClear, 0.2)
    }

    func testSegmentIntersectionPrimitive() {
        // The crossing rule is the map's (Geometry.segmentsIntersect, tested in MapsTests); the grid finds the walls.
        let g = FloorGeometry(walls: [Wall(from: Point2(5, -10), to: Point2(5, 10))])
        XCTAssertTrue(g.segmentCrossesWall(Point2(5, 10), Point2(6, 11)), "touching an end counts")
        XCTAssertTrue(g.segmentCrossesWall(Point2(0, 0), Point2(10, 1)))
        XCTAssertFalse(g.segmentCrossesWall(Point2(0, 0), Point2(4.9, 1)))
        XCTAssertEqual(g.clearance(at: Point2(4, 0)), 1, accuracy: 1e-12)
        XCTAssertEqual(g.firstHit(from: Point2(0, 0), dx: 1, dy: 0.5, maxT: 100)?.t ?? -1, 5, accuracy: 1e-9)
        XCTAssertNil(g.firstHit(from: Point2(0, 0), dx: -1, dy: 0, maxT: 100))
    }

    func testCruiseSpeedStaysWithinBoundsAndMeanSpeedIsHuman() throws {
        var cruising: [Double] = []
        for seed: UInt64 in 1...6 {
            let w = try Fixtures.walk(SimulationScenario(name: "speed", from: "room-101", to: "room-109", seed: seed))
            let d = w.diagnostics
            for (ph, v) in zip(d.phases, d.speedsMetersPerSecond) where ph == .cruising { cruising.append(v) }
            // Whole-walk speed from truth positions while walking (not standing, paused, turning or changing floor).
            var dist = 0.0, time = 0.0
            for k in 1..<w.truth.count where d.phases[k] == .cruising || d.phases[k] == .changingSpeed {
                dist += hypot(w.truth[k].x - w.truth[k - 1].x, w.truth[k].y - w.truth[k - 1].y)
                time += w.truth[k].t - w.truth[k - 1].t
            }
            XCTAssertGreaterThan(dist / time, 0.7, "seed \(seed)")
            XCTAssertLessThan(dist / time, 1.4, "seed \(seed)")
        }
        XCTAssertGreaterThan(cruising.count, 3000)
        XCTAssertGreaterThanOrEqual(cruising.min()!, 0.8 - 1e-9)
        XCTAssertLessThanOrEqual(cruising.max()!, 1.4 + 1e-9)
        let m = Fixtures.median(cruising)
        XCTAssertGreaterThan(m, 0.9); XCTAssertLessThan(m, 1.3)
    }

    func testWalkStartsAtStartEndsAtDestinationAndPauses() throws {
        let w = try Fixtures.walk(SimulationScenario(name: "ends", from: "room-101", to: "room-111", seed: 1))
        let start = Fixtures.office.pointOfInterest(id: "room-101")!.position, end = Fixtures.office.pointOfInterest(id: "room-111")!.position
        XCTAssertEqual(w.truth.first!.x, start.x, accuracy: 1e-9); XCTAssertEqual(w.truth.first!.y, start.y, accuracy: 1e-9)
        XCTAssertEqual(hypot(w.truth.last!.x - end.x, w.truth.last!.y - end.y), 0, accuracy: 0.05)
        XCTAssertEqual(w.diagnostics.routeNodeIds.first, "room-101"); XCTAssertEqual(w.diagnostics.routeNodeIds.last, "room-111")
        // Time stamps are exact multiples of the frame period.
        for (k, f) in w.frames.enumerated() { XCTAssertEqual(f.t, Double(k) / 30, accuracy: 1e-9) }
    }

    func testRouteIsShortestByDijkstra() throws {
        let planner = RoutePlanner(building: Fixtures.office)
        let a = try planner.resolve("room-101"), b = try planner.resolve("Room 106")
        let path = planner.shortestPath(from: a.nodeIndex, to: b.nodeIndex)!
        let ids = path.map { Fixtures.office.graph.nodes[$0].id }
        XCTAssertEqual(ids.first, "room-101"); XCTAssertEqual(ids.last, "room-106")
        // Straight along the south corridor: every intermediate node has y = 7.
        for id in ids.dropFirst().dropLast() { XCTAssertEqual(Fixtures.office.node(id: id)!.position.y, 7, "\(id)") }
    }

    func testWrongTurnLeavesTheRouteAndComesBack() throws {
        let s = SimulationScenario(name: "wrong", from: "room-116", to: "room-103", seed: 5, wrongTurn: true)
        let w = try Fixtures.walk(s)
        let plain = try Fixtures.walk(SimulationScenario(name: "plain", from: "room-116", to: "room-103", seed: 5))
        XCTAssertNotNil(w.diagnostics.wrongTurnAtNodeId)
        // Distance of each truth point from the route polyline: the detour goes >= 2 m off it.
        let nodes = w.diagnostics.routeNodeIds.map { Fixtures.office.node(id: $0)!.position }
        func offRoute(_ p: Point2) -> Double {
            (1..<nodes.count).map { FloorGeometry.distance(p, nodes[$0 - 1], nodes[$0]) }.min()!
        }
        let maxOff = w.truth.map { offRoute(Point2($0.x, $0.y)) }.max()!
        XCTAssertGreaterThan(maxOff, 2.0)
        XCTAssertLessThan(plain.truth.map { offRoute(Point2($0.x, $0.y)) }.max()!, 1.0)
        XCTAssertTrue(w.diagnostics.phases.contains(.turning), "turns around in place")
        XCTAssertGreaterThan(w.truth.last!.t, plain.truth.last!.t + 4)
        let end = Fixtures.office.pointOfInterest(id: "room-103")!.position
        XCTAssertEqual(hypot(w.truth.last!.x - end.x, w.truth.last!.y - end.y), 0, accuracy: 0.05)
    }

    func testFloorChangeByElevatorOrStairs() throws {
        let w = try Fixtures.walk(SimulationScenario(name: "floors", from: "room-105", to: "room-214", seed: 4))
        XCTAssertEqual(w.truth.first!.floorId, "1"); XCTAssertEqual(w.truth.last!.floorId, "2")
        XCTAssertTrue(w.diagnostics.phases.contains(.changingFloor))
        let switches = zip(w.truth, w.truth.dropFirst()).filter { $0.floorId != $1.floorId }.count
        XCTAssertEqual(switches, 1)
    }

    func testUnknownPlaceAndBadSettingsAreClearErrors() {
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office,
                                                        scenario: SimulationScenario(name: "x", from: "nowhere", to: "room-101", seed: 1))) {
            XCTAssertEqual($0 as? SimulationError, .unknownPlace("nowhere"))
        }
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office,
                                                        scenario: SimulationScenario(name: "x", from: "room-101", to: "room-102", seed: 1, rateHz: 0))) {
            guard case .invalidScenario(let m)? = $0 as? SimulationError else { return XCTFail("\($0)") }
            XCTAssertTrue(m.contains("rateHz"))
        }
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office,
                                                        scenario: SimulationScenario(name: "x", from: "room-101", to: "room-101", seed: 1)))
        var p = SimulationParameters(); p.walker.maxTurnRateRadPerSecond = 0
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office, scenario: Fixtures.scenario(), parameters: p)) {
            XCTAssertTrue("\($0)".contains("maxTurnRateRadPerSecond"))
        }
        for bias in [-1.0, .nan] {
            var b = SimulationParameters(); b.detector.rangeBias = bias
            XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office, scenario: Fixtures.scenario(), parameters: b)) {
                XCTAssertTrue("\($0)".contains("rangeBias"), "\($0)")
            }
        }
    }

    func testRouteThroughAWallIsRefused() throws {
        // A map whose graph edge crosses a wall: the simulator refuses rather than walk through it.
        var b = Fixtures.office
        b.floors[0].walls.append(Wall(from: Point2(10, 6.2), to: Point2(10, 7.8)))   // across the south corridor
        XCTAssertThrowsError(try WalkSimulator.simulate(building: b, scenario: SimulationScenario(
            name: "wall", from: "room-101", to: "room-106", seed: 1))) {
            guard case .routeCrossesWall(let m)? = $0 as? SimulationError else { return XCTFail("\($0)") }
            XCTAssertTrue(m.contains("floor 1"))
        }
    }
    // MARK: - Corner cutting

    /// For each corner of the walk's route (a direction change of 30 to 150 degrees at an interior node):
    /// the truth's closest approach to the node and the corridor width there (twice the node's distance to
    /// the nearest wall), meters.
    private func cornerPasses(_ w: SimulatedWalk, building: Building) -> [(node: String, passMeters: Double, widthMeters: Double)] {
        let ids = w.diagnostics.routeNodeIds
        var out: [(node: String, passMeters: Double, widthMeters: Double)] = []
        for i in ids.indices.dropFirst().dropLast() {
            guard let a = building.node(id: ids[i - 1]), let v = building.node(id: ids[i]), let b = building.node(id: ids[i + 1]),
                  a.floorId == v.floorId, b.floorId == v.floorId else { continue }
            let turn = abs(atan2(sin(atan2(b.position.y - v.position.y, b.position.x - v.position.x) - atan2(v.position.y - a.position.y, v.position.x - a.position.x)),
                                 cos(atan2(b.position.y - v.position.y, b.position.x - v.position.x) - atan2(v.position.y - a.position.y, v.position.x - a.position.x)))) * 180 / .pi
            guard turn > 30, turn < 150 else { continue }
            let pass = w.truth.filter { $0.floorId == v.floorId }.map { hypot($0.x - v.position.x, $0.y - v.position.y) }.min() ?? .infinity
            let geo = FloorGeometry(walls: building.floor(id: v.floorId)!.walls)
            out.append((v.id, pass, 2 * geo.clearance(at: v.position, maxMeters: 10)))
        }
        return out
    }

    private let cornerScenarios: [SimulationScenario] = [
        SimulationScenario(name: "k1", from: "room-101", to: "room-111", seed: 1),
        SimulationScenario(name: "k2", from: "room-118", to: "room-107", seed: 2),
        SimulationScenario(name: "k3", from: "exit-main-entrance", to: "exit-rear", seed: 3),
        SimulationScenario(name: "k4", from: "room-116", to: "room-103", seed: 4),
        SimulationScenario(name: "k5", from: "room-105", to: "room-214", seed: 5),
    ]

    func testWalkerCutsCornersUpToTheCorridorWidth() throws {
        var passes: [Double] = []
        for s in cornerScenarios {
            for seed in [s.seed, s.seed + 50, s.seed + 100] {
                var sc = s; sc.seed = seed
                for c in cornerPasses(try Fixtures.walk(sc), building: Fixtures.office) {
                    passes.append(c.passMeters)
                    // The cut stays within the corridor (plus the walker's sway and wander).
                    XCTAssertLessThanOrEqual(c.passMeters, c.widthMeters + 0.35, "\(sc.name) seed \(seed) at \(c.node)")
                }
            }
        }
        XCTAssertGreaterThan(passes.count, 20)
        // People cut corners: some pass a meter or more from the corner's node (a 2 m corridor's inner
        // corner, less the wall clearance, is 1.16 m away); the old walker's round corners stayed within
        // 0.42 m plus its wander.
        XCTAssertGreaterThan(passes.max()!, 0.95, "\(passes.sorted())")
        XCTAssertGreaterThanOrEqual(passes.filter { $0 > 0.8 }.count, 3, "\(passes.sorted())")
    }

    func testCornerCuttingIsParameterisedAndSeeded() throws {
        var tight = SimulationParameters()
        tight.walker.cornerCutRangeMeters = 0.3...0.3
        tight.walker.cornerCutStraightnessRange = 0...0
        tight.walker.cornerWidenProbability = 0
        var maxPass = 0.0
        for s in cornerScenarios {
            for c in cornerPasses(try WalkSimulator.simulate(building: Fixtures.office, scenario: s, parameters: tight), building: Fixtures.office) {
                maxPass = max(maxPass, c.passMeters)
            }
        }
        // A 0.3 m round cut passes 0.11 m inside a right-angled corner; the rest is sway and wander.
        XCTAssertLessThan(maxPass, 0.6)
        // The same scenario and seed give the same walk.
        let a = try WalkSimulator.simulate(building: Fixtures.office, scenario: cornerScenarios[1])
        let b = try WalkSimulator.simulate(building: Fixtures.office, scenario: cornerScenarios[1])
        XCTAssertEqual(a.truth, b.truth)
        var bad = SimulationParameters()
        bad.walker.cornerCutStraightnessRange = 0...2
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office, scenario: cornerScenarios[0], parameters: bad)) {
            XCTAssertTrue("\($0)".contains("cornerCutStraightnessRange"), "\($0)")
        }
    }

    func testCutCornersNeverCrossAWallOnTheSkeriFloors() throws {
        let shared = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent()
            .deletingLastPathComponent().appendingPathComponent("../shared/data").standardizedFileURL
        guard FileManager.default.fileExists(atPath: shared.appendingPathComponent("skeri_inavigate").path) else {
            throw XCTSkip("../shared/data/skeri_inavigate is not present")
        }
        let skeri = try ScenarioMaps.load("skeri", sharedData: shared)
        let floors = Dictionary(uniqueKeysWithValues: skeri.floors.map { ($0.id, $0) })
        let walks = [("brandons-office-4f", "jamess-office-4f"), ("node-65", "node-45"), ("node-19", "node-1"),
                     ("node-39", "node-33"), ("node-30", "node-25"), ("node-22", "node-3")]
        var steps = 0
        var widest = 0.0
        for (k, (from, to)) in walks.enumerated() {
            for seed: UInt64 in [UInt64(300 + k), UInt64(400 + k)] {
                let w = try WalkSimulator.simulate(building: skeri, scenario: SimulationScenario(
                    name: "skeri-walls", map: "skeri", from: from, to: to, seed: seed, rateHz: 10))
                for i in 1..<w.truth.count where w.truth[i].floorId == w.truth[i - 1].floorId {
                    let a = Point2(w.truth[i - 1].x, w.truth[i - 1].y), b = Point2(w.truth[i].x, w.truth[i].y)
                    if a == b { continue }
                    steps += 1
                    XCTAssertFalse(crossesAnyWall(a, b, floor: floors[w.truth[i].floorId]!),
                                   "\(from) -> \(to) seed \(seed): step at t=\(w.truth[i].t) crosses a wall")
                }
                widest = max(widest, cornerPasses(w, building: skeri).map(\.passMeters).max() ?? 0)
            }
        }
        XCTAssertGreaterThan(steps, 3000)
        XCTAssertGreaterThan(widest, 0.8, "corners are cut on SKERI too")
    }
}
