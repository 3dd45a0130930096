import Foundation
import Maps
import SessionFormat

/// Per-frame and per-walk facts behind a simulated walk that the bundle does not carry: what tests and the
/// evaluation compare generated data with.
public struct SimulationDiagnostics: Sendable {
    /// Graph node ids of the planned route, start to destination.
    public var routeNodeIds: [String]
    /// Node at which the wrong turn was taken, if any.
    public var wrongTurnAtNodeId: String?
    /// The walker's activity at each frame.
    public var phases: [WalkPhase]
    /// Speed along the path at each frame, m/s.
    public var speedsMetersPerSecond: [Double]
    /// The walk's preferred speed is not recorded; this is the camera height above the floor per frame, m.
    public var cameraHeightsMeters: [Double]
    /// Camera pitch per frame, radians.
    public var pitchesRad: [Double]
    /// Camera roll per frame, radians.
    public var rollsRad: [Double]
    /// Map-to-VIO yaw rotation per frame, radians (VIO yaw = map yaw + this), including drift and jumps.
    public var mapToVIOYawRad: [Double]
    /// VIO scale, drift and events.
    public var vio: VIOEvents
    /// Truth behind each observation (parallel to `SimulatedWalk.observations`).
    public var observationTruth: [ObservationTruth]
    /// Every truly visible sign on every processed frame, detected or not.
    public var visibleSigns: [VisibleSign]
    /// Indices of the frames the detector processed.
    public var processedFrameIndices: [Int]
    /// Barometer drift rate drawn for the walk, m/s.
    public var barometerDriftMetersPerSecond: Double
    /// Angle from magnetic north to map +y used by the compass, degrees clockwise.
    public var mapNorthOffsetDeg: Double
    /// Compass disturbance at each frame (floor bias + field + hotspot, without white noise), degrees; 0 when
    /// the compass is absent.
    public var compassDisturbanceDeg: [Double]
    /// Whether each frame's compass reading lies in a steel hotspot (a large deviation).
    public var compassInHotspot: [Bool]
    /// Core Location's `headingAccuracy` per frame, degrees (the bundle has no field for it); nil when the
    /// compass is absent.
    public var compassHeadingAccuracyDeg: [Double?]
    /// Altitude of the phone above the building reference per frame, m.
    public var altitudesMeters: [Double]
}

/// A simulated walk: everything a recorded-session bundle holds, plus diagnostics.
public struct SimulatedWalk: Sendable {
    /// The scenario it was made from.
    public var scenario: SimulationScenario
    /// session.json.
    public var info: SessionInfo
    /// One record per camera frame (ARKit pose in an arbitrary world frame, tracking, barometer, compass).
    public var frames: [FrameRecord]
    /// Simulated sign observations (only on processed frames).
    public var observations: [ObservationRecord]
    /// Ground truth per frame (camera position and heading in the map).
    public var truth: [TruthRecord]
    /// Expected announcements (none: the simulator does not speak; evaluation scores against truth).
    public var expected: [ExpectedAnnouncement]
    /// Facts behind the data.
    public var diagnostics: SimulationDiagnostics
    /// The scene, for rendering images when the walk is written.
    let renderer: SceneRenderer?
    /// Frame indices whose images are rendered (empty without `scenario.images`).
    public var imageFrameIndices: [Int]
    /// Simulated ARKit plane-anchor events (planes.jsonl; PlaneSimulator.swift).
    public var planes: [PlaneRecord] = []

    /// Lines the simulator's writer holds before writing them (`BundleWriter` group flush): a kill while
    /// writing loses at most this many lines minus one in all the files, plus at worst a partial last line.
    public static let flushEveryLines = 16

    /// Writes the walk as a recorded-session bundle (format v1) in `directory` through `BundleWriter`,
    /// rendering the images when the scenario asks for them. The directory must be absent or empty unless
    /// `overwrite` is true.
    ///
    /// The files are written interleaved in time order, as a phone records them: for each frame its image
    /// (first, so a frame line never names an image not yet on disk), the frame, its truth pose, then the
    /// observations at or before its time; lines go out in group flushes of `flushEveryLines`. A walk cut
    /// off by a kill is therefore a time prefix of the whole walk in every file.
    public func write(to directory: URL, overwrite: Bool = false) throws {
        try write(to: directory, overwrite: overwrite, afterFrame: nil)
    }

