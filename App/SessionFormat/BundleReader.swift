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
    /// Problems the reader recovered from (truncated last line, missing images, dropped implausible records).
    public var warnings: [BundleWarning]
    /// planes.jsonl after screening (empty when absent): ARKit plane-anchor events, non-decreasing `t`
    /// (PlaneRecords.swift).
    public var planes: [PlaneRecord] = []
    /// 1-based line of each observation in observations.jsonl (parallel to `observations`), for messages
    /// that name the line; empty for bundles built in memory.
    public var observationLineNumbers: [Int]

    /// Creates a bundle value in memory (nothing is read or written).
    public init(url: URL, info: SessionInfo, frames: [FrameRecord], observations: [ObservationRecord] = [],
                truth: [TruthRecord] = [], expected: [ExpectedAnnouncement] = [], warnings: [BundleWarning] = [],
                observationLineNumbers: [Int] = []) {
        self.url = url; self.info = info; self.frames = frames; self.observations = observations
        self.truth = truth; self.expected = expected; self.warnings = warnings
        self.observationLineNumbers = observationLineNumbers
    }

    /// Path of observations.jsonl.
    public var observationsFile: URL { url.appendingPathComponent(ObservationRecord.fileName) }

    /// `PATH line N` of observation `index` (`PATH` alone when the line is unknown), for messages.
    public func observationLocation(_ index: Int) -> String {
        if index < observationLineNumbers.count { return "\(observationsFile.path) line \(observationLineNumbers[index])" }
        return observationsFile.path
    }

    /// Directory holding the frames' images.
    public var imagesDirectory: URL { url.appendingPathComponent(imagesDirectoryName, isDirectory: true) }

    /// URL of the image a frame names (nil when the frame has none). The file may be missing (see warnings).
    public func imageURL(for frame: FrameRecord) -> URL? {
        frame.image.map { imagesDirectory.appendingPathComponent($0) }
    }

    /// The image a frame names when it is actually there: a regular file inside the bundle (links
    /// resolved, as the reader's policy requires). Nil when the frame names none, the file is missing, or
    /// it is refused (a link leaving the bundle, a FIFO...). Checks the file system on each call.
    public func presentImageURL(for frame: FrameRecord) -> URL? {
        guard let u = imageURL(for: frame),
              case .regularFile(let p)? = try? BundleFileAccess.resolve(u, root: BundleFileAccess.resolvedRoot(url)) else {
            return nil
        }
        return URL(fileURLWithPath: p)
    }

    /// Reads and checks the bundle directory at `url`.
    ///
    /// Throws `BundleError` (naming the file and line) when: the directory or session.json or frames.jsonl
    /// is missing; a bundle file is not a regular file (FIFO, device...) or a link leaving the bundle;
    /// session.json is not JSON, lacks a field, is over 1 MiB or has an unsupported formatVersion; a line
    /// of any .jsonl file is over its length limit, not JSON or not a valid record (wrong field types,
    /// unknown tracking state, a transform without 16 finite numbers or not column-major, non-positive
    /// intrinsics, non-positive range...); timestamps repeat or go back; frames.jsonl has no frame.
    /// Recovers with a `BundleWarning` from: a cut-off last line of any .jsonl file (dropped), frames
    /// naming images absent from images/, implausible records (an observation range over 100 m: dropped).
    public static func read(from url: URL) throws -> SessionBundle {
        var isDir: ObjCBool = false
        guard FileManager.default.fileExists(atPath: url.path, isDirectory: &isDir) else {
            if BundleFileAccess.realPath(url.path).error == ELOOP {
                throw BundleError(.linkOutsideBundle, file: url.path, reason: "symbolic link loop, not a bundle directory")
            }
            if BundleFileAccess.isSymbolicLink(url.path) {
                throw BundleError(.missingDirectory, file: url.path, reason: "is a symbolic link to nothing (no bundle directory)")
            }
            throw BundleError(.missingDirectory, file: url.path, reason: "session bundle directory not found")
        }
        guard isDir.boolValue else {
            throw BundleError(.notADirectory, file: url.path,
                              reason: "is a file; a session bundle is a directory holding session.json and frames.jsonl")
        }
        let root = BundleFileAccess.resolvedRoot(url)
        let info = try readSessionInfo(url.appendingPathComponent(sessionFileName), bundleRoot: url)
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
        // Optional files: absent (or a link to nothing) means no records.
        func optional<R: BundleLineRecord>(_ type: R.Type) throws -> (records: [R], lines: [Int]) {
            let fileURL = url.appendingPathComponent(R.fileName)
            guard case .regularFile = try BundleFileAccess.resolve(fileURL, root: root) else { return ([], []) }
            let reader = try RecordLineReader<R>(bundle: url)
            let read = try reader.readAllWithLineNumbers()
            warnings += reader.warnings
            return read
        }
        let (observations, observationLines) = try optional(ObservationRecord.self)
        let truth = try optional(TruthRecord.self).records
        let expected = try optional(ExpectedAnnouncement.self).records

        // Images: a missing file is a warning (poses and observations still replay; only the detector
        // stage lacks its input). One warning for all of them, naming the first. An image that is a link
        // leaving the bundle, or not a regular file, is an error (the same policy as every bundle file).
        let imagesDir = url.appendingPathComponent(imagesDirectoryName, isDirectory: true)
        var missing: [(line: Int, name: String)] = []
        for (i, f) in frames.enumerated() {
            guard let name = f.image else { continue }
            let target: BundleFileAccess.Target
            do { target = try BundleFileAccess.resolve(imagesDir.appendingPathComponent(name), root: root) } catch var e as BundleError {
                e.reason += " (image named by \(framesReader.url.path) line \(imageLines[i] ?? i + 1))"
                throw e
            }
            if case .missing = target { missing.append((imageLines[i] ?? i + 1, name)) }
        }
        // images/ itself may not lead out of the bundle, even when no frame names an image.
        if let resolvedImages = BundleFileAccess.realPath(imagesDir.path).path,
           !BundleFileAccess.isInside(resolvedImages, root: root) {
            throw BundleError(.linkOutsideBundle, file: imagesDir.path,
                              reason: "is a symbolic link to \(resolvedImages), outside the bundle directory \(root); links "
                                  + "that leave the bundle are refused (docs/session-format.md)")
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
                                   expected: expected, warnings: warnings + planeWarnings,
                                   observationLineNumbers: observationLines)
        bundle.planes = planes
        return bundle
    }

    /// Reads and checks session.json alone. `bundleRoot` is the bundle directory the file must stay in
    /// (default: the directory holding it); it must be a regular file of at most `maximumSessionFileBytes`.
    public static func readSessionInfo(_ fileURL: URL, bundleRoot: URL? = nil) throws -> SessionInfo {
        let root = BundleFileAccess.resolvedRoot(bundleRoot ?? fileURL.deletingLastPathComponent())
        let data: Data
        do {
            data = try BundleFileAccess.openForReading(fileURL, root: root).readAll(limit: maximumSessionFileBytes)
        } catch var e as BundleError where e.kind == .missingFile {
            e.reason += " (every bundle has session.json)"
            throw e
        }
        // Foundation's JSON parsers trap on text ending at their 512-level limit (JSONNesting).
        let depth = JSONNesting.depth(data)
        guard depth <= JSONNesting.maximumDepth else {
            throw BundleError(.invalidJSON, file: fileURL.path,
                              reason: "JSON nested \(depth) levels deep (at most \(JSONNesting.maximumDepth) accepted)")
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
            if case DecodingError.dataCorrupted(let ctx) = error, ctx.codingPath.isEmpty,
               let range = outOfRangeNumberDescription(data) {
                throw BundleError(.invalidRecord, file: fileURL.path, reason: "not a valid SessionInfo: \(range)")
            }
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
