import Foundation

/// Streaming reader of one JSON-lines file of a bundle (`frames.jsonl`, `observations.jsonl`...): reads the
/// file in 64 KiB chunks, decodes one record per line, validates it (`BundleLineRecord.validationProblem`)
/// and checks the timestamp order, so a long recording never has to fit in memory. `SessionBundle.read`
/// uses this same reader.
///
/// Rules: blank lines are skipped; a last line cut off in the middle of its JSON (a crash while
/// recording) is dropped with a `BundleWarning`; any other bad line throws a `BundleError` naming the file
/// and the 1-based line. Not thread-safe: use from one thread.
public final class RecordLineReader<Record: BundleLineRecord> {
    /// Path of the file read.
    public let url: URL
    /// Recovered problems met so far (a truncated last line).
    public private(set) var warnings: [BundleWarning] = []
    /// Number of the last line returned by `next()` (1-based; 0 before the first).
    public private(set) var lineNumber = 0

    private let handle: FileHandle
    private var buffer: [UInt8] = []
    private var start = 0
    private var atEOF = false
    private var rawLineCount = 0
    private var lookahead: RawLine?
    private var primed = false
    private var previousTime: Double?
    private var previousLine = 0
    private let decoder = JSONDecoder()

    private struct RawLine {
        var bytes: Data
        var number: Int
        var terminated: Bool
    }

    /// Opens `url`. Throws `BundleError.missingFile` when it does not exist, `.unreadableFile` when it
    /// cannot be opened.
    public init(url: URL) throws {
        self.url = url
        var isDir: ObjCBool = false
        guard FileManager.default.fileExists(atPath: url.path, isDirectory: &isDir) else {
            throw BundleError(.missingFile, file: url.path, reason: "file not found")
        }
        if isDir.boolValue { throw BundleError(.unreadableFile, file: url.path, reason: "is a directory, expected a file") }
        do {
            handle = try FileHandle(forReadingFrom: url)
        } catch {
            throw BundleError(.unreadableFile, file: url.path, reason: "cannot open: \(error.localizedDescription)")
        }
    }

    /// Opens the file `Record.fileName` inside the bundle directory `bundle`.
    public convenience init(bundle: URL) throws {
        try self.init(url: bundle.appendingPathComponent(Record.fileName))
    }

    deinit { try? handle.close() }

    /// The next record, or nil at the end of the file. Throws `BundleError` for a damaged line.
    public func next() throws -> Record? {
        if !primed {
            primed = true
            lookahead = try readNonBlankLine()
        }
        guard let line = lookahead else { return nil }
        lookahead = try readNonBlankLine()
        let isLast = lookahead == nil
        lineNumber = line.number

        let record: Record
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
        return record
    }

    /// Reads every remaining record.
    public func readAll() throws -> [Record] {
        var out: [Record] = []
        while let r = try next() { out.append(r) }
        return out
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

    private func readRawLine() throws -> RawLine? {
        while true {
            if let nl = buffer[start...].firstIndex(of: 0x0A) {
                var end = nl
                if end > start, buffer[end - 1] == 0x0D { end -= 1 }
                let bytes = Data(buffer[start..<end])
                start = nl + 1
                rawLineCount += 1
                return RawLine(bytes: bytes, number: rawLineCount, terminated: true)
            }
            if atEOF {
                guard start < buffer.count else { return nil }
                let bytes = Data(buffer[start...])
                start = buffer.count
                rawLineCount += 1
                return RawLine(bytes: bytes, number: rawLineCount, terminated: false)
            }
            let chunk: Data?
            do { chunk = try handle.read(upToCount: 1 << 16) } catch {
                throw BundleError(.unreadableFile, file: url.path, line: rawLineCount + 1,
                                  reason: "read failed: \(error.localizedDescription)")
            }
            if let chunk, !chunk.isEmpty {
                if start > 0 { buffer.removeFirst(start); start = 0 }   // keep only the unfinished line
                buffer.append(contentsOf: chunk)
            } else {
                atEOF = true
            }
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
