import Foundation
import XCTest
@testable import SessionFormat
import TestRandom

/// A fresh empty directory under the temporary directory, removed when the test ends.
func makeTemporaryDirectory(_ test: XCTestCase, _ label: String = "bundle") throws -> URL {
    let url = FileManager.default.temporaryDirectory
        .appendingPathComponent("sessionformat-tests-\(label)-\(UUID().uuidString)", isDirectory: true)
    try FileManager.default.createDirectory(at: url, withIntermediateDirectories: true)
    test.addTeardownBlock { try? FileManager.default.removeItem(at: url) }
    return url
}

/// The package root, found from this file's path (Tests/SessionFormatTests/TestSupport.swift).
let packageRoot = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent()
    .deletingLastPathComponent()

/// ../shared/data/NAME next to the package root; XCTSkip when the shared data are absent.
func sharedData(_ name: String) throws -> URL {
    let url = packageRoot.deletingLastPathComponent().appendingPathComponent("shared/data/\(name)", isDirectory: true)
    guard FileManager.default.fileExists(atPath: url.path) else {
        throw XCTSkip("shared data \(url.path) not present")
    }
    return url
}

/// A valid frame at time `t`: the camera walks along VIO east at 1 m/s, portrait, looking slightly down.
func sampleFrame(_ t: Double, image: String? = nil) -> FrameRecord {
    let pose = CameraPose(positionInWorld: (x: t * 1.0, y: 1.4, z: -0.1 * t), yawRad: 0.1 * t, pitchRad: -0.1,
                          rollRad: -Double.pi / 2)
    return FrameRecord(t: t, cameraToWorld: pose.columnMajor, tracking: t < 0.2 ? .limited : .normal,
                       trackingReason: t < 0.2 ? .initializing : nil, intrinsics: .iPhone8Full,
                       relativeAltitudeMeters: 0.01 * t, compassHeadingDeg: 90, image: image, compassAccuracyDeg: 15)
}

/// session.json content used by the tests.
let sampleInfo = SessionInfo(device: "iPhone10,4", appVersion: "test 1", mapId: "skeri-4", floorId: "4",
                             start: "elevator", destination: "room-417", intrinsics: .iPhone8Full, carry: "handheld")

/// Writes a valid bundle with `frameCount` frames at 10 Hz, two observations, truth and one expected line.
@discardableResult
func writeSampleBundle(at dir: URL, frameCount: Int = 20) throws -> [FrameRecord] {
    let w = try BundleWriter(directory: dir, info: sampleInfo, overwrite: true)
    var frames: [FrameRecord] = []
    for i in 0..<frameCount {
        let f = sampleFrame(Double(i) * 0.1)
        try w.append(f)
        frames.append(f)
    }
    try w.append(ObservationRecord(t: 0.5, kind: "exit", rangeMeters: 4.2, bearingRad: 0.3, score: 0.9, source: "simulated"))
    try w.append(ObservationRecord(t: 0.5, kind: "exit", rangeMeters: 7.0, bearingRad: -0.2, score: 0.6, source: "simulated"))
    try w.append(TruthRecord(t: 0, x: 1, y: 2, floorId: "4", headingRad: 0))
    try w.append(TruthRecord(t: 0.1, x: 1.1, y: 2, floorId: "4", headingRad: 0.01))
    try w.append(ExpectedAnnouncement(text: "Turn left", notBefore: 0.3, notAfter: 1.5))
    try w.close()
    return frames
}

/// Frame line text (sorted keys, as the writer writes it).
func jsonLine<T: Encodable>(_ value: T) throws -> String {
    let e = JSONEncoder()
    e.outputFormatting = [.sortedKeys, .withoutEscapingSlashes]
    return String(decoding: try e.encode(value), as: UTF8.self)
}

/// Replaces the content of `file` in `dir` with `text` (raw bytes, no newline added).
func overwriteFile(_ dir: URL, _ file: String, _ text: String) throws {
    try Data(text.utf8).write(to: dir.appendingPathComponent(file))
}

/// Appends raw text to a file with a plain FileHandle (what a crash in the middle of a write leaves).
func appendRaw(_ dir: URL, _ file: String, _ text: String) throws {
    let h = try FileHandle(forWritingTo: dir.appendingPathComponent(file))
    try h.seekToEnd()
    try h.write(contentsOf: Data(text.utf8))
    try h.close()
}

/// The BundleError `body` throws; fails the test when it throws something else or nothing.
func bundleError(_ body: () throws -> Any, file: StaticString = #filePath, line: UInt = #line) -> BundleError? {
    do {
        _ = try body()
        XCTFail("expected a BundleError, nothing was thrown", file: file, line: line)
    } catch let e as BundleError {
        return e
    } catch {
        XCTFail("expected a BundleError, got \(error)", file: file, line: line)
    }
    return nil
}

/// Median of a non-empty array.
func median(_ values: [Double]) -> Double {
    let s = values.sorted()
    return s.count % 2 == 1 ? s[s.count / 2] : (s[s.count / 2 - 1] + s[s.count / 2]) / 2
}
