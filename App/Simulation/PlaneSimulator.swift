import Foundation
import Maps
import SessionFormat

/// ARKit vertical plane detection (ARPlaneAnchor, alignment vertical). Meters, seconds, degrees.
public struct PlaneParameters: Codable, Sendable, Equatable {
    /// Simulate planes at all (planes.jsonl is written only when some were produced).
    public var enabled = true
    /// How often plane detection is evaluated, Hz (ARKit refines anchors a few times a second).
    public var evaluationRateHz = 10.0
    /// A wall is seen by plane detection up to this horizontal distance from the camera, m.
    public var maxRangeMeters = 5.0
    /// Horizontal field of view in which walls are observed, degrees (the camera's, a little wider: ARKit keeps
    /// refining what it saw a moment ago).
    public var horizontalFieldOfViewDeg = 60.0
    /// Walls seen more obliquely than this from their normal give no plane, degrees.
    public var maxViewAngleFromNormalDeg = 80.0
    /// Probability that a wall face is textureless (blank paint, glass) and never detected.
    public var texturelessWallProbability = 0.3
    /// Observation time before an anchor appears, s (drawn uniformly per wall).
    public var lagSecondsRange: ClosedRange<Double> = 0.5...2.0
    /// Width of a plane when it first appears, m (drawn uniformly).
    public var initialWidthRangeMeters: ClosedRange<Double> = 0.3...0.8
    /// Speed at which an anchor's extent grows toward the part of the wall seen so far, m per second of
    /// observation.
    public var extentGrowthMetersPerSecond = 1.0
    /// An anchor is re-reported (didUpdate) at most this often while observed, s.
    public var updateIntervalSeconds = 0.5
    /// Standard deviation of the plane's offset along its normal, m (Ornstein-Uhlenbeck: re-estimated over time).
    public var normalOffsetSigmaMeters = 0.04
    /// Standard deviation of the plane's orientation error, degrees (Ornstein-Uhlenbeck).
    public var angleSigmaDeg = 2.0
    /// Correlation time of the re-estimation errors, s.
    public var reestimationTauSeconds = 5.0
    /// False planes from furniture (cabinets, boards, partitions): mean number per meter walked (Poisson).
    public var furniturePlanesPerMeter = 0.04
    /// Width of a furniture plane, m.
    public var furnitureWidthRangeMeters: ClosedRange<Double> = 0.6...1.6
    /// Probability that a door of the map stands open (its leaf, perpendicular to the wall, is a false plane).
    public var openDoorProbability = 0.3
    /// Wall segments this close to collinear (degrees) and touching (within 5 cm) are one wall face.
    public var mergeAngleDeg = 3.0
    /// The defaults.
    public init() {}
}

/// Generates ARPlaneAnchor events for a simulated walk: which wall faces are in view of the camera, with a lag
/// before each anchor appears, extents that start small and grow with observation, textureless walls that are
/// never detected, false planes from furniture and open doors, and pose errors re-estimated over time
/// (Ornstein-Uhlenbeck). Poses are expressed in the walk's VIO / ARKit world frame through the same map-to-VIO
/// relation as the camera at that frame (p_vio = v_k + s R(theta_k) (p_map - c_k)), so anchors drift with VIO
/// like real ones; when tracking comes back after a loss or a relocalization every live anchor is re-reported
/// (didUpdate) in the possibly moved world frame, as ARKit does; a VIO reset removes every anchor; nothing is
/// reported while tracking is unavailable, relocalizing or initializing. Deterministic for a seed.
struct PlaneSimulator {
    /// Random stream of plane detection (`SeededRandom(seed:stream:)`), apart from `RandomStream`'s ids.
    static let randomStream: UInt64 = 20
    let parameters: PlaneParameters
    let floors: [String: Floor]
    let geometry: [String: FloorGeometry]
    /// Where the walls truly stand against the map (`SurveyParameters.wallOffsetSigmaMeters`): each wall face is
    /// shifted along its normal by a draw of this many meters, from `surveyRng` (the planes' own stream is left
    /// untouched, so walks without survey errors are those of before). 0: the map's walls are the truth.
    var wallOffsetSigmaMeters = 0.0
    /// The survey's random stream for the wall offsets (drawn per floor in id order, per face in order).
    var surveyRng = SeededRandom(seed: 0, stream: RandomStream.survey.rawValue)

