import Foundation

/// Streaming reader of one JSON-lines file of a bundle (`frames.jsonl`, `observations.jsonl`...): reads the
/// file in 64 KiB chunks, decodes one record per line, validates it (`BundleLineRecord.validationProblem`)
/// and checks the timestamp order, so a long recording never has to fit in memory. `SessionBundle.read`
/// uses this same reader; a new record type (one more `.jsonl` file) only needs a `BundleLineRecord`
/// conformance.
///
/// Rules: blank lines are skipped; a last line cut off in the middle of its JSON (a crash while
/// recording) is dropped with a `BundleWarning`; a record failing `plausibilityProblem()` is dropped with
/// one `BundleWarning` per file (count and first line); any other bad line throws a `BundleError` naming
/// the file and the 1-based line. The file must be a regular file inside the bundle (`BundleFileAccess`).
///
/// Limits: a line longer than `maximumLineBytes` throws `.lineTooLong` as soon as that many bytes have
/// been read without a newline, so memory stays below about two lines plus one chunk. Reading is linear in
/// the file size: each byte is searched for the newline once (`bytesExamined` counts the work, for tests).
/// Not thread-safe: use from one thread.
public final class RecordLineReader<Record: BundleLineRecord> {
    /// Path of the file read.
    public let url: URL
    /// Recovered problems met so far (a truncated last line, dropped implausible records).
    public private(set) var warnings: [BundleWarning] = []
    /// Number of the last line returned by `next()` (1-based; 0 before the first).
    public private(set) var lineNumber = 0
    /// Longest line accepted, bytes (newline excluded).
    public let maximumLineBytes: Int
    /// Bytes searched for a line end plus bytes moved when the buffer is compacted, since the file was
    /// opened: a measure of the reader's work that is about the file size when reading is linear (an
    /// injectable-free counter for tests; no timing involved).
    public private(set) var bytesExamined = 0
    /// Number of records dropped by `plausibilityProblem()` so far.
    public private(set) var droppedRecordCount = 0

    private let file: ReadOnlyFile
    private var buffer: [UInt8] = []
    private var start = 0          // first byte of the unfinished line in `buffer`
    private var scanned = 0        // bytes of `buffer` before this index hold no newline after `start`
    private var atEOF = false
    private var rawLineCount = 0
    private var lookahead: RawLine?
    private var primed = false
    private var previousTime: Double?
    private var previousLine = 0
    private var implausibleWarningIndex: Int?
    private var firstImplausible: String?
    private let decoder = JSONDecoder()
    private static var chunkBytes: Int { 1 << 16 }

    private struct RawLine {
        var bytes: Data
        var number: Int
        var terminated: Bool
    }

    /// Opens `url`, a file of the bundle directory `bundleRoot` (default: the directory holding `url`).
    /// `maximumLineBytes` overrides `Record.maximumLineBytes`.
    /// Throws `BundleError`: `.missingFile` when it does not exist, `.notARegularFile` for a FIFO, device or
    /// directory, `.linkOutsideBundle` for a link leaving the bundle, `.unreadableFile` when it cannot be
    /// opened.
    public init(url: URL, bundleRoot: URL? = nil, maximumLineBytes: Int? = nil) throws {
        self.url = url
        self.maximumLineBytes = max(1, maximumLineBytes ?? Record.maximumLineBytes)
        let root = BundleFileAccess.resolvedRoot(bundleRoot ?? url.deletingLastPathComponent())
        file = try BundleFileAccess.openForReading(url, root: root)
    }

    /// Opens the file `Record.fileName` inside the bundle directory `bundle`.
    public convenience init(bundle: URL, maximumLineBytes: Int? = nil) throws {
        try self.init(url: bundle.appendingPathComponent(Record.fileName), bundleRoot: bundle,
                      maximumLineBytes: maximumLineBytes)
    }

