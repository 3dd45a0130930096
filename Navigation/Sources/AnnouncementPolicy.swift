// Decides what is spoken and when. Guidance logic submits candidate announcements; the policy orders
// them by priority, keeps speech from overlapping, drops stale and repeated messages, and spaces out
// informational ones. Haptics are a separate channel and pass straight through.
import Foundation

/// Importance of a spoken message, lowest first.
public enum AnnouncementPriority: Int, Sendable, Comparable, CaseIterable {
    /// Progress and context ("Continue 15 meters", "Start walking", route starts). Waits for silence and
    /// keeps `informationSpacingSeconds` from the previous informational message.
    case information = 0
    /// Early alerts ("In 8 meters, turn left"). Waits for silence; never interrupts.
    case alert = 1
    /// Cues at the maneuver ("Turn left now") and arrival. Interrupts anything but safety.
    case cue = 2
    /// Corrections ("Wrong way, turn around", "Off route, recalculating"). Interrupts everything.
    case safety = 3

    /// Orders by importance.
    public static func < (a: Self, b: Self) -> Bool { a.rawValue < b.rawValue }
}

/// A vibration pattern, rendered by the platform layer.
public enum HapticPattern: String, Sendable, Equatable, CaseIterable {
    /// Heading against the route for a sustained moment (paper section 4: path deviation is signalled by
    /// haptic feedback).
    case wrongWay
    /// More than the off-route distance from the route.
    case offRoute
    /// Emitted with a turn cue, so a cue heard over noise is also felt.
    case turnCue
    /// At the destination.
    case arrived
}

/// What the platform layer renders: speech or a vibration.
public enum GuidanceEvent: Sendable, Equatable {
    /// Speak `text`. When `interrupt` is true, stop any current speech first (safety, cues and answers to
    /// requests); otherwise the text is only sent when the policy expects silence.
    case speak(text: String, priority: AnnouncementPriority, interrupt: Bool)
    /// Play a haptic pattern.
    case haptic(HapticPattern)
}

/// A guidance event with the time it is issued.
public struct TimedGuidanceEvent: Sendable, Equatable {
    /// Issue time, seconds, on the clock of `NavigationInput.t`.
    public var t: Double
    /// The event.
    public var event: GuidanceEvent
    /// Creates a timed event.
    public init(t: Double, event: GuidanceEvent) { self.t = t; self.event = event }

    /// The spoken text, when this is a speech event.
    public var spokenText: String? {
        if case .speak(let text, _, _) = event { return text }
        return nil
    }
}

extension TimedGuidanceEvent: CustomStringConvertible {
    /// One line for logs and the command line, e.g. `12.30 s  speak cue!  Turn left now.` (`!` =
    /// interrupt) or `12.30 s  haptic     turnCue`.
    public var description: String {
        let time = String(format: "%.2f s", t)
        switch event {
        case .speak(let text, let priority, let interrupt):
            let tag = "\(priority)" + (interrupt ? "!" : "")
            return "\(time)  speak \(tag.padding(toLength: 12, withPad: " ", startingAt: 0)) \(text)"
        case .haptic(let pattern):
            return "\(time)  haptic \(pattern.rawValue)"
        }
    }
}

/// Tunables of `AnnouncementPolicy`, seconds unless named otherwise.
public struct AnnouncementPolicyConfig: Sendable, Equatable {
    /// How long an utterance lasts (syllables and pauses at a speaking rate, calibrated on espeak-ng;
    /// `SpeechTimingModel`). The navigator sets its language to the phrase book's.
    public var speechTiming = SpeechTimingModel.espeakEnglish
    /// Shortest estimated utterance, seconds.
    public var minimumUtteranceSeconds = 0.5
    /// A cue not spoken within this time after it was submitted is dropped: it would be said after the
    /// control point is passed. At 1.2 m/s, 1.5 s is 1.8 m.
    public var cueMaxAgeSeconds = 1.5
    /// Alerts older than this are dropped (the distance in them is out of date).
    public var alertMaxAgeSeconds = 4.0
    /// Safety messages older than this are dropped.
    public var safetyMaxAgeSeconds = 3.0
    /// Informational messages older than this are dropped.
    public var informationMaxAgeSeconds = 8.0
    /// The same text is not spoken again within this time unless requested.
    public var repeatSuppressionSeconds = 10.0
    /// Silence required after an informational message before the next informational one starts.
    public var informationSpacingSeconds = 1.5
    /// Creates the defaults above.
    public init() {}
}

