import Foundation

/// Geometry of an ARKit camera-to-world transform, with the conventions checked on real recordings
/// (../shared/reference/arkit-frames.md, docs/frames.md):
/// - world: gravity aligned, y up, x and z horizontal, origin and yaw arbitrary;
/// - camera: x along the sensor's long side (image u), y along the short side (image -v), looks along -z;
/// - VIO floor plane: the horizontal coordinates `(east, north) = (x_w, -z_w)`, so that a yaw measured
///   CCW from the VIO east axis composes with the map frame's CCW yaw by plain addition.
///
/// The pose is a value; it owns its 16 numbers.
public struct CameraPose: Hashable, Sendable {
    /// Column-major 4x4 camera-to-world transform (ARKit/simd order), meters.
    public var columnMajor: [Double]

    /// Wraps 16 column-major numbers. Returns nil unless there are exactly 16 finite numbers.
    public init?(columnMajor: [Double]) {
        guard columnMajor.count == 16, columnMajor.allSatisfy({ $0.isFinite }) else { return nil }
        self.columnMajor = columnMajor
    }

    /// Builds the transform of a camera at `positionInWorld` (meters, ARKit world) whose forward direction
    /// has the VIO-plane yaw `yawRad` (CCW from VIO east), elevation `pitchRad` (positive up) and roll
    /// `rollRad` about its viewing axis (0 = landscape with image top up; -pi/2 = portrait, the traveler's
    /// posture). R = Ry(yaw - pi/2) * Rx(pitch) * Rz(roll).
    public init(positionInWorld: (x: Double, y: Double, z: Double), yawRad: Double, pitchRad: Double, rollRad: Double) {
        let psi = yawRad - Double.pi / 2
        let (cy, sy) = (cos(psi), sin(psi))
        let (cp, sp) = (cos(pitchRad), sin(pitchRad))
        let (cr, sr) = (cos(rollRad), sin(rollRad))
        // Rx * Rz
        let a: [[Double]] = [
            [cr, -sr, 0],
            [cp * sr, cp * cr, -sp],
            [sp * sr, sp * cr, cp],
        ]
        // Ry * a
        var r = [[Double]](repeating: [0, 0, 0], count: 3)
        for j in 0..<3 {
            r[0][j] = cy * a[0][j] + sy * a[2][j]
            r[1][j] = a[1][j]
            r[2][j] = -sy * a[0][j] + cy * a[2][j]
        }
        columnMajor = [
            r[0][0], r[1][0], r[2][0], 0,
            r[0][1], r[1][1], r[2][1], 0,
            r[0][2], r[1][2], r[2][2], 0,
            positionInWorld.x, positionInWorld.y, positionInWorld.z, 1,
        ]
    }

    /// Element at row `row`, column `column` of the 4x4 matrix.
    public func element(row: Int, column: Int) -> Double { columnMajor[column * 4 + row] }

    /// Camera position in the ARKit world, meters.
    public var positionInWorld: (x: Double, y: Double, z: Double) { (columnMajor[12], columnMajor[13], columnMajor[14]) }

    /// Camera position on the VIO floor plane `(east, north) = (x_w, -z_w)`, meters.
    public var positionInVIOPlane: (east: Double, north: Double) { (columnMajor[12], -columnMajor[14]) }

    /// Camera forward direction (-z axis) in the world, unit vector.
    public var forwardInWorld: (x: Double, y: Double, z: Double) { (-columnMajor[8], -columnMajor[9], -columnMajor[10]) }

    /// Yaw of the forward direction on the VIO plane, radians CCW from VIO east. Undefined (returns the
    /// yaw of the camera's -y axis instead) only when looking straight up or down.
    public var yawInVIOPlaneRad: Double {
        let f = forwardInWorld
        if hypot(f.x, f.z) > 1e-6 { return atan2(-f.z, f.x) }
        // Looking straight down/up: use the image-up direction (camera +y) projected on the plane.
        return atan2(-columnMajor[6], columnMajor[4])
    }

    /// Elevation of the optical axis above the horizon, radians (positive looking up).
    public var pitchRad: Double { asin(max(-1, min(1, forwardInWorld.y))) }

    /// Roll about the optical axis, radians: the angle of world-up in the camera's x-y plane,
    /// atan2(up_x, up_y) with up = R^T (0, 1, 0). 0 = landscape, image top up; -pi/2 = portrait (camera x
    /// pointing down), matching ARKit's Euler roll.
    public var rollRad: Double {
        let upX = columnMajor[1]   // R[1][0]: world-y component of camera x
        let upY = columnMajor[5]   // R[1][1]: world-y component of camera y
        return atan2(upX, upY)
    }

    /// World direction of the ray through pixel (u, v) for these intrinsics (not normalised):
    /// R * [(u - cx)/fx, -(v - cy)/fy, -1].
    public func rayInWorld(u: Double, v: Double, intrinsics k: CameraIntrinsics) -> (x: Double, y: Double, z: Double) {
        let c = ((u - k.cx) / k.fx, -(v - k.cy) / k.fy, -1.0)
        let m = columnMajor
        return (m[0] * c.0 + m[4] * c.1 + m[8] * c.2,
                m[1] * c.0 + m[5] * c.1 + m[9] * c.2,
                m[2] * c.0 + m[6] * c.1 + m[10] * c.2)
    }
}
