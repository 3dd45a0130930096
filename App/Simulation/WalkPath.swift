import Foundation
import Maps

/// A stretch walked without stopping on one floor: a dense polyline (about 5 cm between points) with its
/// cumulative arc length. Corners are already rounded (cut or widened); legs end where the walker stops and
/// turns around (a wrong turn's end), at vertical links and at the destination.
struct PathLeg: Sendable {
    /// Floor walked.
    var floorId: String
    /// Dense polyline, meters.
    var points: [Point2]
    /// Arc length at each point, meters (starts at 0).
    var cumulative: [Double]
    /// Total length, meters.
    var length: Double { cumulative.last ?? 0 }

    init(floorId: String, points: [Point2]) {
        self.floorId = floorId
        self.points = points
        var c = [0.0]
        for i in 1..<max(1, points.count) { c.append(c[i - 1] + hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y)) }
        cumulative = c
    }

    /// Segment index containing arc length `s` (searching forward from `hint`).
    func segment(at s: Double, hint: inout Int) -> Int {
        guard points.count > 1 else { return 0 }
        var i = min(max(0, hint), points.count - 2)
        while i > 0 && cumulative[i] > s { i -= 1 }
        while i < points.count - 2 && cumulative[i + 1] < s { i += 1 }
        hint = i
        return i
    }

    /// Position at arc length `s` (clamped to the leg).
    func position(at s: Double, hint: inout Int) -> Point2 {
        guard points.count > 1 else { return points[0] }
        let i = segment(at: s, hint: &hint)
        let l = cumulative[i + 1] - cumulative[i]
        let f = l > 0 ? max(0, min(1, (s - cumulative[i]) / l)) : 0
        return Point2(points[i].x + f * (points[i + 1].x - points[i].x), points[i].y + f * (points[i + 1].y - points[i].y))
    }

    /// Direction of travel at arc length `s`, radians CCW from +x.
    func tangent(at s: Double, hint: inout Int) -> Double {
        guard points.count > 1 else { return 0 }
        var i = segment(at: s, hint: &hint)
        // Skip degenerate segments.
        while i < points.count - 2 && cumulative[i + 1] - cumulative[i] < 1e-9 { i += 1 }
        return atan2(points[i + 1].y - points[i].y, points[i + 1].x - points[i].x)
    }
}

/// One piece of the planned walk.
enum WalkSegment: Sendable {
    /// Walk a leg.
    case leg(PathLeg)
    /// Change floors at a vertical link (elevator or stairs).
    case vertical(fromFloor: String, toFloor: String, fromPosition: Point2, toPosition: Point2,
                  fromElevation: Double, toElevation: Double, kind: VerticalLinkKind)
}

/// Turns a route (graph node sequence, optionally with a wrong-turn detour) into walk segments: splits it
/// at floor changes and turn-arounds, and rounds its corners within the walkable area.
struct WalkPathBuilder {
    let building: Building
    let geometry: [String: FloorGeometry]
    let parameters: WalkerParameters

    /// A waypoint: floor, position, and whether the walker stops and turns around there.
    struct Waypoint { var floorId: String; var position: Point2; var cusp: Bool; var nodeIndex: Int? }

    /// Builds the segments; throws when a straight piece of the route itself crosses a wall.
    func build(waypoints: [Waypoint], rng: inout SeededRandom) throws -> [WalkSegment] {
        var segments: [WalkSegment] = []
        var current: [Waypoint] = []
        let elevation = Dictionary(building.floors.map { ($0.id, $0.elevationMeters) }, uniquingKeysWith: { a, _ in a })
        func flush() throws {
            if current.count >= 2 { segments.append(.leg(try makeLeg(current, rng: &rng))) }
            current = current.last.map { [$0] } ?? []
        }
        for (k, w) in waypoints.enumerated() {
            if let last = current.last, last.floorId != w.floorId {
                try flush()
                let kind: VerticalLinkKind = (w.nodeIndex.map { building.graph.nodes[$0].verticalLink } ?? nil) ?? .elevator
                segments.append(.vertical(fromFloor: last.floorId, toFloor: w.floorId, fromPosition: last.position,
                                          toPosition: w.position, fromElevation: elevation[last.floorId] ?? 0,
                                          toElevation: elevation[w.floorId] ?? 0, kind: kind))
                current = [w]
                continue
            }
            // Skip duplicate consecutive points.
            if let last = current.last, hypot(last.position.x - w.position.x, last.position.y - w.position.y) < 1e-6 {
                if w.cusp { current[current.count - 1].cusp = true }
                continue
            }
            current.append(w)
            if w.cusp && k != waypoints.count - 1 { try flush() }
        }
        if current.count >= 2 { segments.append(.leg(try makeLeg(current, rng: &rng))) }
        return segments
    }

