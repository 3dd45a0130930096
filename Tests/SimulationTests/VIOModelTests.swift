import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// VIO: scale, yaw drift, jitter, tracking states, loss, reset, relocalization.
final class VIOModelTests: XCTestCase {
    private func pose(_ f: FrameRecord) -> CameraPose { CameraPose(columnMajor: f.cameraToWorld)! }

    func testScaleErrorIsRecoveredFromPathLengthsWithinHalfAPercent() throws {
        for seed: UInt64 in [1, 2, 3, 4] {
            let w = try Fixtures.walk(SimulationScenario(name: "scale", from: "room-101", to: "room-109", seed: seed))
            let s = w.diagnostics.vio.scale
            XCTAssertGreaterThanOrEqual(abs(s - 1), 0.01 - 1e-12); XCTAssertLessThanOrEqual(abs(s - 1), 0.05 + 1e-12)
            var vioLength = 0.0, truthLength = 0.0
            let stride = 30
            var k = stride
            while k < w.frames.count {
                let window = (k - stride)...k
                let clean = window.allSatisfy { w.frames[$0].tracking == .normal } &&
                    !w.diagnostics.vio.relocalizationTimes.contains { $0 >= w.frames[k - stride].t && $0 <= w.frames[k].t }
                if clean {
                    let a = pose(w.frames[k - stride]).positionInVIOPlane, b = pose(w.frames[k]).positionInVIOPlane
                    vioLength += hypot(b.east - a.east, b.north - a.north)
                    truthLength += hypot(w.truth[k].x - w.truth[k - stride].x, w.truth[k].y - w.truth[k - stride].y)
                }
                k += stride
            }
            XCTAssertGreaterThan(truthLength, 20)
            XCTAssertEqual(vioLength / truthLength, s, accuracy: 0.005 * s, "seed \(seed)")
        }
    }

    func testVIOYawIsTruthPlusTheDocumentedOffsetAndDriftRateIsInRange() throws {
        let w = try Fixtures.walk(SimulationScenario(name: "yaw", from: "room-101", to: "room-109", seed: 2))
        let d = w.diagnostics
        XCTAssertGreaterThanOrEqual(abs(d.vio.yawDriftRateRadPerSecond) * 60 * 180 / .pi, 0.5 - 1e-9)
        XCTAssertLessThanOrEqual(abs(d.vio.yawDriftRateRadPerSecond) * 60 * 180 / .pi, 2.0 + 1e-9)
        var maxErrDeg = 0.0
        for (k, f) in w.frames.enumerated() where f.tracking != .notAvailable {
            let e = wrapAngle(pose(f).yawInVIOPlaneRad - w.truth[k].headingRad - d.mapToVIOYawRad[k])
            maxErrDeg = max(maxErrDeg, abs(e) * 180 / .pi)
        }
        // Orientation jitter is 0.1 degree (sigma): 6 sigma bound over ~2000 frames.
        XCTAssertLessThan(maxErrDeg, 0.6)
    }

    func testYawDriftWithoutRandomWalkMatchesItsRate() throws {
        var p = SimulationParameters()
        p.vio.yawRandomWalkDegPerSqrtMinute = 0
        p.vio.relocalizationsPerSecond = 0
        let w = try Fixtures.walk(SimulationScenario(name: "drift", from: "room-101", to: "room-109", seed: 8), parameters: p)
        // Least-squares slope of (VIO yaw - truth heading) over time, from the frames alone.
        var ts: [Double] = [], es: [Double] = []
        var prev: Double?
        var unwrap = 0.0
        for (k, f) in w.frames.enumerated() {
            var e = wrapAngle(pose(f).yawInVIOPlaneRad - w.truth[k].headingRad)
            if let q = prev { unwrap += wrapAngle(e - q) ; e = unwrap } else { unwrap = e }
            prev = wrapAngle(pose(f).yawInVIOPlaneRad - w.truth[k].headingRad)
            ts.append(f.t); es.append(unwrap)
        }
        let n = Double(ts.count)
        let mt: Double = ts.reduce(0, +) / n
        let me: Double = es.reduce(0, +) / n
        var sxy = 0.0, sxx = 0.0
        for (t, e) in zip(ts, es) { sxy += (t - mt) * (e - me); sxx += (t - mt) * (t - mt) }
        let slope = sxy / sxx
        let rate = w.diagnostics.vio.yawDriftRateRadPerSecond
        XCTAssertEqual(slope * 60 * 180 / .pi, rate * 60 * 180 / .pi, accuracy: 0.05)
    }

