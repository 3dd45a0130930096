import Foundation
import Localizer
import SessionFormat

/// Converts ARKit poses to the localizer's VIO samples: the camera's position and yaw on the VIO floor
/// plane (see `CameraPose` for the frame conventions).
enum VIOConversion {
    /// The localizer's tracking state for ARKit's.
    static func tracking(_ state: TrackingState) -> VIOTracking {
        switch state {
        case .normal: return .normal
        case .limited: return .limited
        case .notAvailable: return .notAvailable
        }
    }

    /// The VIO sample of a pose at time `t`.
    static func sample(t: Double, pose: CameraPose, tracking state: TrackingState) -> VIOSample {
        let p = pose.positionInVIOPlane
        return VIOSample(t: t, east: p.east, north: p.north, yawRad: pose.yawInVIOPlaneRad, tracking: tracking(state))
    }
}
