import Foundation

/// CMAltimeter's relative altitude: the true change of the phone's altitude since the start, plus a constant
/// drift rate drawn per walk (weather and temperature) and white noise per reading; readings arrive at about
/// 1 Hz and frames repeat the latest one.
struct BarometerModel {
    let parameters: BarometerParameters

    func run(times: [Double], altitudes: [Double], rng: inout SeededRandom) -> (readings: [Double], driftRateMetersPerSecond: Double) {
        let p = parameters
        let drift = rng.normal(sigma: p.driftRateSigmaMetersPerMinute) / 60
        var out: [Double] = []
        out.reserveCapacity(times.count)
        var nextReading = 0.0
        var current = 0.0
        let base = altitudes.first ?? 0
        for (t, a) in zip(times, altitudes) {
            if t >= nextReading {
                current = (a - base) + drift * t + rng.normal(sigma: p.noiseSigmaMeters)
                nextReading += 1 / p.updateRateHz
            }
            out.append(current)
        }
        return (out, drift)
    }
}

/// Core Location's heading indoors, calibrated on 31 real phone walks in two steel-framed malls
/// (`scripts/compass_study.py`, figures in docs/compass.md). The reading is the true heading of the camera
/// (degrees clockwise from map north, plus the building's north offset) plus an error that is a function of
/// where the phone is, not white noise:
///
/// - a constant bias per floor (normal, `floorBiasSigmaDeg`): the measured floors' offsets from map north
///   scatter by about 7 degrees;
/// - a smooth stationary Gaussian random field over the floor (standard deviation `fieldSigmaDeg` times a
///   log-normal factor per floor of spread `fieldSigmaFloorLogSigma` and mean square 1, correlation
///   exp(-(d / L)^2) with L = `fieldCorrelationLengthMeters`, the distance where it falls to 1/e), made by the
///   spectral (random Fourier mode) method: `fieldModeCount` plane waves with wave vectors drawn from the
///   field's Gaussian spectral density, uniform phases and equal amplitudes sigma * sqrt(2 / N) (Shinozuka and
///   Deodatis, "Simulation of stochastic processes by spectral representation", 1991);
/// - occasional large deviations near steel: disc-shaped hotspots of radius `hotspotRadiusMeters` with a
///   smooth bump (peak `hotspotPeakDeg` in either direction), placed at most one per square cell of
///   `hotspotCellMeters` with the probability that makes the covered share of the floor (hence of the distance
///   walked) equal `outlierShare`;
/// - white noise per reading (`noiseSigmaDeg`).
///
/// Core Location's `headingAccuracy` is simulated as a per-walk typical value (`accuracyTypicalDeg` times a
/// log-normal factor) that grows with the hotspot deviation (`accuracyHotspotGain`): loosely informative, as
/// indoors on real phones. The bundle has no field for it, so it only reaches the diagnostics.
struct CompassModel {
    let parameters: CompassParameters

    /// The disturbance field of one floor: bias, smooth modes and the hotspot placement seed.
    struct Field {
        /// Constant bias of the floor, degrees.
        var floorBiasDeg: Double
        /// Plane waves: wave vector (rad/m), phase (rad); all share `amplitudeDeg`.
        var modes: [(kx: Double, ky: Double, phase: Double)]
        /// Amplitude of every mode, degrees.
        var amplitudeDeg: Double
        /// Seed of the hotspot lattice (hotspots are a pure function of it and the cell index).
        var hotspotSeed: UInt64

        /// The smooth part at a point, degrees.
        func smoothDeg(x: Double, y: Double) -> Double {
            var v = 0.0
            for m in modes { v += cos(m.kx * x + m.ky * y + m.phase) }
            return amplitudeDeg * v
        }
    }

    /// The error at one point of a floor (without white noise), degrees.
    struct Disturbance {
        /// Floor bias plus smooth field plus hotspot, degrees.
        var totalDeg: Double
        /// The hotspot part alone (0 outside every hotspot), degrees.
        var hotspotDeg: Double
        /// True inside a hotspot disc.
        var inHotspot: Bool
    }

    /// Probability that a lattice cell holds a hotspot so that the discs cover `outlierShare` of the floor.
    var hotspotCellProbability: Double {
        let p = parameters
        let discArea = Double.pi * p.hotspotRadiusMeters * p.hotspotRadiusMeters
        return min(1, p.outlierShare * p.hotspotCellMeters * p.hotspotCellMeters / max(discArea, 1e-12))
    }

