import Foundation
#if canImport(Glibc)
import Glibc
#elseif canImport(Darwin)
import Darwin
#endif

/// The one writer of session bundle format v1, used by the iOS recorder, the simulator and importers.
///
/// Crash safety: each JSON-lines file is opened with `O_APPEND` (never truncated, never through a
/// symbolic link) and lines reach the files only whole, each file's pending lines in a single `write`, so
/// a recording cut off by a crash or a kill holds only whole lines, except at worst a partial last line
/// per file, which the reader drops with a warning. With `flushEveryLines: 1` (the default, the phone's
/// recorder) each record is handed to the OS as soon as it is appended: a kill loses nothing but, at
/// worst, the line being written. With `flushEveryLines: N` the pending lines of **all** files are written
/// together once N lines are pending in all (a group flush), so a producer that appends in time order
/// (the simulator) keeps the files consistent in time: a kill loses at most the N - 1 most recent lines in
/// all, plus a partial last line. `flush()` additionally forces the files to storage (fsync) against power
/// loss. session.json and images are written atomically (temporary file + rename).
///
/// Every record is checked with the reader's own rules before it is written (finite numbers, 16-element
/// column-major transform, increasing timestamps, plausible ranges...), so the writer cannot produce a
/// bundle the reader rejects or trims: a bad record throws `BundleError` and nothing is written for it.
///
/// Thread-safe (an internal lock): the recorder may append frames and images from different queues.
public final class BundleWriter: @unchecked Sendable {
    /// The bundle directory.
    public let directory: URL
    /// The session description written to session.json.
    public let info: SessionInfo
    /// Lines pending in all files before they are all written (1 = each line written when appended).
    public let flushEveryLines: Int

    private let lock = NSLock()
    private var sinks: [String: LineSink] = [:]
    private var sinkOrder: [LineSink] = []
    private var pendingLines = 0
    private var closed = false
    private let encoder: JSONEncoder

    /// Number of lines appended so far to each file, by file name (`frames.jsonl`...).
    public var lineCounts: [String: Int] {
        lock.lock(); defer { lock.unlock() }
        return sinks.mapValues { $0.linesAppended }
    }

    /// Creates the bundle directory (with intermediates) and writes session.json atomically; frames.jsonl is
    /// created empty at once, the optional files on their first record.
    ///
    /// - Parameters:
    ///   - directory: bundle directory. It must be absent or empty unless `overwrite` is true.
    ///   - info: session description; `formatVersion` must be `sessionFormatVersion`.
    ///   - overwrite: replace an existing bundle: its session.json, .jsonl files and images/ are deleted
    ///     first (other files are left alone).
    ///   - flushEveryLines: lines pending in all files before they are written together (>= 1). Larger
    ///     values mean fewer system calls; a crash then loses at most this many lines minus one in all.
    /// - Throws: `BundleError` (`.alreadyExists`, `.notADirectory`, `.unsupportedVersion`, `.invalidValue`,
    ///   `.writeFailed`).
    public init(directory: URL, info: SessionInfo, overwrite: Bool = false, flushEveryLines: Int = 1) throws {
        self.directory = directory
        self.info = info
        self.flushEveryLines = max(1, flushEveryLines)
        encoder = JSONEncoder()
        encoder.outputFormatting = [.sortedKeys, .withoutEscapingSlashes]

        let fm = FileManager.default
        let sessionURL = directory.appendingPathComponent(sessionFileName)
        guard info.formatVersion == sessionFormatVersion else {
            throw BundleError(.unsupportedVersion, file: sessionURL.path,
                              reason: "this writer writes formatVersion \(sessionFormatVersion), info says \(info.formatVersion)")
        }
        if let problem = info.validationProblem() {
            throw BundleError(.invalidValue, file: sessionURL.path, reason: problem)
        }
        var isDir: ObjCBool = false
        if fm.fileExists(atPath: directory.path, isDirectory: &isDir) {
            guard isDir.boolValue else {
                throw BundleError(.notADirectory, file: directory.path, reason: "exists and is a file, cannot hold a bundle")
            }
            let contents = (try? fm.contentsOfDirectory(atPath: directory.path)) ?? []
            if !contents.isEmpty {
                guard overwrite else {
                    throw BundleError(.alreadyExists, file: directory.path,
                                      reason: "directory is not empty (\(contents.sorted().prefix(4).joined(separator: ", "))"
                                          + "\(contents.count > 4 ? ", ..." : "")); refusing to overwrite a recording "
                                          + "(pass overwrite: true / --overwrite to replace it)")
                }
                let bundleNames = [sessionFileName, imagesDirectoryName] + bundleLineFileNames
                for name in bundleNames where contents.contains(name) {
                    do { try fm.removeItem(at: directory.appendingPathComponent(name)) } catch {
                        throw BundleError(.writeFailed, file: directory.appendingPathComponent(name).path,
                                          reason: "cannot remove for overwrite: \(error.localizedDescription)")
                    }
                }
            }
        }
        do { try fm.createDirectory(at: directory, withIntermediateDirectories: true) } catch {
            throw BundleError(.writeFailed, file: directory.path, reason: "cannot create directory: \(error.localizedDescription)")
        }
        let pretty = JSONEncoder()
        pretty.outputFormatting = [.sortedKeys, .withoutEscapingSlashes, .prettyPrinted]
        do {
            var data = try pretty.encode(info)
            data.append(0x0A)
            try data.write(to: sessionURL, options: .atomic)
        } catch {
            throw BundleError(.writeFailed, file: sessionURL.path, reason: "cannot write: \(error.localizedDescription)")
        }
        _ = try sink(for: FrameRecord.self)
    }

