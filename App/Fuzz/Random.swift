/// SplitMix64 pseudo-random generator (Steele, Lea and Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014): 64-bit state, one multiply-xorshift finaliser per draw. Used so that every fuzz
/// input is a pure function of (seed, target, iteration index) and can be regenerated from those alone.
struct SplitMix64: RandomNumberGenerator {
    /// Generator state.
    private(set) var state: UInt64

    /// Starts at `seed`.
    init(seed: UInt64) { state = seed }

    /// The generator for iteration `index` of `target` under `seed`: the three are mixed through the
    /// SplitMix finaliser so neighbouring indices give unrelated streams.
    init(seed: UInt64, target: String, index: UInt64) {
        var h: UInt64 = 0xcbf2_9ce4_8422_2325  // FNV-1a over the target name
        for b in target.utf8 { h = (h ^ UInt64(b)) &* 0x0000_0100_0000_01b3 }
        state = SplitMix64.mix(seed ^ SplitMix64.mix(h ^ SplitMix64.mix(index &+ 0x9e37_79b9_7f4a_7c15)))
    }

    /// The SplitMix64 output finaliser.
    static func mix(_ z0: UInt64) -> UInt64 {
        var z = z0
        z = (z ^ (z >> 30)) &* 0xbf58_476d_1ce4_e5b9
        z = (z ^ (z >> 27)) &* 0x94d0_49bb_1331_11eb
        return z ^ (z >> 31)
    }

    /// Next 64 random bits.
    mutating func next() -> UInt64 {
        state &+= 0x9e37_79b9_7f4a_7c15
        return SplitMix64.mix(state)
    }

    /// Uniform integer in 0..<n (n > 0).
    mutating func below(_ n: Int) -> Int { Int(next() % UInt64(max(n, 1))) }

    /// True with probability `p`.
    mutating func chance(_ p: Double) -> Bool { Double(next() >> 11) / Double(1 << 53) < p }

    /// A random element of a non-empty array.
    mutating func pick<T>(_ a: [T]) -> T { a[below(a.count)] }
}
