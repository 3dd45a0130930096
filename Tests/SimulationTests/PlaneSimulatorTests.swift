import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// Simulated ARKit planes: valid records in the VIO frame that map back onto the walls through the walk's own
/// VIO transform, lag and growing extents, textureless walls missed, false planes, seeds, bundle round trip.
final class PlaneSimulatorTests: XCTestCase {
    private func walk(seed: UInt64 = 3, parameters: SimulationParameters = .standard, resetAt: Double? = nil) throws -> SimulatedWalk {
        var s = Fixtures.scenario("planes", from: "room-101", to: "room-111", seed: seed)
        s.vioResetAt = resetAt
        return try Fixtures.walk(s, parameters: parameters)
    }

    /// Map position of a plane record's center, through the VIO transform of the frame at its time.
    private func mapCenter(_ r: PlaneRecord, in w: SimulatedWalk) -> (x: Double, y: Double, floor: String)? {
        guard let k = w.frames.firstIndex(where: { abs($0.t - r.t) < 1e-9 }), let c = r.centerInVIOPlane else { return nil }
        let m = w.frames[k].cameraToWorld
        let theta = w.diagnostics.mapToVIOYawRad[k], s = w.diagnostics.vio.scale
        let de = (c.east - m[12]) / s, dn = (c.north - -m[14]) / s
        // Inverse rotation by theta.
        let dx = cos(theta) * de + sin(theta) * dn, dy = -sin(theta) * de + cos(theta) * dn
        return (w.truth[k].x + dx, w.truth[k].y + dy, w.truth[k].floorId)
    }

    private func distanceToWall(_ x: Double, _ y: Double, floor: String) -> Double {
        let f = Fixtures.office.floor(id: floor)!
        return FloorGeometry(walls: f.walls).clearance(at: Point2(x: x, y: y), maxMeters: 5)
    }

    func testPlanesAreValidAndLieOnTheWallsInTheVIOFrame() throws {
        let w = try walk()
        XCTAssertGreaterThan(w.planes.count, 20)
        for r in w.planes { XCTAssertNil(r.validationProblem(), "\(r)") }
        let placed = w.planes.filter { $0.event != .remove }
        var near = 0
        for r in placed {
            let c = try XCTUnwrap(mapCenter(r, in: w))
            if distanceToWall(c.x, c.y, floor: c.floor) < 0.2 { near += 1 }
        }
        // Most planes are walls (a few are furniture or open doors, the rest within the pose noise).
        XCTAssertGreaterThan(Double(near) / Double(placed.count), 0.8)
        // Each anchor is added once, before its updates.
        var seen = Set<String>()
        for r in w.planes {
            if r.event == .add { XCTAssertTrue(seen.insert(r.anchorId).inserted, "added twice: \(r.anchorId)") }
            else { XCTAssertTrue(seen.contains(r.anchorId), "update before add: \(r.anchorId)") }
        }
        XCTAssertTrue(w.planes.contains { $0.event == .update })
    }

    func testExtentsStartSmallAndGrowWithObservation() throws {
        let w = try walk()
        var byAnchor: [String: [Double]] = [:]
        for r in w.planes where r.event != .remove { byAnchor[r.anchorId, default: []].append(r.widthMeters!) }
        let firsts = byAnchor.values.map { $0[0] }
        XCTAssertLessThanOrEqual(firsts.max()!, 0.8 * 1.06)
        let grown = byAnchor.values.filter { $0.count >= 3 }.filter { $0.last! > $0.first! + 0.5 }
        XCTAssertGreaterThan(grown.count, 2)
    }

    func testLagDelaysTheFirstAnchor() throws {
        var p = SimulationParameters()
        p.planes.lagSecondsRange = 3.0...3.0
        p.planes.furniturePlanesPerMeter = 0
        let slow = try walk(parameters: p)
        p.planes.lagSecondsRange = 0.2...0.2
        let fast = try walk(parameters: p)
        XCTAssertGreaterThan(slow.planes.first!.t, fast.planes.first!.t + 2.0)
    }

