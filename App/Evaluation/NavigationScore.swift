import Foundation
import Maps
import Navigation
import SessionFormat

/// A turn the traveler truly made at a control point of the graph.
public struct TrueTurn: Codable, Sendable, Equatable {
    /// Graph node id of the control point.
    public var nodeId: String
    /// Time of closest approach to the last node of the turn, seconds (cues must come before it).
    public var t: Double
    /// Times of closest approach to each node the turn passes (a corner may span a door node and a
    /// control point), seconds, increasing.
    public var passTimes: [Double]
    /// Signed change of walking direction, degrees, positive = left (counter-clockwise).
    public var angleDeg: Double
    /// "left" or "right".
    public var direction: String
    /// Time the turn begins: where the path's change of direction first exceeds the stretch threshold
    /// (about 1.7 m before a sharp corner, earlier for a cut one), seconds.
    public var beginT: Double
    /// True for the second half of a jog (two opposite turns close together that leave the direction
    /// unchanged): the navigator announces a jog as one slight turn toward its first half, so this half is
    /// never expected to be cued (a cue of its direction is not wrong either).
    public var secondHalfOfJog = false
}

/// A phrase spoken at a time.
public struct SpokenCue: Codable, Sendable, Equatable {
    /// Time, seconds (the walk's clock).
    public var t: Double
    /// The phrase.
    public var text: String
}

/// Navigation figures of one walk, scored against truth.
///
/// Method (documented in docs/evaluation.md): true turns are found from the truth track itself — a change
/// of walking direction of more than `turnThresholdDeg` over a few meters of walking, matched to the graph
/// node (control point) where the route makes that turn (see `trueTurns`); how close the walker passes the
/// node does not matter, people cut corners. A cue is a phrase that tells the traveler to turn left or right
/// at once (see `cueDirection`: "Turn left now.", "Then turn right.", "Turn left, then go 8 meters."). Each
/// true turn after first
/// convergence should have a cue of the same direction in the `cueWindowSeconds` before the closest
/// approach to its node.
public struct NavigationScore: Codable, Sendable, Equatable {
    /// True turns after the first convergence and before arrival was announced (the ones guidance is
    /// responsible for).
    public var expectedTurns: [TrueTurn]
    /// For each expected turn that was cued: meters walked between the cue and the control point
    /// (positive = the cue came before the point).
    public var cueDistancesBeforeMeters: [Double]
    /// Expected turns with no cue of the right direction.
    public var missingInstructions: Int
    /// The turns counted in `missingInstructions`.
    public var missingTurns: [TrueTurn]
    /// Cues whose direction disagrees with the next true turn (or with no true turn near).
    public var wrongInstructions: Int
    /// The cues counted in `wrongInstructions`: time (seconds) and text, for people to look at.
    public var wrongCues: [SpokenCue]
    /// True when an arrival phrase was spoken.
    public var arrivalAnnounced: Bool
    /// True distance to the destination when arrival was spoken, meters.
    public var arrivalDistanceMeters: Double?
    /// Seconds from each wrong-way/off-route correction to the next route instruction.
    public var rerouteSeconds: [Double]
    /// For each expected turn cued by a "now" cue ("Turn left now."): meters walked (truth) between the
    /// estimated END of the cue (its time + `SpeechTimingModel` duration, espeak-ng calibrated, 175 words per
    /// minute) and the control point; positive = the cue was over before the point (issue 17 wants >= 0.5 m).
    /// Nil in scores made before it existed.
    public var nowCueEndBeforeMeters: [Double]?

    /// A "now" cue should end at least this far before its control point, meters (issue 17).
    public static let nowCueEndMarginMeters = 0.5
    /// The duration model used for `nowCueEndBeforeMeters` (English phrase book at espeak-ng's default rate).
    public static let speechTiming = SpeechTimingModel.calibrated(language: "en")

    /// Change of walking direction above which a turn is a true turn, degrees (see `trueTurns`).
    public static let turnThresholdDeg = 35.0
    /// How long before the closest approach a cue may come, seconds.
    public static let cueWindowSeconds = 8.0

