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

/// Core Location's heading indoors: the true heading (degrees clockwise from map north, plus the building's
/// north offset) disturbed by a smooth random field over the floor (steel, wiring: sum of plane waves of
/// 3-15 m wavelength, standard deviation 15 degrees, clipped at 30) and white noise.
struct CompassModel {
    let parameters: CompassParameters

    /// A plane-wave disturbance field per floor index.
    struct Field {
        var waves: [(kx: Double, ky: Double, phase: Double, amplitude: Double)]
        func value(x: Double, y: Double) -> Double { waves.reduce(0) { $0 + $1.amplitude * cos($1.kx * x + $1.ky * y + $1.phase) } }
    }

    func makeField(rng: inout SeededRandom) -> Field {
        let p = parameters
        let n = 4
        let amplitude = p.disturbanceSigmaDeg * (2.0 / Double(n)).squareRoot()
        var waves: [(Double, Double, Double, Double)] = []
        for _ in 0..<n {
            let lambda = rng.uniform(p.disturbanceWavelengthRangeMeters.lowerBound, p.disturbanceWavelengthRangeMeters.upperBound)
            let dir = rng.uniform(0, 2 * Double.pi)
            let k = 2 * Double.pi / lambda
            waves.append((k * cos(dir), k * sin(dir), rng.uniform(0, 2 * Double.pi), amplitude))
        }
        return Field(waves: waves)
    }

    /// Disturbance at a point, degrees (clipped).
    func disturbance(_ field: Field, x: Double, y: Double) -> Double {
        max(-parameters.disturbanceMaxDeg, min(parameters.disturbanceMaxDeg, field.value(x: x, y: y)))
    }

    /// Heading reading, degrees in [0, 360), for a camera yaw (radians CCW from map +x).
    func reading(yawRad: Double, northOffsetDeg: Double, disturbanceDeg: Double, rng: inout SeededRandom) -> Double {
        let trueDeg = 90 - yawRad * 180 / Double.pi
        var h = northOffsetDeg + trueDeg + disturbanceDeg + rng.normal(sigma: parameters.noiseSigmaDeg)
        h = h.truncatingRemainder(dividingBy: 360)
        if h < 0 { h += 360 }
        return h
    }
}
