/// Structure-aware byte mutations for text formats (JSON, JSON lines, CSV, YAML) and little-endian binary
/// headers (BMP). Every choice is drawn from the caller's `SplitMix64`, so a mutation is reproducible from
/// the generator's seed. Mutations are stacked (1 to 8 per input, fewer more likely), the way libFuzzer and
/// AFL stack theirs ("havoc").
struct Mutator {
    /// Largest input a mutation may produce, bytes (longer results are cut).
    static let maximumFileBytes = 1 << 20

    /// Numerals that break parsers and number conversions: signed zero, NaN and infinity spellings, values
    /// at and just past the Int32, UInt32, Int64 and UInt64 limits (2^63 traps `Int(Double)`), overflow to
    /// infinity (1e309), subnormals, long digit strings and malformed numerals.
    static let interestingNumbers: [String] = [
        "0", "-0", "-0.0", "1", "-1", "1e19", "-1e19", "1e308", "1e309", "-1e309", "2.2e-308", "4.9e-324", "1e-400",
        "NaN", "nan", "-nan", "inf", "-inf", "Infinity", "9223372036854775807", "9223372036854775808",
        "-9223372036854775808", "-9223372036854775809", "9.223372036854775807e18", "18446744073709551615",
        "18446744073709551616", "2147483647", "2147483648", "-2147483649", "4294967296", "65535", "65536", "65537",
        "1e9", "999999999", "0.5", "1.0000000000000002", "123456789012345678901234567890", "0x10", "1e", "--1", ".",
        "1.5e300", "-1e-7", "1E+2", "+1", "01", "3.0",
    ]

    /// Fragments that break tokenisers: quotes, escapes (NUL, lone surrogate), separators of every format
    /// in use, literals, YAML markers, invalid UTF-8 and CR LF.
    static let interestingFragments: [[UInt8]] = {
        let text = ["", "\"", "\\", "\\u0000", "\\ud800", "\\uDFFF", "\u{0}", "é", "\u{FFFD}", "\r\n", "\r", "\n", "\t",
                    ",", ";", ":", "[", "]", "{", "}", "null", "true", "false", "#", "---", "\n    ", "%YAML:1.0",
                    "\"\":", ",,", "[]", "{}", "\"x-a\": 1,", "  ", "\u{2028}"]
        return text.map { Array($0.utf8) } + [[0xC3, 0x28], [0xFF], [0xED, 0xA0, 0x80], [0xEF, 0xBB, 0xBF], [0x80]]
    }()

    /// Little-endian integers written over binary headers: 0, 1, sign-bit and all-ones patterns, and sizes
    /// around 2^16 (the BMP reader's size limit).
    static let interestingUInt32: [UInt32] = [0, 1, 2, 3, 4, 8, 16, 24, 32, 40, 54, 0x7F, 0x80, 0xFF, 0x100, 0x7FFF,
                                              0x8000, 0xFFFF, 0x1_0000, 0x1_0001, 0x7FFF_FFFF, 0x8000_0000,
                                              0xFFFF_FFFF, 0xFFFF_FFFE, 1078, 1024, 256, 257]

    /// Applies 1 to 8 stacked mutations to `bytes`; `donors` are same-named files of other corpus entries
    /// (for splicing); `binary` selects header-aware integer writes over text-token mutations.
    static func mutate(_ bytes: [UInt8], donors: [[UInt8]], binary: Bool, rng: inout SplitMix64) -> [UInt8] {
        var b = bytes
        let count = 1 + min(rng.below(8), rng.below(8))  // 1...8, small counts more likely
        for _ in 0..<count {
            b = mutateOnce(b, donors: donors, binary: binary, rng: &rng)
            if b.count > maximumFileBytes { b.removeLast(b.count - maximumFileBytes) }
        }
        return b
    }

