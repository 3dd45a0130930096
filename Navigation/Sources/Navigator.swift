// The navigator: location estimates in, guidance events out (a value-driven state machine in the style
// of InvisibleMap: no clock, no audio, no platform types). Per update: snap the estimate (grid), track
// progress along the current route (a window of the polyline), detect wrong way / off route, re-route
// with hysteresis, and submit maneuver phrases at their distances to the announcement policy.
import Foundation
import Maps

/// One location update from the localizer.
public struct NavigationInput: Sendable, Equatable {
    /// Time, seconds (any monotonic clock; events carry the same clock).
    public var t: Double
    /// Estimated position, meters in the floor's map frame (x east, y north).
    public var positionInMap: Point2
    /// Floor of the estimate.
    public var floorId: String
    /// Walking/phone heading in the map frame, radians counter-clockwise from +x.
    public var headingRad: Double
    /// False until the localizer has converged; the navigator then says only "Start walking".
    public var isLocalized: Bool
    /// Localizer confidence in [0, 1] (kept for logging; guidance does not use it yet).
    public var confidence: Double
    /// The localizer's pose hypotheses (heaviest first). While not localized the navigator plans a safe,
    /// informative instruction over them (DisambiguationPlanner); empty = unknown ("Start walking").
    public var hypotheses: [PoseCandidate]
    /// Walls the phone sees now (ARKit planes), in the traveler's frame: no exploratory instruction leads into
    /// one (`PerceivedWall`). Empty when planes are off or none is known.
    public var perceivedWalls: [PerceivedWall]
    /// True while the phone's visual-inertial tracking is lost (ARKit `notAvailable`): while not localized the
    /// navigator then says nothing (the phone's tracking prompt asks for the camera; "Start walking" from no
    /// hypotheses would send the traveler off with nothing to guide them).
    public var trackingLost: Bool
    /// True while the localizer reports sightings that its dominant hypothesis leaves unexplained (signs seen
    /// where that hypothesis has none, until one it explains; `LocalizationEstimate.sightingsUnexplained`): the
    /// traveler may stand where no hypothesis is, so while not localized no directional instruction is planned
    /// from the hypotheses (the advice is the plain "keep walking slowly").
    public var sightingsUnexplained: Bool

    /// Creates an input.
    public init(t: Double, positionInMap: Point2, floorId: String, headingRad: Double, isLocalized: Bool,
                confidence: Double = 1, hypotheses: [PoseCandidate] = [], perceivedWalls: [PerceivedWall] = [],
                trackingLost: Bool = false, sightingsUnexplained: Bool = false) {
        self.t = t; self.positionInMap = positionInMap; self.floorId = floorId; self.headingRad = headingRad
        self.isLocalized = isLocalized; self.confidence = confidence; self.hypotheses = hypotheses
        self.perceivedWalls = perceivedWalls; self.trackingLost = trackingLost
        self.sightingsUnexplained = sightingsUnexplained
    }
}

/// Navigator tunables. Distances in meters, times in seconds, angles in degrees.
public struct NavigatorOptions: Sendable {
    /// The cue ("Turn left now") is issued at the latest when the position snapped on the route is this far
    /// before the control point. 0.75 m from the paper (section 4). It is issued earlier when needed to end
    /// in time (`cueEndMarginMeters`).
    public var cueDistanceMeters = 0.75
    /// A "now" cue is scheduled to END at least this far before the control point: it is issued once the
    /// distance left is at most `cueEndMarginMeters + cueSchedulingSlackMeters + v x (wait + duration)`,
    /// v the walking speed (`speedWindowSeconds`, at most `maximumSchedulingSpeedMetersPerSecond`), the
    /// duration from `announcements.speechTiming` and the wait for speech that may not be cut off. 0.5 m
    /// (issue 17: "Turn left now." lasts 1.17 s, 1.3 m at 1.1 m/s: started 0.75 m before the turn it ended
    /// past it).
    public var cueEndMarginMeters = 0.5
    /// Added to the cue distance for what the schedule cannot see: one update (0.1 s at 10 Hz is 0.11 m at
    /// 1.1 m/s), the estimate's error along the route, a walker speeding up and the duration model's error
    /// (95th percentile 0.32 s, 0.35 m at 1.1 m/s), meters. 0.5 m: with 0.3 m, 85 % of the "now" cues of
    /// the SKERI convergence study ended 0.5 m before the turn (truth), short of the 95 % asked.
    public var cueSchedulingSlackMeters = 0.5
    /// Walking speed used for scheduling is capped here, m/s (a jump of the estimate is not walking).
    public var maximumSchedulingSpeedMetersPerSecond = 2.0
    /// The scheduling speed is the progress along the route over this window, seconds (along the route,
    /// so that noise across the corridor does not count as walking; longer than `speedWindowSeconds` to
    /// average the estimate's noise along it).
    public var schedulingSpeedWindowSeconds = 2.0
    /// Two announcements that would follow each other with less than this silence between them (a route
    /// start or "Continue" and the early alert of the next maneuver) are merged into one utterance
    /// ("Go straight ahead, 10 meters. Then turn right."), seconds.
    public var mergeGapSeconds = 2.0
    /// Least walking speed assumed for scheduling (cue timing, merging) when the measured speed is lower
    /// (the traveler stopped or is about to walk), m/s: 1.1 m/s, a typical indoor pace of a cane user and
    /// the figure of issue 17.
    public var nominalWalkingSpeedMetersPerSecond = 1.1
    /// A traveler off the route toward the inside of a coming turn (cutting its corner) gets the turn's
    /// cue earlier by that offset, up to this much, meters (see `Navigator.cornerCutMeters`).
    public var maxCornerCutMeters = 1.5
    /// The early alert ("In 8 meters, turn left") is issued this far before a maneuver.
    public var alertDistanceMeters = 8.0
    /// No alert when the maneuver is closer than the cue distance plus this gap (the cue follows at once),
    /// and an alert ends at least this far before its cue starts (at the walking speed), meters.
    public var alertCueGapMeters = 1.0
    /// A long alert (clock-face wording, steps) is said up to this much earlier than `alertDistanceMeters`
    /// so that it ends `alertCueGapMeters` before the cue, meters.
    public var maximumAlertAdvanceMeters = 4.0
    /// Arrival when the remaining route is at most this long. 1 m from the paper (section 4).
    public var arrivalRadiusMeters = 1.0
    /// Never route over stairs.
    public var avoidStairs = false
    /// Never route over elevators.
    public var avoidElevators = false
    /// How guidance is worded: unit, clock-face directions, verbosity, language.
    public var phrasing = PhrasingOptions()
    /// Phrase file language (`Navigation/Locales/<language>.json`); the same as `phrasing.language`.
    public var language: String {
        get { phrasing.language }
        set { phrasing.language = newValue }
    }
    /// Off route when the estimate is farther than this from the route polyline.
    public var offRouteDistanceMeters = 3.0
    /// Re-route when the estimate is nearer to an edge off the route than to the route by this much.
    public var closerEdgeMarginMeters = 1.0
    /// Hysteresis: a new route replaces the current one only when it is shorter (in routing cost) by more
    /// than max(`rerouteMinimumGainMeters`, `rerouteMinimumGainFraction` x current remaining cost).
    public var rerouteMinimumGainMeters = 2.0
    /// See `rerouteMinimumGainMeters`.
    public var rerouteMinimumGainFraction = 0.10
    /// While the estimate snaps to an edge off the route (but within the margins above), a candidate
    /// route is computed at most this often.
    public var rerouteCheckIntervalSeconds = 1.0
    /// Wrong way when the heading is more than this from the route direction ...
    public var wrongWayAngleDeg = 120.0
    /// ... for at least this long ...
    public var wrongWaySustainSeconds = 2.0
    /// ... while moving at least this fast (speed over the last `speedWindowSeconds`).
    public var movingSpeedMetersPerSecond = 0.3
    /// Window for the walking speed estimate.
    public var speedWindowSeconds = 1.0
    /// The same spoken correction (wrong way, off route) is not repeated within this time.
    public var correctionCooldownSeconds = 6.0
    /// "Continue N meters" after a maneuver only when the next one is farther than the alert distance
    /// plus this margin, and once the traveler is this far past the maneuver.
    public var continuationMarginMeters = 2.0
    /// With no route to the destination, a new search is made this often, seconds.
    public var noRouteRetrySeconds = 5.0
    /// A turn or door counts as passed once the estimate is this far beyond it along the route (until
    /// then its cue may still be said, late rather than never), meters.
    public var passedMarginMeters = 0.5
    /// A turn whose cue was not said before the estimate passed it (a jump near a corner) is still cued
    /// when the estimate is at most this far past it, meters.
    public var lateCueMeters = 1.5
    /// "Start walking" (or the exploratory instruction) is repeated this often while not localized.
    public var startWalkingRepeatSeconds = 15.0
    /// While not localized, the exploratory instruction is re-planned this often, seconds, and a changed
    /// instruction is said at most this often (`disambiguationMinimumGapSeconds`).
    public var disambiguationIntervalSeconds = 1.0
    public var disambiguationMinimumGapSeconds = 5.0
    /// Planner tunables (safety margins, look-ahead).
    public var disambiguation = DisambiguationOptions()
    /// After localization is lost during a route, "Start walking" is said only once the loss has lasted
    /// this long.
    public var relocalizationGraceSeconds = 3.0
    /// Route direction used for wrong-way detection and the first instruction: from the position on the
    /// route to the route point this far ahead.
    public var lookAheadMeters = 1.5
    /// Edge costs (elevator and stairs penalties, door penalty); `avoidStairs`/`avoidElevators` above
    /// override the fields of the same name.
    public var routing = RoutingOptions()
    /// Speech policy tunables.
    public var announcements = AnnouncementPolicyConfig()
    /// Creates the defaults above.
    public init() {}
}

