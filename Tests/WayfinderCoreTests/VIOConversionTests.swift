import XCTest
import SessionFormat
@testable import WayfinderCore

/// The pose -> VIO-plane conversion the localizer relies on, on exact synthetic poses.
final class VIOConversionTests: XCTestCase {
    func testYawPitchRollRoundTripThroughCameraPose() {
        for yaw in stride(from: -3.0, through: 3.0, by: 0.5) {
            for pitch in [-0.5, -0.1, 0, 0.2, 0.5] {
                for roll in [-Double.pi / 2, -1.2, 0, 0.4] {
                    let pose = CameraPose(positionInWorld: (1, 1.4, -2), yawRad: yaw, pitchRad: pitch, rollRad: roll)
                    let s = VIOConversion.sample(t: 0, pose: pose, tracking: .normal)
                    XCTAssertEqual(cos(s.yawRad - yaw), 1, accuracy: 1e-9, "yaw \(yaw) pitch \(pitch) roll \(roll)")
                    XCTAssertEqual(pose.pitchRad, pitch, accuracy: 1e-9)
                    XCTAssertEqual(pose.rollRad, roll, accuracy: 1e-9)
                    XCTAssertEqual(s.east, 1, accuracy: 1e-12)
                    XCTAssertEqual(s.north, 2, accuracy: 1e-12)
                }
            }
        }
    }

    /// arkit-frames.md: held in portrait, camera forward, the camera x axis points down in the world.
    func testPortraitCameraXAxisPointsDown() {
        let pose = CameraPose(positionInWorld: (0, 1.4, 0), yawRad: 0.3, pitchRad: 0, rollRad: -Double.pi / 2)
        XCTAssertEqual(pose.element(row: 1, column: 0), -1, accuracy: 1e-12)
    }

    func testNonFinitePoseIsRejected() {
        var m = CameraPose(positionInWorld: (0, 0, 0), yawRad: 0, pitchRad: 0, rollRad: 0).columnMajor
        m[12] = .nan
        XCTAssertNil(CameraPose(columnMajor: m))
        XCTAssertNil(CameraPose(columnMajor: Array(m.prefix(15))))
    }
}
