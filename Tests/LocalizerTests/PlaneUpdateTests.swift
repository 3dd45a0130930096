import Foundation
import Maps
import XCTest

@testable import Localizer

/// `ParticleLocalizer.updatePlanes`: walls seen as planes move the estimate's heading onto the corridor axis;
/// bad planes are reported, not applied.
final class PlaneUpdateTests: XCTestCase {
    private func options() -> LocalizerOptions {
        var o = LocalizerOptions()
        o.particleCount = 8000
        o.minParticles = 2000
        o.maxParticles = 30000
        return o
    }

    func testPlanesOfTheCorridorWallsFavourHeadingsAlongIt() throws {
        let localizer = try ParticleLocalizer(building: ParticleLocalizerTests.lBuilding(), options: options(), seed: 5)
        // Start known to within 1 m at (10, 1.25) in the east-west corridor, heading unknown.
        try localizer.reset(prior: .startPoint(floorId: "1", position: Point2(10, 1.25), radiusMeters: 1))
        localizer.predict(VIOSample(t: 0, east: 0, north: 0, yawRad: 0, tracking: .normal))
        func shareAlongAxis() -> Double {
            let p = localizer.particleSnapshot(maxCount: 8000)
            let total = p.reduce(0) { $0 + $1.weight }
            let along = p.filter { abs(atan2(sin(2 * $0.headingRad), cos(2 * $0.headingRad))) / 2 < 0.2 }.reduce(0) { $0 + $1.weight }
            return along / total
        }
        let before = shareAlongAxis()
        // The corridor's walls 1.25 m to the left and right of the camera (VIO = map here, up to the offset).
        for (k, t) in [0.1, 1.2, 2.3, 3.4].enumerated() {
            let id = UInt64(10 * k)
            localizer.updatePlanes([
                PlaneObservation(anchorId: id + 1, centerEast: 0.5, centerNorth: 1.25, normalYawRad: -Double.pi / 2, widthMeters: 3),
                PlaneObservation(anchorId: id + 2, centerEast: -0.5, centerNorth: -1.25, normalYawRad: Double.pi / 2, widthMeters: 3),
            ], t: t)
            XCTAssertNil(localizer.lastInputError)
        }
        let after = shareAlongAxis()
        XCTAssertLessThan(before, 0.2)
        XCTAssertGreaterThan(after, 1.8 * before, "before \(before), after \(after)")
    }

    func testBadPlanesAreReported() throws {
        let localizer = try ParticleLocalizer(building: ParticleLocalizerTests.lBuilding(), options: options(), seed: 5)
        let plane = PlaneObservation(anchorId: 1, centerEast: 0, centerNorth: 1, normalYawRad: 0, widthMeters: 2)
        localizer.updatePlanes([plane], t: 0)
        guard case .notInitialized = localizer.lastInputError else { return XCTFail("expected notInitialized") }
        try localizer.reset(prior: .floorOnly(floorId: "1"))
        localizer.predict(VIOSample(t: 0, east: 0, north: 0, yawRad: 0, tracking: .normal))
        var bad = plane
        bad.centerEast = .nan
        localizer.updatePlanes([bad], t: 0.1)
        guard case .nonFiniteInput(let m) = localizer.lastInputError else { return XCTFail("expected nonFiniteInput") }
        XCTAssertTrue(m.contains("plane"), m)
        var flat = plane
        flat.widthMeters = 0
        localizer.updatePlanes([flat], t: 0.2)
        XCTAssertNil(localizer.lastInputError, "a zero-width plane is ignored, not an error")
        XCTAssertTrue(localizer.estimate.positionInMap.x.isFinite)
    }
}
