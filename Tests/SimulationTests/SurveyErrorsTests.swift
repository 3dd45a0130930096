import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// The survey's errors (SurveyErrors.swift): signs slid along their walls and resized against the map.
final class SurveyErrorsTests: XCTestCase {
    private var officeFloors: [String: Floor] {
        Dictionary(uniqueKeysWithValues: Fixtures.office.floors.map { ($0.id, $0) })
    }

    func testWithoutSurveyErrorsTheWorldIsTheMap() {
        var rng = SeededRandom(seed: 7, stream: RandomStream.survey.rawValue)
        let world = SurveyErrors(floors: officeFloors, parameters: SurveyParameters(), rng: &rng)
        XCTAssertEqual(world.floors, officeFloors)
        XCTAssertTrue(world.rangeFactors.isEmpty)
        XCTAssertEqual(world.rangeFactor(floorId: "1", signId: "anything"), 1)
    }

    /// Each sign slides along its wall (perpendicular to its facing; a projecting one along its facing) with the
    /// given spread, keeps its facing, kind and id, and is resized by its range factor's inverse. Over 40 draws of
    /// the office's signs the slide's standard deviation is 0.3 m within 10 % and the log size's 0.1 within 10 %
    /// (several hundred draws each).
    func testSignsSlideAlongTheirWallsAndResizeWithTheGivenSpreads() {
        var p = SurveyParameters()
        p.signAlongWallSigmaMeters = 0.3
        p.signSizeLogSigma = 0.1
        var slides: [Double] = [], logSizes: [Double] = []
        for seed: UInt64 in 1...40 {
            var rng = SeededRandom(seed: seed, stream: RandomStream.survey.rawValue)
            let world = SurveyErrors(floors: officeFloors, parameters: p, rng: &rng)
            for (floorId, floor) in officeFloors {
                let moved = world.floors[floorId]!.signs
                XCTAssertEqual(moved.count, floor.signs.count)
                for (a, b) in zip(floor.signs, moved) {
                    XCTAssertEqual(a.id, b.id)
                    XCTAssertEqual(a.kind, b.kind)
                    XCTAssertEqual(a.facing, b.facing)
                    let dx = b.position.x - a.position.x, dy = b.position.y - a.position.y
                    let n = hypot(a.facing.x, a.facing.y)
                    let along = (dx * a.facing.x + dy * a.facing.y) / n, across = (dx * -a.facing.y + dy * a.facing.x) / n
                    if a.placement == .projecting {
                        // Along the corridor it hangs across: along its facing.
                        XCTAssertEqual(across, 0, accuracy: 1e-9, "a projecting sign moved sideways")
                        slides.append(along)
                    } else {
                        XCTAssertEqual(along, 0, accuracy: 1e-9, "off its wall's line")
                        slides.append(across)
                    }
                    let k = b.heightMeters / a.heightMeters
                    XCTAssertEqual(b.widthMeters / a.widthMeters, k, accuracy: 1e-9)
                    XCTAssertEqual(world.rangeFactor(floorId: floorId, signId: a.id), 1 / k, accuracy: 1e-12)
                    logSizes.append(log(k))
                }
            }
        }
        XCTAssertGreaterThan(slides.count, 300)
        func sd(_ xs: [Double]) -> Double { (xs.map { $0 * $0 }.reduce(0, +) / Double(xs.count)).squareRoot() }
        XCTAssertEqual(sd(slides), 0.3, accuracy: 0.03)
        XCTAssertEqual(sd(logSizes), 0.1, accuracy: 0.01)
        XCTAssertEqual(slides.reduce(0, +) / Double(slides.count), 0, accuracy: 0.05)
    }

    /// The two faces of a sign hung across a corridor (two map signs at one position, facing opposite ways,
    /// `.projecting`) are one sign: they move together along the corridor and keep one size.
    func testTheFacesOfOneProjectingSignMoveTogether() {
        var east = Sign(id: "e", kind: "exit", position: Point2(5, 2), facing: Point2(1, 0), widthMeters: 0.3, heightMeters: 0.2)
        east.placement = .projecting
        var west = east
        west.id = "w"
        west.facing = Point2(-1, 0)
        let wall = Sign(id: "n", kind: "exit", position: Point2(9, 0), facing: Point2(0, 1), widthMeters: 0.3, heightMeters: 0.2)
        let floor = Floor(id: "1", name: "F1", elevationMeters: 0, walls: [], signs: [east, west, wall])
        var p = SurveyParameters()
        p.signAlongWallSigmaMeters = 0.5
        p.signSizeLogSigma = 0.2
        for seed: UInt64 in 1...10 {
            var rng = SeededRandom(seed: seed, stream: RandomStream.survey.rawValue)
            let moved = SurveyErrors(floors: ["1": floor], parameters: p, rng: &rng).floors["1"]!.signs
            XCTAssertEqual(moved[0].position, moved[1].position)
            XCTAssertEqual(moved[0].position.y, 2, accuracy: 1e-12, "along the corridor (x) only")
            XCTAssertEqual(moved[0].heightMeters, moved[1].heightMeters)
            XCTAssertEqual(moved[2].position.y, 0, accuracy: 1e-12, "the wall sign stays on its wall")
        }
    }

