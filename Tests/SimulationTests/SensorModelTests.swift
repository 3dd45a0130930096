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

    /// Pooled correlation of `values` at coordinate separations within `halfWidth` of `lag`; with `removeMean`
    /// each series' mean is removed first (for series with an unknown constant), else the mean is taken as 0.
    private func correlation(_ series: [(coordinate: [Double], values: [Double])], lag: Double, halfWidth: Double,
                             removeMean: Bool = false) -> Double {
        var num = 0.0, a = 0.0, b = 0.0
        for s in series {
            let m = removeMean ? s.values.reduce(0, +) / Double(s.values.count) : 0
            let v = s.values.map { $0 - m }
            for i in v.indices {
                for j in (i + 1)..<v.count where abs(abs(s.coordinate[j] - s.coordinate[i]) - lag) <= halfWidth {
                    num += v[i] * v[j]; a += v[i] * v[i]; b += v[j] * v[j]
                }
            }
        }
        return num / (a * b).squareRoot()
    }

    /// The default compass model, sampled directly over many floors: the error's standard deviation, the share
    /// of the floor in steel hotspots and the field's correlation length match the configured values, and the
    /// large-deviation share lies near the real traces' (1.9 % beyond 45 degrees, docs/compass.md).
    func testCompassErrorMatchesConfiguredStatistics() {
        let p = CompassParameters()
        let model = CompassModel(parameters: p)
        var errors: [Double] = [], inside = 0, beyond45 = 0
        var lines: [(coordinate: [Double], values: [Double])] = []
        for floorSeed: UInt64 in 1...300 {
            var rng = SeededRandom(seed: floorSeed, stream: 99)
            let field = model.makeField(rng: &rng)
            for _ in 0..<400 {
                let d = model.disturbance(field, x: rng.uniform(0, 100), y: rng.uniform(0, 100))
                let e = d.totalDeg + rng.normal(sigma: p.noiseSigmaDeg)
                errors.append(e)
                if d.inHotspot { inside += 1 }
                if abs(e) > 45 { beyond45 += 1 }
            }
            // A straight 60-m line sampled every 0.5 m: the smooth field without the floor's constant bias.
            let x0 = rng.uniform(0, 100), y0 = rng.uniform(0, 100), dir = rng.uniform(0, 2 * .pi)
            let s = stride(from: 0.0, through: 60.0, by: 0.5).map { $0 }
            lines.append((s, s.map { field.smoothDeg(x: x0 + $0 * cos(dir), y: y0 + $0 * sin(dir)) }))
        }
        let n = Double(errors.count)
        let sd = (errors.map { $0 * $0 }.reduce(0, +) / n).squareRoot()
        XCTAssertEqual(sd, p.expectedErrorSigmaDeg, accuracy: 0.05 * p.expectedErrorSigmaDeg, "error standard deviation")
        XCTAssertEqual(p.expectedErrorSigmaDeg, 16.8, accuracy: 1.0, "the default matches the real traces' 16.8 degrees")
        XCTAssertEqual(Double(inside) / n, p.outlierShare, accuracy: 0.004, "share inside hotspots")
        XCTAssertGreaterThan(Double(beyond45) / n, 0.01); XCTAssertLessThan(Double(beyond45) / n, 0.035)
        // Quantiles of |error| near the real traces' (median 9.9, 95 % 34.7, 99 % 49.9, none beyond 90 degrees).
        let sortedAbs = errors.map(abs).sorted()
        func q(_ f: Double) -> Double { sortedAbs[Int(f * (n - 1))] }
        XCTAssertEqual(q(0.5), 9.9, accuracy: 1.5); XCTAssertEqual(q(0.95), 34.7, accuracy: 3); XCTAssertEqual(q(0.99), 49.9, accuracy: 5)
        XCTAssertLessThan(Double(sortedAbs.filter { $0 > 90 }.count) / n, 0.002)
        let L = p.fieldCorrelationLengthMeters
        // Tolerances: about three standard errors of the pooled estimate over 300 independent 60-m lines.
        XCTAssertEqual(correlation(lines, lag: L, halfWidth: 0.26), exp(-1), accuracy: 0.07, "1/e at the correlation length")
        XCTAssertGreaterThan(correlation(lines, lag: L / 2, halfWidth: 0.26), 0.68, "exp(-1/4) = 0.78")
        XCTAssertLessThan(abs(correlation(lines, lag: 2.5 * L, halfWidth: 0.26)), 0.08, "decorrelated after 2.5 L")
    }

    /// A configured correlation length and spread are reproduced (not only the defaults).
    func testCompassFieldFollowsOtherSettings() {
        var p = CompassParameters(); p.fieldCorrelationLengthMeters = 10; p.fieldSigmaDeg = 25; p.outlierShare = 0.05
        p.fieldSigmaFloorLogSigma = 0
        let model = CompassModel(parameters: p)
        var lines: [(coordinate: [Double], values: [Double])] = [], smooth: [Double] = [], inside = 0, count = 0
        for floorSeed: UInt64 in 1...60 {
            var rng = SeededRandom(seed: floorSeed, stream: 98)
            let field = model.makeField(rng: &rng)
            let x0 = rng.uniform(0, 100), y0 = rng.uniform(0, 100), dir = rng.uniform(0, 2 * .pi)
            let s = stride(from: 0.0, through: 60.0, by: 0.5).map { $0 }
            lines.append((s, s.map { field.smoothDeg(x: x0 + $0 * cos(dir), y: y0 + $0 * sin(dir)) }))
            for _ in 0..<2000 {
                let x = rng.uniform(0, 200), y = rng.uniform(0, 200)
                smooth.append(field.smoothDeg(x: x, y: y))
                if model.disturbance(field, x: x, y: y).inHotspot { inside += 1 }
                count += 1
            }
        }
        let sd = (smooth.map { $0 * $0 }.reduce(0, +) / Double(smooth.count)).squareRoot()
        XCTAssertEqual(sd, 25, accuracy: 1.25)
        XCTAssertEqual(Double(inside) / Double(count), 0.05, accuracy: 0.006)
        XCTAssertEqual(correlation(lines, lag: 10, halfWidth: 0.26), exp(-1), accuracy: 0.1)
        XCTAssertLessThan(correlation(lines, lag: 4, halfWidth: 0.26), 0.95)
        XCTAssertGreaterThan(correlation(lines, lag: 4, halfWidth: 0.26), 0.7, "exp(-(4/10)^2) = 0.85")
    }

    func testCompassIsTrueHeadingPlusNorthOffsetPlusSpatialDisturbance() throws {
        var noise: [Double] = [], series: [(coordinate: [Double], values: [Double])] = []
        var accInside: [Double] = [], accOutside: [Double] = []
        for seed: UInt64 in 1...6 {
            let w = try Fixtures.walk(SimulationScenario(name: "compass", from: "room-118", to: "room-107", seed: seed))
            let d = w.diagnostics
            XCTAssertTrue((0..<360).contains(d.mapNorthOffsetDeg))
            var s = 0.0, dist: [Double] = [], vals: [Double] = []
            for (k, f) in w.frames.enumerated() {
                let h = f.compassHeadingDeg!
                XCTAssertTrue(h >= 0 && h < 360)
                let expected = d.mapNorthOffsetDeg + 90 - w.truth[k].headingRad * 180 / .pi + d.compassDisturbanceDeg[k]
                noise.append(wrapAngle((h - expected) * .pi / 180) * 180 / .pi)
                if k > 0 { s += hypot(w.truth[k].x - w.truth[k - 1].x, w.truth[k].y - w.truth[k - 1].y) }
                // One sample per 0.25 m walked on the start floor (the disturbance is a function of position).
                if w.truth[k].floorId == w.truth[0].floorId, s >= (dist.last ?? -1) + 0.25 {
                    dist.append(s); vals.append(d.compassDisturbanceDeg[k])
                }
                let acc = try XCTUnwrap(d.compassHeadingAccuracyDeg[k])
                XCTAssertGreaterThanOrEqual(acc, 0)
                if d.compassInHotspot[k] { accInside.append(acc) } else { accOutside.append(acc) }
            }
            series.append((dist, vals))
        }
        let sd = (noise.map { $0 * $0 }.reduce(0, +) / Double(noise.count)).squareRoot()
        XCTAssertEqual(sd, 2, accuracy: 0.15, "white noise per reading")
        // Along the walked path the disturbance stays correlated over metres and decorrelates after ~2.5 L.
        XCTAssertGreaterThan(correlation(series, lag: 1, halfWidth: 0.13, removeMean: true), 0.8)
        XCTAssertLessThan(correlation(series, lag: 10, halfWidth: 0.13, removeMean: true), 0.3)
        if !accInside.isEmpty {
            XCTAssertGreaterThan(accInside.reduce(0, +) / Double(accInside.count), accOutside.reduce(0, +) / Double(accOutside.count))
        }
        // Fixed north offset: facing map north reads the offset.
        let fixed = try WalkSimulator.simulate(building: Fixtures.office, scenario: SimulationScenario(
            name: "north", from: "room-101", to: "room-111", seed: 1, mapNorthOffsetDeg: 30))
        XCTAssertEqual(fixed.diagnostics.mapNorthOffsetDeg, 30)
    }

    func testUndisturbedCompassHasOnlyWhiteNoise() throws {
        var p = SimulationParameters(); p.compass = .undisturbed
        let w = try Fixtures.walk(SimulationScenario(name: "clean", from: "room-101", to: "room-109", seed: 2), parameters: p)
        XCTAssertEqual(w.diagnostics.compassDisturbanceDeg.map(abs).max()!, 0)
        XCTAssertFalse(w.diagnostics.compassInHotspot.contains(true))
    }

    func testAbsentCompassRecordsNoHeadingAndLeavesOtherStreamsUnchanged() throws {
        let s = SimulationScenario(name: "nocompass", from: "room-101", to: "room-109", seed: 5)
        var p = SimulationParameters(); p.compass = .absent
        let absent = try Fixtures.walk(s, parameters: p)
        let present = try Fixtures.walk(s)
        XCTAssertTrue(absent.frames.allSatisfy { $0.compassHeadingDeg == nil })
        XCTAssertTrue(absent.diagnostics.compassHeadingAccuracyDeg.allSatisfy { $0 == nil })
        XCTAssertTrue(present.frames.allSatisfy { $0.compassHeadingDeg != nil })
        XCTAssertEqual(absent.frames.count, present.frames.count)
        XCTAssertEqual(absent.frames.map(\.cameraToWorld), present.frames.map(\.cameraToWorld))
        XCTAssertEqual(absent.observations.count, present.observations.count)
    }

    func testBadCompassParametersAreRejectedByName() {
        var p = SimulationParameters(); p.compass.fieldCorrelationLengthMeters = 0
        let s = SimulationScenario(name: "bad", from: "room-101", to: "room-109", seed: 1)
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office, scenario: s, parameters: p)) {
            XCTAssertTrue("\($0)".contains("fieldCorrelationLengthMeters"), "\($0)")
        }
        p = SimulationParameters(); p.compass.outlierShare = 0.4
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office, scenario: s, parameters: p)) {
            XCTAssertTrue("\($0)".contains("outlierShare"), "\($0)")
        }
        p = SimulationParameters(); p.compass.noiseSigmaDeg = .nan
        XCTAssertThrowsError(try p.validate())
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