    /// One wall face (collinear segments merged), map frame.
    struct Face {
        var a: Point2
        var b: Point2
        var length: Double
        var textured: Bool
        var lag: Double
        var isFalse: Bool
        var classification: String?
        /// The survey's error: the true wall stands this far along the face's left normal (-uy, ux) from the
        /// map's, m (0 for the map's own walls and for false planes).
        var surveyOffsetMeters = 0.0
    }

    /// Per-face detection state.
    private struct Track {
        var observed = 0.0
        var anchorId: String?
        var extent: ClosedRange<Double>?   // along the face, meters from a
        var seen: ClosedRange<Double>?
        var lastReport = -Double.infinity
        var normalError: OrnsteinUhlenbeck
        var angleError: OrnsteinUhlenbeck
        var lastStep: Double
    }

    /// Merges collinear touching segments of a floor into faces and draws which are textured.
    func faces(floorId: String, rng: inout SeededRandom) -> [Face] {
        guard let floor = floors[floorId] else { return [] }
        var segs = floor.walls.map { (a: $0.from, b: $0.to) }.filter { hypot($0.b.x - $0.a.x, $0.b.y - $0.a.y) > 1e-3 }
        let tol = radians(parameters.mergeAngleDeg)
        // Passes of pairwise merging until nothing merges; a bounding-box test rejects most pairs cheaply.
        var merged = true
        var passes = 0
        while merged && passes < 8 {
            merged = false
            passes += 1
            var i = 0
            while i < segs.count {
                var j = i + 1
                while j < segs.count {
                    let (s, t) = (segs[i], segs[j])
                    if min(t.a.x, t.b.x) > max(s.a.x, s.b.x) + 0.05 || max(t.a.x, t.b.x) < min(s.a.x, s.b.x) - 0.05
                        || min(t.a.y, t.b.y) > max(s.a.y, s.b.y) + 0.05 || max(t.a.y, t.b.y) < min(s.a.y, s.b.y) - 0.05 {
                        j += 1
                        continue
                    }
                    if let m = Self.merge(s, t, angleTolerance: tol) {
                        segs[i] = m; segs.remove(at: j); merged = true
                    } else {
                        j += 1
                    }
                }
                i += 1
            }
        }
        var out: [Face] = []
        for s in segs {
            let len = hypot(s.b.x - s.a.x, s.b.y - s.a.y)
            let textured = !rng.bernoulli(parameters.texturelessWallProbability)
            let lag = rng.uniform(parameters.lagSecondsRange.lowerBound, parameters.lagSecondsRange.upperBound)
            out.append(Face(a: s.a, b: s.b, length: len, textured: textured, lag: lag, isFalse: false, classification: nil))
        }
        // Open doors: the leaf stands perpendicular to the nearest wall, hinged at one side of the opening.
        for d in floor.doors {
            let open = rng.bernoulli(parameters.openDoorProbability)
            let side = rng.sign()
            let swing = rng.sign()
            guard open, let wallDir = nearestWallDirection(floorId: floorId, at: d.position) else { continue }
            let (ux, uy) = (cos(wallDir), sin(wallDir))
            let (nx, ny) = (-uy * swing, ux * swing)
            let hinge = Point2(x: d.position.x + side * 0.5 * d.widthMeters * ux, y: d.position.y + side * 0.5 * d.widthMeters * uy)
            let tip = Point2(x: hinge.x + d.widthMeters * nx, y: hinge.y + d.widthMeters * ny)
            let lag = rng.uniform(parameters.lagSecondsRange.lowerBound, parameters.lagSecondsRange.upperBound)
            out.append(Face(a: hinge, b: tip, length: d.widthMeters, textured: true, lag: lag, isFalse: true, classification: nil))
        }
        return out
    }

    private func nearestWallDirection(floorId: String, at p: Point2) -> Double? {
        guard let floor = floors[floorId] else { return nil }
        var best = 2.0, dir: Double?
        for w in floor.walls {
            let d = FloorGeometry.distance(p, w.from, w.to)
            if d < best { best = d; dir = atan2(w.to.y - w.from.y, w.to.x - w.from.x) }
        }
        return dir
    }

