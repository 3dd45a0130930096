// Guidance while the localizer is not sure yet: an exploratory instruction that is safe under every live
// hypothesis and leads soonest to a place where the hypotheses predict different sightings or walls, so that
// the traveler's own walking settles where they are (active localization: expected information gain over
// the hypotheses, as in Fox, Burgard & Thrun, "Active Markov localization for mobile robots", 1998, here
// with a handful of cluster hypotheses instead of a grid and four body-frame actions instead of a path
// planner). Hand-written: no library plans over a particle filter's hypotheses on a floor plan.
//
// For each action (walk ahead, turn around, turn left, turn right, then walk) and each live hypothesis
// (weight >= `minimumLiveWeight`), the planner casts the walking direction against the floor's walls:
//  - safety: the walk must stay `wallMarginMeters` (plus twice the hypothesis' position std) short of the first wall, pass no stairs landing closer than
//    `stairsClearanceMeters` and no door centre closer than `doorClearanceMeters`, under EVERY
//    live hypothesis, walked from the hypothesis' mean; from the edges of its spread (`spreadCheckStds`
//    position stds ahead, behind and to each side: the traveler stands somewhere in the cluster) it must
//    also leave `spreadMinimumWalkMeters`; the safe walk length is the shortest over them, capped at
//    `lookaheadMeters`;
//  - information: every `stepMeters` along the walk each hypothesis predicts what the camera will see: the
//    signs in its field of view (kind, range and side, bucketed) and how far the wall ahead is (ARKit planes
//    see it). Hypotheses whose predictions differ will be told apart by the localizer; the partition's entropy
//    (nats, over the live weights) is the expected information gain of walking that far.
// The action with the best gain per meter walked (turns cost `turnCostMeters` of walking) wins; without any
// gain, the safe action with the longest walk (ahead preferred) keeps the traveler moving along a corridor;
// with no safe action, or while the live hypotheses hold less than `minimumCoverage` of the weight (the cloud
// is still spread out, so safety where the traveler really is cannot be known), the advice is to walk slowly.
import Foundation
import Maps

/// One pose hypothesis as the planner sees it.
public struct PoseCandidate: Sendable, Equatable {
    /// Normalised weight, 0...1.
    public var weight: Double
    /// Floor id.
    public var floorId: String
    /// Position, meters, map frame.
    public var positionInMap: Point2
    /// Camera (walking) heading, radians CCW from map +x.
    public var headingRad: Double
    /// Position spread of the hypothesis (largest axis), meters: a cluster spread over a whole corridor is no
    /// pose to plan from.
    public var positionStdMeters: Double
    /// Heading spread of the hypothesis (circular std), radians.
    public var headingStdRad: Double
    /// Creates a candidate.
    public init(weight: Double, floorId: String, positionInMap: Point2, headingRad: Double, positionStdMeters: Double = 0,
                headingStdRad: Double = 0) {
        self.weight = weight; self.floorId = floorId; self.positionInMap = positionInMap; self.headingRad = headingRad
        self.positionStdMeters = positionStdMeters; self.headingStdRad = headingStdRad
    }
}

/// An exploratory action, in the traveler's body frame.
public enum ExploratoryAction: String, Sendable, CaseIterable {
    /// Walk straight ahead.
    case ahead
    /// Turn around, then walk.
    case turnAround
    /// Turn left (90 degrees), then walk.
    case left
    /// Turn right (90 degrees), then walk.
    case right

    /// Turn relative to the current heading, radians (CCW positive).
    public var turnRad: Double {
        switch self {
        case .ahead: return 0
        case .turnAround: return Double.pi
        case .left: return Double.pi / 2
        case .right: return -Double.pi / 2
        }
    }

    /// Phrase-book key of the instruction.
    public var phraseKey: String { "disambiguate.\(rawValue)" }
}

