import Foundation
import XCTest
@testable import SessionFormat
import TestRandom

/// The facts of ../shared/reference/arkit-frames.md, checked on CameraPose and on a real full-rate
/// ARKit recording (../shared/data/arkit_data_logger_sample/ARKit_camera_pose.txt: iPhone XS, 60 Hz,
/// rows `timestamp_ns r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz`, row-major 3x4).
final class ARKitFramesTests: XCTestCase {
    /// Parses the logger file into (seconds, column-major 4x4) pairs.
    private func loggerPoses() throws -> [(t: Double, m: [Double])] {
        let url = try sharedData("arkit_data_logger_sample").appendingPathComponent("ARKit_camera_pose.txt")
        let text = try String(contentsOf: url, encoding: .utf8)
        var out: [(Double, [Double])] = []
        for (n, line) in text.split(separator: "\n").enumerated() where !line.hasPrefix("#") {
            let v = line.split(separator: " ").compactMap { Double($0) }
            XCTAssertEqual(v.count, 13, "line \(n + 1)")
            guard v.count == 13 else { continue }
            let r = Array(v[1...])   // row-major 3x4
            // Column-major 4x4: column j = (r[j], r[4 + j], r[8 + j], j == 3 ? 1 : 0).
            var m = [Double](repeating: 0, count: 16)
            for j in 0..<4 {
                for i in 0..<3 { m[j * 4 + i] = r[i * 4 + j] }
            }
            m[15] = 1
            out.append((v[0] * 1e-9, m))
        }
        return out
    }

    func testLoggerRecordingIsSixtyHertzWithTranslationInTheLastColumn() throws {
        let poses = try loggerPoses()
        XCTAssertEqual(poses.count, 2762)
        let dts = zip(poses, poses.dropFirst()).map { $1.t - $0.t }
        XCTAssertTrue(dts.allSatisfy { $0 > 0 })
        XCTAssertEqual(median(dts), 1.0 / 60, accuracy: 0.001)
        XCTAssertEqual(poses.last!.t - poses.first!.t, 46, accuracy: 1)
        // Every pose is a valid frame for the bundle (bottom row, orthonormal rotation)...
        for p in poses {
            XCTAssertNil(FrameRecord(t: p.t, cameraToWorld: p.m, intrinsics: .iPhone8Full).validationProblem())
        }
        // ...and the translation column describes a room-sized motion (SOURCE.md: 3.5 x 0.5 x 3.2 m).
        let xs = poses.map { $0.m[12] }, ys = poses.map { $0.m[13] }, zs = poses.map { $0.m[14] }
        XCTAssertLessThan(xs.max()! - xs.min()!, 5)
        XCTAssertLessThan(ys.max()! - ys.min()!, 1.5)
        XCTAssertLessThan(zs.max()! - zs.min()!, 5)
    }

    /// Held in portrait: camera x points down (roll about -90 degrees; the hand also pitches the phone down,
    /// so x is not always vertical), camera y is horizontal.
    func testLoggerRecordingIsPortraitWithRollNearMinus90() throws {
        let poses = try loggerPoses().map { CameraPose(columnMajor: $0.m)! }
        let rollDeg = median(poses.map { $0.rollRad * 180 / .pi })
        XCTAssertEqual(rollDeg, -90, accuracy: 10)
        let nearPortrait = poses.filter { abs($0.rollRad * 180 / .pi + 90) < 20 }.count
        XCTAssertGreaterThan(Double(nearPortrait) / Double(poses.count), 0.9)
        let xDown = poses.filter { $0.columnMajor[1] < -0.5 }.count        // world-y of camera x
        XCTAssertGreaterThan(Double(xDown) / Double(poses.count), 0.9)
        let yFlat = poses.filter { abs($0.columnMajor[5]) < 0.3 }.count    // world-y of camera y
        XCTAssertGreaterThan(Double(yFlat) / Double(poses.count), 0.9)
    }

    /// The real Exit-sign shot of arkit-frames.md: eulerAngles (pitch 0.093, yaw -0.006, roll -1.580).
    func testCameraPoseMatchesARKitEulerAngles() throws {
        let pitch = 0.093, yaw = -0.006, roll = -1.580
        // ARKit's eulerAngles compose R = Ry(yaw) Rx(pitch) Rz(roll); CameraPose's yaw is measured from VIO
        // east, ARKit's from the -z axis (VIO north), hence the pi/2.
        let pose = CameraPose(positionInWorld: (x: 0, y: 0, z: 0), yawRad: yaw + .pi / 2, pitchRad: pitch, rollRad: roll)
        XCTAssertEqual(pose.pitchRad, pitch, accuracy: 1e-9)
        XCTAssertEqual(pose.rollRad, roll, accuracy: 1e-9)
        XCTAssertEqual(pose.yawInVIOPlaneRad, yaw + .pi / 2, accuracy: 1e-9)
        // Portrait: the camera's x axis points (almost) straight down.
        XCTAssertLessThan(pose.columnMajor[1], -0.99)
    }

    func testCameraPoseRoundTripsYawPitchRoll() throws {
        var rng = SplitMix64(seed: 7)
        for _ in 0..<500 {
            let yaw = Double.random(in: -Double.pi...Double.pi, using: &rng)
            let pitch = Double.random(in: -1.4...1.4, using: &rng)
            let roll = Double.random(in: -Double.pi...Double.pi, using: &rng)
            let p = CameraPose(positionInWorld: (x: 1, y: 2, z: 3), yawRad: yaw, pitchRad: pitch, rollRad: roll)
            XCTAssertNil(FrameRecord(t: 0, cameraToWorld: p.columnMajor, intrinsics: .iPhone8Full).validationProblem())
            XCTAssertEqual(p.pitchRad, pitch, accuracy: 1e-9)
            XCTAssertEqual(remainder(p.yawInVIOPlaneRad - yaw, 2 * .pi), 0, accuracy: 1e-9)
            XCTAssertEqual(remainder(p.rollRad - roll, 2 * .pi), 0, accuracy: 1e-9)
            XCTAssertEqual(p.positionInVIOPlane.east, 1)
            XCTAssertEqual(p.positionInVIOPlane.north, -3)
        }
    }

    /// The principal point's ray is the forward axis; a pixel right of centre (larger u) in a landscape
    /// camera is to the right (negative bearing), a pixel below centre is below the horizon.
    func testPixelRays() throws {
        let k = CameraIntrinsics.iPhone8Full
        let p = CameraPose(positionInWorld: (x: 0, y: 0, z: 0), yawRad: 0.3, pitchRad: 0, rollRad: 0)
        let c = p.rayInWorld(u: k.cx, v: k.cy, intrinsics: k)
        let f = p.forwardInWorld
        XCTAssertEqual(c.x, f.x, accuracy: 1e-12)
        XCTAssertEqual(c.y, f.y, accuracy: 1e-12)
        XCTAssertEqual(c.z, f.z, accuracy: 1e-12)
        let r = p.rayInWorld(u: k.cx + 500, v: k.cy, intrinsics: k)
        let bearing = remainder(atan2(-r.z, r.x) - p.yawInVIOPlaneRad, 2 * .pi)
        XCTAssertEqual(bearing, -atan(500 / k.fx), accuracy: 1e-9)
        let d = p.rayInWorld(u: k.cx, v: k.cy + 300, intrinsics: k)
        XCTAssertEqual(atan2(d.y, hypot(d.x, d.z)), -atan(300 / k.fy), accuracy: 1e-9)
    }
}