    /// The union of two collinear segments that touch or overlap, else nil.
    static func merge(_ s: (a: Point2, b: Point2), _ t: (a: Point2, b: Point2), angleTolerance: Double) -> (a: Point2, b: Point2)? {
        let d1 = atan2(s.b.y - s.a.y, s.b.x - s.a.x), d2 = atan2(t.b.y - t.a.y, t.b.x - t.a.x)
        let diff = abs(wrapAngle(2 * (d1 - d2))) / 2
        guard diff <= angleTolerance else { return nil }
        let len = hypot(s.b.x - s.a.x, s.b.y - s.a.y)
        let (ux, uy) = ((s.b.x - s.a.x) / len, (s.b.y - s.a.y) / len)
        // t's ends must lie on s's line (within 5 cm) and its span must touch s's span.
        func off(_ p: Point2) -> Double { abs(-(p.x - s.a.x) * uy + (p.y - s.a.y) * ux) }
        func along(_ p: Point2) -> Double { (p.x - s.a.x) * ux + (p.y - s.a.y) * uy }
        guard off(t.a) < 0.05, off(t.b) < 0.05 else { return nil }
        let ta = along(t.a), tb = along(t.b)
        guard min(ta, tb) <= len + 0.05, max(ta, tb) >= -0.05 else { return nil }
        let lo = min(0, ta, tb), hi = max(len, ta, tb)
        return (Point2(x: s.a.x + lo * ux, y: s.a.y + lo * uy), Point2(x: s.a.x + hi * ux, y: s.a.y + hi * uy))
    }

