import Foundation

/// Imports the OCCaM Lab InvisibleMap recordings (../shared/data/occamlab_invisible_map_arkit, SOURCE.md):
/// real ARKit walks with AprilTag sightings, into a session bundle.
///
/// Layout read (checked on the three files):
/// - `map_id` (string, e.g. "floor_2 82489399050875": map name and a number);
/// - `pose_data[]`: `id`, `timestamp` (s, ARKit clock), `pose` = 16 numbers, the ARKit camera-to-world
///   transform stored column-major (translation at 12, 13, 14). The order is verified per file from the
///   bottom row; a file stored row-major is transposed, a mix of both is refused.
/// - `tag_data[][]` (groups of detections): `tag_id`, `pose_id`, `timestamp`, `tag_pose` = 16 numbers, the
///   tag's pose in the camera frame stored ROW-major (translation at 3, 7, 11) in the computer-vision camera
///   convention (x = image u right, y = image v down, z forward: the translation projects through
///   `camera_intrinsics` onto the tag's pixel corners), `camera_intrinsics` = [fx, fy, cx, cy] pixels.
///
/// Output: one `FrameRecord` per pose (tracking `normal`: the file has no state; intrinsics of the
/// detections made from that pose, else the latest earlier ones, at 1920 x 1440), and one
/// `ObservationRecord` per sighting: kind `landmark`, `landmarkId` = tag id, source `imported`, score 1,
/// `rangeMeters` = horizontal distance camera -> tag centre, `bearingRad` = horizontal angle of the tag from
/// the camera's forward direction, positive to the left (CameraPose conventions). The tag's position in
/// the ARKit camera frame is (x, -y, -z) of its computer-vision position.
public enum OccamImporter {
    /// Image size of the InvisibleMap captures (not stored in the files; cx, cy ≈ 954, 718 fit it).
    public static let imageWidth = 1920
    /// Image height, pixels.
    public static let imageHeight = 1440

    /// Figures of one import.
    public struct Summary: Codable, Hashable, Sendable {
        /// `map_id` as stored in the file.
        public var originalMapId: String
        /// Frames written (one per distinct pose timestamp).
        public var frameCount: Int
        /// Last minus first frame time, seconds.
        public var durationSeconds: Double
        /// ARKit path length (3-D), meters.
        public var pathLengthMeters: Double
        /// Observations written (tag sightings).
        public var sightingCount: Int
        /// Distinct tag ids sighted.
        public var distinctTagCount: Int
        /// Sightings dropped: unknown pose id, malformed tag pose, tag behind the camera or at the camera, range over
        /// `ObservationRecord.maximumRangeMeters`, or a sighting the bundle format refuses (e.g. an infinite range).
        public var skippedSightings: Int
        /// Poses dropped because they repeat the previous pose's timestamp.
        public var droppedDuplicatePoses: Int
        /// `columnMajor` (as documented) or `rowMajor` (transposed on import).
        public var poseMatrixOrder: String
    }

    /// A failure to import, naming the file and the problem.
    public struct ImportError: Error, CustomStringConvertible, Sendable {
        /// Path of the OCCaM file.
        public var file: String
        /// What is wrong.
        public var reason: String
        /// `PATH: REASON`.
        public var description: String { "\(file): \(reason)" }
    }

    /// The converted recording, before anything is written.
    public struct Converted: Sendable {
        /// session.json content.
        public var info: SessionInfo
        /// Frames in time order.
        public var frames: [FrameRecord]
        /// Tag sightings in time order.
        public var observations: [ObservationRecord]
        /// Figures.
        public var summary: Summary
    }

    /// Reads the OCCaM file at `file` and writes the bundle directory `bundleDir` with `BundleWriter`.
    /// Throws `ImportError` for an unreadable or malformed file, `BundleError` when writing fails (e.g. a
    /// non-empty `bundleDir` without `overwrite`).
    @discardableResult
    public static func importWalk(from file: URL, to bundleDir: URL, overwrite: Bool = false) throws -> Summary {
        let c = try convert(from: file)
        let writer = try BundleWriter(directory: bundleDir, info: c.info, overwrite: overwrite, flushEveryLines: 256)
        for f in c.frames { try writer.append(f) }
        for o in c.observations { try writer.append(o) }
        try writer.close()
        return c.summary
    }

