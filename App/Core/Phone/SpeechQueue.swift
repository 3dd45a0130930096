import Foundation

/// Events of the speech channel, from the shell's requests and the platform's callbacks.
public enum SpeechEvent: Sendable, Equatable {
    /// Say `text` at `t` (seconds, any monotonic clock). `interrupt` cuts off what is being said and drops
    /// what waits; `requested` marks an answer to the traveler ("Where am I", "Repeat"), spoken even while
    /// guidance speech is paused.
    case say(String, interrupt: Bool, requested: Bool = false, t: Double)
    /// VoiceOver's `announcementDidFinishNotification`: the announced string and its success flag (false =
    /// VoiceOver cut it off, e.g. by the traveler's own gesture).
    case announcementFinished(text: String, success: Bool)
    /// `speechSynthesizer(_:didFinish:)` for the utterance with this id.
    case synthesizerFinished(id: Int)
    /// `speechSynthesizer(_:didCancel:)` for the utterance with this id.
    case synthesizerCancelled(id: Int)
    /// VoiceOver was switched on or off (`voiceOverStatusDidChangeNotification`).
    case voiceOver(running: Bool)
    /// AVAudioSession interruption began (a call, Siri, an alarm) at `t`.
    case interruptionBegan(t: Double)
    /// The interruption ended at `t`; `shouldResume` is the system's `.shouldResume` option.
    case interruptionEnded(shouldResume: Bool, t: Double)
    /// `routeChangeNotification` with reason `.oldDeviceUnavailable` (headphones unplugged, Bluetooth gone) at `t`.
    case outputDeviceLost(t: Double)
    /// The traveler paused guidance speech (Magic Tap / headphone pause): what is said stops, guidance
    /// speech is dropped until `resume`, answers to requests still speak.
    case pause(t: Double)
    /// The traveler resumed guidance speech.
    case resume(t: Double)
    /// Stop what is being said and drop what waits (Magic Tap while speaking).
    case silence
    /// A clock tick at `t` (about once a second): an utterance whose completion never came is given up
    /// after `maximumSeconds(for:)`, so a lost notification cannot silence the queue.
    case tick(t: Double)
}

/// What the speech adapter must do.
public enum SpeechCommand: Sendable, Equatable {
    /// AVAudioSession.setActive(true) (category playback, mode voicePrompt, ducking others).
    case activateAudioSession
    /// AVAudioSession.setActive(false, options: .notifyOthersOnDeactivation): other audio comes back up.
    case deactivateAudioSession
    /// Post a VoiceOver announcement of `text` (not queued by VoiceOver: this queue orders them).
    case announce(id: Int, text: String)
    /// Speak `text` with AVSpeechSynthesizer at `rate` (AVSpeechUtterance rate, 0...1), voice id or nil.
    case synthesize(id: Int, text: String, rate: Double, voiceIdentifier: String?)
    /// Stop the synthesizer at once (`stopSpeaking(at: .immediate)`); VoiceOver announcements are cut by the
    /// next announcement instead.
    case stopSpeaking
}

/// The speech channel as a queue with completion events: one utterance at a time, the next only when the
/// platform reports the current one finished; an interrupting utterance cuts off the current one and drops
/// the waiting ones; a VoiceOver announcement reported cut off (success false) is retried once; the audio
/// session is active only while something is to be said and is deactivated with
/// notifyOthersOnDeactivation when the queue empties (other audio stops being ducked); an audio
/// interruption stops speech and, when the system says to resume, repeats the cut utterance if it is still
/// fresh; losing the output device (headphones unplugged) says so from the speaker and repeats the cut
/// utterance. Events in, commands out; the adapter renders them.
public struct SpeechQueue: Sendable {
    /// One utterance.
    public struct Utterance: Sendable, Equatable {
        /// Identifier used in commands and synthesizer events.
        public var id: Int
        /// Text.
        public var text: String
        /// Answer to a request.
        public var requested: Bool
        /// When it was asked for, seconds.
        public var t: Double
        /// Times it was handed to the platform.
        public var attempts: Int
        /// When it was last handed to the platform, seconds (nil while waiting).
        public var startedT: Double? = nil
    }

    /// True while VoiceOver is running (announcements instead of the synthesizer).
    public private(set) var voiceOverRunning: Bool
    /// The utterance being spoken.
    public private(set) var current: Utterance?
    /// Waiting utterances, oldest first.
    public private(set) var waiting: [Utterance] = []
    /// Guidance speech paused by the traveler.
    public private(set) var paused = false
    /// The audio session is active (as far as this queue asked).
    public private(set) var audioActive = false
    /// An audio interruption is in progress.
    public private(set) var interrupted = false
    /// Synthesizer rate (AVSpeechUtterance scale, 0...1).
    public var synthesizerRate: Double
    /// Synthesizer voice identifier (nil = the system's for the language).
    public var voiceIdentifier: String?
    /// Times a cut-off VoiceOver announcement is retried.
    public var maxRetries = 1
    /// A cut utterance older than this is not repeated after an interruption, seconds (guidance moved on).
    public var repeatMaxAgeSeconds = 10.0
    /// At most this many waiting utterances; the oldest are dropped beyond it.
    public var maxWaiting = 4
    /// Text spoken when the output device is lost (phone.audio.headphonesGone).
    public var outputLostText: String

    private var nextId = 1
    private var cutByInterruption: Utterance?
    private var clockT = -Double.infinity

