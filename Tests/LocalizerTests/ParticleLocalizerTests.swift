import Foundation
import Maps
import XCTest

@testable import Localizer
import TestRandom

/// Tests of the Swift wrapper over the C++ particle filter: a small L-shaped building made in code, a
/// synthetic walk with known truth (fixed seeds), and errors for bad input.
final class ParticleLocalizerTests: XCTestCase {
    /// L-shaped corridor: 30 m east-west (2.5 m wide) meeting a 25 m north-south corridor at its east end;
    /// exit signs placed asymmetrically; graph nodes along both corridors; an elevator node.
    static func lBuilding() -> Building {
        let outline: [Point2] = [Point2(0, 0), Point2(30, 0), Point2(30, 25), Point2(27.5, 25), Point2(27.5, 2.5),
                                 Point2(0, 2.5)]
        let walls = outline.indices.map { Wall(from: outline[$0], to: outline[($0 + 1) % outline.count]) }
        func exit(_ id: String, _ x: Double, _ y: Double, _ fx: Double, _ fy: Double) -> Sign {
            Sign(id: id, kind: "exit", position: Point2(x, y), facing: Point2(fx, fy), widthMeters: 0.3, heightMeters: 0.2)
        }
        let signs = [exit("w", 0, 1.25, 1, 0), exit("n1", 12, 2.5, 0, -1), exit("s1", 20, 0, 0, 1),
                     exit("e2", 30, 12, -1, 0), exit("top", 28.75, 25, 0, -1), exit("w2", 27.5, 18, 1, 0)]
        var nodes: [GraphNode] = []
        for (i, x) in stride(from: 1.0, to: 29.0, by: 3.0).enumerated() {
            nodes.append(GraphNode(id: "h\(i)", kind: .control, floorId: "1", position: Point2(x, 1.25)))
        }
        for (i, y) in stride(from: 4.0, to: 25.0, by: 3.0).enumerated() {
            nodes.append(GraphNode(id: "v\(i)", kind: .control, floorId: "1", position: Point2(28.75, y)))
        }
        nodes.append(GraphNode(id: "lift", kind: .verticalLink, floorId: "1", position: Point2(28.75, 23),
                               verticalLink: .elevator))
        let floor = Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: walls, signs: signs)
        return Building(id: "test-l", name: "Test L", floors: [floor], graph: NavigationGraph(nodes: nodes, edges: []))
    }

    struct Frame {
        var vio: VIOSample
        var sightings: [SignSighting]
        var truth: Point2
        var heading: Double
    }

    static func wrap(_ a: Double) -> Double { atan2(sin(a), cos(a)) }

    /// Walks the waypoints at 1.2 m/s, 10 Hz, turning in place at 1.5 rad/s; VIO frame rotated by 0.7 rad
    /// and offset from the map; exit sightings with 8 % range noise and 2 deg bearing noise (90 % detected)
    /// for signs in a 38 deg field of view, within 10 m, facing the camera (walls ignored: the corridors'
    /// signs are all in line of sight where they face the walker).
    static func walk(_ building: Building, _ waypoints: [Point2], seed: UInt64 = 3) -> [Frame] {
        var rng = SplitMix64(seed: seed)
        let vioYaw = 0.7
        var frames: [Frame] = []
        var p = waypoints[0], h = 0.0, t = 0.0
        func emit() {
            let c = cos(-vioYaw), s = sin(-vioYaw)
            let vio = VIOSample(t: t, east: c * (p.x + 3) - s * (p.y - 5), north: s * (p.x + 3) + c * (p.y - 5),
                                yawRad: wrap(h - vioYaw), tracking: .normal)
            var sightings: [SignSighting] = []
            for sign in building.floors[0].signs {
                let dx = sign.position.x - p.x, dy = sign.position.y - p.y
                let r = (dx * dx + dy * dy).squareRoot()
                let b = wrap(atan2(dy, dx) - h)
                let facingCamera = sign.facing.x * (p.x - sign.position.x) + sign.facing.y * (p.y - sign.position.y) > 0
                guard r > 0.5, r < 10, abs(b) < 0.33, facingCamera, rng.unit() < 0.9 else { continue }
                sightings.append(SignSighting(kind: "exit", rangeMeters: r * (1 + 0.08 * rng.normal()),
                                              bearingRad: b + 0.035 * rng.normal(), score: 0.95))
            }
            frames.append(Frame(vio: vio, sightings: sightings, truth: p, heading: h))
            t += 0.1
        }
        emit()
        for target in waypoints.dropFirst() {
            let goal = atan2(target.y - p.y, target.x - p.x)
            while abs(wrap(goal - h)) > 0.15 {
                h = wrap(h + (wrap(goal - h) > 0 ? 0.15 : -0.15))
                emit()
            }
            h = goal
            let start = p
            let length = ((target.x - p.x) * (target.x - p.x) + (target.y - p.y) * (target.y - p.y)).squareRoot()
            let steps = max(1, Int((length / 0.12).rounded(.up)))
            for i in 1...steps {
                let f = Double(i) / Double(steps)
                p = Point2(start.x + (target.x - start.x) * f, start.y + (target.y - start.y) * f)
                emit()
            }
        }
        return frames
    }

    func smallOptions() -> LocalizerOptions {
        var o = LocalizerOptions()
        o.particleCount = 8000
        o.minParticles = 2000
        o.maxParticles = 30000
        // The synthetic walks (`walk`) see a sign from anywhere in front of its face; so must the filter.
        o.maxViewAngleFromNormalRad = Double.pi / 2
        return o
    }

    func testDefaultsComeFromTheCore() {
        let o = LocalizerOptions()
        XCTAssertEqual(o.particleCount, 20_000)
        XCTAssertEqual(o.horizontalFieldOfViewRad, 48 * Double.pi / 180, accuracy: 1e-12)
        XCTAssertEqual(o.maxSignRangeMeters, 12)
        XCTAssertTrue(o.negativeInformation)
        XCTAssertTrue(o.recovery)
        XCTAssertTrue(o.adaptiveParticleCount)
        XCTAssertEqual(o.maxViewAngleFromNormalRad, 80 * Double.pi / 180, accuracy: 1e-12)
        XCTAssertEqual(o.startPointDoubtShare, 0.05)
    }

    func testConvergesOnSyntheticWalkFromFloorOnly() throws {
        let building = Self.lBuilding()
        let localizer = try ParticleLocalizer(building: building, options: smallOptions(), seed: 11)
        try localizer.reset(prior: .floorOnly(floorId: "1"))
        XCTAssertFalse(localizer.estimate.isLocalized)
        let frames = Self.walk(building, [Point2(2, 1.25), Point2(28.75, 1.25), Point2(28.75, 22)])
        var errorsWhenLocalized: [Double] = []
        for f in frames {
            localizer.predict(f.vio)
            localizer.update(sightings: f.sightings, t: f.vio.t)
            let e = localizer.estimate
            XCTAssertTrue(e.positionInMap.x.isFinite && e.headingRad.isFinite)
            if e.isLocalized {
                errorsWhenLocalized.append(hypot(e.positionInMap.x - f.truth.x, e.positionInMap.y - f.truth.y))
            }
        }
        XCTAssertNil(localizer.lastInputError)
        XCTAssertGreaterThan(errorsWhenLocalized.count, frames.count / 3)
        let sorted = errorsWhenLocalized.sorted()
        XCTAssertLessThan(sorted[sorted.count / 2], 0.5, "median error while localized")
        let last = localizer.estimate
        XCTAssertTrue(last.isLocalized)
        XCTAssertEqual(last.floorId, "1")
        XCTAssertEqual(last.hypothesisCount, 1)
        XCTAssertLessThan(abs(Self.wrap(last.headingRad - frames.last!.heading)), 0.1)
        XCTAssertGreaterThan(last.confidence, 0.5)
        XCTAssertLessThanOrEqual(last.confidence, 1)
        let particles = localizer.particleSnapshot(maxCount: 500)
        XCTAssertEqual(particles.count, 500)
        XCTAssertTrue(particles.allSatisfy { $0.floorId == "1" && $0.weight >= 0 })
    }

    func testStartPointPriorAndCompass() throws {
        var options = smallOptions()
        options.startPointDoubtShare = 0  // every particle in the disc
        let localizer = try ParticleLocalizer(building: Self.lBuilding(), options: options)
        localizer.predict(VIOSample(t: 0, east: 0, north: 0, yawRad: 0.25, tracking: .normal))
        localizer.setCompassPrior(headingInMapRad: 1.5, sigmaRad: 0.1)
        try localizer.reset(prior: .startPoint(floorId: "1", position: Point2(10, 1.25), radiusMeters: 0.5))
        let e = localizer.estimate
        XCTAssertEqual(e.positionInMap.x, 10, accuracy: 0.1)
        XCTAssertEqual(e.headingRad, 1.5, accuracy: 0.03)
        // The compass prior is a mixture (0.8 from the reading, 0.2 uniform): 80 % of the particles within
        // 3 sigma of the reading, plus the uniform ones that fall there (0.2 * 0.6 / 2 pi); +-0.02 for 8,000.
        let snapshot = localizer.particleSnapshot(maxCount: 8000)
        let near = snapshot.filter { abs(atan2(sin($0.headingRad - 1.5), cos($0.headingRad - 1.5))) <= 0.3 }
        XCTAssertEqual(Double(near.count) / Double(snapshot.count), 0.8 * 0.997 + 0.2 * 0.6 / (2 * Double.pi), accuracy: 0.02)
        XCTAssertEqual(e.particleCount, 8000)
    }

    func testSightingsTheDominantHypothesisCannotExplainAreReported() throws {
        // A 30 m x 2 m corridor whose only sign is an Exit on its east end wall. Started at (2, 1) facing east
        // (compass prior) and walking east, the detector reports an Exit sign 5 m ahead-right ten times a
        // second: from anywhere on this walk the only Exit is 22-28 m away, so the hypothesis explains them only
        // as false positives. The estimate says so once a second's worth reaches the refutation margin, and
        // keeps saying so when they stop (nothing has been explained since).
        let walls = [Wall(from: Point2(0, 0), to: Point2(30, 0)), Wall(from: Point2(30, 0), to: Point2(30, 2)),
                     Wall(from: Point2(30, 2), to: Point2(0, 2)), Wall(from: Point2(0, 2), to: Point2(0, 0))]
        let exit = Sign(id: "e", kind: "exit", position: Point2(30, 1), facing: Point2(-1, 0), widthMeters: 0.3, heightMeters: 0.2)
        let floor = Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: walls, signs: [exit])
        let corridor = Building(id: "corridor", name: "Corridor", floors: [floor],
                                graph: NavigationGraph(nodes: [GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(1, 1))],
                                                       edges: []))
        var options = smallOptions()
        options.startPointDoubtShare = 0
        let localizer = try ParticleLocalizer(building: corridor, options: options)
        let frames = Self.walk(corridor, [Point2(2, 1), Point2(8, 1)])
        localizer.predict(frames[0].vio)
        localizer.setCompassPrior(headingInMapRad: 0, sigmaRad: 0.05)
        try localizer.reset(prior: .startPoint(floorId: "1", position: Point2(2, 1), radiusMeters: 0.5))
        XCTAssertFalse(localizer.estimate.sightingsUnexplained)
        for (k, f) in frames.enumerated().dropFirst().prefix(40) {
            localizer.predict(f.vio)
            let phantom = k < 25 ? [SignSighting(kind: "exit", rangeMeters: 5, bearingRad: -0.3, score: 0.9)] : []
            localizer.update(sightings: phantom, t: f.vio.t)
            let e = localizer.estimate
            if k >= 12 && k < 25 {
                XCTAssertTrue(e.sightingsUnexplained, "frame \(k)")
                XCTAssertGreaterThanOrEqual(e.unexplainedSightingNats, 4, "frame \(k)")
            }
            if k >= 37 { XCTAssertTrue(e.sightingsUnexplained, "frame \(k): latched until a sighting is explained") }
        }
    }

    /// A frame on which the detector did not look for a kind (its wall kinds are searched in turn): a plainly
    /// visible sign of that kind costs nothing by its absence. Particles 2-6 m in front of the west Exit sign, facing
    /// it: an empty frame lowers those 2.5-5 m away (negative information, x0.8), unless "exit" was not searched.
    func testAKindNotLookedForCostsNothingByItsAbsence() throws {
        func weightSpread(unsearched: Set<String>) throws -> Double {
            let localizer = try ParticleLocalizer(building: Self.lBuilding(), options: smallOptions(), seed: 3)
            // A VIO sample first, so the init draws the headings from the compass prior (equal weights).
            localizer.predict(VIOSample(t: 0, east: 0, north: 0, yawRad: 0, tracking: .normal))
            localizer.setCompassPrior(headingInMapRad: Double.pi, sigmaRad: 0.02)
            try localizer.reset(prior: .startPoint(floorId: "1", position: Point2(4, 1.25), radiusMeters: 2))
            localizer.update(sightings: [], unsearchedKinds: unsearched, t: 0.1)
            XCTAssertNil(localizer.lastInputError)
            let weights = localizer.particleSnapshot(maxCount: 100_000).map(\.weight)
            return try XCTUnwrap(weights.max()) / XCTUnwrap(weights.min())
        }
        XCTAssertEqual(try weightSpread(unsearched: []), 1 / 0.8, accuracy: 1e-3)
        XCTAssertEqual(try weightSpread(unsearched: ["exit"]), 1, accuracy: 1e-6)
        XCTAssertEqual(try weightSpread(unsearched: ["restroom"]), 1 / 0.8, accuracy: 1e-3)  // not in the map
    }

    func testErrorsForBadInput() throws {
        let building = Self.lBuilding()
        let localizer = try ParticleLocalizer(building: building, options: smallOptions())
        XCTAssertThrowsError(try localizer.reset(prior: .floorOnly(floorId: "9"))) { error in
            XCTAssertEqual(error as? LocalizerError, .unknownFloor("9"))
        }
        XCTAssertThrowsError(try localizer.reset(prior: .startPoint(floorId: "1", position: Point2(500, 500),
                                                                     radiusMeters: 1))) { error in
            guard case .noWalkableSpace = error as? LocalizerError else { return XCTFail("\(error)") }
        }
        localizer.update(sightings: [], t: 0)
        guard case .notInitialized = localizer.lastInputError else { return XCTFail("expected notInitialized") }

        try localizer.reset(prior: .floorOnly(floorId: "1"))
        localizer.predict(VIOSample(t: 0, east: .nan, north: 0, yawRad: 0, tracking: .normal))
        guard case .nonFiniteInput = localizer.lastInputError else { return XCTFail("expected nonFiniteInput") }
        localizer.update(sightings: [SignSighting(kind: "exit", rangeMeters: .infinity, bearingRad: 0, score: 1)], t: 0.1)
        guard case .nonFiniteInput = localizer.lastInputError else { return XCTFail("expected nonFiniteInput") }
        // A kind the map does not have is not an error: it carries no information.
        localizer.update(sightings: [SignSighting(kind: "restroom", rangeMeters: 3, bearingRad: 0, score: 1)], t: 0.2)
        XCTAssertNil(localizer.lastInputError)
        localizer.setCompassPrior(headingInMapRad: 0, sigmaRad: -1)
        guard case .invalidArgument = localizer.lastInputError else { return XCTFail("expected invalidArgument") }
        let e = localizer.estimate
        XCTAssertTrue(e.positionInMap.x.isFinite && e.positionInMap.y.isFinite && e.confidence.isFinite)

        var bad = smallOptions()
        bad.bearingSigmaRad = 0
        XCTAssertThrowsError(try ParticleLocalizer(building: building, options: bad)) { error in
            guard case .invalidArgument = error as? LocalizerError else { return XCTFail("\(error)") }
        }
        var broken = building
        broken.floors[0].walls[0] = Wall(from: Point2(.nan, 0), to: Point2(1, 1))
        XCTAssertThrowsError(try ParticleLocalizer(building: broken)) { error in
            guard case .invalidMap(let message) = error as? LocalizerError else { return XCTFail("\(error)") }
            XCTAssertTrue(message.contains("test-l"), message)
        }
    }

    func testBuildingWithoutFloorsIsRejected() {
        let empty = Building(id: "empty", name: "Empty", floors: [], graph: NavigationGraph(nodes: [], edges: []))
        XCTAssertThrowsError(try ParticleLocalizer(building: empty)) { error in
            guard case .invalidMap = error as? LocalizerError else { return XCTFail("\(error)") }
        }
    }

    /// The bundled office is symmetric under a half turn about its centre; an L-shaped plan is not; an unknown floor
    /// has none.
    func testFloorSymmetriesAreReported() throws {
        let office = try BundledMaps.office()
        let localizer = try ParticleLocalizer(building: office)
        let s = localizer.floorSymmetries(floorId: office.floors[0].id)
        XCTAssertEqual(s.count, 1)
        XCTAssertEqual(s.first?.angleRad ?? 0, Double.pi, accuracy: 1e-6)
        XCTAssertEqual(s.first?.center.x ?? 0, 20, accuracy: 1e-6)
        XCTAssertEqual(s.first?.center.y ?? 0, 12, accuracy: 1e-6)
        XCTAssertGreaterThan(s.first?.matchedFraction ?? 0, 0.9)
        XCTAssertEqual(s.first?.turnDescription, "a half turn")
        XCTAssertTrue(localizer.floorSymmetries(floorId: "no such floor").isEmpty)
    }
}