/// Turn-by-turn guidance to one destination.
public final class Navigator {
    /// Options in force.
    public let options: NavigatorOptions
    /// The routing graph of the building.
    public let graph: RoutingGraph
    /// The router (snapping and shortest paths).
    public let router: Router
    /// Phrase rendering.
    public let narrative: Narrative
    /// The announcement policy all speech goes through.
    public let policy: AnnouncementPolicy

    /// Destination node index.
    public let destinationNode: Int
    /// Spoken name of the destination.
    public let destinationName: String
    /// Destination position used for the arrival side (the point of interest's entrance, else the node).
    public let destinationPosition: Point2
    /// True when the destination is behind a door (announced on arrival).
    public let destinationBehindDoor: Bool

    /// The route being followed, nil before localization or when there is no route.
    public private(set) var currentRoute: Route?
    /// The route's first instruction is still to be said (composed when the channel is free, see `adopt`).
    private var departurePending = false
    /// Since when the first instruction has been held back because the arrival would come before it ended
    /// (`announceDepartureWhenChannelFree`), s; nil when it is not held.
    private var departureHeldSince: Double?
    /// True once arrival was announced; later updates produce nothing.
    public private(set) var hasArrived = false
    /// Maneuvers of the current route (empty before there is one).
    public var lastManeuvers: [Maneuver] { currentRoute?.maneuvers ?? [] }
    /// Distance walked along the current route, meters.
    public private(set) var progressMeters = 0.0
    /// Distance from the last estimate to the current route, meters.
    public private(set) var distanceFromRouteMeters = 0.0
    /// Number of routes computed and adopted so far (the first included).
    public private(set) var routeCount = 0
    /// The last instruction spoken (what "Repeat" says).
    public private(set) var lastInstruction: String?

    private let builder: RouteBuilder
    private var routeEdges: Set<Int> = []
    private var routeCumulativeCost: [Double] = []
    /// Continuous polyline position of the traveler on the current route.
    private var polylinePosition = 0.0
    private var nextManeuver = 0
    private var alertIssued: [Bool] = []
    private var cueIssued: [Bool] = []
    private var continuationDue: Int? = nil
    private var lastStartWalkingT: Double? = nil
    private let planner: DisambiguationPlanner
    private var lastPlanT = -Double.infinity
    private var lastAdvice: DisambiguationAdvice? = nil
    private var lastSpokenAdviceKey: String? = nil
    /// The last exploratory advice (nil when localized or before any); for the trainer's view and tests.
    public private(set) var currentAdvice: DisambiguationAdvice? = nil
    /// The last exploratory advice that was spoken, with its time (for scoring its safety against truth).
    public private(set) var lastSpokenAdvice: (t: Double, advice: DisambiguationAdvice)? = nil
    /// The dominant hypothesis of the last unlocalized update ("Where am I" answers "probably ...").
    private var lastUnsureInput: NavigationInput? = nil
    private var lastInput: NavigationInput? = nil
    private var lastSnap: SnappedPosition? = nil
    private var history: [(t: Double, p: Vec2, floor: String)] = []
    /// Progress along the current route per update, for the scheduling speed.
    private var progressHistory: [(t: Double, s: Double)] = []
    private var wrongWaySince: Double? = nil
    private var lastCorrectionT: [HapticPattern: Double] = [:]
    private var lastRerouteCheckT = -Double.infinity
    private var noRouteAnnounced = false
    private var offRouteLatched = false
    private var unlocalizedSince: Double? = nil
    private var lastNoRouteT: Double? = nil

    /// Creates a navigator to `destinationId`: a point-of-interest id (routed to the graph node that
    /// references it, else to the nearest node on its floor) or a graph node id. Throws
    /// `NavigationError` for an inconsistent graph, an unknown destination or a missing phrase file.
    public init(building: Building, destinationId: String, options: NavigatorOptions = NavigatorOptions()) throws {
        self.options = options
        graph = try RoutingGraph(building: building)
        var routing = options.routing
        routing.avoidStairs = options.avoidStairs
        routing.avoidElevators = options.avoidElevators
        router = Router(graph: graph, options: routing)
        let phrases = try PhraseBook.load(language: options.phrasing.language)
        narrative = Narrative(phrases: phrases, options: options.phrasing)
        var announcements = options.announcements
        // Durations are estimated with the syllable rules of the language spoken, at the configured rate.
        if announcements.speechTiming.language != phrases.language {
            announcements.speechTiming = .calibrated(language: phrases.language,
                                                     wordsPerMinute: options.announcements.speechTiming.wordsPerMinute)
        }
        policy = AnnouncementPolicy(config: announcements)
        builder = RouteBuilder(graph: graph)
        planner = DisambiguationPlanner(building: building, options: options.disambiguation)

        let graph = self.graph
        var poi: (PointOfInterest, Floor)? = nil
        for f in building.floors { if let p = f.pointsOfInterest.first(where: { $0.id == destinationId }) { poi = (p, f); break } }
        if let (p, floor) = poi {
            if let n = graph.nodes.firstIndex(where: { $0.pointOfInterestId == p.id }) {
                destinationNode = n
            } else {
                let candidates = graph.nodes.indices.filter { graph.nodes[$0].floorId == floor.id }
                guard let n = candidates.min(by: {
                    graph.positions[$0].distance(to: Vec2(p.position)) < graph.positions[$1].distance(to: Vec2(p.position))
                }) else { throw NavigationError.unknownDestination(destinationId) }
                destinationNode = n
            }
            destinationName = p.name
            destinationPosition = p.position
            destinationBehindDoor = p.behindDoor
        } else if let n = graph.nodeIndex(id: destinationId) {
            destinationNode = n
            let node = graph.nodes[n]
            let linked = node.pointOfInterestId.flatMap { id in building.floors.lazy.compactMap { $0.pointsOfInterest.first { $0.id == id } }.first }
            destinationName = linked?.name ?? node.label ?? node.id
            destinationPosition = linked?.position ?? node.position
            destinationBehindDoor = linked?.behindDoor ?? false
        } else {
            throw NavigationError.unknownDestination(destinationId)
        }
    }

