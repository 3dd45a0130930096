import Foundation

/// A reader for the flat YAML of the iNavigate map files (info.yml, OpenCV FileStorage mapFeatures_N.yml):
/// top-level `key: value` lines and `key:` lines opening a record whose fields are the following
/// indented `key: value` lines. Indentation may mix tabs and spaces (the survey files do): any indented
/// line belongs to the current record. `%YAML` directives, `---` and `#` comments are skipped. Flow
/// lists `[a, b]` and `[a   b]` (OpenCV writes both) are read by `numbers(_:)`. Not a general YAML parser.
public struct SimpleYAML: Sendable {
    /// A record opened by `key:` at column 0, with its fields in file order.
    public struct Record: Sendable {
        /// The opening key (e.g. `floor`, `map_feature`).
        public let key: String
        /// 1-based line of the opening key.
        public let line: Int
        /// Field name -> raw value text (trimmed; quotes removed).
        public let fields: [String: String]
    }
    /// Top-level `key: value` scalars.
    public let scalars: [String: String]
    /// Records in file order.
    public let records: [Record]

    /// Why a YAML file could not be read.
    public struct ParseError: Error, CustomStringConvertible, Sendable {
        /// File name or path.
        public let file: String
        /// 1-based line number.
        public let line: Int
        /// What is wrong.
        public let reason: String
        /// `file:line: reason`.
        public var description: String { "\(file):\(line): \(reason)" }
    }

    /// Parses `text`; `file` is used in errors.
    /// - Throws: `ParseError` for a line that is not `key: value` / `key:`.
    public init(text: String, file: String) throws {
        var scalars: [String: String] = [:]
        var records: [Record] = []
        var current: (key: String, line: Int, fields: [String: String])?
        func close() { if let c = current { records.append(Record(key: c.key, line: c.line, fields: c.fields)) }; current = nil }
        for (i, rawLine) in text.split(separator: "\n", omittingEmptySubsequences: false).enumerated() {
            let lineNo = i + 1
            var line = String(rawLine)
            if line.hasSuffix("\r") { line.removeLast() }
            let trimmed = line.trimmingCharacters(in: .whitespaces)
            if trimmed.isEmpty || trimmed.hasPrefix("#") || trimmed.hasPrefix("%") || trimmed == "---" || trimmed == "..." { continue }
            let indented = line.first == " " || line.first == "\t"
            guard let colon = trimmed.firstIndex(of: ":") else {
                throw ParseError(file: file, line: lineNo, reason: "expected 'key: value', got \"\(trimmed)\"")
            }
            let key = trimmed[..<colon].trimmingCharacters(in: .whitespaces)
            var value = trimmed[trimmed.index(after: colon)...].trimmingCharacters(in: .whitespaces)
            if let hash = value.range(of: " #") { value = String(value[..<hash.lowerBound]).trimmingCharacters(in: .whitespaces) }
            if value.count >= 2, (value.hasPrefix("\"") && value.hasSuffix("\"")) || (value.hasPrefix("'") && value.hasSuffix("'")) {
                value = String(value.dropFirst().dropLast())
            }
            guard !key.isEmpty else { throw ParseError(file: file, line: lineNo, reason: "empty key") }
            if indented {
                guard current != nil else {
                    throw ParseError(file: file, line: lineNo, reason: "indented field '\(key)' outside any record")
                }
                current!.fields[key] = value
            } else if value.isEmpty {
                close()
                current = (key, lineNo, [:])
            } else {
                close()
                scalars[key] = value
            }
        }
        close()
        self.scalars = scalars
        self.records = records
    }

    /// The numbers of a flow list `[a, b, c]` or `[a b c]`; nil when the text is not such a list of numbers.
    public static func numbers(_ text: String) -> [Double]? {
        let t = text.trimmingCharacters(in: .whitespaces)
        guard t.hasPrefix("["), t.hasSuffix("]") else { return nil }
        let parts = t.dropFirst().dropLast().split { $0 == "," || $0 == " " || $0 == "\t" }
        var out: [Double] = []
        for p in parts {
            guard let v = Double(p), v.isFinite else { return nil }
            out.append(v)
        }
        return out
    }
}