/// The announcement policy. Feed it with `submit` / `submitHaptic`, then call `flush(t:)` on every tick;
/// it returns what to render now. Deterministic: time only comes from the arguments.
public final class AnnouncementPolicy {
    struct Pending {
        var text: String
        var priority: AnnouncementPriority
        var submittedAt: Double
        var requested: Bool
        var sequence: Int
        var key: String
    }

    /// Tunables.
    public let config: AnnouncementPolicyConfig
    private var pending: [Pending] = []
    private var haptics: [HapticPattern] = []
    private var sequence = 0
    /// Estimated end of the current utterance, seconds.
    public private(set) var speakingUntil = -Double.infinity
    private var speakingPriority = AnnouncementPriority.information
    private var lastInformationEnd = -Double.infinity
    /// The next utterance must stop what is playing (`supersede` ended it early).
    private var interruptNext = false
    private var lastSpoken: [String: Double] = [:]
    /// True when the last utterance emitted answered a request ("Where am I", "Repeat").
    public private(set) var lastUtteranceWasRequested = false

    /// Creates a policy.
    public init(config: AnnouncementPolicyConfig = AnnouncementPolicyConfig()) { self.config = config }

    /// Estimated speaking time of `text`: `config.speechTiming`, at least `minimumUtteranceSeconds`.
    public func estimatedDurationSeconds(_ text: String) -> Double {
        max(config.minimumUtteranceSeconds, config.speechTiming.durationSeconds(text))
    }

    /// The earliest time at or after `t` at which a message of `priority` could start: now when the
    /// channel is silent or the message may interrupt what is playing (see `flush`), else when the current
    /// utterance is estimated to end.
    public func earliestStart(priority: AnnouncementPriority, t: Double) -> Double {
        guard t < speakingUntil else { return t }
        if priority >= .cue && priority > speakingPriority { return t }
        return speakingUntil
    }

    /// Queues a message. `requested` marks an answer to the traveler ("Where am I", "Repeat"): it
    /// interrupts like a cue and is exempt from repeat suppression and spacing. `repeatKey` identifies the
    /// message for repeat suppression (default: its text); give distinct keys to equal texts that say
    /// different things, e.g. two different doors' "Go through the door now."
    public func submit(_ text: String, priority: AnnouncementPriority, t: Double, requested: Bool = false,
                       repeatKey: String? = nil) {
        pending.append(Pending(text: text, priority: priority, submittedAt: t, requested: requested, sequence: sequence,
                               key: repeatKey ?? text))
        sequence += 1
    }

    /// Queues a haptic pattern; it is emitted at the next `flush`, whatever the speech channel is doing.
    public func submitHaptic(_ pattern: HapticPattern) { haptics.append(pattern) }

    /// Drops every queued message below `priority` except requests (e.g. when a new route replaces the
    /// old one's alerts).
    public func discardPending(below priority: AnnouncementPriority) {
        pending.removeAll { $0.priority < priority && !$0.requested }
    }

    /// Ends an utterance of at most `priority` (not an answer to a request) that is still playing at `t`, and
    /// drops the queued messages of at most that priority: what they say no longer holds (the "not sure where you
    /// are" advice once the traveler is localized). The next utterance is sent with `interrupt: true`, so the
    /// platform stops the old one. Nothing changes when the channel is silent or holds something more important.
    public func supersede(upTo priority: AnnouncementPriority, t: Double) {
        pending.removeAll { $0.priority <= priority && !$0.requested }
        guard t < speakingUntil, speakingPriority <= priority, !lastUtteranceWasRequested else { return }
        speakingUntil = t
        interruptNext = true
        lastInformationEnd = min(lastInformationEnd, t)
    }

