import Foundation
import Maps
import SessionFormat
import TestRandom
import XCTest

@testable import WayfinderCore

/// CompassNorthCheck: a wrong map north is reported from the residual between the compass and the localized
/// heading, once enough walking under one lock agrees on it; real disturbance, standing still, lock changes and
/// VIO jumps do not make one.
final class CompassNorthCheckTests: XCTestCase {
    /// Walks east along +x in 0.5 m steps while localized with heading `heading`; the compass reads `heading`
    /// turned by `offsetDeg` plus `noise()` degrees. Returns the first verdict and the distance walked then.
    private func walk(_ check: inout CompassNorthCheck, meters: Double, from startEast: Double = 0,
                      offsetDeg: Double, heading: Double = 0.3,
                      noise: () -> Double = { 0 }) -> (CompassNorthCheck.Verdict, Double)? {
        var east = startEast
        while east <= startEast + meters {
            let reading = heading + (offsetDeg + noise()) * Double.pi / 180
            if let v = check.observe(compassInMapRad: reading, localizedHeadingRad: heading, cameraEastMeters: east,
                                     cameraNorthMeters: 2) {
                return (v, east - startEast)
            }
            east += 0.5
        }
        return nil
    }

    func testATurnedNorthIsReportedAfterFifteenMetersUnderOneLock() throws {
        var check = CompassNorthCheck()
        var rng = SplitMix64(seed: 3)
        let found = try XCTUnwrap(walk(&check, meters: 40, offsetDeg: 180, noise: { rng.normal() * 10 }))
        XCTAssertEqual(found.1, 15, accuracy: 0.51)
        XCTAssertEqual(abs(found.0.offsetDeg), 180, accuracy: 6)
        XCTAssertGreaterThan(found.0.resultant, 0.9)
        XCTAssertEqual(found.0.samples, 16)  // one per meter, the first at the start
        XCTAssertEqual(check.verdict, found.0)
        // Reported once: the check stops watching.
        XCTAssertNil(walk(&check, meters: 20, from: 50, offsetDeg: 180))

        var quarter = CompassNorthCheck()
        let q = try XCTUnwrap(walk(&quarter, meters: 40, offsetDeg: -90))
        XCTAssertEqual(q.0.offsetDeg, -90, accuracy: 1e-9)
    }

    func testRealIndoorDisturbanceIsNotAWrongNorth() {
        // A 22-degree walk offset (the largest measured on the real mall walks, docs/compass.md) under a field of
        // 30 degrees standard deviation, over 200 m: no verdict.
        var check = CompassNorthCheck()
        var rng = SplitMix64(seed: 5)
        XCTAssertNil(walk(&check, meters: 200, offsetDeg: 22, noise: { rng.normal() * 30 }))
        // A compass that points anywhere (resultant near 0) is no north either, however far off its mean.
        var wild = CompassNorthCheck()
        var rng2 = SplitMix64(seed: 6)
        XCTAssertNil(walk(&wild, meters: 200, offsetDeg: 0, noise: { rng2.uniform(-180, 180) }))
    }

    func testStandingStillAddsNothing() {
        var check = CompassNorthCheck()
        for _ in 0..<3000 {
            XCTAssertNil(check.observe(compassInMapRad: Double.pi, localizedHeadingRad: 0, cameraEastMeters: 1,
                                       cameraNorthMeters: 1))
        }
        XCTAssertNil(check.verdict)
    }

    func testANewLockStartsAgain() throws {
        var check = CompassNorthCheck()
        XCTAssertNil(walk(&check, meters: 10, offsetDeg: 180))
        // The lock drops for a frame: the next lock is a new hypothesis, checked from its own start.
        XCTAssertNil(check.observe(compassInMapRad: 0, localizedHeadingRad: nil, cameraEastMeters: 10.5,
                                   cameraNorthMeters: 2))
        XCTAssertNil(walk(&check, meters: 10, from: 11, offsetDeg: 180))
        let found = try XCTUnwrap(walk(&check, meters: 10, from: 21.5, offsetDeg: 180))
        XCTAssertEqual(found.0.walkedMeters, 15, accuracy: 0.51)
    }