    /// Longest an utterance may take before its completion is presumed lost, seconds: 3 s plus 1.5 words a
    /// second (the slowest rate offered speaks about 1.7 words a second).
    public static func maximumSeconds(for text: String) -> Double {
        3 + Double(text.split(whereSeparator: { $0 == " " }).count) / 1.5
    }

    /// Creates an idle queue.
    public init(voiceOverRunning: Bool, synthesizerRate: Double = SpeechRate.defaultSynthesizerRate,
                voiceIdentifier: String? = nil, outputLostText: String) {
        self.voiceOverRunning = voiceOverRunning
        self.synthesizerRate = synthesizerRate
        self.voiceIdentifier = voiceIdentifier
        self.outputLostText = outputLostText
    }

    /// True while something is being said or waits.
    public var isSpeaking: Bool { current != nil || !waiting.isEmpty }

    /// Handles one event; returns the commands in order.
    public mutating func handle(_ event: SpeechEvent) -> [SpeechCommand] {
        switch event {
        case .say(let text, let interrupt, let requested, let t):
            clockT = max(clockT, t)
            guard !text.isEmpty, !paused || requested else { return [] }
            let u = Utterance(id: nextId, text: text, requested: requested, t: t, attempts: 0)
            nextId += 1
            if interrupt {
                var out: [SpeechCommand] = current != nil && !voiceOverRunning ? [.stopSpeaking] : []
                current = nil
                waiting = [u]
                out += startNextIfIdle()
                return out
            }
            waiting.append(u)
            if waiting.count > maxWaiting { waiting.removeFirst(waiting.count - maxWaiting) }
            return startNextIfIdle()
        case .announcementFinished(let text, let success):
            guard voiceOverRunning, let c = current, c.text == text else { return [] }
            current = nil
            if !success, c.attempts <= maxRetries, !interrupted {
                // Cut off (the traveler touched the screen, VoiceOver spoke something): say it once more.
                waiting.insert(c, at: 0)
            }
            return startNextIfIdle() + deactivateIfDone()
        case .synthesizerFinished(let id):
            guard current?.id == id else { return [] }
            current = nil
            return startNextIfIdle() + deactivateIfDone()
        case .synthesizerCancelled(let id):
            // Cancelled by this queue (interrupt, silence, interruption): nothing more to do.
            guard current?.id == id else { return [] }
            current = nil
            return startNextIfIdle() + deactivateIfDone()
        case .voiceOver(let running):
            guard running != voiceOverRunning else { return [] }
            var out: [SpeechCommand] = current != nil && !voiceOverRunning ? [.stopSpeaking] : []
            voiceOverRunning = running
            if let c = current { waiting.insert(c, at: 0); current = nil }
            out += startNextIfIdle()
            return out
        case .interruptionBegan:
            interrupted = true
            audioActive = false   // the system deactivated the session
            cutByInterruption = current
            current = nil
            waiting.removeAll()
            return []
        case .interruptionEnded(let shouldResume, let t):
            clockT = max(clockT, t)
            guard interrupted else { return [] }
            interrupted = false
            let cut = cutByInterruption
            cutByInterruption = nil
            guard shouldResume, let c = cut, t - c.t <= repeatMaxAgeSeconds, !paused || c.requested else { return [] }
            waiting = [c]
            return startNextIfIdle()
        case .outputDeviceLost(let t):
            clockT = max(clockT, t)
            guard let c = current else { return [] }
            var out: [SpeechCommand] = voiceOverRunning ? [] : [.stopSpeaking]
            current = nil
            let notice = Utterance(id: nextId, text: outputLostText, requested: true, t: t, attempts: 0)
            nextId += 1
            waiting = [notice, Utterance(id: c.id, text: c.text, requested: c.requested, t: c.t, attempts: 0)] + waiting
            out += startNextIfIdle()
            return out
        case .pause:
            paused = true
            return silence()
        case .resume:
            paused = false
            return []
        case .silence:
            return silence()
        case .tick(let t):
            clockT = max(clockT, t)
            guard let c = current, let started = c.startedT, t - started > Self.maximumSeconds(for: c.text) else { return [] }
            current = nil
            return startNextIfIdle() + deactivateIfDone()
        }
    }

    private mutating func silence() -> [SpeechCommand] {
        let wasSpeaking = current != nil
        current = nil
        waiting.removeAll()
        var out: [SpeechCommand] = wasSpeaking && !voiceOverRunning ? [.stopSpeaking] : []
        out += deactivateIfDone()
        return out
    }

    private mutating func startNextIfIdle() -> [SpeechCommand] {
        guard current == nil, !interrupted, !waiting.isEmpty else { return [] }
        var u = waiting.removeFirst()
        u.attempts += 1
        u.startedT = clockT.isFinite ? clockT : u.t
        current = u
        var out: [SpeechCommand] = []
        if !audioActive { audioActive = true; out.append(.activateAudioSession) }
        out.append(voiceOverRunning ? .announce(id: u.id, text: u.text)
                                    : .synthesize(id: u.id, text: u.text, rate: synthesizerRate, voiceIdentifier: voiceIdentifier))
        return out
    }

    private mutating func deactivateIfDone() -> [SpeechCommand] {
        guard current == nil, waiting.isEmpty, audioActive else { return [] }
        audioActive = false
        return [.deactivateAudioSession]
    }
}
