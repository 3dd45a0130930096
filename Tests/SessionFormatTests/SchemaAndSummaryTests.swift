import Foundation
import XCTest
@testable import SessionFormat

/// docs/schemas/*.schema.json describe exactly the fields the records encode; the summary that
/// `wayfinder inspect` prints counts what the bundle holds.
final class SchemaAndSummaryTests: XCTestCase {
    private func schema(_ name: String) throws -> [String: Any] {
        let url = packageRoot.appendingPathComponent("docs/schemas/\(name).schema.json")
        return try XCTUnwrap(JSONSerialization.jsonObject(with: Data(contentsOf: url)) as? [String: Any], name)
    }

    private func keys<T: Encodable>(_ value: T) throws -> Set<String> {
        Set(try XCTUnwrap(JSONSerialization.jsonObject(with: JSONEncoder().encode(value)) as? [String: Any]).keys)
    }

    /// Schema properties = keys of a fully populated record; schema required = keys of a minimal one.
    private func check<T: Encodable>(_ name: String, full: T, minimal: T) throws {
        let s = try schema(name)
        let properties = Set((s["properties"] as? [String: Any] ?? [:]).keys)
        let required = Set(s["required"] as? [String] ?? [])
        XCTAssertEqual(properties, try keys(full), "\(name): properties")
        XCTAssertEqual(required, try keys(minimal), "\(name): required")
    }

    func testSchemasMatchTheRecords() throws {
        try check("session", full: SessionInfo(device: "d", appVersion: "1", mapId: "m", floorId: "f", start: "s",
                                               destination: "e", intrinsics: .iPhone8Full, carry: "handheld", source: "x"),
                  minimal: SessionInfo(device: "d", appVersion: "1"))
        var fullFrame = sampleFrame(0, image: "a.jpg")
        fullFrame.unsearchedSignKinds = ["placard"]
        try check("frame", full: fullFrame,
                  minimal: FrameRecord(t: 0, cameraToWorld: sampleFrame(0).cameraToWorld, intrinsics: .iPhone8Full))
        try check("observation",
                  full: ObservationRecord(t: 0, kind: "landmark", rangeMeters: 1, bearingRad: 0, score: 1, source: "imported",
                                          landmarkId: "306", text: "402"),
                  minimal: ObservationRecord(t: 0, kind: "exit", rangeMeters: 1, bearingRad: 0, score: 1))
        try check("truth", full: TruthRecord(t: 0, x: 1, y: 2, floorId: "4", headingRad: 0),
                  minimal: TruthRecord(t: 0, x: 1, y: 2, floorId: "4", headingRad: 0))
        try check("expected", full: ExpectedAnnouncement(text: "a", notBefore: 1, notAfter: 2),
                  minimal: ExpectedAnnouncement(text: "a"))
        try check("planes",
                  full: PlaneRecord(t: 0, anchorId: "A", event: .add, alignment: .vertical, centerInWorld: [0, 1, 2],
                                    normalInWorld: [1, 0, 0], widthMeters: 1, heightMeters: 2, classification: "wall"),
                  minimal: PlaneRecord(t: 0, anchorId: "A", event: .remove))
        let planeProps = try XCTUnwrap(try schema("planes")["properties"] as? [String: Any])
        XCTAssertEqual(Set(try XCTUnwrap((planeProps["event"] as? [String: Any])?["enum"] as? [String])),
                       Set(PlaneEvent.allCases.map(\.rawValue)))
        XCTAssertEqual(Set(try XCTUnwrap((planeProps["alignment"] as? [String: Any])?["enum"] as? [String])),
                       Set(PlaneAlignment.allCases.map(\.rawValue)))
        // Intrinsics definition and the tracking enums.
        let frame = try schema("frame")
        let defs = try XCTUnwrap((frame["$defs"] as? [String: Any])?["intrinsics"] as? [String: Any])
        XCTAssertEqual(Set((defs["properties"] as? [String: Any] ?? [:]).keys), try keys(CameraIntrinsics.iPhone8Full))
        let props = try XCTUnwrap(frame["properties"] as? [String: Any])
        let states = try XCTUnwrap((props["tracking"] as? [String: Any])?["enum"] as? [String])
        XCTAssertEqual(Set(states), Set([TrackingState.normal, .limited, .notAvailable].map(\.rawValue)))
        let reasons = try XCTUnwrap((props["trackingReason"] as? [String: Any])?["enum"] as? [String])
        XCTAssertEqual(Set(reasons), Set([TrackingReason.initializing, .excessiveMotion, .insufficientFeatures,
                                          .relocalizing].map(\.rawValue)))
    }