    /// Runs plane detection over the walk. `states`, `vio` and `mapToVIOYaw` are per frame; `scale` the VIO
    /// scale; `resetTime` the time of a full VIO reset, if any.
    func run(states: [TrueCameraState], vio: [VIOFrame], mapToVIOYaw: [Double], scale: Double, resetTime: Double?,
             rng: inout SeededRandom) -> [PlaneRecord] {
        guard parameters.enabled, states.count >= 2, parameters.evaluationRateHz > 0 else { return [] }
        let p = parameters
        var facesByFloor: [String: [Face]] = [:]
        var surveyRng = self.surveyRng
        for id in floors.keys.sorted() {
            var fl = faces(floorId: id, rng: &rng)
            if wallOffsetSigmaMeters > 0 {
                for i in fl.indices where !fl[i].isFalse { fl[i].surveyOffsetMeters = wallOffsetSigmaMeters * surveyRng.normal() }
            }
            facesByFloor[id] = fl
        }
        var tracks: [String: [Track]] = [:]
        func newTrack(_ t: Double) -> Track {
            Track(normalError: OrnsteinUhlenbeck(sigma: p.normalOffsetSigmaMeters, tauSeconds: p.reestimationTauSeconds, rng: &rng),
                  angleError: OrnsteinUhlenbeck(sigma: radians(p.angleSigmaDeg), tauSeconds: p.reestimationTauSeconds, rng: &rng),
                  lastStep: t)
        }
        let dtFrame = states[1].t - states[0].t
        let stride = max(1, Int((1 / (p.evaluationRateHz * max(dtFrame, 1e-6))).rounded()))
        let halfFov = radians(p.horizontalFieldOfViewDeg) / 2
        let maxView = radians(p.maxViewAngleFromNormalDeg)
        var out: [PlaneRecord] = []
        var anchorCount = 0
        var walkedSinceFurniture = 0.0
        var nextFurnitureAt = rng.exponential(ratePerSecond: p.furniturePlanesPerMeter)
        var didReset = false
        var wasInReset = true
        var lastK = 0
        for k in Swift.stride(from: 0, to: states.count, by: stride) {
            let s = states[k]
            let t = s.t
            // Walked distance since the last evaluation (for the furniture Poisson process).
            if k > 0 { walkedSinceFurniture += hypot(s.position.x - states[lastK].position.x, s.position.y - states[lastK].position.y) }
            lastK = k
            if let r = resetTime, !didReset, t >= r {
                // ARKit's resetTracking removes every anchor.
                didReset = true
                for fid in tracks.keys.sorted() {
                    for tr in tracks[fid]! { if let id = tr.anchorId { out.append(PlaneRecord(t: t, anchorId: id, event: .remove)) } }
                    tracks[fid] = tracks[fid]!.map { _ in newTrack(t) }
                }
            }
            let frame = vio[k]
            if isVIOResetState(frame.tracking, frame.reason) { wasInReset = true; continue }
            if wasInReset {
                // Tracking is back: ARKit re-places every surviving anchor in the (possibly moved) world frame.
                wasInReset = false
                for fid in tracks.keys.sorted() {
                    guard let list = tracks[fid], let fl = facesByFloor[fid] else { continue }
                    for (i, tr) in list.enumerated() {
                        guard let id = tr.anchorId, let e = tr.extent else { continue }
                        out.append(record(face: fl[i], extent: e, normalError: tr.normalError.value, angleError: tr.angleError.value,
                                          anchorId: id, event: .update, t: t, state: s, vio: frame, theta: mapToVIOYaw[k],
                                          scale: scale))
                        tracks[fid]![i].lastReport = t
                    }
                }
            }
            guard var faces = facesByFloor[s.floorId], let geo = geometry[s.floorId] else { continue }
            if tracks[s.floorId] == nil { tracks[s.floorId] = faces.map { _ in newTrack(t) } }
            // Furniture: a false plane appears ahead in open space.
            if walkedSinceFurniture >= nextFurnitureAt {
                walkedSinceFurniture = 0
                nextFurnitureAt = rng.exponential(ratePerSecond: p.furniturePlanesPerMeter)
                let dist = rng.uniform(1.5, 4.0), bearing = rng.uniform(-halfFov, halfFov)
                let c = Point2(x: s.position.x + dist * cos(s.yawRad + bearing), y: s.position.y + dist * sin(s.yawRad + bearing))
                let orient = rng.uniform(-Double.pi, Double.pi)
                let w = rng.uniform(p.furnitureWidthRangeMeters.lowerBound, p.furnitureWidthRangeMeters.upperBound)
                let a = Point2(x: c.x - 0.5 * w * cos(orient), y: c.y - 0.5 * w * sin(orient))
                let b = Point2(x: c.x + 0.5 * w * cos(orient), y: c.y + 0.5 * w * sin(orient))
                let cam = Point2(x: s.position.x, y: s.position.y)
                if geo.clearance(at: c, maxMeters: 0.5) >= 0.4, !geo.segmentCrossesWall(cam, c), !geo.segmentCrossesWall(a, b) {
                    let lag = rng.uniform(p.lagSecondsRange.lowerBound, p.lagSecondsRange.upperBound)
                    faces.append(Face(a: a, b: b, length: w, textured: true, lag: lag, isFalse: true, classification: nil))
                    facesByFloor[s.floorId] = faces
                    tracks[s.floorId]!.append(newTrack(t))
                }
            }
            let cam = Point2(x: s.position.x, y: s.position.y)
            let dt = Double(stride) * dtFrame
            for (i, f) in faces.enumerated() where f.textured {
                guard let seen = visibleInterval(f, from: cam, yaw: s.yawRad, halfFov: halfFov, maxView: maxView, geo: geo) else { continue }
                var tr = tracks[s.floorId]![i]
                tr.observed += dt
                tr.seen = tr.seen.map { min($0.lowerBound, seen.lowerBound)...max($0.upperBound, seen.upperBound) } ?? seen
                let elapsed = max(0, t - tr.lastStep)
                tr.lastStep = t
                _ = tr.normalError.step(dt: elapsed, rng: &rng)
                _ = tr.angleError.step(dt: elapsed, rng: &rng)
                guard tr.observed >= f.lag else { tracks[s.floorId]![i] = tr; continue }
                let seenAll = tr.seen!
                if let e = tr.extent {
                    let g = p.extentGrowthMetersPerSecond * dt
                    tr.extent = max(seenAll.lowerBound, e.lowerBound - g)...min(seenAll.upperBound, e.upperBound + g)
                } else {
                    let mid = 0.5 * (seen.lowerBound + seen.upperBound)
                    let w0 = min(f.length, rng.uniform(p.initialWidthRangeMeters.lowerBound, p.initialWidthRangeMeters.upperBound))
                    let lo = max(0, min(f.length - w0, mid - w0 / 2))
                    tr.extent = lo...(lo + w0)
                }
                let event: PlaneEvent
                if tr.anchorId == nil {
                    anchorCount += 1
                    tr.anchorId = String(format: "sim-plane-%05d", anchorCount)
                    event = .add
                } else if t - tr.lastReport >= p.updateIntervalSeconds - 1e-9 {
                    event = .update
                } else {
                    tracks[s.floorId]![i] = tr
                    continue
                }
                tr.lastReport = t
                out.append(record(face: f, extent: tr.extent!, normalError: tr.normalError.value, angleError: tr.angleError.value,
                                  anchorId: tr.anchorId!, event: event, t: t, state: s, vio: frame, theta: mapToVIOYaw[k],
                                  scale: scale))
                tracks[s.floorId]![i] = tr
            }
        }
        return out
    }

