import Foundation
import XCTest
@testable import SessionFormat

/// Imports the three real OCCaM walks (../shared/data/occamlab_invisible_map_arkit), reads the bundles back
/// with the one reader and checks physical facts about them.
final class OccamImporterTests: XCTestCase {
    /// Figures from the data's SOURCE.md: file, poses, sightings, distinct tags, duration s, path m.
    private let walks: [(file: String, poses: Int, sightings: Int, tags: Int, duration: Double, path: Double)] = [
        ("floor_2_straight_uncleaned.json", 1004, 54, 25, 502, 336),
        ("floor_2_obleft.json", 1120, 75, 25, 560, 384),
        ("oblique_209_occam.json", 926, 175, 20, 463, 282),
    ]

    /// Imported bundles, shared by the tests of this class (each walk is imported once per run).
    nonisolated(unsafe) private static var imported: [String: (SessionBundle, OccamImporter.Summary)] = [:]
    nonisolated(unsafe) private static var importRoot: URL?

    override class func tearDown() {
        if let importRoot { try? FileManager.default.removeItem(at: importRoot) }
        importRoot = nil
        imported = [:]
        super.tearDown()
    }

    private func importWalk(_ file: String) throws -> (SessionBundle, OccamImporter.Summary, URL) {
        let source = try sharedData("occamlab_invisible_map_arkit").appendingPathComponent(file)
        guard FileManager.default.fileExists(atPath: source.path) else { throw XCTSkip("\(source.path) absent") }
        if let hit = Self.imported[file] { return (hit.0, hit.1, source) }
        let root = Self.importRoot ?? FileManager.default.temporaryDirectory
            .appendingPathComponent("sessionformat-tests-occam-\(UUID().uuidString)", isDirectory: true)
        Self.importRoot = root
        let dir = root.appendingPathComponent(file, isDirectory: true)
        let summary = try OccamImporter.importWalk(from: source, to: dir, overwrite: true)
        let bundle = try SessionBundle.read(from: dir)
        Self.imported[file] = (bundle, summary)
        return (bundle, summary, source)
    }

    func testImportFiguresMatchTheSource() throws {
        for w in walks {
            let (b, s, _) = try importWalk(w.file)
            XCTAssertEqual(b.frames.count, w.poses, w.file)
            XCTAssertGreaterThan(b.frames.count, 100)
            XCTAssertEqual(s.sightingCount, w.sightings, w.file)
            XCTAssertEqual(b.observations.count, w.sightings, w.file)
            XCTAssertEqual(s.distinctTagCount, w.tags, w.file)
            XCTAssertEqual(s.skippedSightings, 0, w.file)
            XCTAssertEqual(s.poseMatrixOrder, "columnMajor")
            XCTAssertEqual(s.durationSeconds, w.duration, accuracy: 1, w.file)
            XCTAssertEqual(s.pathLengthMeters, w.path, accuracy: 1, w.file)
            XCTAssertTrue(b.warnings.isEmpty, "\(b.warnings)")
            XCTAssertEqual(b.info.mapId, String(w.file.dropLast(5)).replacingOccurrences(of: "_straight_uncleaned", with: ""))
            XCTAssertTrue(b.observations.allSatisfy { $0.kind == "landmark" && $0.source == "imported" && $0.landmarkId != nil })
        }
    }

    func testTimestampsIncreaseAtTwoHertz() throws {
        for w in walks {
            let (b, _, _) = try importWalk(w.file)
            let dts = zip(b.frames, b.frames.dropFirst()).map { $1.t - $0.t }
            XCTAssertTrue(dts.allSatisfy { $0 > 0 }, w.file)
            XCTAssertEqual(median(dts), 0.5, accuracy: 0.01, w.file)
            XCTAssertEqual(b.summary().frameRateHz, 2, accuracy: 0.05)
        }
    }

    /// The translation is the last column: the path starts at the ARKit origin, stays on one floor
    /// (height within a few meters) and moves at walking speed.
    func testTranslationIsTheLastColumnAndTheSpeedIsAWalk() throws {
        for w in walks {
            let (b, _, _) = try importWalk(w.file)
            let poses = b.frames.map { CameraPose(columnMajor: $0.cameraToWorld)! }
            let first = poses[0].positionInWorld
            XCTAssertEqual(first.x, 0, accuracy: 1e-6)
            XCTAssertEqual(first.y, 0, accuracy: 1e-6)
            XCTAssertEqual(first.z, 0, accuracy: 1e-6)
            let heights = poses.map { $0.positionInWorld.y }
            XCTAssertLessThan(heights.max()! - heights.min()!, 6, w.file)
            var speeds: [Double] = []
            for i in 1..<poses.count {
                let a = poses[i - 1].positionInVIOPlane, c = poses[i].positionInVIOPlane
                speeds.append(hypot(c.east - a.east, c.north - a.north) / (b.frames[i].t - b.frames[i - 1].t))
            }
            let m = median(speeds)
            XCTAssertLessThan(m, 2, w.file)
            XCTAssertGreaterThan(m, 0.3, w.file)
        }
    }