    func testAVIOJumpIsNotWalking() {
        var check = CompassNorthCheck()
        // Twenty relocalization snaps of 5 m between frames: no distance walked, no verdict.
        for k in 0..<20 {
            XCTAssertNil(check.observe(compassInMapRad: Double.pi, localizedHeadingRad: 0,
                                       cameraEastMeters: Double(k) * 5, cameraNorthMeters: 0))
        }
        XCTAssertNil(check.verdict)
    }

    func testFramesWithoutACompassReadingOrPoseCountNoResidual() {
        var check = CompassNorthCheck()
        var east = 0.0
        while east < 40 {
            XCTAssertNil(check.observe(compassInMapRad: nil, localizedHeadingRad: 0, cameraEastMeters: east,
                                       cameraNorthMeters: 0))
            XCTAssertNil(check.observe(compassInMapRad: Double.pi, localizedHeadingRad: 0, cameraEastMeters: nil,
                                       cameraNorthMeters: nil))
            east += 0.5
        }
        // Only the no-pose frames carried readings, and they walk nowhere: one residual, no verdict.
        XCTAssertNil(check.verdict)
    }
}

/// The north check in the pipeline, on the committed sample walk (its compass is simulated against a north that
/// the office map does not record: the test gives the map the north the readings imply, or one turned from it).
final class CompassNorthCheckReplayTests: XCTestCase {
    /// The map north (compassHeadingOfMapNorthDeg) under which the sample's readings match its true headings:
    /// reading = north + 90 - heading (degrees), averaged on the circle.
    private func impliedNorthDeg(_ bundle: SessionBundle) -> Double {
        var c = 0.0, s = 0.0
        for (f, g) in zip(bundle.frames, bundle.truth) {
            guard let r = f.compassHeadingDeg else { continue }
            let north = (r - 90 + g.headingRad * 180 / Double.pi) * Double.pi / 180
            c += cos(north)
            s += sin(north)
        }
        return (atan2(s, c) * 180 / Double.pi + 360).truncatingRemainder(dividingBy: 360)
    }

    private func run(northTurnedByDeg turn: Double, check: Bool) throws -> ReplayResult {
        let bundle = try TestData.sample()
        var building = try TestData.office()
        building.compassHeadingOfMapNorthDeg = (impliedNorthDeg(bundle) + turn + 360).truncatingRemainder(dividingBy: 360)
        var o = PipelineOptions()
        // The sample walk is short (about 25 m): a check over 5 m, for a 40-degree turn.
        var p = CompassNorthCheck.Parameters()
        p.minWalkedMeters = 5
        p.minOffsetDeg = 30
        o.compassNorthCheck = check ? p : nil
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: o))
        options.pipeline.localizer.particleCount = 3000
        options.snapshotParticleCount = 0
        return try Replay.run(bundle: bundle, building: building, options: options)
    }

    func testATurnedNorthIsWarnedOnceAndTheRightOneNever() throws {
        let turned = try run(northTurnedByDeg: 40, check: true)
        let warned = turned.warnings.filter { $0.contains("may be wrong") }
        XCTAssertEqual(warned.count, 1, "\(turned.warnings)")
        XCTAssertTrue(warned.first?.contains("compassHeadingOfMapNorthDeg") ?? false)
        XCTAssertTrue(turned.trace.contains(where: \.localized), "the sample walk localizes")

        let right = try run(northTurnedByDeg: 0, check: true)
        XCTAssertFalse(right.warnings.contains { $0.contains("may be wrong") }, "\(right.warnings)")

        let off = try run(northTurnedByDeg: 40, check: false)
        XCTAssertFalse(off.warnings.contains { $0.contains("may be wrong") })
    }
}
