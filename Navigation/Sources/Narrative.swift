// Stage 2 of guidance (after valhalla's narrative builder): maneuvers become phrases, from a template file
// per language in Navigation/Locales/<language>.json. Code never builds sentences itself: every spoken
// word comes from the file, so a language is added by adding a file.
import Foundation
import Maps

/// The phrase templates of one language.
public struct PhraseBook: Sendable {
    /// Language code, e.g. "en" (the file's name without `.json`).
    public let language: String
    /// Template per key; placeholders are `{name}`.
    public let templates: [String: String]

    /// Every key the navigator uses. A phrase file must define all of them.
    public static let requiredKeys: [String] = {
        var keys = ["distance.one", "distance.other", "distance.feet.one", "distance.feet.other",
                    "distance.steps.one", "distance.steps.other", "clock.toward.one", "clock.toward.other",
                    "startWalking", "noRoute",
                    "depart.ahead", "depart.left", "depart.right", "depart.turnAround",
                    "continuation", "safety.wrongWay", "safety.offRoute",
                    "whereAmI.between", "whereAmI.near", "whereAmI.unknown", "whereAmI.probably",
                    "disambiguate.ahead", "disambiguate.turnAround", "disambiguate.left", "disambiguate.right",
                    "disambiguate.unsure", "repeat.none", "cue.continue",
                    "cue.continue.short"]
        let alerted: [ManeuverKind] = [.turnLeft, .turnRight, .slightLeft, .slightRight, .sharpLeft, .sharpRight,
                                       .uTurn, .takeElevator, .takeStairs, .goThroughDoor]
        keys += alerted.map { "alert.\($0.rawValue)" } + ["alert.arrive"]
        keys += alerted.map { "cue.\($0.rawValue)" }
        keys += alerted.map { "then.\($0.rawValue)" }
        for side in ArrivalSide.allCases {
            keys += ["arrival.\(side.rawValue)", "arrival.\(side.rawValue).door"]
        }
        keys += sessionKeys
        return keys
    }()

    /// Keys of the app's own prompts and status lines (App/Core/Session: tracking prompts, the guidance
    /// session's status), spoken or shown to VoiceOver, so they come from the phrase book too.
    public static let sessionKeys: [String] = [
        "tracking.covered", "tracking.slowDown", "tracking.pointAhead", "tracking.lost",
        "status.chooseBuilding", "status.chooseStart", "status.chooseDestination", "status.ready", "status.locating",
        "status.onRoute", "status.unsure", "status.arrived", "status.stopped",
    ]

    /// Placeholders the code fills; any other `{...}` in a template is an error. `{toward}` is the
    /// clock-face suffix (`clock.toward.*`, empty with turn words).
    public static let knownPlaceholders: Set<String> = ["distance", "count", "floor", "destination", "place", "from", "to",
                                                        "toward"]

    /// The English phrase book, or (should the resource be missing from a broken app bundle) a book that
    /// says each key: the non-throwing default for the app's session logic.
    public static let english: PhraseBook = (try? load(language: "en")) ?? PhraseBook(language: "en", templates: [:])

    /// A phrase book from templates already in memory (no validation; tests and fallbacks).
    public init(language: String, templates: [String: String]) {
        self.language = language
        self.templates = templates
    }

    /// Loads `Navigation/Locales/<language>.json` from the module's resources (SwiftPM: `Bundle.module`;
    /// the Xcode app build must copy `Navigation/Locales` into the app bundle, where it is looked up).
    /// A regional code without its own file falls back to the language ("en-GB" -> "en").
    public static func load(language: String) throws -> PhraseBook {
        do {
            return try loadExactly(language: language)
        } catch NavigationError.unknownLanguage(_) where language.contains(where: { $0 == "-" || $0 == "_" }) {
            let base = String(language.prefix { $0 != "-" && $0 != "_" })
            guard let book = try? loadExactly(language: base) else { throw NavigationError.unknownLanguage(language) }
            return book
        }
    }