    /// Draws the field of one floor.
    func makeField(rng: inout SeededRandom) -> Field {
        let p = parameters
        let n = max(1, p.fieldModeCount)
        // Correlation exp(-d^2 / (2 l^2)) with l = L / sqrt(2) has wave vector components N(0, 1 / l^2).
        let kSigma = 2.0.squareRoot() / max(p.fieldCorrelationLengthMeters, 1e-6)
        var modes: [(Double, Double, Double)] = []
        modes.reserveCapacity(n)
        for _ in 0..<n {
            modes.append((rng.normal(sigma: kSigma), rng.normal(sigma: kSigma), rng.uniform(0, 2 * Double.pi)))
        }
        let ls = p.fieldSigmaFloorLogSigma
        let floorSigmaDeg = p.fieldSigmaDeg * exp(rng.normal(sigma: ls) - ls * ls)
        return Field(floorBiasDeg: rng.normal(sigma: p.floorBiasSigmaDeg), modes: modes,
                     amplitudeDeg: floorSigmaDeg * (2.0 / Double(n)).squareRoot(), hotspotSeed: rng.next())
    }

    /// The hotspot deviation at a point, degrees (0 outside every disc), from the 3 x 3 cells around it.
    func hotspot(_ field: Field, x: Double, y: Double) -> (deg: Double, inside: Bool) {
        let p = parameters
        guard p.outlierShare > 0, p.hotspotRadiusMeters > 0 else { return (0, false) }
        let c = p.hotspotCellMeters, r = p.hotspotRadiusMeters
        let prob = hotspotCellProbability
        let ix = Int((x / c).rounded(.down)), iy = Int((y / c).rounded(.down))
        var total = 0.0, inside = false
        for cx in (ix - 1)...(ix + 1) {
            for cy in (iy - 1)...(iy + 1) {
                let cellKey = (UInt64(bitPattern: Int64(cx)) &* 0x9E37_79B9_7F4A_7C15) ^ (UInt64(bitPattern: Int64(cy)) &* 0xC2B2_AE3D_27D4_EB4F)
                var cell = SeededRandom(seed: field.hotspotSeed ^ cellKey, stream: 1)
                guard cell.bernoulli(prob) else { continue }
                let hx = (Double(cx) + cell.uniform()) * c, hy = (Double(cy) + cell.uniform()) * c
                let peak = cell.sign() * cell.uniform(p.hotspotPeakDeg.lowerBound, p.hotspotPeakDeg.upperBound)
                let d2 = ((x - hx) * (x - hx) + (y - hy) * (y - hy)) / (r * r)
                guard d2 < 1 else { continue }
                inside = true
                total += peak * (1 - d2) * (1 - d2)
            }
        }
        return (total, inside)
    }

    /// The error at a point of a floor, degrees (no white noise).
    func disturbance(_ field: Field, x: Double, y: Double) -> Disturbance {
        let h = hotspot(field, x: x, y: y)
        return Disturbance(totalDeg: field.floorBiasDeg + field.smoothDeg(x: x, y: y) + h.deg, hotspotDeg: h.deg,
                           inHotspot: h.inside)
    }

    /// The walk's typical reported accuracy, degrees (drawn once per walk).
    func drawTypicalAccuracyDeg(rng: inout SeededRandom) -> Double {
        parameters.accuracyTypicalDeg * exp(rng.normal(sigma: parameters.accuracyLogSigma))
    }

    /// Core Location's `headingAccuracy` at a point, degrees (non-negative: the reading is valid).
    func reportedAccuracyDeg(typicalDeg: Double, disturbance: Disturbance) -> Double {
        typicalDeg + parameters.accuracyHotspotGain * abs(disturbance.hotspotDeg)
    }

    /// Heading reading, degrees in [0, 360), for a camera yaw (radians CCW from map +x).
    func reading(yawRad: Double, northOffsetDeg: Double, disturbanceDeg: Double, rng: inout SeededRandom) -> Double {
        let trueDeg = 90 - yawRad * 180 / Double.pi
        var h = northOffsetDeg + trueDeg + disturbanceDeg + rng.normal(sigma: parameters.noiseSigmaDeg)
        h = h.truncatingRemainder(dividingBy: 360)
        if h < 0 { h += 360 }
        return h >= 360 ? 0 : h
    }
}
