import Foundation

/// How the timestamps of a JSON-lines file must progress from one line to the next.
public enum BundleTimeOrder: Sendable {
    /// Each line's time is greater than the previous line's (frames, truth).
    case strictlyIncreasing
    /// Each line's time is at least the previous line's (observations: several per frame).
    case nonDecreasing
    /// No order (expected announcements).
    case unordered
}

/// A record stored one per line in a bundle's JSON-lines file. The reader and the writer apply the same
/// checks, so the writer can never produce a bundle the reader rejects.
public protocol BundleLineRecord: Codable, Sendable {
    /// File name inside the bundle directory (`frames.jsonl`...).
    static var fileName: String { get }
    /// Order the file's timestamps must follow.
    static var timeOrder: BundleTimeOrder { get }
    /// The timestamp the order applies to, seconds; nil when the record has none.
    var orderTime: Double? { get }
    /// Nil when every field is in range, otherwise what is wrong, in words. The reader refuses the file
    /// (`BundleError.Kind.invalidValue`); the writer refuses the record.
    func validationProblem() -> String?
    /// Nil when the record is physically plausible, otherwise why not. Checked after
    /// `validationProblem()`: the reader drops such a record with a `BundleWarning` (`.implausibleValue`,
    /// naming the file and first line) and keeps the rest of the file; the writer refuses it. Default: nil.
    func plausibilityProblem() -> String?
    /// Longest line the reader accepts in this record's file, bytes without the newline; a longer line is
    /// a `BundleError` (`.lineTooLong`) naming the file and line, and is never held in memory whole.
    /// Default `defaultMaximumLineBytes` (1 MiB); a record type with bulkier lines may raise it.
    static var maximumLineBytes: Int { get }
}

/// File names of every JSON-lines file of format v1, in the order `BundleWriter` lists them (an overwrite
/// removes these). A new record type adds its `fileName` here.
public let bundleLineFileNames = [FrameRecord.fileName, ObservationRecord.fileName, TruthRecord.fileName,
                                  ExpectedAnnouncement.fileName, PlaneRecord.fileName]

/// Default longest JSON-lines line, bytes: 1 MiB. Frame lines are about 500 bytes, observation lines
/// about 150, so this leaves room for any future field while bounding memory and decoding time.
public let defaultMaximumLineBytes = 1 << 20

extension BundleLineRecord {
    /// No plausibility rule beyond `validationProblem()`.
    public func plausibilityProblem() -> String? { nil }
    /// `defaultMaximumLineBytes`.
    public static var maximumLineBytes: Int { defaultMaximumLineBytes }
}

/// Largest tolerated deviation of the transform's bottom row from (0, 0, 0, 1) and of the rotation from
/// orthonormality (max |RᵀR − I| element). ARKit stores Float32 matrices: about 1e-7 off.
let transformTolerance = 1e-3

extension CameraIntrinsics {
    /// Nil when focal lengths and image size are positive and every number finite; otherwise the problem.
    public func validationProblem() -> String? {
        for (name, v) in [("fx", fx), ("fy", fy), ("cx", cx), ("cy", cy)] where !v.isFinite {
            return "intrinsics.\(name) is not a finite number"
        }
        if fx <= 0 || fy <= 0 { return "intrinsics focal lengths must be positive pixels, got fx \(fx), fy \(fy)" }
        if width <= 0 || height <= 0 { return "intrinsics image size must be positive, got \(width) x \(height)" }
        return nil
    }
}

/// True when `name` is a plain file name that stays inside images/ (no separators, not `.`/`..`).
func isSafeImageName(_ name: String) -> Bool {
    !name.isEmpty && name != "." && name != ".." && !name.contains("/") && !name.contains("\\") && !name.contains("\0")
}

extension FrameRecord: BundleLineRecord {
    /// `frames.jsonl`.
    public static let fileName = "frames.jsonl"
    /// Frames come at strictly increasing times.
    public static let timeOrder = BundleTimeOrder.strictlyIncreasing
    /// `t`.
    public var orderTime: Double? { t }