    /// Scores spoken announcements against the truth track on `building`, toward `destination`
    /// (point-of-interest id or name, optional). `convergenceT` is the first localized time (nil = never).
    public init(announcements: [(t: Double, text: String)], truth: TruthTrack, building: Building,
                destination: String?, convergenceT: Double?) {
        // Guidance is responsible for the turns between first convergence and the arrival announcement.
        let arrivalT = announcements.first { Self.isArrival($0.text) }?.t ?? .infinity
        // Every change of direction the navigator may name, from a bend ("Bear left now") up: what a cue
        // may be for. Turns begun before convergence count here (a cue said during them is right).
        let anyTurns = Self.trueTurns(truth: truth, building: building, minimumAngleDeg: TurnClassifier.straightBelowDeg)
        // The turns a cue is required for: begun after convergence, before arrival, of more than
        // `turnThresholdDeg` (a jog counts by its larger half), not the second half of a jog.
        let turns = anyTurns.enumerated().filter { (i, turn) in
            guard let c = convergenceT, turn.beginT > c, turn.t < arrivalT, !turn.secondHalfOfJog else { return false }
            var size = abs(turn.angleDeg)
            if i + 1 < anyTurns.count, anyTurns[i + 1].secondHalfOfJog { size = max(size, abs(anyTurns[i + 1].angleDeg)) }
            return size > Self.turnThresholdDeg
        }.map(\.1)
        expectedTurns = turns
        var distances: [Double] = []
        var endDistances: [Double] = []
        var missing: [TrueTurn] = []
        var usedCues = Set<Int>()
        let cues: [(index: Int, t: Double, direction: String)] = announcements.enumerated().compactMap { (i, a) in
            Self.cueDirection(a.text).map { (i, a.t, $0) }
        }
        for turn in turns {
            if let cue = cues.last(where: { $0.t <= turn.t && $0.t >= turn.t - Self.cueWindowSeconds && $0.direction == turn.direction }) {
                usedCues.insert(cue.index)
                // Distance to the first node of the turn not yet passed when the cue was spoken.
                let passT = turn.passTimes.first { $0 >= cue.t } ?? turn.t
                distances.append(truth.distanceWalked(at: passT) - truth.distanceWalked(at: cue.t))
            } else {
                missing.append(turn)
            }
        }
        cueDistancesBeforeMeters = distances
        // The "now" cue of each expected turn (the last one of its direction in the window before it, each
        // used once): a chained "Then turn right." said right after it may be the turn's last cue above.
        var usedNowCues = Set<Int>()
        for turn in turns {
            guard let cue = cues.last(where: { $0.t <= turn.t && $0.t >= turn.t - Self.cueWindowSeconds
                && $0.direction == turn.direction && !usedNowCues.contains($0.index)
                && Self.isNowCue(announcements[$0.index].text) }) else { continue }
            usedNowCues.insert(cue.index)
            let passT = turn.passTimes.first { $0 >= cue.t } ?? turn.t
            let endT = cue.t + Self.speechTiming.durationSeconds(announcements[cue.index].text)
            endDistances.append(truth.distanceWalked(at: passT) - truth.distanceWalked(at: endT))
        }
        nowCueEndBeforeMeters = endDistances
        missingInstructions = missing.count
        missingTurns = missing
        let wrong = cues.filter { cue in
            guard !usedCues.contains(cue.index) else { return false }
            // A cue with a true turn or bend of its direction shortly after it (or under way) is not wrong.
            if anyTurns.contains(where: { $0.direction == cue.direction && $0.t >= cue.t - 2 && $0.t <= cue.t + Self.cueWindowSeconds }) {
                return false
            }
            // Nor is one the traveler did not follow: the route from the true pose turns that way next.
            return !Self.routeFromTruthTurns(cue.direction, at: cue.t, truth: truth, building: building, destination: destination)
        }
        wrongInstructions = wrong.count
        wrongCues = wrong.map { SpokenCue(t: $0.t, text: announcements[$0.index].text) }

        let arrival = announcements.first { Self.isArrival($0.text) }
        arrivalAnnounced = arrival != nil
        if let arrival, let destination, !truth.isEmpty, let target = Self.destinationPosition(destination, in: building) {
            let s = truth.state(at: arrival.t)
            arrivalDistanceMeters = s.floorId == target.floorId ? hypot(s.x - target.point.x, s.y - target.point.y) : nil
        }
        var reroutes: [Double] = []
        for (i, a) in announcements.enumerated() {
            let text = a.text.lowercased()
            guard text.contains("wrong way") || text.contains("off route") else { continue }
            if let next = announcements[(i + 1)...].first(where: {
                let t = $0.text.lowercased()
                return !t.contains("wrong way") && !t.contains("off route")
            }) {
                reroutes.append(next.t - a.t)
            }
        }
        rerouteSeconds = reroutes
    }