/// What the planner advises.
public struct DisambiguationAdvice: Sendable, Equatable {
    /// The instruction, or nil when no action is safe under every live hypothesis.
    public var action: ExploratoryAction?
    /// Length of the walk that is safe under every live hypothesis, meters (0 when none).
    public var safeWalkMeters: Double
    /// Expected information gain of the walk (entropy of the hypotheses' prediction partition), nats.
    public var informationNats: Double
    /// Distance at which the hypotheses' predictions first differ along the chosen walk, meters (nil if never).
    public var distinguishingMeters: Double?
    /// Phrase-book key to speak.
    public var phraseKey: String { action?.phraseKey ?? "disambiguate.unsure" }
}

/// Tunables of the planner. Meters, radians.
public struct DisambiguationOptions: Sendable {
    /// Hypotheses lighter than this are ignored (their weight is not "real").
    public var minimumLiveWeight = 0.05
    /// Every compact hypothesis at least this heavy must be safe under an instruction (the localizer's
    /// `rival_min_weight`: lighter ones never hold the flag off, so they are not live rivals).
    public var minimumGuardedWeight = 0.001
    /// The live hypotheses must hold at least this share of the whole weight (the weights given are the
    /// localizer's, normalised over all particles): with the cloud still spread over the floor, no instruction
    /// can be known to be safe where the traveler really is, so the advice is to walk slowly.
    public var minimumCoverage = 0.9
    /// A hypothesis spread wider than this (position std, meters) counts as no hypothesis at all: early on the
    /// whole cloud can form one connected cluster whose mean pose is meaningless.
    public var maximumSpreadMeters = 2.0
    /// The walk stops this far before the first wall ahead.
    public var wallMarginMeters = 1.0
    /// A walk must also leave `spreadMinimumWalkMeters` from points this many position stds ahead of, behind,
    /// left and right of the hypothesis' mean (0: from the mean only). Behind rough noise models, with clusters
    /// 0.4-0.8 m wide, a traveler 0.25-0.36 m from the mean was told to turn into a doorway or past the end of
    /// a wall (`wayfinder eval --explain`, docs/navigation.md).
    public var spreadCheckStds = 0.75
    /// The walk those points must leave, meters: what `wayfinder eval` asks of an instruction from the true pose.
    public var spreadMinimumWalkMeters = 2.0
    /// Those points stop this far before a wall between them and the mean (half a shoulder width), meters.
    public var spreadWallClearanceMeters = 0.2
    /// The walk must also leave `spreadMinimumWalkMeters` from every pose of the hypothesis' fan: starts anywhere
    /// between its left and right spread points, walking up to this many heading stds (`PoseCandidate.headingStdRad`)
    /// either side of its heading (0: the fan is off). A cluster's heading spread is a few degrees, and a walk along
    /// a wall half a meter to the side meets it 3 m on at 5 degrees off (`wayfinder eval --explain`, all-rough,
    /// conv-3-08, filter seed 4: the truth 0.38 m and 5.2 degrees off a hypothesis of std 0.39 m and 3.7 degrees).
    /// 1.5 std cost a third more of the directional time for no safety the 1 std did not give
    /// (docs/benchmarks.md "Nineteenth stop").
    public var headingCheckStds = 1.0
    /// The fan's half-angle is at most this, radians (a hypothesis spread wider has no heading worth a walk).
    public var maximumFanHalfAngleRad = 20.0 * Double.pi / 180
    /// A walk shorter than this is not worth an instruction (3 m: 1 m beyond the 2 m that `wayfinder eval`
    /// requires of an instruction from the true pose, so a hypothesis a few decimeters off stays safe).
    public var minimumWalkMeters = 3.0
    /// How far ahead the planner looks.
    public var lookaheadMeters = 10.0
    /// Spacing of the predicted views along the walk.
    public var stepMeters = 1.0
    /// A stairs landing closer than this to the walk makes it unsafe.
    public var stairsClearanceMeters = 1.5
    /// A walk passing closer than this to a door's centre goes through the doorway: unsafe (never through a
    /// door). Walking along a corridor past a door in its side wall passes about half the corridor's width away.
    public var doorClearanceMeters = 0.4
    /// Walking cost charged for turning before the walk (a turn is slower and less certain than walking on).
    public var turnCostMeters = 2.0
    /// Half the camera's horizontal field of view, and the range within which a sign is predicted visible.
    public var halfFieldOfViewRad = 24.0 * Double.pi / 180
    public var signRangeMeters = 10.0
    /// Buckets of the predicted view: range (m), bearing (rad), wall-ahead distance (m).
    public var rangeBucketMeters = 2.0
    public var bearingBucketRad = 16.0 * Double.pi / 180
    public var wallBucketMeters = 2.0
    /// Creates the defaults.
    public init() {}
}