    /// Checks: finite time; 16 finite numbers; bottom row (0, 0, 0, 1) (catches row-major matrices);
    /// orthonormal rotation; valid intrinsics; compass heading in [0, 360]; safe image name; unsearched sign kinds
    /// non-empty and distinct.
    public func validationProblem() -> String? {
        guard t.isFinite else { return "timestamp t is not a finite number" }
        guard cameraToWorld.count == 16 else {
            return "cameraToWorld has \(cameraToWorld.count) numbers, expected 16 (a 4x4 matrix, column-major)"
        }
        if let i = cameraToWorld.firstIndex(where: { !$0.isFinite }) {
            return "cameraToWorld[\(i)] is not a finite number (\(cameraToWorld[i]))"
        }
        let m = cameraToWorld
        let bottom = [m[3], m[7], m[11], m[15]]
        if zip(bottom, [0.0, 0, 0, 1]).contains(where: { abs($0 - $1) > transformTolerance }) {
            return "cameraToWorld bottom row is (\(bottom.map { String($0) }.joined(separator: ", "))), expected (0, 0, 0, 1): "
                + "the matrix must be column-major with the translation in elements 12, 13, 14 (row-major input?)"
        }
        var worst = 0.0
        for a in 0..<3 {
            for b in 0..<3 {
                var dot = 0.0
                for k in 0..<3 { dot += m[a * 4 + k] * m[b * 4 + k] }
                worst = max(worst, abs(dot - (a == b ? 1 : 0)))
            }
        }
        if worst > transformTolerance {
            return "cameraToWorld rotation is not orthonormal (largest |RᵀR − I| element \(worst))"
        }
        if let p = intrinsics.validationProblem() { return p }
        if let h = relativeAltitudeMeters, !h.isFinite { return "relativeAltitudeMeters is not a finite number" }
        if let c = compassHeadingDeg, !(c.isFinite && c >= 0 && c <= 360) {
            return "compassHeadingDeg \(c) is outside 0...360 (write nil when the heading is unknown)"
        }
        if let a = compassAccuracyDeg, !(a.isFinite && a >= 0 && a <= 180) {
            return "compassAccuracyDeg \(a) is outside 0...180 (write nil when the accuracy is unknown or invalid)"
        }
        if let image, !isSafeImageName(image) {
            return "image name '\(image)' is not a plain file name inside images/"
        }
        if let kinds = unsearchedSignKinds {
            if kinds.contains(where: \.isEmpty) { return "unsearchedSignKinds holds an empty kind" }
            if Set(kinds).count != kinds.count { return "unsearchedSignKinds names a kind twice" }
        }
        return nil
    }
}

extension ObservationRecord: BundleLineRecord {
    /// `observations.jsonl`.
    public static let fileName = "observations.jsonl"
    /// Several observations may share a frame's time.
    public static let timeOrder = BundleTimeOrder.nonDecreasing
    /// `t`.
    public var orderTime: Double? { t }

    /// Checks: finite time; non-empty kind; range finite and > 0 m; bearing in [-pi, pi]; score in [0, 1]; text,
    /// landmarkId non-empty when present.
    public func validationProblem() -> String? {
        guard t.isFinite else { return "timestamp t is not a finite number" }
        if kind.isEmpty { return "kind is empty" }
        guard rangeMeters.isFinite else { return "rangeMeters is not a finite number" }
        if rangeMeters <= 0 {
            return "rangeMeters \(rangeMeters) is not positive (a horizontal distance camera -> sign, meters)"
        }
        guard bearingRad.isFinite, abs(bearingRad) <= Double.pi + 1e-9 else {
            return "bearingRad \(bearingRad) is outside [-pi, pi]"
        }
        guard score.isFinite, score >= 0, score <= 1 else { return "score \(score) is outside 0...1" }
        if let landmarkId, landmarkId.isEmpty { return "landmarkId is empty (omit it instead)" }
        if let text, text.isEmpty { return "text is empty (omit it when the legend was not read)" }
        return nil
    }

    /// Longest plausible sign range, meters: 100. A 0.21 m sign at 100 m is about 3 pixels tall at the
    /// iPhone's 1602-pixel focal length, below what any detector finds, and longer than most indoor
    /// lines of sight; a larger value (1e300) is a broken measurement.
    public static let maximumRangeMeters = 100.0

    /// Checks: `rangeMeters` at most `maximumRangeMeters`.
    public func plausibilityProblem() -> String? {
        if rangeMeters > Self.maximumRangeMeters {
            return "rangeMeters \(rangeMeters) is beyond the physical limit of \(Self.maximumRangeMeters) m for a sign sighting"
        }
        return nil
    }
}

extension TruthRecord: BundleLineRecord {
    /// `truth.jsonl`.
    public static let fileName = "truth.jsonl"
    /// One truth pose per time.
    public static let timeOrder = BundleTimeOrder.strictlyIncreasing
    /// `t`.
    public var orderTime: Double? { t }

    /// Checks: finite time, position and heading; non-empty floor id.
    public func validationProblem() -> String? {
        guard t.isFinite else { return "timestamp t is not a finite number" }
        guard x.isFinite, y.isFinite else { return "position (\(x), \(y)) is not finite" }
        guard headingRad.isFinite else { return "headingRad is not a finite number" }
        if floorId.isEmpty { return "floorId is empty" }
        return nil
    }
}

extension ExpectedAnnouncement: BundleLineRecord {
    /// `expected.jsonl`.
    public static let fileName = "expected.jsonl"
    /// Announcements are listed in any order.
    public static let timeOrder = BundleTimeOrder.unordered
    /// None.
    public var orderTime: Double? { nil }

