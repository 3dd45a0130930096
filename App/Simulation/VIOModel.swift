import Foundation
import SessionFormat

/// The true camera pose in the map frame at one frame, the input of the sensor models.
struct TrueCameraState: Sendable {
    var t: Double
    var floorId: String
    /// Camera position on the plan, meters.
    var position: Point2Value
    /// Camera height above the building reference (floor elevation + height above the floor), meters.
    var altitudeMeters: Double
    /// Camera height above the current floor, meters.
    var heightAboveFloorMeters: Double
    /// Yaw of the camera's forward direction, radians CCW from map +x.
    var yawRad: Double
    var pitchRad: Double
    var rollRad: Double
    /// Camera yaw rate, rad/s (smoothed over ~0.2 s).
    var yawRateRadPerSecond: Double
}

/// A plain (x, y) pair, meters (kept separate from Maps' Point2 so this file needs only SessionFormat).
struct Point2Value: Sendable { var x: Double; var y: Double }

/// One VIO output frame.
struct VIOFrame: Sendable {
    var cameraToWorld: [Double]
    var tracking: TrackingState
    var reason: TrackingReason?
}

/// Where VIO events happened (diagnostics).
public struct VIOEvents: Sendable, Codable, Equatable {
    /// Scale factor s: VIO distances are s times the true ones.
    public var scale: Double
    /// Constant yaw drift rate, radians per second.
    public var yawDriftRateRadPerSecond: Double
    /// Times at which the world origin jumped after relocalizing, seconds.
    public var relocalizationTimes: [Double]
    /// Size of each jump, meters.
    public var relocalizationJumpMeters: [Double]
    /// Time of the full reset, if any.
    public var resetTime: Double?
    /// Tracking-loss interval, if any.
    public var trackingLoss: ClosedRange<Double>?
}

/// ARKit VIO as it behaves in real recordings: the world frame has an arbitrary origin and yaw; horizontal and
/// vertical displacements are scaled by s (scale error); the map-to-world yaw drifts (constant rate plus random
/// walk); poses carry millimetre jitter; tracking degrades to `limited` on fast turns (excessiveMotion), in
/// dark stretches (insufficientFeatures, Poisson) and while relocalizing (Poisson; afterwards the origin jumps
/// by up to ~1 m and a few degrees); a tracking loss freezes the pose (`notAvailable`) and the displacement
/// walked meanwhile is lost; a reset starts a new world frame (`initializing`).
///
/// Poses are integrated from true increments: p[k] = p[k-1] + s R(theta_k) (x[k] - x[k-1]) (+ a random walk
/// while limited), so errors accumulate like odometry.
struct VIOModel {
    let parameters: VIOParameters
    let dt: Double
    let trackingLossAt: Double?
    let trackingLossDuration: Double
    let resetAt: Double?