    // MARK: - Updates

    /// Processes one location update; returns what to render now (already through the policy).
    public func update(_ input: NavigationInput) -> [TimedGuidanceEvent] {
        let t = input.t
        guard t.isFinite else { return [] }
        guard input.positionInMap.x.isFinite, input.positionInMap.y.isFinite, input.headingRad.isFinite else {
            return emit(t)
        }
        if hasArrived { return emit(t) }
        guard input.isLocalized else {
            // Paper section 4: "the app issues no directions other than 'start walking' until it is able
            // to estimate the user's location". After a loss of localization mid-route, only once the loss
            // has lasted `relocalizationGraceSeconds` (a flicker of the localizer says nothing).
            let since = unlocalizedSince ?? t
            unlocalizedSince = since
            let due = lastStartWalkingT.map { t - $0 >= options.startWalkingRepeatSeconds - 1e-6 } ?? true
            let graceOver = currentRoute == nil || t - since >= options.relocalizationGraceSeconds - 1e-6
            if input.trackingLost {
                currentAdvice = nil  // nothing to plan from until tracking returns
            } else if graceOver && !input.hypotheses.isEmpty {
                guideWhileUnsure(input, repeatDue: due)
            } else if due && graceOver {
                say(narrative.phrases.phrase("startWalking"), .information, t)
                lastStartWalkingT = t
            }
            lastUnsureInput = input
            lastInput = nil
            history.removeAll()
            progressHistory.removeAll()
            wrongWaySince = nil
            return emit(t)
        }
        if let since = unlocalizedSince, let said = lastStartWalkingT, said >= since - 1e-9 {
            // Localized after guidance while unsure was spoken: the exploratory advice or "start walking" still
            // playing no longer holds, and the route's first instruction must not wait behind it (a cue at the
            // start would come first and speak for a turn the departure instruction covers).
            policy.supersede(upTo: .information, t: t)
        }
        let relocked = unlocalizedSince != nil
        unlocalizedSince = nil
        currentAdvice = nil
        lastSpokenAdviceKey = nil
        lastUnsureInput = nil
        lastInput = input
        let p = Vec2(input.positionInMap)
        history.append((t, p, input.floorId))
        while let first = history.first, t - first.t > options.speedWindowSeconds + 0.5 { history.removeFirst() }

        guard let snap = router.snap(input.positionInMap, floorId: input.floorId) else { return emit(t) }
        lastSnap = snap

        if currentRoute == nil {
            // With no route possible (e.g. stairs avoided and no elevator), retry only now and then.
            if lastNoRouteT.map({ t - $0 >= options.noRouteRetrySeconds }) ?? true {
                adoptRoute(from: snap, input: input)
                lastNoRouteT = currentRoute == nil ? t : nil
            }
        } else {
            trackProgress(p, floorId: input.floorId)
            if relocked && distanceFromRouteMeters > options.offRouteDistanceMeters {
                // Localized again after a spell unsure, away from the route: the estimate moved, not the traveler
                // (who followed the advice given while unsure). The route is taken again from here without "Off
                // route, recalculating": that correction, spoken at safety rank, would hold back a turn cue due
                // a second later, and it blames the traveler for the localizer's change of mind.
                adoptRoute(from: snap, input: input)
            } else {
                checkDeviation(input: input, snap: snap)
            }
        }
        guard currentRoute != nil else { return emit(t) }
        if checkArrival(input: input) { return emit(t) }
        recordProgress(t: t)
        announceDepartureWhenChannelFree(input: input)
        announceManeuvers(input: input)
        return emit(t)
    }

    /// "Where am I": the nearest labelled place on the floor (preferring one not behind a wall) and the
    /// labelled places found by following the current corridor both ways.
    public func requestWhereAmI(t: Double) -> [TimedGuidanceEvent] {
        guard let input = lastInput, let snap = lastSnap else {
            // "Probably near" names the dominant hypothesis' place: not while it leaves the sightings unexplained.
            if let unsure = lastUnsureInput, !unsure.sightingsUnexplained, let place = probablePlace(unsure) {
                policy.submit(narrative.phrases.phrase("whereAmI.probably", ["place": place]), priority: .information,
                              t: t, requested: true)
                return emit(t)
            }
            policy.submit(narrative.phrases.phrase("whereAmI.unknown"), priority: .information, t: t, requested: true)
            return emit(t)
        }
        let p = Vec2(input.positionInMap)
        var places: [(name: String, position: Vec2)] = []
        if let floor = graph.building.floor(id: input.floorId) {
            places += floor.pointsOfInterest.map { ($0.name, Vec2($0.position)) }
        }
        for n in graph.nodes where n.floorId == input.floorId && n.pointOfInterestId == nil {
            if let label = n.label { places.append((label, Vec2(n.position))) }
        }
        places.sort { $0.position.distance(to: p) < $1.position.distance(to: p) }
        let place = places.first { graph.isUnobstructed(from: input.positionInMap, to: $0.position.point2, floorId: input.floorId) }
            ?? places.first
        guard let place else {
            policy.submit(narrative.phrases.phrase("whereAmI.unknown"), priority: .information, t: t, requested: true)
            return emit(t)
        }
        let e = snap.edgeIndex
        let a = labelAlongCorridor(from: graph.edgeFrom[e], cameFrom: graph.edgeTo[e], skipping: place.name)
        let b = labelAlongCorridor(from: graph.edgeTo[e], cameFrom: graph.edgeFrom[e], skipping: place.name)
        let text: String
        if let a, let b, a != b {
            text = narrative.phrases.phrase("whereAmI.between", ["place": place.name, "from": a, "to": b])
        } else {
            text = narrative.phrases.phrase("whereAmI.near", ["place": place.name])
        }
        policy.submit(text, priority: .information, t: t, requested: true)
        return emit(t)
    }

    /// "Repeat": the last instruction spoken, again (exempt from repeat suppression).
    public func requestRepeat(t: Double) -> [TimedGuidanceEvent] {
        policy.submit(lastInstruction ?? narrative.phrases.phrase("repeat.none"), priority: .information, t: t,
                      requested: true)
        return emit(t)
    }