    /// The direction a phrase tells the traveler to turn at once, "left" or "right", nil for any other
    /// phrase. English templates (Navigation/Locales/en.json), matched by whole words: a cue ("Turn left
    /// now.", "Bear right now.", "Sharp left now."), the cue chained right after another one ("Then turn
    /// left.", said for a turn less than 3 m after the first) and a departure that starts with a turn ("Turn
    /// right, then go 10 meters.", said on first localizing when the route turns within 1.5 m).
    /// Only the first sentence counts: a route start merged with the next maneuver ("Turn left, then go 10
    /// meters. Then turn right.") is a cue for its first turn only.
    public static func cueDirection(_ text: String) -> String? {
        let firstSentence = text.components(separatedBy: ". ").first ?? text
        let words = firstSentence.lowercased().split { !$0.isLetter }.map(String.init)
        guard let first = words.first, first != "arrived", first != "near" else { return nil }
        let isCue = words.contains("now") || first == "then"
            || (words.count >= 3 && first == "turn" && words[2] == "then")
        guard isCue else { return nil }
        let left = words.contains("left"), right = words.contains("right")
        if left == right { return nil }
        return left ? "left" : "right"
    }

    /// True for a cue to turn at once, said at the turn ("Turn left now.", "Bear right now."): not a
    /// chained "Then turn left." nor a route start.
    public static func isNowCue(_ text: String) -> Bool {
        cueDirection(text) != nil && text.lowercased().split { !$0.isLetter }.contains("now")
    }

    /// True for the arrival phrase ("Arrived. Room 312 is on your left...").
    /// How far ahead of the true position the route's next turn may be for a cue of its direction to be right
    /// under the true pose, meters: the navigator starts a "now" cue so that it ends 0.5 m before the control
    /// point (about 2.3 m before it at walking speed, the suite's median cue distance) and chains a second turn
    /// up to 3 m after the first.
    public static let truthRouteTurnWithinMeters = 4.0

    /// True when the shortest route to `destination` from the true pose at `t` (a navigator given the truth, as if
    /// localized exactly) makes its next turn or bend toward `direction` ("left"/"right") within
    /// `truthRouteTurnWithinMeters`: the cue was right and the traveler did not follow it (the wrong-turn walks walk
    /// past the turn on purpose). False without a destination or a route.
    static func routeFromTruthTurns(_ direction: String, at t: Double, truth: TruthTrack, building: Building,
                                    destination: String?) -> Bool {
        guard let destination, !truth.isEmpty,
              let navigator = try? Navigator(building: building, destinationId: destination) else { return false }
        let s = truth.state(at: t)
        _ = navigator.update(NavigationInput(t: t, positionInMap: Point2(s.x, s.y), floorId: s.floorId,
                                             headingRad: s.headingRad, isLocalized: true))
        guard let route = navigator.currentRoute,
              let turn = route.maneuvers.first(where: { ($0.turnAngleDeg.map { abs($0) } ?? 0) >= TurnClassifier.straightBelowDeg })
        else { return false }
        return turn.distanceFromStartMeters <= truthRouteTurnWithinMeters
            && (turn.turnAngleDeg! > 0 ? "left" : "right") == direction
    }

    static func isArrival(_ text: String) -> Bool {
        let t = text.lowercased()
        return t.hasPrefix("arrived") || t.contains("you have arrived")
    }

    /// Position of a destination given by point-of-interest id or name, or graph node id.
    static func destinationPosition(_ key: String, in building: Building) -> (floorId: String, point: Point2)? {
        if let found = building.pointOfInterest(idOrName: key) { return (found.floorId, found.poi.position) }
        if let n = building.graph.nodes.first(where: { $0.id == key }) { return (n.floorId, n.position) }
        return nil
    }