    /// Drops queued messages whose repeat key starts with `prefix` (e.g. an alert made moot by its cue).
    public func discardPending(repeatKeyPrefix prefix: String) {
        pending.removeAll { $0.key.hasPrefix(prefix) }
    }

    private func maxAge(_ p: Pending) -> Double {
        switch p.priority {
        case .safety: return config.safetyMaxAgeSeconds
        case .cue: return config.cueMaxAgeSeconds
        case .alert: return config.alertMaxAgeSeconds
        case .information: return config.informationMaxAgeSeconds
        }
    }

    /// Priority used when deciding whether a message may cut off the current one: answers to requests
    /// count as cues.
    private func interruptRank(_ p: Pending) -> AnnouncementPriority { p.requested ? max(p.priority, .cue) : p.priority }

    /// What to render at time `t`: all queued haptics, then at most one utterance. Rules, in order:
    /// 1. stale messages are dropped (cue > 1.5 s, alert > 4 s, safety > 3 s, information > 8 s old);
    /// 2. the most important message goes first (safety > cue > alert > information; requests rank as
    ///    cues; oldest first within a rank);
    /// 3. a message whose repeat key (default: text) was spoken within the last 10 s is dropped unless
    ///    requested;
    /// 4. while speech is estimated to be playing, only a message of cue rank or above whose rank is
    ///    higher than the current one's (or equal, for a request) is spoken (with `interrupt: true`); the
    ///    others wait;
    /// 5. an informational message also waits for `informationSpacingSeconds` of silence after the
    ///    previous informational one.
    public func flush(t: Double) -> [TimedGuidanceEvent] {
        var out = haptics.map { TimedGuidanceEvent(t: t, event: .haptic($0)) }
        haptics.removeAll()
        pending.removeAll { t - $0.submittedAt > maxAge($0) }
        if lastSpoken.count > 64 { lastSpoken = lastSpoken.filter { t - $0.value < config.repeatSuppressionSeconds } }
        while !pending.isEmpty {
            var best = 0
            for i in pending.indices.dropFirst() {
                let a = pending[i], b = pending[best]
                let ka = (interruptRank(a).rawValue, a.priority.rawValue, -a.sequence)
                let kb = (interruptRank(b).rawValue, b.priority.rawValue, -b.sequence)
                if ka > kb { best = i }
            }
            let c = pending[best]
            if !c.requested, let last = lastSpoken[c.key], t - last < config.repeatSuppressionSeconds {
                pending.remove(at: best)
                continue
            }
            let rank = interruptRank(c)
            let mayInterrupt = rank >= .cue
            if t < speakingUntil {
                // Only a more important message cuts one off; an equal one waits (two cues in a row are
                // both heard in full, the second dropped if it would come 1.5 s late).
                guard mayInterrupt && (rank > speakingPriority || (c.requested && rank >= speakingPriority)) else { break }
            } else if c.priority == .information && !c.requested
                        && t < lastInformationEnd + config.informationSpacingSeconds {
                break
            }
            pending.remove(at: best)
            let end = t + estimatedDurationSeconds(c.text)
            out.append(TimedGuidanceEvent(t: t, event: .speak(text: c.text, priority: c.priority,
                                                              interrupt: mayInterrupt || interruptNext)))
            interruptNext = false
            speakingUntil = end
            speakingPriority = rank
            lastUtteranceWasRequested = c.requested
            lastSpoken[c.key] = t
            if c.priority == .information { lastInformationEnd = end }
            break  // one utterance per tick: the next waits for it (or interrupts it on a later tick)
        }
        return out
    }
}