    /// The next record, or nil at the end of the file. Throws `BundleError` for a damaged line.
    public func next() throws -> Record? {
        while true {
            if !primed {
                primed = true
                lookahead = try readNonBlankLine()
            }
            guard let line = lookahead else { return nil }
            lookahead = try readNonBlankLine()
            let isLast = lookahead == nil

            let record: Record
            let depth = JSONNesting.depth(line.bytes)
            guard depth <= JSONNesting.maximumDepth else {
                throw BundleError(.invalidJSON, file: url.path, line: line.number,
                                  reason: "JSON nested \(depth) levels deep (at most \(JSONNesting.maximumDepth) accepted; a record needs under 10)")
            }
            do {
                record = try decoder.decode(Record.self, from: line.bytes)
            } catch DecodingError.dataCorrupted(let ctx) where ctx.codingPath.isEmpty {
                // Not JSON at all. A cut-off object at the very end is a crash while recording.
                if isJSONIncomplete(line.bytes) {
                    if isLast {
                        warnings.append(BundleWarning(
                            .truncatedLastLine, file: url.path, line: line.number,
                            reason: "last line is cut off (\(line.bytes.count) bytes of incomplete JSON"
                                + "\(line.terminated ? "" : ", no final newline")); dropped, the \(line.number - 1) lines before it kept"))
                        return nil
                    }
                    throw BundleError(.invalidJSON, file: url.path, line: line.number,
                                      reason: "incomplete JSON line followed by more lines (cut off in the middle of the file)")
                }
                // Valid JSON the decoder still calls invalid: a number its field cannot hold (1e23 as a width).
                if let range = outOfRangeNumberDescription(line.bytes) {
                    throw BundleError(.invalidRecord, file: url.path, line: line.number,
                                      reason: "not a valid \(Record.self): \(range)")
                }
                throw BundleError(.invalidJSON, file: url.path, line: line.number,
                                  reason: "not valid JSON: \(jsonSyntaxDetail(line.bytes))")
            } catch {
                throw BundleError(.invalidRecord, file: url.path, line: line.number,
                                  reason: "not a valid \(Record.self): \(describeDecodingError(error))")
            }
            if let problem = record.validationProblem() {
                throw BundleError(.invalidValue, file: url.path, line: line.number, reason: problem)
            }
            try checkOrder(record, line: line.number)
            if let problem = record.plausibilityProblem() {
                noteImplausible(line: line.number, problem: problem)
                continue
            }
            lineNumber = line.number
            return record
        }
    }

    /// Reads every remaining record.
    public func readAll() throws -> [Record] {
        var out: [Record] = []
        while let r = try next() { out.append(r) }
        return out
    }

    /// Reads every remaining record with its 1-based line number.
    public func readAllWithLineNumbers() throws -> (records: [Record], lines: [Int]) {
        var out: [Record] = [], lines: [Int] = []
        while let r = try next() { out.append(r); lines.append(lineNumber) }
        return (out, lines)
    }

    /// One warning per file for dropped implausible records: the first line and reason, and the count.
    private func noteImplausible(line: Int, problem: String) {
        droppedRecordCount += 1
        if firstImplausible == nil {
            firstImplausible = problem
            implausibleWarningIndex = warnings.count
            warnings.append(BundleWarning(.implausibleValue, file: url.path, line: line, reason: ""))
        }
        let noun = droppedRecordCount == 1 ? "record" : "records"
        warnings[implausibleWarningIndex!].reason =
            "\(droppedRecordCount) \(noun) dropped as physically implausible (the rest kept); first: \(firstImplausible!)"
    }

    private func checkOrder(_ record: Record, line: Int) throws {
        guard let t = record.orderTime else { return }
        defer { previousTime = t; previousLine = line }
        guard let p = previousTime else { return }
        switch Record.timeOrder {
        case .unordered: return
        case .nonDecreasing:
            if t < p {
                throw BundleError(.timestampOrder, file: url.path, line: line,
                                  reason: "timestamp t=\(t) goes back in time (line \(previousLine) has t=\(p))")
            }
        case .strictlyIncreasing:
            if t == p {
                throw BundleError(.duplicateTimestamp, file: url.path, line: line,
                                  reason: "duplicate timestamp t=\(t) (line \(previousLine) has the same)")
            }
            if t < p {
                throw BundleError(.timestampOrder, file: url.path, line: line,
                                  reason: "timestamp t=\(t) goes back in time (line \(previousLine) has t=\(p)); "
                                      + "timestamps must increase")
            }
        }
    }