/// Plans exploratory instructions over a building's floors. A value; cheap to copy (the building is shared).
public struct DisambiguationPlanner: Sendable {
    /// The building.
    public let building: Building
    /// Options.
    public var options: DisambiguationOptions

    /// Creates a planner.
    public init(building: Building, options: DisambiguationOptions = DisambiguationOptions()) {
        self.building = building
        self.options = options
    }

    /// The advice for the given hypotheses (any order; weights as the localizer normalises them, over all
    /// particles: the live ones must cover `minimumCoverage`). `perceivedWalls` are the walls the phone sees
    /// now, in the traveler's frame: an action's walk also stops `wallMarginMeters` short of the first of them,
    /// whatever the hypotheses say (none: the map's walls alone). `hypothesesExplainSightings` false (the
    /// localizer reports sightings its dominant hypothesis leaves unexplained) gives the advice with no action,
    /// as a spread-out cloud does: the traveler may stand where no hypothesis is.
    public func advise(_ hypotheses: [PoseCandidate], perceivedWalls: [PerceivedWall] = [],
                       hypothesesExplainSightings: Bool = true) -> DisambiguationAdvice {
        let usable = hypotheses.filter { $0.weight.isFinite && $0.positionStdMeters <= options.maximumSpreadMeters &&
            $0.positionInMap.x.isFinite && $0.positionInMap.y.isFinite && $0.headingRad.isFinite &&
            building.floor(id: $0.floorId) != nil }
        let live = usable.filter { $0.weight >= options.minimumLiveWeight }
        // Safety is checked under every compact hypothesis the localizer reports, however light: it reports the
        // light ones only while they are unrefuted rivals (the true place after a wrong named start starts light).
        // (Never fewer than the live ones, whatever the two options are set to.)
        let guarded = usable.filter { $0.weight >= min(options.minimumGuardedWeight, options.minimumLiveWeight) }
        let total = live.reduce(0) { $0 + $1.weight }
        // The hypotheses must also account for what was seen: a sign that the dominant one leaves unexplained was
        // made by some sign, so the traveler may stand where no hypothesis is, and no walk is known to be safe.
        guard hypothesesExplainSightings, !live.isEmpty, total > 0, total >= options.minimumCoverage - 1e-12 else {
            return DisambiguationAdvice(action: nil, safeWalkMeters: 0, informationNats: 0, distinguishingMeters: nil)
        }
        var best: (advice: DisambiguationAdvice, utility: Double)?
        var fallback: DisambiguationAdvice?
        for action in ExploratoryAction.allCases {
            var walk = safeWalkMeters(action, guarded)
            if !perceivedWalls.isEmpty {
                let seen = PerceivedWall.freeDistance(perceivedWalls, turnRad: action.turnRad, far: options.lookaheadMeters + 1)
                walk = min(walk, max(0, seen - options.wallMarginMeters))
            }
            guard walk >= options.minimumWalkMeters else { continue }
            let (gain, at) = informationGain(action, live, walkMeters: walk, total: total)
            let advice = DisambiguationAdvice(action: action, safeWalkMeters: walk, informationNats: gain,
                                              distinguishingMeters: at)
            if fallback == nil || walk > fallback!.safeWalkMeters + 1.0 { fallback = advice }
            guard gain > 1e-9, let at else { continue }
            let utility = gain / (at + (action == .ahead ? 0 : options.turnCostMeters))
            if best == nil || utility > best!.utility + 1e-12 { best = (advice, utility) }
        }
        return best?.advice ?? fallback ??
            DisambiguationAdvice(action: nil, safeWalkMeters: 0, informationNats: 0, distinguishingMeters: nil)
    }

