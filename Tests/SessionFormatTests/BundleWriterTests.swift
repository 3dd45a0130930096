import Foundation
import XCTest
@testable import SessionFormat
import TestRandom

/// The writer: round trips, refusal to overwrite, validation before writing, crash safety, images.
final class BundleWriterTests: XCTestCase {
    func testRoundTripOfEveryRecordType() throws {
        let dir = try makeTemporaryDirectory(self)
        let frames = try writeSampleBundle(at: dir, frameCount: 30)
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.info, sampleInfo)
        XCTAssertEqual(b.frames, frames)
        XCTAssertEqual(b.observations.map(\.rangeMeters), [4.2, 7.0])
        XCTAssertEqual(b.truth.map(\.t), [0, 0.1])
        XCTAssertEqual(b.expected.count, 1)
        XCTAssertTrue(b.warnings.isEmpty)
    }

    /// Doubles written by the writer read back bit for bit (seeded random values over many magnitudes).
    func testFloatsRoundTripExactly() throws {
        let dir = try makeTemporaryDirectory(self)
        var rng = SplitMix64(seed: 42)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        var written: [ObservationRecord] = []
        var t = 1000.0
        for _ in 0..<500 {
            t += Double.random(in: 1e-9...0.05, using: &rng)
            let range = Double.random(in: 1e-6...1, using: &rng) * pow(10, Double(Int.random(in: -3...2, using: &rng)))   // 1e-9 ... 100 m (the plausible limit)
            let o = ObservationRecord(t: t, kind: "exit", rangeMeters: range,
                                      bearingRad: Double.random(in: -Double.pi...Double.pi, using: &rng),
                                      score: Double.random(in: 0...1, using: &rng))
            try w.append(o)
            written.append(o)
        }
        try w.append(sampleFrame(0))
        try w.close()
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.observations, written)
        for (a, r) in zip(written, b.observations) {
            XCTAssertEqual(a.rangeMeters.bitPattern, r.rangeMeters.bitPattern)
            XCTAssertEqual(a.t.bitPattern, r.t.bitPattern)
        }
    }

    func testLinesAreSortedKeysWithoutEscapedSlashes() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(0, image: "a.jpg"))
        try w.append(ExpectedAnnouncement(text: "Door 4/17 ahead"))
        try w.close()
        let frame = try String(contentsOf: dir.appendingPathComponent("frames.jsonl"), encoding: .utf8)
        XCTAssertTrue(frame.hasPrefix("{\"cameraToWorld\":["), frame)
        XCTAssertTrue(frame.hasSuffix("}\n"))
        XCTAssertEqual(frame.filter { $0 == "\n" }.count, 1)
        let expected = try String(contentsOf: dir.appendingPathComponent("expected.jsonl"), encoding: .utf8)
        XCTAssertTrue(expected.contains("4/17"), expected)
    }

    func testOptionalFilesAreOnlyCreatedWhenUsed() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(0))
        try w.close()
        let names = try FileManager.default.contentsOfDirectory(atPath: dir.path).sorted()
        XCTAssertEqual(names, ["frames.jsonl", "session.json"])
    }

    func testCreatesMissingParentDirectories() throws {
        let dir = try makeTemporaryDirectory(self).appendingPathComponent("a/b/walk")
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(0))
        try w.close()
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 1)
    }

    func testRefusesToOverwriteANonEmptyBundleAndLeavesItIntact() throws {
        let dir = try makeTemporaryDirectory(self)
        try writeSampleBundle(at: dir)
        let framesURL = dir.appendingPathComponent("frames.jsonl")
        let before = try Data(contentsOf: framesURL)
        let e = bundleError { try BundleWriter(directory: dir, info: sampleInfo) }
        XCTAssertEqual(e?.kind, .alreadyExists)
        XCTAssertTrue(e?.reason.contains("overwrite") ?? false)
        XCTAssertEqual(try Data(contentsOf: framesURL), before)
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 20)
    }

    func testOverwriteReplacesTheBundleFilesOnly() throws {
        let dir = try makeTemporaryDirectory(self)
        try writeSampleBundle(at: dir)
        try Data("notes".utf8).write(to: dir.appendingPathComponent("README.txt"))
        let w = try BundleWriter(directory: dir, info: sampleInfo, overwrite: true)
        try w.append(sampleFrame(5))
        try w.close()
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames.count, 1)
        XCTAssertTrue(b.observations.isEmpty && b.truth.isEmpty && b.expected.isEmpty)
        XCTAssertTrue(FileManager.default.fileExists(atPath: dir.appendingPathComponent("README.txt").path))
    }

    func testAnEmptyExistingDirectoryIsUsed() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(0))
        try w.close()
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 1)
    }

    func testRefusesInvalidRecordsAndWritesNothingForThem() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(1))
        var nan = sampleFrame(2)
        nan.cameraToWorld[12] = .nan
        XCTAssertEqual(bundleError { try w.append(nan) }?.kind, .invalidValue)
        var short = sampleFrame(2)
        short.cameraToWorld.removeLast()
        XCTAssertEqual(bundleError { try w.append(short) }?.kind, .invalidValue)
        let back = bundleError { try w.append(sampleFrame(0.5)) }
        XCTAssertEqual(back?.kind, .timestampOrder)
        XCTAssertEqual(back?.line, 2)
        XCTAssertEqual(bundleError { try w.append(sampleFrame(1)) }?.kind, .duplicateTimestamp)
        XCTAssertEqual(bundleError {
            try w.append(ObservationRecord(t: 1, kind: "exit", rangeMeters: 0, bearingRad: 0, score: 1))
        }?.kind, .invalidValue)
        try w.append(sampleFrame(2))
        try w.close()
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames.map(\.t), [1, 2])
        XCTAssertTrue(b.observations.isEmpty)
    }

    func testRefusesInvalidSessionInfo() throws {
        let dir = try makeTemporaryDirectory(self)
        var info = sampleInfo
        info.formatVersion = 2
        XCTAssertEqual(bundleError { try BundleWriter(directory: dir, info: info) }?.kind, .unsupportedVersion)
        info = sampleInfo
        info.signHeightMeters = -0.2
        XCTAssertEqual(bundleError { try BundleWriter(directory: dir, info: info) }?.kind, .invalidValue)
    }

    func testAppendAfterCloseThrows() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(0))
        try w.close()
        try w.close()   // twice is fine
        XCTAssertEqual(bundleError { try w.append(sampleFrame(1)) }?.kind, .closed)
    }

    /// A recording cut off by a crash: complete lines are on disk without close(); a half line written
    /// at the end (raw FileHandle) is dropped with a warning and every whole line is kept.
    func testCrashMidLineKeepsEveryCompleteLine() throws {
        let dir = try makeTemporaryDirectory(self)
        var w: BundleWriter? = try BundleWriter(directory: dir, info: sampleInfo)
        var frames: [FrameRecord] = []
        for i in 0..<50 {
            let f = sampleFrame(Double(i) / 30)
            try w!.append(f)
            frames.append(f)
        }
        // Before close(): with flushEveryLines 1 every line is already in the file.
        let onDisk = try SessionBundle.read(from: dir)
        XCTAssertEqual(onDisk.frames, frames)
        let half = try jsonLine(sampleFrame(50.0 / 30))
        try appendRaw(dir, "frames.jsonl", String(half.prefix(half.count / 2)))
        w = nil   // the "crashed" writer goes away; its close() does not repair the file
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames, frames)
        XCTAssertEqual(b.warnings.map(\.kind), [.truncatedLastLine])
        XCTAssertEqual(b.warnings.first?.line, 51)
    }

    func testFlushEveryNLinesWritesWholeLinesOnly() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo, flushEveryLines: 4)
        for i in 0..<10 { try w.append(sampleFrame(Double(i))) }
        let framesURL = dir.appendingPathComponent("frames.jsonl")
        let partial = try String(contentsOf: framesURL, encoding: .utf8)
        XCTAssertEqual(partial.filter { $0 == "\n" }.count, 8)
        XCTAssertTrue(partial.hasSuffix("\n"))
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 8)
        try w.flush()
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 10)
        XCTAssertEqual(w.lineCounts["frames.jsonl"], 10)
        try w.close()
    }

    func testImagesAreWrittenAtomicallyAndNeverReplaced() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        let jpeg = Data([0xFF, 0xD8, 0xFF, 0xE0, 1, 2, 3, 0xFF, 0xD9])
        try w.writeImage(named: "000001.jpg", data: jpeg)
        try w.append(sampleFrame(0, image: "000001.jpg"))
        XCTAssertEqual(bundleError { try w.writeImage(named: "000001.jpg", data: Data([0])) }?.kind, .alreadyExists)
        XCTAssertEqual(bundleError { try w.writeImage(named: "../escape.jpg", data: jpeg) }?.kind, .unsafeImageName)
        XCTAssertEqual(bundleError { try w.writeImage(named: "", data: jpeg) }?.kind, .unsafeImageName)
        try w.close()
        let b = try SessionBundle.read(from: dir)
        XCTAssertTrue(b.warnings.isEmpty)
        XCTAssertEqual(try Data(contentsOf: try XCTUnwrap(b.imageURL(for: b.frames[0]))), jpeg)
        let names = try FileManager.default.contentsOfDirectory(atPath: b.imagesDirectory.path)
        XCTAssertEqual(names, ["000001.jpg"])   // no temporary file left behind
    }

    func testConcurrentAppendsAreWholeLines() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        try w.append(sampleFrame(0))
        DispatchQueue.concurrentPerform(iterations: 400) { i in
            try? w.append(ObservationRecord(t: 1, kind: "exit", rangeMeters: Double(i + 1) / 4, bearingRad: 0, score: 0.5))
        }
        try w.close()
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(Set(b.observations.map(\.rangeMeters)), Set((1...400).map { Double($0) / 4 }))
    }

    func testStreamingReaderAcrossChunkBoundaries() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo, flushEveryLines: 100)
        var frames: [FrameRecord] = []
        for i in 0..<3000 {
            let f = sampleFrame(Double(i) / 60)
            frames.append(f)
            try w.append(f)
        }
        try w.close()
        let size = try FileManager.default.attributesOfItem(atPath: dir.appendingPathComponent("frames.jsonl").path)[.size] as! Int
        XCTAssertGreaterThan(size, 10 * 65536)   // many 64 KiB chunks
        let reader = try FramesReader(bundle: dir)
        var i = 0
        while let f = try reader.next() {
            XCTAssertEqual(f, frames[i])
            i += 1
            XCTAssertEqual(reader.lineNumber, i)
        }
        XCTAssertEqual(i, 3000)
        XCTAssertTrue(reader.warnings.isEmpty)
        XCTAssertNil(try reader.next())
    }
}