    deinit { try? close() }

    /// Appends one frame to frames.jsonl. Throws `BundleError` if the frame is invalid (same rules as the
    /// reader, including a `t` greater than the previous frame's) or the write fails.
    public func append(_ frame: FrameRecord) throws { try appendRecord(frame) }

    /// Appends one observation to observations.jsonl (created on first use).
    public func append(_ observation: ObservationRecord) throws { try appendRecord(observation) }

    /// Appends one truth pose to truth.jsonl (created on first use).
    public func append(_ truth: TruthRecord) throws { try appendRecord(truth) }

    /// Appends one expected announcement to expected.jsonl (created on first use).
    public func append(_ expected: ExpectedAnnouncement) throws { try appendRecord(expected) }

    /// Appends one plane-anchor event to planes.jsonl (created on first use).
    public func append(_ plane: PlaneRecord) throws { try appendRecord(plane) }
    /// Appends a record of any bundle line type to its file (`R.fileName`, created on first use), with the
    /// same checks: the entry point for a record type added later.
    public func append<R: BundleLineRecord>(record: R) throws { try appendRecord(record) }

    /// Writes `data` to images/`name` atomically. `name` must be a plain file name; an existing image is
    /// never replaced (`.alreadyExists`).
    public func writeImage(named name: String, data: Data) throws {
        let dir = directory.appendingPathComponent(imagesDirectoryName, isDirectory: true)
        let fileURL = dir.appendingPathComponent(name)
        guard isSafeImageName(name) else {
            throw BundleError(.unsafeImageName, file: fileURL.path, reason: "image name '\(name)' is not a plain file name")
        }
        lock.lock(); defer { lock.unlock() }
        guard !closed else { throw BundleError(.closed, file: fileURL.path, reason: "writer is closed") }
        let fm = FileManager.default
        if fm.fileExists(atPath: fileURL.path) {
            throw BundleError(.alreadyExists, file: fileURL.path, reason: "image already recorded; refusing to replace it")
        }
        do {
            try fm.createDirectory(at: dir, withIntermediateDirectories: true)
            try data.write(to: fileURL, options: .atomic)
        } catch {
            throw BundleError(.writeFailed, file: fileURL.path, reason: "cannot write image: \(error.localizedDescription)")
        }
    }

    /// Writes every buffered line and forces the files to storage (fsync).
    public func flush() throws {
        lock.lock(); defer { lock.unlock() }
        guard !closed else { return }
        for sink in sinkOrder { try sink.writeBuffered(); try sink.sync() }
        pendingLines = 0
    }

    /// Flushes and closes every file. Later appends throw `.closed`; closing twice does nothing.
    public func close() throws {
        lock.lock(); defer { lock.unlock() }
        guard !closed else { return }
        closed = true
        var firstError: Error?
        for sink in sinkOrder {
            do { try sink.writeBuffered(); try sink.sync() } catch { firstError = firstError ?? error }
            sink.close()
        }
        pendingLines = 0
        if let firstError { throw firstError }
    }