    // MARK: - Routing

    /// Computes a route from `snap` and adopts it unconditionally; announces its start.
    private func adoptRoute(from snap: SnappedPosition, input: NavigationInput) {
        guard let path = router.shortestPath(from: snap, to: destinationNode) else {
            currentRoute = nil
            if !noRouteAnnounced {
                say(narrative.phrases.phrase("noRoute", ["destination": destinationName]), .information, input.t)
                noRouteAnnounced = true
            }
            return
        }
        noRouteAnnounced = false
        adopt(path, input: input)
    }

    private func adopt(_ path: PathResult, input: NavigationInput) {
        let route = builder.build(path: path, routeCost: path.costMeters, destinationBehindDoor: destinationBehindDoor,
                                  destinationName: destinationName)
        currentRoute = route
        routeCount += 1
        routeEdges = Set(route.segmentEdges)
        var cc: [Double] = [0]
        for (i, e) in route.segmentEdges.enumerated() {
            let full = router.cost(ofEdge: e, continuingRide: i > 0 && route.segmentVertical[i - 1])
            let segCost: Double
            if i == 0 {
                let len = graph.edgeLength[e]
                segCost = len > 1e-9 ? full * (route.cumulativeMeters[1] / len) : 0
            } else {
                segCost = full
            }
            cc.append(cc[i] + segCost)
        }
        routeCumulativeCost = cc
        polylinePosition = 0
        progressMeters = 0
        progressHistory.removeAll()
        distanceFromRouteMeters = 0
        nextManeuver = 1
        alertIssued = Array(repeating: false, count: route.maneuvers.count)
        cueIssued = Array(repeating: false, count: route.maneuvers.count)
        continuationDue = nil
        wrongWaySince = nil
        policy.discardPending(below: .safety)
        trackProgress(Vec2(input.positionInMap), floorId: input.floorId)
        // A route adopted far from every edge (open area) is not "off route" until the traveler has
        // been within the distance once.
        offRouteLatched = distanceFromRouteMeters > options.offRouteDistanceMeters

        // The first instruction says a distance: it is composed when it can be spoken (the channel may still
        // be playing the exploratory advice for 3-4 s), never queued with a distance that is stale by then
        // ("Go straight ahead, 8 meters." said 3.4 s late, 4 m before the turn).
        departurePending = true
        departureHeldSince = nil
        announceDepartureWhenChannelFree(input: input)
    }

    /// Speaks the route's first instruction once the speech channel is free for it (see `adopt`): the
    /// direction of the route relative to the heading and the distance to the next maneuver, from the
    /// traveler's progress at that moment. Dropped when a maneuver's cue has already been issued.
    private func announceDepartureWhenChannelFree(input: NavigationInput) {
        guard departurePending, let route = currentRoute else { return }
        if cueIssued.dropFirst().contains(true) { departurePending = false; return }
        guard policy.earliestStart(priority: .alert, t: input.t) <= input.t + 1e-9 else { return }
        departurePending = false
        // First instruction: direction of the route relative to the heading, distance to the next maneuver.
        let ahead = route.point(atDistance: progressMeters + options.lookAheadMeters, fromSegment: 0).point
        let here = route.point(atDistance: progressMeters, fromSegment: 0).point
        let dir = ahead - here
        var relativeBearingRad: Double? = dir.length > 1e-6 ? dir.angleRad - input.headingRad : nil
        var orientation: DepartOrientation = relativeBearingRad.map { DepartOrientation.classify(relativeBearingRad: $0) } ?? .ahead
        if let turning = cornerBeingTurned(route: route, headingRad: input.headingRad),
           orientation == .left || orientation == .right, orientation != turning {
            orientation = .ahead
            relativeBearingRad = nil
        }
        // Turns and doors within the look-ahead of the start are covered by the first instruction, whose
        // direction already points past them (e.g. out of a room's door into the corridor): not cued.
        // Except a turn still to be made: "Go straight ahead" to a traveler facing along the corridor a
        // meter before a corner (the look-ahead point just past the corner lies in the "ahead" sector)
        // does not tell them to turn; the turn keeps its cue.
        func stillToTurn(_ m: Maneuver) -> Bool {
            guard orientation == .ahead, m.kind.isTurn, let (inDir, outDir) = Self.cornerLegs(m, route: route) else { return false }
            return abs(normalizedAngleRad(input.headingRad - inDir.angleRad)) < abs(normalizedAngleRad(input.headingRad - outDir.angleRad))
        }
        var first = 1
        while first < route.maneuvers.count - 1,
              route.maneuvers[first].kind.isTurn || route.maneuvers[first].kind == .goThroughDoor,
              !stillToTurn(route.maneuvers[first]),
              route.maneuvers[first].distanceFromStartMeters - progressMeters < options.lookAheadMeters {
            alertIssued[first] = true
            cueIssued[first] = true
            first += 1
        }
        let next = route.maneuvers[min(first, route.maneuvers.count - 1)]
        let toNext = next.distanceFromStartMeters - progressMeters
        // Facing along the route with a turn so close that its cue is due at once: the cue is the first
        // instruction ("Go straight ahead, 1 meter." before or after "Turn left now." only confuses).
        // So is a turn whose cue would be due before this instruction ended (at the walking speed): the cue
        // would cut it off.
        let text = narrative.depart(orientation, distanceMeters: toNext, relativeBearingRad: relativeBearingRad)
        let departWalkMeters = schedulingSpeed() * policy.estimatedDurationSeconds(text)
        // A lock a step or two from the destination: walking on, the traveler would hear the arrival ("Arrived.
        // Room 107 is ahead, behind a door.") before "Turn right, then go 1 meter." ended, and the two would
        // disagree (the route's look-ahead against the destination's side). The first instruction is held while
        // the arrival may come first, at most `departureHoldSeconds` (the walking speed is not known yet at a
        // lock: a traveler standing there hears it that much later).
        if next.kind == .arrive, toNext > options.arrivalRadiusMeters,
           toNext - departWalkMeters <= options.arrivalRadiusMeters,
           input.t - (departureHeldSince ?? input.t) < Self.departureHoldSeconds {
            if departureHeldSince == nil { departureHeldSince = input.t }
            departurePending = true
            return
        }
        departureHeldSince = nil
        let cueDueAtOnce = orientation == .ahead && next.kind.isTurn && first < route.maneuvers.count
            && toNext <= cueLeadMeters(narrative.cue(next, floorName: floorName(next.floorId)), priority: .cue, t: input.t)
                + departWalkMeters
        if !cueDueAtOnce && (next.kind != .arrive || toNext > options.arrivalRadiusMeters) {
            // Alert rank: it must precede the alert of the next maneuver, which it makes redundant when
            // that one is already within the alert distance ("Turn left, then go 5 meters." then the cue).
            say(mergedWithNext(text, remainingMeters: toNext, next: min(first, route.maneuvers.count - 1), route: route),
                .alert, input.t)
            if first < route.maneuvers.count && toNext <= options.alertDistanceMeters { alertIssued[first] = true }
        }
    }

