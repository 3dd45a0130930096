import Foundation
import Navigation

/// How the traveler carries the phone. Recorded in session.json's `carry` ("handheld" / "lanyard", the
/// simulator's `CarryMode` spelling) and used by the pipeline (`CarryProfile`).
public enum PhoneCarry: String, Sendable, Codable, CaseIterable {
    /// Held upright in front of the chest, camera forward (portrait).
    case handheld
    /// Hanging on a lanyard at mid-chest, camera forward; swings with each stride.
    case lanyard
}

/// What the carry mode changes in the pipeline and the coaching. The lanyard swings the camera with the
/// torso (the simulator's lanyard model: +/- 8 deg of yaw at half the step frequency, +/- 5 deg of pitch and
/// +/- 6 deg of roll at the step frequency, docs/simulator.md), so the camera heading the navigator reads
/// wobbles more and the traveler cannot "point the camera": wrong-way needs a longer sustain, and the
/// orientation coach accepts a wider pitch band.
public struct CarryProfile: Sendable, Equatable {
    /// The carry mode.
    public var carry: PhoneCarry
    /// Seconds the heading must stay against the route before "wrong way" (NavigatorOptions default 2 s;
    /// a lanyard's stride swing adds about one stride period, so 3 s).
    public var wrongWaySustainSeconds: Double
    /// Camera pitch the orientation coach aims for, degrees (0 = optical axis level; positive = up).
    public var targetPitchDeg: Double
    /// Half-width of the accepted pitch band around the target, degrees.
    public var pitchToleranceDeg: Double
    /// Accepted roll away from upright portrait, degrees.
    public var rollToleranceDeg: Double

    /// The profile of a carry mode. Handheld: level camera +/- 15 deg (the simulator's handheld pitch lies
    /// within -5...20 deg); lanyard: the lanyard cannot be aimed, so +/- 20 deg and 3 s wrong-way sustain.
    public static func of(_ carry: PhoneCarry) -> CarryProfile {
        switch carry {
        case .handheld:
            return CarryProfile(carry: carry, wrongWaySustainSeconds: 2.0, targetPitchDeg: 5, pitchToleranceDeg: 15,
                                rollToleranceDeg: 15)
        case .lanyard:
            return CarryProfile(carry: carry, wrongWaySustainSeconds: 3.0, targetPitchDeg: 0, pitchToleranceDeg: 20,
                                rollToleranceDeg: 20)
        }
    }

    /// Applies the profile to pipeline options (the phone does this at Start; replay can do the same from a
    /// bundle's `carry` so both run the same pipeline).
    public func apply(to options: inout PipelineOptions) {
        options.navigator.wrongWaySustainSeconds = wrongWaySustainSeconds
    }
}

/// The traveler's settings, persisted by the iOS adapter in UserDefaults as JSON (`encoded()` /
/// `AppSettings.decode`). Every field has a default, and a stored value that is missing or out of range is
/// replaced by its default (never a crash, never a refusal to start), so an update that adds a field still
/// reads the old settings.
public struct AppSettings: Sendable, Equatable, Codable {
    /// Wording: units, clock-face directions, verbosity, language (shared with `wayfinder replay`).
    public var phrasing: PhrasingOptions
    /// Speech rate as a multiple of the system's default rate, 0.5...2.0 (the synthesizer's rate is
    /// `SpeechRate.synthesizerRate`; VoiceOver uses its own rate).
    public var speechRateMultiplier: Double
    /// `AVSpeechSynthesisVoice` identifier; nil = the system voice for `phrasing.language`.
    public var voiceIdentifier: String?
    /// How the phone is carried.
    public var carry: PhoneCarry
    /// Record each walk as a bundle for replay.
    public var recordWalks: Bool
    /// While recording, store every `recordImageEveryNthFrame`-th camera frame as a JPEG (docs/ios.md), so
    /// `wayfinder replay` can run the detector on it.
    public var recordImages: Bool
    /// Image subsampling of recordings (1 = every frame), at least 1.
    public var recordImageEveryNthFrame: Int
    /// Haptic cues on (the vocabulary in `HapticVocabulary`).
    public var hapticsEnabled: Bool
    /// The first-run onboarding (safety notice, how to hold the phone) was completed.
    public var onboardingCompleted: Bool

    /// Allowed speech-rate multipliers.
    public static let speechRateRange: ClosedRange<Double> = 0.5...2.0

    /// Default settings: default phrasing, normal rate, system voice, handheld, recording off, images on
    /// when recording (every 10th frame), haptics on, onboarding not done.
    public init(phrasing: PhrasingOptions = PhrasingOptions(), speechRateMultiplier: Double = 1.0,
                voiceIdentifier: String? = nil, carry: PhoneCarry = .handheld, recordWalks: Bool = false,
                recordImages: Bool = true, recordImageEveryNthFrame: Int = 10, hapticsEnabled: Bool = true,
                onboardingCompleted: Bool = false) {
        self.phrasing = phrasing; self.speechRateMultiplier = speechRateMultiplier
        self.voiceIdentifier = voiceIdentifier; self.carry = carry; self.recordWalks = recordWalks
        self.recordImages = recordImages; self.recordImageEveryNthFrame = recordImageEveryNthFrame
        self.hapticsEnabled = hapticsEnabled; self.onboardingCompleted = onboardingCompleted
    }

