import Foundation

/// One sighting of a sign read from a range-observation CSV (the input of `wayfinder range`).
public struct RangeObservationRow: Sendable {
    /// 1-based line number in the file (the header is line 1).
    public var lineNumber: Int
    /// Raw image width, pixels.
    public var imageWidthPx: Int
    /// Raw image height, pixels.
    public var imageHeightPx: Int
    /// Raw-image intrinsics, pixels.
    public var intrinsics: RangeEstimator.Intrinsics
    /// Camera orientation: `camera_to_world` when the row has one, else `pitch_rad` and `roll_rad`.
    public var orientation: RangeEstimator.Orientation
    /// Raw-image corners TL, TR, BR, BL of the upright sign, pixels.
    public var corners: [(u: Double, v: Double)]
    /// Sign face height, meters.
    public var signHeightMeters: Double
    /// Sign face width, meters (PnP), when given.
    public var signWidthMeters: Double?
    /// Camera height above the floor, meters (horizon method), when given.
    public var cameraHeightMeters: Double?
    /// Height of the sign's centre above the floor, meters (horizon method), when given.
    public var signCenterHeightMeters: Double?
    /// Measured (true) range, meters, when given: the CLI reports the percent error against it.
    public var trueRangeMeters: Double?

    /// The raw <-> unrolled pixel mapping of this row's camera roll (for slice measurements taken on the
    /// unrolled image).
    public func unrollMapping() throws -> UnrollMapping {
        try UnrollMapping(intrinsics: intrinsics, rollRad: try orientation.pitchAndRoll().rollRad,
                          imageWidthPx: Double(imageWidthPx), imageHeightPx: Double(imageHeightPx))
    }

    /// Runs one method on this row.
    public func estimate(_ method: RangeMethod) throws -> RangeEstimate {
        try RangeEstimator.estimateFull(method: method, corners: corners, intrinsics: intrinsics,
                                        orientation: orientation, signHeightMeters: signHeightMeters,
                                        signWidthMeters: signWidthMeters, cameraHeightMeters: cameraHeightMeters,
                                        signCenterHeightMeters: signCenterHeightMeters)
    }
}

/// A malformed range-observation CSV: the file, the 1-based line and what is wrong.
public struct RangeCSVError: Error, Equatable, CustomStringConvertible {
    /// File name as given by the caller.
    public var fileName: String
    /// 1-based line number (1 = header); 0 when the file cannot be read at all.
    public var lineNumber: Int
    /// What is wrong.
    public var message: String
    /// "file:line: message" ("file: message" for whole-file problems, line 0).
    public var description: String { lineNumber > 0 ? "\(fileName):\(lineNumber): \(message)" : "\(fileName): \(message)" }
}

/// Reader of range-observation CSVs (docs/range-estimation.md, "CSV input").
///
/// A header line is required; columns are found by name, in any order; unknown columns are an error (a
/// misspelt optional column would otherwise be silently ignored). Blank lines and lines starting with '#' are
/// skipped. Required: image_width, image_height, fx, fy, cx, cy, u_tl, v_tl, u_tr, v_tr, u_br, v_br, u_bl,
/// v_bl, sign_height_m, and per row either pitch_rad and roll_rad, or camera_to_world (16 numbers separated
/// by ';', column-major, ARKit order), which wins when both are given. Optional (may be empty per row):
/// sign_width_m, camera_height_m, sign_center_height_m, true_range_m.
public enum RangeCSV {
    /// Columns every file must have.
    public static let requiredColumns = ["image_width", "image_height", "fx", "fy", "cx", "cy",
                                         "u_tl", "v_tl", "u_tr", "v_tr", "u_br", "v_br", "u_bl", "v_bl",
                                         "sign_height_m"]
    /// Columns a file may have.
    public static let optionalColumns = ["pitch_rad", "roll_rad", "camera_to_world", "sign_width_m",
                                         "camera_height_m", "sign_center_height_m", "true_range_m"]