    /// Reads and converts the OCCaM file at `file` (no output written).
    public static func convert(from file: URL) throws -> Converted {
        func fail(_ reason: String) -> ImportError { ImportError(file: file.path, reason: reason) }
        let data: Data
        do {
            // A regular file only (a FIFO or /dev/zero would block or never end), at most 1 GiB.
            data = try BundleFileAccess.openForReading(file, root: nil).readAll(limit: 1 << 30)
        } catch let e as BundleError {
            throw fail("cannot read: \(e.reason)")
        } catch {
            throw fail("cannot read: \(error.localizedDescription)")
        }
        // Foundation's JSONDecoder (Swift 6.3 toolchain) traps instead of throwing on text that ends exactly at
        // its 512-level nesting limit (e.g. 513 '['; found by wayfinder-fuzz, docs/fuzzing.md): deep nesting
        // is refused here first. An OCCaM file nests 5 levels.
        let depth = JSONNesting.depth(data)
        guard depth <= JSONNesting.maximumDepth else {
            throw fail("not an OCCaM InvisibleMap recording: JSON nested \(depth) levels deep (at most \(JSONNesting.maximumDepth) accepted)")
        }
        let root: OccamFile
        do { root = try JSONDecoder().decode(OccamFile.self, from: data) } catch {
            throw fail("not an OCCaM InvisibleMap recording: \(describeDecodingError(error))")
        }
        guard !root.pose_data.isEmpty else { throw fail("pose_data is empty") }
        for (i, p) in root.pose_data.enumerated() where p.pose.count != 16 || !p.pose.allSatisfy(\.isFinite) {
            throw fail("pose_data[\(i)] (id \(p.id)): pose must be 16 finite numbers, has \(p.pose.count)")
        }

        // Matrix order, decided from the bottom row over the whole file.
        func bottomRowOK(_ m: [Double], _ idx: [Int]) -> Bool {
            abs(m[idx[0]]) < 1e-3 && abs(m[idx[1]]) < 1e-3 && abs(m[idx[2]]) < 1e-3 && abs(m[15] - 1) < 1e-3
        }
        var columnOnly = 0, rowOnly = 0
        for p in root.pose_data {
            let col = bottomRowOK(p.pose, [3, 7, 11]), row = bottomRowOK(p.pose, [12, 13, 14])
            if col && !row { columnOnly += 1 }
            if row && !col { rowOnly += 1 }
        }
        if columnOnly > 0 && rowOnly > 0 {
            throw fail("pose_data mixes column-major (\(columnOnly)) and row-major (\(rowOnly)) matrices")
        }
        let rowMajor = rowOnly > 0
        func transposed(_ m: [Double]) -> [Double] { (0..<16).map { m[($0 % 4) * 4 + $0 / 4] } }

        // Poses in time order; a repeated timestamp keeps the first pose.
        let sortedPoses = root.pose_data.sorted { $0.timestamp < $1.timestamp }
        var poses: [(id: Int, t: Double, m: [Double])] = []
        var dropped = 0
        for p in sortedPoses {
            if let last = poses.last, p.timestamp <= last.t { dropped += 1; continue }
            poses.append((p.id, p.timestamp, rowMajor ? transposed(p.pose) : p.pose))
        }
        var poseById: [Int: [Double]] = [:]
        for p in root.pose_data { poseById[p.id] = rowMajor ? transposed(p.pose) : p.pose }

        // Intrinsics per pose id from the detections made there.
        let detections = root.tag_data.flatMap { $0 }
        var intrinsicsByPose: [Int: CameraIntrinsics] = [:]
        for d in detections {
            guard intrinsicsByPose[d.pose_id] == nil, let k = d.camera_intrinsics, k.count == 4 else { continue }
            let ci = CameraIntrinsics(fx: k[0], fy: k[1], cx: k[2], cy: k[3], width: imageWidth, height: imageHeight)
            if ci.validationProblem() == nil { intrinsicsByPose[d.pose_id] = ci }
        }
        let firstKnown = poses.lazy.compactMap { intrinsicsByPose[$0.id] }.first
            ?? intrinsicsByPose.values.first ?? CameraIntrinsics.iPhone8Full
        var current = firstKnown
        var frames: [FrameRecord] = []
        frames.reserveCapacity(poses.count)
        for p in poses {
            if let k = intrinsicsByPose[p.id] { current = k }
            let frame = FrameRecord(t: p.t, cameraToWorld: p.m, tracking: .normal, intrinsics: current)
            // The bundle's own frame checks (rigid transform, finite time...), so that a pose the writer would
            // refuse is reported here against the OCCaM file.
            if let problem = frame.validationProblem() {
                throw fail("pose_data id \(p.id) (timestamp \(p.t)): \(problem)")
            }
            frames.append(frame)
        }

        // Sightings.
        var observations: [ObservationRecord] = []
        var skipped = 0
        for d in detections {
            guard let m = poseById[d.pose_id], let camera = CameraPose(columnMajor: m), d.tag_pose.count == 16,
                  d.tag_pose.allSatisfy(\.isFinite), d.timestamp.isFinite,
                  abs(d.tag_pose[12]) < 1e-3, abs(d.tag_pose[13]) < 1e-3, abs(d.tag_pose[14]) < 1e-3,
                  let rb = rangeBearing(tagTranslationCV: (d.tag_pose[3], d.tag_pose[7], d.tag_pose[11]), camera: camera),
                  rb.rangeMeters <= ObservationRecord.maximumRangeMeters
            else { skipped += 1; continue }
            let o = ObservationRecord(t: d.timestamp, kind: "landmark", rangeMeters: rb.rangeMeters, bearingRad: rb.bearingRad,
                                      score: 1, source: "imported", landmarkId: String(d.tag_id))
            guard o.validationProblem() == nil else { skipped += 1; continue }
            observations.append(o)
        }
        observations = observations.enumerated().sorted {
            $0.element.t != $1.element.t ? $0.element.t < $1.element.t : $0.offset < $1.offset
        }.map(\.element)

        var path = 0.0
        for (a, b) in zip(frames, frames.dropFirst()) {
            let p = a.cameraToWorld, q = b.cameraToWorld
            path += ((q[12] - p[12]) * (q[12] - p[12]) + (q[13] - p[13]) * (q[13] - p[13])
                + (q[14] - p[14]) * (q[14] - p[14])).squareRoot()
        }
        let mapName = root.map_id.split(separator: " ").first.map(String.init) ?? root.map_id
        let info = SessionInfo(
            device: "iPhone (OCCaM Lab InvisibleMap app)", appVersion: "wayfinder import-occam 1",
            mapId: mapName.isEmpty ? nil : mapName, intrinsics: firstKnown,
            source: "OCCaM Lab InvisibleMap recording \(file.lastPathComponent), map_id '\(root.map_id)'")
        let summary = Summary(
            originalMapId: root.map_id, frameCount: frames.count,
            durationSeconds: (frames.last?.t ?? 0) - (frames.first?.t ?? 0), pathLengthMeters: path,
            sightingCount: observations.count, distinctTagCount: Set(observations.compactMap(\.landmarkId)).count,
            skippedSightings: skipped, droppedDuplicatePoses: dropped, poseMatrixOrder: rowMajor ? "rowMajor" : "columnMajor")
        return Converted(info: info, frames: frames, observations: observations, summary: summary)
    }

