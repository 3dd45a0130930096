import Foundation

/// Camera pitch and roll from the gravity vector in the device frame (CMDeviceMotion.gravity: x to the
/// right of the screen, y to its top, z out of the screen, in g). The back camera looks along -z.
public struct PhoneAttitude: Sendable, Equatable {
    /// Elevation of the back camera's optical axis, degrees: 0 level, positive up, -90 lying screen up.
    public var cameraPitchDeg: Double
    /// Rotation in the screen's plane away from upright portrait, degrees: positive = the top leans right.
    public var rollDeg: Double

    /// From a gravity vector (any length > 0); nil when it is not finite or zero.
    public init?(gravityX x: Double, y: Double, z: Double) {
        let n = (x * x + y * y + z * z).squareRoot()
        guard n.isFinite, n > 1e-6 else { return nil }
        // Up is -gravity; the optical axis is (0, 0, -1): its elevation is asin(axis . up) = asin(z / n).
        cameraPitchDeg = asin(max(-1, min(1, z / n))) * 180 / .pi
        rollDeg = atan2(x, -y) * 180 / .pi
    }

    /// Direct values, degrees.
    public init(cameraPitchDeg: Double, rollDeg: Double) { self.cameraPitchDeg = cameraPitchDeg; self.rollDeg = rollDeg }
}

/// The first-run phone-orientation training (after Clew's): while the traveler holds the phone, say how to
/// correct its pitch and roll until it is held right for `holdSeconds`. Feedback for a condition is spoken
/// once it has lasted `settleSeconds` (no chatter while the hand moves) and repeated every
/// `repeatSeconds` while it lasts. Events in (attitude samples), texts out.
public struct OrientationCoach: Sendable {
    /// What is wrong with the pose, worst first.
    public enum Feedback: String, Sendable, Equatable {
        /// Lying flat (|pitch| above 60 deg).
        case flat
        /// Camera looks down.
        case pitchDown
        /// Camera looks up.
        case pitchUp
        /// Top leans left.
        case rollLeft
        /// Top leans right.
        case rollRight
        /// Within tolerance.
        case good

        /// Its phrase-book key.
        public var key: PhoneKey {
            switch self {
            case .flat: return .coachFlat
            case .pitchDown: return .coachPitchDown
            case .pitchUp: return .coachPitchUp
            case .rollLeft: return .coachRollLeft
            case .rollRight: return .coachRollRight
            case .good: return .coachGood
            }
        }
    }

    /// Target and tolerances (from the carry mode).
    public var profile: CarryProfile
    /// Seconds a condition must last before it is spoken.
    public var settleSeconds = 0.6
    /// Repeat interval of the same feedback, seconds.
    public var repeatSeconds = 4.0
    /// Seconds held right that complete the training.
    public var holdSeconds = 3.0
    /// True once the training is complete.
    public private(set) var completed = false

    private let phrases: PhonePhrases
    private var condition: (feedback: Feedback, since: Double)?
    private var lastSpoken: (feedback: Feedback, t: Double)?

    /// Creates the coach for a carry mode.
    public init(profile: CarryProfile, phrases: PhonePhrases) { self.profile = profile; self.phrases = phrases }

    /// The feedback for an attitude.
    public func feedback(for a: PhoneAttitude) -> Feedback {
        if abs(a.cameraPitchDeg) > 60 { return .flat }
        let dp = a.cameraPitchDeg - profile.targetPitchDeg
        if dp < -profile.pitchToleranceDeg { return .pitchDown }
        if dp > profile.pitchToleranceDeg { return .pitchUp }
        if a.rollDeg < -profile.rollToleranceDeg { return .rollLeft }
        if a.rollDeg > profile.rollToleranceDeg { return .rollRight }
        return .good
    }

    /// One attitude sample at `t` seconds; returns the text to speak now, if any (the completion phrase once,
    /// then nothing).
    public mutating func update(_ a: PhoneAttitude, t: Double) -> String? {
        guard !completed else { return nil }
        let f = feedback(for: a)
        if condition?.feedback != f { condition = (f, t) }
        guard let c = condition else { return nil }
        if f == .good, t - c.since >= holdSeconds - 1e-9 {
            completed = true
            return phrases.text(.coachDone)
        }
        guard t - c.since >= settleSeconds - 1e-9 else { return nil }
        if let last = lastSpoken, last.feedback == f, t - last.t < repeatSeconds - 1e-9 { return nil }
        // "Good" is said once per stretch of holding right, not repeated.
        if f == .good, lastSpoken?.feedback == .good { return nil }
        lastSpoken = (f, t)
        return phrases.text(f.key)
    }
}

/// The first-run onboarding steps, in order: the safety notice (must be acknowledged), the carry choice,
/// how to hold (or wear) the phone, then the orientation practice (`OrientationCoach`).
public enum OnboardingStep: String, Sendable, CaseIterable {
    /// Safety notice.
    case safety
    /// Hand or lanyard.
    case carry
    /// How to hold the phone.
    case hold
    /// Practice with spoken pitch / roll feedback.
    case practice

    /// The step after this one, nil after the practice (onboarding complete).
    public var next: OnboardingStep? {
        let all = Self.allCases
        guard let i = all.firstIndex(of: self), i + 1 < all.count else { return nil }
        return all[i + 1]
    }

    /// The text spoken and shown for the step (nil for the carry choice, which is two buttons).
    public func text(_ phrases: PhonePhrases, carry: PhoneCarry) -> String? {
        switch self {
        case .safety: return phrases.text(.onboardingSafety)
        case .carry: return nil
        case .hold, .practice: return phrases.text(carry == .lanyard ? .holdLanyard : .holdHandheld)
        }
    }
}
