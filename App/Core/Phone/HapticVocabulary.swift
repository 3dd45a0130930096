import Foundation
import Navigation

/// One element of a haptic pattern, in Core Haptics terms (CHHapticEvent).
public struct HapticPulse: Sendable, Equatable {
    /// Transient tap (`.hapticTransient`) or a held buzz (`.hapticContinuous`).
    public enum Kind: String, Sendable {
        /// A transient tap (CHHapticEvent .hapticTransient).
        case tap
        /// A held vibration (CHHapticEvent .hapticContinuous) of `durationSeconds`.
        case buzz
    }
    /// Kind.
    public var kind: Kind
    /// Start, seconds after the pattern starts.
    public var timeSeconds: Double
    /// Length of a buzz, seconds (0 for a tap).
    public var durationSeconds: Double
    /// `.hapticIntensity`, 0...1.
    public var intensity: Double
    /// `.hapticSharpness`, 0...1.
    public var sharpness: Double

    /// A tap at `t` seconds.
    public static func tap(_ t: Double, _ intensity: Double = 1, sharpness: Double = 0.8) -> HapticPulse {
        HapticPulse(kind: .tap, timeSeconds: t, durationSeconds: 0, intensity: intensity, sharpness: sharpness)
    }
    /// A buzz from `t` for `d` seconds.
    public static func buzz(_ t: Double, _ d: Double, _ intensity: Double = 0.8, sharpness: Double = 0.3) -> HapticPulse {
        HapticPulse(kind: .buzz, timeSeconds: t, durationSeconds: d, intensity: intensity, sharpness: sharpness)
    }
}

/// The events the traveler can feel. One distinct pattern each: a turn's side is in the rhythm (left: long
/// then short, "daah-dit", like the left end of a Morse "-." ; right: short then long, "dit-daah"), the
/// turn's size in the count and weight of its taps (slight: a light version, sharp: an extra tap, U-turn:
/// three long); corrections are not rhythms of one long and one short at all (off route: four quick light
/// taps; wrong way: two strong doubles); arrival is one long swelling buzz. Learnable in the onboarding
/// by playing each while its name is spoken.
public enum HapticCue: String, Sendable, CaseIterable {
    /// Turn left.
    case turnLeft
    /// Turn right.
    case turnRight
    /// Bear left.
    case slightLeft
    /// Bear right.
    case slightRight
    /// Sharp left.
    case sharpLeft
    /// Sharp right.
    case sharpRight
    /// U-turn.
    case uTurn
    /// A turn whose side is not known (the cue's speech was not in the same batch).
    case turn
    /// More than the off-route distance from the route (Navigation's `offRoute`).
    case offRoute
    /// Heading against the route (Navigation's `wrongWay`).
    case wrongWay
    /// At the destination (Navigation's `arrived`).
    case arrived

    /// The pattern of this cue.
    public var pattern: [HapticPulse] {
        let long = 0.28, gap = 0.12
        switch self {
        case .turnLeft: return [.buzz(0, long, 0.9), .tap(long + gap, 1)]
        case .turnRight: return [.tap(0, 1), .buzz(gap, long, 0.9)]
        case .slightLeft: return [.buzz(0, long, 0.5, sharpness: 0.15), .tap(long + gap, 0.55, sharpness: 0.4)]
        case .slightRight: return [.tap(0, 0.55, sharpness: 0.4), .buzz(gap, long, 0.5, sharpness: 0.15)]
        case .sharpLeft: return [.buzz(0, long, 1), .tap(long + gap, 1), .tap(long + 2 * gap, 1)]
        case .sharpRight: return [.tap(0, 1), .tap(gap, 1), .buzz(2 * gap, long, 1)]
        case .uTurn: return [.buzz(0, long, 1), .buzz(long + gap, long, 1), .buzz(2 * (long + gap), long, 1)]
        case .turn: return [.tap(0, 0.8)]
        case .offRoute: return (0..<4).map { .tap(Double($0) * 0.09, 0.6, sharpness: 0.5) }
        case .wrongWay: return [.tap(0, 1, sharpness: 1), .tap(0.15, 1, sharpness: 1), .tap(0.45, 1, sharpness: 1), .tap(0.6, 1, sharpness: 1)]
        case .arrived: return [.buzz(0, 0.35, 0.4, sharpness: 0.2), .buzz(0.35, 0.35, 0.8, sharpness: 0.2)]
        }
    }

