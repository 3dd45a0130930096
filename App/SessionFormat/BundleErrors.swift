import Foundation

/// Why a session bundle could not be read or written. Every error names the file (path as opened) and,
/// for JSON-lines files, the 1-based line, plus a reason a person can act on. `description` reads
/// `PATH line N: REASON` (or `PATH: REASON` when no line applies).
public struct BundleError: Error, FileLineMessage, Equatable, Sendable {
    /// The category of the problem, for code that reacts to it (tests, the CLI's exit code).
    public enum Kind: String, Sendable, Codable {
        /// The bundle directory does not exist.
        case missingDirectory
        /// The bundle path exists but is a plain file.
        case notADirectory
        /// A mandatory file (session.json, frames.jsonl) is absent.
        case missingFile
        /// A file exists but could not be opened or read (permissions, I/O error).
        case unreadableFile
        /// A bundle file is a FIFO, a device (`/dev/zero`), a socket or a directory: refused before reading.
        case notARegularFile
        /// A bundle file is a symbolic link (or lies under one) resolving outside the bundle directory, or a
        /// link loop: refused (docs/session-format.md, "Links and special files").
        case linkOutsideBundle
        /// A JSON-lines line is longer than its file's limit (`BundleLineRecord.maximumLineBytes`).
        case lineTooLong
        /// A whole-file read (session.json) is larger than its limit (`maximumSessionFileBytes`).
        case fileTooLarge
        /// A line (or session.json) is not valid JSON, or a line was cut off in the middle of the file.
        case invalidJSON
        /// Valid JSON but not the expected record: missing field, wrong type, unknown enum value.
        case invalidRecord
        /// session.json's formatVersion is not one this build reads.
        case unsupportedVersion
        /// A field holds a value outside its valid range (non-finite number, 15-element transform,
        /// negative range, non-positive focal length...).
        case invalidValue
        /// A timestamp goes back in time relative to the previous line of the same file.
        case timestampOrder
        /// Two consecutive lines of a file that needs strictly increasing time carry the same timestamp.
        case duplicateTimestamp
        /// frames.jsonl holds no frame.
        case noFrames
        /// An image name is not a plain file name (holds '/', is '..', empty...).
        case unsafeImageName
        /// The writer refused to replace an existing non-empty bundle or image.
        case alreadyExists
        /// Writing to disk failed.
        case writeFailed
        /// The writer was already closed.
        case closed
    }

    /// Category.
    public var kind: Kind
    /// Path of the file (or directory) concerned, as opened.
    public var file: String
    /// 1-based line number in a JSON-lines file, nil when the problem is not tied to a line.
    public var line: Int?
    /// What is wrong, in words.
    public var reason: String

    /// Creates an error.
    public init(_ kind: Kind, file: String, line: Int? = nil, reason: String) {
        self.kind = kind; self.file = file; self.line = line; self.reason = reason
    }

}

/// A problem the reader recovered from: the bundle is still usable, but something was dropped or is
/// missing. Shown by `wayfinder inspect` and kept in `SessionBundle.warnings`.
public struct BundleWarning: FileLineMessage, Hashable, Sendable, Codable {
    /// The category of the recovered problem.
    public enum Kind: String, Sendable, Codable {
        /// The last line of a JSON-lines file was cut off (a crash while recording); it was dropped and
        /// every complete line before it kept.
        case truncatedLastLine
        /// Frames name image files that are not in images/ (poses and observations still replay).
        case missingImages
        /// Plane-anchor events of planes.jsonl that were dropped or will not be used (horizontal, zero
        /// extent, before a VIO reset, a file whose anchors never update): see `readPlaneRecords`.
        case ignoredPlanes
        /// Records holding a value outside its physical range (an observation's `rangeMeters` beyond
        /// `ObservationRecord.maximumRangeMeters`) were dropped; the rest of the file is kept.
        case implausibleValue
    }

    /// Category.
    public var kind: Kind
    /// Path of the file concerned.
    public var file: String
    /// 1-based line number (the first one concerned), nil when not tied to a line.
    public var line: Int?
    /// What happened, in words.
    public var reason: String

    /// Creates a warning.
    public init(_ kind: Kind, file: String, line: Int? = nil, reason: String) {
        self.kind = kind; self.file = file; self.line = line; self.reason = reason
    }

}

/// A problem tied to a file and, for JSON-lines files, a 1-based line: errors and warnings print alike.
public protocol FileLineMessage: CustomStringConvertible {
    /// Path of the file concerned, as opened.
    var file: String { get }
    /// 1-based line number, nil when the problem is not tied to a line.
    var line: Int? { get }
    /// What is wrong, in words.
    var reason: String { get }
}

extension FileLineMessage {
    /// `PATH line N: REASON` (or `PATH: REASON` when no line applies).
    public var description: String {
        if let line { return "\(file) line \(line): \(reason)" }
        return "\(file): \(reason)"
    }
}