    /// Free walking length of `action` that is safe under every hypothesis, meters (walls, stairs, doors).
    /// Each hypothesis is walked from its mean, and must also leave `spreadMinimumWalkMeters` from the edges
    /// of its spread (`spreadStarts`): the traveler stands somewhere in the cluster, not at its mean.
    public func safeWalkMeters(_ action: ExploratoryAction, _ live: [PoseCandidate]) -> Double {
        var walk = options.lookaheadMeters
        for h in live {
            guard let floor = building.floor(id: h.floorId) else { return 0 }
            let direction = h.headingRad + action.turnRad
            let spread = max(0, h.positionStdMeters)
            // The hypothesis' own spread widens the margin: its particles stand up to about two std from its mean.
            walk = walkLength(floor, from: h.positionInMap, directionRad: direction,
                              marginMeters: options.wallMarginMeters + 2 * spread, capMeters: walk)
            if walk < options.minimumWalkMeters { return max(0, walk) }
            for start in spreadStarts(floor, h.positionInMap, spread: spread, directionRad: direction) {
                let edge = walkLength(floor, from: start, directionRad: direction, marginMeters: options.wallMarginMeters,
                                      capMeters: options.lookaheadMeters)
                if edge < options.spreadMinimumWalkMeters { return max(0, min(walk, edge)) }
            }
            if options.headingCheckStds > 0 {
                let halfAngle = min(options.headingCheckStds * max(0, h.headingStdRad), options.maximumFanHalfAngleRad)
                let fan = fanWalkMeters(floor, h.positionInMap, spread: spread, directionRad: direction, halfAngleRad: halfAngle)
                if fan < options.spreadMinimumWalkMeters { return max(0, min(walk, fan)) }
            }
        }
        return max(0, walk)
    }

    /// The shortest walk any pose of a hypothesis' fan leaves, meters, looked at as far as deciding whether it
    /// reaches `spreadMinimumWalkMeters` needs: starts on the segment between the mean's left and right spread
    /// points (`spreadCheckStds` position stds, each pulled back before a wall as in `spreadStarts`), walking
    /// within `halfAngleRad` of `directionRad`. The fan is bounded by the trapezoid |s| <= reach + t tan(half
    /// angle), 0 <= t <= L (t along the walk from the mean, s to its side), a slight over-approximation: a wall
    /// crossing it at t stops the walk t - `wallMarginMeters` on (a slanted walk reaches that point no sooner), a
    /// stairs landing or a door centre within its clearance of it stops the walk that clearance before.
    /// Unlike the spread points' three walks, it also sees the end of a wall between them.
    func fanWalkMeters(_ floor: Floor, _ mean: Point2, spread: Double, directionRad: Double, halfAngleRad: Double) -> Double {
        let left = spreadOffset(floor, mean, spread: spread, directionRad: directionRad + Double.pi / 2)
        let right = spreadOffset(floor, mean, spread: spread, directionRad: directionRad - Double.pi / 2)
        let slope = tan(max(0, halfAngleRad))
        let clearance = max(options.wallMarginMeters, options.stairsClearanceMeters, options.doorClearanceMeters)
        let length = options.spreadMinimumWalkMeters + clearance
        let u = (x: cos(directionRad), y: sin(directionRad)), n = (x: -sin(directionRad), y: cos(directionRad))
        func local(_ q: Point2) -> (t: Double, s: Double) {
            let dx = q.x - mean.x, dy = q.y - mean.y
            return (dx * u.x + dy * u.y, dx * n.x + dy * n.y)
        }
        // The fan: 0 <= t <= length, -right - t slope <= s <= left + t slope, as four half-planes a t + b s <= c.
        let fan: [(a: Double, b: Double, c: Double)] = [(-1, 0, 0), (1, 0, length), (-slope, 1, left), (-slope, -1, right)]
        var walk = length - options.wallMarginMeters
        for wall in floor.walls {
            // Cyrus-Beck: the part of the wall inside the fan, as parameters [lo, hi] along it.
            let p = local(wall.from), q = local(wall.to)
            var lo = 0.0, hi = 1.0
            for h in fan where lo <= hi {
                let at = h.a * p.t + h.b * p.s - h.c, slopeAlong = h.a * (q.t - p.t) + h.b * (q.s - p.s)
                if abs(slopeAlong) < 1e-15 {
                    if at > 0 { lo = 1; hi = 0 }
                } else if slopeAlong > 0 {
                    hi = min(hi, -at / slopeAlong)
                } else {
                    lo = max(lo, -at / slopeAlong)
                }
            }
            guard lo <= hi else { continue }
            let nearest = min(p.t + lo * (q.t - p.t), p.t + hi * (q.t - p.t))
            walk = min(walk, nearest - options.wallMarginMeters)
        }
        // Within `widen` of the fan's sides (and no more than `widen` behind its start).
        func inside(_ c: (t: Double, s: Double), widen: Double) -> Bool {
            c.t >= -widen && c.s <= left + widen + c.t * slope && -c.s <= right + widen + c.t * slope
        }
        for node in building.graph.nodes where node.floorId == floor.id && node.verticalLink == .stairs {
            let c = local(node.position)
            if c.t <= length, inside(c, widen: options.stairsClearanceMeters) {
                walk = min(walk, c.t - options.stairsClearanceMeters)
            }
        }
        for door in floor.doors {
            let c = local(door.position)
            if c.t <= length, inside(c, widen: options.doorClearanceMeters) {
                walk = min(walk, c.t - options.doorClearanceMeters)
            }
        }
        return max(0, walk)
    }

