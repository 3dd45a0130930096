import Foundation
import SessionFormat

/// Spoken prompts when ARKit tracking degrades ("Slow down", "Point the camera ahead", "The camera is
/// covered"), rate-limited so they never become chatter: the same prompt at most every
/// `repeatIntervalSeconds`, any prompt at most every `minimumSpacingSeconds`, and only after the condition
/// has lasted `persistenceSeconds` (brief glitches stay silent).
public struct TrackingPromptPolicy: Sendable {
    /// How long a condition must last before it is spoken, seconds.
    public var persistenceSeconds = 1.5
    /// Minimum time between two repeats of the same prompt, seconds.
    public var repeatIntervalSeconds = 12.0
    /// Minimum time between any two prompts, seconds.
    public var minimumSpacingSeconds = 5.0

    private var conditionSince: (prompt: String, t: Double)?
    private var lastSpoken: [String: Double] = [:]
    private var lastAnyT = -Double.infinity

    /// Creates the policy with default timings.
    public init() {}

    /// The prompt for a tracking state, or nil when tracking is fine. `meanLuma` (0...255) of the frame
    /// distinguishes a covered camera from a texture-less view.
    public static func prompt(for state: TrackingState, reason: TrackingReason?, meanLuma: Double?) -> String? {
        if let luma = meanLuma, luma < 8 { return "The camera is covered" }
        switch (state, reason) {
        case (.normal, _): return nil
        case (.limited, .excessiveMotion?): return "Slow down"
        case (.limited, .insufficientFeatures?): return "Point the camera ahead"
        case (.limited, .initializing?), (.limited, .relocalizing?): return nil
        case (.limited, nil): return "Point the camera ahead"
        case (.notAvailable, _): return "Tracking lost. Point the camera ahead"
        }
    }

    /// Feeds one frame's state; returns the text to speak now, if any.
    public mutating func update(t: Double, state: TrackingState, reason: TrackingReason?, meanLuma: Double? = nil) -> String? {
        guard let prompt = Self.prompt(for: state, reason: reason, meanLuma: meanLuma) else {
            conditionSince = nil
            return nil
        }
        if conditionSince?.prompt != prompt { conditionSince = (prompt, t) }
        guard let since = conditionSince, t - since.t >= persistenceSeconds else { return nil }
        guard t - lastAnyT >= minimumSpacingSeconds, t - (lastSpoken[prompt] ?? -.infinity) >= repeatIntervalSeconds else { return nil }
        lastSpoken[prompt] = t
        lastAnyT = t
        return prompt
    }
}