    private static func loadExactly(language: String) throws -> PhraseBook {
        #if SWIFT_PACKAGE
        let bundle = Bundle.module
        #else
        let bundle = Bundle.main
        #endif
        guard !language.isEmpty, language.allSatisfy({ $0.isLetter || $0 == "-" || $0 == "_" }),
              let url = bundle.url(forResource: language, withExtension: "json", subdirectory: "Locales")
                ?? bundle.url(forResource: language, withExtension: "json")
        else { throw NavigationError.unknownLanguage(language) }
        let data: Data
        do { data = try Data(contentsOf: url) } catch {
            throw NavigationError.invalidPhraseFile("\(language).json: cannot read (\(error.localizedDescription))")
        }
        return try PhraseBook(language: language, json: data, sourceName: "\(language).json")
    }

    /// Parses a phrase file: `{"language": "...", "phrases": {"key": "template", ...}}`. Throws
    /// `invalidPhraseFile` naming `sourceName` and the key when a required key is missing or a template
    /// uses an unknown placeholder.
    public init(language: String, json: Data, sourceName: String) throws {
        struct File: Decodable { var language: String; var phrases: [String: String] }
        let file: File
        do { file = try JSONDecoder().decode(File.self, from: json) } catch {
            throw NavigationError.invalidPhraseFile("\(sourceName): not a phrase file (\(error))")
        }
        for key in Self.requiredKeys where file.phrases[key] == nil {
            throw NavigationError.invalidPhraseFile("\(sourceName): missing key '\(key)'")
        }
        for (key, template) in file.phrases {
            for name in Self.placeholders(in: template) where !Self.knownPlaceholders.contains(name) {
                throw NavigationError.invalidPhraseFile("\(sourceName): key '\(key)' uses unknown placeholder {\(name)}")
            }
        }
        self.language = language
        templates = file.phrases
    }

    static func placeholders(in template: String) -> [String] {
        var out: [String] = []
        var rest = template[...]
        while let open = rest.firstIndex(of: "{"), let close = rest[open...].firstIndex(of: "}") {
            out.append(String(rest[rest.index(after: open)..<close]))
            rest = rest[rest.index(after: close)...]
        }
        return out
    }

    /// The template for `key` with `{name}` replaced by `values[name]`. A missing key (impossible after
    /// validation) yields the key itself, so nothing crashes.
    /// `{toward}` left unfilled is empty (turn words).
    public func phrase(_ key: String, _ values: [String: String] = [:]) -> String {
        var text = templates[key] ?? key
        for (name, value) in values { text = text.replacingOccurrences(of: "{\(name)}", with: value) }
        if values["toward"] == nil { text = text.replacingOccurrences(of: "{toward}", with: "") }
        return text
    }

    /// Spoken distances are rounded: to the nearest meter under 10 m (at least 1), to the nearest 5 m from
    /// 10 m up (half rounds up: 12.5 -> 15). 9.6 m is "10 meters".
    public static func roundedDistanceMeters(_ meters: Double) -> Int {
        guard meters.isFinite else { return 0 }
        let m = max(0, meters)
        let whole = Int(m.rounded(.toNearestOrAwayFromZero))
        if whole < 10 { return max(1, whole) }
        return Int((m / 5).rounded(.toNearestOrAwayFromZero)) * 5
    }

    /// A distance as spoken ("1 meter", "15 meters").
    public func distance(_ meters: Double) -> String {
        let n = Self.roundedDistanceMeters(meters)
        return n == 1 ? phrase("distance.one") : phrase("distance.other", ["count": String(n)])
    }

    /// A count rounded as spoken distances are: to the nearest whole number below `fineBelow` (at least
    /// 1), to the nearest multiple of 5 from there up (half rounds up).
    public static func roundedCount(_ value: Double, fineBelow: Int) -> Int {
        guard value.isFinite else { return 0 }
        let v = max(0, value)
        let whole = Int(v.rounded(.toNearestOrAwayFromZero))
        if whole < fineBelow { return max(1, whole) }
        return Int((v / 5).rounded(.toNearestOrAwayFromZero)) * 5
    }

