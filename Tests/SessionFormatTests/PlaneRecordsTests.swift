import Foundation
import XCTest
@testable import SessionFormat

/// planes.jsonl: writing and reading back, the VIO-plane projection, the per-line errors (file and line named)
/// and the screening warnings (horizontal, zero extent, before a VIO reset, anchors that never update).
final class PlaneRecordsTests: XCTestCase {
    private var dir: URL!

    override func setUpWithError() throws {
        dir = try makeTemporaryDirectory(self, "planes")
        try writeSampleBundle(at: dir, frameCount: 20)   // frames at 0.0 ... 1.9 s, normal from 0.2 s
    }

    /// A wall 2 m in front of VIO east (normal pointing back at the camera), `width` m wide.
    private func wall(_ t: Double, _ id: String, _ event: PlaneEvent = .add, width: Double = 1.5) -> PlaneRecord {
        PlaneRecord(t: t, anchorId: id, event: event, centerInWorld: [2, 1.2, 0], normalInWorld: [-1, 0, 0],
                    widthMeters: width, heightMeters: 2)
    }

    private func writePlanes(_ records: [PlaneRecord]) throws {
        let lines = try records.map { try jsonLine($0) }
        try overwriteFile(dir, PlaneRecord.fileName, lines.joined(separator: "\n") + "\n")
    }

    private func planeWarnings(_ b: SessionBundle) -> [BundleWarning] { b.warnings.filter { $0.kind == .ignoredPlanes } }

    func testBundleWithoutPlanesReadsAsBefore() throws {
        let b = try SessionBundle.read(from: dir)
        XCTAssertTrue(b.planes.isEmpty)
        XCTAssertTrue(planeWarnings(b).isEmpty)
    }

    func testWriterAndReaderRoundTrip() throws {
        let out = try makeTemporaryDirectory(self, "planes-rt")
        let w = try BundleWriter(directory: out, info: sampleInfo)
        for i in 0..<5 { try w.append(sampleFrame(Double(i) * 0.1)) }
        let records = [wall(0.1, "A"), wall(0.2, "B"), wall(0.3, "A", .update, width: 2.5),
                       PlaneRecord(t: 0.4, anchorId: "B", event: .remove)]
        for r in records { try w.append(r) }
        try w.close()
        let b = try SessionBundle.read(from: out)
        XCTAssertEqual(b.planes, records)
        XCTAssertTrue(planeWarnings(b).isEmpty, "\(b.warnings)")
        // VIO plane: (east, north) = (x, -z); a normal along world -x points VIO west (yaw pi).
        let c = try XCTUnwrap(records[0].centerInVIOPlane)
        XCTAssertEqual(c.east, 2); XCTAssertEqual(c.north, -0.0)
        XCTAssertEqual(abs(try XCTUnwrap(records[0].normalYawInVIOPlaneRad)), Double.pi, accuracy: 1e-12)
        let southFacing = PlaneRecord(t: 0, anchorId: "S", event: .add, centerInWorld: [0, 1, 0], normalInWorld: [0, 0, 1], widthMeters: 1)
        XCTAssertEqual(try XCTUnwrap(southFacing.normalYawInVIOPlaneRad), -Double.pi / 2, accuracy: 1e-12)
    }

    func testWriterRefusesNaNPoseAndBadNormal() throws {
        let out = try makeTemporaryDirectory(self, "planes-bad")
        let w = try BundleWriter(directory: out, info: sampleInfo)
        try w.append(sampleFrame(0))
        var bad = wall(0.1, "A")
        bad.centerInWorld = [.nan, 1, 0]
        XCTAssertThrowsError(try w.append(bad)) { e in
            let err = e as! BundleError
            XCTAssertEqual(err.kind, .invalidValue)
            XCTAssertTrue(err.description.contains("planes.jsonl line 1"), err.description)
            XCTAssertTrue(err.reason.contains("centerInWorld[0]"), err.reason)
        }
        bad = wall(0.1, "A"); bad.normalInWorld = [0, 1, 0]
        XCTAssertThrowsError(try w.append(bad)) { e in XCTAssertTrue("\(e)".contains("not horizontal"), "\(e)") }
        bad = wall(0.1, "A"); bad.normalInWorld = [2, 0, 0]
        XCTAssertThrowsError(try w.append(bad)) { e in XCTAssertTrue("\(e)".contains("unit vector"), "\(e)") }
        bad = wall(0.1, "A"); bad.widthMeters = -1
        XCTAssertThrowsError(try w.append(bad)) { e in XCTAssertTrue("\(e)".contains("widthMeters"), "\(e)") }
        bad = wall(0.1, "A"); bad.widthMeters = nil
        XCTAssertThrowsError(try w.append(bad)) { e in XCTAssertTrue("\(e)".contains("without widthMeters"), "\(e)") }
        try w.close()
    }

