import Foundation
import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// The placard survey of the identifying-sign study (`PlacardSurvey`) and the simulator's text reading: the
/// surveyed map is valid, placards are sighted only within their kind's range and view angle, and the legends
/// read are right about as often as the model says (fixed seeds, stated tolerances).
final class PlacardSurveyTests: XCTestCase {
    func testSurveyedOfficeIsValidAndHasAPlacardBesideEveryRoom() throws {
        // The office without its own placards, as an importer leaves a building.
        var office = Fixtures.office
        for i in office.floors.indices { office.floors[i].signs.removeAll { $0.kind == PlacardSurvey.placardKind.kind } }
        let surveyed = PlacardSurvey.addingPlacards(to: office)
        XCTAssertNoThrow(try MapValidator.validate(surveyed))
        let rooms = office.floors.flatMap(\.pointsOfInterest).filter { !PlacardSurvey.categoriesWithoutPlacard.contains($0.category) }
        let placards = surveyed.floors.flatMap(\.signs).filter { $0.kind == PlacardSurvey.placardKind.kind }
        XCTAssertGreaterThan(rooms.count, 10)
        XCTAssertEqual(placards.count, rooms.count, "one per room-like place (each office room is beside a wall)")
        XCTAssertEqual(Set(placards.compactMap(\.text)), Set(rooms.map(\.id)))
        XCTAssertEqual(surveyed.signCatalogue.spec(kind: "placard"), PlacardSurvey.placardKind)
        XCTAssertEqual(surveyed.signCatalogue.spec(kind: "exit"), office.signCatalogue.spec(kind: "exit"))
        // The bundled office keeps its own placards (room numbers) and gets one only where a place has none.
        let bundled = PlacardSurvey.addingPlacards(to: Fixtures.office)
        let all = bundled.floors.flatMap(\.signs).filter { $0.kind == PlacardSurvey.placardKind.kind }
        XCTAssertEqual(all.count, rooms.count, "one per room-like place, the office's own included")
        XCTAssertTrue(all.contains { $0.text == "101" })
        XCTAssertFalse(all.contains { $0.text == "room-101" })
    }

    /// A corridor with two placards ("101" at x = 2, "102" at x = 18) on the south wall, facing north.
    private func corridorModel() -> SignObservationModel {
        let outline = [Point2(0, 0), Point2(20, 0), Point2(20, 2.5), Point2(0, 2.5)]
        let walls = outline.indices.map { Wall(from: outline[$0], to: outline[($0 + 1) % outline.count]) }
        func placard(_ text: String, _ x: Double) -> Sign {
            var s = Sign(id: "p\(text)", kind: "placard", position: Point2(x, 0.01), facing: Point2(0, 1), widthMeters: 0.15,
                         heightMeters: 0.15, mountingHeightMeters: PlacardSurvey.mountingHeightMeters)
            s.text = text
            return s
        }
        let floor = Floor(id: "1", name: "1", elevationMeters: 0, walls: walls, signs: [placard("101", 2), placard("102", 18)])
        return SignObservationModel(parameters: DetectorParameters(), floors: ["1": floor],
                                    geometry: ["1": FloorGeometry(walls: walls)],
                                    intrinsics: CameraIntrinsics(fx: 1602, fy: 1602, cx: 960, cy: 720, width: 1920, height: 1440),
                                    catalogue: SignCatalogue(kinds: [PlacardSurvey.placardKind]))
    }

    /// Sightings of the placards from a camera at (x, y), 1.4 m high, portrait, facing `yawRad`, over `frames`
    /// frames: (share of frames with a sighting of placard 101, share of those that read "101", read "102").
    private func reads(x: Double, y: Double, yawRad: Double, frames: Int = 3000) -> (seen: Double, right: Double, wrong: Double) {
        let model = corridorModel()
        var rng = SeededRandom(seed: 3, stream: 1), fp = SeededRandom(seed: 3, stream: 2), alike = SeededRandom(seed: 3, stream: 3)
        var log: [VisibleSign] = []
        var seen = 0, right = 0, wrong = 0
        for k in 0..<frames {
            let s = TrueCameraState(t: Double(k) * 0.1, floorId: "1", position: Point2Value(x: x, y: y), altitudeMeters: 1.4,
                                    heightAboveFloorMeters: 1.4, yawRad: yawRad, pitchRad: 0, rollRad: -.pi / 2,
                                    yawRateRadPerSecond: 0)
            for (o, t) in model.observe(frameIndex: k, state: s, rng: &rng, fpRng: &fp, lookAlikeRng: &alike, visibleLog: &log) where t.signId == "p101" {
                seen += 1
                if o.text == "101" { right += 1 } else if o.text == "102" { wrong += 1 }
            }
        }
        return (Double(seen) / Double(frames), Double(right) / Double(max(1, seen)), Double(wrong) / Double(max(1, seen)))
    }

    func testPlacardsAreReadOnlyCloseAndSquareOnAtTheModelsRates() {
        // 1.5 m away, square on: sighted (the detector curve shrunk to 2.5 m: 12 m's curve at 7.2 m) and read.
        let near = reads(x: 2, y: 1.5, yawRad: -.pi / 2)
        XCTAssertEqual(near.seen, DetectorParameters().detectionProbability(rangeMeters: 1.49 * 12 / 2.5), accuracy: 0.03)
        XCTAssertEqual(near.right, SignObservationModel.textReadProbability, accuracy: 0.03)
        XCTAssertEqual(near.wrong, SignObservationModel.textMisreadProbability, accuracy: 0.015)
        // 2.9 m away at 47 degrees (beyond the kind's 2.5 m) or 2.2 m at 55 degrees (beyond its 50): never sighted.
        XCTAssertEqual(reads(x: 4.1, y: 2.0, yawRad: atan2(-1.99, -2.1), frames: 500).seen, 0)
        XCTAssertEqual(reads(x: 3.8, y: 1.26, yawRad: atan2(-1.25, -1.8), frames: 500).seen, 0)
        // 45 degrees off at 2 m: still read.
        XCTAssertGreaterThan(reads(x: 3.4, y: 1.41, yawRad: atan2(-1.4, -1.4), frames: 500).seen, 0.5)
    }
}