    /// The way (`.left` or `.right`) the traveler is turning a corner now, or nil: a turn of the route
    /// within the look-ahead whose incoming and outgoing legs the heading lies strictly between, turned at
    /// least `cornerTakenMinDeg` from the incoming leg. A lock often comes while the traveler cuts a corner,
    /// with the estimate a little behind them: the look-ahead point is then just past the corner, on the far
    /// side of the heading, and "Turn right" would send a traveler who is turning left back against the
    /// turn. Such a first instruction is said as "ahead" (they are already going the way the route goes);
    /// the turn keeps its cue unless the heading is nearer the outgoing leg (`stillToTurn`).
    private func cornerBeingTurned(route: Route, headingRad: Double) -> DepartOrientation? {
        for m in route.maneuvers.dropFirst() where m.kind.isTurn {
            guard m.distanceFromStartMeters - progressMeters < options.lookAheadMeters else { break }
            guard m.distanceFromStartMeters - progressMeters >= 0 else { continue }
            guard let (inDir, outDir) = Self.cornerLegs(m, route: route) else { continue }
            let turnRad = normalizedAngleRad(outDir.angleRad - inDir.angleRad)
            let turnedRad = normalizedAngleRad(headingRad - inDir.angleRad)
            let minRad = Self.cornerTakenMinDeg * Double.pi / 180
            if turnRad * turnedRad > 0, abs(turnedRad) >= minRad, abs(turnedRad) < abs(turnRad) {
                return turnRad > 0 ? .left : .right
            }
            return nil
        }
        return nil
    }

    /// The incoming and outgoing legs (map frame, meters) of the route at turn `m`'s polyline point, or nil at
    /// the route's ends or where a leg has no length.
    private static func cornerLegs(_ m: Maneuver, route: Route) -> (Vec2, Vec2)? {
        let q = Int(m.polylinePosition.rounded(.down))
        guard q >= 1, q + 1 < route.points.count else { return nil }
        let inDir = Vec2(route.points[q].position) - Vec2(route.points[q - 1].position)
        let outDir = Vec2(route.points[q + 1].position) - Vec2(route.points[q].position)
        guard inDir.length > 1e-9, outDir.length > 1e-9 else { return nil }
        return (inDir, outDir)
    }

    /// Longest hold of a first instruction for an arrival that may come first, s: about two steps' time (a
    /// traveler who stands, turns away or dawdles within the arrival's reach hears the instruction after it).
    public static let departureHoldSeconds = 2.0

    /// How far (degrees) the heading must have turned from a corner's incoming leg toward its outgoing one
    /// for the traveler to count as turning it (`cornerBeingTurned`): past a walker's sway and the
    /// heading estimate's error (a few degrees), well inside any turn the route cues (> 30 degrees).
    static let cornerTakenMinDeg = 15.0

    /// Remaining routing cost from the traveler's position on the current route.
    private func remainingCost() -> Double {
        guard let r = currentRoute, r.points.count > 1 else { return 0 }
        let i = min(Int(polylinePosition.rounded(.down)), r.points.count - 2)
        let f = polylinePosition - Double(i)
        let at = routeCumulativeCost[i] + f * (routeCumulativeCost[i + 1] - routeCumulativeCost[i])
        return routeCumulativeCost[r.points.count - 1] - at
    }

    /// Re-routes when the traveler left the route (off route: correction spoken), is clearly nearer to
    /// another edge (silent re-route), or a better route appeared (hysteresis); flags a wrong way.
    private func checkDeviation(input: NavigationInput, snap: SnappedPosition) {
        let t = input.t
        if distanceFromRouteMeters <= options.offRouteDistanceMeters { offRouteLatched = false }
        if distanceFromRouteMeters > options.offRouteDistanceMeters && !offRouteLatched {
            // Latched until the traveler is back within the distance: in an open area the new route
            // starts as far away as the old one was, and must not be announced again on every update.
            offRouteLatched = true
            correction(.offRoute, key: "safety.offRoute", t: t)
            adoptRoute(from: snap, input: input)
            return
        }
        let onRouteEdge = routeEdges.contains(snap.edgeIndex)
        if !onRouteEdge && snap.distanceMeters + options.closerEdgeMarginMeters < distanceFromRouteMeters {
            adoptRoute(from: snap, input: input)
            return
        }
        if !onRouteEdge && t - lastRerouteCheckT >= options.rerouteCheckIntervalSeconds {
            lastRerouteCheckT = t
            considerBetterRoute(snap: snap, input: input)
        }
        // Wrong way: heading against the route direction, sustained, while moving.
        guard let r = currentRoute else { return }
        let here = r.point(atDistance: progressMeters, fromSegment: Int(polylinePosition)).point
        let ahead = r.point(atDistance: progressMeters + options.lookAheadMeters, fromSegment: Int(polylinePosition)).point
        let dir = ahead - here
        var wrong = false
        if dir.length > 0.2, speedMetersPerSecond() >= options.movingSpeedMetersPerSecond {
            let err = abs(normalizedAngleRad(input.headingRad - dir.angleRad)) * 180 / Double.pi
            wrong = err > options.wrongWayAngleDeg
        }
        if wrong {
            let since = wrongWaySince ?? t
            wrongWaySince = since
            if t - since >= options.wrongWaySustainSeconds {
                correction(.wrongWay, key: "safety.wrongWay", t: t)
                wrongWaySince = nil
                // The route from the virtual start node already goes both ways along the edge; a better
                // route in the direction now walked replaces it only past the hysteresis.
                considerBetterRoute(snap: snap, input: input)
            }
        } else {
            wrongWaySince = nil
        }
    }

    private func considerBetterRoute(snap: SnappedPosition, input: NavigationInput) {
        guard let path = router.shortestPath(from: snap, to: destinationNode) else { return }
        let current = remainingCost() + distanceFromRouteMeters
        let candidate = path.costMeters + snap.distanceMeters
        let needed = max(options.rerouteMinimumGainMeters, options.rerouteMinimumGainFraction * current)
        if current - candidate > needed { adopt(path, input: input) }
    }

    private func correction(_ pattern: HapticPattern, key: String, t: Double) {
        policy.submitHaptic(pattern)
        if lastCorrectionT[pattern].map({ t - $0 >= options.correctionCooldownSeconds }) ?? true {
            say(narrative.phrases.phrase(key), .safety, t)
            lastCorrectionT[pattern] = t
        }
    }

    private func speedMetersPerSecond() -> Double {
        guard let last = history.last else { return 0 }
        guard let first = history.first(where: { last.t - $0.t <= options.speedWindowSeconds && $0.floor == last.floor }),
              last.t - first.t > 0.2 else { return 0 }
        return last.p.distance(to: first.p) / (last.t - first.t)
    }

    // MARK: - Progress

    /// Projects the estimate on the current route: first on a window of segments around the last
    /// position (constant work per update), then, only when that fails or lands off route, on the whole
    /// route (work bounded by the route, not the map). Points of the route on other floors are skipped; a
    /// ride segment counts as its end point on the estimate's floor.
    private func trackProgress(_ p: Vec2, floorId: String) {
        guard let r = currentRoute, r.points.count > 1 else { return }
        let segCount = r.points.count - 1
        let cur = min(Int(polylinePosition.rounded(.down)), segCount - 1)
        var best = bestProjection(p, floorId: floorId, route: r, segments: max(0, cur - 2)...min(segCount - 1, cur + 6))
        if best == nil || best!.distance > options.offRouteDistanceMeters {
            if let full = bestProjection(p, floorId: floorId, route: r, segments: 0...(segCount - 1)),
               best == nil || full.distance < best!.distance {
                best = full
            }
        }
        guard let best else {
            distanceFromRouteMeters = .infinity
            return
        }
        polylinePosition = best.u
        progressMeters = r.distanceAlong(best.u)
        distanceFromRouteMeters = best.distance
    }