    func testSummaryCountsTheBundle() throws {
        let dir = try makeTemporaryDirectory(self)
        let w = try BundleWriter(directory: dir, info: sampleInfo)
        for i in 0..<31 {
            let name = i % 10 == 0 ? "f\(i).jpg" : nil
            if let name { try w.writeImage(named: name, data: Data([1, 2, 3])) }
            try w.append(sampleFrame(Double(i) / 10, image: name))
        }
        try w.append(ObservationRecord(t: 1, kind: "exit", rangeMeters: 3, bearingRad: 0, score: 0.8))
        try w.append(ObservationRecord(t: 1, kind: "landmark", rangeMeters: 3, bearingRad: 0, score: 1, landmarkId: "7"))
        try w.append(ObservationRecord(t: 2, kind: "landmark", rangeMeters: 2, bearingRad: 0, score: 1, landmarkId: "7"))
        try w.append(TruthRecord(t: 0, x: 0, y: 0, floorId: "4", headingRad: 0))
        try w.close()
        let s = try SessionBundle.read(from: dir).summary()
        XCTAssertEqual(s.formatVersion, 1)
        XCTAssertEqual(s.device, "iPhone10,4")
        XCTAssertEqual(s.mapId, "skeri-4")
        XCTAssertEqual(s.frameCount, 31)
        XCTAssertEqual(s.durationSeconds, 3, accuracy: 1e-12)
        XCTAssertEqual(s.frameRateHz, 10, accuracy: 1e-9)
        XCTAssertEqual(s.trackingShare["limited"] ?? 0, 2.0 / 31, accuracy: 1e-12)   // t = 0 and 0.1
        XCTAssertEqual(s.trackingShare["normal"] ?? 0, 29.0 / 31, accuracy: 1e-12)
        XCTAssertNil(s.trackingShare["notAvailable"])
        XCTAssertEqual(s.observationsByKind, ["exit": 1, "landmark": 2])
        XCTAssertEqual(s.distinctLandmarkCount, 1)
        XCTAssertTrue(s.hasTruth)
        XCTAssertEqual(s.imageFileCount, 4)
        XCTAssertEqual(s.framesWithImage, 4)
        XCTAssertTrue(s.warnings.isEmpty)
        // Path: sampleFrame moves (1, 0, -0.1) m per second of t.
        XCTAssertEqual(s.pathLengthMeters, 3 * (1 + 0.01).squareRoot(), accuracy: 1e-9)
        XCTAssertTrue(s.text.contains("frames           31 at 10.00 Hz"), s.text)
        let decoded = try JSONDecoder().decode(BundleSummary.self, from: JSONEncoder().encode(s))
        XCTAssertEqual(decoded, s)
    }

    func testSummaryListsWarnings() throws {
        let dir = try makeTemporaryDirectory(self)
        try writeSampleBundle(at: dir)
        try appendRaw(dir, "frames.jsonl", "{\"t\": 9, \"camera")
        let s = try SessionBundle.read(from: dir).summary()
        XCTAssertEqual(s.warnings.count, 1)
        XCTAssertTrue(s.text.contains("warnings         1"), s.text)
        XCTAssertTrue(s.text.contains("line 21"), s.text)
    }
}
