import Foundation

/// A deterministic pseudo-random generator for the simulator: xoshiro256** (Blackman and Vigna, "Scrambled
/// linear pseudorandom number generators", 2018) seeded through SplitMix64, the seeding procedure its authors
/// recommend. The same seed gives the same stream on every platform; the simulator never uses
/// `SystemRandomNumberGenerator`.
///
/// Each noise source of a walk draws from its own stream (`SeededRandom(seed:stream:)`), so switching one model
/// on or off (images, false positives) does not change what the others draw.
public struct SeededRandom: RandomNumberGenerator, Sendable {
    private var s0: UInt64, s1: UInt64, s2: UInt64, s3: UInt64
    /// A spare standard normal from the last Box-Muller pair, if any.
    private var spareNormal: Double?

    /// Creates the generator for `seed`, independent substream `stream` (a small integer naming the consumer).
    public init(seed: UInt64, stream: UInt64 = 0) {
        var sm = seed ^ (stream &* 0xD1B5_4A32_D192_ED03)
        func next() -> UInt64 {
            sm &+= 0x9E37_79B9_7F4A_7C15
            var z = sm
            z = (z ^ (z >> 30)) &* 0xBF58_476D_1CE4_E5B9
            z = (z ^ (z >> 27)) &* 0x94D0_49BB_1331_11EB
            return z ^ (z >> 31)
        }
        s0 = next(); s1 = next(); s2 = next(); s3 = next()
        if s0 | s1 | s2 | s3 == 0 { s0 = 1 }
    }

    /// Next 64 random bits (xoshiro256**).
    public mutating func next() -> UInt64 {
        let result = rotl(s1 &* 5, 7) &* 9
        let t = s1 << 17
        s2 ^= s0; s3 ^= s1; s1 ^= s2; s0 ^= s3
        s2 ^= t
        s3 = rotl(s3, 45)
        return result
    }

    private func rotl(_ x: UInt64, _ k: UInt64) -> UInt64 { (x << k) | (x >> (64 - k)) }

    /// Uniform double in [0, 1) with 53 random bits.
    public mutating func uniform() -> Double { Double(next() >> 11) * 0x1.0p-53 }

    /// Uniform double in [lower, upper).
    public mutating func uniform(_ lower: Double, _ upper: Double) -> Double { lower + (upper - lower) * uniform() }

    /// True with probability `p`.
    public mutating func bernoulli(_ p: Double) -> Bool { uniform() < p }

    /// Standard normal N(0, 1) by the Box-Muller transform (both values of a pair are used).
    public mutating func normal() -> Double {
        if let z = spareNormal { spareNormal = nil; return z }
        var u1 = uniform()
        while u1 <= 1e-300 { u1 = uniform() }
        let u2 = uniform()
        let r = (-2 * log(u1)).squareRoot()
        spareNormal = r * sin(2 * Double.pi * u2)
        return r * cos(2 * Double.pi * u2)
    }

    /// Normal with mean `mean` and standard deviation `sigma`.
    public mutating func normal(mean: Double = 0, sigma: Double) -> Double { mean + sigma * normal() }

    /// Exponential waiting time with rate `ratePerSecond` (seconds); infinity when the rate is 0.
    public mutating func exponential(ratePerSecond: Double) -> Double {
        guard ratePerSecond > 0 else { return .infinity }
        return -log(max(1e-300, 1 - uniform())) / ratePerSecond
    }

    /// -1 or +1 with equal probability.
    public mutating func sign() -> Double { bernoulli(0.5) ? 1 : -1 }
}

/// Ornstein-Uhlenbeck process (mean-reverting random walk) with stationary standard deviation `sigma` and
/// correlation time `tauSeconds`, integrated exactly for any step: the slowly varying part of pitch, roll,
/// speed, lateral wander and compass disturbance.
struct OrnsteinUhlenbeck: Sendable {
    /// Stationary standard deviation, in the unit of the value.
    var sigma: Double
    /// Correlation time, seconds.
    var tauSeconds: Double
    /// Current value (starts from the stationary distribution).
    private(set) var value: Double

    init(sigma: Double, tauSeconds: Double, rng: inout SeededRandom) {
        self.sigma = sigma; self.tauSeconds = tauSeconds
        value = rng.normal(sigma: sigma)
    }

    /// Advances by `dt` seconds and returns the new value.
    mutating func step(dt: Double, rng: inout SeededRandom) -> Double {
        let a = exp(-dt / max(1e-9, tauSeconds))
        value = a * value + sigma * (1 - a * a).squareRoot() * rng.normal()
        return value
    }
}

/// Stream ids of the simulator's noise sources (see `SeededRandom(seed:stream:)`).
enum RandomStream: UInt64 {
    case walker = 1, phone, vio, detector, falsePositives, barometer, compass, route, tracking, lookAlikes, lookAlikeDetections, survey
}

/// Wraps an angle to (-pi, pi].
@inline(__always) func wrapAngle(_ a: Double) -> Double {
    var x = a.truncatingRemainder(dividingBy: 2 * Double.pi)
    if x > Double.pi { x -= 2 * Double.pi }
    if x <= -Double.pi { x += 2 * Double.pi }
    return x
}

/// Degrees to radians.
@inline(__always) func radians(_ degrees: Double) -> Double { degrees * Double.pi / 180 }
