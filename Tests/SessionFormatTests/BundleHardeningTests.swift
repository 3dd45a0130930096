import Foundation
import XCTest
#if canImport(Glibc)
import Glibc
#elseif canImport(Darwin)
import Darwin
#endif
@testable import SessionFormat

/// Hostile bundles (issue 14): special files, links leaving the bundle, huge lines, implausible values.
/// Each must give a clear error (or warning) naming the file, never a hang, a crash or a silent read of a
/// file outside the bundle.
final class BundleHardeningTests: XCTestCase {
    private var dir: URL!
    private let fm = FileManager.default

    override func setUpWithError() throws {
        dir = try makeTemporaryDirectory(self, "hardening")
        try writeSampleBundle(at: dir, frameCount: 20)
    }

    private func file(_ name: String) -> URL { dir.appendingPathComponent(name) }

    private func replaceWithFIFO(_ name: String) throws {
        try fm.removeItem(at: file(name))
        XCTAssertEqual(mkfifo(file(name).path, 0o644), 0, "mkfifo failed")
    }

    private func replaceWithLink(_ name: String, to target: String) throws {
        if fm.fileExists(atPath: file(name).path) || BundleFileAccess.isSymbolicLink(file(name).path) {
            try fm.removeItem(at: file(name))
        }
        try fm.createSymbolicLink(atPath: file(name).path, withDestinationPath: target)
    }

    private func readError() -> BundleError? { bundleError { try SessionBundle.read(from: self.dir) } }

    // MARK: Deep nesting (Foundation's JSON parsers trap at their 512-level limit; found by wayfinder-fuzz)

    func testDeeplyNestedLinesAndSessionFileAreErrorsNotTraps() throws {
        // A frames.jsonl line of 513 '[' (the fuzzer's reproducer) and one of '{"t":' + 512 '['.
        for line in [String(repeating: "[", count: 513), "{\"t\":" + String(repeating: "[", count: 512)] {
            let original = try Data(contentsOf: file("frames.jsonl"))
            try (String(decoding: original, as: UTF8.self) + line + "\n").write(to: file("frames.jsonl"), atomically: true, encoding: .utf8)
            let e = try XCTUnwrap(readError())
            XCTAssertEqual(e.kind, .invalidJSON)
            XCTAssertTrue(e.reason.contains("nested"), e.reason)
            try original.write(to: file("frames.jsonl"))
        }
        try Data(String(repeating: "[", count: 513).utf8).write(to: file("session.json"))
        let e = try XCTUnwrap(readError())
        XCTAssertTrue(e.file.hasSuffix("session.json") && e.reason.contains("nested"), "\(e)")
        XCTAssertEqual(JSONNesting.depth(Data("{\"a\": \"[[[[\", \"b\": [[1]]}".utf8)), 3)
    }

    // MARK: Numbers a field cannot hold ("width 1e23 says unreadable JSON")

    func testANumberOutOfRangeNamesTheFieldNotUnreadableJSON() throws {
        let original = try String(contentsOf: file("frames.jsonl"), encoding: .utf8)
        var lines = original.split(separator: "\n", omittingEmptySubsequences: false).map(String.init)
        lines[2] = lines[2].replacingOccurrences(of: "\"width\":1920", with: "\"width\":1e23")
            .replacingOccurrences(of: "\"width\" : 1920", with: "\"width\" : 1e23")
        XCTAssertTrue(lines[2].contains("1e23"), "fixture line has no width 1920: \(lines[2])")
        try lines.joined(separator: "\n").write(to: file("frames.jsonl"), atomically: true, encoding: .utf8)
        let e = try XCTUnwrap(readError())
        XCTAssertEqual(e.line, 3)
        XCTAssertTrue(e.reason.contains("intrinsics.width") && e.reason.contains("out of range"), e.reason)
        XCTAssertFalse(e.reason.contains("unreadable"), e.reason)
    }