    // MARK: Line splitting

    private func readNonBlankLine() throws -> RawLine? {
        while let line = try readRawLine() {
            if line.bytes.contains(where: { !($0 == 0x20 || $0 == 0x09 || $0 == 0x0D) }) { return line }
        }
        return nil
    }

    private func lineTooLong(_ number: Int) -> BundleError {
        BundleError(.lineTooLong, file: url.path, line: number,
                    reason: "line is longer than the limit of \(maximumLineBytes) bytes for \(Record.fileName) "
                        + "(docs/session-format.md); refused")
    }

    /// Index of the first newline in `buffer[from..<buffer.count]`, or nil (memchr: fast in debug builds too).
    private func newline(from: Int) -> Int? {
        guard from < buffer.count else { return nil }
        return buffer.withUnsafeBytes { raw -> Int? in
            guard let base = raw.baseAddress, let hit = memchr(base + from, 0x0A, raw.count - from) else { return nil }
            return base.distance(to: UnsafeRawPointer(hit))
        }
    }

    private func readRawLine() throws -> RawLine? {
        while true {
            if let nl = newline(from: scanned) {
                bytesExamined += nl + 1 - scanned
                let number = rawLineCount + 1
                if nl - start > maximumLineBytes { throw lineTooLong(number) }
                var end = nl
                if end > start, buffer[end - 1] == 0x0D { end -= 1 }
                let bytes = Data(buffer[start..<end])
                start = nl + 1
                scanned = start
                rawLineCount = number
                return RawLine(bytes: bytes, number: number, terminated: true)
            }
            bytesExamined += buffer.count - scanned
            scanned = buffer.count
            // No newline in the unfinished line so far: refuse it once it is over the limit.
            if buffer.count - start > maximumLineBytes { throw lineTooLong(rawLineCount + 1) }
            if atEOF {
                guard start < buffer.count else { return nil }
                let bytes = Data(buffer[start...])
                start = buffer.count
                scanned = start
                rawLineCount += 1
                return RawLine(bytes: bytes, number: rawLineCount, terminated: false)
            }
            if start > 0 {   // keep only the unfinished line
                bytesExamined += buffer.count - start
                buffer.removeFirst(start)
                scanned -= start
                start = 0
            }
            let n: Int
            do { n = try file.read(into: &buffer, upTo: Self.chunkBytes) } catch {
                throw BundleError(.unreadableFile, file: url.path, line: rawLineCount + 1,
                                  reason: "read failed: \(error.localizedDescription)")
            }
            if n == 0 { atEOF = true; file.close() }
        }
    }
}

/// Streaming reader of frames.jsonl.
public typealias FramesReader = RecordLineReader<FrameRecord>

/// True when `bytes` is the beginning of a JSON value that ends too early: an object or array left open,
/// or a string left unterminated. A complete-but-invalid text (`{"t": NaN}`) is not incomplete.
func isJSONIncomplete(_ bytes: Data) -> Bool {
    var depth = 0
    var inString = false
    var escaped = false
    var sawOpen = false
    for b in bytes {
        if inString {
            if escaped { escaped = false } else if b == 0x5C { escaped = true } else if b == 0x22 { inString = false }
            continue
        }
        switch b {
        case 0x22: inString = true
        case 0x7B, 0x5B: depth += 1; sawOpen = true
        case 0x7D, 0x5D: depth -= 1
        default: break
        }
    }
    return sawOpen && (depth > 0 || inString)
}

/// The parser's own words for why `bytes` is not JSON (JSONSerialization's debug description).
func jsonSyntaxDetail(_ bytes: Data) -> String {
    do {
        _ = try JSONSerialization.jsonObject(with: bytes, options: [.fragmentsAllowed])
        return "unreadable JSON"
    } catch let error as NSError {
        if let d = error.userInfo[NSDebugDescriptionErrorKey] as? String { return d }
        return error.localizedDescription
    }
}