    /// Meters per foot (international foot).
    public static let metersPerFoot = 0.3048

    /// A distance in the traveler's unit: meters as `distance(_:)`; feet (nearest foot under 30 ft, then
    /// nearest 5 ft: 8 m is "25 feet"); steps of `strideMeters` (nearest step under 20, then nearest 5:
    /// 8 m at 0.7 m per step is "11 steps"). A stride that is not a positive finite length falls back to
    /// meters.
    public func distance(_ meters: Double, unit: DistanceUnit, strideMeters: Double) -> String {
        switch unit {
        case .meters:
            return distance(meters)
        case .feet:
            let n = Self.roundedCount(meters / Self.metersPerFoot, fineBelow: 30)
            return n == 1 ? phrase("distance.feet.one") : phrase("distance.feet.other", ["count": String(n)])
        case .steps:
            guard strideMeters.isFinite, strideMeters > 0 else { return distance(meters) }
            let n = Self.roundedCount(meters / strideMeters, fineBelow: 20)
            return n == 1 ? phrase("distance.steps.one") : phrase("distance.steps.other", ["count": String(n)])
        }
    }

    /// The clock-face hour of a direction relative to the traveler's heading, 12 straight ahead, 3 to the
    /// right, 9 to the left (Clew's convention): `relativeDeg` positive = left (counter-clockwise), rounded
    /// to the nearest 30 deg.
    public static func clockHour(relativeDeg: Double) -> Int {
        guard relativeDeg.isFinite else { return 12 }
        let steps = Int((-relativeDeg / 30).rounded(.toNearestOrAwayFromZero))
        let h = ((steps % 12) + 12) % 12
        return h == 0 ? 12 : h
    }

    /// The `{toward}` suffix: ", toward 9 o'clock" for a direction `relativeDeg` (positive = left).
    public func toward(relativeDeg: Double) -> String {
        let h = Self.clockHour(relativeDeg: relativeDeg)
        return h == 1 ? phrase("clock.toward.one") : phrase("clock.toward.other", ["count": String(h)])
    }
}

/// Where the destination lies relative to the traveler's heading on arrival.
public enum ArrivalSide: String, Sendable, CaseIterable, Equatable {
    /// 45 to 135 deg counter-clockwise of the heading.
    case left
    /// 45 to 135 deg clockwise of the heading.
    case right
    /// Within 45 deg of the heading.
    case ahead
    /// More than 135 deg from the heading.
    case behind

    /// Classifies the bearing of the destination relative to the heading (radians, positive = left).
    public static func classify(relativeBearingRad r: Double) -> ArrivalSide {
        let d = abs(normalizedAngleRad(r)) * 180 / Double.pi
        if d <= 45 { return .ahead }
        if d >= 135 { return .behind }
        return normalizedAngleRad(r) > 0 ? .left : .right
    }
}

/// Direction of the first leg relative to the traveler's heading when a route starts.
public enum DepartOrientation: String, Sendable, Equatable {
    /// Within 30 deg of the heading.
    case ahead
    /// 30 to 135 deg to the left.
    case left
    /// 30 to 135 deg to the right.
    case right
    /// More than 135 deg away.
    case turnAround

    /// Classifies the route direction relative to the heading (radians, positive = left). 30 deg is wider
    /// than the straight band of turns (20 deg) because the heading of a hand-held phone wobbles.
    public static func classify(relativeBearingRad r: Double) -> DepartOrientation {
        let d = abs(normalizedAngleRad(r)) * 180 / Double.pi
        if d <= 30 { return .ahead }
        if d > 135 { return .turnAround }
        return normalizedAngleRad(r) > 0 ? .left : .right
    }
}

/// Turns maneuvers into phrases with a `PhraseBook`, worded by `PhrasingOptions` (unit, direction style).
/// Verbosity is applied by the navigator (what is said), not here (how it is said).
public struct Narrative: Sendable {
    /// The phrase templates.
    public let phrases: PhraseBook
    /// Unit and direction style of the phrases (its `language` is the phrase book's).
    public let options: PhrasingOptions

