// Private 2-D geometry for routing and guidance. Kept internal (a small value type of our own instead of
// operators on Maps' `Point2`) so that helpers added to Maps later can never make a call here ambiguous.
// Frame: the floor's map frame, x east, y north, meters; angles radians CCW from +x unless named `...Deg`.
import Foundation
import Maps

/// A 2-D vector or point in a floor's map frame, meters.
struct Vec2: Equatable, Sendable {
    var x: Double
    var y: Double

    init(_ x: Double, _ y: Double) { self.x = x; self.y = y }
    init(_ p: Point2) { x = p.x; y = p.y }

    static let zero = Vec2(0, 0)

    var point2: Point2 { Point2(x: x, y: y) }

    static func + (a: Vec2, b: Vec2) -> Vec2 { Vec2(a.x + b.x, a.y + b.y) }
    static func - (a: Vec2, b: Vec2) -> Vec2 { Vec2(a.x - b.x, a.y - b.y) }
    static func * (a: Vec2, s: Double) -> Vec2 { Vec2(a.x * s, a.y * s) }

    /// Dot product.
    func dot(_ o: Vec2) -> Double { x * o.x + y * o.y }
    /// z component of the 3-D cross product: positive when `o` is counter-clockwise (to the left) of `self`.
    func cross(_ o: Vec2) -> Double { x * o.y - y * o.x }
    /// Euclidean length, meters.
    var length: Double { (x * x + y * y).squareRoot() }
    /// Squared length.
    var lengthSquared: Double { x * x + y * y }
    /// Direction angle, radians CCW from +x.
    var angleRad: Double { atan2(y, x) }
    /// Distance to another point, meters.
    func distance(to o: Vec2) -> Double { (self - o).length }
}

/// Wraps an angle into (-pi, pi].
func normalizedAngleRad(_ a: Double) -> Double {
    var r = a.truncatingRemainder(dividingBy: 2 * Double.pi)
    if r > Double.pi { r -= 2 * Double.pi }
    if r <= -Double.pi { r += 2 * Double.pi }
    return r
}

/// Signed change of direction from `incoming` to `outgoing`, radians in (-pi, pi]; positive = left (CCW).
func signedTurnAngleRad(from incoming: Vec2, to outgoing: Vec2) -> Double {
    atan2(incoming.cross(outgoing), incoming.dot(outgoing))
}

/// Closest point to `p` on the segment `a`-`b`: the parameter t in [0, 1] (0 at `a`) and the point.
func projectOntoSegment(_ p: Vec2, _ a: Vec2, _ b: Vec2) -> (t: Double, point: Vec2, distance: Double) {
    let ab = b - a
    let len2 = ab.lengthSquared
    var t = 0.0
    if len2 > 1e-18 { t = max(0, min(1, (p - a).dot(ab) / len2)) }
    let q = a + ab * t
    return (t, q, p.distance(to: q))
}

/// Orientation of the triangle (a, b, c): > 0 counter-clockwise, < 0 clockwise.
@inline(__always)
private func orient(_ a: Vec2, _ b: Vec2, _ c: Vec2) -> Double { (b - a).cross(c - a) }

/// True when the segment p1-p2 (a line of sight) crosses the wall q1-q2: its ends lie strictly on
/// opposite sides of the wall's line, and the wall's ends are not both strictly on one side of p1-p2.
/// A wall end exactly on the line of sight blocks it (so a line through the joint of two wall segments
/// is blocked); a line-of-sight end exactly on a wall line does not (an estimate lying on a wall is not
/// behind it).
func segmentsCrossProperly(_ p1: Vec2, _ p2: Vec2, _ q1: Vec2, _ q2: Vec2, eps: Double = 1e-12) -> Bool {
    let d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2)
    guard (d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps) else { return false }
    let d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2)
    return !((d3 > eps && d4 > eps) || (d3 < -eps && d4 < -eps))
}