    // MARK: - True turns from the truth track

    /// Half-width of the stretch of walking over which the change of direction at a point is measured:
    /// the direction of the path over this distance before the point against the direction over this
    /// distance after it, meters.
    public static let headingWindowMeters = 2.0
    /// Points where that change exceeds this form a turn's stretch (its total angle is then measured from
    /// just before the stretch to just after it, so a corner cut wide over several meters keeps its full
    /// angle), degrees.
    public static let turnStretchThresholdDeg = 20.0
    /// A true turn is tied to a graph node at most this far from the turn's corner (where the path's line
    /// before the turn meets its line after it), meters.
    public static let turnMatchRadiusMeters = 4.0
    /// A node with two or more edges on the floor is a match only when some pair of its edges leads in and
    /// out within this angle of the path's directions before and after the turn, degrees.
    public static let edgeAlignmentToleranceDeg = 60.0
    /// Opposite turns closer than this along the path that cancel out are a jog (the navigator collapses
    /// jogs of up to 1.5 m between their nodes; a walker rounding both corners spreads them), meters.
    public static let jogMaxMeters = 3.0
    /// Stretches of one direction closer than this along the path are one turn (a corner cut on the
    /// diagonal), meters.
    public static let mergeGapMeters = 6.0
    /// Resampling step along the path, meters.
    static let sampleStepMeters = 0.1
    /// A reversal sharper than `cuspAngleDeg` between the 0.3 m before and after a point is a turn-around
    /// in place (the end of a wrong turn): the path is split there and each part is scored on its own.
    static let cuspAngleDeg = 160.0
    static let cuspWindowMeters = 0.3
    /// At the ends of a stretch of walking at least this much path is needed on each side of a point to
    /// tell its change of direction, meters.
    static let minimumSideMeters = 0.5

    /// One resampled point of the truth path.
    struct PathSample { var t: Double; var x: Double; var y: Double }

    /// The true turns of the walk, detected from the truth track alone (no node proximity, no route):
    ///
    /// 1. the path is resampled every 0.1 m of walking (standing still adds nothing), cut at floor changes
    ///    and at turn-arounds in place;
    /// 2. at each point the signed change of direction between the `headingWindowMeters` walked before and
    ///    after it is computed; consecutive points with a change above `turnStretchThresholdDeg`, same
    ///    sign, form one turn (as do such stretches of one sign less than `mergeGapMeters` apart that match
    ///    the same control point: a corner cut on the diagonal), whose angle is the direction after the stretch against the direction before
    ///    it (wrapped to +-180 degrees); turns of more than `turnThresholdDeg` and less than 150 degrees
    ///    are kept; a stretch of 150 degrees or more (a U-shaped route: two turns a meter or two apart) is
    ///    cut where the path's direction is halfway round and each part measured on its own;
    /// 3. each turn is matched to the route's control point it belongs to: the nearest graph node on the
    ///    floor within `turnMatchRadiusMeters` of the turn's corner where the graph can make that turn (an
    ///    edge pair aligned with the path before and after it within `edgeAlignmentToleranceDeg`, the same
    ///    side, at least a slight turn); dead ends (one edge) never match, nodes without edges (a graph
    ///    given without them) match by distance only. A turn with no such node is not at a control point
    ///    (an incidental change of direction) and is not expected to be cued.
    ///
    /// The turn's time is the closest approach to its node.
    ///
    /// `minimumAngleDeg` (default `turnThresholdDeg`) is the smallest turn kept. Two consecutive opposite
    /// turns less than `jogMaxMeters` of walking apart whose angles cancel to within 20 degrees are a jog:
    /// the second is flagged `secondHalfOfJog`.
    public static func trueTurns(truth: TruthTrack, building: Building, minimumAngleDeg: Double = turnThresholdDeg) -> [TrueTurn] {
        guard truth.records.count > 2 else { return [] }
        // Same-floor neighbours of every node, for the turn check.
        var nodeById: [String: GraphNode] = [:]
        for n in building.graph.nodes where nodeById[n.id] == nil { nodeById[n.id] = n }
        var neighbours: [String: [Point2]] = [:]
        for e in building.graph.edges {
            guard let a = nodeById[e.from], let b = nodeById[e.to], a.id != b.id, a.floorId == b.floorId else { continue }
            neighbours[a.id, default: []].append(b.position)
            neighbours[b.id, default: []].append(a.position)
        }
        var turns: [TrueTurn] = []
        for run in walkingRuns(truth) {
            let nodes = building.graph.nodes.filter { $0.floorId == run.floorId }
            for piece in splitAtTurnArounds(run.samples) {
                var found = Self.turns(in: piece, nodes: nodes, neighbours: neighbours, minimumAngleDeg: minimumAngleDeg)
                for i in found.indices.dropFirst() where !found[i - 1].secondHalfOfJog {
                    let a = found[i - 1], b = found[i]
                    if a.angleDeg * b.angleDeg < 0, abs(a.angleDeg + b.angleDeg) < TurnClassifier.straightBelowDeg,
                       truth.distanceWalked(at: b.t) - truth.distanceWalked(at: a.t) < jogMaxMeters {
                        found[i].secondHalfOfJog = true
                    }
                }
                turns += found
            }
        }
        return turns.sorted { $0.t < $1.t }
    }