    /// `write(to:overwrite:)` calling `afterFrame(i)` once frame `i` and its truth and observations are
    /// appended (tests look at the files on disk mid-write).
    func write(to directory: URL, overwrite: Bool, afterFrame: ((Int) throws -> Void)?) throws {
        let writer = try BundleWriter(directory: directory, info: info, overwrite: overwrite,
                                      flushEveryLines: Self.flushEveryLines)
        var nextObservation = 0
        for (i, f) in frames.enumerated() {
            if let name = f.image, let r = renderer {
                do { try writer.writeImage(named: name, data: r.renderPPM(frameIndex: i)) } catch { try? writer.close(); throw error }
            }
            try writer.append(f)
            if i < truth.count { try writer.append(truth[i]) }
            while nextObservation < observations.count, observations[nextObservation].t <= f.t {
                try writer.append(observations[nextObservation])
                nextObservation += 1
            }
            try afterFrame?(i)
        }
        for i in frames.count..<max(frames.count, truth.count) { try writer.append(truth[i]) }
        for o in observations[nextObservation...] { try writer.append(o) }
        for e in expected { try writer.append(e) }
        for p in planes { try writer.append(p) }
        try writer.close()
    }

    /// The image of frame `index` as binary PPM (P6), rendered on demand; nil when the walk has no renderer.
    public func renderImage(frameIndex index: Int) -> Data? { renderer?.renderPPM(frameIndex: index) }
}

/// The simulator: a person walking a route with a phone, and what the phone records (see docs/simulator.md).
public enum WalkSimulator {
    /// Version string written as `appVersion` in session.json.
    public static let version = "wayfinder-simulator 1"

