// How guidance is worded for one traveler: units, direction style, verbosity, language. Shared by the
// `wayfinder` command line (replay flags) and the iPhone app's settings, so both speak the same way.
// Options offered as in peer apps: Clew's clock-face directions, Soundscape's and Lazarillo's units and
// verbosity levels.

/// Unit in which spoken distances are given.
public enum DistanceUnit: String, Sendable, CaseIterable, Codable {
    /// Whole meters ("8 meters").
    case meters
    /// Whole feet ("25 feet"), 0.3048 m per foot.
    case feet
    /// The traveler's own steps, from a stride length calibrated on their walking ("11 steps").
    case steps
}

/// How a change of direction is said.
public enum DirectionStyle: String, Sendable, CaseIterable, Codable {
    /// "Turn left", "slight right".
    case turnWords
    /// Turn words plus the clock face, 12 o'clock straight ahead ("slight right, toward 1 o'clock"; Clew).
    case clockFace
}

/// How much is said.
public enum Verbosity: String, Sendable, CaseIterable, Codable {
    /// The route start, maneuver cues, rides, arrival and corrections only: no early alerts, no
    /// "Continue N meters".
    case brief
    /// Cues, early alerts and continuations on long legs (the default).
    case normal
    /// Everything in `normal` plus the distance after every turn or door ("Continue N meters" unless the
    /// next maneuver is within 4.75 m). Landmarks passed are not said yet.
    case detailed
}

/// The wording choices of one traveler. Value type; no ownership concerns.
public struct PhrasingOptions: Sendable, Equatable, Codable {
    /// Spoken distance unit.
    public var distanceUnit: DistanceUnit
    /// Stride length used for `DistanceUnit.steps`, meters per step: the walker's own, measured (distance
    /// walked / steps counted; the phone has no step cadence from VIO, so it is a setting); 0.7 m, a
    /// typical adult walking stride, when unknown.
    public var strideMeters: Double
    /// Direction wording.
    public var directionStyle: DirectionStyle
    /// Amount of speech.
    public var verbosity: Verbosity
    /// Phrase-book language code (`Navigation/Locales/<language>.json`), e.g. "en", "es".
    public var language: String

    /// Creates options; the defaults are meters, turn words, normal verbosity, English.
    public init(distanceUnit: DistanceUnit = .meters, strideMeters: Double = 0.7,
                directionStyle: DirectionStyle = .turnWords, verbosity: Verbosity = .normal,
                language: String = "en") {
        self.distanceUnit = distanceUnit; self.strideMeters = strideMeters
        self.directionStyle = directionStyle; self.verbosity = verbosity; self.language = language
    }
}