    /// The rhythm of the pattern as a word, one letter per pulse: "L" a buzz of 0.2 s or more, "S" a
    /// shorter buzz or a tap; used to check that cues differ by more than intensity.
    public var rhythm: String {
        pattern.map { $0.kind == .buzz && $0.durationSeconds >= 0.2 ? "L" : "S" }.joined()
    }

    /// The cue of a maneuver's turn, nil for a maneuver that is not a turn.
    public init?(turn kind: ManeuverKind) {
        switch kind {
        case .turnLeft: self = .turnLeft
        case .turnRight: self = .turnRight
        case .slightLeft: self = .slightLeft
        case .slightRight: self = .slightRight
        case .sharpLeft: self = .sharpLeft
        case .sharpRight: self = .sharpRight
        case .uTurn: self = .uTurn
        default: return nil
        }
    }

    /// The cue of a navigator haptic (exact `HapticPattern` name, as `GuidanceCommand.haptic` carries it);
    /// `turn` gives the side of a `turnCue`. Nil for a name that is not a `HapticPattern`.
    public init?(patternName: String, turn: ManeuverKind? = nil) {
        guard let p = HapticPattern(rawValue: patternName) else { return nil }
        switch p {
        case .wrongWay: self = .wrongWay
        case .offRoute: self = .offRoute
        case .arrived: self = .arrived
        case .turnCue: self = turn.flatMap { HapticCue(turn: $0) } ?? .turn
        }
    }
}

/// Finds the side of a turn cue from the guidance batch it came in: the navigator submits a turn's haptic
/// with its cue phrase, so the batch's utterance equal to a `cue.<turn>` phrase of the phrase book (whole
/// text, exact) names the maneuver. Until the session's commands carry the maneuver kind itself, this is
/// how the adapter tells left from right.
public struct TurnCueResolver: Sendable {
    /// The literal pieces of each turn cue's template around its placeholders (`{toward}` for clock-face
    /// directions), in order, with the maneuver they cue.
    private let cueTemplates: [(pieces: [String], kind: ManeuverKind)]

    /// Builds the lookup from the phrase book the navigator speaks with.
    public init(phrases: PhraseBook) {
        var list: [(pieces: [String], kind: ManeuverKind)] = []
        for kind in ManeuverKind.allCases where kind.isTurn {
            guard let template = phrases.templates["cue.\(kind.rawValue)"] else { continue }
            list.append((Self.literalPieces(of: template), kind))
        }
        cueTemplates = list
    }

    /// `template` split at its `{name}` placeholders: "Turn left now{toward}." -> ["Turn left now", "."].
    static func literalPieces(of template: String) -> [String] {
        var pieces: [String] = [], current = "", inside = false
        for ch in template {
            if ch == "{" { inside = true; pieces.append(current); current = ""; continue }
            if ch == "}" && inside { inside = false; continue }
            if !inside { current.append(ch) }
        }
        pieces.append(current)
        return pieces
    }

    /// Whether `text` is an instance of the template whose literal pieces are `pieces` (each placeholder
    /// standing for any text, possibly empty).
    static func matches(_ text: String, pieces: [String]) -> Bool {
        guard let first = pieces.first, text.hasPrefix(first) else { return false }
        var rest = text.dropFirst(first.count)
        for (i, piece) in pieces.enumerated().dropFirst() {
            if i == pieces.count - 1 { return rest.hasSuffix(piece) }
            guard let r = rest.range(of: piece) else { return false }
            rest = rest[r.upperBound...]
        }
        return rest.isEmpty
    }

    /// The turn that one of `texts` (the batch's spoken texts) cues, if any.
    public func turn(spokenIn texts: [String]) -> ManeuverKind? {
        for text in texts {
            if let hit = cueTemplates.first(where: { Self.matches(text, pieces: $0.pieces) }) { return hit.kind }
        }
        return nil
    }

    /// The cues of a batch of guidance commands, in order: each `.haptic` resolved with the batch's speech.
    public func cues(of commands: [GuidanceCommand]) -> [HapticCue] {
        let texts = commands.compactMap { c -> String? in if case .speak(let text, _) = c { return text } else { return nil } }
        let turn = turn(spokenIn: texts)
        return commands.compactMap { c in
            guard case .haptic(let name) = c else { return nil }
            return HapticCue(patternName: name, turn: turn)
        }
    }
}