    private func bestProjection(_ p: Vec2, floorId: String, route r: Route, segments: ClosedRange<Int>)
        -> (u: Double, distance: Double)? {
        var best: (u: Double, distance: Double)? = nil
        for i in segments {
            let a = r.points[i], b = r.points[i + 1]
            let onA = a.floorId == floorId, onB = b.floorId == floorId
            let candidate: (t: Double, d: Double)
            if i == 0 && onA && onB {
                // The first segment is the part of the snapped edge ahead of the start. Behind the start the
                // traveler is still on that edge (walking the wrong way, not off route): project on the whole
                // edge and clamp the progress at 0.
                let e = r.segmentEdges[0]
                let p1 = Vec2(b.position)
                let ea = graph.positions[graph.edgeFrom[e]], eb = graph.positions[graph.edgeTo[e]]
                let tail = ea.distance(to: p1) > eb.distance(to: p1) ? ea : eb
                let pr = projectOntoSegment(p, tail, p1)
                let start = Vec2(a.position), ab = p1 - start
                let t = ab.lengthSquared > 1e-18 ? max(0, min(1, (pr.point - start).dot(ab) / ab.lengthSquared)) : 0
                candidate = (t, pr.distance)
            } else if onA && onB {
                let pr = projectOntoSegment(p, Vec2(a.position), Vec2(b.position))
                candidate = (pr.t, pr.distance)
            } else if onA {
                candidate = (0, p.distance(to: Vec2(a.position)))
            } else if onB {
                candidate = (1, p.distance(to: Vec2(b.position)))
            } else {
                continue
            }
            let u = Double(i) + candidate.t
            if let b = best {
                // Nearest wins; near-ties go to the position closest to the previous one (a route may pass
                // the same corridor twice).
                if candidate.d < b.distance - 1e-6
                    || (abs(candidate.d - b.distance) <= 1e-6 && abs(u - polylinePosition) < abs(b.u - polylinePosition)) {
                    best = (u, candidate.d)
                }
            } else {
                best = (u, candidate.d)
            }
        }
        return best
    }

    // MARK: - Announcements

    private func checkArrival(input: NavigationInput) -> Bool {
        guard let r = currentRoute else { return false }
        let remaining = r.lengthMeters - progressMeters
        guard input.floorId == r.points[r.points.count - 1].floorId, remaining <= options.arrivalRadiusMeters,
              distanceFromRouteMeters <= options.offRouteDistanceMeters,
              polylinePosition >= Double(r.points.count - 1) - 1 - 1e-9 || remaining <= 1e-9
        else { return false }
        let v = Vec2(destinationPosition) - Vec2(input.positionInMap)
        let side: ArrivalSide
        if v.length < 0.25 {
            side = .ahead
        } else {
            side = ArrivalSide.classify(relativeBearingRad: v.angleRad - input.headingRad)
        }
        // Whatever is still queued about the route (a turn cue or chained alert that came due with a late
        // relock) is moot now, and would hold the arrival back until it is too old to say.
        policy.discardPending(below: .safety)
        policy.submitHaptic(.arrived)
        say(narrative.arrival(side: side, behindDoor: destinationBehindDoor, destinationName: destinationName), .cue, input.t)
        hasArrived = true
        return true
    }

    private func isRide(_ m: Maneuver) -> Bool { m.kind == .takeElevator || m.kind == .takeStairs }

    /// A ride is passed on reaching the next floor. A turn or door is passed once the traveler is beyond
    /// it by `passedMarginMeters` (or past the next route point): an estimate that merely projects onto
    /// the outgoing segment near a corner (localizer noise) still gets the cue, late rather than never.
    private func isPassed(_ m: Maneuver, u: Double, s: Double) -> Bool {
        let beyond = u > m.polylinePosition + 1e-9
        if isRide(m) { return beyond }
        return beyond && (s - m.distanceFromStartMeters > options.passedMarginMeters
                          || u >= m.polylinePosition.rounded(.down) + 1 + 1e-9)
    }

