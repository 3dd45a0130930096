#if canImport(CoreMotion) && os(iOS)
import CoreMotion
import QuartzCore
import WayfinderCore

/// Device-motion gravity for the onboarding's orientation practice (`OrientationCoach`), 10 Hz on the
/// main queue.
@MainActor
final class AttitudeSource {
    private let motion = CMMotionManager()
    /// Called with each attitude and its time, seconds.
    var onAttitude: ((PhoneAttitude, Double) -> Void)?

    func start() {
        guard motion.isDeviceMotionAvailable else { return }
        motion.deviceMotionUpdateInterval = 0.1
        motion.startDeviceMotionUpdates(to: .main) { [weak self] data, _ in
            guard let g = data?.gravity, let a = PhoneAttitude(gravityX: g.x, y: g.y, z: g.z) else { return }
            MainActor.assumeIsolated { self?.onAttitude?(a, CACurrentMediaTime()) }
        }
    }

    func stop() { motion.stopDeviceMotionUpdates() }
}
#endif