    func testYawRandomWalkSpreadMatchesParameter() throws {
        // Increments of the map-to-VIO yaw over 10 s, drift removed: sigma = 0.5 deg * sqrt(10/60).
        var increments: [Double] = []
        var p = SimulationParameters(); p.vio.relocalizationsPerSecond = 0
        for seed: UInt64 in 1...8 {
            let w = try Fixtures.walk(SimulationScenario(name: "rw", from: "room-101", to: "room-109", seed: seed), parameters: p)
            let th = w.diagnostics.mapToVIOYawRad, rate = w.diagnostics.vio.yawDriftRateRadPerSecond
            var k = 300
            while k < th.count { increments.append(th[k] - th[k - 300] - rate * 10); k += 300 }
        }
        let sd = (increments.map { $0 * $0 }.reduce(0, +) / Double(increments.count)).squareRoot() * 180 / .pi
        XCTAssertEqual(sd, 0.5 * (10.0 / 60).squareRoot(), accuracy: 0.08)
    }

    func testPositionJitterIsMillimetres() throws {
        // While standing still at the start (after initializing), positions scatter by the 2 mm jitter only.
        let w = try Fixtures.walk(SimulationScenario(name: "jitter", from: "room-101", to: "room-111", seed: 1))
        let standing = w.frames.indices.filter { w.diagnostics.phases[$0] == .standing && w.frames[$0].tracking == .normal && $0 < 60 }
        XCTAssertGreaterThan(standing.count, 10)
        let xs = standing.map { pose(w.frames[$0]).positionInWorld.x }
        let m = xs.reduce(0, +) / Double(xs.count)
        let sd = (xs.map { ($0 - m) * ($0 - m) }.reduce(0, +) / Double(xs.count - 1)).squareRoot()
        XCTAssertEqual(sd, 0.002, accuracy: 0.0012)
    }

    func testWorldFrameIsArbitraryAndStartsNearTheOrigin() throws {
        let yaws = try (1...6).map { seed -> Double in
            let w = try Fixtures.walk(SimulationScenario(name: "origin", from: "room-101", to: "room-111", seed: UInt64(seed)))
            let p = pose(w.frames[0]).positionInWorld
            XCTAssertLessThan(hypot(p.x, p.z), 0.3)
            return w.diagnostics.mapToVIOYawRad[0]
        }
        // Different seeds, clearly different world yaws.
        XCTAssertGreaterThan(yaws.max()! - yaws.min()!, 1.0)
        let w = try Fixtures.walk(SimulationScenario(name: "origin", from: "room-101", to: "room-111", seed: 1))
        XCTAssertEqual(w.frames[0].tracking, .limited); XCTAssertEqual(w.frames[0].trackingReason, .initializing)
    }

    func testTrackingLossFreezesThePoseAndIsFollowedByRelocalizing() throws {
        let s = SimulationScenario(name: "loss", from: "room-101", to: "room-109", seed: 3, trackingLossAt: 15, trackingLossDurationSeconds: 4)
        let w = try Fixtures.walk(s)
        let lost = w.frames.indices.filter { w.frames[$0].tracking == .notAvailable }
        XCTAssertEqual(Double(lost.count) / 30, 4, accuracy: 0.1)
        XCTAssertEqual(w.frames[lost.first!].t, 15, accuracy: 0.05)
        for k in lost { XCTAssertEqual(w.frames[k].cameraToWorld, w.frames[lost.first! - 1].cameraToWorld) }
        let after = lost.last! + 1
        XCTAssertEqual(w.frames[after].trackingReason, .relocalizing)
        XCTAssertFalse(w.observations.contains { $0.t >= 15 && $0.t <= 19 }, "no observations without tracking")
        // The walk continued: truth moved while the pose was frozen, and VIO does not contain that displacement.
        let moved = hypot(w.truth[lost.last!].x - w.truth[lost.first!].x, w.truth[lost.last!].y - w.truth[lost.first!].y)
        XCTAssertGreaterThan(moved, 1)
    }

