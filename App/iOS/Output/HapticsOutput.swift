#if canImport(CoreHaptics) && os(iOS)
import CoreHaptics
import WayfinderCore

/// Plays the shared haptic vocabulary (`HapticCue.pattern`, defined and tested in App/Core/Phone): each
/// cue's pulses become CHHapticEvents one to one. No name matching here: the cue is resolved upstream from
/// the navigator's exact pattern name (`TurnCueResolver`).
@MainActor
final class HapticsOutput {
    private var engine: CHHapticEngine?
    /// Haptics on (settings).
    var enabled = true

    init() {
        guard CHHapticEngine.capabilitiesForHardware().supportsHaptics else { return }
        engine = try? CHHapticEngine()
        engine?.playsHapticsOnly = true
        engine?.resetHandler = { [weak self] in
            DispatchQueue.main.async { MainActor.assumeIsolated { try? self?.engine?.start() } }
        }
        try? engine?.start()
    }

    func play(_ cue: HapticCue) {
        guard enabled, let engine else { return }
        let events = cue.pattern.map { p -> CHHapticEvent in
            let parameters = [CHHapticEventParameter(parameterID: .hapticIntensity, value: Float(p.intensity)),
                              CHHapticEventParameter(parameterID: .hapticSharpness, value: Float(p.sharpness))]
            switch p.kind {
            case .tap: return CHHapticEvent(eventType: .hapticTransient, parameters: parameters, relativeTime: p.timeSeconds)
            case .buzz: return CHHapticEvent(eventType: .hapticContinuous, parameters: parameters, relativeTime: p.timeSeconds,
                                             duration: p.durationSeconds)
            }
        }
        if let pattern = try? CHHapticPattern(events: events, parameters: []), let player = try? engine.makePlayer(with: pattern) {
            try? player.start(atTime: CHHapticTimeImmediate)
        }
    }
}
#endif