    /// The part of face `f` (meters along it from `a`) in view of a camera at `cam` looking along `yaw`: within
    /// range and field of view, not too oblique, with a clear line of sight. Nil when less than 0.2 m is seen.
    private func visibleInterval(_ f: Face, from cam: Point2, yaw: Double, halfFov: Double, maxView: Double,
                                 geo: FloorGeometry) -> ClosedRange<Double>? {
        let r = parameters.maxRangeMeters
        guard FloorGeometry.distance(cam, f.a, f.b) <= r else { return nil }
        let ux = (f.b.x - f.a.x) / f.length, uy = (f.b.y - f.a.y) / f.length
        // Points of the face within range: |a + u*l - cam| <= r.
        let wx = f.a.x - cam.x, wy = f.a.y - cam.y
        let bq = wx * ux + wy * uy, cq = wx * wx + wy * wy - r * r
        let disc = bq * bq - cq
        guard disc > 0 else { return nil }
        let l0 = max(0, -bq - disc.squareRoot()), l1 = min(f.length, -bq + disc.squareRoot())
        guard l1 - l0 > 0.2 else { return nil }
        let n = max(2, min(40, Int(((l1 - l0) / 0.25).rounded(.up)) + 1))
        var lo = Double.infinity, hi = -Double.infinity
        for q in 0..<n {
            let l = l0 + (l1 - l0) * Double(q) / Double(n - 1)
            let px = f.a.x + l * ux, py = f.a.y + l * uy
            let dx = px - cam.x, dy = py - cam.y
            let d = hypot(dx, dy)
            guard d > 0.3 else { continue }
            guard abs(wrapAngle(atan2(dy, dx) - yaw)) <= halfFov else { continue }
            // Angle between the line of sight and the face normal.
            let cosView = abs(-dx * uy + dy * ux) / d
            guard cosView >= cos(maxView) else { continue }
            // Line of sight, stopping 3 cm short of the face (the face itself is a wall).
            let end = Point2(x: px - 0.03 * dx / d, y: py - 0.03 * dy / d)
            guard !geo.segmentCrossesWall(cam, end) else { continue }
            lo = min(lo, l); hi = max(hi, l)
        }
        guard hi - lo >= 0.2 else { return nil }
        return lo...hi
    }

    /// The plane record of a face's current estimate, in the frame's VIO / ARKit world.
    private func record(face f: Face, extent: ClosedRange<Double>, normalError: Double, angleError: Double, anchorId: String,
                        event: PlaneEvent, t: Double, state s: TrueCameraState, vio: VIOFrame, theta: Double,
                        scale: Double) -> PlaneRecord {
        let ux = (f.b.x - f.a.x) / f.length, uy = (f.b.y - f.a.y) / f.length
        let mid = 0.5 * (extent.lowerBound + extent.upperBound)
        // Normal pointing toward the camera side, with the re-estimation errors.
        var nx = -uy, ny = ux
        let cx0 = f.a.x + mid * ux, cy0 = f.a.y + mid * uy
        if (s.position.x - cx0) * nx + (s.position.y - cy0) * ny < 0 { nx = -nx; ny = -ny }
        let cMap = (x: cx0 + normalError * nx - f.surveyOffsetMeters * uy, y: cy0 + normalError * ny + f.surveyOffsetMeters * ux)
        let normalMapYaw = atan2(ny, nx) + angleError
        // Map -> VIO at this frame: p_vio = v + s R(theta) (p - c).
        let m = vio.cameraToWorld
        let vEast = m[12], vNorth = -m[14], camUp = m[13]
        let dx = cMap.x - s.position.x, dy = cMap.y - s.position.y
        let east = vEast + scale * (cos(theta) * dx - sin(theta) * dy)
        let north = vNorth + scale * (sin(theta) * dx + cos(theta) * dy)
        let yawVIO = normalMapYaw + theta
        // Plane center 1.2 m above the floor (camera world height minus its height above the floor).
        let up = camUp - scale * s.heightAboveFloorMeters + 1.2
        let width = scale * (extent.upperBound - extent.lowerBound)
        return PlaneRecord(t: t, anchorId: anchorId, event: event, alignment: .vertical,
                           centerInWorld: [east, up, -north], normalInWorld: [cos(yawVIO), 0, -sin(yawVIO)],
                           widthMeters: width, heightMeters: f.isFalse ? 1.0 : 2.4, classification: f.classification)
    }
}
