import Foundation
import Maps
import SessionFormat

/// Records a walk as a recorded-session bundle (format v1) through the shared `BundleWriter`, so a
/// recording from the phone replays on Linux with `wayfinder replay`. Images are optional and subsampled
/// by the caller. Owns its writer; not thread-safe.
///
/// Nothing lost at a kill (docs/session-format.md): the writer hands each frame line to the OS as it is
/// appended (`flushEveryLines: 1`) in one `write`, and a frame's image is written atomically before its
/// line, so an app killed at any moment leaves every frame but at most a partial last line, and every
/// image a kept frame names (tested by RecorderKillTests with SIGKILL at random moments).
public final class WalkRecorder {
    /// The bundle folder being written.
    public let directory: URL
    private let writer: BundleWriter
    private var imageCount = 0
    private var lastT = -Double.infinity
    /// Frames written so far.
    public private(set) var frameCount = 0
    /// Surveyed spots marked during the walk (marks.jsonl; truth.jsonl at `close` from two or more).
    public private(set) var marks: [SurveyMark] = []
    private var track: [SurveyedTruth.TrackPoint] = []
    private var truthWritten = false
    /// The time of the last frame written, seconds (the clock a mark is stamped with).
    public var lastFrameT: Double? { lastT.isFinite ? lastT : nil }

    /// Starts a bundle in `directory` for a walk in `building` (session.json written at once). The session's
    /// `signHeightMeters` is the building's Exit-sign face height (`Building.signCatalogue`) unless given;
    /// `carry` is the traveler's lanyard-mode setting, recorded as session.json's `carry` ("handheld" / "lanyard").
    public init(directory: URL, building: Building, floorId: String?, startId: String?, destinationId: String?,
                device: String, appVersion: String, signHeightMeters: Double? = nil, carry: PhoneCarry = .handheld) throws {
        self.directory = directory
        let catalogue = building.signCatalogue
        let signHeightMeters = signHeightMeters ?? catalogue.heightMeters(kind: SignKindSpec.defaultExit.kind)
            ?? SignKindSpec.defaultExit.heightMeters
        let info = SessionInfo(device: device, appVersion: appVersion, mapId: building.id, floorId: floorId, start: startId,
                               destination: destinationId, signHeightMeters: signHeightMeters, carry: carry.rawValue)
        writer = try BundleWriter(directory: directory, info: info, flushEveryLines: 1)
    }

    /// Appends one frame (and its JPEG, if given). Frames without a finite pose, or out of time order,
    /// are skipped rather than written: the bundle must stay readable.
    public func append(frame: PipelineFrame, jpeg: Data?) throws {
        guard frame.t > lastT, frame.cameraPose != nil else { return }
        var imageName: String?
        if let jpeg {
            imageCount += 1
            let name = String(format: "%06d.jpg", imageCount)
            try writer.writeImage(named: name, data: jpeg)
            imageName = name
        }
        guard let record = FrameConversion.record(of: frame, imageName: imageName) else { return }
        try writer.append(record)
        lastT = frame.t
        frameCount += 1
        if let p = SurveyedTruth.TrackPoint(record) { track.append(p) }
    }

    /// Marks that the walker stands at a surveyed spot now (at the last frame's time), appended to
    /// marks.jsonl at once. Throws when no frame was recorded yet (nothing to stamp it with).
    public func mark(placeId: String, floorId: String, x: Double, y: Double) throws {
        guard let t = lastFrameT else { throw PipelineError.frame("a surveyed spot can be marked only after the first frame") }
        let m = SurveyMark(t: t, placeId: placeId, floorId: floorId, x: x, y: y)
        marks.append(m)
        let e = JSONEncoder()
        e.outputFormatting = [.sortedKeys]
        var line = try e.encode(m)
        line.append(0x0A)
        let url = directory.appendingPathComponent(Self.marksFileName)
        if let handle = try? FileHandle(forWritingTo: url) {
            defer { try? handle.close() }
            try handle.seekToEnd()
            try handle.write(contentsOf: line)
        } else {
            try line.write(to: url)
        }
    }

    /// The bundle's extra file of surveyed spots (one `SurveyMark` JSON object per line).
    public static let marksFileName = "marks.jsonl"

    /// Writes truth.jsonl from the marks (`SurveyedTruth`); returns the problem when it cannot (fewer than
    /// two spots, several floors), nil when written or when nothing was marked.
    @discardableResult
    public func writeSurveyedTruth() -> String? {
        guard !marks.isEmpty, !truthWritten else { return nil }
        truthWritten = true
        do {
            for r in try SurveyedTruth.truth(track: track, marks: marks) { try writer.append(r) }
            return nil
        } catch {
            return "\(directory.lastPathComponent): no truth.jsonl: \(error)"
        }
    }

    /// Appends ARKit plane-anchor events to planes.jsonl. Events the writer refuses (out of time order, bad
    /// values) are skipped: the bundle must stay readable.
    public func append(planes: [PlaneRecord]) {
        for p in planes { try? writer.append(p) }
    }

    /// Finishes the bundle (truth.jsonl first, when spots were marked: `writeSurveyedTruth`).
    public func close() throws {
        writeSurveyedTruth()
        try writer.close()
    }

    /// A bundle folder name for a walk started at `date`: "walk-2026-11-22T14-05-09".
    public static func folderName(for date: Date) -> String {
        let f = ISO8601DateFormatter()
        f.formatOptions = [.withFullDate, .withTime, .withColonSeparatorInTime]
        return "walk-" + f.string(from: date).replacingOccurrences(of: ":", with: "-")
    }
}
