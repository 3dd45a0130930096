import Foundation
import Maps

/// A wall the phone sees now (an ARKit vertical plane: a cabinet or an open door leaf counts too), as a
/// segment in the traveler's own frame: x forward along the camera's horizontal heading, y to the left,
/// meters. It needs no hypothesis: while the localizer is unsure, an exploratory instruction that would lead
/// into a wall the phone sees is not given, whichever place the hypotheses put the traveler in (if the true
/// place is not among them, the map cannot warn; the camera still can). The ray cast is the map's
/// (`Geometry.freeDistance`).
public struct PerceivedWall: Sendable, Equatable {
    /// One end, meters (x forward, y left).
    public var from: Point2
    /// The other end, meters.
    public var to: Point2

    /// Creates a wall segment in the traveler's frame.
    public init(from: Point2, to: Point2) { self.from = from; self.to = to }

    /// The wall of a plane seen from a camera, all on the VIO floor plane (meters; yaws radians CCW from VIO
    /// east): the plane's center, its normal's yaw and its width along the wall; the camera's position and
    /// the yaw of its forward direction. Nil when a number is not finite or the width is not positive.
    public init?(planeCenterEast ce: Double, planeCenterNorth cn: Double, planeNormalYawRad: Double, widthMeters: Double,
                 cameraEast pe: Double, cameraNorth pn: Double, cameraYawRad yaw: Double) {
        guard [ce, cn, planeNormalYawRad, widthMeters, pe, pn, yaw].allSatisfy(\.isFinite), widthMeters > 0 else { return nil }
        let c = cos(yaw), s = sin(yaw)
        // VIO (east, north) offset from the camera to traveler (forward, left).
        func local(_ e: Double, _ n: Double) -> Point2 {
            let de = e - pe, dn = n - pn
            return Point2(x: de * c + dn * s, y: -de * s + dn * c)
        }
        let tangent = planeNormalYawRad + Double.pi / 2, half = widthMeters / 2
        from = local(ce - half * cos(tangent), cn - half * sin(tangent))
        to = local(ce + half * cos(tangent), cn + half * sin(tangent))
    }

    /// Distance from the traveler along the direction `turnRad` (radians CCW from straight ahead) to the first
    /// of `walls`, meters; `far` when none is nearer.
    public static func freeDistance(_ walls: [PerceivedWall], turnRad: Double, far: Double) -> Double {
        Geometry.freeDistance(from: Point2(x: 0, y: 0), directionRad: turnRad, far: far,
                              segments: walls.lazy.map { ($0.from, $0.to) })
    }
}
