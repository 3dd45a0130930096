import Foundation

/// Deterministic 64-bit generator for the Swift tests (SplitMix64, Steele, Lea and Flood 2014, as in
/// java.util.SplittableRandom): a fixed seed gives the same sequence on every platform, so randomised tests
/// are reproducible. One copy shared by the test targets. Not for production randomness.
public struct SplitMix64: RandomNumberGenerator {
    /// Generator state; advanced by the golden-ratio increment on every draw.
    public var state: UInt64

    /// Starts the sequence at `seed`.
    public init(seed: UInt64) { state = seed }

    /// Next 64 random bits.
    public mutating func next() -> UInt64 {
        state &+= 0x9E37_79B9_7F4A_7C15
        var z = state
        z = (z ^ (z >> 30)) &* 0xBF58_476D_1CE4_E5B9
        z = (z ^ (z >> 27)) &* 0x94D0_49BB_1331_11EB
        return z ^ (z >> 31)
    }

    /// Uniform in [0, 1) (the top 53 bits).
    public mutating func unit() -> Double { Double(next() >> 11) / Double(1 << 53) }

    /// Uniform in [a, b).
    public mutating func uniform(_ a: Double, _ b: Double) -> Double { a + (b - a) * unit() }

    /// Uniform integer in [0, n), n > 0 (modulo reduction: a bias below 2^-40 for the small n of the tests).
    public mutating func int(_ n: Int) -> Int { Int(next() % UInt64(n)) }

    /// Standard normal draw (Box-Muller, the cosine branch).
    public mutating func normal() -> Double {
        let u = max(unit(), 1e-12), v = unit()
        return (-2 * log(u)).squareRoot() * cos(2 * .pi * v)
    }
}
