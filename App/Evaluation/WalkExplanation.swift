import Foundation
import Maps
import Navigation
import SessionFormat
import WayfinderCore

/// Text for people that explains a walk's navigation score: for every cue scored wrong, every true turn
/// scored missing and every instruction unsafe from the true pose while not localized, where the traveler
/// truly was, where the localizer put them, the true turns and the phrases around that moment. What
/// `wayfinder eval --explain` prints.
public enum WalkExplanation {
    /// Seconds of announcements and true turns listed on each side of an explained moment.
    public static let contextSeconds = 10.0

    /// Lines explaining `score`: one line listing the walk's true turns, then the explanations.
    public static func lines(score: WalkScore, result: ReplayResult, truth: [TruthRecord], building: Building) -> [String] {
        let n = score.navigation
        let track = TruthTrack(truth)
        guard !track.isEmpty else { return [] }
        let turns = NavigationScore.trueTurns(truth: track, building: building, minimumAngleDeg: TurnClassifier.straightBelowDeg)
        var out = ["\(score.name): \(n.wrongInstructions) wrong, \(n.missingInstructions) missing; true turns: "
                   + turns.map { describe($0, track, building) }.joined(separator: "; ")]
        func context(_ t: Double) -> [String] {
            let said = result.announcements.filter { abs($0.t - t) <= contextSeconds }
                .map { String(format: "      %7.2f s (%+.1f m) %@", $0.t, track.distanceWalked(at: $0.t) - track.distanceWalked(at: t), $0.text) }
            return said
        }
        func place(_ t: Double) -> String {
            let s = track.state(at: t)
            var text = String(format: "truth (%.2f, %.2f) floor %@, %.1f m walked", s.x, s.y, s.floorId, track.distanceWalked(at: t))
            if let r = result.trace.last(where: { $0.t <= t + 1e-9 }) {
                let err = r.floorId == s.floorId ? hypot(r.x - s.x, r.y - s.y) : .infinity
                text += String(format: "; estimate (%.2f, %.2f) floor %@, error %.2f m, %@", r.x, r.y, r.floorId, err,
                               r.localized ? "localized" : "not localized")
            }
            if let node = building.graph.nodes.filter({ $0.floorId == s.floorId })
                .min(by: { hypot($0.position.x - s.x, $0.position.y - s.y) < hypot($1.position.x - s.x, $1.position.y - s.y) }) {
                text += String(format: "; nearest node %@ at %.2f m", node.id, hypot(node.position.x - s.x, node.position.y - s.y))
            }
            return text
        }
        for cue in n.wrongCues {
            out.append(String(format: "  WRONG %7.2f s '%@': ", cue.t, cue.text) + place(cue.t))
            let near = turns.filter { abs($0.t - cue.t) <= contextSeconds }
            out.append("    true turns near: " + (near.isEmpty ? "none" : near.map { describe($0, track, building) }.joined(separator: "; ")))
            out += context(cue.t)
        }
        for turn in n.missingTurns {
            out.append("  MISSING " + describe(turn, track, building) + ": " + place(turn.t))
            out += context(turn.t)
        }
        for moment in score.unsureGuidance?.unsafeMoments ?? [] {
            out.append(String(format: "  UNSAFE %7.2f s '%@' (%.2f m free from the true pose): ", moment.t, moment.action,
                              moment.freeWalkMeters) + place(moment.t))
            out += context(moment.t)
        }
        return out
    }

    /// "12.30 s left 88 deg at node-7 (passed 1.62 m from it)".
    private static func describe(_ turn: TrueTurn, _ track: TruthTrack, _ building: Building) -> String {
        let s = track.state(at: turn.t)
        let d = building.graph.nodes.first { $0.id == turn.nodeId }.map { hypot($0.position.x - s.x, $0.position.y - s.y) } ?? .nan
        return String(format: "%.2f s %@ %.0f deg at %@ (passed %.2f m from it%@)", turn.t, turn.direction, turn.angleDeg,
                      turn.nodeId, d, turn.secondHalfOfJog ? ", second half of a jog" : "")
    }
}
