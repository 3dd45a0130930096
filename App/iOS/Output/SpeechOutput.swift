#if canImport(AVFoundation) && canImport(UIKit) && os(iOS)
import AVFoundation
import UIKit
import WayfinderCore

/// Renders the shared `SpeechQueue` (one utterance at a time, retry of a VoiceOver announcement cut off,
/// audio session released when the queue empties, interruptions and route changes): VoiceOver
/// announcements while VoiceOver runs, AVSpeechSynthesizer otherwise. This class only forwards platform
/// callbacks as `SpeechEvent`s and performs the queue's `SpeechCommand`s. Main actor.
@MainActor
final class SpeechOutput: NSObject, AVSpeechSynthesizerDelegate {
    private let synthesizer = AVSpeechSynthesizer()
    private var queue: SpeechQueue
    private var observers: [NSObjectProtocol] = []
    private var idByUtterance: [ObjectIdentifier: Int] = [:]
    private var tickTimer: Timer?
    /// Called when the queue starts or stops speaking (for Magic Tap's "stop if speaking").
    var isSpeaking: Bool { queue.isSpeaking }
    /// Guidance speech paused by the traveler.
    var isPaused: Bool { queue.paused }

    init(outputLostText: String) {
        queue = SpeechQueue(voiceOverRunning: UIAccessibility.isVoiceOverRunning, outputLostText: outputLostText)
        super.init()
        synthesizer.delegate = self
        try? AVAudioSession.sharedInstance().setCategory(.playback, mode: .voicePrompt,
                                                         options: [.duckOthers, .interruptSpokenAudioAndMixWithOthers])
        let center = NotificationCenter.default
        // A completion that never comes (VoiceOver does not always report a superseded announcement) must
        // not silence the queue: SpeechQueue gives it up on a tick.
        tickTimer = Timer.scheduledTimer(withTimeInterval: 1, repeats: true) { [weak self] _ in
            MainActor.assumeIsolated { self?.handle(.tick(t: CACurrentMediaTime())) }
        }
        observers.append(center.addObserver(forName: UIAccessibility.announcementDidFinishNotification, object: nil, queue: .main) { [weak self] note in
            let text = note.userInfo?[UIAccessibility.announcementStringValueUserInfoKey] as? String ?? ""
            let success = (note.userInfo?[UIAccessibility.announcementWasSuccessfulUserInfoKey] as? NSNumber)?.boolValue ?? true
            MainActor.assumeIsolated { self?.handle(.announcementFinished(text: text, success: success)) }
        })
        observers.append(center.addObserver(forName: UIAccessibility.voiceOverStatusDidChangeNotification, object: nil, queue: .main) { [weak self] _ in
            MainActor.assumeIsolated { self?.handle(.voiceOver(running: UIAccessibility.isVoiceOverRunning)) }
        })
        observers.append(center.addObserver(forName: AVAudioSession.interruptionNotification, object: nil, queue: .main) { [weak self] note in
            let raw = (note.userInfo?[AVAudioSessionInterruptionTypeKey] as? NSNumber)?.uintValue ?? 0
            let options = (note.userInfo?[AVAudioSessionInterruptionOptionKey] as? NSNumber)?.uintValue ?? 0
            let began = AVAudioSession.InterruptionType(rawValue: raw) == .began
            let resume = AVAudioSession.InterruptionOptions(rawValue: options).contains(.shouldResume)
            MainActor.assumeIsolated {
                let t = CACurrentMediaTime()
                self?.handle(began ? .interruptionBegan(t: t) : .interruptionEnded(shouldResume: resume, t: t))
            }
        })
        observers.append(center.addObserver(forName: AVAudioSession.routeChangeNotification, object: nil, queue: .main) { [weak self] note in
            let raw = (note.userInfo?[AVAudioSessionRouteChangeReasonKey] as? NSNumber)?.uintValue ?? 0
            guard AVAudioSession.RouteChangeReason(rawValue: raw) == .oldDeviceUnavailable else { return }
            MainActor.assumeIsolated { self?.handle(.outputDeviceLost(t: CACurrentMediaTime())) }
        })
    }

    /// Applies the rate and voice settings.
    func apply(settings: AppSettings) {
        queue.synthesizerRate = SpeechRate.synthesizerRate(multiplier: settings.speechRateMultiplier)
        queue.voiceIdentifier = settings.voiceIdentifier
    }

    /// Says `text`; `requested` for answers to "Where am I" / "Repeat" (spoken even while paused).
    func speak(_ text: String, interrupt: Bool, requested: Bool = false) {
        handle(.say(text, interrupt: interrupt, requested: requested, t: CACurrentMediaTime()))
    }

    /// Stops what is being said (Magic Tap while speaking).
    func silence() { handle(.silence) }
    /// Pauses guidance speech (vibrations continue).
    func pause() { handle(.pause(t: CACurrentMediaTime())) }
    /// Resumes guidance speech.
    func resume() { handle(.resume(t: CACurrentMediaTime())) }

    private func handle(_ event: SpeechEvent) {
        for command in queue.handle(event) { perform(command) }
    }

    private func perform(_ command: SpeechCommand) {
        let audio = AVAudioSession.sharedInstance()
        switch command {
        case .activateAudioSession: try? audio.setActive(true)
        case .deactivateAudioSession: try? audio.setActive(false, options: .notifyOthersOnDeactivation)
        case .announce(_, let text):
            // Not queued by VoiceOver (SpeechQueue orders them); a later announcement cuts this one.
            let attributed = NSAttributedString(string: text, attributes: [.accessibilitySpeechQueueAnnouncement: false])
            UIAccessibility.post(notification: .announcement, argument: attributed)
        case .synthesize(let id, let text, let rate, let voiceIdentifier):
            let utterance = AVSpeechUtterance(string: text)
            utterance.rate = Float(rate)
            if let voiceIdentifier, let voice = AVSpeechSynthesisVoice(identifier: voiceIdentifier) { utterance.voice = voice }
            idByUtterance[ObjectIdentifier(utterance)] = id
            synthesizer.speak(utterance)
        case .stopSpeaking: synthesizer.stopSpeaking(at: .immediate)
        }
    }

    nonisolated func speechSynthesizer(_ synthesizer: AVSpeechSynthesizer, didFinish utterance: AVSpeechUtterance) {
        let key = ObjectIdentifier(utterance)
        DispatchQueue.main.async { [weak self] in
            MainActor.assumeIsolated {
                guard let self, let id = self.idByUtterance.removeValue(forKey: key) else { return }
                self.handle(.synthesizerFinished(id: id))
            }
        }
    }

    nonisolated func speechSynthesizer(_ synthesizer: AVSpeechSynthesizer, didCancel utterance: AVSpeechUtterance) {
        let key = ObjectIdentifier(utterance)
        DispatchQueue.main.async { [weak self] in
            MainActor.assumeIsolated {
                guard let self, let id = self.idByUtterance.removeValue(forKey: key) else { return }
                self.handle(.synthesizerCancelled(id: id))
            }
        }
    }
}
#endif