    // MARK: Special files (a FIFO blocked, /dev/zero ran forever)

    func testFIFOAsFramesFileIsRefusedWithoutBlocking() throws {
        try replaceWithFIFO("frames.jsonl")
        let e = try XCTUnwrap(readError())
        XCTAssertEqual(e.kind, .notARegularFile)
        XCTAssertEqual(e.file, file("frames.jsonl").path)
        XCTAssertTrue(e.reason.contains("FIFO"), e.reason)
    }

    func testFIFOAsSessionFileOrOptionalFileIsRefused() throws {
        try replaceWithFIFO("session.json")
        XCTAssertEqual(readError()?.kind, .notARegularFile)
        try fm.removeItem(at: file("session.json"))
        try writeSampleBundle(at: dir)
        try replaceWithFIFO("observations.jsonl")
        let e = readError()
        XCTAssertEqual(e?.kind, .notARegularFile)
        XCTAssertEqual(e?.file, file("observations.jsonl").path)
    }

    func testDirectoryAsFramesFileIsRefused() throws {
        try fm.removeItem(at: file("frames.jsonl"))
        try fm.createDirectory(at: file("frames.jsonl"), withIntermediateDirectories: false)
        let e = readError()
        XCTAssertEqual(e?.kind, .notARegularFile)
        XCTAssertTrue(e?.reason.contains("directory") ?? false, e?.reason ?? "")
    }

    func testDevZeroBehindALinkIsRefused() throws {
        try replaceWithLink("frames.jsonl", to: "/dev/zero")
        let e = try XCTUnwrap(readError())
        XCTAssertEqual(e.kind, .linkOutsideBundle)
        XCTAssertTrue(e.reason.contains("/dev/zero"), e.reason)
    }

    func testStreamingReaderRefusesAFIFOToo() throws {
        try replaceWithFIFO("frames.jsonl")
        XCTAssertEqual(bundleError { try FramesReader(bundle: self.dir) }?.kind, .notARegularFile)
    }

    // MARK: Links (policy: docs/session-format.md "Links and special files")

    func testLinkToEtcPasswdIsRefused() throws {
        try replaceWithLink("frames.jsonl", to: "/etc/passwd")
        let e = try XCTUnwrap(readError())
        XCTAssertEqual(e.kind, .linkOutsideBundle)
        XCTAssertEqual(e.file, file("frames.jsonl").path)
        XCTAssertTrue(e.description.contains("/etc/passwd") && e.description.contains("outside the bundle"), e.description)
    }

    func testRelativeLinkLeavingTheBundleIsRefused() throws {
        let outside = try makeTemporaryDirectory(self, "outside")
        try Data(try String(contentsOf: file("observations.jsonl"), encoding: .utf8).utf8)
            .write(to: outside.appendingPathComponent("obs.jsonl"))
        let relative = "../" + outside.lastPathComponent + "/obs.jsonl"
        try replaceWithLink("observations.jsonl", to: relative)
        XCTAssertTrue(fm.fileExists(atPath: file("observations.jsonl").path), "the link resolves")
        XCTAssertEqual(readError()?.kind, .linkOutsideBundle)
    }

    func testImagesDirectoryLinkedOutsideIsRefused() throws {
        try replaceWithLink("images", to: "/etc")
        var l = try String(contentsOf: file("frames.jsonl"), encoding: .utf8).split(separator: "\n").map(String.init)
        let f = sampleFrame(0.3, image: "passwd")
        l[3] = try jsonLine(f)
        try overwriteFile(dir, "frames.jsonl", l.joined(separator: "\n") + "\n")
        let e = try XCTUnwrap(readError())
        XCTAssertEqual(e.kind, .linkOutsideBundle)
        XCTAssertTrue(e.file.hasSuffix("images/passwd"), e.file)
        XCTAssertTrue(e.reason.contains("frames.jsonl line 4"), e.reason)
        // And the per-frame accessor replay uses never hands out the outside file.
        let inMemory = SessionBundle(url: dir, info: sampleInfo, frames: [f])
        XCTAssertNil(inMemory.presentImageURL(for: f))
    }

