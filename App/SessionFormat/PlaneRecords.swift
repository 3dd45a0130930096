import Foundation

// planes.jsonl: the ARKit plane anchors of a recording (optional file of bundle format v1, schema
// docs/schemas/planes.schema.json, docs/session-format.md "planes.jsonl"). One line per ARPlaneAnchor event
// (ARSessionDelegate didAdd / didUpdate / didRemove), in ARKit world coordinates like frames.jsonl.
// Reading: `readPlaneRecords` (called by `SessionBundle.read`) validates each line (errors name the file and
// line) and screens the whole file against the frames (recovered problems become `BundleWarning`s).

/// What happened to a plane anchor.
public enum PlaneEvent: String, Codable, Sendable, CaseIterable {
    /// ARKit detected a new plane (`session(_:didAdd:)`).
    case add
    /// ARKit refined the plane's pose or extent (`session(_:didUpdate:)`), or merged another plane into it.
    case update
    /// ARKit dropped the plane (`session(_:didRemove:)`): merged into another anchor or discarded.
    case remove

    /// Decodes the raw string; an unknown value throws `DecodingError.dataCorrupted` listing the valid ones.
    public init(from decoder: Decoder) throws {
        let c = try decoder.singleValueContainer()
        let s = try c.decode(String.self)
        guard let v = PlaneEvent(rawValue: s) else {
            throw DecodingError.dataCorruptedError(in: c, debugDescription: "unknown plane event '\(s)' (expected add, update or remove)")
        }
        self = v
    }
}

/// ARPlaneAnchor.Alignment.
public enum PlaneAlignment: String, Codable, Sendable, CaseIterable {
    /// A wall-like plane (the only kind the localizer uses).
    case vertical
    /// A floor- or table-like plane (ignored by the localizer, warned about by the reader).
    case horizontal

    /// Decodes the raw string; an unknown value throws `DecodingError.dataCorrupted` listing the valid ones.
    public init(from decoder: Decoder) throws {
        let c = try decoder.singleValueContainer()
        let s = try c.decode(String.self)
        guard let v = PlaneAlignment(rawValue: s) else {
            throw DecodingError.dataCorruptedError(in: c, debugDescription: "unknown plane alignment '\(s)' (expected vertical or horizontal)")
        }
        self = v
    }
}

/// One ARPlaneAnchor event: a line of planes.jsonl.
public struct PlaneRecord: Codable, Hashable, Sendable {
    /// Timestamp of the ARKit frame that delivered the event, seconds (the clock of frames.jsonl).
    public var t: Double
    /// The anchor's identifier (ARAnchor.identifier, a UUID string; any non-empty string).
    public var anchorId: String
    /// What happened.
    public var event: PlaneEvent
    /// Vertical (walls) or horizontal.
    public var alignment: PlaneAlignment
    /// Center of the plane in the ARKit world, meters, `[x, y, z]` (y up): the anchor's transform applied to
    /// ARPlaneAnchor.center. Required for add and update.
    public var centerInWorld: [Double]?
    /// Unit normal of the plane in the ARKit world, `[x, y, z]` (the anchor's local +y axis; horizontal for
    /// a vertical plane). Required for add and update.
    public var normalInWorld: [Double]?
    /// Horizontal extent of the plane along the wall, meters (>= 0). Required for add and update.
    public var widthMeters: Double?
    /// Vertical extent of the plane, meters (>= 0), when known.
    public var heightMeters: Double?
    /// ARPlaneAnchor.classification on LiDAR phones (`wall`, `door`, `window`, `seat`, `table`, `none`...);
    /// nil when the phone cannot classify.
    public var classification: String?

    /// Creates a plane record.
    public init(t: Double, anchorId: String, event: PlaneEvent, alignment: PlaneAlignment = .vertical,
                centerInWorld: [Double]? = nil, normalInWorld: [Double]? = nil, widthMeters: Double? = nil,
                heightMeters: Double? = nil, classification: String? = nil) {
        self.t = t; self.anchorId = anchorId; self.event = event; self.alignment = alignment
        self.centerInWorld = centerInWorld; self.normalInWorld = normalInWorld; self.widthMeters = widthMeters
        self.heightMeters = heightMeters; self.classification = classification
    }

    /// Plane center on the VIO floor plane `(east, north) = (x_w, -z_w)`, meters (nil for a remove event or
    /// a missing center).
    public var centerInVIOPlane: (east: Double, north: Double)? {
        guard let c = centerInWorld, c.count == 3 else { return nil }
        return (c[0], -c[2])
    }

    /// Direction of the plane's normal on the VIO floor plane, radians CCW from VIO east (nil when the normal
    /// is missing or vertical).
    public var normalYawInVIOPlaneRad: Double? {
        guard let n = normalInWorld, n.count == 3, hypot(n[0], n[2]) > 1e-6 else { return nil }
        return atan2(-n[2], n[0])
    }
}

