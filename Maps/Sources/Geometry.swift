// Plane geometry in a floor's map frame (meters, x east, y north), for the localizer, the navigator and
// map validation. Algorithms: point-segment distance by clamped projection; segment intersection by the
// orientation (cross-product sign) test with collinear-overlap handling (Cormen et al., "Introduction to
// Algorithms", 3rd ed., section 33.1).
import Foundation

/// An axis-aligned rectangle in the map frame, meters.
public struct Rect2: Hashable, Sendable, Codable {
    /// West edge, meters.
    public var minX: Double
    /// South edge, meters.
    public var minY: Double
    /// East edge, meters.
    public var maxX: Double
    /// North edge, meters.
    public var maxY: Double
    /// Creates a rectangle from its edges (min <= max expected).
    public init(minX: Double, minY: Double, maxX: Double, maxY: Double) {
        self.minX = minX; self.minY = minY; self.maxX = maxX; self.maxY = maxY
    }
    /// East-west extent, meters.
    public var width: Double { maxX - minX }
    /// North-south extent, meters.
    public var height: Double { maxY - minY }
    /// Centre point.
    public var center: Point2 { Point2((minX + maxX) / 2, (minY + maxY) / 2) }
    /// True when `p` lies inside or on the boundary.
    public func contains(_ p: Point2) -> Bool { p.x >= minX && p.x <= maxX && p.y >= minY && p.y <= maxY }
    /// The smallest rectangle containing `points`; nil for an empty sequence.
    public init?<S: Sequence>(enclosing points: S) where S.Element == Point2 {
        var it = points.makeIterator()
        guard let first = it.next() else { return nil }
        var r = Rect2(minX: first.x, minY: first.y, maxX: first.x, maxY: first.y)
        while let p = it.next() {
            r.minX = Swift.min(r.minX, p.x); r.maxX = Swift.max(r.maxX, p.x)
            r.minY = Swift.min(r.minY, p.y); r.maxY = Swift.max(r.maxY, p.y)
        }
        self = r
    }
}

extension Point2 {
    /// Euclidean distance to `other`, meters.
    public func distance(to other: Point2) -> Double {
        ((other.x - x) * (other.x - x) + (other.y - y) * (other.y - y)).squareRoot()
    }
    /// Length of this point taken as a vector from the origin (for a direction such as a sign's facing).
    public var vectorLength: Double { (x * x + y * y).squareRoot() }
}

/// Free functions on points and segments in the map frame.
public enum Geometry {
    /// The point of segment `a`-`b` closest to `p` (the projection clamped to the segment; `a` when the
    /// segment has zero length).
    public static func closestPoint(to p: Point2, onSegmentFrom a: Point2, to b: Point2) -> Point2 {
        let dx = b.x - a.x, dy = b.y - a.y
        let len2 = dx * dx + dy * dy
        guard len2 > 0 else { return a }
        let t = Swift.max(0, Swift.min(1, ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2))
        return Point2(a.x + t * dx, a.y + t * dy)
    }

    /// Distance from `p` to the closest point of segment `a`-`b`, meters.
    public static func distance(from p: Point2, toSegmentFrom a: Point2, to b: Point2) -> Double {
        p.distance(to: closestPoint(to: p, onSegmentFrom: a, to: b))
    }