    /// Simulates `scenario` on `building` with the given noise parameters (defaults: docs/simulator.md).
    /// Deterministic: the same building, scenario and parameters give identical output.
    /// - Throws: `SimulationError` for unknown places, unreachable destinations, routes through walls, bad
    ///   settings.
    public static func simulate(building: Building, scenario: SimulationScenario,
                                parameters: SimulationParameters = .standard) throws -> SimulatedWalk {
        try scenario.validate()
        try parameters.validate()
        let dt = 1 / scenario.rateHz
        let planner = RoutePlanner(building: building)
        let start = try planner.resolve(scenario.from)
        let dest = try planner.resolve(scenario.to)
        guard start.nodeIndex != dest.nodeIndex else {
            throw SimulationError.invalidScenario("\(scenario.name): start and destination are the same place")
        }
        guard let route = planner.shortestPath(from: start.nodeIndex, to: dest.nodeIndex) else {
            throw SimulationError.noRoute(from: scenario.from, to: scenario.to)
        }
        var geometry: [String: FloorGeometry] = [:]
        var floorsById: [String: Floor] = [:]
        for f in building.floors { geometry[f.id] = FloorGeometry(walls: f.walls); floorsById[f.id] = f }
        let elevations = Dictionary(building.floors.map { ($0.id, $0.elevationMeters) }, uniquingKeysWith: { a, _ in a })
        let nodes = building.graph.nodes

        // Waypoints (with the wrong-turn detour).
        var routeRng = SeededRandom(seed: scenario.seed, stream: RandomStream.route.rawValue)
        var waypoints: [WalkPathBuilder.Waypoint] = route.map {
            .init(floorId: nodes[$0].floorId, position: nodes[$0].position, cusp: false, nodeIndex: $0)
        }
        var wrongTurnNode: String?
        if scenario.wrongTurn {
            let (wps, node) = try insertWrongTurn(route: route, planner: planner, building: building,
                                                  geometry: geometry, parameters: parameters.walker, rng: &routeRng)
            waypoints = wps; wrongTurnNode = node
        }
        if let minutes = scenario.tourMinutes {
            waypoints = tourWaypoints(route: route, nodes: nodes, minutes: minutes,
                                      fastestSpeed: parameters.walker.preferredSpeedRange.upperBound)
        }
        var walkerRng = SeededRandom(seed: scenario.seed, stream: RandomStream.walker.rawValue)
        let segments = try WalkPathBuilder(building: building, geometry: geometry, parameters: parameters.walker)
            .build(waypoints: waypoints, rng: &walkerRng)
        var startHeading = 0.0
        if case .leg(let l)? = segments.first { var h = 0; startHeading = l.tangent(at: 0, hint: &h) }
        let body = WalkerModel(parameters: parameters.walker, geometry: geometry, elevations: elevations, rateHz: scenario.rateHz)
            .run(segments: segments, startHeading: startHeading, rng: &walkerRng)
        guard body.count < WalkerModel.maxFrames(rateHz: scenario.rateHz) else {
            throw SimulationError.invalidScenario("\(scenario.name): the walk did not finish within 4 hours of simulated time")
        }
        try verifyNoWallCrossing(body, geometry: geometry)

        // Phone on the body.
        var phoneRng = SeededRandom(seed: scenario.seed, stream: RandomStream.phone.rawValue)
        let phone = PhoneModel(parameters: parameters.phone, carry: scenario.carry, orientation: scenario.orientation, dt: dt)
            .run(body: body, rng: &phoneRng)

        // True camera states, with a smoothed yaw rate.
        var states: [TrueCameraState] = []
        states.reserveCapacity(body.count)
        let yaws = zip(body, phone).map { wrapAngle($0.headingRad + $1.yawOffsetRad) }
        let bodyRates: [Double] = body.indices.map { k in
            let w = max(1, Int((0.1 / dt).rounded()))
            let a = max(0, k - w), b = min(body.count - 1, k + w)
            return b > a ? wrapAngle(body[b].headingRad - body[a].headingRad) / (body[b].t - body[a].t) : 0
        }
        for (k, (b, ph)) in zip(body, phone).enumerated() {
            states.append(TrueCameraState(t: b.t, floorId: b.floorId, position: Point2Value(x: b.position.x, y: b.position.y),
                                          altitudeMeters: b.floorElevation + ph.heightMeters, heightAboveFloorMeters: ph.heightMeters,
                                          yawRad: yaws[k], pitchRad: ph.pitchRad, rollRad: ph.rollRad,
                                          yawRateRadPerSecond: bodyRates[k]))
        }

        // VIO.
        var vioRng = SeededRandom(seed: scenario.seed, stream: RandomStream.vio.rawValue)
        var trackingRng = SeededRandom(seed: scenario.seed, stream: RandomStream.tracking.rawValue)
        let (vio, thetas, events) = VIOModel(parameters: parameters.vio, dt: dt, trackingLossAt: scenario.trackingLossAt,
                                             trackingLossDuration: scenario.trackingLossDurationSeconds,
                                             resetAt: scenario.vioResetAt)
            .run(states: states, rng: &vioRng, trackingRng: &trackingRng)

        // Barometer and compass.
        var baroRng = SeededRandom(seed: scenario.seed, stream: RandomStream.barometer.rawValue)
        let (baro, baroDrift) = BarometerModel(parameters: parameters.barometer)
            .run(times: states.map(\.t), altitudes: states.map(\.altitudeMeters), rng: &baroRng)
        var compassRng = SeededRandom(seed: scenario.seed, stream: RandomStream.compass.rawValue)
        let compassModel = CompassModel(parameters: parameters.compass)
        let northOffset = scenario.mapNorthOffsetDeg ?? building.compassHeadingOfMapNorthDeg ?? compassRng.uniform(0, 360)
        var fields: [String: CompassModel.Field] = [:]
        for f in building.floors { fields[f.id] = compassModel.makeField(rng: &compassRng) }
        let typicalAccuracyDeg = compassModel.drawTypicalAccuracyDeg(rng: &compassRng)
        let compassPresent = parameters.compass.isPresent

        // Frames, images and truth.
        let imageMode = scenario.images
        let intrinsics = imageMode ? SceneRenderer.imageIntrinsics : CameraIntrinsics.iPhone8Full
        let detectorStride = max(1, Int((scenario.rateHz / scenario.detectorRateHz).rounded()))
        let imageStride = max(detectorStride, Int((scenario.rateHz / scenario.imageRateHz).rounded()))
        var frames: [FrameRecord] = [], truth: [TruthRecord] = []
        var disturbances: [Double] = [], inHotspot: [Bool] = [], headingAccuracies: [Double?] = []
        var imageIndices: [Int] = []
        frames.reserveCapacity(states.count); truth.reserveCapacity(states.count)
        for (k, s) in states.enumerated() {
            var heading: Double?
            if compassPresent, let field = fields[s.floorId] {
                let dist = compassModel.disturbance(field, x: s.position.x, y: s.position.y)
                disturbances.append(dist.totalDeg); inHotspot.append(dist.inHotspot)
                headingAccuracies.append(compassModel.reportedAccuracyDeg(typicalDeg: typicalAccuracyDeg, disturbance: dist))
                heading = compassModel.reading(yawRad: s.yawRad, northOffsetDeg: northOffset, disturbanceDeg: dist.totalDeg,
                                               rng: &compassRng)
            } else {
                disturbances.append(0); inHotspot.append(false); headingAccuracies.append(nil)
            }
            var image: String?
            if imageMode && k % imageStride == 0 { image = String(format: "frame-%06d.ppm", k); imageIndices.append(k) }
            frames.append(FrameRecord(t: s.t, cameraToWorld: vio[k].cameraToWorld, tracking: vio[k].tracking,
                                      trackingReason: vio[k].reason, intrinsics: intrinsics, relativeAltitudeMeters: baro[k],
                                      compassHeadingDeg: heading, image: image,
                                      compassAccuracyDeg: heading == nil ? nil : headingAccuracies.last ?? nil))
            truth.append(TruthRecord(t: s.t, x: s.position.x, y: s.position.y, floorId: s.floorId, headingRad: s.yawRad))
        }

        // The building as it truly is against the map (the survey's errors; the map itself when there are none).
        var surveyRng = SeededRandom(seed: scenario.seed, stream: RandomStream.survey.rawValue)
        let world = SurveyErrors(floors: floorsById, parameters: parameters.survey, rng: &surveyRng)

        // Observations on processed frames.
        var obsModel = SignObservationModel(parameters: parameters.detector, floors: world.floors, geometry: geometry,
                                            intrinsics: intrinsics, catalogue: building.signCatalogue)
        obsModel.surveyRangeFactors = world.rangeFactors
        var placeRng = SeededRandom(seed: scenario.seed, stream: RandomStream.lookAlikes.rawValue)
        obsModel.lookAlikes = obsModel.placeLookAlikes(rng: &placeRng)
        var detRng = SeededRandom(seed: scenario.seed, stream: RandomStream.detector.rawValue)
        var fpRng = SeededRandom(seed: scenario.seed, stream: RandomStream.falsePositives.rawValue)
        var lookAlikeRng = SeededRandom(seed: scenario.seed, stream: RandomStream.lookAlikeDetections.rawValue)
        var observations: [ObservationRecord] = [], obsTruth: [ObservationTruth] = [], visible: [VisibleSign] = []
        var processed: [Int] = []
        for k in stride(from: 0, to: states.count, by: detectorStride) {
            processed.append(k)
            // The detector runs on images; none while tracking is unavailable (no pose to range with).
            if vio[k].tracking == .notAvailable { continue }
            for (o, tr) in obsModel.observe(frameIndex: k, state: states[k], rng: &detRng, fpRng: &fpRng,
                                                 lookAlikeRng: &lookAlikeRng, visibleLog: &visible) {
                observations.append(o); obsTruth.append(tr)
            }
        }

        let startFloor = body.first?.floorId ?? start.floorId
        // The session records the Exit-sign face height of the building's catalogue (as WalkRecorder does).
        let signHeight = building.signCatalogue.heightMeters(kind: SignKindSpec.defaultExit.kind)
            ?? SignKindSpec.defaultExit.heightMeters
        var declaredStartId: String?
        if let declared = scenario.declaredStart {
            guard let poi = building.pointOfInterest(idOrName: declared) else {
                throw SimulationError.invalidScenario("\(scenario.name): declaredStart '\(declared)' is not a point of interest of the map")
            }
            declaredStartId = poi.poi.id
        } else if scenario.startKnown {
            declaredStartId = start.poi?.id ?? nodes[start.nodeIndex].id
        }
        let info = SessionInfo(device: "simulator", appVersion: version, mapId: building.id, floorId: startFloor,
                               start: declaredStartId,
                               destination: dest.poi?.id ?? nodes[dest.nodeIndex].id, signHeightMeters: signHeight,
                               intrinsics: intrinsics, carry: scenario.carry.rawValue,
                               source: "simulated: scenario \(scenario.name), seed \(scenario.seed)")
        let diagnostics = SimulationDiagnostics(
            routeNodeIds: route.map { nodes[$0].id }, wrongTurnAtNodeId: wrongTurnNode,
            phases: body.map(\.phase), speedsMetersPerSecond: body.map(\.speed),
            cameraHeightsMeters: phone.map(\.heightMeters), pitchesRad: phone.map(\.pitchRad), rollsRad: phone.map(\.rollRad),
            mapToVIOYawRad: thetas, vio: events, observationTruth: obsTruth, visibleSigns: visible,
            processedFrameIndices: processed, barometerDriftMetersPerSecond: baroDrift, mapNorthOffsetDeg: northOffset,
            compassDisturbanceDeg: disturbances, compassInHotspot: inHotspot,
            compassHeadingAccuracyDeg: headingAccuracies, altitudesMeters: states.map(\.altitudeMeters))
        let renderer = imageMode ? SceneRenderer(floors: world.floors, geometry: geometry, states: states, intrinsics: intrinsics,
                                                 seed: scenario.seed) : nil
        var walk = SimulatedWalk(scenario: scenario, info: info, frames: frames, observations: observations, truth: truth,
                                 expected: [], diagnostics: diagnostics, renderer: renderer, imageFrameIndices: imageIndices)
        // ARKit vertical planes (own random stream: switching planes off changes nothing else).
        var planeRng = SeededRandom(seed: scenario.seed, stream: PlaneSimulator.randomStream)
        var planeSimulator = PlaneSimulator(parameters: parameters.planes, floors: floorsById, geometry: geometry)
        planeSimulator.wallOffsetSigmaMeters = parameters.survey.wallOffsetSigmaMeters
        planeSimulator.surveyRng = surveyRng  // after the signs' draws
        walk.planes = planeSimulator
            .run(states: states, vio: vio, mapToVIOYaw: thetas, scale: events.scale, resetTime: events.resetTime, rng: &planeRng)
        return walk
    }