    private func announceManeuvers(input: NavigationInput) {
        guard let r = currentRoute else { return }
        let t = input.t
        let u = polylinePosition
        let s = progressMeters
        // At most one turn haptic per update: when a late relock brings two turn cues due at once, the second
        // cue's speech waits for the first, and a second haptic felt with the first cue's words would give the
        // first turn's side twice (the phone reads the side from the batch's speech).
        var turnHapticSent = false
        func turnHaptic() {
            if !turnHapticSent { policy.submitHaptic(.turnCue) }
            turnHapticSent = true
        }
        // 1. Move past the maneuvers left behind (and say the landing phrase on reaching a landing).
        while nextManeuver < r.maneuvers.count {
            let i = nextManeuver
            let m = r.maneuvers[i]
            if m.kind == .arrive { break }
            if m.kind == .continue {
                guard u >= m.polylinePosition - 1e-9 else { break }
                if !cueIssued[i], let text = narrative.cue(m, floorName: floorName(m.floorId)) {
                    // Alert rank: orientation after a ride; a turn cue right after it may cut it off.
                    say(text, .alert, t, about: m, variant: "cue")
                    sayChained(after: i, route: r, t: t)
                    // The phrase gives the distance to the next maneuver: no separate early alert.
                    if i + 1 < r.maneuvers.count && m.distanceToNextMeters <= options.alertDistanceMeters {
                        alertIssued[i + 1] = true
                    }
                }
                cueIssued[i] = true
                nextManeuver += 1
                continue
            }
            guard isPassed(m, u: u, s: s) else { break }
            // Anything about it still waiting to be said would now be wrong.
            policy.discardPending(repeatKeyPrefix: maneuverKey(m, variant: "cue"))
            policy.discardPending(repeatKeyPrefix: maneuverKey(m, variant: "alert"))
            if m.kind.isTurn && !cueIssued[i] && s - m.distanceFromStartMeters <= options.lateCueMeters {
                // The estimate jumped past the turn before its cue (noise near a corner): the traveler is
                // most likely right at it, so say it now rather than never.
                cueIssued[i] = true
                alertIssued[i] = true
                if let text = narrative.cue(m, floorName: floorName(m.floorId)) {
                    turnHaptic()
                    say(text, .cue, t, about: m, variant: "cue")
                }
            }
            if m.kind.isTurn || m.kind == .goThroughDoor { continuationDue = i }
            nextManeuver += 1
        }
        // 2. Alert and cue the next maneuver. When its cue is already out (the traveler is at the turn, not
        //    yet past it), the cue of the one after it is also due at its distance; never beyond a ride:
        //    nothing after a ride is announced before the ride.
        var i = nextManeuver
        var lookingAhead = false
        // Doors passed over, their cue not yet out: a turn just beyond a door may be due first (its cue is
        // timed to end before the turn); the door's cue is then not said (the turn's comes first, and the
        // door is met anyway).
        var doorsPassedOver: [Int] = []
        while i < r.maneuvers.count {
            let m = r.maneuvers[i]
            let d = m.distanceFromStartMeters - s
            if m.kind == .arrive {
                if !lookingAhead, !departurePending, !alertIssued[i], d > options.arrivalRadiusMeters + options.alertCueGapMeters,
                   d <= options.alertDistanceMeters {
                    alertIssued[i] = true
                    if options.phrasing.verbosity != .brief,
                       let text = narrative.alert(m, distanceMeters: d, destinationName: destinationName) {
                        say(text, .alert, t, about: m, variant: "alert")
                    }
                }
                break
            }
            if m.kind == .continue { break }
            let cueText = narrative.cue(m, floorName: floorName(m.floorId))
            // Doors rank as alerts: a door is met anyway; it must not delay or cut off the cue of a turn or
            // a ride a metre or two away, which it would as a cue.
            let cuePriority: AnnouncementPriority = m.kind == .goThroughDoor ? .alert : .cue
            // Turn cues are timed to end before the turn; doors and rides keep the paper's distance (the
            // traveler stops at them anyway, and their cue must not come before the maneuver ahead of them).
            let cueLead = m.kind.isTurn ? cueLeadMeters(cueText, priority: cuePriority, t: t) : options.cueDistanceMeters
            if !cueIssued[i] && d - cornerCutMeters(toward: m, route: r, input: input) <= cueLead {
                cueIssued[i] = true
                alertIssued[i] = true
                for door in doorsPassedOver { cueIssued[door] = true; alertIssued[door] = true }
                if let text = cueText {
                    if m.kind.isTurn { turnHaptic() }
                    say(text, cuePriority, t, about: m, variant: "cue")
                    sayChained(after: i, route: r, t: t)
                }
            } else if !lookingAhead && !departurePending && !alertIssued[i], d > options.cueDistanceMeters + options.alertCueGapMeters,
                      let alertDue = alertDueMeters(m, d: d, cueLead: cueLead, t: t), d <= alertDue.trigger {
                let text = alertDue.text
                // The alert must end (at the walking speed) a gap before its cue is due; it is brought
                // forward from `alertDistanceMeters` when it is long. When it can no longer end in time (the
                // maneuver came into view late), the cue would cut it off or follow it back to back: only
                // the cue is said.
                if options.phrasing.verbosity == .brief || alertDue.endBeforeMeters > cueLead + options.alertCueGapMeters - 1e-9 {
                    alertIssued[i] = true
                    continuationDue = nil
                    if options.phrasing.verbosity != .brief { say(text, .alert, t, about: m, variant: "alert") }
                }
            }
            if !cueIssued[i] && m.kind == .goThroughDoor && !lookingAhead {
                doorsPassedOver.append(i)
            } else {
                guard cueIssued[i], !isRide(m) else { break }
            }
            lookingAhead = true
            i += 1
        }
        // Post-maneuver continuation on a long leg (detailed: after every turn or door, unless the next
        // maneuver is only steps away; brief: never).
        if let c = continuationDue, c + 1 < r.maneuvers.count {
            let m = r.maneuvers[c]
            let next = r.maneuvers[c + 1]
            let remaining = next.distanceFromStartMeters - s
            let shortest = options.phrasing.verbosity == .detailed
                ? options.cueDistanceMeters + 2 * options.continuationMarginMeters
                : options.alertDistanceMeters + options.continuationMarginMeters
            if options.phrasing.verbosity == .brief || remaining <= shortest {
                continuationDue = nil
            } else if s >= m.distanceFromStartMeters + options.continuationMarginMeters {
                continuationDue = nil
                let text = narrative.continuation(distanceMeters: remaining)
                say(mergedWithNext(text, remainingMeters: remaining, next: c + 1, route: r), .information, t)
            }
        }
    }

    private func floorName(_ id: String) -> String { graph.building.floor(id: id)?.name ?? id }

    /// Walking speed used to schedule cues, m/s: progress along the route over the last
    /// `schedulingSpeedWindowSeconds` (at least 0.5 s of it), at least `nominalWalkingSpeedMetersPerSecond`
    /// (a traveler who stopped, or just stepped out of an elevator, is about to walk at a normal pace: a
    /// cue scheduled for standing still would end after the turn) and at most the cap.
    private func schedulingSpeed() -> Double {
        var v = 0.0
        if let last = progressHistory.last, let first = progressHistory.first, last.t - first.t >= 0.5 {
            v = (last.s - first.s) / (last.t - first.t)
        } else {
            // Just after a route was adopted: the speed of the estimate itself.
            v = speedMetersPerSecond()
        }
        return min(options.maximumSchedulingSpeedMetersPerSecond, max(options.nominalWalkingSpeedMetersPerSecond, v))
    }

    private func recordProgress(t: Double) {
        progressHistory.append((t, progressMeters))
        while let first = progressHistory.first, t - first.t > options.schedulingSpeedWindowSeconds + 1e-9 {
            progressHistory.removeFirst()
        }
    }

    /// How far before its control point a cue `text` of `priority` is issued so that it ends
    /// `cueEndMarginMeters` before it: margin + slack + speed x (wait for speech it may not cut off +
    /// its duration), at least `cueDistanceMeters`.
    private func cueLeadMeters(_ text: String?, priority: AnnouncementPriority, t: Double) -> Double {
        guard let text else { return options.cueDistanceMeters }
        let wait = policy.earliestStart(priority: priority, t: t) - t
        let lead = options.cueEndMarginMeters + options.cueSchedulingSlackMeters
            + schedulingSpeed() * (wait + policy.estimatedDurationSeconds(text))
        return max(options.cueDistanceMeters, lead)
    }

    /// Scheduling of the early alert of maneuver `m`, `d` meters ahead: its text, the distance at which it
    /// is due (`alertDistanceMeters`, or earlier so that it ends `alertCueGapMeters` before the cue's
    /// `cueLead`, plus the scheduling slack for the update step, at most `alertDistanceMeters + maximumAlertAdvanceMeters`) and the distance left when it
    /// would end if said now. Nil for maneuvers without an alert.
    private func alertDueMeters(_ m: Maneuver, d: Double, cueLead: Double, t: Double)
        -> (text: String, trigger: Double, endBeforeMeters: Double)? {
        guard let text = narrative.alert(m, distanceMeters: d, destinationName: destinationName) else { return nil }
        let v = schedulingSpeed()
        let lasts = v * (policy.earliestStart(priority: .alert, t: t) - t + policy.estimatedDurationSeconds(text))
        let trigger = min(options.alertDistanceMeters + options.maximumAlertAdvanceMeters,
                          max(options.alertDistanceMeters, cueLead + options.alertCueGapMeters + lasts
                                + options.cueSchedulingSlackMeters))
        return (text, trigger, d - lasts)
    }

    /// `text` (a route start or "Continue N meters" that names the distance to maneuver `next`), merged
    /// with the maneuver's "Then ..." phrase when its early alert would otherwise follow with less than
    /// `mergeGapSeconds` of silence (the alert would only repeat the distance): "Go straight ahead, 10
    /// meters. Then turn right." The alert is then not said. Unchanged for arrival, brief verbosity, or
    /// when the alert comes later.
    private func mergedWithNext(_ text: String, remainingMeters: Double, next: Int, route r: Route) -> String {
        guard options.phrasing.verbosity != .brief, next < r.maneuvers.count, !alertIssued[next],
              remainingMeters > options.alertDistanceMeters,
              let then = narrative.then(r.maneuvers[next]) else { return text }
        let v = schedulingSpeed()
        let alertDueAfterSeconds = (remainingMeters - options.alertDistanceMeters) / v
        guard alertDueAfterSeconds < policy.estimatedDurationSeconds(text) + options.mergeGapSeconds else { return text }
        alertIssued[next] = true
        return text + " " + then
    }