    /// How far a walk from `start` along `directionRad` goes, at most `capMeters`: it stops `marginMeters`
    /// before the first wall, short of a stairs landing's clearance circle and before passing a door centre
    /// closer than `doorClearanceMeters`. Meters, >= 0.
    func walkLength(_ floor: Floor, from start: Point2, directionRad: Double, marginMeters: Double,
                    capMeters: Double) -> Double {
        var walk = min(capMeters, freeDistance(floor, from: start, directionRad: directionRad) - marginMeters)
        let end = Point2(x: start.x + walk * cos(directionRad), y: start.y + walk * sin(directionRad))
        for node in building.graph.nodes where node.floorId == floor.id && node.verticalLink == .stairs {
            if Geometry.distance(from: node.position, toSegmentFrom: start, to: end) < options.stairsClearanceMeters {
                // Stop short of the landing: the walk up to its clearance circle is still safe.
                let reach = projection(of: node.position, from: start, directionRad: directionRad) - options.stairsClearanceMeters
                walk = min(walk, max(0, reach))
            }
        }
        for door in floor.doors {
            let reach = options.doorClearanceMeters
            let doorEnd = Point2(x: start.x + walk * cos(directionRad), y: start.y + walk * sin(directionRad))
            if Geometry.distance(from: door.position, toSegmentFrom: start, to: doorEnd) < reach {
                walk = min(walk, max(0, projection(of: door.position, from: start, directionRad: directionRad) - reach))
            }
        }
        return max(0, walk)
    }

    /// The edges of one hypothesis' spread a walk is also checked from: the points `spreadCheckStds` x its
    /// position std ahead of, behind, left and right of its mean along the walking direction, each pulled back
    /// to `spreadWallClearanceMeters` before a wall between it and the mean (particles do not stand in walls);
    /// none without a spread. Sigma points of the cluster, as the unscented transform places them (Julier &
    /// Uhlmann 1997), on the axes of the walk.
    func spreadStarts(_ floor: Floor, _ mean: Point2, spread: Double, directionRad: Double) -> [Point2] {
        guard options.spreadCheckStds * spread > 1e-9 else { return [] }
        var starts: [Point2] = []
        for turn in [0, Double.pi / 2, Double.pi, -Double.pi / 2] {
            let d = directionRad + turn
            let offset = spreadOffset(floor, mean, spread: spread, directionRad: d)
            if offset > 1e-9 { starts.append(Point2(x: mean.x + offset * cos(d), y: mean.y + offset * sin(d))) }
        }
        return starts
    }

