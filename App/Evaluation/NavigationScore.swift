import Foundation
import Maps
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
}

/// Navigation figures of one walk, scored against truth.
///
/// Method (documented in docs/evaluation.md): true turns are found from the truth path — every graph node
/// passed within `passRadiusMeters` where the walking direction 2 m before and 2 m after differs by more
/// than `turnThresholdDeg`. A cue is a spoken phrase containing "now" and "left"/"right" (the English
/// template's cue form, see Navigation/Locales/en.json). Each true turn after first convergence should
/// have a cue of the same direction in the `cueWindowSeconds` before the closest approach.
public struct NavigationScore: Codable, Sendable, Equatable {
    /// True turns after the first convergence and before arrival was announced (the ones guidance is
    /// responsible for).
    public var expectedTurns: [TrueTurn]
    /// For each expected turn that was cued: meters walked between the cue and the control point
    /// (positive = the cue came before the point).
    public var cueDistancesBeforeMeters: [Double]
    /// Expected turns with no cue of the right direction.
    public var missingInstructions: Int
    /// Cues whose direction disagrees with the next true turn (or with no true turn near).
    public var wrongInstructions: Int
    /// True when an arrival phrase was spoken.
    public var arrivalAnnounced: Bool
    /// True distance to the destination when arrival was spoken, meters.
    public var arrivalDistanceMeters: Double?
    /// Seconds from each wrong-way/off-route correction to the next route instruction.
    public var rerouteSeconds: [Double]

    /// Radius within which the truth path counts as passing a graph node, meters.
    public static let passRadiusMeters = 1.5
    /// Direction change above which passing a node counts as a turn, degrees.
    public static let turnThresholdDeg = 35.0
    /// How long before the closest approach a cue may come, seconds.
    public static let cueWindowSeconds = 8.0

    /// Scores spoken announcements against the truth track on `building`, toward `destination`
    /// (point-of-interest id or name, optional). `convergenceT` is the first localized time (nil = never).
    public init(announcements: [(t: Double, text: String)], truth: TruthTrack, building: Building,
                destination: String?, convergenceT: Double?) {
        // Guidance is responsible for the turns between first convergence and the arrival announcement.
        let arrivalT = announcements.first { Self.isArrival($0.text) }?.t ?? .infinity
        let turns = Self.trueTurns(truth: truth, building: building).filter {
            convergenceT != nil && $0.passTimes.first! > convergenceT! && $0.passTimes.first! < arrivalT
        }
        expectedTurns = turns
        var distances: [Double] = []
        var missing = 0
        var usedCues = Set<Int>()
        let cues: [(index: Int, t: Double, direction: String)] = announcements.enumerated().compactMap { (i, a) in
            let text = a.text.lowercased()
            guard text.contains("now") else { return nil }
            if text.contains("left") { return (i, a.t, "left") }
            if text.contains("right") { return (i, a.t, "right") }
            return nil
        }
        for turn in turns {
            if let cue = cues.last(where: { $0.t <= turn.t && $0.t >= turn.t - Self.cueWindowSeconds && $0.direction == turn.direction }) {
                usedCues.insert(cue.index)
                // Distance to the first node of the turn not yet passed when the cue was spoken.
                let passT = turn.passTimes.first { $0 >= cue.t } ?? turn.t
                distances.append(truth.distanceWalked(at: passT) - truth.distanceWalked(at: cue.t))
            } else {
                missing += 1
            }
        }
        cueDistancesBeforeMeters = distances
        missingInstructions = missing
        wrongInstructions = cues.filter { cue in
            guard !usedCues.contains(cue.index) else { return false }
            // A cue with a matching true turn shortly after it is not wrong (it may have been a repeat).
            return !turns.contains { $0.direction == cue.direction && $0.t >= cue.t - 2 && $0.t <= cue.t + Self.cueWindowSeconds }
        }.count

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

    /// True for the arrival phrase ("Arrived. Room 312 is on your left...").
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

    /// The turns the truth path makes at graph nodes (see the type's documentation). Passes of nodes less
    /// than `mergeMeters` apart along the path (a corner with a door node beside it, a cut corner spread
    /// over two control points) are one turn, measured from 2 m before the first to 2 m after the last.
    public static func trueTurns(truth: TruthTrack, building: Building) -> [TrueTurn] {
        guard truth.records.count > 2 else { return [] }
        let records = truth.records
        var passes: [(index: Int, node: GraphNode)] = []
        for node in building.graph.nodes {
            // Closest approaches: local minima of distance below the pass radius.
            var bestIndex: Int?
            var bestDistance = Double.infinity
            for (i, r) in records.enumerated() {
                let d = r.floorId == node.floorId ? hypot(r.x - node.position.x, r.y - node.position.y) : .infinity
                if d < passRadiusMeters {
                    if d < bestDistance { bestDistance = d; bestIndex = i }
                } else if let b = bestIndex {
                    passes.append((b, node))
                    bestIndex = nil
                    bestDistance = .infinity
                }
            }
            if let b = bestIndex { passes.append((b, node)) }
        }
        passes.sort { $0.index < $1.index }
        var groups: [[(index: Int, node: GraphNode)]] = []
        for p in passes {
            if let last = groups.last?.last,
               truth.cumulativeDistanceMeters[p.index] - truth.cumulativeDistanceMeters[last.index] < mergeMeters {
                groups[groups.count - 1].append(p)
            } else {
                groups.append([p])
            }
        }
        return groups.compactMap { group in
            // A walk that ends at the group's last node (the destination's door) has no path after it:
            // measure the turn at the first node then.
            (turn(first: group.first!.index, last: group.last!.index, nodeId: group.first!.node.id, truth: truth)
                ?? turn(first: group.first!.index, last: group.first!.index, nodeId: group.first!.node.id, truth: truth))
                .map { var t = $0; t.passTimes = group.map { records[$0.index].t }; return t }
        }
    }

    /// Node passes closer than this along the path form one turn, meters.
    public static let mergeMeters = 2.0

    private static func turn(first: Int, last: Int, nodeId: String, truth: TruthTrack) -> TrueTurn? {
        let records = truth.records
        let cum = truth.cumulativeDistanceMeters
        let before = records.indices.last(where: { cum[$0] <= cum[first] - 2 && $0 < first }) ?? 0
        let after = records.indices.first(where: { cum[$0] >= cum[last] + 2 && $0 > last }) ?? records.count - 1
        // At the ends of the walk (a cut corner into the destination's door) at least 0.3 m of path is
        // needed on each side to tell a direction.
        guard cum[first] - cum[before] >= 0.3, cum[after] - cum[last] >= 0.3 else { return nil }
        let a = records[before], m1 = records[first], m2 = records[last], b = records[after]
        let inAngle = atan2(m1.y - a.y, m1.x - a.x)
        let outAngle = atan2(b.y - m2.y, b.x - m2.x)
        var d = outAngle - inAngle
        while d > .pi { d -= 2 * .pi }
        while d < -.pi { d += 2 * .pi }
        let deg = d * 180 / .pi
        guard abs(deg) > turnThresholdDeg, abs(deg) < 150 else { return nil }
        return TrueTurn(nodeId: nodeId, t: m2.t, passTimes: [m1.t], angleDeg: deg, direction: deg > 0 ? "left" : "right")
    }
}
