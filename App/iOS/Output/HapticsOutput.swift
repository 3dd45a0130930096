#if canImport(CoreHaptics) && os(iOS)
import CoreHaptics

/// Plays the navigator's haptic patterns with Core Haptics: a strong double pulse for "wrong way", a short
/// tick for turn cues, a long soft pulse for arrival. Pattern names come from Navigation's HapticPattern.
final class HapticsOutput {
    private var engine: CHHapticEngine?

    init() {
        guard CHHapticEngine.capabilitiesForHardware().supportsHaptics else { return }
        engine = try? CHHapticEngine()
        engine?.resetHandler = { [weak self] in try? self?.engine?.start() }
        try? engine?.start()
    }

    func play(_ pattern: String) {
        guard let engine else { return }
        let events: [CHHapticEvent]
        func tap(_ t: TimeInterval, _ intensity: Float) -> CHHapticEvent {
            CHHapticEvent(eventType: .hapticTransient, parameters: [CHHapticEventParameter(parameterID: .hapticIntensity, value: intensity)], relativeTime: t)
        }
        switch pattern {
        case let p where p.lowercased().contains("wrong"): events = [tap(0, 1), tap(0.15, 1), tap(0.45, 1), tap(0.6, 1)]
        case let p where p.lowercased().contains("arriv"):
            events = [CHHapticEvent(eventType: .hapticContinuous, parameters: [CHHapticEventParameter(parameterID: .hapticIntensity, value: 0.6)], relativeTime: 0, duration: 0.6)]
        default: events = [tap(0, 0.7)]
        }
        if let p = try? CHHapticPattern(events: events, parameters: []), let player = try? engine.makePlayer(with: p) {
            try? player.start(atTime: CHHapticTimeImmediate)
        }
    }
}
#endif