    /// The camera looks along -z: its horizontal forward direction agrees with the walking direction.
    /// These mapping walks were recorded with the phone in LANDSCAPE (camera x horizontal, roll near 0 or
    /// ±180 degrees), not in the portrait posture of arkit-frames.md (roll -90): checked, not assumed.
    func testCameraLooksWhereTheTravelerWalksAndIsHeldInLandscape() throws {
        for w in walks {
            let (b, _, _) = try importWalk(w.file)
            let poses = b.frames.map { CameraPose(columnMajor: $0.cameraToWorld)! }
            var cosines: [Double] = []
            for i in 1..<poses.count {
                let a = poses[i - 1].positionInVIOPlane, c = poses[i].positionInVIOPlane
                let step = hypot(c.east - a.east, c.north - a.north)
                guard step > 0.3 else { continue }
                let yaw = poses[i - 1].yawInVIOPlaneRad
                cosines.append(((c.east - a.east) * cos(yaw) + (c.north - a.north) * sin(yaw)) / step)
            }
            XCTAssertGreaterThan(median(cosines), 0.85, w.file)
            XCTAssertGreaterThan(Double(cosines.filter { $0 > 0 }.count) / Double(cosines.count), 0.85, w.file)
            // Landscape: |sin(roll)| small for most frames, i.e. camera x (image u) horizontal.
            let landscape = poses.filter { abs(sin($0.rollRad)) < 0.5 }.count
            XCTAssertGreaterThan(Double(landscape) / Double(poses.count), 0.9, w.file)
            let pitchDeg = median(poses.map { $0.pitchRad * 180 / .pi })
            XCTAssertLessThan(pitchDeg, 0, w.file)      // looking slightly down
            XCTAssertGreaterThan(pitchDeg, -30, w.file)
        }
    }

    func testSightingRangesAndBearingsArePlausible() throws {
        for w in walks {
            let (b, _, _) = try importWalk(w.file)
            for o in b.observations {
                XCTAssertGreaterThan(o.rangeMeters, 0.2, w.file)
                XCTAssertLessThan(o.rangeMeters, 15, w.file)
                // Inside the camera's horizontal field of view (half angle atan(960/1590) = 31 deg).
                XCTAssertLessThan(abs(o.bearingRad), 40 * Double.pi / 180, w.file)
            }
            let frameTimes = Set(b.frames.map(\.t))
            XCTAssertTrue(b.observations.allSatisfy { frameTimes.contains($0.t) }, "each sighting at a frame time")
        }
    }

    /// The same tag seen from different poses lands at the same place on the VIO plane when rebuilt
    /// from the camera pose plus range and bearing; with the bearing sign flipped it scatters (checked on
    /// oblique_209, the walk with the most sightings per tag). Tolerance: 0.5 m median (VIO drift).
    func testRepeatedSightingsOfATagAgree() throws {
        func spread(_ b: SessionBundle, bearingSign: Double) -> Double {
            var byTime: [Double: CameraPose] = [:]
            for f in b.frames { byTime[f.t] = CameraPose(columnMajor: f.cameraToWorld) }
            var points: [String: [(Double, Double)]] = [:]
            for o in b.observations {
                let cam = byTime[o.t]!
                let p = cam.positionInVIOPlane
                let a = cam.yawInVIOPlaneRad + bearingSign * o.bearingRad
                points[o.landmarkId!, default: []].append((p.east + o.rangeMeters * cos(a), p.north + o.rangeMeters * sin(a)))
            }
            var spreads: [Double] = []
            for pts in points.values where pts.count > 1 {
                let me = median(pts.map(\.0)), mn = median(pts.map(\.1))
                spreads.append(median(pts.map { hypot($0.0 - me, $0.1 - mn) }))
            }
            return median(spreads)
        }
        for w in walks {
            let (b, _, _) = try importWalk(w.file)
            XCTAssertLessThan(spread(b, bearingSign: 1), 0.5, w.file)
        }
        let (b, _, _) = try importWalk("oblique_209_occam.json")
        XCTAssertLessThan(spread(b, bearingSign: 1), 0.05)
        XCTAssertGreaterThan(spread(b, bearingSign: -1), 2 * spread(b, bearingSign: 1))
    }

