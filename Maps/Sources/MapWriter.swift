import Foundation

/// Writes map format v1: pretty-printed JSON with sorted keys (stable diffs), points as `[x, y]`.
public enum MapWriter {
    /// Encodes `building` after validating it (a file this writes always loads).
    /// - Throws: `MapError` when the building breaks a rule (file "<memory>"), or an encoding error.
    public static func encode(_ building: Building) throws -> Data {
        try MapValidator.validate(building)
        return try encodeUnvalidated(building)
    }

    /// Encodes without validation (for tests that need to write damaged maps).
    public static func encodeUnvalidated(_ building: Building) throws -> Data {
        let encoder = JSONEncoder()
        encoder.outputFormatting = [.prettyPrinted, .sortedKeys, .withoutEscapingSlashes]
        let pretty = String(decoding: try encoder.encode(building), as: UTF8.self)
        // Points on one line: "[\n  1.5,\n  2\n]" -> "[1.5, 2]" (raw newlines never occur inside JSON strings).
        let regex = try NSRegularExpression(pattern: #"\[\n\s*(-?[0-9][0-9.eE+-]*),\n\s*(-?[0-9][0-9.eE+-]*)\n\s*\]"#)
        let compact = regex.stringByReplacingMatches(in: pretty, range: NSRange(pretty.startIndex..., in: pretty),
                                                     withTemplate: "[$1, $2]")
        return Data((compact + "\n").utf8)
    }

    /// Validates and writes `building` to `url` atomically.
    /// - Throws: `MapError` or a file-system error.
    public static func write(_ building: Building, to url: URL) throws {
        try encode(building).write(to: url, options: .atomic)
    }
}
