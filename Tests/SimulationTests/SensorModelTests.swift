import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// Barometer, compass and the phone's pose on the body.
final class SensorModelTests: XCTestCase {
    func testBarometerStepsByTheFloorElevationDifference() throws {
        let w = try Fixtures.walk(SimulationScenario(name: "baro", from: "room-105", to: "room-214", seed: 4))
        let first = w.frames.prefix(30).compactMap(\.relativeAltitudeMeters)
        let last = w.frames.suffix(30).compactMap(\.relativeAltitudeMeters)
        XCTAssertEqual(first.reduce(0, +) / Double(first.count), 0, accuracy: 0.35)
        // Floor 2 is 3.8 m above floor 1: the reading rises by 3.8 m (noise 0.1 m, drift a few cm/min).
        XCTAssertEqual(last.reduce(0, +) / Double(last.count), 3.8, accuracy: 0.35)
    }

    func testBarometerNoiseAndDriftMatchParameters() throws {
        var residuals: [Double] = []
        var drifts: [Double] = []
        for seed: UInt64 in 1...10 {
            let w = try Fixtures.walk(SimulationScenario(name: "baro", from: "room-101", to: "room-109", seed: seed))
            let d = w.diagnostics
            drifts.append(d.barometerDriftMetersPerSecond * 60)
            let base = d.altitudesMeters[0]
            var lastReading: Double?
            for (k, f) in w.frames.enumerated() {
                guard let r = f.relativeAltitudeMeters, r != lastReading else { continue }   // one per new reading
                lastReading = r
                residuals.append(r - (d.altitudesMeters[k] - base) - d.barometerDriftMetersPerSecond * f.t)
            }
        }
        let sd = (residuals.map { $0 * $0 }.reduce(0, +) / Double(residuals.count)).squareRoot()
        XCTAssertEqual(sd, 0.1, accuracy: 0.015)
        // New readings at about 1 Hz.
        let w = try Fixtures.walk(SimulationScenario(name: "baro", from: "room-101", to: "room-109", seed: 1))
        let changes = zip(w.frames, w.frames.dropFirst()).filter { $0.relativeAltitudeMeters != $1.relativeAltitudeMeters }.count
        XCTAssertEqual(Double(changes), w.truth.last!.t, accuracy: 2)
        XCTAssertLessThan(drifts.map(abs).max()!, 0.15, "a few cm per minute")
    }

    func testCompassIsTrueHeadingPlusNorthOffsetPlusBoundedDisturbance() throws {
        var noise: [Double] = [], disturbance: [Double] = []
        for seed: UInt64 in 1...6 {
            let w = try Fixtures.walk(SimulationScenario(name: "compass", from: "room-118", to: "room-107", seed: seed))
            let d = w.diagnostics
            XCTAssertTrue((0..<360).contains(d.mapNorthOffsetDeg))
            for (k, f) in w.frames.enumerated() {
                let h = f.compassHeadingDeg!
                XCTAssertTrue(h >= 0 && h < 360)
                let expected = d.mapNorthOffsetDeg + 90 - w.truth[k].headingRad * 180 / .pi + d.compassDisturbanceDeg[k]
                noise.append(wrapAngle((h - expected) * .pi / 180) * 180 / .pi)
                disturbance.append(d.compassDisturbanceDeg[k])
            }
        }
        let sd = (noise.map { $0 * $0 }.reduce(0, +) / Double(noise.count)).squareRoot()
        XCTAssertEqual(sd, 2, accuracy: 0.15)
        XCTAssertLessThanOrEqual(disturbance.map(abs).max()!, 30 + 1e-9)
        let dsd = (disturbance.map { $0 * $0 }.reduce(0, +) / Double(disturbance.count)).squareRoot()
        XCTAssertGreaterThan(dsd, 7); XCTAssertLessThan(dsd, 25)
        // Fixed north offset: facing map north reads the offset.
        let fixed = try WalkSimulator.simulate(building: Fixtures.office, scenario: SimulationScenario(
            name: "north", from: "room-101", to: "room-111", seed: 1, mapNorthOffsetDeg: 30))
        XCTAssertEqual(fixed.diagnostics.mapNorthOffsetDeg, 30)
    }

