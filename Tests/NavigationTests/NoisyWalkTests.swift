// Whole routes walked with localizer noise (0.3 m per axis, 10 deg heading, seeded): the route must not
// flap, no false wrong-way or off-route correction may be raised, and the traveler must arrive.
import Foundation
import Maps
import XCTest
@testable import Navigation
import TestRandom

final class NoisyWalkTests: XCTestCase {
    private func walkNoisy(_ building: Building, from poi: String, to destination: String, seeds: ClosedRange<UInt64>,
                           file: StaticString = #filePath, line: UInt = #line) throws {
        let start = try XCTUnwrap(building.graph.nodes.first { $0.pointOfInterestId == poi }, file: file, line: line)
        for seed in seeds {
            let nav = try Navigator(building: building, destinationId: destination)
            var w = Walker(start: start.position, floorId: start.floorId)
            w.positionNoiseMeters = 0.3
            w.headingNoiseRad = 10 * .pi / 180
            w.rng = SplitMix64(seed: seed)
            w.run(nav, [.wait(seconds: 0.1)])
            let route = try XCTUnwrap(nav.currentRoute, file: file, line: line)
            w.run(nav, walkSteps(along: route) + [.wait(seconds: 2)])
            let what = "seed \(seed): \(w.spoken)"
            XCTAssertTrue(nav.hasArrived, what, file: file, line: line)
            XCTAssertEqual(nav.routeCount, 1, what, file: file, line: line)
            XCTAssertFalse(w.haptics.contains(.wrongWay), what, file: file, line: line)
            XCTAssertFalse(w.haptics.contains(.offRoute), what, file: file, line: line)
            XCTAssertEqual(w.haptics.last, .arrived, what, file: file, line: line)
            // Every ride is announced.
            for m in route.maneuvers where m.kind == .takeElevator || m.kind == .takeStairs {
                let text = try XCTUnwrap(m.announcedWithPrevious ? nav.narrative.then(m) : nav.narrative.cue(m, floorName: ""))
                XCTAssertTrue(w.spoken.contains(text), what, file: file, line: line)
            }
        }
    }

    func testBundledOfficeAcrossFloors() throws {
        try walkNoisy(try BundledMaps.office(), from: "room-101", to: "room-215", seeds: 1...6)
    }

    func testSkeriAcrossFloors() throws {
        try walkNoisy(try SkeriRouteTests.skeriBuilding(), from: "library-2f", to: "haptics-lab-4f", seeds: 1...6)
    }
}