    /// The tag translation is in the computer-vision camera frame (x = u right, y = v down, z forward):
    /// projected through the stored intrinsics it falls on the centre of the tag's pixel corners.
    func testTagPoseConventionAgainstPixelCorners() throws {
        let source = try sharedData("occamlab_invisible_map_arkit").appendingPathComponent("oblique_209_occam.json")
        let root = try JSONSerialization.jsonObject(with: Data(contentsOf: source)) as! [String: Any]
        let groups = root["tag_data"] as! [[[String: Any]]]
        var errors: [Double] = []
        for d in groups.joined() {
            let p = (d["tag_pose"] as! [NSNumber]).map(\.doubleValue)
            let k = (d["camera_intrinsics"] as! [NSNumber]).map(\.doubleValue)
            let c = (d["tag_corners_pixel_coordinates"] as! [NSNumber]).map(\.doubleValue)
            let u = k[0] * p[3] / p[11] + k[2], v = k[1] * p[7] / p[11] + k[3]
            let cu = (c[0] + c[2] + c[4] + c[6]) / 4, cv = (c[1] + c[3] + c[5] + c[7]) / 4
            errors.append(hypot(u - cu, v - cv))
        }
        XCTAssertEqual(errors.count, 175)
        XCTAssertLessThan(median(errors), 10)   // pixels
    }

    func testRangeBearingGeometry() throws {
        // Camera at the origin, portrait, facing VIO north (yaw pi/2). A tag 2 m ahead and 1 m to the right
        // in the image frame: CV x = +1 is image u = right... in portrait image u points DOWN in the world,
        // so use a landscape camera (roll 0) where u is to the right.
        let cam = CameraPose(positionInWorld: (x: 0, y: 1.5, z: 0), yawRad: .pi / 2, pitchRad: 0, rollRad: 0)
        let rb = try XCTUnwrap(OccamImporter.rangeBearing(tagTranslationCV: (1, 0.3, 2), camera: cam))
        XCTAssertEqual(rb.rangeMeters, hypot(1, 2), accuracy: 1e-9)
        XCTAssertEqual(rb.bearingRad, -atan2(1, 2), accuracy: 1e-9)   // right of forward = negative
        XCTAssertNil(OccamImporter.rangeBearing(tagTranslationCV: (0, 0, -1), camera: cam))   // behind
        // Portrait (roll -pi/2): image u points down, image v points to the traveler's LEFT... v down in
        // the image is camera -y; camera y is world-horizontal to the right, so +v is to the left.
        let portrait = CameraPose(positionInWorld: (x: 0, y: 1.5, z: 0), yawRad: 0, pitchRad: 0, rollRad: -.pi / 2)
        let left = try XCTUnwrap(OccamImporter.rangeBearing(tagTranslationCV: (0, 1, 2), camera: portrait))
        XCTAssertEqual(left.bearingRad, atan2(1, 2), accuracy: 1e-9)
    }

    func testMalformedFilesGiveClearErrors() throws {
        let dir = try makeTemporaryDirectory(self, "occam-bad")
        let bad = dir.appendingPathComponent("bad.json")
        try Data("{\"map_id\": \"x\", \"pose_data\": [{\"id\": 0, \"timestamp\": 1, \"pose\": [1, 0, 0]}], \"tag_data\": []}".utf8)
            .write(to: bad)
        XCTAssertThrowsError(try OccamImporter.convert(from: bad)) { e in
            let s = String(describing: e)
            XCTAssertTrue(s.contains("bad.json") && s.contains("pose_data[0]") && s.contains("16"), s)
        }
        try Data("[1, 2]".utf8).write(to: bad)
        XCTAssertThrowsError(try OccamImporter.convert(from: bad)) { e in
            XCTAssertTrue(String(describing: e).contains("not an OCCaM InvisibleMap recording"), "\(e)")
        }
        XCTAssertThrowsError(try OccamImporter.convert(from: dir.appendingPathComponent("absent.json"))) { e in
            XCTAssertTrue(String(describing: e).contains("cannot read"), "\(e)")
        }
    }

