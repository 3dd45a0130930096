import Foundation
import XCTest
@testable import SessionFormat

/// Reading valid bundles and the damage cases: each must give a clear error naming the file and line,
/// or, for the recoverable ones, a warning with the rest of the data kept.
final class BundleReaderTests: XCTestCase {
    private var dir: URL!
    private var frames: [FrameRecord] = []

    override func setUpWithError() throws {
        dir = try makeTemporaryDirectory(self)
        frames = try writeSampleBundle(at: dir, frameCount: 20)
    }

    private func lines(_ file: String = "frames.jsonl") throws -> [String] {
        try String(contentsOf: dir.appendingPathComponent(file), encoding: .utf8)
            .split(separator: "\n", omittingEmptySubsequences: false).map(String.init).filter { !$0.isEmpty }
    }

    private func setLines(_ lines: [String], _ file: String = "frames.jsonl") throws {
        try overwriteFile(dir, file, lines.joined(separator: "\n") + "\n")
    }

    /// Replaces frames.jsonl line `n` (1-based) with `text`.
    private func replaceFrameLine(_ n: Int, with text: String) throws {
        var l = try lines()
        l[n - 1] = text
        try setLines(l)
    }

    /// Frame `i` as a mutable JSON dictionary.
    private func frameDict(_ i: Int) throws -> [String: Any] {
        try JSONSerialization.jsonObject(with: Data(jsonLine(frames[i]).utf8)) as! [String: Any]
    }

    private func line(of dict: [String: Any]) throws -> String {
        String(decoding: try JSONSerialization.data(withJSONObject: dict, options: [.sortedKeys]), as: UTF8.self)
    }

    private func readError() -> BundleError? { bundleError { try SessionBundle.read(from: self.dir) } }

    // MARK: Valid bundles