    /// The route chained with its reverse (out, back, out, ...), a turn-around (cusp) at each end, long enough
    /// that walking it at `fastestSpeed` takes at least `minutes` (so any drawn preferred speed takes longer).
    static func tourWaypoints(route: [Int], nodes: [GraphNode], minutes: Double, fastestSpeed: Double) -> [WalkPathBuilder.Waypoint] {
        var length = 0.0
        for (a, b) in zip(route, route.dropFirst()) where nodes[a].floorId == nodes[b].floorId {
            length += hypot(nodes[b].position.x - nodes[a].position.x, nodes[b].position.y - nodes[a].position.y)
        }
        let legs = max(1, Int((minutes * 60 * fastestSpeed / max(length, 1)).rounded(.up)))
        var out: [WalkPathBuilder.Waypoint] = []
        for leg in 0..<legs {
            let order = leg % 2 == 0 ? route : Array(route.reversed())
            for (k, n) in order.enumerated() where leg == 0 || k > 0 {
                out.append(.init(floorId: nodes[n].floorId, position: nodes[n].position,
                                 cusp: k == order.count - 1 && leg < legs - 1, nodeIndex: n))
            }
        }
        return out
    }

    /// Throws when any step between consecutive truth positions on one floor crosses a wall.
    static func verifyNoWallCrossing(_ body: [BodyState], geometry: [String: FloorGeometry]) throws {
        for k in 1..<max(1, body.count) where body[k].floorId == body[k - 1].floorId {
            let a = body[k - 1].position, b = body[k].position
            if a == b { continue }
            if geometry[body[k].floorId]?.segmentCrossesWall(a, b) == true {
                throw SimulationError.routeCrossesWall("truth step at t=\(String(format: "%.2f", body[k].t)) s on floor \(body[k].floorId) from (\(fmt(a))) to (\(fmt(b)))")
            }
        }
    }

