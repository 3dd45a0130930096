import Foundation

/// Nesting depth of JSON text, measured before decoding. Foundation's JSONDecoder (Swift 6.3 toolchain) traps
/// instead of throwing on text that ends exactly at its 512-level nesting limit (e.g. 513 `[`; found by
/// wayfinder-fuzz, docs/fuzzing.md), so every reader of untrusted JSON (bundle lines, session.json, OCCaM
/// recordings) refuses deep nesting first. Hand-written: a bracket count, no parser needed.
public enum JSONNesting {
    /// Deepest nesting any Wayfinder JSON record needs is under 10 levels; readers refuse more than this.
    public static let maximumDepth = 64

    /// Deepest array/object nesting of JSON text: brackets and braces outside strings, counted without
    /// parsing (unbalanced text is measured as far as it goes).
    public static func depth<Bytes: Sequence>(_ bytes: Bytes) -> Int where Bytes.Element == UInt8 {
        var depth = 0, deepest = 0, inString = false, escaped = false
        for b in bytes {
            if inString {
                if escaped { escaped = false } else if b == UInt8(ascii: "\\") { escaped = true } else if b == UInt8(ascii: "\"") { inString = false }
                continue
            }
            switch b {
            case UInt8(ascii: "\""): inString = true
            case UInt8(ascii: "["), UInt8(ascii: "{"): depth += 1; deepest = max(deepest, depth)
            case UInt8(ascii: "]"), UInt8(ascii: "}"): depth -= 1
            default: break
            }
        }
        return deepest
    }
}
