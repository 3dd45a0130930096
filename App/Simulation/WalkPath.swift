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

    /// One rounded corner: the path leaves the route `d` meters before vertex `vertex` (arc length) and
    /// rejoins it `d` meters after, along the cubic Bezier curve `curve` (dense points, first `a`, last `b`).
    struct Corner { var vertex: Int; var d: Double; var curve: [Point2] }

    /// A leg through the waypoints with rounded corners, densely sampled.
    ///
    /// Corners (direction changes of 10 to 150 degrees) are cut as people do: the walker leaves the route a
    /// drawn distance `d` (`cornerCutRangeMeters`) before the corner and rejoins it `d` after, on a cubic
    /// Bezier curve tangent to the route at both ends whose handles shrink with a drawn straightness
    /// (`cornerCutStraightnessRange`: 0 = the round curve through the corner's control point, 1 = the
    /// straight diagonal). `d` is measured along the route polyline, so graph nodes along a straight
    /// corridor do not limit the cut; it is at most 0.45 of the way to the neighbouring corners and the leg
    /// ends, and is scaled down so that the curve passes at most `cornerCutMaxCorridorWidths` corridor
    /// widths (twice the corner's wall clearance) from the corner. With probability
    /// `cornerWidenProbability` a corner is swung wide instead (the round curve with its control point moved
    /// outwards by `cornerWidenRangeMeters`). Every curve is checked against the map's walls (no crossing,
    /// the wall clearance kept); `d` is halved up to five times until it passes, else the corner stays sharp.
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
        var arc = [0.0]
        for i in 1..<p.count { arc.append(arc[i - 1] + hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y)) }
        func point(atArc s: Double) -> Point2 {
            var i = 0
            while i < p.count - 2 && arc[i + 1] < s { i += 1 }
            let l = arc[i + 1] - arc[i]
            let f = l > 0 ? max(0, min(1, (s - arc[i]) / l)) : 0
            return Point2(p[i].x + f * (p[i + 1].x - p[i].x), p[i].y + f * (p[i + 1].y - p[i].y))
        }
        // Turn at each interior vertex (0 where undefined).
        var turnAt = [Double](repeating: 0, count: p.count)
        for i in 1..<max(1, p.count - 1) {
            let lin = arc[i] - arc[i - 1], lout = arc[i + 1] - arc[i]
            guard lin > 1e-6, lout > 1e-6 else { continue }
            turnAt[i] = abs(wrapAngle(atan2(p[i + 1].y - p[i].y, p[i + 1].x - p[i].x) - atan2(p[i].y - p[i - 1].y, p[i].x - p[i - 1].x)))
        }
        let cornerIndices = (0..<p.count).filter { turnAt[$0] > radians(10) && turnAt[$0] < radians(150) }
        var corners: [Corner] = []
        for i in 1..<max(1, p.count - 1) {
            // Draw even when unused so the stream does not depend on geometry tests.
            let dDraw = rng.uniform(parameters.cornerCutRangeMeters.lowerBound, parameters.cornerCutRangeMeters.upperBound)
            let widen = rng.bernoulli(parameters.cornerWidenProbability)
            let wDraw = rng.uniform(parameters.cornerWidenRangeMeters.lowerBound, parameters.cornerWidenRangeMeters.upperBound)
            let straightness = rng.uniform(parameters.cornerCutStraightnessRange.lowerBound, parameters.cornerCutStraightnessRange.upperBound)
            guard turnAt[i] > radians(10), turnAt[i] < radians(150) else { continue }
            // Room along the route: 0.45 of the way to the neighbouring corners and to the leg's ends.
            let k = cornerIndices.firstIndex(of: i)!
            let prevArc = k > 0 ? arc[cornerIndices[k - 1]] : arc[0]
            let nextArc = k + 1 < cornerIndices.count ? arc[cornerIndices[k + 1]] : arc[p.count - 1]
            let room = 0.45 * min(arc[i] - prevArc, nextArc - arc[i])
            var d = min(dDraw, room)
            let w = widen ? wDraw : 0
            let handle = widen ? 2.0 / 3.0 : (2.0 / 3.0) * (1 - max(0, min(1, straightness)))
            // Corridor width at the corner: twice the distance from the corner to the nearest wall.
            let widthMeters = 2 * geo.clearance(at: p[i], maxMeters: 10)
            let maxApex = parameters.cornerCutMaxCorridorWidths * widthMeters
            for attempt in 0..<6 {
                guard d > 0.05 else { break }
                var curve = cornerCurve(vertex: p[i], a: point(atArc: arc[i] - d), b: point(atArc: arc[i] + d),
                                        widen: w, handle: handle)
                if attempt == 0 && !widen {
                    // The curve's farthest point from the corner scales with d: scale d to the corridor.
                    let apex = curve.map { hypot($0.x - p[i].x, $0.y - p[i].y) }.max() ?? 0
                    if apex > maxApex && apex > 0 {
                        d *= maxApex / apex
                        guard d > 0.05 else { break }
                        curve = cornerCurve(vertex: p[i], a: point(atArc: arc[i] - d), b: point(atArc: arc[i] + d),
                                            widen: w, handle: handle)
                    }
                }
                if cornerIsClear(curve, vertex: p[i], geometry: geo) {
                    corners.append(Corner(vertex: i, d: d, curve: curve))
                    break
                }
                d *= 0.5
            }
        }
        // Dense sampling: the route's polyline, with each corner's stretch [arc - d, arc + d] replaced by its curve.
        var out: [Point2] = [p[0]]
        func addLine(to q: Point2) {
            let last = out[out.count - 1]
            let l = hypot(q.x - last.x, q.y - last.y)
            guard l > 1e-9 else { return }
            let n = max(1, Int((l / 0.05).rounded(.up)))
            for k in 1...n { let f = Double(k) / Double(n); out.append(Point2(last.x + f * (q.x - last.x), last.y + f * (q.y - last.y))) }
        }
        var v = 1
        for c in corners {
            let leave = arc[c.vertex] - c.d, rejoin = arc[c.vertex] + c.d
            while v < p.count && arc[v] < leave { addLine(to: p[v]); v += 1 }
            addLine(to: c.curve[0])
            for q in c.curve.dropFirst() { out.append(q) }
            while v < p.count && arc[v] <= rejoin { v += 1 }
        }
        while v < p.count { addLine(to: p[v]); v += 1 }
        return PathLeg(floorId: floorId, points: out)
    }

    /// The cubic Bezier from `a` to `b` around `vertex`: control point C = vertex moved outwards (away from
    /// the inside of the turn) by `widen` meters; handles a + h (C - a) and b + h (C - b). h = 2/3 is the
    /// quadratic curve through C; h = 0 the straight line from `a` to `b`. 16 segments.
    private func cornerCurve(vertex: Point2, a: Point2, b: Point2, widen: Double, handle h: Double) -> [Point2] {
        let lin = hypot(vertex.x - a.x, vertex.y - a.y), lout = hypot(b.x - vertex.x, b.y - vertex.y)
        var control = vertex
        if widen > 0, lin > 1e-9, lout > 1e-9 {
            let uin = Point2((vertex.x - a.x) / lin, (vertex.y - a.y) / lin), uout = Point2((b.x - vertex.x) / lout, (b.y - vertex.y) / lout)
            var ox = uin.x - uout.x, oy = uin.y - uout.y
            let on = hypot(ox, oy)
            if on > 1e-9 { ox /= on; oy /= on; control = Point2(vertex.x + widen * ox, vertex.y + widen * oy) }
        }
        let c1 = Point2(a.x + h * (control.x - a.x), a.y + h * (control.y - a.y))
        let c2 = Point2(b.x + h * (control.x - b.x), b.y + h * (control.y - b.y))
        return (0...16).map { k in
            let t = Double(k) / 16, u = 1 - t
            let b0 = u * u * u, b1 = 3 * u * u * t, b2 = 3 * u * t * t, b3 = t * t * t
            return Point2(b0 * a.x + b1 * c1.x + b2 * c2.x + b3 * b.x, b0 * a.y + b1 * c1.y + b2 * c2.y + b3 * b.y)
        }
    }

    /// A cut corner is acceptable when it crosses no wall and keeps the wall clearance (or at least the
    /// clearance of the sharp corner it replaces, where that is smaller).
    private func cornerIsClear(_ pts: [Point2], vertex: Point2, geometry geo: FloorGeometry) -> Bool {
        guard let a = pts.first, let b = pts.last else { return false }
        let minOriginal = min(geo.clearance(at: a), geo.clearance(at: vertex), geo.clearance(at: b))
        let needed = min(parameters.wallClearanceMeters, minOriginal - 1e-6)
        for k in 0..<pts.count {
            if geo.clearance(at: pts[k]) < needed { return false }
            if k > 0 && geo.segmentCrossesWall(pts[k - 1], pts[k]) { return false }
        }
        return true
    }
}

func fmt(_ p: Point2) -> String { String(format: "%.2f, %.2f", p.x, p.y) }
