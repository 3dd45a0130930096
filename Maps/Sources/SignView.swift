import Foundation

/// The geometry of seeing a sign from a point of its floor, shared by the walk simulator's detector model and the
/// app's expected sign kinds (`ExpectedSignKinds`), so both judge a sign's face and line of sight alike.
extension Sign {
    /// Whether the sign's face is turned towards a viewer within `maxViewAngleDeg` of its normal (`facing`, any length;
    /// a zero one counts as 1e-9 long): (`dx`, `dy`) = sign position minus viewer position, meters, `distanceMeters`
    /// their length (> 0). Either face of a double-sided sign counts.
    public func faceIsTurned(towardsViewerAtOffset dx: Double, _ dy: Double, distanceMeters r: Double,
                             maxViewAngleDeg: Double) -> Bool {
        let facingLength = max(1e-9, hypot(facing.x, facing.y))
        let cosView = -(facing.x * dx + facing.y * dy) / (r * facingLength)
        return (doubleSided ? abs(cosView) : cosView) >= cos(maxViewAngleDeg * Double.pi / 180)
    }

    /// The end of a line-of-sight test from a viewer at offset (`dx`, `dy`) (sign minus viewer, meters, length
    /// `distanceMeters` > 0): a point 5 cm in front of the sign towards the viewer, so the wall it hangs on is not
    /// crossed.
    public func lineOfSightEnd(viewerOffset dx: Double, _ dy: Double, distanceMeters r: Double) -> Point2 {
        Point2(position.x - 0.05 * dx / r, position.y - 0.05 * dy / r)
    }
}