    /// How far from the mean along `directionRad` a spread point lies: `spreadCheckStds` x `spread`, pulled back
    /// to `spreadWallClearanceMeters` before a wall (particles do not stand in walls). Meters, >= 0.
    func spreadOffset(_ floor: Floor, _ mean: Point2, spread: Double, directionRad: Double) -> Double {
        let reach = options.spreadCheckStds * spread
        guard reach > 0 else { return 0 }
        return min(reach, max(0, freeDistance(floor, from: mean, directionRad: directionRad) - options.spreadWallClearanceMeters))
    }

    /// Entropy of the partition of the hypotheses by their predicted views along the walk, and the first
    /// distance at which the partition is no longer trivial.
    func informationGain(_ action: ExploratoryAction, _ live: [PoseCandidate], walkMeters: Double,
                         total: Double) -> (nats: Double, atMeters: Double?) {
        var histories = [String](repeating: "", count: live.count)
        var firstSplit: Double?
        var entropy = 0.0
        var s = options.stepMeters
        while s <= walkMeters + 1e-9 {
            for (i, h) in live.enumerated() {
                guard let floor = building.floor(id: h.floorId) else { continue }
                let direction = h.headingRad + action.turnRad
                let p = Point2(x: h.positionInMap.x + s * cos(direction), y: h.positionInMap.y + s * sin(direction))
                histories[i] += "|" + predictedView(floor, at: p, headingRad: direction)
            }
            var groups: [String: Double] = [:]
            for (i, key) in histories.enumerated() { groups[key, default: 0] += live[i].weight / total }
            let h = groups.values.reduce(0.0) { $0 - ($1 > 0 ? $1 * log($1) : 0) }
            if h > 1e-9 && firstSplit == nil { firstSplit = s }
            entropy = h
            if firstSplit != nil { break }  // the nearest place where they differ is what the walk aims for
            s += options.stepMeters
        }
        return (entropy, firstSplit)
    }

    /// What a camera at `p` looking along `headingRad` is predicted to see: visible signs (kind, range bucket,
    /// bearing bucket) and the wall-ahead bucket, as a canonical string.
    func predictedView(_ floor: Floor, at p: Point2, headingRad: Double) -> String {
        var seen: [String] = []
        for sign in floor.signs {
            let dx = sign.position.x - p.x, dy = sign.position.y - p.y
            let range = (dx * dx + dy * dy).squareRoot()
            guard range > 0.3, range <= options.signRangeMeters else { continue }
            let bearing = atan2(sin(atan2(dy, dx) - headingRad), cos(atan2(dy, dx) - headingRad))
            guard abs(bearing) <= options.halfFieldOfViewRad else { continue }
            // Readable only from in front of its face (the localizer's rule, loosely).
            guard sign.facing.x * -dx + sign.facing.y * -dy > 0.17 * range else { continue }
            // Not through a wall: stop 5 cm short of the sign (it hangs on one).
            let t = max(0, (range - 0.05) / range)
            let q = Point2(x: p.x + dx * t, y: p.y + dy * t)
            guard !floor.walls.contains(where: { $0.intersects(from: p, to: q) }) else { continue }
            seen.append("\(sign.kind):\(Int(range / options.rangeBucketMeters)):\(Int((bearing / options.bearingBucketRad).rounded()))")
        }
        let wall = min(freeDistance(floor, from: p, directionRad: headingRad), options.lookaheadMeters)
        return seen.sorted().joined(separator: ",") + "#" + String(Int(wall / options.wallBucketMeters))
    }

    /// Distance from `p` along `directionRad` to the first wall, meters (`lookaheadMeters` + 1 when none is
    /// that close).
    func freeDistance(_ floor: Floor, from p: Point2, directionRad: Double) -> Double {
        Geometry.freeDistance(from: p, directionRad: directionRad, far: options.lookaheadMeters + 1,
                              segments: floor.walls.lazy.map { ($0.from, $0.to) })
    }

    private func projection(of q: Point2, from p: Point2, directionRad: Double) -> Double {
        (q.x - p.x) * cos(directionRad) + (q.y - p.y) * sin(directionRad)
    }
}
