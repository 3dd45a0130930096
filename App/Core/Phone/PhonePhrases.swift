import Foundation
import Navigation

/// Phrase-book keys of the phone shell (health, audio, pause, onboarding), all in
/// `Navigation/Locales/en.json` under `phone.`. Code never spells these sentences itself.
public enum PhoneKey: String, Sendable, CaseIterable {
    /// Spoken when camera permission is denied: what happened and how to turn it on.
    case cameraDenied = "phone.camera.denied"
    /// Spoken when the camera is restricted (Screen Time, device management).
    case cameraRestricted = "phone.camera.restricted"
    /// Spoken when world tracking is unsupported on this device.
    case cameraUnsupported = "phone.camera.unsupported"
    /// Spoken when the AR session failed (`session(_:didFailWithError:)`).
    case sessionFailed = "phone.session.failed"
    /// Spoken when the AR session was interrupted (`sessionWasInterrupted`).
    case sessionInterrupted = "phone.session.interrupted"
    /// Spoken when camera frames come back after an interruption or a stall.
    case sessionResumed = "phone.session.resumed"
    /// Spoken when no camera frame arrived for the watchdog time while guiding.
    case sessionNoFrames = "phone.session.noFrames"
    /// Spoken when tracking stays initializing / relocalizing / unavailable too long (handheld).
    case trackingStuck = "phone.tracking.stuck"
    /// The same, for the lanyard (the phone cannot be aimed).
    case trackingStuckLanyard = "phone.tracking.stuck.lanyard"
    /// Spoken once when the thermal state reaches critical (detection slowed).
    case thermalCritical = "phone.thermal.critical"
    /// Status line: camera permission needed.
    case statusCameraDenied = "phone.status.cameraDenied"
    /// Status line: camera restricted or unsupported.
    case statusCameraUnavailable = "phone.status.cameraUnavailable"
    /// Status line: the AR session failed.
    case statusFailed = "phone.status.failed"
    /// Status line: the AR session is interrupted.
    case statusInterrupted = "phone.status.interrupted"
    /// Status line: no camera frames.
    case statusNoFrames = "phone.status.noFrames"
    /// Status line: tracking poor for too long.
    case statusTracking = "phone.status.tracking"
    /// Spoken (from the speaker) when the headphones were unplugged mid-utterance.
    case headphonesGone = "phone.audio.headphonesGone"
    /// Spoken when the traveler pauses guidance speech.
    case paused = "phone.paused"
    /// Spoken when guidance speech resumes.
    case resumed = "phone.resumed"
    /// First-run safety notice.
    case onboardingSafety = "phone.onboarding.safety"
    /// How to hold the phone in the hand.
    case holdHandheld = "phone.onboarding.hold.handheld"
    /// How to wear the phone on a lanyard.
    case holdLanyard = "phone.onboarding.hold.lanyard"
    /// Orientation coach: the camera looks down.
    case coachPitchDown = "phone.coach.pitchDown"
    /// Orientation coach: the camera looks up.
    case coachPitchUp = "phone.coach.pitchUp"
    /// Orientation coach: the phone leans left.
    case coachRollLeft = "phone.coach.rollLeft"
    /// Orientation coach: the phone leans right.
    case coachRollRight = "phone.coach.rollRight"
    /// Orientation coach: the phone lies flat.
    case coachFlat = "phone.coach.flat"
    /// Orientation coach: the pose is right (keep holding).
    case coachGood = "phone.coach.good"
    /// Orientation coach: held right long enough; training complete.
    case coachDone = "phone.coach.done"
}

/// The phone shell's phrases in the traveler's language, falling back key by key to English when that
/// language's file lacks a `phone.` key (phrase files are added by translators at their own pace; the
/// navigator's required keys are checked by `PhraseBook` itself).
public struct PhonePhrases: Sendable {
    /// The traveler's phrase book.
    public let book: PhraseBook
    /// English, for keys `book` lacks (nil when `book` is English).
    public let fallback: PhraseBook?

    /// Wraps loaded phrase books.
    public init(book: PhraseBook, fallback: PhraseBook?) { self.book = book; self.fallback = fallback }

    /// Loads `Navigation/Locales/<language>.json` and English. Throws `NavigationError` naming the file
    /// when the language's file is missing or malformed.
    public static func load(language: String) throws -> PhonePhrases {
        let book = try PhraseBook.load(language: language)
        return PhonePhrases(book: book, fallback: book.language == "en" ? nil : try PhraseBook.load(language: "en"))
    }

    /// The text of `key`. A key missing from both books yields the key itself (a test keeps en.json complete).
    public func text(_ key: PhoneKey, _ values: [String: String] = [:]) -> String {
        if book.templates[key.rawValue] != nil { return book.phrase(key.rawValue, values) }
        return (fallback ?? book).phrase(key.rawValue, values)
    }

    /// Keys of `PhoneKey` that `book` itself lacks (for a translator's checklist).
    public var missingKeys: [PhoneKey] { PhoneKey.allCases.filter { book.templates[$0.rawValue] == nil } }
}