    func testRowMajorPosesAreTransposed() throws {
        let dir = try makeTemporaryDirectory(self, "occam-rm")
        let cm = CameraPose(positionInWorld: (x: 1, y: 0.2, z: -3), yawRad: 0.4, pitchRad: -0.1, rollRad: 0).columnMajor
        let rm = (0..<16).map { cm[($0 % 4) * 4 + $0 / 4] }
        let json: [String: Any] = [
            "map_id": "test 1", "tag_data": [[[String: Any]]](),
            "pose_data": [["id": 0, "timestamp": 1.0, "pose": rm], ["id": 1, "timestamp": 1.5, "pose": rm]],
        ]
        let file = dir.appendingPathComponent("rm.json")
        try JSONSerialization.data(withJSONObject: json).write(to: file)
        let c = try OccamImporter.convert(from: file)
        XCTAssertEqual(c.summary.poseMatrixOrder, "rowMajor")
        for (a, b) in zip(c.frames[0].cameraToWorld, cm) { XCTAssertEqual(a, b, accuracy: 1e-12) }
        XCTAssertEqual(c.info.mapId, "test")
    }

    /// Found by wayfinder-fuzz (target occam, docs/fuzzing.md): a pose that is not a rigid transform used to
    /// convert, and the bundle writer then refused it ("refusing to write") after the bundle directory had
    /// been created. The converter now names the pose in the OCCaM file.
    func testNonRigidPosesAreRefusedWithThePoseNamed() throws {
        let dir = try makeTemporaryDirectory(self, "occam-fuzz")
        let file = dir.appendingPathComponent("scaled.json")
        var scaled = CameraPose(positionInWorld: (x: 0, y: 1.4, z: 0), yawRad: 0, pitchRad: 0, rollRad: 0).columnMajor
        scaled[10] = 4_294_967_296  // a 2^32 entry in the rotation: bottom row still (0, 0, 0, 1)
        let good = CameraPose(positionInWorld: (x: 0.2, y: 1.4, z: -0.5), yawRad: 0, pitchRad: 0, rollRad: 0).columnMajor
        let json: [String: Any] = ["map_id": "m 1", "tag_data": [[[String: Any]]](),
                                   "pose_data": [["id": 7, "timestamp": 1.0, "pose": scaled], ["id": 8, "timestamp": 1.5, "pose": good]]]
        try JSONSerialization.data(withJSONObject: json).write(to: file)
        XCTAssertThrowsError(try OccamImporter.convert(from: file)) { e in
            let s = String(describing: e)
            XCTAssertTrue(s.hasPrefix(file.path + ": pose_data id 7 (timestamp 1.0): cameraToWorld rotation is not orthonormal"), s)
        }
        let out = dir.appendingPathComponent("bundle")
        XCTAssertThrowsError(try OccamImporter.importWalk(from: file, to: out)) { e in XCTAssertTrue(e is OccamImporter.ImportError, "\(e)") }
        XCTAssertFalse(FileManager.default.fileExists(atPath: out.path), "nothing is written for a refused file")
        // Control: with the rigid pose in its place the file converts.
        let fixed: [String: Any] = ["map_id": "m 1", "tag_data": [[[String: Any]]](),
                                    "pose_data": [["id": 7, "timestamp": 1.0, "pose": good], ["id": 8, "timestamp": 1.5, "pose": good]]]
        try JSONSerialization.data(withJSONObject: fixed).write(to: file)
        XCTAssertEqual(try OccamImporter.convert(from: file).frames.count, 2)
    }

    /// Found by wayfinder-fuzz (target occam): a file of exactly 513 '[' trapped inside Foundation's
    /// JSONDecoder (its nesting-limit error path); the importer now refuses deep nesting itself.
    func testDeeplyNestedJSONIsAnErrorNotATrap() throws {
        let dir = try makeTemporaryDirectory(self, "occam-deep")
        let file = dir.appendingPathComponent("deep.json")
        for text in [String(repeating: "[", count: 513), String(repeating: "[", count: 65) + String(repeating: "]", count: 65),
                     "{\"pose_data\": " + String(repeating: "[", count: 600)] {
            try Data(text.utf8).write(to: file)
            XCTAssertThrowsError(try OccamImporter.convert(from: file)) { e in
                XCTAssertTrue(String(describing: e).contains("levels deep (at most 64 accepted)"), "\(e)")
            }
        }
        // Brackets inside strings do not count; 64 levels are accepted by the depth check (then fail as JSON).
        XCTAssertEqual(JSONNesting.depth(Data("{\"map_id\": \"[[[[\\\"[[\", \"a\": [[1]]}".utf8)), 3)
        try Data((String(repeating: "[", count: 64) + String(repeating: "]", count: 64)).utf8).write(to: file)
        XCTAssertThrowsError(try OccamImporter.convert(from: file)) { e in
            XCTAssertTrue(String(describing: e).contains("not an OCCaM InvisibleMap recording: "), "\(e)")
            XCTAssertFalse(String(describing: e).contains("levels deep"), "\(e)")
        }
    }
}