    func testImagesDirectoryLinkedOutsideIsRefusedEvenWhenNoFrameNamesAnImage() throws {
        try replaceWithLink("images", to: "/etc")
        let e = readError()
        XCTAssertEqual(e?.kind, .linkOutsideBundle)
        XCTAssertEqual(e?.file, file("images").path)
    }

    func testImageThatIsAFIFOIsRefused() throws {
        try fm.createDirectory(at: file("images"), withIntermediateDirectories: true)
        XCTAssertEqual(mkfifo(file("images/a.ppm").path, 0o644), 0)
        var l = try String(contentsOf: file("frames.jsonl"), encoding: .utf8).split(separator: "\n").map(String.init)
        l[2] = try jsonLine(sampleFrame(0.2, image: "a.ppm"))
        try overwriteFile(dir, "frames.jsonl", l.joined(separator: "\n") + "\n")
        let e = readError()
        XCTAssertEqual(e?.kind, .notARegularFile)
        XCTAssertTrue(e?.file.hasSuffix("images/a.ppm") ?? false)
    }

    func testLinksThatStayInsideTheBundleAreFollowed() throws {
        try fm.createDirectory(at: file("data"), withIntermediateDirectories: false)
        try fm.moveItem(at: file("frames.jsonl"), to: file("data/frames.jsonl"))
        try replaceWithLink("frames.jsonl", to: "data/frames.jsonl")
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 20)
        // The bundle directory itself may be reached through a link (links are resolved before the check).
        let alias = try makeTemporaryDirectory(self, "alias").appendingPathComponent("walk")
        try fm.createSymbolicLink(atPath: alias.path, withDestinationPath: dir.path)
        XCTAssertEqual(try SessionBundle.read(from: alias).frames.count, 20)
    }

    func testLinkLoopIsAClearError() throws {
        try replaceWithLink("frames.jsonl", to: "loop-b")
        try fm.createSymbolicLink(atPath: file("loop-b").path, withDestinationPath: "frames.jsonl")
        let e = readError()
        XCTAssertEqual(e?.kind, .linkOutsideBundle)
        XCTAssertTrue(e?.reason.contains("loop") ?? false, e?.reason ?? "")
    }

    func testDanglingLinkIsAMissingFile() throws {
        try replaceWithLink("frames.jsonl", to: "nowhere.jsonl")
        let e = readError()
        XCTAssertEqual(e?.kind, .missingFile)
        XCTAssertTrue(e?.reason.contains("symbolic link") ?? false, e?.reason ?? "")
    }

    // MARK: Limits

    func testOversizedSessionFileIsRefused() throws {
        var text = try String(contentsOf: file("session.json"), encoding: .utf8)
        text.removeLast(2)   // "}\n"
        text += ", \"padding\": \"" + String(repeating: "x", count: maximumSessionFileBytes) + "\"}\n"
        try overwriteFile(dir, "session.json", text)
        let e = readError()
        XCTAssertEqual(e?.kind, .fileTooLarge)
        XCTAssertTrue(e?.file.hasSuffix("session.json") ?? false)
    }

    /// A frame line padded with an unknown field to exactly `bytes` bytes.
    private func paddedFrameLine(_ t: Double, bytes: Int) throws -> String {
        let base = try jsonLine(sampleFrame(t))
        let overhead = ",\"pad\":\"\"".utf8.count
        let pad = String(repeating: "a", count: bytes - base.utf8.count - overhead)
        return String(base.dropLast()) + ",\"pad\":\"\(pad)\"}"
    }

    func testLineLongerThanTheLimitIsAnErrorNamingFileAndLine() throws {
        var l = try String(contentsOf: file("frames.jsonl"), encoding: .utf8).split(separator: "\n").map(String.init)
        l[2] = try paddedFrameLine(0.2, bytes: 2000)
        try overwriteFile(dir, "frames.jsonl", l.joined(separator: "\n") + "\n")
        // At the limit: accepted. One byte over: refused, naming the line.
        XCTAssertEqual(try FramesReader(bundle: dir, maximumLineBytes: 2000).readAll().count, 20)
        let e = bundleError { try FramesReader(bundle: self.dir, maximumLineBytes: 1999).readAll() }
        XCTAssertEqual(e?.kind, .lineTooLong)
        XCTAssertEqual(e?.line, 3)
        XCTAssertTrue(e?.description.contains("frames.jsonl line 3") ?? false, e?.description ?? "")
        // The default limit is 1 MiB and documented.
        XCTAssertEqual(FrameRecord.maximumLineBytes, 1 << 20)
        l[2] = try paddedFrameLine(0.2, bytes: (1 << 20) + 1)
        try overwriteFile(dir, "frames.jsonl", l.joined(separator: "\n") + "\n")
        XCTAssertEqual(readError()?.kind, .lineTooLong)
    }

    func testAFileOfZeroBytesWithoutNewlineStopsAtTheLimit() throws {
        try Data(count: 3 << 20).write(to: file("frames.jsonl"))
        let reader = try FramesReader(bundle: dir, maximumLineBytes: 1 << 20)
        let e = bundleError { try reader.next() as Any }
        XCTAssertEqual(e?.kind, .lineTooLong)
        XCTAssertEqual(e?.line, 1)
        // It stopped reading soon after the limit instead of holding the whole file.
        XCTAssertLessThanOrEqual(reader.bytesExamined, (1 << 20) + 2 * 65536)
    }

    /// Reading must be linear in the line length: the old reader searched the whole unfinished line again
    /// for every 64 KiB chunk (a 16 MB line took 3.2 s, 48 MB 24.5 s). Counted, not timed.
    func testReadingALongLineIsLinear() throws {
        var examined: [Int: Int] = [:]
        for megabytes in [2, 4] {
            let bytes = megabytes << 20
            try overwriteFile(dir, "frames.jsonl", try paddedFrameLine(0, bytes: bytes) + "\n" + jsonLine(sampleFrame(1)) + "\n")
            let size = try XCTUnwrap(fm.attributesOfItem(atPath: file("frames.jsonl").path)[.size] as? Int)
            let reader = try FramesReader(bundle: dir, maximumLineBytes: 8 << 20)
            XCTAssertEqual(try reader.readAll().count, 2)
            examined[megabytes] = reader.bytesExamined
            // Each byte is searched once, plus at most one move of the unfinished line per chunk boundary
            // where a line ends inside the chunk. Quadratic rescanning gave about bytes^2 / 128 KiB (16 x at 2 MiB).
            XCTAssertLessThanOrEqual(reader.bytesExamined, 2 * size, "\(megabytes) MiB line: \(reader.bytesExamined) bytes examined")
            XCTAssertGreaterThanOrEqual(reader.bytesExamined, size, "every byte is looked at")
        }
        let ratio = Double(examined[4]!) / Double(examined[2]!)
        XCTAssertLessThan(ratio, 2.5, "doubling the line should double the work, not quadruple it (\(examined))")
    }

    func testReadingManyLinesIsLinear() throws {
        let w = try BundleWriter(directory: dir, info: sampleInfo, overwrite: true, flushEveryLines: 64)
        for i in 0..<2000 { try w.append(sampleFrame(Double(i) / 30)) }
        try w.close()
        let size = try XCTUnwrap(fm.attributesOfItem(atPath: file("frames.jsonl").path)[.size] as? Int)
        let reader = try FramesReader(bundle: dir)
        XCTAssertEqual(try reader.readAll().count, 2000)
        XCTAssertLessThanOrEqual(reader.bytesExamined, 2 * size)
    }

    // MARK: Implausible values

    func testObservationRangeBeyondThePhysicalLimitIsDroppedWithAWarning() throws {
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 0.9, kind: "exit", rangeMeters: 1e300, bearingRad: 0, score: 0.5)) + "\n")
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 1.0, kind: "exit", rangeMeters: 5, bearingRad: 0, score: 0.5)) + "\n")
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 1.1, kind: "exit", rangeMeters: 100.5, bearingRad: 0, score: 0.5)) + "\n")
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.observations.map(\.rangeMeters), [4.2, 7.0, 5])
        XCTAssertEqual(b.observationLineNumbers, [1, 2, 4])
        XCTAssertEqual(b.warnings.count, 1)
        let w = try XCTUnwrap(b.warnings.first)
        XCTAssertEqual(w.kind, .implausibleValue)
        XCTAssertEqual(w.line, 3)
        XCTAssertTrue(w.file.hasSuffix("observations.jsonl"))
        XCTAssertTrue(w.reason.contains("2 records dropped") && w.reason.contains("1e+300"), w.reason)
        // At the limit is still plausible.
        XCTAssertNil(ObservationRecord(t: 0, kind: "exit", rangeMeters: 100, bearingRad: 0, score: 1).plausibilityProblem())
    }

    func testWriterRefusesImplausibleRangesAndOverlongLines() throws {
        let w = try BundleWriter(directory: dir, info: sampleInfo, overwrite: true)
        try w.append(sampleFrame(0))
        let e = bundleError { try w.append(ObservationRecord(t: 0, kind: "exit", rangeMeters: 1e300, bearingRad: 0, score: 1)) }
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertTrue(e?.reason.contains("refusing to write") ?? false)
        let long = ExpectedAnnouncement(text: String(repeating: "x", count: 1 << 20))
        XCTAssertEqual(bundleError { try w.append(long) }?.kind, .lineTooLong)
        try w.close()
        let b = try SessionBundle.read(from: dir)
        XCTAssertTrue(b.observations.isEmpty && b.expected.isEmpty && b.warnings.isEmpty)
    }

    // MARK: Writer: group flush keeps the files consistent in time

    func testGroupFlushWritesEveryFileTogether() throws {
        let w = try BundleWriter(directory: dir, info: sampleInfo, overwrite: true, flushEveryLines: 4)
        func onDisk(_ name: String) -> Int {
            ((try? String(contentsOf: file(name), encoding: .utf8)) ?? "").filter { $0 == "\n" }.count
        }
        for i in 0..<3 {
            try w.append(sampleFrame(Double(i)))
            try w.append(TruthRecord(t: Double(i), x: 0, y: 0, floorId: "4", headingRad: 0))
        }
        // Six lines appended, one group of four written: two frames and two truth poses, same times.
        XCTAssertEqual(onDisk("frames.jsonl"), 2)
        XCTAssertEqual(onDisk("truth.jsonl"), 2)
        try w.append(ObservationRecord(t: 2, kind: "exit", rangeMeters: 3, bearingRad: 0, score: 1))
        try w.append(sampleFrame(3))
        XCTAssertEqual([onDisk("frames.jsonl"), onDisk("truth.jsonl"), onDisk("observations.jsonl")], [4, 3, 1])
        try w.close()
    }
}

/// The importer's input file is read under the regular-file rule too (a FIFO blocked it).
final class ImporterInputHardeningTests: XCTestCase {
    func testFIFOAsOccamInputIsAClearError() throws {
        let dir = try makeTemporaryDirectory(self, "occam-fifo")
        let input = dir.appendingPathComponent("walk.json")
        XCTAssertEqual(mkfifo(input.path, 0o644), 0)
        XCTAssertThrowsError(try OccamImporter.convert(from: input)) { error in
            XCTAssertTrue("\(error)".contains(input.path) && "\(error)".contains("FIFO"), "\(error)")
        }
    }
}
