import Foundation
import Maps
import XCTest

@testable import Localizer

/// The C++ core's own reason for refusing a map or options reaches the Swift caller (issue 14: the bridge
/// used to drop it and say only "invalid map").
final class LocalizerBridgeErrorTests: XCTestCase {
    /// A 10 x 4 m room with one node; `extraWall` is added to the floor with id "ground".
    static func room(extraWall: Wall? = nil) -> Building {
        var walls = [Wall(from: Point2(0, 0), to: Point2(10, 0)), Wall(from: Point2(10, 0), to: Point2(10, 4)),
                     Wall(from: Point2(10, 4), to: Point2(0, 4)), Wall(from: Point2(0, 4), to: Point2(0, 0))]
        if let extraWall { walls.append(extraWall) }
        let floor = Floor(id: "ground", name: "Ground", elevationMeters: 0, walls: walls,
                          signs: [Sign(id: "s", kind: "exit", position: Point2(0, 2), facing: Point2(1, 0), widthMeters: 0.3, heightMeters: 0.2)])
        return Building(id: "room", name: "Room", floors: [floor],
                        graph: NavigationGraph(nodes: [GraphNode(id: "n", kind: .control, floorId: "ground", position: Point2(5, 2))], edges: []))
    }

    func testCoreReasonForAnOversizedFloorReachesTheCaller() throws {
        // Built in code past the validator (which refuses it first with the same limit).
        let b = Self.room(extraWall: Wall(from: Point2(-60_000, 0), to: Point2(60_000, 0)))
        XCTAssertThrowsError(try MapValidator.validate(b)) { XCTAssertTrue("\($0)".contains("at most 100000 m (100 km)"), "\($0)") }
        XCTAssertThrowsError(try ParticleLocalizer(building: b)) { e in
            guard case .invalidMap(let m)? = e as? LocalizerError else { return XCTFail("\(e)") }
            XCTAssertTrue(m.hasPrefix("building 'room': floor 0 (id \"ground\"): extent 120000.0 m x 4.0 m"), m)
            XCTAssertTrue(m.contains("is larger than 100 km"), m)
            XCTAssertFalse("\(e)".hasSuffix("invalid map"), "\(e)")
        }
    }

    func testValidatedFloorJustUnder100KilometersBuilds() throws {
        // 99.999 km wide: the validator accepts it, and so must the core (it used to add 2 m of padding on each
        // side before comparing, and refused it).
        let b = Self.room(extraWall: Wall(from: Point2(99_998, 0), to: Point2(99_999, 0)))
        XCTAssertNoThrow(try MapValidator.validate(b))
        var options = LocalizerOptions()
        options.particleCount = 500
        XCTAssertNoThrow(try ParticleLocalizer(building: b, options: options))
    }

    func testCoreReasonForBadOptionsReachesTheCaller() {
        var options = LocalizerOptions()
        options.minParticles = 5000
        options.maxParticles = 100
        XCTAssertThrowsError(try ParticleLocalizer(building: Self.room(), options: options)) { e in
            guard case .invalidArgument(let m)? = e as? LocalizerError else { return XCTFail("\(e)") }
            XCTAssertEqual(m, "building 'room': options: option min_particles is larger than max_particles")
        }
    }

    func testFloorNamingLeavesOtherMessagesAlone() {
        XCTAssertEqual(LocalizerBridge.namingFloors("floor 1: sign 3 has kind 9", floorIds: ["a", "b"]), "floor 1 (id \"b\"): sign 3 has kind 9")
        XCTAssertEqual(LocalizerBridge.namingFloors("floor 7: x", floorIds: ["a"]), "floor 7: x")
        XCTAssertEqual(LocalizerBridge.namingFloors("map has no floor", floorIds: ["a"]), "map has no floor")
    }
}