    /// Checks: non-empty text; finite window bounds with notBefore <= notAfter.
    public func validationProblem() -> String? {
        if text.trimmingCharacters(in: .whitespacesAndNewlines).isEmpty { return "text is empty" }
        if let a = notBefore, !a.isFinite { return "notBefore is not a finite number" }
        if let b = notAfter, !b.isFinite { return "notAfter is not a finite number" }
        if let a = notBefore, let b = notAfter, a > b { return "notBefore \(a) is after notAfter \(b)" }
        return nil
    }
}

extension SessionInfo {
    /// Nil when session.json's content is usable; otherwise the problem. The version is checked separately.
    public func validationProblem() -> String? {
        guard signHeightMeters.isFinite, signHeightMeters > 0 else {
            return "signHeightMeters \(signHeightMeters) must be a positive number of meters"
        }
        if let p = intrinsics?.validationProblem() { return p }
        return nil
    }
}

// Decoding of the tracking enums with messages that list the accepted values.
extension TrackingState {
    /// Decodes the raw string; an unknown value throws `DecodingError.dataCorrupted` listing the valid ones.
    public init(from decoder: Decoder) throws {
        let c = try decoder.singleValueContainer()
        let s = try c.decode(String.self)
        guard let v = TrackingState(rawValue: s) else {
            throw DecodingError.dataCorruptedError(
                in: c, debugDescription: "unknown tracking state '\(s)' (expected normal, limited or notAvailable)")
        }
        self = v
    }
}

extension TrackingReason {
    /// Decodes the raw string; an unknown value throws `DecodingError.dataCorrupted` listing the valid ones.
    public init(from decoder: Decoder) throws {
        let c = try decoder.singleValueContainer()
        let s = try c.decode(String.self)
        guard let v = TrackingReason(rawValue: s) else {
            throw DecodingError.dataCorruptedError(
                in: c, debugDescription: "unknown tracking reason '\(s)' (expected initializing, excessiveMotion, "
                    + "insufficientFeatures or relocalizing)")
        }
        self = v
    }
}

/// For JSON text that parses but that the decoder refused as "not valid JSON" (Foundation's decoder says so
/// when a number does not fit the field's type, e.g. an integer field holding 1e23): the first number that no
/// record field can hold (magnitude of 2^53 or more, beyond exact integers), with its path; nil otherwise.
func outOfRangeNumberDescription(_ data: Data) -> String? {
    guard let root = try? JSONSerialization.jsonObject(with: data, options: [.fragmentsAllowed]) else { return nil }
    func find(_ value: Any, _ path: String) -> String? {
        if let d = value as? [String: Any] {
            for key in d.keys.sorted() {
                if let hit = find(d[key]!, path.isEmpty ? key : "\(path).\(key)") { return hit }
            }
        } else if let a = value as? [Any] {
            for (i, v) in a.enumerated() { if let hit = find(v, "\(path)[\(i)]") { return hit } }
        } else if let n = value as? NSNumber {
            let v = n.doubleValue
            if !v.isFinite || abs(v) >= 9_007_199_254_740_992 {
                return "field '\(path)' = \(v) is out of range (numbers must stay below 2^53 in magnitude)"
            }
        }
        return nil
    }
    return find(root, "") ?? "a value does not fit its field's type (e.g. a fraction where a whole number is expected)"
}

/// Words for a decoding failure: the field path and what was wrong.
func describeDecodingError(_ error: Error) -> String {
    func path(_ keys: [CodingKey]) -> String {
        var s = ""
        for k in keys {
            if let i = k.intValue { s += "[\(i)]" } else { s += s.isEmpty ? k.stringValue : ".\(k.stringValue)" }
        }
        return s
    }
    guard let e = error as? DecodingError else { return "\(error)" }
    switch e {
    case .keyNotFound(let key, let ctx):
        return "missing field '\(path(ctx.codingPath + [key]))'"
    case .valueNotFound(let type, let ctx):
        return "field '\(path(ctx.codingPath))' is null, expected \(type)"
    case .typeMismatch(let type, let ctx):
        if ctx.codingPath.isEmpty { return "expected a JSON object, got another kind of value" }
        var s = "field '\(path(ctx.codingPath))': expected \(type == Double.self ? "a number" : "\(type)")"
        if type == Double.self || type == Int.self {
            s += " (\(ctx.debugDescription)); non-finite numbers such as NaN or Infinity are not allowed"
        }
        return s
    case .dataCorrupted(let ctx):
        if ctx.codingPath.isEmpty { return ctx.debugDescription }
        return "field '\(path(ctx.codingPath))': \(ctx.debugDescription)"
    @unknown default:
        return "\(e)"
    }
}