    /// Wraps a phrase book; `options` defaults to meters and turn words.
    public init(phrases: PhraseBook, options: PhrasingOptions = PhrasingOptions()) {
        self.phrases = phrases
        self.options = options
    }

    /// A distance in the chosen unit ("8 meters", "25 feet", "11 steps").
    public func distance(_ meters: Double) -> String {
        phrases.distance(meters, unit: options.distanceUnit, strideMeters: options.strideMeters)
    }

    /// The `{toward}` value: empty with turn words; with clock-face directions ", toward 9 o'clock" for
    /// a direction `relativeDeg` from the heading (positive = left); empty when the angle is unknown.
    public func toward(relativeDeg: Double?) -> String {
        guard options.directionStyle == .clockFace, let relativeDeg else { return "" }
        return phrases.toward(relativeDeg: relativeDeg)
    }

    /// Start of a route: "Turn left, then go 10 meters." (clock face: "Turn left, toward 9 o'clock, then
    /// go 10 meters."); `relativeBearingRad` is the route's direction from the heading (positive = left).
    public func depart(_ orientation: DepartOrientation, distanceMeters: Double, relativeBearingRad: Double? = nil) -> String {
        phrases.phrase("depart.\(orientation.rawValue)",
                       ["distance": distance(distanceMeters),
                        "toward": toward(relativeDeg: relativeBearingRad.map { normalizedAngleRad($0) * 180 / Double.pi })])
    }

    /// The early alert: "In 8 meters, turn left." Nil for kinds without one (depart, continue).
    public func alert(_ m: Maneuver, distanceMeters: Double, destinationName: String) -> String? {
        switch m.kind {
        case .depart, .continue: return nil
        default:
            return phrases.phrase("alert.\(m.kind.rawValue)",
                                  ["distance": distance(distanceMeters), "floor": m.toFloorName ?? "",
                                   "destination": destinationName, "toward": toward(relativeDeg: m.turnAngleDeg)])
        }
    }

    /// The cue at the maneuver: "Turn left now." For `continue` (off an elevator or stairs):
    /// "Now on Floor 2. Continue 10 meters." Nil for depart and arrive (see `depart`, `arrival`).
    public func cue(_ m: Maneuver, floorName: String) -> String? {
        switch m.kind {
        case .depart, .arrive: return nil
        case .continue:
            // With the next maneuver only steps away, just the floor: its own cue follows at once.
            if m.distanceToNextMeters < RouteBuilder.chainMeters {
                return phrases.phrase("cue.continue.short", ["floor": floorName])
            }
            return phrases.phrase("cue.continue", ["floor": floorName, "distance": distance(m.distanceToNextMeters)])
        default:
            return phrases.phrase("cue.\(m.kind.rawValue)", ["floor": m.toFloorName ?? "",
                                                              "toward": toward(relativeDeg: m.turnAngleDeg)])
        }
    }

    /// A maneuver announced right after the previous one's cue: "Then turn left." Nil for kinds that are
    /// never chained.
    public func then(_ m: Maneuver) -> String? {
        switch m.kind {
        case .depart, .continue, .arrive: return nil
        default: return phrases.phrase("then.\(m.kind.rawValue)", ["floor": m.toFloorName ?? "",
                                                                     "toward": toward(relativeDeg: m.turnAngleDeg)])
        }
    }

    /// After a maneuver, on a long leg: "Continue 15 meters."
    public func continuation(distanceMeters: Double) -> String {
        phrases.phrase("continuation", ["distance": distance(distanceMeters)])
    }

    /// "Arrived. Room 312 is on your left, behind a door."
    public func arrival(side: ArrivalSide, behindDoor: Bool, destinationName: String) -> String {
        phrases.phrase("arrival.\(side.rawValue)" + (behindDoor ? ".door" : ""), ["destination": destinationName])
    }
}