    /// The truth resampled every `sampleStepMeters` of walking, one array per stay on a floor.
    static func walkingRuns(_ truth: TruthTrack) -> [(floorId: String, samples: [PathSample])] {
        let r = truth.records, cum = truth.cumulativeDistanceMeters
        var runs: [(floorId: String, samples: [PathSample])] = []
        var i = 0
        while i < r.count {
            var j = i
            while j + 1 < r.count && r[j + 1].floorId == r[i].floorId { j += 1 }
            var samples: [PathSample] = []
            var s = cum[i]
            var k = i
            while k < j {
                let a = r[k], b = r[k + 1], len = cum[k + 1] - cum[k]
                if len <= 1e-12 || s > cum[k + 1] { k += 1; continue }
                let f = max(0, (s - cum[k]) / len)
                samples.append(PathSample(t: a.t + f * (b.t - a.t), x: a.x + f * (b.x - a.x), y: a.y + f * (b.y - a.y)))
                s += sampleStepMeters
            }
            if j > i, let last = samples.last, hypot(r[j].x - last.x, r[j].y - last.y) > 1e-9 {
                samples.append(PathSample(t: r[j].t, x: r[j].x, y: r[j].y))
            }
            if samples.count > 1 { runs.append((r[i].floorId, samples)) }
            i = j + 1
        }
        return runs
    }

    private static func direction(_ a: PathSample, _ b: PathSample) -> Double { atan2(b.y - a.y, b.x - a.x) }

    private static func wrapDeg(_ rad: Double) -> Double {
        var d = rad
        while d > .pi { d -= 2 * .pi }
        while d <= -.pi { d += 2 * .pi }
        return d * 180 / .pi
    }

    /// Cuts a resampled stretch at each turn-around in place (the sharpest point of each cluster of points
    /// whose direction reverses by more than `cuspAngleDeg` within `cuspWindowMeters`).
    static func splitAtTurnArounds(_ samples: [PathSample]) -> [[PathSample]] {
        let m = max(1, Int((cuspWindowMeters / sampleStepMeters).rounded()))
        guard samples.count > 2 * m else { return [samples] }
        var cuts: [Int] = []
        var k = m
        while k < samples.count - m {
            let change = abs(wrapDeg(direction(samples[k], samples[k + m]) - direction(samples[k - m], samples[k])))
            if change > cuspAngleDeg {
                // Sharpest point of this cluster.
                var best = k, bestChange = change
                var q = k + 1
                while q < samples.count - m {
                    let c = abs(wrapDeg(direction(samples[q], samples[q + m]) - direction(samples[q - m], samples[q])))
                    guard c > cuspAngleDeg else { break }
                    if c > bestChange { best = q; bestChange = c }
                    q += 1
                }
                cuts.append(best)
                k = q
            } else {
                k += 1
            }
        }
        var pieces: [[PathSample]] = []
        var from = 0
        for c in cuts { pieces.append(Array(samples[from...c])); from = c }
        pieces.append(Array(samples[from...]))
        return pieces.filter { $0.count > 1 }
    }