    func run(states: [TrueCameraState], rng: inout SeededRandom, trackingRng: inout SeededRandom) -> ([VIOFrame], [Double], VIOEvents) {
        let p = parameters
        let scale = 1 + rng.sign() * rng.uniform(p.scaleErrorRange.lowerBound, p.scaleErrorRange.upperBound)
        let driftRate = rng.sign() * radians(rng.uniform(p.yawDriftRateRangeDegPerMinute.lowerBound, p.yawDriftRateRangeDegPerMinute.upperBound)) / 60
        let rwPerSqrtSecond = radians(p.yawRandomWalkDegPerSqrtMinute) / (60.0).squareRoot()
        var theta = rng.uniform(-Double.pi, Double.pi)
        var east = rng.normal(sigma: p.originOffsetMeters), north = rng.normal(sigma: p.originOffsetMeters)
        var up = rng.normal(sigma: p.originOffsetMeters)
        var events = VIOEvents(scale: scale, yawDriftRateRadPerSecond: driftRate, relocalizationTimes: [],
                               relocalizationJumpMeters: [], resetTime: resetAt, trackingLoss: nil)
        if let a = trackingLossAt { events.trackingLoss = a...(a + trackingLossDuration) }

        // Tracking schedule: Poisson dark spells and relocalization events (own stream).
        var darkSpells: [ClosedRange<Double>] = []
        var relocSpells: [ClosedRange<Double>] = []
        let endT = states.last?.t ?? 0
        var tt = trackingRng.exponential(ratePerSecond: p.darkSpellsPerSecond)
        while tt < endT {
            let d = trackingRng.uniform(p.darkSpellSecondsRange.lowerBound, p.darkSpellSecondsRange.upperBound)
            darkSpells.append(tt...(tt + d)); tt += d + trackingRng.exponential(ratePerSecond: p.darkSpellsPerSecond)
        }
        tt = trackingRng.exponential(ratePerSecond: p.relocalizationsPerSecond)
        while tt < endT {
            let d = trackingRng.uniform(p.relocalizingSecondsRange.lowerBound, p.relocalizingSecondsRange.upperBound)
            relocSpells.append(tt...(tt + d)); tt += d + trackingRng.exponential(ratePerSecond: p.relocalizationsPerSecond)
        }

        var frames: [VIOFrame] = []
        var thetas: [Double] = []
        frames.reserveCapacity(states.count)
        var frozen: [Double]?
        var initializingUntil = p.initializingSeconds
        var relocalizingUntil = -1.0
        var inRelocSpell = -1
        var didReset = false
        for (k, s) in states.enumerated() {
            let t = s.t
            theta += driftRate * dt + rwPerSqrtSecond * dt.squareRoot() * rng.normal()
            // Full reset: a new arbitrary world frame around the current camera.
            if let r = resetAt, !didReset, t >= r {
                didReset = true
                theta = rng.uniform(-Double.pi, Double.pi)
                east = rng.normal(sigma: p.originOffsetMeters); north = rng.normal(sigma: p.originOffsetMeters)
                up = rng.normal(sigma: p.originOffsetMeters)
                initializingUntil = t + p.initializingSeconds
                frozen = nil
            }
            let lost = events.trackingLoss.map { $0.contains(t) } ?? false
            if k > 0 {
                let prev = states[k - 1]
                let dx = s.position.x - prev.position.x, dy = s.position.y - prev.position.y
                if !lost || p.poseKeptThroughLoss {
                    east += scale * (cos(theta) * dx - sin(theta) * dy)
                    north += scale * (sin(theta) * dx + cos(theta) * dy)
                    up += scale * (s.altitudeMeters - prev.altitudeMeters)
                }
                if let loss = events.trackingLoss, prev.t <= loss.upperBound, t > loss.upperBound {
                    relocalizingUntil = t + p.afterLossRelocalizingSeconds
                }
            }
            // Relocalization: at the end of each spell the origin jumps (position and yaw about the camera).
            var relocalizing = t < relocalizingUntil
            if let i = relocSpells.firstIndex(where: { $0.contains(t) }) { relocalizing = true; inRelocSpell = i }
            else if inRelocSpell >= 0 {
                let mag = rng.uniform(p.relocalizationJumpMetersRange.lowerBound, p.relocalizationJumpMetersRange.upperBound)
                let dir = rng.uniform(-Double.pi, Double.pi)
                east += mag * cos(dir); north += mag * sin(dir)
                let yj = max(-3, min(3, rng.normal())) * radians(p.relocalizationYawJumpSigmaDeg)
                theta += yj
                events.relocalizationTimes.append(t); events.relocalizationJumpMeters.append(mag)
                inRelocSpell = -1
            }
            let excessive = abs(s.yawRateRadPerSecond) > radians(p.excessiveMotionTurnRateDegPerSecond)
            let dark = darkSpells.contains { $0.contains(t) }
            var tracking = TrackingState.normal
            var reason: TrackingReason?
            if lost { tracking = .notAvailable }
            else if t < initializingUntil { tracking = .limited; reason = .initializing }
            else if relocalizing { tracking = .limited; reason = .relocalizing }
            else if excessive { tracking = .limited; reason = .excessiveMotion }
            else if dark { tracking = .limited; reason = .insufficientFeatures }
            if tracking == .limited && reason != .initializing {
                let w = p.limitedPositionRandomWalkMetersPerSqrtSecond * dt.squareRoot()
                east += w * rng.normal(); north += w * rng.normal()
            }
            thetas.append(theta)
            if lost, let f = frozen {
                frames.append(VIOFrame(cameraToWorld: f, tracking: .notAvailable, reason: nil))
                continue
            }
            let j = p.positionJitterMeters, a = radians(p.orientationJitterDeg)
            let pose = CameraPose(
                positionInWorld: (x: east + rng.normal(sigma: j), y: up + rng.normal(sigma: j), z: -(north + rng.normal(sigma: j))),
                yawRad: wrapAngle(s.yawRad + theta + rng.normal(sigma: a)),
                pitchRad: s.pitchRad + rng.normal(sigma: a),
                rollRad: s.rollRad + rng.normal(sigma: a))
            frozen = pose.columnMajor
            frames.append(VIOFrame(cameraToWorld: pose.columnMajor, tracking: tracking, reason: reason))
        }
        return (frames, thetas, events)
    }
}
