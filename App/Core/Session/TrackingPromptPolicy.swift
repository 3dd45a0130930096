import Foundation
import Navigation
import SessionFormat

/// A tracking condition worth telling the traveler about; its words are in the phrase book.
public enum TrackingPrompt: String, Sendable, Equatable, CaseIterable {
    /// The frame is nearly black: a finger or a pocket over the lens.
    case covered
    /// ARKit reports excessive motion.
    case slowDown
    /// Too few features (a blank wall, the floor) or limited for an unknown reason.
    case pointAhead
    /// Tracking is not available at all.
    case lost

    /// Phrase-book key (`Navigation/Locales/<language>.json`).
    public var phraseKey: String { "tracking.\(rawValue)" }
}

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

    /// The words of the prompts.
    public let phrases: PhraseBook
    private var conditionSince: (prompt: TrackingPrompt, t: Double)?
    private var lastSpoken: [TrackingPrompt: Double] = [:]
    private var lastAnyT = -Double.infinity

    /// Creates the policy with default timings, speaking from `phrases` (default English).
    public init(phrases: PhraseBook = .english) { self.phrases = phrases }

    /// The condition of a tracking state, or nil when tracking is fine. `meanLuma` (0...255) of the frame
    /// distinguishes a covered camera from a texture-less view.
    public static func condition(for state: TrackingState, reason: TrackingReason?, meanLuma: Double?) -> TrackingPrompt? {
        if let luma = meanLuma, luma < 8 { return .covered }
        switch (state, reason) {
        case (.normal, _): return nil
        case (.limited, .excessiveMotion?): return .slowDown
        case (.limited, .insufficientFeatures?): return .pointAhead
        case (.limited, .initializing?), (.limited, .relocalizing?): return nil
        case (.limited, nil): return .pointAhead
        case (.notAvailable, _): return .lost
        }
    }

    /// The prompt's words for a tracking state in `phrases` (default English), or nil when tracking is fine.
    public static func prompt(for state: TrackingState, reason: TrackingReason?, meanLuma: Double?,
                              phrases: PhraseBook = .english) -> String? {
        condition(for: state, reason: reason, meanLuma: meanLuma).map { phrases.phrase($0.phraseKey) }
    }

    /// Feeds one frame's state; returns the text to speak now, if any.
    public mutating func update(t: Double, state: TrackingState, reason: TrackingReason?, meanLuma: Double? = nil) -> String? {
        guard let prompt = Self.condition(for: state, reason: reason, meanLuma: meanLuma) else {
            conditionSince = nil
            return nil
        }
        if conditionSince?.prompt != prompt { conditionSince = (prompt, t) }
        guard let since = conditionSince, t - since.t >= persistenceSeconds else { return nil }
        guard t - lastAnyT >= minimumSpacingSeconds, t - (lastSpoken[prompt] ?? -.infinity) >= repeatIntervalSeconds else { return nil }
        lastSpoken[prompt] = t
        lastAnyT = t
        return phrases.phrase(prompt.phraseKey)
    }
}
