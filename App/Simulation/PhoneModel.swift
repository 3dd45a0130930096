import Foundation

/// The phone's pose relative to the walking body at one frame.
struct PhonePose: Sendable {
    /// Camera height above the floor, meters.
    var heightMeters: Double
    /// Camera pitch, radians (positive looking up).
    var pitchRad: Double
    /// Camera roll about the optical axis, radians (-pi/2 portrait, 0 landscape).
    var rollRad: Double
    /// Camera yaw relative to the body's heading, radians CCW.
    var yawOffsetRad: Double
}

/// How the phone moves on the body: a per-walk mean pitch and height, slow Ornstein-Uhlenbeck wander of pitch,
/// roll and yaw, oscillations locked to the step phase (pitch and roll at the step frequency, the lanyard's yaw
/// swing at half of it), and white tremor.
struct PhoneModel {
    let parameters: PhoneParameters
    let carry: CarryMode
    let orientation: PhoneOrientation
    let dt: Double

    func run(body: [BodyState], rng: inout SeededRandom) -> [PhonePose] {
        let p = parameters
        let height = rng.uniform(p.cameraHeightRange.lowerBound, p.cameraHeightRange.upperBound)
        let handheld = carry == .handheld
        let pitchMeanRange = handheld ? p.handheldPitchMeanRangeDeg : p.lanyardPitchMeanRangeDeg
        let pitchMean = rng.uniform(pitchMeanRange.lowerBound, pitchMeanRange.upperBound)
        let wanderSigma = handheld ? p.handheldWanderSigmaDeg : p.lanyardWanderSigmaDeg
        var pitchOU = OrnsteinUhlenbeck(sigma: wanderSigma, tauSeconds: p.wanderTauSeconds, rng: &rng)
        var rollOU = OrnsteinUhlenbeck(sigma: wanderSigma, tauSeconds: p.wanderTauSeconds, rng: &rng)
        var yawOU = OrnsteinUhlenbeck(sigma: wanderSigma, tauSeconds: p.wanderTauSeconds, rng: &rng)
        let rollBase = orientation == .portrait ? -90.0 : 0.0
        let stepPhaseOffset = rng.uniform(0, 2 * Double.pi)
        var out: [PhonePose] = []
        out.reserveCapacity(body.count)
        for b in body {
            let moving = b.speed > 0.1 ? min(1, b.speed / 0.8) : 0
            let ph = b.stepPhaseRad + stepPhaseOffset
            var pitch = pitchMean + pitchOU.step(dt: dt, rng: &rng)
            var roll = rollBase + rollOU.step(dt: dt, rng: &rng)
            var yaw = yawOU.step(dt: dt, rng: &rng)
            if handheld {
                pitch += moving * p.handheldStepAmplitudeDeg * sin(ph)
                roll += moving * p.handheldStepAmplitudeDeg * sin(ph + 1.0)
            } else {
                pitch += moving * p.lanyardPitchAmplitudeDeg * sin(ph)
                roll += moving * p.lanyardRollAmplitudeDeg * sin(ph + 0.5)
                yaw += moving * p.lanyardYawAmplitudeDeg * sin(ph / 2)
            }
            pitch += rng.normal(sigma: p.tremorSigmaDeg)
            if handheld { pitch = max(p.handheldPitchLimitsDeg.lowerBound, min(p.handheldPitchLimitsDeg.upperBound, pitch)) }
            roll += rng.normal(sigma: p.tremorSigmaDeg)
            yaw += rng.normal(sigma: p.tremorSigmaDeg)
            let h = height + moving * p.bobAmplitudeMeters * sin(ph)
            out.append(PhonePose(heightMeters: h, pitchRad: radians(pitch), rollRad: radians(roll), yawOffsetRad: radians(yaw)))
        }
        return out
    }
}