    // MARK: Internals

    private func appendRecord<R: BundleLineRecord>(_ record: R) throws {
        lock.lock(); defer { lock.unlock() }
        let fileURL = directory.appendingPathComponent(R.fileName)
        guard !closed else { throw BundleError(.closed, file: fileURL.path, reason: "writer is closed") }
        let s = try sink(for: R.self)
        let line = s.linesAppended + 1
        if let problem = record.validationProblem() ?? record.plausibilityProblem() {
            throw BundleError(.invalidValue, file: fileURL.path, line: line, reason: "refusing to write: \(problem)")
        }
        if let t = record.orderTime, let p = s.lastTime {
            switch R.timeOrder {
            case .unordered: break
            case .nonDecreasing where t < p:
                throw BundleError(.timestampOrder, file: fileURL.path, line: line,
                                  reason: "refusing to write: t=\(t) goes back in time (previous t=\(p))")
            case .strictlyIncreasing where t <= p:
                throw BundleError(t == p ? .duplicateTimestamp : .timestampOrder, file: fileURL.path, line: line,
                                  reason: "refusing to write: t=\(t) is not after the previous t=\(p)")
            default: break
            }
        }
        var data: Data
        do { data = try encoder.encode(record) } catch {
            throw BundleError(.invalidValue, file: fileURL.path, line: line, reason: "cannot encode: \(error)")
        }
        data.append(0x0A)
        if data.count - 1 > R.maximumLineBytes {
            throw BundleError(.lineTooLong, file: fileURL.path, line: line,
                              reason: "refusing to write: the line has \(data.count - 1) bytes, over the reader's limit of "
                                  + "\(R.maximumLineBytes)")
        }
        s.buffer.append(data)
        s.bufferedLines += 1
        s.linesAppended += 1
        pendingLines += 1
        if let t = record.orderTime { s.lastTime = t }
        if pendingLines >= flushEveryLines {
            // Group flush: every file's pending lines, in the order the files were first used.
            for sink in sinkOrder { try sink.writeBuffered() }
            pendingLines = 0
        }
    }

    private func sink<R: BundleLineRecord>(for type: R.Type) throws -> LineSink {
        if let s = sinks[R.fileName] { return s }
        let s = try LineSink(url: directory.appendingPathComponent(R.fileName))
        sinks[R.fileName] = s
        sinkOrder.append(s)
        return s
    }
}

/// One append-only JSON-lines file: a file descriptor opened with O_APPEND (never O_TRUNC, never through
/// a symbolic link) and the lines not yet written.
private final class LineSink {
    let url: URL
    let fd: Int32
    var buffer = Data()
    var bufferedLines = 0
    var linesAppended = 0
    var lastTime: Double?
    private var isOpen = true

    init(url: URL) throws {
        self.url = url
        fd = open(url.path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0o644)
        if fd < 0 {
            throw BundleError(.writeFailed, file: url.path, reason: "cannot open for appending: \(String(cString: strerror(errno)))")
        }
    }

    /// Writes the buffered lines with one write() call (looping only if the OS takes part of them).
    func writeBuffered() throws {
        guard !buffer.isEmpty, isOpen else { return }
        var offset = 0
        let total = buffer.count
        try buffer.withUnsafeBytes { (raw: UnsafeRawBufferPointer) in
            while offset < total {
                let n = write(fd, raw.baseAddress! + offset, total - offset)
                if n < 0 {
                    if errno == EINTR { continue }
                    throw BundleError(.writeFailed, file: url.path, reason: "write failed: \(String(cString: strerror(errno)))")
                }
                offset += n
            }
        }
        buffer.removeAll(keepingCapacity: true)
        bufferedLines = 0
    }

    func sync() throws {
        guard isOpen else { return }
        if fsync(fd) != 0 && errno != EINVAL {
            throw BundleError(.writeFailed, file: url.path, reason: "fsync failed: \(String(cString: strerror(errno)))")
        }
    }

    func close() {
        guard isOpen else { return }
        isOpen = false
        _ = posixClose(fd)
    }
}

/// `close(2)`, named apart from the writer's own `close()`.
@inline(__always) private func posixClose(_ fd: Int32) -> Int32 {
    #if canImport(Glibc)
    return Glibc.close(fd)
    #else
    return Darwin.close(fd)
    #endif
}