    /// How far the traveler has cut the corner of turn `m`: their offset from the route segment leading
    /// into the turn toward its inside (left of the segment for a left turn), meters, 0 when on the outside,
    /// elsewhere on the route or for other maneuvers, at most `maxCornerCutMeters`. People cut corners
    /// (up to a corridor's width): walking the diagonal they begin the turn before the route's corner and
    /// their progress along the route lags, so the cue is brought forward by as much.
    private func cornerCutMeters(toward m: Maneuver, route r: Route, input: NavigationInput) -> Double {
        guard m.kind.isTurn, let angle = m.turnAngleDeg else { return 0 }
        let q = Int(m.polylinePosition.rounded(.down))
        let i = Int(polylinePosition.rounded(.down))
        guard q >= 1, i == q - 1, r.points[i].floorId == input.floorId, r.points[q].floorId == input.floorId else { return 0 }
        let a = Vec2(r.points[i].position), b = Vec2(r.points[q].position)
        let dir = b - a
        guard dir.length > 1e-9 else { return 0 }
        let left = dir.cross(Vec2(input.positionInMap) - a) / dir.length
        let inside = angle > 0 ? left : -left
        return min(options.maxCornerCutMeters, max(0, inside))
    }

    /// Announces the maneuver chained to maneuver `i` ("Then turn left.") right after its cue, at alert
    /// rank so that it waits for the cue to end and a later cue may cut it off; the chained maneuver
    /// gets no alert or cue of its own.
    private func sayChained(after i: Int, route r: Route, t: Double) {
        let j = i + 1
        guard j < r.maneuvers.count, r.maneuvers[j].announcedWithPrevious, !cueIssued[j] else { return }
        cueIssued[j] = true
        alertIssued[j] = true
        if let text = narrative.then(r.maneuvers[j]) { say(text, .alert, t, about: r.maneuvers[j], variant: "cue") }
    }

    /// Follows the corridor from `start` (arrived from `cameFrom`) while it goes on within 45 deg of
    /// straight, up to 40 nodes, and returns the first spoken name met other than `skipping`.
    private func labelAlongCorridor(from start: Int, cameFrom: Int, skipping: String) -> String? {
        var prev = cameFrom, v = start
        for _ in 0..<40 {
            if let name = spokenName(ofNode: v), name != skipping { return name }
            let incoming = graph.positions[v] - graph.positions[prev]
            var bestNext: Int? = nil
            var bestAngle = 45.0
            for k in graph.adjStart[v]..<graph.adjStart[v + 1] {
                let e = Int(graph.adjEdge[k]), w = Int(graph.adjNode[k])
                guard w != prev, graph.edgeKind[e] == .horizontal else { continue }
                let out = graph.positions[w] - graph.positions[v]
                guard incoming.length > 1e-9, out.length > 1e-9 else { continue }
                let a = abs(signedTurnAngleRad(from: incoming, to: out)) * 180 / Double.pi
                if a < bestAngle { bestAngle = a; bestNext = w }
            }
            guard let n = bestNext else { return nil }
            prev = v; v = n
        }
        return nil
    }

    private func spokenName(ofNode v: Int) -> String? {
        let n = graph.nodes[v]
        if let id = n.pointOfInterestId {
            for f in graph.building.floors { if let p = f.pointsOfInterest.first(where: { $0.id == id }) { return p.name } }
        }
        return n.label
    }

    // MARK: - Output

    private func say(_ text: String, _ priority: AnnouncementPriority, _ t: Double, about m: Maneuver? = nil,
                     variant: String = "") {
        // Alerts and cues are keyed by the maneuver (kind, place, floor) so that two doors' identical
        // "Go through the door now." are both said, while the same maneuver is not repeated after a re-route.
        if variant == "cue", let m { policy.discardPending(repeatKeyPrefix: maneuverKey(m, variant: "alert")) }
        policy.submit(text, priority: priority, t: t, repeatKey: m.map { maneuverKey($0, variant: variant) + text })
    }

    /// While not localized: re-plans the exploratory instruction now and then and says it when it is new
    /// (a turn, or a different instruction after a gap) or when the repeat is due. A plain "walk ahead" right
    /// after a turn instruction is not said: it is what the turn instruction already told.
    private func guideWhileUnsure(_ input: NavigationInput, repeatDue: Bool) {
        let t = input.t
        if t - lastPlanT >= options.disambiguationIntervalSeconds - 1e-9 || lastAdvice == nil {
            lastPlanT = t
            lastAdvice = plan(input)
        }
        guard let advice = lastAdvice else { return }
        currentAdvice = advice
        let key = advice.phraseKey
        let changed = key != lastSpokenAdviceKey
        let gapOver = lastStartWalkingT.map { t - $0 >= options.disambiguationMinimumGapSeconds - 1e-6 } ?? true
        let redundant = advice.action == .ahead && lastSpokenAdviceKey.map { $0 != ExploratoryAction.ahead.phraseKey &&
            $0 != "disambiguate.unsure" } ?? false
        if repeatDue || (changed && gapOver && !redundant) {
            // What is said must hold where the traveler is now, not a second ago: re-plan before speaking.
            if t - lastPlanT > 1e-9 {
                lastPlanT = t
                lastAdvice = plan(input)
            }
            guard let fresh = lastAdvice else { return }
            currentAdvice = fresh
            let key = fresh.phraseKey
            say(narrative.phrases.phrase(key), .information, t)
            lastStartWalkingT = t
            lastSpokenAdviceKey = key
            lastSpokenAdvice = (t, fresh)
        }
    }

    /// The planner's advice for this input: its hypotheses, the walls the phone sees, and whether the hypotheses
    /// explain the sightings.
    private func plan(_ input: NavigationInput) -> DisambiguationAdvice {
        planner.advise(input.hypotheses, perceivedWalls: input.perceivedWalls,
                       hypothesesExplainSightings: !input.sightingsUnexplained)
    }

    /// The labelled place nearest the dominant hypothesis on its floor, for "Probably near ...".
    private func probablePlace(_ input: NavigationInput) -> String? {
        guard let h = input.hypotheses.first, let floor = graph.building.floor(id: h.floorId) else { return nil }
        let p = h.positionInMap
        var best: (name: String, d: Double)?
        for poi in floor.pointsOfInterest {
            let d = poi.position.distance(to: p)
            if d <= 15, best == nil || d < best!.d { best = (poi.name, d) }
        }
        for node in graph.building.graph.nodes where node.floorId == h.floorId {
            guard let label = node.label else { continue }
            let d = node.position.distance(to: p)
            if d <= 15, best == nil || d < best!.d { best = (label, d) }
        }
        return best?.name
    }

    private func maneuverKey(_ m: Maneuver, variant: String) -> String {
        "\(variant):\(m.kind.rawValue)@\(m.floorId):\(Int((m.position.x * 10).rounded())),\(Int((m.position.y * 10).rounded())):"
    }

    private func emit(_ t: Double) -> [TimedGuidanceEvent] {
        let events = policy.flush(t: t)
        for e in events {
            if case .speak(let text, _, _) = e.event, !policy.lastUtteranceWasRequested { lastInstruction = text }
        }
        return events
    }
}