    /// A leg through the waypoints with rounded corners, densely sampled.
    private func makeLeg(_ wps: [Waypoint], rng: inout SeededRandom) throws -> PathLeg {
        let floorId = wps[0].floorId
        let geo = geometry[floorId] ?? FloorGeometry(walls: [])
        let p = wps.map(\.position)
        // The map validator's rule for graph edges (Floor.firstWallCrossed), applied to the route's straight
        // pieces (graph edges or parts of them): a map that validates never fails here; a building made in
        // code without validation is refused rather than walked through a wall.
        if let floor = building.floors.first(where: { $0.id == floorId }) {
            for i in 0..<(p.count - 1) {
                guard let wi = floor.firstWallCrossed(from: p[i], to: p[i + 1]) else { continue }
                throw SimulationError.routeCrossesWall(
                    "floor \(floorId): from (\(fmt(p[i]))) to (\(fmt(p[i + 1]))) crosses wall \(wi) (a graph edge through a wall; wayfinder validate-map rejects such a map)")
            }
        }
        // Corner replacements: for each interior vertex, (d, control point) or nil for a sharp corner.
        var corners = [(d: Double, control: Point2)?](repeating: nil, count: p.count)
        for i in 1..<(p.count - 1) {
            let lin = hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y), lout = hypot(p[i + 1].x - p[i].x, p[i + 1].y - p[i].y)
            guard lin > 1e-6, lout > 1e-6 else { continue }
            let uin = Point2((p[i].x - p[i - 1].x) / lin, (p[i].y - p[i - 1].y) / lin)
            let uout = Point2((p[i + 1].x - p[i].x) / lout, (p[i + 1].y - p[i].y) / lout)
            let turn = abs(wrapAngle(atan2(uout.y, uout.x) - atan2(uin.y, uin.x)))
            // Draw even when unused so the stream does not depend on geometry tests.
            let dDraw = rng.uniform(parameters.cornerCutRangeMeters.lowerBound, parameters.cornerCutRangeMeters.upperBound)
            let widen = rng.bernoulli(parameters.cornerWidenProbability)
            let wDraw = rng.uniform(parameters.cornerWidenRangeMeters.lowerBound, parameters.cornerWidenRangeMeters.upperBound)
            guard turn > radians(10), turn < radians(150) else { continue }
            var d = min(dDraw, 0.45 * min(lin, lout))
            // Outward direction: away from the inside of the turn.
            var ox = uin.x - uout.x, oy = uin.y - uout.y
            let on = hypot(ox, oy); ox /= on; oy /= on
            let w = widen ? wDraw : 0
            for _ in 0..<4 {
                let control = Point2(p[i].x + w * ox, p[i].y + w * oy)
                let a = Point2(p[i].x - d * uin.x, p[i].y - d * uin.y), b = Point2(p[i].x + d * uout.x, p[i].y + d * uout.y)
                if cornerIsClear(a: a, control: control, b: b, vertex: p[i], geometry: geo) {
                    corners[i] = (d, control)
                    break
                }
                d *= 0.5
            }
        }
        // Dense sampling.
        var out: [Point2] = [p[0]]
        func addLine(to q: Point2) {
            let last = out[out.count - 1]
            let l = hypot(q.x - last.x, q.y - last.y)
            let n = max(1, Int((l / 0.05).rounded(.up)))
            for k in 1...n { let f = Double(k) / Double(n); out.append(Point2(last.x + f * (q.x - last.x), last.y + f * (q.y - last.y))) }
        }
        for i in 1..<p.count {
            if i < p.count - 1, let c = corners[i] {
                let lin = hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y), lout = hypot(p[i + 1].x - p[i].x, p[i + 1].y - p[i].y)
                let a = Point2(p[i].x - c.d * (p[i].x - p[i - 1].x) / lin, p[i].y - c.d * (p[i].y - p[i - 1].y) / lin)
                let b = Point2(p[i].x + c.d * (p[i + 1].x - p[i].x) / lout, p[i].y + c.d * (p[i + 1].y - p[i].y) / lout)
                addLine(to: a)
                for q in bezier(a, c.control, b, samples: 12).dropFirst() { out.append(q) }
            } else {
                addLine(to: p[i])
            }
        }
        return PathLeg(floorId: floorId, points: out)
    }

    private func bezier(_ a: Point2, _ c: Point2, _ b: Point2, samples: Int) -> [Point2] {
        (0...samples).map { k in
            let t = Double(k) / Double(samples), u = 1 - t
            return Point2(u * u * a.x + 2 * u * t * c.x + t * t * b.x, u * u * a.y + 2 * u * t * c.y + t * t * b.y)
        }
    }

    /// A rounded corner is acceptable when it crosses no wall and keeps the wall clearance (or at least the
    /// clearance of the sharp corner it replaces, where that is smaller).
    private func cornerIsClear(a: Point2, control: Point2, b: Point2, vertex: Point2, geometry geo: FloorGeometry) -> Bool {
        let minOriginal = min(geo.clearance(at: a), geo.clearance(at: vertex), geo.clearance(at: b))
        let needed = min(parameters.wallClearanceMeters, minOriginal - 1e-6)
        let pts = bezier(a, control, b, samples: 12)
        for k in 0..<pts.count {
            if geo.clearance(at: pts[k]) < needed { return false }
            if k > 0 && geo.segmentCrossesWall(pts[k - 1], pts[k]) { return false }
        }
        return true
    }
}

func fmt(_ p: Point2) -> String { String(format: "%.2f, %.2f", p.x, p.y) }
