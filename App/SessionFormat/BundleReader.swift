import Foundation

/// A recorded session read into memory: the one reader of bundle format v1 (docs/session-format.md), used
/// by replay, the simulator's tests and `wayfinder inspect`. For recordings too long to hold in memory,
/// iterate `FramesReader` instead (same checks).
public struct SessionBundle: Sendable {
    /// The bundle directory.
    public var url: URL
    /// session.json.
    public var info: SessionInfo
    /// frames.jsonl, in file order (strictly increasing `t`). Never empty.
    public var frames: [FrameRecord]
    /// observations.jsonl (empty when the file is absent), non-decreasing `t`.
    public var observations: [ObservationRecord]
    /// truth.jsonl (empty when absent), strictly increasing `t`.
    public var truth: [TruthRecord]
    /// expected.jsonl (empty when absent), file order.
    public var expected: [ExpectedAnnouncement]
    /// Problems the reader recovered from (truncated last line, missing images).
    public var warnings: [BundleWarning]
    /// planes.jsonl after screening (empty when absent): ARKit plane-anchor events, non-decreasing `t`
    /// (PlaneRecords.swift).
    public var planes: [PlaneRecord] = []

    /// Creates a bundle value in memory (nothing is read or written).
    public init(url: URL, info: SessionInfo, frames: [FrameRecord], observations: [ObservationRecord] = [],
                truth: [TruthRecord] = [], expected: [ExpectedAnnouncement] = [], warnings: [BundleWarning] = []) {
        self.url = url; self.info = info; self.frames = frames; self.observations = observations
        self.truth = truth; self.expected = expected; self.warnings = warnings
    }

    /// Directory holding the frames' images.
    public var imagesDirectory: URL { url.appendingPathComponent(imagesDirectoryName, isDirectory: true) }

    /// URL of the image a frame names (nil when the frame has none). The file may be missing (see warnings).
    public func imageURL(for frame: FrameRecord) -> URL? {
        frame.image.map { imagesDirectory.appendingPathComponent($0) }
    }

    /// Reads and checks the bundle directory at `url`.
    ///
    /// Throws `BundleError` (naming the file and line) when: the directory or session.json or frames.jsonl
    /// is missing; session.json is not JSON, lacks a field or has an unsupported formatVersion; a line of
    /// any .jsonl file is not JSON or not a valid record (wrong field types, unknown tracking state, a
    /// transform without 16 finite numbers or not column-major, non-positive intrinsics, non-positive
    /// range...); timestamps repeat or go back; frames.jsonl has no frame.
    /// Recovers with a `BundleWarning` from: a cut-off last line of any .jsonl file (dropped), frames
    /// naming images absent from images/.
    public static func read(from url: URL) throws -> SessionBundle {
        var isDir: ObjCBool = false
        guard FileManager.default.fileExists(atPath: url.path, isDirectory: &isDir) else {
            throw BundleError(.missingDirectory, file: url.path, reason: "session bundle directory not found")
        }
        guard isDir.boolValue else {
            throw BundleError(.notADirectory, file: url.path,
                              reason: "is a file; a session bundle is a directory holding session.json and frames.jsonl")
        }
        let info = try readSessionInfo(url.appendingPathComponent(sessionFileName))
        var warnings: [BundleWarning] = []

        let framesReader = try FramesReader(bundle: url)
        var frames: [FrameRecord] = []
        var imageLines: [Int: Int] = [:]   // frame index -> line number, for frames naming an image
        while let f = try framesReader.next() {
            if f.image != nil { imageLines[frames.count] = framesReader.lineNumber }
            frames.append(f)
        }
        warnings += framesReader.warnings
        if frames.isEmpty {
            throw BundleError(.noFrames, file: framesReader.url.path,
                              reason: "no frames (the file has no complete frame line)")
        }
        func optional<R: BundleLineRecord>(_ type: R.Type) throws -> [R] {
            let fileURL = url.appendingPathComponent(R.fileName)
            guard FileManager.default.fileExists(atPath: fileURL.path) else { return [] }
            let reader = try RecordLineReader<R>(url: fileURL)
            let records = try reader.readAll()
            warnings += reader.warnings
            return records
        }
        let observations = try optional(ObservationRecord.self)
        let truth = try optional(TruthRecord.self)
        let expected = try optional(ExpectedAnnouncement.self)

        // Images: a missing file is a warning (poses and observations still replay; only the detector
        // stage lacks its input). One warning for all of them, naming the first.
        let imagesDir = url.appendingPathComponent(imagesDirectoryName, isDirectory: true)
        var missing: [(line: Int, name: String)] = []
        for (i, f) in frames.enumerated() {
            guard let name = f.image else { continue }
            if !FileManager.default.fileExists(atPath: imagesDir.appendingPathComponent(name).path) {
                missing.append((imageLines[i] ?? i + 1, name))
            }
        }
        if let first = missing.first {
            warnings.append(BundleWarning(
                .missingImages, file: framesReader.url.path, line: first.line,
                reason: "\(missing.count) of \(frames.filter { $0.image != nil }.count) frames name images missing "
                    + "from images/ (first: '\(first.name)')"))
        }
        // Plane anchors (optional file; PlaneRecords.swift reads and screens it).
        let (planes, planeWarnings) = try readPlaneRecords(bundle: url, frames: frames)
        var bundle = SessionBundle(url: url, info: info, frames: frames, observations: observations, truth: truth,
                                   expected: expected, warnings: warnings + planeWarnings)
        bundle.planes = planes
        return bundle
    }

    /// Reads and checks session.json alone.
    public static func readSessionInfo(_ fileURL: URL) throws -> SessionInfo {
        guard FileManager.default.fileExists(atPath: fileURL.path) else {
            throw BundleError(.missingFile, file: fileURL.path, reason: "file not found (every bundle has session.json)")
        }
        let data: Data
        do { data = try Data(contentsOf: fileURL) } catch {
            throw BundleError(.unreadableFile, file: fileURL.path, reason: "cannot read: \(error.localizedDescription)")
        }
        let object: Any
        do { object = try JSONSerialization.jsonObject(with: data) } catch {
            throw BundleError(.invalidJSON, file: fileURL.path, reason: "not valid JSON: \(jsonSyntaxDetail(data))")
        }
        guard let dict = object as? [String: Any] else {
            throw BundleError(.invalidRecord, file: fileURL.path, reason: "expected a JSON object")
        }
        guard let version = dict["formatVersion"] as? Int else {
            throw BundleError(.invalidRecord, file: fileURL.path, reason: "missing or non-integer field 'formatVersion'")
        }
        guard version == sessionFormatVersion else {
            throw BundleError(.unsupportedVersion, file: fileURL.path,
                              reason: "unsupported formatVersion \(version) (this build reads version \(sessionFormatVersion))")
        }
        let info: SessionInfo
        do { info = try JSONDecoder().decode(SessionInfo.self, from: data) } catch {
            throw BundleError(.invalidRecord, file: fileURL.path, reason: "not a valid SessionInfo: \(describeDecodingError(error))")
        }
        if let problem = info.validationProblem() {
            throw BundleError(.invalidValue, file: fileURL.path, reason: problem)
        }
        return info
    }
}

/// Name of the bundle's session description file.
public let sessionFileName = "session.json"
/// Name of the bundle's image directory.
public let imagesDirectoryName = "images"
