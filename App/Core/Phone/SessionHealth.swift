import Foundation
import SessionFormat

/// Camera permission as AVCaptureDevice.authorizationStatus(for: .video) reports it.
public enum CameraAuthorization: String, Sendable, CaseIterable {
    /// Never asked.
    case notDetermined
    /// Granted.
    case authorized
    /// The traveler said no (changeable in Settings).
    case denied
    /// Blocked by Screen Time or device management (not changeable by the traveler).
    case restricted
}

/// Why an ARSession failed, from `session(_:didFailWithError:)` (the adapter maps ARError codes).
public enum SessionFailure: String, Sendable, CaseIterable {
    /// ARError.cameraUnauthorized.
    case cameraUnauthorized
    /// ARError.unsupportedConfiguration (no world tracking on this device).
    case unsupportedConfiguration
    /// ARError.sensorUnavailable / sensorFailed / worldTrackingFailed and anything else.
    case sensorFailed
}

/// What happened to the camera session, in domain terms.
public enum HealthEvent: Sendable, Equatable {
    /// The traveler pressed Start; the camera permission as it stands.
    case startRequested(CameraAuthorization)
    /// The permission prompt was answered.
    case permissionAnswered(granted: Bool)
    /// The AR session was started at `t` (seconds, the frames' clock).
    case sessionStarted(t: Double)
    /// A camera frame at `t` with its tracking state.
    case frame(t: Double, tracking: TrackingState, reason: TrackingReason?)
    /// `session(_:didFailWithError:)`.
    case sessionFailed(SessionFailure)
    /// `sessionWasInterrupted(_:)` at `t`.
    case interrupted(t: Double)
    /// `sessionInterruptionEnded(_:)` at `t`.
    case interruptionEnded(t: Double)
    /// A once-a-second clock tick at `t`, for the frame watchdog.
    case tick(t: Double)
    /// The thermal state changed (critical is announced once per walk).
    case thermal(ThermalLevel)
    /// Guidance stopped (by the traveler or on arrival).
    case stopped
}

/// What the health machine asks the shell to do.
public enum HealthCommand: Sendable, Equatable {
    /// Ask for camera permission (AVCaptureDevice.requestAccess).
    case requestCameraPermission
    /// Permission is fine: start guidance (GuidanceSession.start, then the sensors).
    case beginGuidance
    /// Stop guidance (the session cannot run).
    case endGuidance
    /// Say this (from the phrase book); `interrupt` cuts off current speech.
    case speak(String, interrupt: Bool)
    /// Show (and expose to VoiceOver) this status instead of the session's, or nil to show the session's.
    case status(String?)
    /// Offer a button that opens the app's page in Settings (UIApplication.openSettingsURLString).
    case offerSettings(Bool)
    /// Restart world tracking from scratch (ARSession.run with .resetTracking and .removeExistingAnchors): ARKit
    /// has been relocalizing for `SessionHealth.relocalizationTimeoutSeconds`, and a relocalization that has not
    /// succeeded by then may never succeed (the traveler walked on during the interruption, away from the place
    /// ARKit mapped). The pipeline tells the localizer the VIO frame is new (`ParticleLocalizer.noteVIOReset`);
    /// the particles are kept.
    case restartTracking
}

/// The camera session's health: tells the traveler what happened and what to do whenever the camera cannot
/// serve guidance, so the screen never reads "Locating. Keep walking." over silence. Events in, commands out
/// (InvisibleMap style); the iOS adapter maps AVFoundation / ARKit callbacks to events and renders commands.
///
/// Rules: permission is checked before the sensors start; a failed session ends guidance with the reason;
/// an interruption pauses with a spoken reason and a spoken resumption; no frame for
/// `frameTimeoutSeconds` while running is a stall (spoken, resumed on the next frame); tracking stuck in
/// initializing, relocalizing or not-available for `stuckTrackingSeconds` is spoken and repeated every
/// `stuckRepeatSeconds` while it lasts (TrackingPromptPolicy stays silent for those reasons, as it must
/// for brief ones); relocalizing for `relocalizationTimeoutSeconds` restarts world tracking once per spell
/// (`HealthCommand.restartTracking`): after an interruption ARKit relocalizes only where it mapped before, and
/// otherwise stays relocalizing indefinitely (Apple, "Managing Session Life Cycle and Tracking Quality": offer a
/// reset), which a traveler who cannot see the screen could not resolve.
public struct SessionHealth: Sendable {
    /// Where the session stands.
    public enum State: String, Sendable, Equatable {
        /// Not guiding.
        case idle
        /// Waiting for the permission prompt.
        case askingPermission
        /// Running with frames arriving.
        case running
        /// Interrupted by the system.
        case interrupted
        /// No frames for too long.
        case stalled
        /// Failed or not permitted: guidance cannot run until Start is pressed again.
        case failed
    }

