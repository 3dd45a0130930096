#if canImport(AVFoundation) && canImport(UIKit) && os(iOS)
import AVFoundation
import UIKit

/// Speaks guidance through VoiceOver announcements when VoiceOver is running, through the speech
/// synthesizer otherwise. The audio session ducks other audio while speaking. What to say and when is
/// decided upstream (Navigation's AnnouncementPolicy); this only renders.
final class SpeechOutput {
    private let synthesizer = AVSpeechSynthesizer()

    init() {
        try? AVAudioSession.sharedInstance().setCategory(.playback, mode: .voicePrompt,
                                                         options: [.duckOthers, .interruptSpokenAudioAndMixWithOthers])
    }

    func speak(_ text: String, interrupt: Bool) {
        if UIAccessibility.isVoiceOverRunning {
            let attributed = NSAttributedString(string: text, attributes: [.accessibilitySpeechQueueAnnouncement: !interrupt])
            UIAccessibility.post(notification: .announcement, argument: attributed)
            return
        }
        if interrupt { synthesizer.stopSpeaking(at: .immediate) }
        try? AVAudioSession.sharedInstance().setActive(true)
        synthesizer.speak(AVSpeechUtterance(string: text))
    }
}
#endif