    private enum CodingKeys: String, CodingKey {
        case phrasing, speechRateMultiplier, voiceIdentifier, carry, recordWalks, recordImages, recordImageEveryNthFrame,
             hapticsEnabled, onboardingCompleted
    }

    /// Decodes leniently: a missing or undecodable field takes its default; out-of-range numbers are
    /// clamped (`sanitized()`).
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        let d = AppSettings()
        func value<T: Decodable>(_ key: CodingKeys, _ fallback: T) -> T { ((try? c.decodeIfPresent(T.self, forKey: key)) ?? nil) ?? fallback }
        self.init(phrasing: value(.phrasing, d.phrasing), speechRateMultiplier: value(.speechRateMultiplier, d.speechRateMultiplier),
                  voiceIdentifier: value(.voiceIdentifier, d.voiceIdentifier), carry: value(.carry, d.carry),
                  recordWalks: value(.recordWalks, d.recordWalks), recordImages: value(.recordImages, d.recordImages),
                  recordImageEveryNthFrame: value(.recordImageEveryNthFrame, d.recordImageEveryNthFrame),
                  hapticsEnabled: value(.hapticsEnabled, d.hapticsEnabled),
                  onboardingCompleted: value(.onboardingCompleted, d.onboardingCompleted))
        self = sanitized()
    }

    /// The settings with every number inside its range: rate clamped to `speechRateRange` (NaN -> 1),
    /// image subsampling at least 1, stride length 0.3...1.5 m (NaN -> 0.7), an empty voice id -> nil.
    public func sanitized() -> AppSettings {
        var s = self
        s.speechRateMultiplier = speechRateMultiplier.isFinite
            ? min(max(speechRateMultiplier, Self.speechRateRange.lowerBound), Self.speechRateRange.upperBound) : 1.0
        s.recordImageEveryNthFrame = max(1, recordImageEveryNthFrame)
        s.phrasing.strideMeters = phrasing.strideMeters.isFinite ? min(max(phrasing.strideMeters, 0.3), 1.5) : 0.7
        if s.voiceIdentifier?.isEmpty == true { s.voiceIdentifier = nil }
        if s.phrasing.language.isEmpty { s.phrasing.language = "en" }
        return s
    }

    /// The JSON stored in UserDefaults.
    public func encoded() -> Data {
        let e = JSONEncoder()
        e.outputFormatting = [.sortedKeys]
        return (try? e.encode(self)) ?? Data("{}".utf8)
    }

    /// Reads stored settings. Nil data (first run) gives the defaults; data that is not a JSON object gives
    /// the defaults and a warning naming the problem (the adapter logs it; the traveler is never blocked).
    public static func decode(_ data: Data?) -> (settings: AppSettings, warning: String?) {
        guard let data else { return (AppSettings(), nil) }
        do { return (try JSONDecoder().decode(AppSettings.self, from: data), nil) } catch {
            return (AppSettings(), "stored settings (UserDefaults key \(userDefaultsKey)) are not readable JSON; defaults used: \(error)")
        }
    }

    /// The UserDefaults key the adapter stores the JSON under.
    public static let userDefaultsKey = "wayfinder.settings.v1"

    /// The carry profile of `carry`.
    public var carryProfile: CarryProfile { CarryProfile.of(carry) }

    /// Pipeline options for a walk: `base` with the phrase-book language and the carry profile applied
    /// (the detector stays `base`'s choice: `.automatic` runs the U-Net on the camera frames).
    public func pipelineOptions(base: PipelineOptions = PipelineOptions()) -> PipelineOptions {
        var o = base
        o.navigator.language = phrasing.language
        carryProfile.apply(to: &o)
        return o
    }
}

/// The synthesizer rate of a multiplier: AVSpeechUtterance's rate runs 0...1 with 0.5 the default
/// (`AVSpeechUtteranceDefaultSpeechRate`); the scale is roughly linear around the default, so the rate is
/// 0.5 x multiplier, capped to 0.1...1.0.
public enum SpeechRate {
    /// `AVSpeechUtteranceDefaultSpeechRate` (0.5).
    public static let defaultSynthesizerRate = 0.5
    /// The synthesizer's rate for a settings multiplier.
    public static func synthesizerRate(multiplier: Double) -> Double {
        let m = multiplier.isFinite ? multiplier : 1
        return min(1.0, max(0.1, defaultSynthesizerRate * m))
    }
}
