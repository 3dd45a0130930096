import Foundation
import SessionFormat

/// A surveyed spot of a recorded walk: at time `t` the walker stood at a known map position (a place they
/// picked from the map's list when the phone was there). Written to the bundle's marks.jsonl.
public struct SurveyMark: Sendable, Equatable, Codable {
    /// Time, seconds (the frames' clock).
    public var t: Double
    /// Point-of-interest id of the spot.
    public var placeId: String
    /// Floor id of the spot.
    public var floorId: String
    /// Map x of the spot (east), meters.
    public var x: Double
    /// Map y of the spot (north), meters.
    public var y: Double

    /// Creates a mark.
    public init(t: Double, placeId: String, floorId: String, x: Double, y: Double) {
        self.t = t; self.placeId = placeId; self.floorId = floorId; self.x = x; self.y = y
    }
}

/// Ground truth for a phone recording, so `wayfinder eval` can score a real walk: the walker marks at least
/// two surveyed spots; the VIO track (the frames' camera positions on the VIO floor plane) is mapped onto the
/// map by a 2-D similarity (rotation, scale, translation) that puts the VIO position at each mark exactly on
/// its spot, piecewise between consecutive marks (so VIO drift is corrected at every mark), with one
/// least-squares similarity over all marks (Umeyama's method in 2-D) before the first mark, after the last,
/// and across marks less than `minimumSegmentMeters` apart in VIO. Headings are the VIO yaw plus the
/// segment's rotation. One floor only. Accuracy: exact at the marks, VIO drift between them (about 1 % of
/// the distance walked for ARKit).
public enum SurveyedTruth {
    /// VIO displacement below which two consecutive marks do not define a segment of their own, meters.
    public static let minimumSegmentMeters = 1.0

    /// Problems that make truth impossible, each naming what to change.
    public enum Failure: Error, Equatable, CustomStringConvertible {
        /// Fewer than two marks, or all at one spot.
        case tooFewMarks(Int)
        /// Marks on more than one floor.
        case severalFloors([String])
        /// A mark outside the frames' time span or at a frame without a pose.
        case markWithoutPose(placeId: String, t: Double)

        /// Message for people.
        public var description: String {
            switch self {
            case .tooFewMarks(let n):
                return "surveyed truth needs at least two marks at spots at least \(minimumSegmentMeters) m apart; the walk has \(n)"
            case .severalFloors(let f): return "surveyed truth works on one floor; the marks are on floors \(f.joined(separator: ", "))"
            case .markWithoutPose(let id, let t): return "mark '\(id)' at t=\(t) s has no camera pose at or near its time"
            }
        }
    }

    /// A 2-D similarity: p' = s R(theta) p + (tx, ty).
    struct Similarity: Equatable {
        var scale: Double, thetaRad: Double, tx: Double, ty: Double
        func apply(_ e: Double, _ n: Double) -> (x: Double, y: Double) {
            let c = cos(thetaRad) * scale, s = sin(thetaRad) * scale
            return (c * e - s * n + tx, s * e + c * n + ty)
        }
        /// Least squares over pairs (Umeyama 1991, 2-D), nil when the sources have no spread.
        static func fit(_ from: [(Double, Double)], _ to: [(Double, Double)]) -> Similarity? {
            let n = Double(from.count)
            guard from.count == to.count, from.count >= 2 else { return nil }
            let mf = (from.map(\.0).reduce(0, +) / n, from.map(\.1).reduce(0, +) / n)
            let mt = (to.map(\.0).reduce(0, +) / n, to.map(\.1).reduce(0, +) / n)
            var dot = 0.0, cross = 0.0, varF = 0.0
            for (a, b) in zip(from, to) {
                let ax = a.0 - mf.0, ay = a.1 - mf.1, bx = b.0 - mt.0, by = b.1 - mt.1
                dot += ax * bx + ay * by
                cross += ax * by - ay * bx
                varF += ax * ax + ay * ay
            }
            guard varF > 1e-9 else { return nil }
            let theta = atan2(cross, dot)
            let scale = (dot * cos(theta) + cross * sin(theta)) / varF
            let c = cos(theta) * scale, s = sin(theta) * scale
            return Similarity(scale: scale, thetaRad: theta, tx: mt.0 - (c * mf.0 - s * mf.1), ty: mt.1 - (s * mf.0 + c * mf.1))
        }
    }

    /// One frame's camera on the VIO floor plane.
    public struct TrackPoint: Sendable, Equatable {
        /// Time, seconds.
        public var t: Double
        /// VIO east, meters.
        public var east: Double
        /// VIO north, meters.
        public var north: Double
        /// Camera yaw on the VIO plane, radians CCW from VIO east.
        public var yawRad: Double

        /// The track point of a frame; nil when its pose is not finite.
        public init?(_ f: FrameRecord) {
            guard let pose = CameraPose(columnMajor: f.cameraToWorld) else { return nil }
            let p = pose.positionInVIOPlane
            t = f.t; east = p.east; north = p.north; yawRad = pose.yawInVIOPlaneRad
        }
    }

    /// Truth for every frame with a pose, in time order.
    public static func truth(frames: [FrameRecord], marks: [SurveyMark]) throws -> [TruthRecord] {
        try truth(track: frames.compactMap(TrackPoint.init), marks: marks)
    }

    /// Truth for every point of a VIO track, in time order.
    public static func truth(track: [TrackPoint], marks unsorted: [SurveyMark]) throws -> [TruthRecord] {
        let marks = unsorted.sorted { $0.t < $1.t }
        let floors = Array(Set(marks.map(\.floorId))).sorted()
        guard floors.count <= 1 else { throw Failure.severalFloors(floors) }
        let posed = track.map { (t: $0.t, e: $0.east, n: $0.north, yaw: $0.yawRad) }
        // Each mark's VIO position: the posed frame nearest its time, within 0.5 s.
        var vio: [(Double, Double)] = []
        for m in marks {
            guard let nearest = posed.min(by: { abs($0.t - m.t) < abs($1.t - m.t) }), abs(nearest.t - m.t) <= 0.5 else {
                throw Failure.markWithoutPose(placeId: m.placeId, t: m.t)
            }
            vio.append((nearest.e, nearest.n))
        }
        guard let floorId = floors.first,
              let global = Similarity.fit(vio, marks.map { ($0.x, $0.y) }) else { throw Failure.tooFewMarks(marks.count) }
        // Piecewise exact similarities between consecutive marks far enough apart in VIO.
        var segments: [(t0: Double, t1: Double, s: Similarity)] = []
        for i in 0..<(marks.count - 1) {
            let a = vio[i], b = vio[i + 1]
            guard hypot(b.0 - a.0, b.1 - a.1) >= minimumSegmentMeters,
                  let s = Similarity.fit([a, b], [(marks[i].x, marks[i].y), (marks[i + 1].x, marks[i + 1].y)]) else { continue }
            segments.append((marks[i].t, marks[i + 1].t, s))
        }
        return posed.map { f in
            let s = segments.first { f.t >= $0.t0 && f.t <= $0.t1 }?.s ?? global
            let p = s.apply(f.e, f.n)
            let h = f.yaw + s.thetaRad
            return TruthRecord(t: f.t, x: p.x, y: p.y, floorId: floorId, headingRad: atan2(sin(h), cos(h)))
        }
    }
}
