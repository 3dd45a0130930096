import Foundation

/// Inputs that reach the app without looking at the screen.
public enum EyesFreeInput: String, Sendable, CaseIterable {
    /// VoiceOver's Magic Tap (two-finger double tap anywhere; `accessibilityPerformMagicTap`).
    case magicTap
    /// Headphone / lock-screen play-pause toggle (MPRemoteCommandCenter.togglePlayPauseCommand; one click
    /// of wired EarPods, one press of AirPods).
    case remoteTogglePlayPause
    /// MPRemoteCommandCenter.playCommand.
    case remotePlay
    /// MPRemoteCommandCenter.pauseCommand.
    case remotePause
    /// MPRemoteCommandCenter.nextTrackCommand (double click).
    case remoteNextTrack
    /// MPRemoteCommandCenter.previousTrackCommand (triple click).
    case remotePreviousTrack
    /// The big "Where am I?" button (also the VoiceOver rotor action).
    case whereAmIButton
    /// The big "Repeat" button.
    case repeatButton
}

/// What an eyes-free input does.
public enum EyesFreeAction: String, Sendable, Equatable {
    /// Repeat the last instruction (GuidanceSession.repeatLast).
    case repeatLast
    /// Say where the traveler is (GuidanceSession.whereAmI).
    case whereAmI
    /// Stop what is being said now (SpeechEvent.silence).
    case silence
    /// Pause guidance speech (vibrations continue) (SpeechEvent.pause).
    case pauseSpeech
    /// Resume guidance speech (SpeechEvent.resume).
    case resumeSpeech
    /// Nothing to do (not guiding).
    case none
}

/// The eyes-free command map, after Soundscape's RemoteCommandManager (play/pause = the main "callout"
/// action, next/previous = more callouts) and VoiceOver's Magic Tap convention (the app's main action;
/// while something is being said, it stops it, as Magic Tap stops a phone call or music):
///
/// | input | while speaking | silent, speech on | speech paused |
/// |---|---|---|---|
/// | Magic Tap, play-pause | silence | repeat last | resume |
/// | play | repeat last | repeat last | resume |
/// | pause | pause speech | pause speech | - |
/// | next track | where am I | where am I | where am I |
/// | previous track | repeat last | repeat last | repeat last |
/// | Where am I? / Repeat buttons | where am I / repeat last (always) | | |
///
/// Outside guidance, "Where am I" and "Repeat" still answer (the session speaks its status); the rest does
/// nothing.
public enum EyesFreeCommandMap {
    /// The action of `input` given whether speech is playing, whether guidance speech is paused, and whether
    /// guidance is running.
    public static func action(for input: EyesFreeInput, speaking: Bool, speechPaused: Bool, guiding: Bool) -> EyesFreeAction {
        switch input {
        case .whereAmIButton, .remoteNextTrack: return .whereAmI
        case .repeatButton, .remotePreviousTrack: return .repeatLast
        case .magicTap, .remoteTogglePlayPause:
            if speechPaused { return .resumeSpeech }
            if speaking { return .silence }
            return .repeatLast
        case .remotePlay: return speechPaused ? .resumeSpeech : .repeatLast
        case .remotePause:
            guard guiding, !speechPaused else { return speaking ? .silence : .none }
            return .pauseSpeech
        }
    }
}

/// Keeps the screen awake while the phone must keep sensing: the idle timer is off while guiding or
/// recording (a locked phone stops ARKit, fatal on a lanyard), on otherwise so the battery is spared.
/// Emits `UIApplication.isIdleTimerDisabled` only when it changes.
public struct ScreenWakePolicy: Sendable {
    /// The last value asked for.
    public private(set) var idleTimerDisabled = false

    /// Creates the policy (idle timer enabled).
    public init() {}

    /// The new `isIdleTimerDisabled` value when it changes, nil otherwise.
    public mutating func update(guiding: Bool, recording: Bool) -> Bool? {
        let want = guiding || recording
        guard want != idleTimerDisabled else { return nil }
        idleTimerDisabled = want
        return want
    }
}