    /// In walks, the detector sees each sign where it truly hangs and reads its range with its size factor: over
    /// every sighting of 12 office walks, log(measured / true range) - log(factor) has median 0 within 0.015 and
    /// standard deviation 0.12 (the detector's own log-normal spread) within 0.015, while log(measured / true
    /// range) alone spreads by about sqrt(0.12^2 + 0.15^2) = 0.19 (above 0.16). The truth's ranges are to the
    /// moved signs. The frames are the standard walk's: the survey draws from its own stream.
    func testTheDetectorSeesTheSignsAsTheyTrulyAre() throws {
        var p = SimulationParameters.standard
        p.survey.signAlongWallSigmaMeters = 0.5
        p.survey.signSizeLogSigma = 0.15
        let routes = [("room-101", "room-109"), ("room-118", "room-107"), ("room-110", "room-102"), ("exit-main-entrance", "exit-rear")]
        var residuals: [Double] = [], raw: [Double] = []
        for (i, r) in routes.enumerated() {
            for seed: UInt64 in [1, 2, 3] {
                let scenario = Fixtures.scenario("survey", from: r.0, to: r.1, seed: seed * 10 + UInt64(i))
                let walk = try Fixtures.walk(scenario, parameters: p)
                var surveyRng = SeededRandom(seed: scenario.seed, stream: RandomStream.survey.rawValue)
                let world = SurveyErrors(floors: officeFloors, parameters: p.survey, rng: &surveyRng)
                for (o, t) in zip(walk.observations, walk.diagnostics.observationTruth) {
                    guard let id = t.signId, let trueRange = t.trueRangeMeters else { continue }
                    let frame = walk.truth.firstIndex { $0.t >= o.t } ?? 0
                    let floorId = walk.truth[frame].floorId
                    raw.append(log(o.rangeMeters / trueRange))
                    residuals.append(raw.last! - log(world.rangeFactor(floorId: floorId, signId: id)))
                }
                if seed == 1 && i == 0 {
                    let standard = try Fixtures.walk(scenario)
                    XCTAssertEqual(walk.frames, standard.frames)
                    XCTAssertEqual(walk.truth, standard.truth)
                }
            }
        }
        func sd(_ xs: [Double]) -> Double {
            let m = xs.reduce(0, +) / Double(xs.count)
            return (xs.map { ($0 - m) * ($0 - m) }.reduce(0, +) / Double(xs.count)).squareRoot()
        }
        XCTAssertGreaterThan(residuals.count, 500)
        XCTAssertEqual(Fixtures.median(residuals), 0, accuracy: 0.015)
        XCTAssertEqual(sd(residuals), 0.12, accuracy: 0.015)
        XCTAssertGreaterThan(sd(raw), 0.16)
    }

    /// ARKit's planes see the walls where they truly stand: with `wallOffsetSigmaMeters` 0.3 every anchor of
    /// the standard walk is reported again at the same times with the same extents, its centre moved along its
    /// normal (within ARKit's angle error) by one persistent distance per anchor (times the VIO scale), and those
    /// distances spread with a root mean square of 0.3 m within a third (a few dozen wall faces).
    func testPlanesSeeTheWallsWhereTheyTrulyStand() throws {
        var p = SimulationParameters.standard
        p.survey.wallOffsetSigmaMeters = 0.3
        var offsets: [Double] = []
        for seed: UInt64 in [3, 4, 5, 6] {
            let scenario = Fixtures.scenario("survey-walls", from: "room-101", to: "room-111", seed: seed)
            let standard = try Fixtures.walk(scenario), moved = try Fixtures.walk(scenario, parameters: p)
            XCTAssertEqual(standard.planes.count, moved.planes.count)
            XCTAssertEqual(standard.frames, moved.frames)
            let scale = moved.diagnostics.vio.scale
            var byAnchor: [String: Double] = [:]
            for (a, b) in zip(standard.planes, moved.planes) where a.event != .remove {
                XCTAssertEqual(a.anchorId, b.anchorId)
                XCTAssertEqual(a.t, b.t)
                XCTAssertEqual(a.widthMeters, b.widthMeters)
                let ca = try XCTUnwrap(a.centerInVIOPlane), cb = try XCTUnwrap(b.centerInVIOPlane)
                let yaw = try XCTUnwrap(a.normalYawInVIOPlaneRad)
                let de = cb.east - ca.east, dn = cb.north - ca.north
                let size = hypot(de, dn) / scale
                // Along the face's normal: the reported normal carries ARKit's angle error (a few degrees).
                if size > 1e-6 { XCTAssertLessThan(abs(de * -sin(yaw) + dn * cos(yaw)) / (size * scale), sin(radians(12))) }
                if let first = byAnchor[a.anchorId] {
                    XCTAssertEqual(size, first, accuracy: 1e-9, "one offset per wall face")
                } else {
                    byAnchor[a.anchorId] = size
                }
            }
            offsets += byAnchor.values
        }
        XCTAssertGreaterThan(offsets.count, 20)
        let sd = (offsets.map { $0 * $0 }.reduce(0, +) / Double(offsets.count)).squareRoot()
        XCTAssertEqual(sd, 0.3, accuracy: 0.1)
    }

    func testOutOfRangeSurveySettingsAreRejected() {
        var p = SimulationParameters.standard
        p.survey.signAlongWallSigmaMeters = -0.1
        XCTAssertThrowsError(try p.validate())
        p.survey.signAlongWallSigmaMeters = 0.3
        p.survey.signSizeLogSigma = .nan
        XCTAssertThrowsError(try p.validate())
    }
}