    func testVIOResetStartsANewWorldFrame() throws {
        let s = SimulationScenario(name: "reset", from: "room-101", to: "room-109", seed: 4, vioResetAt: 20)
        let w = try Fixtures.walk(s)
        let k = w.frames.firstIndex { $0.t >= 20 }!
        XCTAssertEqual(w.frames[k].trackingReason, .initializing)
        let p = pose(w.frames[k]).positionInWorld
        XCTAssertLessThan(hypot(p.x, p.z), 0.3, "the new origin is at the camera")
        let before = pose(w.frames[k - 1]).positionInWorld
        XCTAssertGreaterThan(hypot(before.x, before.z), 5, "far from the old origin after 20 s of walking")
        // Later poses follow the truth in the new frame: VIO yaw - truth heading is the new offset.
        let off = wrapAngle(pose(w.frames[k + 60]).yawInVIOPlaneRad - w.truth[k + 60].headingRad)
        XCTAssertEqual(off, wrapAngle(w.diagnostics.mapToVIOYawRad[k + 60]), accuracy: 0.01)
    }

    func testRelocalizationJumpsAreAtMostOneMetre() throws {
        var p = SimulationParameters()
        p.vio.relocalizationsPerSecond = 1.0 / 4
        p.vio.limitedPositionRandomWalkMetersPerSqrtSecond = 0
        let w = try Fixtures.walk(SimulationScenario(name: "reloc", from: "room-101", to: "room-109", seed: 5), parameters: p)
        let times = w.diagnostics.vio.relocalizationTimes
        XCTAssertGreaterThan(times.count, 2)
        for (t, mag) in zip(times, w.diagnostics.vio.relocalizationJumpMeters) {
            XCTAssertLessThanOrEqual(mag, 1.0); XCTAssertGreaterThanOrEqual(mag, 0.2)
            let k = w.frames.firstIndex { $0.t >= t - 1e-9 }!
            XCTAssertEqual(w.frames[k - 1].trackingReason, .relocalizing)
            // Observed jump: VIO step minus the scaled true step.
            let a = pose(w.frames[k - 1]).positionInVIOPlane, b = pose(w.frames[k]).positionInVIOPlane
            let trueStep = hypot(w.truth[k].x - w.truth[k - 1].x, w.truth[k].y - w.truth[k - 1].y) * w.diagnostics.vio.scale
            let vioStep = hypot(b.east - a.east, b.north - a.north)
            XCTAssertEqual(vioStep, mag, accuracy: trueStep + 0.01)
        }
    }

    func testFastTurnsReportExcessiveMotion() throws {
        let w = try Fixtures.walk(SimulationScenario(name: "turn", from: "room-116", to: "room-103", seed: 5, wrongTurn: true))
        XCTAssertTrue(w.frames.contains { $0.trackingReason == .excessiveMotion }, "turning around in place is fast")
    }

    func testDarkSpellAndRelocalizationRatesMatchParameters() throws {
        // Dark spells at 0.1/s lasting 1-3 s (mean 2): a renewal process in which 0.1 * 2 / (1 + 0.1 * 2) = 1/6 of
        // the time is dark. Relocalizations at 0.05/s: the count over the walked time is Poisson.
        var p = SimulationParameters()
        p.vio.darkSpellsPerSecond = 0.1
        p.vio.relocalizationsPerSecond = 0.05
        p.vio.excessiveMotionTurnRateDegPerSecond = 10_000
        var dark = 0, eligible = 0, relocs = 0
        var seconds = 0.0
        for seed: UInt64 in 1...8 {
            let w = try Fixtures.walk(SimulationScenario(name: "events", from: "room-101", to: "room-109", seed: seed), parameters: p)
            for f in w.frames where f.trackingReason != .initializing && f.trackingReason != .relocalizing {
                eligible += 1
                if f.trackingReason == .insufficientFeatures { dark += 1 }
            }
            relocs += w.diagnostics.vio.relocalizationTimes.count
            seconds += w.truth.last!.t
        }
        XCTAssertEqual(Double(dark) / Double(eligible), 1.0 / 6, accuracy: 0.06)
        // Expected count: rate * time / (1 + rate * mean spell 1.5 s); allow 3 Poisson standard deviations.
        let expected = 0.05 * seconds / (1 + 0.05 * 1.5)
        XCTAssertEqual(Double(relocs), expected, accuracy: 3 * expected.squareRoot())
    }
}