    /// Current state.
    public private(set) var state: State = .idle
    /// The status shown instead of the session's (nil = the session's own).
    public private(set) var statusOverride: String?
    /// Seconds without a frame before a stall is announced (ARKit delivers 60 Hz; 2 s is unmistakable).
    public var frameTimeoutSeconds = 2.0
    /// Seconds of initializing / relocalizing / not-available tracking before it is spoken.
    public var stuckTrackingSeconds = 8.0
    /// Repeat interval of the stuck-tracking prompt, seconds.
    public var stuckRepeatSeconds = 15.0
    /// Seconds of continuous relocalizing after which world tracking is restarted (`HealthCommand.restartTracking`).
    /// A relocalization that works takes a second or two once the camera sees the mapped place again; 6 s is past
    /// that and before the stuck-tracking prompt (8 s), so the prompt, when it comes, is about the restart's
    /// initializing. 0 or less: never restart.
    public var relocalizationTimeoutSeconds = 6.0
    /// Carry mode (chooses the stuck-tracking wording).
    public var carry: PhoneCarry

    private let phrases: PhonePhrases
    private var lastFrameT: Double?
    private var stuckSince: Double?
    /// Start of the current relocalizing spell, and whether it has been answered with a restart.
    private var relocalizingSince: Double?
    private var restartedThisSpell = false
    private var lastStuckSpokenT: Double?
    private var thermalAnnounced = false
    private var stallAnnounced = false

    /// Creates the machine in `idle`.
    public init(phrases: PhonePhrases, carry: PhoneCarry = .handheld) { self.phrases = phrases; self.carry = carry }

    /// Handles one event; returns the commands in order.
    public mutating func handle(_ event: HealthEvent) -> [HealthCommand] {
        switch event {
        case .startRequested(let auth):
            switch auth {
            case .authorized: return begin()
            case .notDetermined:
                state = .askingPermission
                return [.requestCameraPermission]
            case .denied: return fail(.cameraDenied, status: .statusCameraDenied, settings: true, endGuidance: false)
            case .restricted: return fail(.cameraRestricted, status: .statusCameraUnavailable, settings: false, endGuidance: false)
            }
        case .permissionAnswered(let granted):
            guard state == .askingPermission else { return [] }
            return granted ? begin() : fail(.cameraDenied, status: .statusCameraDenied, settings: true, endGuidance: false)
        case .sessionStarted(let t):
            guard state == .running else { return [] }
            lastFrameT = t
            return []
        case .frame(let t, let tracking, let reason):
            return frame(t: t, tracking: tracking, reason: reason)
        case .sessionFailed(let failure):
            guard state != .idle else { return [] }
            switch failure {
            case .cameraUnauthorized: return fail(.cameraDenied, status: .statusCameraDenied, settings: true, endGuidance: true)
            case .unsupportedConfiguration: return fail(.cameraUnsupported, status: .statusCameraUnavailable, settings: false, endGuidance: true)
            case .sensorFailed: return fail(.sessionFailed, status: .statusFailed, settings: false, endGuidance: true)
            }
        case .interrupted:
            guard state == .running || state == .stalled else { return [] }
            state = .interrupted
            return setStatus(.statusInterrupted) + [.speak(phrases.text(.sessionInterrupted), interrupt: true)]
        case .interruptionEnded(let t):
            guard state == .interrupted else { return [] }
            // Running again, but not "resumed" until a frame proves it; the watchdog restarts now.
            state = .stalled
            stallAnnounced = false
            lastFrameT = t
            return []
        case .tick(let t):
            guard state == .running || (state == .stalled && !stallAnnounced), let last = lastFrameT,
                  t - last >= frameTimeoutSeconds else { return [] }
            state = .stalled
            stallAnnounced = true
            return setStatus(.statusNoFrames) + [.speak(phrases.text(.sessionNoFrames), interrupt: true)]
        case .thermal(let level):
            guard level == .critical, state == .running || state == .stalled, !thermalAnnounced else { return [] }
            thermalAnnounced = true
            return [.speak(phrases.text(.thermalCritical), interrupt: false)]
        case .stopped:
            // A failure keeps saying why on the status line until Start is pressed again.
            guard state != .failed else { return [] }
            let hadOverride = statusOverride != nil
            state = .idle
            reset()
            return hadOverride ? [.status(nil), .offerSettings(false)] : []
        }
    }