    /// Parses the text of a file; `fileName` only labels errors.
    public static func parse(_ text: String, fileName: String) throws -> [RangeObservationRow] {
        // "\r\n" is one Character in Swift, and a newline: splitting on isNewline handles both line ends.
        var lines = text.split(omittingEmptySubsequences: false, whereSeparator: \.isNewline)
        if lines.last == "" { lines.removeLast() }
        guard let headerIndex = lines.firstIndex(where: { !isSkippable($0) }) else {
            throw RangeCSVError(fileName: fileName, lineNumber: 1, message: "empty file: a header line is required")
        }
        let header = lines[headerIndex].split(separator: ",", omittingEmptySubsequences: false)
            .map { $0.trimmingCharacters(in: .whitespaces) }
        let headerLine = headerIndex + 1
        var column: [String: Int] = [:]
        for (i, name) in header.enumerated() {
            guard requiredColumns.contains(name) || optionalColumns.contains(name) else {
                throw RangeCSVError(fileName: fileName, lineNumber: headerLine,
                                    message: "unknown column '\(name)' (expected \((requiredColumns + optionalColumns).joined(separator: ", ")))")
            }
            guard column[name] == nil else {
                throw RangeCSVError(fileName: fileName, lineNumber: headerLine, message: "column '\(name)' appears twice")
            }
            column[name] = i
        }
        if let missing = requiredColumns.first(where: { column[$0] == nil }) {
            throw RangeCSVError(fileName: fileName, lineNumber: headerLine, message: "missing required column '\(missing)'")
        }
        let hasPitchRoll = column["pitch_rad"] != nil && column["roll_rad"] != nil
        guard hasPitchRoll || column["camera_to_world"] != nil else {
            throw RangeCSVError(fileName: fileName, lineNumber: headerLine,
                                message: "need columns pitch_rad and roll_rad, or camera_to_world")
        }

        var rows: [RangeObservationRow] = []
        for index in (headerIndex + 1)..<lines.count where !isSkippable(lines[index]) {
            let lineNumber = index + 1
            let fields = lines[index].split(separator: ",", omittingEmptySubsequences: false)
                .map { $0.trimmingCharacters(in: .whitespaces) }
            func fail(_ message: String) -> RangeCSVError {
                RangeCSVError(fileName: fileName, lineNumber: lineNumber, message: message)
            }
            guard fields.count == header.count else {
                throw fail("\(fields.count) fields, the header has \(header.count)")
            }
            func text(_ name: String) -> String? {
                guard let i = column[name], !fields[i].isEmpty else { return nil }
                return fields[i]
            }
            func optionalNumber(_ name: String) throws -> Double? {
                guard let s = text(name) else { return nil }
                guard let v = Double(s), v.isFinite else { throw fail("\(name) is not a finite number: '\(s)'") }
                return v
            }
            func number(_ name: String) throws -> Double {
                guard let v = try optionalNumber(name) else { throw fail("\(name) is empty") }
                return v
            }
            func positive(_ name: String, _ v: Double?) throws -> Double? {
                if let v, !(v > 0) { throw fail("\(name) must be > 0, got \(v)") }
                return v
            }
            func positiveInt(_ name: String) throws -> Int {
                let v = try number(name)
                guard v > 0, v == v.rounded(), v < 1e9 else { throw fail("\(name) must be a positive integer, got \(v)") }
                return Int(v)
            }

            let width = try positiveInt("image_width"), height = try positiveInt("image_height")
            let k = RangeEstimator.Intrinsics(fx: try positive("fx", number("fx"))!, fy: try positive("fy", number("fy"))!,
                                              cx: try number("cx"), cy: try number("cy"))
            let orientation: RangeEstimator.Orientation
            if let m = text("camera_to_world") {
                let parts = m.split(separator: ";", omittingEmptySubsequences: false)
                    .map { $0.trimmingCharacters(in: .whitespaces) }
                guard parts.count == 16 else { throw fail("camera_to_world needs 16 ';'-separated numbers, got \(parts.count)") }
                var values: [Double] = []
                for p in parts {
                    guard let v = Double(p), v.isFinite else { throw fail("camera_to_world has a non-number: '\(p)'") }
                    values.append(v)
                }
                orientation = .cameraToWorld(values)
            } else if text("pitch_rad") != nil || text("roll_rad") != nil {
                orientation = .pitchRoll(pitchRad: try number("pitch_rad"), rollRad: try number("roll_rad"))
            } else {
                throw fail("no orientation: give pitch_rad and roll_rad, or camera_to_world")
            }
            let corners: [(u: Double, v: Double)] = [
                (try number("u_tl"), try number("v_tl")), (try number("u_tr"), try number("v_tr")),
                (try number("u_br"), try number("v_br")), (try number("u_bl"), try number("v_bl")),
            ]
            rows.append(RangeObservationRow(
                lineNumber: lineNumber, imageWidthPx: width, imageHeightPx: height, intrinsics: k,
                orientation: orientation, corners: corners,
                signHeightMeters: try positive("sign_height_m", number("sign_height_m"))!,
                signWidthMeters: try positive("sign_width_m", optionalNumber("sign_width_m")),
                cameraHeightMeters: try optionalNumber("camera_height_m"),
                signCenterHeightMeters: try optionalNumber("sign_center_height_m"),
                trueRangeMeters: try positive("true_range_m", optionalNumber("true_range_m"))))
        }
        return rows
    }

    /// Reads and parses a file. Throws RangeCSVError (line 0) when it cannot be read.
    public static func read(path: String) throws -> [RangeObservationRow] {
        guard let data = FileManager.default.contents(atPath: path) else {
            throw RangeCSVError(fileName: path, lineNumber: 0, message: "cannot read the file")
        }
        guard let text = String(data: data, encoding: .utf8) else {
            throw RangeCSVError(fileName: path, lineNumber: 0, message: "not UTF-8 text")
        }
        return try parse(text, fileName: path)
    }

    private static func isSkippable(_ line: Substring) -> Bool {
        let t = line.trimmingCharacters(in: .whitespaces)
        return t.isEmpty || t.hasPrefix("#")
    }
}
