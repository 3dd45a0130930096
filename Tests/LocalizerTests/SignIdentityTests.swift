import Foundation
import Maps
import XCTest

@testable import Localizer

/// Identifying signs (`Sign.text`, issue 16 section 3): a sighting that read a room-number placard's legend
/// is matched to that placard alone, one that did not read it to no surveyed placard, and a kind's own
/// recognition range keeps far placards out of the prediction.
final class SignIdentityTests: XCTestCase {
    /// A straight 20 m x 2.5 m corridor, mirror-symmetric: a placard on the south wall near each end ("101"
    /// west, "102" east), both facing north, and the placard kind read from 2.5 m and 50 degrees.
    static func corridor(maxRangeMeters: Double? = 2.5, maxViewAngleDeg: Double = 50) -> Building {
        let outline = [Point2(0, 0), Point2(20, 0), Point2(20, 2.5), Point2(0, 2.5)]
        let walls = outline.indices.map { Wall(from: outline[$0], to: outline[($0 + 1) % outline.count]) }
        func placard(_ text: String, _ x: Double) -> Sign {
            var s = Sign(id: "placard-\(text)", kind: "placard", position: Point2(x, 0.01), facing: Point2(0, 1),
                         widthMeters: 0.15, heightMeters: 0.15, mountingHeightMeters: 1.35)
            s.text = text
            return s
        }
        let nodes = stride(from: 1.0, to: 20.0, by: 2.0).enumerated().map {
            GraphNode(id: "n\($0.offset)", kind: .control, floorId: "1", position: Point2($0.element, 1.25))
        }
        let floor = Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: walls,
                          signs: [placard("101", 2), placard("102", 18)])
        return Building(id: "test-corridor", name: "Corridor", floors: [floor], graph: NavigationGraph(nodes: nodes, edges: []),
                        signKinds: [SignKindSpec(kind: "placard", heightMeters: 0.15, widthMeters: 0.15,
                                                 maxRangeMeters: maxRangeMeters, maxViewAngleDeg: maxViewAngleDeg)])
    }

    /// Weighted mean x of the particles after `frames` updates with `sightings`, standing still (VIO at rest).
    private func meanX(after sightings: [SignSighting], frames: Int = 8, building: Building = corridor()) throws -> Double {
        var o = LocalizerOptions()
        o.particleCount = 20000
        o.minParticles = 20000
        o.maxParticles = 20000
        let localizer = try ParticleLocalizer(building: building, options: o, seed: 5)
        try localizer.reset(prior: .floorOnly(floorId: "1"))
        for k in 0..<frames {
            let t = 0.1 * Double(k)
            localizer.predict(VIOSample(t: t, east: 0, north: 0, yawRad: 0, tracking: .normal))
            localizer.update(sightings: sightings, t: t)
        }
        XCTAssertNil(localizer.lastInputError)
        let particles = localizer.particleSnapshot(maxCount: 20000)
        let total = particles.reduce(0) { $0 + $1.weight }
        return particles.reduce(0) { $0 + $1.weight * $1.position.x } / total
    }

    func testAReadLegendPicksItsPlacardAndAnUnreadOneTellsNothing() throws {
        // Seen 1.7 m away, 0.3 rad to the right: from about (x - 1.2, 1.25) facing down the corridor's south wall.
        func sighting(_ text: String?) -> SignSighting {
            SignSighting(kind: "placard", rangeMeters: 1.7, bearingRad: -0.3, score: 0.95, text: text)
        }
        let east = try meanX(after: [sighting("102")])
        let west = try meanX(after: [sighting("101")])
        let unread = try meanX(after: [sighting(nil)])
        let none = try meanX(after: [])
        XCTAssertGreaterThan(east, 14, "placard 102 is at x = 18")
        XCTAssertLessThan(west, 6, "placard 101 is at x = 2")
        // Unread: no placard of the map lacks a surveyed legend, so the sighting is no evidence at all.
        XCTAssertEqual(unread, none, accuracy: 1e-9)
        XCTAssertEqual(none, 10, accuracy: 1.5, "the floor-only prior is spread along the corridor")
    }

    func testAPlacardIsNotPredictedBeyondItsKindsRange() throws {
        // Read 5 m away (seen 65 degrees off its normal: the view-angle limit is opened to 85 here so that only
        // the range limit is tested). With the kind's 2.5 m no particle predicts the placard there (5 m is
        // 4 range sigmas beyond it), so the sighting is clutter and the cloud stays spread; with no range of
        // its own (the options' 12 m) the cloud gathers 5 m from placard 102.
        let far = SignSighting(kind: "placard", rangeMeters: 5.0, bearingRad: -0.2, score: 0.95, text: "102")
        let limited = try meanX(after: [far], building: Self.corridor(maxRangeMeters: 2.5, maxViewAngleDeg: 85))
        let unlimited = try meanX(after: [far], building: Self.corridor(maxRangeMeters: nil, maxViewAngleDeg: 85))
        XCTAssertGreaterThan(unlimited, 13, "without the kind's range the 5 m sighting pulls the cloud east")
        XCTAssertEqual(limited, 10, accuracy: 1.5, "with it the cloud stays spread")
    }
}