    func testReadsWhatTheWriterWrote() throws {
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.info, sampleInfo)
        XCTAssertEqual(b.frames, frames)
        XCTAssertEqual(b.observations.count, 2)
        XCTAssertEqual(b.truth.count, 2)
        XCTAssertEqual(b.expected, [ExpectedAnnouncement(text: "Turn left", notBefore: 0.3, notAfter: 1.5)])
        XCTAssertEqual(b.warnings, [])
    }

    func testOptionalFilesMayBeAbsent() throws {
        for f in ["observations.jsonl", "truth.jsonl", "expected.jsonl"] {
            try FileManager.default.removeItem(at: dir.appendingPathComponent(f))
        }
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames.count, 20)
        XCTAssertTrue(b.observations.isEmpty && b.truth.isEmpty && b.expected.isEmpty)
    }

    func testBlankLinesAndCRLFAreAccepted() throws {
        let l = try lines()
        try overwriteFile(dir, "frames.jsonl", "\n" + l.joined(separator: "\r\n\r\n") + "\r\n\n")
        XCTAssertEqual(try SessionBundle.read(from: dir).frames, frames)
    }

    func testUnknownFieldsAreIgnored() throws {
        var d = try frameDict(3)
        d["futureField"] = ["a": 1]
        try replaceFrameLine(4, with: try line(of: d))
        XCTAssertEqual(try SessionBundle.read(from: dir).frames.count, 20)
    }

    // MARK: Directory and session.json

    func testMissingDirectory() throws {
        let e = bundleError { try SessionBundle.read(from: self.dir.appendingPathComponent("nope")) }
        XCTAssertEqual(e?.kind, .missingDirectory)
        XCTAssertTrue(e?.description.contains("nope") ?? false)
    }

    func testBundlePathIsAFile() throws {
        let e = bundleError { try SessionBundle.read(from: self.dir.appendingPathComponent("frames.jsonl")) }
        XCTAssertEqual(e?.kind, .notADirectory)
    }

    func testMissingSessionJSON() throws {
        try FileManager.default.removeItem(at: dir.appendingPathComponent("session.json"))
        let e = readError()
        XCTAssertEqual(e?.kind, .missingFile)
        XCTAssertTrue(e?.file.hasSuffix("session.json") ?? false)
    }

    func testSessionJSONNotJSON() throws {
        try overwriteFile(dir, "session.json", "{ \"formatVersion\": 1, device: iPhone ")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidJSON)
        XCTAssertTrue(e?.file.hasSuffix("session.json") ?? false)
        XCTAssertTrue(e?.reason.hasPrefix("not valid JSON") ?? false, e?.reason ?? "")
    }

    func testSessionJSONWithoutVersion() throws {
        try overwriteFile(dir, "session.json", "{\"device\": \"x\", \"appVersion\": \"1\", \"signHeightMeters\": 0.2}")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertTrue(e?.reason.contains("formatVersion") ?? false)
    }

    func testUnsupportedFormatVersion() throws {
        try overwriteFile(dir, "session.json", "{\"formatVersion\": 2, \"somethingNew\": true}")
        let e = readError()
        XCTAssertEqual(e?.kind, .unsupportedVersion)
        XCTAssertTrue(e?.reason.contains("unsupported formatVersion 2") ?? false, e?.reason ?? "")
    }

    func testSessionJSONMissingField() throws {
        try overwriteFile(dir, "session.json", "{\"formatVersion\": 1, \"appVersion\": \"1\", \"signHeightMeters\": 0.2}")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertTrue(e?.reason.contains("missing field 'device'") ?? false, e?.reason ?? "")
    }

    func testSessionJSONNonPositiveSignHeight() throws {
        try overwriteFile(dir, "session.json", "{\"formatVersion\": 1, \"device\": \"d\", \"appVersion\": \"1\", \"signHeightMeters\": 0}")
        XCTAssertEqual(readError()?.kind, .invalidValue)
    }

    // MARK: frames.jsonl

    func testMissingFramesFile() throws {
        try FileManager.default.removeItem(at: dir.appendingPathComponent("frames.jsonl"))
        let e = readError()
        XCTAssertEqual(e?.kind, .missingFile)
        XCTAssertTrue(e?.file.hasSuffix("frames.jsonl") ?? false)
    }

    func testEmptyFramesFile() throws {
        try overwriteFile(dir, "frames.jsonl", "")
        let e = readError()
        XCTAssertEqual(e?.kind, .noFrames)
        XCTAssertTrue(e?.reason.contains("no frames") ?? false)
    }

    func testFramesFileWithOnlyACutOffLine() throws {
        try overwriteFile(dir, "frames.jsonl", String(try lines()[0].prefix(40)))
        XCTAssertEqual(readError()?.kind, .noFrames)
    }

    func testGarbageLineInTheMiddle() throws {
        try replaceFrameLine(7, with: "this is not json")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidJSON)
        XCTAssertEqual(e?.line, 7)
        XCTAssertTrue(e?.file.hasSuffix("frames.jsonl") ?? false)
        XCTAssertTrue(e?.description.contains("frames.jsonl line 7: not valid JSON") ?? false, e?.description ?? "")
    }

    func testCutOffLineInTheMiddleIsAnError() throws {
        let l = try lines()
        try replaceFrameLine(5, with: String(l[4].prefix(l[4].count / 2)))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidJSON)
        XCTAssertEqual(e?.line, 5)
        XCTAssertTrue(e?.reason.contains("middle of the file") ?? false, e?.reason ?? "")
    }

    func testTransformWith15Numbers() throws {
        var d = try frameDict(2)
        d["cameraToWorld"] = Array(frames[2].cameraToWorld.prefix(15))
        try replaceFrameLine(3, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertEqual(e?.line, 3)
        XCTAssertTrue(e?.reason.contains("15 numbers, expected 16") ?? false, e?.reason ?? "")
    }

    func testNaNAsStringInTransform() throws {
        let l = try lines()
        let bad = l[9].replacingOccurrences(of: "\"cameraToWorld\":[", with: "\"cameraToWorld\":[\"NaN\",")
            .replacingOccurrences(of: ",1],", with: "],")   // keep 16 elements
        try replaceFrameLine(10, with: bad)
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertEqual(e?.line, 10)
        XCTAssertTrue(e?.reason.contains("cameraToWorld[0]") ?? false, e?.reason ?? "")
        XCTAssertTrue(e?.reason.contains("NaN") ?? false, e?.reason ?? "")
    }

    func testOverflowingNumberInTransform() throws {
        let l = try lines()
        try replaceFrameLine(4, with: l[3].replacingOccurrences(of: ",1],", with: ",1e999],"))
        let e = readError()
        // Linux Foundation refuses the number while parsing; a parser that yields +inf is caught by validation.
        XCTAssertTrue([.invalidJSON, .invalidValue].contains(e?.kind), "\(String(describing: e))")
        XCTAssertEqual(e?.line, 4)
    }

    func testOverflowingNumberOnTheLastLineIsNotMistakenForATruncation() throws {
        let l = try lines()
        try replaceFrameLine(20, with: l[19].replacingOccurrences(of: ",1],", with: ",1e999],"))
        let e = readError()
        XCTAssertTrue([.invalidJSON, .invalidValue].contains(e?.kind), "\(String(describing: e))")
        XCTAssertEqual(e?.line, 20)
    }

    func testRowMajorTransformIsRejected() throws {
        var d = try frameDict(1)
        let m = frames[1].cameraToWorld
        d["cameraToWorld"] = (0..<16).map { m[($0 % 4) * 4 + $0 / 4] }   // transposed
        try replaceFrameLine(2, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertEqual(e?.line, 2)
        XCTAssertTrue(e?.reason.contains("bottom row") ?? false, e?.reason ?? "")
    }

    func testNonOrthonormalRotationIsRejected() throws {
        var d = try frameDict(1)
        var m = frames[1].cameraToWorld
        m[0] *= 1.1
        d["cameraToWorld"] = m
        try replaceFrameLine(2, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertTrue(e?.reason.contains("orthonormal") ?? false)
    }

    func testTimestampGoingBack() throws {
        var l = try lines()
        l.swapAt(11, 12)
        try setLines(l)
        let e = readError()
        XCTAssertEqual(e?.kind, .timestampOrder)
        XCTAssertEqual(e?.line, 13)
        XCTAssertTrue(e?.reason.contains("line 12") ?? false, e?.reason ?? "")
    }

    func testDuplicateTimestamp() throws {
        var l = try lines()
        l[8] = l[7]
        try setLines(l)
        let e = readError()
        XCTAssertEqual(e?.kind, .duplicateTimestamp)
        XCTAssertEqual(e?.line, 9)
    }

    func testUnknownTrackingState() throws {
        var d = try frameDict(5)
        d["tracking"] = "lost"
        try replaceFrameLine(6, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertEqual(e?.line, 6)
        XCTAssertTrue(e?.reason.contains("unknown tracking state 'lost'") ?? false, e?.reason ?? "")
    }

    func testUnknownTrackingReason() throws {
        var d = try frameDict(0)
        d["trackingReason"] = "sleepy"
        try replaceFrameLine(1, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertTrue(e?.reason.contains("unknown tracking reason 'sleepy'") ?? false, e?.reason ?? "")
    }

    func testNonPositiveFocalLength() throws {
        var d = try frameDict(4)
        var k = d["intrinsics"] as! [String: Any]
        k["fx"] = 0
        d["intrinsics"] = k
        try replaceFrameLine(5, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertEqual(e?.line, 5)
        XCTAssertTrue(e?.reason.contains("focal") ?? false)
    }

    func testNonPositiveImageSize() throws {
        var d = try frameDict(4)
        var k = d["intrinsics"] as! [String: Any]
        k["height"] = -1440
        d["intrinsics"] = k
        try replaceFrameLine(5, with: try line(of: d))
        XCTAssertEqual(readError()?.kind, .invalidValue)
    }

    func testUnsearchedSignKindsAreReadBackAndAbsentMeansNone() throws {
        var d = try frameDict(2)
        d["unsearchedSignKinds"] = ["placard", "restroom"]
        try replaceFrameLine(3, with: try line(of: d))
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames[2].unsearchedSignKinds, ["placard", "restroom"])
        XCTAssertNil(b.frames[1].unsearchedSignKinds)
        XCTAssertEqual(b.warnings, [])
    }

    func testUnsearchedSignKindsMustBeNonEmptyAndDistinct() throws {
        for (kinds, words) in [([""], "empty kind"), (["stairs", "stairs"], "names a kind twice")] {
            try setUpWithError()
            var d = try frameDict(4)
            d["unsearchedSignKinds"] = kinds
            try replaceFrameLine(5, with: try line(of: d))
            let e = readError()
            XCTAssertEqual(e?.kind, .invalidValue)
            XCTAssertEqual(e?.line, 5)
            XCTAssertTrue(e?.reason.contains(words) ?? false, e?.reason ?? "")
            XCTAssertTrue(e?.description.contains("frames.jsonl") ?? false, e?.description ?? "")
        }
    }

    func testMissingTimestampField() throws {
        var d = try frameDict(4)
        d.removeValue(forKey: "t")
        try replaceFrameLine(5, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertTrue(e?.reason.contains("missing field 't'") ?? false, e?.reason ?? "")
    }

    func testLineThatIsNotAnObject() throws {
        try replaceFrameLine(2, with: "[1, 2, 3]")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertTrue(e?.reason.contains("expected a JSON object") ?? false, e?.reason ?? "")
    }

    func testInvalidCompassHeading() throws {
        var d = try frameDict(4)
        d["compassHeadingDeg"] = -1
        try replaceFrameLine(5, with: try line(of: d))
        XCTAssertEqual(readError()?.kind, .invalidValue)
    }

    func testImageNameEscapingTheImagesDirectory() throws {
        var d = try frameDict(4)
        d["image"] = "../session.json"
        try replaceFrameLine(5, with: try line(of: d))
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertTrue(e?.reason.contains("image name") ?? false)
    }

    /// Decision: a frame naming a missing image is a warning (the poses and observations still replay;
    /// only the detector lacks input), one warning for all, naming the first line.
    func testMissingImagesAreOneWarning() throws {
        for i in [3, 6] {
            var d = try frameDict(i)
            d["image"] = "frame-\(i).jpg"
            try replaceFrameLine(i + 1, with: try line(of: d))
        }
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames.count, 20)
        XCTAssertEqual(b.warnings.count, 1)
        XCTAssertEqual(b.warnings.first?.kind, .missingImages)
        XCTAssertEqual(b.warnings.first?.line, 4)
        XCTAssertTrue(b.warnings.first?.reason.contains("2 of 2 frames") ?? false, b.warnings.first?.reason ?? "")
    }

    // MARK: Truncated last line (a crash while recording)

    func testTruncatedLastFrameLineIsAWarningAndTheRestKept() throws {
        let l = try lines()
        try overwriteFile(dir, "frames.jsonl", l.prefix(19).joined(separator: "\n") + "\n" + l[19].prefix(70))
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames, Array(frames.prefix(19)))
        XCTAssertEqual(b.warnings.count, 1)
        let w = try XCTUnwrap(b.warnings.first)
        XCTAssertEqual(w.kind, .truncatedLastLine)
        XCTAssertEqual(w.line, 20)
        XCTAssertTrue(w.file.hasSuffix("frames.jsonl"))
        XCTAssertTrue(w.description.contains("frames.jsonl line 20"), w.description)
    }

    func testTruncatedLastLineCutInsideAString() throws {
        let l = try lines()
        let cut = l[19].range(of: "\"tracking\":\"nor")!.upperBound
        try overwriteFile(dir, "frames.jsonl", l.prefix(19).joined(separator: "\n") + "\n" + l[19][..<cut])
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames.count, 19)
        XCTAssertEqual(b.warnings.map(\.kind), [.truncatedLastLine])
    }

    func testTruncatedLastObservationLine() throws {
        try appendRaw(dir, "observations.jsonl", "{\"bearingRad\":0.1,\"kind\":\"ex")
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.observations.count, 2)
        XCTAssertEqual(b.warnings.map(\.kind), [.truncatedLastLine])
        XCTAssertEqual(b.warnings.first?.line, 3)
        XCTAssertTrue(b.warnings.first?.file.hasSuffix("observations.jsonl") ?? false)
    }

    func testCompleteButInvalidLastLineIsAnError() throws {
        try replaceFrameLine(20, with: "{\"t\": 99}")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidRecord)
        XCTAssertEqual(e?.line, 20)
    }

    // MARK: observations, truth, expected

    func testNegativeObservationRange() throws {
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 0.9, kind: "exit", rangeMeters: -3, bearingRad: 0, score: 0.5)) + "\n")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertEqual(e?.line, 3)
        XCTAssertTrue(e?.file.hasSuffix("observations.jsonl") ?? false)
        XCTAssertTrue(e?.reason.contains("rangeMeters -3.0 is not positive") ?? false, e?.reason ?? "")
    }

    func testObservationBearingOutOfRange() throws {
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 0.9, kind: "exit", rangeMeters: 3, bearingRad: 4, score: 0.5)) + "\n")
        XCTAssertEqual(readError()?.kind, .invalidValue)
    }

    func testObservationScoreOutOfRange() throws {
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 0.9, kind: "exit", rangeMeters: 3, bearingRad: 0, score: 1.5)) + "\n")
        XCTAssertEqual(readError()?.kind, .invalidValue)
    }

    func testObservationTimeGoingBack() throws {
        try appendRaw(dir, "observations.jsonl", try jsonLine(
            ObservationRecord(t: 0.2, kind: "exit", rangeMeters: 3, bearingRad: 0, score: 0.5)) + "\n")
        let e = readError()
        XCTAssertEqual(e?.kind, .timestampOrder)
        XCTAssertEqual(e?.line, 3)
    }

    func testTruthWithEmptyFloorAndDuplicateTime() throws {
        try appendRaw(dir, "truth.jsonl", try jsonLine(TruthRecord(t: 0.2, x: 1, y: 2, floorId: "", headingRad: 0)) + "\n")
        XCTAssertEqual(readError()?.kind, .invalidValue)
        var l = try lines("truth.jsonl")
        l[2] = try jsonLine(TruthRecord(t: 0.1, x: 1, y: 2, floorId: "4", headingRad: 0))
        try setLines(l, "truth.jsonl")
        let e = readError()
        XCTAssertEqual(e?.kind, .duplicateTimestamp)
        XCTAssertTrue(e?.file.hasSuffix("truth.jsonl") ?? false)
    }

    func testExpectedWindowInverted() throws {
        try appendRaw(dir, "expected.jsonl", try jsonLine(ExpectedAnnouncement(text: "Arrived", notBefore: 5, notAfter: 2)) + "\n")
        let e = readError()
        XCTAssertEqual(e?.kind, .invalidValue)
        XCTAssertEqual(e?.line, 2)
        XCTAssertTrue(e?.file.hasSuffix("expected.jsonl") ?? false)
    }

    func testErrorDescriptionNamesFileAndLine() throws {
        try replaceFrameLine(7, with: "{")
        try replaceFrameLine(8, with: "x")
        let e = try XCTUnwrap(readError())
        XCTAssertEqual(e.description, "\(dir.appendingPathComponent("frames.jsonl").path) line 7: \(e.reason)")
    }
}