    /// Turns in one stretch without turn-arounds (steps 2 and 3 of `trueTurns`).
    private static func turns(in p: [PathSample], nodes: [GraphNode], neighbours: [String: [Point2]],
                              minimumAngleDeg: Double) -> [TrueTurn] {
        let n = p.count
        let w = max(1, Int((headingWindowMeters / sampleStepMeters).rounded()))
        let side = max(1, Int((minimumSideMeters / sampleStepMeters).rounded()))
        guard n > 2 * side else { return [] }
        var change = [Double](repeating: 0, count: n)
        for k in side..<(n - side) {
            change[k] = wrapDeg(direction(p[k], p[min(n - 1, k + w)]) - direction(p[max(0, k - w)], p[k]))
        }
        // Stretches of one sign above the threshold.
        // (Looking for bends smaller than the default, the threshold is lowered with them.)
        let threshold = min(turnStretchThresholdDeg, 0.6 * minimumAngleDeg)
        var stretches: [(from: Int, to: Int, left: Bool)] = []
        var k = 0
        while k < n {
            guard abs(change[k]) > threshold else { k += 1; continue }
            let left = change[k] > 0
            var end = k
            while end + 1 < n && abs(change[end + 1]) > threshold && (change[end + 1] > 0) == left { end += 1 }
            stretches.append((k, end, left))
            k = end + 1
        }
        // A corner cut on a straight diagonal bends twice, where the walker leaves the route and where it
        // rejoins it: stretches of the same sign less than `mergeGapMeters` apart are one turn (unless
        // they belong to different control points, or together turn back on themselves, which two turns
        // of a U-shaped route do).
        let gap = Int((mergeGapMeters / sampleStepMeters).rounded())
        var groups: [[(from: Int, to: Int, left: Bool)]] = []
        for st in stretches {
            if let last = groups.last?.last, last.left == st.left, st.from - last.to <= gap {
                groups[groups.count - 1].append(st)
            } else {
                groups.append([st])
            }
        }
        /// A measured turn: the stretch `from...to`, the lines before and after it (two samples each).
        struct Candidate { var from: Int; var to: Int; var in1: Int; var in2: Int; var out1: Int; var out2: Int
            var before: Int; var after: Int }
        func whole(_ from: Int, _ to: Int) -> Candidate {
            let before = max(0, from - w), after = min(n - 1, to + w)
            return Candidate(from: from, to: to, in1: before, in2: from, out1: to, out2: after, before: before, after: after)
        }
        func angle(_ c: Candidate) -> Double { wrapDeg(direction(p[c.out1], p[c.out2]) - direction(p[c.in1], p[c.in2])) }
        // A group that turns back on itself (150 degrees or more) is two turns of a U-shaped route (turns
        // in place were cut off above): it is cut where the path's direction is halfway round (the
        // straight bit between the two corners), and each part is measured against the direction there.
        let local = max(1, Int((cuspWindowMeters / sampleStepMeters).rounded()))
        func match(_ c: Candidate) -> (node: GraphNode, t: Double)? {
            let inDir = direction(p[c.in1], p[c.in2]), outDir = direction(p[c.out1], p[c.out2])
            // The turn's corner: where the path's line before the turn meets its line after it (the route's
            // corner however the walker rounded it).
            let corner = intersection(p[c.in1], p[c.in2], p[c.out1], p[c.out2]) ?? Point2(p[c.from].x, p[c.from].y)
            return matchNode(p[c.before...c.after], corner: corner, angleDeg: angle(c), inDir: inDir, outDir: outDir,
                             nodes: nodes, neighbours: neighbours)
        }
        var candidates: [Candidate] = []
        var split: [[(from: Int, to: Int, left: Bool)]] = []
        for g in groups {
            // Stretches that belong to different control points (two bends of one direction a few meters
            // apart) are not one cut corner.
            let own = Set(g.compactMap { match(whole($0.from, $0.to))?.node.id })
            if g.count > 1 && own.count > 1 { split += g.map { [$0] } } else { split.append(g) }
        }
        for g in split {
            let c = whole(g.first!.from, g.last!.to)
            guard abs(angle(c)) >= 150, c.to - c.from >= 4 else { candidates.append(c); continue }
            // Where the path's own direction is halfway round (the sign from the stretches: near 180
            // degrees the measured angle cannot tell left from right).
            let total = (g.first!.left ? 1.0 : -1.0) * abs(angle(c))
            let target = direction(p[c.in1], p[c.in2]) + total / 2 * .pi / 180
            var saddle = c.from, best = Double.infinity
            for q in c.from...c.to {
                let off = abs(wrapDeg(direction(p[max(0, q - local)], p[min(n - 1, q + local)]) - target))
                if off < best { best = off; saddle = q }
            }
            let s1 = max(0, saddle - local), s2 = min(n - 1, saddle + local)
            candidates.append(Candidate(from: c.from, to: saddle, in1: c.in1, in2: c.in2, out1: s1, out2: s2,
                                        before: c.before, after: s2))
            candidates.append(Candidate(from: saddle, to: c.to, in1: s1, in2: s2, out1: c.out1, out2: c.out2,
                                        before: s1, after: c.after))
        }
        var out: [TrueTurn] = []
        for c in candidates {
            let a = angle(c)
            guard abs(a) > minimumAngleDeg, abs(a) < 150 else { continue }
            guard let found = match(c) else { continue }
            out.append(TrueTurn(nodeId: found.node.id, t: found.t, passTimes: [found.t], angleDeg: a,
                                direction: a > 0 ? "left" : "right", beginT: min(p[c.from].t, found.t)))
        }
        return out
    }