    static func mutateOnce(_ input: [UInt8], donors: [[UInt8]], binary: Bool, rng: inout SplitMix64) -> [UInt8] {
        var b = input
        let kinds = binary ? 12 : 16
        switch rng.below(kinds) {
        case 0:  // bit flip
            guard !b.isEmpty else { return [rng.pick([0x30, 0x5B, 0x7B])] }
            b[rng.below(b.count)] ^= UInt8(1) << UInt8(rng.below(8))
        case 1:  // interesting or random byte
            guard !b.isEmpty else { return b }
            b[rng.below(b.count)] = rng.chance(0.5) ? UInt8(truncatingIfNeeded: rng.next())
                : rng.pick([0, 1, 0x7F, 0x80, 0xFF, 0x22, 0x2C, 0x0A, 0x30, 0x39, 0x2D, 0x2E, 0x5B, 0x7D, 0x3A, 0x20])
        case 2:  // insert random bytes
            let n = 1 + rng.below(8)
            b.insert(contentsOf: (0..<n).map { _ in UInt8(truncatingIfNeeded: rng.next()) }, at: rng.below(b.count + 1))
        case 3:  // delete a range
            guard !b.isEmpty else { return b }
            let start = rng.below(b.count), len = 1 + rng.below(min(64, b.count - start))
            b.removeSubrange(start..<(start + len))
        case 4:  // duplicate a range somewhere
            guard !b.isEmpty else { return b }
            let start = rng.below(b.count), len = 1 + rng.below(min(rng.chance(0.2) ? 4096 : 64, b.count - start))
            b.insert(contentsOf: Array(b[start..<(start + len)]), at: rng.below(b.count + 1))
        case 5:  // truncate
            guard !b.isEmpty else { return b }
            b.removeSubrange(rng.below(b.count)..<b.count)
        case 6:  // splice: prefix of this file + suffix of another entry's same-named file
            guard let d = donors.isEmpty ? nil : rng.pick(donors), !d.isEmpty else { return b }
            let cut = rng.below(b.count + 1), from = rng.below(d.count)
            b = Array(b[..<cut]) + Array(d[from...])
        case 7:  // overwrite with a chunk of a donor
            guard let d = donors.isEmpty ? nil : rng.pick(donors), !d.isEmpty, !b.isEmpty else { return b }
            let from = rng.below(d.count), len = 1 + rng.below(min(256, d.count - from))
            let at = rng.below(b.count)
            b.replaceSubrange(at..<min(b.count, at + len), with: d[from..<(from + len)])
        case 8, 9:  // little-endian integer over a header field (binary) / at a random place
            guard b.count >= 4 else { return b }
            let at = binary && rng.chance(0.7) ? rng.below(min(64, b.count - 3)) : rng.below(b.count - 3)
            var v = rng.pick(interestingUInt32)
            if rng.chance(0.2) { v = v &+ UInt32(bitPattern: Int32(rng.below(5) - 2)) }
            let width = rng.chance(0.3) ? 2 : 4
            for k in 0..<width { b[at + k] = UInt8(truncatingIfNeeded: v >> (8 * UInt32(k))) }
        case 10:  // repeat the whole file (size growth)
            let times = 2 + rng.below(3)
            b = Array([[UInt8]](repeating: b, count: times).joined())
        case 11:  // interesting fragment inserted
            b.insert(contentsOf: rng.pick(interestingFragments), at: rng.below(b.count + 1))
        case 12, 13:  // replace a numeral token with an extreme value
            guard let r = numberToken(in: b, near: rng.below(b.count + 1)) else {
                b.insert(contentsOf: Array(rng.pick(interestingNumbers).utf8), at: rng.below(b.count + 1))
                return b
            }
            b.replaceSubrange(r, with: Array(rng.pick(interestingNumbers).utf8))
        case 14:  // line-level: duplicate, delete or swap lines, or copy a donor's line
            b = mutateLines(b, donors: donors, rng: &rng)
        default:  // deep nesting or a long string
            let depth = rng.pick([64, 200, 512, 513, 1000, 5000, 100_000])
            let at = rng.below(b.count + 1)
            switch rng.below(5) {
            case 0: b.insert(contentsOf: [UInt8](repeating: 0x5B, count: depth) + [UInt8](repeating: 0x5D, count: depth), at: at)
            case 1: b.insert(contentsOf: Array(String(repeating: "{\"a\":", count: depth).utf8) + [0x31]
                                 + [UInt8](repeating: 0x7D, count: depth), at: at)
            case 2: b.insert(contentsOf: [UInt8](repeating: 0x5B, count: depth), at: at)  // unbalanced
            case 3:  // unbalanced, and the text (line) ends right after: parsers' limit checks at end of input
                var end = at
                while end < b.count && b[end] != 0x0A { end += 1 }
                b.replaceSubrange(at..<end, with: [UInt8](repeating: rng.chance(0.5) ? 0x5B : 0x7B, count: depth))
            default: b.insert(contentsOf: [0x22] + [UInt8](repeating: 0x41, count: depth) + [0x22], at: at)
            }
        }
        return b
    }

    /// Range of the numeral token at or after `position` (wrapping to the start once): a maximal run of
    /// digits, signs, '.', 'e' and 'E' holding at least one digit.
    static func numberToken(in b: [UInt8], near position: Int) -> Range<Int>? {
        func isNumeral(_ c: UInt8) -> Bool { (c >= 0x30 && c <= 0x39) || c == 0x2D || c == 0x2B || c == 0x2E || c == 0x65 || c == 0x45 }
        func isDigit(_ c: UInt8) -> Bool { c >= 0x30 && c <= 0x39 }
        for start in [position, 0] {
            var i = start
            while i < b.count && !isDigit(b[i]) { i += 1 }
            guard i < b.count else { continue }
            var lo = i, hi = i
            while lo > 0 && isNumeral(b[lo - 1]) { lo -= 1 }
            while hi < b.count && isNumeral(b[hi]) { hi += 1 }
            return lo..<hi
        }
        return nil
    }

    static func mutateLines(_ b: [UInt8], donors: [[UInt8]], rng: inout SplitMix64) -> [UInt8] {
        func lineRange(in s: [UInt8], at p: Int) -> Range<Int> {
            var lo = min(p, s.count), hi = min(p, s.count)
            while lo > 0 && s[lo - 1] != 0x0A { lo -= 1 }
            while hi < s.count && s[hi] != 0x0A { hi += 1 }
            return lo..<min(hi + 1, s.count)
        }
        guard !b.isEmpty else { return b }
        var out = b
        let r = lineRange(in: b, at: rng.below(b.count))
        switch rng.below(4) {
        case 0: out.insert(contentsOf: Array(b[r]), at: r.lowerBound)
        case 1: out.removeSubrange(r)
        case 2:
            let r2 = lineRange(in: b, at: rng.below(b.count))
            guard r2 != r else { return out }
            let (first, second) = r.lowerBound < r2.lowerBound ? (r, r2) : (r2, r)
            guard first.upperBound <= second.lowerBound else { return out }
            out = Array(b[..<first.lowerBound]) + Array(b[second]) + Array(b[first.upperBound..<second.lowerBound])
                + Array(b[first]) + Array(b[second.upperBound...])
        default:
            guard let d = donors.isEmpty ? nil : rng.pick(donors), !d.isEmpty else { return out }
            out.insert(contentsOf: Array(d[lineRange(in: d, at: rng.below(d.count))]), at: r.lowerBound)
        }
        return out
    }
}