    func testHandheldPoseRanges() throws {
        for seed: UInt64 in 1...6 {
            let w = try Fixtures.walk(SimulationScenario(name: "hand", from: "room-101", to: "room-109", seed: seed))
            let d = w.diagnostics
            let pitchDeg = d.pitchesRad.map { $0 * 180 / .pi }
            XCTAssertGreaterThanOrEqual(pitchDeg.min()!, -5 - 1e-9); XCTAssertLessThanOrEqual(pitchDeg.max()!, 20 + 1e-9)
            let roll = d.rollsRad.map { $0 * 180 / .pi }
            XCTAssertEqual(roll.reduce(0, +) / Double(roll.count), -90, accuracy: 5, "portrait")
            XCTAssertGreaterThanOrEqual(d.cameraHeightsMeters.min()!, 1.28); XCTAssertLessThanOrEqual(d.cameraHeightsMeters.max()!, 1.52)
            // What replay decodes from the frames equals the simulated pitch and roll (jitter 0.1 deg).
            for k in stride(from: 0, to: w.frames.count, by: 17) where w.frames[k].tracking != .notAvailable {
                let pose = CameraPose(columnMajor: w.frames[k].cameraToWorld)!
                XCTAssertEqual(pose.pitchRad, d.pitchesRad[k], accuracy: 0.01)
                XCTAssertEqual(wrapAngle(pose.rollRad - d.rollsRad[k]), 0, accuracy: 0.01)
            }
        }
        let land = try Fixtures.walk(SimulationScenario(name: "land", from: "room-101", to: "room-109", seed: 1, orientation: .landscape))
        XCTAssertEqual(land.diagnostics.rollsRad.reduce(0, +) / Double(land.frames.count) * 180 / .pi, 0, accuracy: 5)
    }

    /// Standard deviation of x after removing a 1-s moving average (the step-frequency part).
    private func highPassSD(_ x: [Double], window: Int = 30) -> Double {
        var out: [Double] = []
        for k in window..<(x.count - window) {
            let m = x[(k - window / 2)...(k + window / 2)].reduce(0, +) / Double(window + 1)
            out.append(x[k] - m)
        }
        return (out.map { $0 * $0 }.reduce(0, +) / Double(out.count)).squareRoot()
    }

    func testLanyardSwingsMoreAtTheStepFrequency() throws {
        let hand = try Fixtures.walk(SimulationScenario(name: "hand", from: "room-101", to: "room-109", seed: 3))
        let lan = try Fixtures.walk(SimulationScenario(name: "lan", from: "room-101", to: "room-109", seed: 3, carry: .lanyard))
        XCTAssertEqual(lan.info.carry, "lanyard")
        XCTAssertGreaterThan(highPassSD(lan.diagnostics.pitchesRad), 2 * highPassSD(hand.diagnostics.pitchesRad))
        XCTAssertGreaterThan(highPassSD(lan.diagnostics.rollsRad), 2 * highPassSD(hand.diagnostics.rollsRad))
        // Dominant pitch frequency while cruising: about 1.8 Hz (scaled by sqrt(speed / 1.1)).
        let p = lan.diagnostics.pitchesRad, phases = lan.diagnostics.phases
        var bestF = 0.0, bestPower = 0.0
        let idx = p.indices.filter { phases[$0] == .cruising }
        let mean = idx.map { p[$0] }.reduce(0, +) / Double(idx.count)
        for f in stride(from: 0.5, through: 4.0, by: 0.05) {
            var re = 0.0, im = 0.0
            for k in idx { let t = lan.frames[k].t; re += (p[k] - mean) * cos(2 * .pi * f * t); im += (p[k] - mean) * sin(2 * .pi * f * t) }
            if re * re + im * im > bestPower { bestPower = re * re + im * im; bestF = f }
        }
        XCTAssertEqual(bestF, 1.8, accuracy: 0.4)
    }
}