    private mutating func begin() -> [HealthCommand] {
        let hadOverride = statusOverride != nil
        state = .running
        reset()
        return (hadOverride ? [.status(nil), .offerSettings(false)] : []) + [.beginGuidance]
    }

    private mutating func reset() {
        statusOverride = nil
        lastFrameT = nil
        stuckSince = nil
        lastStuckSpokenT = nil
        relocalizingSince = nil
        restartedThisSpell = false
        thermalAnnounced = false
        stallAnnounced = false
    }

    private mutating func fail(_ spoken: PhoneKey, status: PhoneKey, settings: Bool, endGuidance: Bool) -> [HealthCommand] {
        state = .failed
        var out: [HealthCommand] = endGuidance ? [.endGuidance] : []
        out += setStatus(status)
        out.append(.offerSettings(settings))
        out.append(.speak(phrases.text(spoken), interrupt: true))
        return out
    }

    private mutating func setStatus(_ key: PhoneKey?) -> [HealthCommand] {
        let text = key.map { phrases.text($0) }
        guard text != statusOverride else { return [] }
        statusOverride = text
        return [.status(text)]
    }

    /// `.restartTracking` once a relocalizing spell has lasted `relocalizationTimeoutSeconds` (once per spell).
    private mutating func restartIfRelocalizingTooLong(t: Double, relocalizing: Bool) -> [HealthCommand] {
        guard relocalizing else {
            relocalizingSince = nil
            restartedThisSpell = false
            return []
        }
        let since = relocalizingSince ?? t
        relocalizingSince = since
        guard relocalizationTimeoutSeconds > 0, !restartedThisSpell, t - since >= relocalizationTimeoutSeconds else { return [] }
        restartedThisSpell = true
        return [.restartTracking]
    }

    private mutating func frame(t: Double, tracking: TrackingState, reason: TrackingReason?) -> [HealthCommand] {
        guard state == .running || state == .stalled else { return [] }
        var out: [HealthCommand] = []
        lastFrameT = t
        if state == .stalled {
            state = .running
            stuckSince = nil
            stallAnnounced = false
            out += setStatus(nil)
            out.append(.speak(phrases.text(.sessionResumed), interrupt: true))
        }
        out += restartIfRelocalizingTooLong(t: t, relocalizing: tracking == .limited && reason == .relocalizing)
        let stuck: Bool
        switch (tracking, reason) {
        case (.notAvailable, _), (.limited, .initializing?), (.limited, .relocalizing?): stuck = true
        default: stuck = false
        }
        guard stuck else {
            if stuckSince != nil {
                stuckSince = nil
                lastStuckSpokenT = nil
                out += setStatus(nil)
            }
            return out
        }
        let since = stuckSince ?? t
        stuckSince = since
        guard t - since >= stuckTrackingSeconds else { return out }
        if let last = lastStuckSpokenT, t - last < stuckRepeatSeconds { return out }
        lastStuckSpokenT = t
        out += setStatus(.statusTracking)
        out.append(.speak(phrases.text(carry == .lanyard ? .trackingStuckLanyard : .trackingStuck), interrupt: false))
        return out
    }
}
