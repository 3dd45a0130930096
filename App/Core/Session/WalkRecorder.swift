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

    /// Starts a bundle in `directory` for a walk in `building` (session.json written at once). The session's
    /// `signHeightMeters` is the building's Exit-sign face height (`Building.signCatalogue`) unless given.
    public init(directory: URL, building: Building, floorId: String?, startId: String?, destinationId: String?,
                device: String, appVersion: String, signHeightMeters: Double? = nil) throws {
        self.directory = directory
        let catalogue = building.signCatalogue
        let signHeightMeters = signHeightMeters ?? catalogue.heightMeters(kind: SignKindSpec.defaultExit.kind)
            ?? SignKindSpec.defaultExit.heightMeters
        let info = SessionInfo(device: device, appVersion: appVersion, mapId: building.id, floorId: floorId, start: startId,
                               destination: destinationId, signHeightMeters: signHeightMeters, carry: "handheld")
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
    }

    /// Appends ARKit plane-anchor events to planes.jsonl. Events the writer refuses (out of time order, bad
    /// values) are skipped: the bundle must stay readable.
    public func append(planes: [PlaneRecord]) {
        for p in planes { try? writer.append(p) }
    }

    /// Finishes the bundle.
    public func close() throws { try writer.close() }

    /// A bundle folder name for a walk started at `date`: "walk-2026-11-22T14-05-09".
    public static func folderName(for date: Date) -> String {
        let f = ISO8601DateFormatter()
        f.formatOptions = [.withFullDate, .withTime, .withColonSeparatorInTime]
        return "walk-" + f.string(from: date).replacingOccurrences(of: ":", with: "-")
    }
}