    /// Horizontal range (meters) and bearing (radians, CCW from camera forward, in [-pi, pi]) of a point
    /// given in the computer-vision camera frame (x right, y down, z forward, meters), seen from `camera`.
    /// Nil when the point is behind the camera or horizontally at the camera (no bearing).
    public static func rangeBearing(tagTranslationCV p: (Double, Double, Double), camera: CameraPose)
        -> (rangeMeters: Double, bearingRad: Double)?
    {
        guard p.2 > 0 else { return nil }
        let c = (p.0, -p.1, -p.2)  // ARKit camera frame: x right, y up, looks along -z
        let m = camera.columnMajor
        let dx = m[0] * c.0 + m[4] * c.1 + m[8] * c.2
        let dz = m[2] * c.0 + m[6] * c.1 + m[10] * c.2
        let range = (dx * dx + dz * dz).squareRoot()
        guard range > 1e-6 else { return nil }
        // VIO plane (east, north) = (x_w, -z_w).
        var bearing = atan2(-dz, dx) - camera.yawInVIOPlaneRad
        bearing = atan2(sin(bearing), cos(bearing))
        return (range, bearing)
    }
}

// MARK: OCCaM file layout (only the fields used)

private struct OccamFile: Decodable {
    var map_id: String
    var pose_data: [OccamPose]
    var tag_data: [[OccamDetection]]

    enum CodingKeys: String, CodingKey { case map_id, pose_data, tag_data }

    init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        map_id = try c.decodeIfPresent(String.self, forKey: .map_id) ?? ""
        pose_data = try c.decode([OccamPose].self, forKey: .pose_data)
        // Groups of detections; a flat list is accepted too.
        if let groups = try? c.decodeIfPresent([[OccamDetection]].self, forKey: .tag_data) {
            tag_data = groups
        } else if let flat = try c.decodeIfPresent([OccamDetection].self, forKey: .tag_data) {
            tag_data = flat.map { [$0] }
        } else {
            tag_data = []
        }
    }
}

private struct OccamPose: Decodable {
    var id: Int
    var timestamp: Double
    var pose: [Double]
}

private struct OccamDetection: Decodable {
    var tag_id: Int
    var pose_id: Int
    var timestamp: Double
    var tag_pose: [Double]
    var camera_intrinsics: [Double]?
    var tag_corners_pixel_coordinates: [Double]?
}