    func testNaNOrNullPoseInFileIsAnErrorNamingFileAndLine() throws {
        let good = try jsonLine(wall(0.5, "A"))
        for badLine in [
            #"{"alignment":"vertical","anchorId":"B","centerInWorld":[NaN,1,0],"event":"add","normalInWorld":[1,0,0],"t":0.6,"widthMeters":1}"#,
            #"{"alignment":"vertical","anchorId":"B","centerInWorld":[null,1,0],"event":"add","normalInWorld":[1,0,0],"t":0.6,"widthMeters":1}"#,
            #"{"alignment":"vertical","anchorId":"B","centerInWorld":[1,1],"event":"add","normalInWorld":[1,0,0],"t":0.6,"widthMeters":1}"#,
            #"{"alignment":"vertical","anchorId":"B","event":"appear","t":0.6}"#,
        ] {
            try overwriteFile(dir, PlaneRecord.fileName, good + "\n" + badLine + "\n" + good.replacingOccurrences(of: "0.5", with: "0.7") + "\n")
            XCTAssertThrowsError(try SessionBundle.read(from: dir), badLine) { e in
                let err = e as! BundleError
                XCTAssertTrue(err.file.hasSuffix("planes.jsonl"), err.description)
                XCTAssertEqual(err.line, 2, err.description)
            }
        }
    }

    func testZeroExtentAndHorizontalPlanesAreDroppedWithWarnings() throws {
        var floorPlane = wall(0.6, "F")
        floorPlane.alignment = .horizontal
        floorPlane.normalInWorld = [0, 1, 0]
        try writePlanes([wall(0.5, "A", width: 0), wall(0.6, "B"), floorPlane, wall(0.7, "B", .update), wall(0.8, "C"),
                         wall(0.9, "A", .update, width: 1)])
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.planes.map(\.anchorId), ["B", "B", "C", "A"])
        let w = planeWarnings(b)
        XCTAssertTrue(w.contains { $0.line == 1 && $0.reason.contains("zero extent") }, "\(w)")
        XCTAssertTrue(w.contains { $0.line == 3 && $0.reason.contains("horizontal") }, "\(w)")
        // A's update comes before any accepted add: kept, as an addition, with a warning.
        XCTAssertTrue(w.contains { $0.line == 6 && $0.reason.contains("never added") }, "\(w)")
    }

    func testAnchorsThatNeverUpdateAreIgnoredWithAWarning() throws {
        try writePlanes([wall(0.5, "A"), wall(0.6, "B"), wall(0.7, "C")])
        let b = try SessionBundle.read(from: dir)
        XCTAssertTrue(b.planes.isEmpty)
        let w = planeWarnings(b)
        XCTAssertEqual(w.count, 1)
        XCTAssertTrue(w[0].reason.contains("is ever updated"), w[0].reason)
        XCTAssertTrue(w[0].description.contains("planes.jsonl line 1"), w[0].description)
    }

    func testAnchorsFromBeforeAVIOResetAreWarnedAbout() throws {
        // Frames with a relocalizing spell from 1.0 s to 1.2 s.
        var frames = (0..<20).map { sampleFrame(Double($0) * 0.1) }
        for i in 10...12 { frames[i].tracking = .limited; frames[i].trackingReason = .relocalizing }
        XCTAssertEqual(vioResetTimes(frames), [1.0])
        let lines: [(record: PlaneRecord, line: Int)] = [
            (wall(0.5, "A"), 1), (wall(0.6, "B"), 2), (wall(0.7, "A", .update), 3), (wall(1.5, "B", .update), 4),
        ]
        let (kept, warnings) = screenPlaneRecords(lines, frames: frames, file: "x/planes.jsonl")
        XCTAssertEqual(kept.count, 4)
        XCTAssertEqual(warnings.count, 1, "\(warnings)")
        XCTAssertTrue(warnings[0].reason.hasPrefix("1 plane anchor(s) last placed before a VIO reset"), warnings[0].reason)
        XCTAssertEqual(warnings[0].line, 3)
        XCTAssertTrue(isVIOResetState(.notAvailable, nil))
        XCTAssertFalse(isVIOResetState(.limited, .excessiveMotion))
    }

    func testEventsOutsideTheFramesAreDropped() throws {
        try writePlanes([wall(0.5, "A"), wall(0.6, "A", .update), wall(30, "A", .update)])
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.planes.count, 2)
        XCTAssertTrue(planeWarnings(b).contains { $0.line == 3 && $0.reason.contains("time span") })
    }
}