    /// Twice the signed area of triangle (a, b, c): positive when c is to the left of a->b.
    public static func cross(_ a: Point2, _ b: Point2, _ c: Point2) -> Double {
        (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
    }

    /// True when closed segments p1-p2 and q1-q2 share at least one point (crossing, touching at an end,
    /// or overlapping collinearly). Exact orientation test, no tolerance.
    public static func segmentsIntersect(_ p1: Point2, _ p2: Point2, _ q1: Point2, _ q2: Point2) -> Bool {
        let d1 = cross(q1, q2, p1), d2 = cross(q1, q2, p2), d3 = cross(p1, p2, q1), d4 = cross(p1, p2, q2)
        if ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)) { return true }
        func onSegment(_ a: Point2, _ b: Point2, _ c: Point2) -> Bool {
            Swift.min(a.x, b.x) <= c.x && c.x <= Swift.max(a.x, b.x) && Swift.min(a.y, b.y) <= c.y && c.y <= Swift.max(a.y, b.y)
        }
        if d1 == 0 && onSegment(q1, q2, p1) { return true }
        if d2 == 0 && onSegment(q1, q2, p2) { return true }
        if d3 == 0 && onSegment(p1, p2, q1) { return true }
        if d4 == 0 && onSegment(p1, p2, q2) { return true }
        return false
    }

    /// Where segment p1-p2 crosses segment q1-q2, as the fraction `t` in [0, 1] along p1-p2 and the
    /// point; nil when they do not meet or are parallel (collinear overlaps give nil: no single point).
    /// Used for ray casting (the first wall along a ray is the hit with the smallest `t`).
    public static func segmentIntersection(_ p1: Point2, _ p2: Point2, _ q1: Point2, _ q2: Point2) -> (t: Double, point: Point2)? {
        let rx = p2.x - p1.x, ry = p2.y - p1.y, sx = q2.x - q1.x, sy = q2.y - q1.y
        let denom = rx * sy - ry * sx
        guard denom != 0 else { return nil }
        let qpx = q1.x - p1.x, qpy = q1.y - p1.y
        let t = (qpx * sy - qpy * sx) / denom
        let u = (qpx * ry - qpy * rx) / denom
        guard t >= 0, t <= 1, u >= 0, u <= 1 else { return nil }
        return (t, Point2(p1.x + t * rx, p1.y + t * ry))
    }

    /// Distance from `p` along `directionRad` (radians CCW from +x) to the first of `segments` the ray meets,
    /// meters; `far` when none is nearer (a ray cast over `segmentIntersection`).
    public static func freeDistance<S: Sequence>(from p: Point2, directionRad: Double, far: Double, segments: S) -> Double
        where S.Element == (Point2, Point2) {
        let end = Point2(x: p.x + far * cos(directionRad), y: p.y + far * sin(directionRad))
        var best = far
        for (a, b) in segments {
            if let hit = segmentIntersection(p, end, a, b) { best = min(best, hit.t * far) }
        }
        return best
    }
}

extension Wall {
    /// Distance from `p` to this wall segment, meters.
    public func distance(to p: Point2) -> Double { Geometry.distance(from: p, toSegmentFrom: from, to: to) }
    /// The point of this wall closest to `p`.
    public func closestPoint(to p: Point2) -> Point2 { Geometry.closestPoint(to: p, onSegmentFrom: from, to: to) }
    /// True when the segment `a`-`b` touches or crosses this wall.
    public func intersects(from a: Point2, to b: Point2) -> Bool { Geometry.segmentsIntersect(a, b, from, to) }
}

extension Floor {
    /// Bounding box of the walls, doors, signs and points of interest of this floor, meters; a zero-size
    /// rectangle at the origin for an empty floor (which `MapValidator` rejects).
    public var bounds: Rect2 {
        var pts: [Point2] = []
        pts.reserveCapacity(walls.count * 2 + doors.count + signs.count + pointsOfInterest.count)
        for w in walls { pts.append(w.from); pts.append(w.to) }
        pts += doors.map(\.position) + signs.map(\.position) + pointsOfInterest.map(\.position)
        return Rect2(enclosing: pts) ?? Rect2(minX: 0, minY: 0, maxX: 0, maxY: 0)
    }

    /// The wall closest to `p` and its distance in meters; nil when the floor has no walls. Linear scan.
    public func nearestWall(to p: Point2) -> (index: Int, distanceMeters: Double)? {
        var best: (Int, Double)?
        for (i, w) in walls.enumerated() {
            let d = w.distance(to: p)
            if best == nil || d < best!.1 { best = (i, d) }
        }
        return best.map { (index: $0.0, distanceMeters: $0.1) }
    }

    /// True when walking straight from `a` to `b` touches or crosses any wall. Linear scan.
    public func crossesWall(from a: Point2, to b: Point2) -> Bool { firstWallCrossed(from: a, to: b) != nil }

    /// Index of the first wall (in file order) that the straight walk from `a` to `b` crosses or touches, nil when
    /// the way is clear. This is the one "walkable in a straight line" rule: `MapValidator` applies it to every
    /// graph edge on a floor and the walk simulator to every leg of a route. Exact orientation test
    /// (`Geometry.segmentsIntersect`), linear scan.
    public func firstWallCrossed(from a: Point2, to b: Point2) -> Int? {
        walls.firstIndex { $0.intersects(from: a, to: b) }
    }

    /// The point of interest with this id on this floor.
    public func pointOfInterest(id poiId: String) -> PointOfInterest? { pointsOfInterest.first { $0.id == poiId } }
    /// The sign with this id on this floor.
    public func sign(id signId: String) -> Sign? { signs.first { $0.id == signId } }
}