/// Largest tolerated |length - 1| of a plane normal.
let planeNormalTolerance = 1e-2
/// Largest tolerated vertical component of a vertical plane's unit normal (sin 15 degrees).
let verticalPlaneMaxNormalY = 0.26

extension PlaneRecord: BundleLineRecord {
    /// `planes.jsonl`.
    public static let fileName = "planes.jsonl"
    /// Several anchors may change in one frame.
    public static let timeOrder = BundleTimeOrder.nonDecreasing
    /// `t`.
    public var orderTime: Double? { t }

    /// Checks: finite time; non-empty anchor id; add and update carry a finite 3-element center, a finite unit
    /// normal (horizontal within 15 degrees for vertical planes) and a finite width >= 0 m (height too when
    /// given); non-empty classification when given. A zero extent is valid here (ARKit's first report can be
    /// a point) and screened out later with a warning.
    public func validationProblem() -> String? {
        guard t.isFinite else { return "timestamp t is not a finite number" }
        if anchorId.isEmpty { return "anchorId is empty" }
        if let classification, classification.isEmpty { return "classification is empty (omit it instead)" }
        if event == .remove { return nil }
        guard let c = centerInWorld else { return "\(event.rawValue) event without centerInWorld (x, y, z meters in the ARKit world)" }
        guard c.count == 3 else { return "centerInWorld has \(c.count) numbers, expected 3 (x, y, z)" }
        if let i = c.firstIndex(where: { !$0.isFinite }) { return "centerInWorld[\(i)] is not a finite number (\(c[i]))" }
        guard let n = normalInWorld else { return "\(event.rawValue) event without normalInWorld (unit vector in the ARKit world)" }
        guard n.count == 3 else { return "normalInWorld has \(n.count) numbers, expected 3 (x, y, z)" }
        if let i = n.firstIndex(where: { !$0.isFinite }) { return "normalInWorld[\(i)] is not a finite number (\(n[i]))" }
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).squareRoot()
        if abs(length - 1) > planeNormalTolerance { return "normalInWorld has length \(length), expected a unit vector" }
        if alignment == .vertical && abs(n[1]) > verticalPlaneMaxNormalY {
            return "normalInWorld (\(n.map { String($0) }.joined(separator: ", "))) of a vertical plane is not horizontal "
                + "(its y component must be within +-\(verticalPlaneMaxNormalY); y is up in the ARKit world)"
        }
        guard let w = widthMeters else { return "\(event.rawValue) event without widthMeters" }
        guard w.isFinite, w >= 0 else { return "widthMeters \(w) is not a finite number >= 0" }
        if let h = heightMeters, !(h.isFinite && h >= 0) { return "heightMeters \(h) is not a finite number >= 0" }
        return nil
    }
}

/// Narrowest plane the screening keeps, meters: narrower add/update events (zero extent) are dropped.
public let minimumPlaneWidthMeters = 0.05

/// True for a frame whose tracking state starts a new VIO session or may move the world origin: ARKit is
/// unavailable, relocalizing, or initializing again. Anchors last placed before such a spell are stale until
/// ARKit updates them.
public func isVIOResetState(_ tracking: TrackingState, _ reason: TrackingReason?) -> Bool {
    tracking == .notAvailable || reason == .relocalizing || reason == .initializing
}

/// Times at which a VIO reset spell begins (see `isVIOResetState`), the session's initial `initializing`
/// spell excluded. Frames must be in time order.
public func vioResetTimes(_ frames: [FrameRecord]) -> [Double] {
    var out: [Double] = []
    var inReset = true   // the first frames of a session are initializing: not a reset
    for f in frames {
        let r = isVIOResetState(f.tracking, f.trackingReason)
        if r && !inReset { out.append(f.t) }
        inReset = r
    }
    return out
}

/// Reads and screens `planes.jsonl` of the bundle at `bundle` (empty result when the file is absent).
///
/// Throws `BundleError` naming the file and line for a line that is not a valid `PlaneRecord` (NaN or
/// missing pose, non-unit normal, negative extent, unknown event) or goes back in time. Recovers with
/// `BundleWarning`s (kind `.ignoredPlanes`, one per problem, naming the first line concerned) and drops:
/// horizontal planes; add/update events narrower than `minimumPlaneWidthMeters` (zero extent); events outside
/// the frames' time span; updates of an anchor never added (kept, as an add) and removes of an unknown
/// anchor. Warns about anchors last placed before a VIO reset and not updated after it (replay does not use
/// them after the reset). Ignores the whole file, with a warning, when it holds at least 3 anchors and not a
/// single update: ARKit refines every anchor within seconds, so such a file comes from a recorder that logs
/// only additions, or a frozen session, and its planes cannot be trusted.
public func readPlaneRecords(bundle: URL, frames: [FrameRecord]) throws -> (planes: [PlaneRecord], warnings: [BundleWarning]) {
    let fileURL = bundle.appendingPathComponent(PlaneRecord.fileName)
    // The bundle's file policy (regular files only, no link leaving the bundle): BundleFileAccess.
    guard case .regularFile = try BundleFileAccess.resolve(fileURL, root: BundleFileAccess.resolvedRoot(bundle)) else {
        return ([], [])
    }
    let reader = try RecordLineReader<PlaneRecord>(bundle: bundle)
    var lines: [(record: PlaneRecord, line: Int)] = []
    while let r = try reader.next() { lines.append((r, reader.lineNumber)) }
    let screened = screenPlaneRecords(lines, frames: frames, file: fileURL.path)
    return (screened.planes, reader.warnings + screened.warnings)
}