    func testTexturelessWallsAreMissedAndFalsePlanesRemain() throws {
        var p = SimulationParameters()
        p.planes.texturelessWallProbability = 1
        p.planes.openDoorProbability = 0
        p.planes.furniturePlanesPerMeter = 0
        XCTAssertTrue(try walk(parameters: p).planes.isEmpty)
        p.planes.furniturePlanesPerMeter = 0.5
        let furniture = try walk(parameters: p)
        XCTAssertFalse(furniture.planes.isEmpty)
        for r in furniture.planes where r.event != .remove {
            let c = try XCTUnwrap(mapCenter(r, in: furniture))
            XCTAssertGreaterThan(distanceToWall(c.x, c.y, floor: c.floor), 0.25, "furniture stands in open space")
        }
        p.planes.enabled = false
        XCTAssertTrue(try walk(parameters: p).planes.isEmpty)
    }

    func testSeededAndIndependentOfTheOtherStreams() throws {
        let a = try walk(seed: 5), b = try WalkSimulator.simulate(building: Fixtures.office,
                                                                   scenario: Fixtures.scenario("planes", from: "room-101", to: "room-111", seed: 5))
        XCTAssertEqual(a.planes, b.planes)
        XCTAssertNotEqual(a.planes, try walk(seed: 6).planes)
        var p = SimulationParameters()
        p.planes.enabled = false
        let off = try walk(seed: 5, parameters: p)
        XCTAssertEqual(off.frames, a.frames, "planes draw from their own stream")
        XCTAssertEqual(off.observations, a.observations)
    }

    func testVIOResetRemovesEveryAnchor() throws {
        let w = try walk(resetAt: 12)
        let removes = w.planes.filter { $0.event == .remove }
        let before = Set(w.planes.filter { $0.t < 12 && $0.event == .add }.map(\.anchorId))
        XCTAssertFalse(before.isEmpty)
        XCTAssertEqual(Set(removes.map(\.anchorId)), before)
        XCTAssertTrue(removes.allSatisfy { $0.t >= 12 && $0.t < 12.1 })
        XCTAssertFalse(w.planes.contains { $0.event == .update && before.contains($0.anchorId) && $0.t >= 12 })
    }

    func testWrittenBundleReadsBackWithItsPlanes() throws {
        let w = try walk()
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-sim-planes-\(UUID().uuidString)")
        defer { try? FileManager.default.removeItem(at: dir) }
        try w.write(to: dir)
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.planes.count, w.planes.count)
        XCTAssertTrue(b.warnings.filter { $0.kind == .ignoredPlanes }.isEmpty, "\(b.warnings)")
    }

    func testCollinearTouchingSegmentsMergeIntoOneFace() {
        let m = PlaneSimulator.merge((Point2(x: 0, y: 0), Point2(x: 2, y: 0)), (Point2(x: 2, y: 0.01), Point2(x: 5, y: 0)),
                                     angleTolerance: radians(3))
        XCTAssertEqual(m?.a.x ?? 9, 0, accuracy: 1e-9)
        XCTAssertEqual(m?.b.x ?? 0, 5, accuracy: 1e-9)
        XCTAssertNil(PlaneSimulator.merge((Point2(x: 0, y: 0), Point2(x: 2, y: 0)), (Point2(x: 3, y: 0), Point2(x: 5, y: 0)),
                                          angleTolerance: radians(3)), "a 1 m gap (a door) keeps two faces")
        XCTAssertNil(PlaneSimulator.merge((Point2(x: 0, y: 0), Point2(x: 2, y: 0)), (Point2(x: 2, y: 0), Point2(x: 2, y: 3)),
                                          angleTolerance: radians(3)), "a corner keeps two faces")
    }
}