    /// Intersection of the line through a1, a2 with the line through b1, b2 (nil when nearly parallel).
    private static func intersection(_ a1: PathSample, _ a2: PathSample, _ b1: PathSample, _ b2: PathSample) -> Point2? {
        let dax = a2.x - a1.x, day = a2.y - a1.y, dbx = b2.x - b1.x, dby = b2.y - b1.y
        let denom = dax * dby - day * dbx
        let la = hypot(dax, day), lb = hypot(dbx, dby)
        guard la > 1e-9, lb > 1e-9, abs(denom) > 1e-3 * la * lb else { return nil }
        let t = ((b1.x - a1.x) * dby - (b1.y - a1.y) * dbx) / denom
        return Point2(a1.x + t * dax, a1.y + t * day)
    }

    /// The control point a turn belongs to (step 3 of `trueTurns`) and the time of closest approach to it.
    private static func matchNode(_ stretch: ArraySlice<PathSample>, corner: Point2, angleDeg: Double, inDir: Double,
                                  outDir: Double, nodes: [GraphNode], neighbours: [String: [Point2]]) -> (node: GraphNode, t: Double)? {
        let r = turnMatchRadiusMeters
        let tolerance = edgeAlignmentToleranceDeg
        var best: (node: GraphNode, d: Double, checked: Bool)?
        for node in nodes {
            let q = node.position
            let d = hypot(corner.x - q.x, corner.y - q.y)
            guard d <= r else { continue }
            let adjacent = neighbours[node.id] ?? []
            // One edge: a dead end (a room's node) where one only arrives, departs or turns around.
            if adjacent.count == 1 { continue }
            let checked = adjacent.count >= 2
            if checked {
                // Some edge pair (in from a, out to b) must make this turn.
                var ok = false
                for a in adjacent where !ok {
                    let inEdge = atan2(q.y - a.y, q.x - a.x)
                    guard abs(wrapDeg(inEdge - inDir)) <= tolerance else { continue }
                    for b in adjacent where b != a {
                        let outEdge = atan2(b.y - q.y, b.x - q.x)
                        guard abs(wrapDeg(outEdge - outDir)) <= tolerance else { continue }
                        let graphTurn = wrapDeg(outEdge - inEdge)
                        if (graphTurn > 0) == (angleDeg > 0) && abs(graphTurn) >= TurnClassifier.straightBelowDeg { ok = true; break }
                    }
                }
                guard ok else { continue }
            }
            // Nodes the turn check applies to come first; then the nearest to the corner.
            if let b = best, (b.checked && !checked) || (b.checked == checked && b.d <= d) { continue }
            best = (node, d, checked)
        }
        guard let best else { return nil }
        var closest = Double.infinity, t = stretch.first!.t
        for s in stretch {
            let e = hypot(s.x - best.node.position.x, s.y - best.node.position.y)
            if e < closest { closest = e; t = s.t }
        }
        return (best.node, t)
    }
}