/// The screening of `readPlaneRecords` on records already read (`line`: 1-based line in `file`).
public func screenPlaneRecords(_ lines: [(record: PlaneRecord, line: Int)], frames: [FrameRecord],
                               file: String) -> (planes: [PlaneRecord], warnings: [BundleWarning]) {
    var warnings: [BundleWarning] = []
    func warn(_ count: Int, _ firstLine: Int, _ reason: String) {
        guard count > 0 else { return }
        warnings.append(BundleWarning(.ignoredPlanes, file: file, line: firstLine, reason: reason))
    }
    let t0 = (frames.first?.t ?? -Double.infinity) - 1, t1 = (frames.last?.t ?? Double.infinity) + 1
    var kept: [(record: PlaneRecord, line: Int)] = []
    var horizontal = (0, 0), narrow = (0, 0), outside = (0, 0), orphanUpdates = (0, 0), orphanRemoves = (0, 0)
    var live = Set<String>()
    func note(_ c: inout (Int, Int), _ line: Int) { if c.0 == 0 { c.1 = line }; c.0 += 1 }
    for (r, line) in lines {
        if r.alignment == .horizontal { note(&horizontal, line); continue }
        if r.t < t0 || r.t > t1 { note(&outside, line); continue }
        switch r.event {
        case .add, .update:
            if (r.widthMeters ?? 0) < minimumPlaneWidthMeters { note(&narrow, line); continue }
            if r.event == .update && !live.contains(r.anchorId) { note(&orphanUpdates, line) }
            live.insert(r.anchorId)
        case .remove:
            if live.remove(r.anchorId) == nil { note(&orphanRemoves, line); continue }
        }
        kept.append((r, line))
    }
    warn(horizontal.0, horizontal.1, "\(horizontal.0) horizontal plane event(s) ignored (the localizer uses walls only)")
    warn(narrow.0, narrow.1, "\(narrow.0) add/update event(s) with an extent under \(minimumPlaneWidthMeters) m (zero extent) ignored")
    warn(outside.0, outside.1, "\(outside.0) plane event(s) outside the frames' time span ignored")
    warn(orphanUpdates.0, orphanUpdates.1, "\(orphanUpdates.0) update(s) of an anchor never added; taken as additions")
    warn(orphanRemoves.0, orphanRemoves.1, "\(orphanRemoves.0) remove event(s) of an unknown anchor ignored")

    // A file whose anchors never update.
    let adds = kept.filter { $0.record.event == .add }
    let anchors = Set(kept.map(\.record.anchorId))
    if anchors.count >= 3 && !kept.contains(where: { $0.record.event == .update }) {
        warn(1, adds.first?.line ?? 1, "none of the \(anchors.count) plane anchors is ever updated (ARKit refines every anchor "
                 + "within seconds: a recorder that logs only additions, or a frozen session); planes not used")
        return ([], warnings)
    }

    // Anchors last placed before a VIO reset and never updated after it.
    let resets = vioResetTimes(frames)
    if !resets.isEmpty {
        var lastPlaced: [String: (t: Double, line: Int)] = [:]
        var removedAt: [String: Double] = [:]
        for (r, line) in kept {
            if r.event == .remove { removedAt[r.anchorId] = r.t } else { lastPlaced[r.anchorId] = (r.t, line); removedAt[r.anchorId] = nil }
        }
        var stale = 0, firstLine = Int.max, firstReset = 0.0
        for (id, placed) in lastPlaced where removedAt[id] == nil {
            if let reset = resets.first(where: { $0 > placed.t }) {
                stale += 1
                if placed.line < firstLine { firstLine = placed.line; firstReset = reset }
            }
        }
        warn(stale, firstLine == Int.max ? 1 : firstLine,
             "\(stale) plane anchor(s) last placed before a VIO reset (first: reset at t=\(firstReset)) and never updated "
                 + "after it: not used after the reset")
    }
    return (kept.map(\.record), warnings)
}
