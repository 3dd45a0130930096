import Foundation
import Maps
import SessionFormat

/// Renders simulated camera images (placeholder until the ray caster lands).
struct SceneRenderer: Sendable {
    /// Intrinsics of rendered images: the iPhone 8 camera scaled to 640 x 480.
    static let imageIntrinsics = CameraIntrinsics(fx: 534, fy: 534, cx: 320, cy: 240, width: 640, height: 480)
    let floors: [String: Floor]
    let geometry: [String: FloorGeometry]
    let states: [TrueCameraState]
    let intrinsics: CameraIntrinsics

    func renderPPM(frameIndex: Int) -> Data {
        let header = "P6\n\(intrinsics.width) \(intrinsics.height)\n255\n"
        return Data(header.utf8) + Data(count: intrinsics.width * intrinsics.height * 3)
    }
}