    /// Picks a junction on the route with a branch off it, and inserts a detour: down the branch a few
    /// meters, turn around, back to the junction.
    static func insertWrongTurn(route: [Int], planner: RoutePlanner, building: Building, geometry: [String: FloorGeometry],
                                parameters: WalkerParameters, rng: inout SeededRandom) throws -> ([WalkPathBuilder.Waypoint], String) {
        let nodes = building.graph.nodes
        var candidates: [(routeIndex: Int, branch: Int)] = []
        var along = 0.0
        var cumulative = [0.0]
        for i in 1..<route.count {
            let a = nodes[route[i - 1]], b = nodes[route[i]]
            along += a.floorId == b.floorId ? hypot(a.position.x - b.position.x, a.position.y - b.position.y) : 0
            cumulative.append(along)
        }
        for i in 1..<max(1, route.count - 1) {
            let j = nodes[route[i]]
            guard nodes[route[i - 1]].floorId == j.floorId, nodes[route[i + 1]].floorId == j.floorId else { continue }
            guard cumulative[i] >= 2 else { continue }
            for (nb, len) in planner.neighbors[route[i]] where nb != route[i - 1] && nb != route[i + 1] {
                let n = nodes[nb]
                guard n.floorId == j.floorId, len >= 2.0, n.kind != .pointOfInterest || len >= 3 else { continue }
                candidates.append((i, nb))
            }
        }
        guard !candidates.isEmpty else {
            throw SimulationError.noWrongTurnPossible("the route \(nodes[route.first!].id) -> \(nodes[route.last!].id) passes no junction with a branch of 2 m or more")
        }
        // Prefer junctions in the middle half of the route.
        let total = cumulative.last ?? 0
        let middle = candidates.filter { cumulative[$0.routeIndex] >= 0.2 * total && cumulative[$0.routeIndex] <= 0.8 * total }
        let pool = middle.isEmpty ? candidates : middle
        let pick = pool[min(pool.count - 1, Int(rng.uniform() * Double(pool.count)))]
        let j = nodes[route[pick.routeIndex]], b = nodes[pick.branch]
        let len = hypot(b.position.x - j.position.x, b.position.y - j.position.y)
        let go = min(rng.uniform(parameters.wrongTurnDistanceRange.lowerBound, parameters.wrongTurnDistanceRange.upperBound), 0.8 * len)
        let far = Point2(j.position.x + go * (b.position.x - j.position.x) / len, j.position.y + go * (b.position.y - j.position.y) / len)
        var wps: [WalkPathBuilder.Waypoint] = []
        for (i, n) in route.enumerated() {
            wps.append(.init(floorId: nodes[n].floorId, position: nodes[n].position, cusp: false, nodeIndex: n))
            if i == pick.routeIndex {
                wps.append(.init(floorId: j.floorId, position: far, cusp: true, nodeIndex: nil))
                wps.append(.init(floorId: j.floorId, position: j.position, cusp: false, nodeIndex: n))
            }
        }
        return (wps, j.id)
    }
}
