import Foundation
import Maps
import Localizer
import Navigation
import SessionFormat

/// What one frame produced.
public struct PipelineUpdate: Sendable {
    /// Frame time, seconds.
    public var t: Double
    /// Localizer output after this frame.
    public var estimate: LocalizationEstimate
    /// Sign sightings fed to the localizer on this frame (empty when the detector did not run).
    public var sightings: [SignSighting]
    /// True when the detector (or the recorded observations) was consulted on this frame.
    public var detectorRan: Bool
    /// Speech and haptic events decided by the navigator's announcement policy.
    public var events: [TimedGuidanceEvent]
    /// Problems with this frame that were degraded gracefully (non-finite pose, unreadable image...).
    public var warnings: [String]
    /// While not localized: the navigator's current exploratory advice (nil when localized or no navigator).
    public var advice: DisambiguationAdvice? = nil
    /// The exploratory advice spoken on this frame, if one was.
    public var spokenAdvice: DisambiguationAdvice? = nil
}

/// The app's pipeline, shared by the iPhone and the command line:
/// frame -> sign detector -> range estimator -> particle filter -> navigator -> announcement policy.
///
/// Owns its localizer, detector and navigator. Not thread-safe: feed frames from one queue.
public final class WayfinderPipeline {
    /// The building being navigated.
    public let building: Building
    /// Options it was created with.
    public let options: PipelineOptions
    private let localizer: ParticleLocalizer
    private let sightingSource: SignSightingSource
    /// Which wall kinds each detector frame looks for (options.wallKindSchedule).
    private var wallKindScheduler: WallKindScheduler
    /// The hypotheses of the last frame's estimate (what the next detector frame expects to see).
    private var lastHypotheses: [PoseHypothesis] = []
    /// The last frame's estimate when localized, nil when not: uncorroborated sightings are weighed only while not
    /// localized, and while localized an object the lock does not explain counts once per meter (`corroboration`).
    private var lastLockedEstimate: LocalizationEstimate?
    private var navigator: Navigator?
    private var lastDetectionT = -Double.infinity
    /// Confirms sightings against the earlier detector frames' (options.sightingCorroboration).
    private var corroboration: SightingCorroboration
    private var lastAltitude: Double?
    private var compassPriorApplied = false
    private var northCheck: CompassNorthCheck?
    /// Set when the north check found the map's north wrong: no more compass evidence this session.
    private var compassOffByNorthCheck = false
    private var planeTable = PlaneAnchorTable()
    private var lastPlaneUpdateT = -Double.infinity
    /// Whether the last frame was tracked and not initializing (an initializing frame after it is then a restart of
    /// world tracking: `isTrackingRestart`).
    private var trackedBefore = false

    /// Creates the pipeline and initializes the localizer from the start prior (floor only, or a chosen
    /// start place). Throws when the floor, start or destination is unknown, or a detector model is missing.
    public init(building: Building, options: PipelineOptions, imagesAvailable: Bool = false) throws {
        self.building = building
        self.options = options
        corroboration = SightingCorroboration(parameters: options.sightingCorroboration)
        guard let firstFloor = building.floors.first else { throw PipelineError.invalidConfiguration("the map has no floors") }
        var parameters = options.localizerParameters
        if !options.useCompass { parameters["compass.enabled"] = 0 }
        var localizerOptions = options.localizer
        localizerOptions.maxSignRangeMeters = max(localizerOptions.maxSignRangeMeters, options.signHorizonMeters)
        localizer = try ParticleLocalizer(building: building, options: localizerOptions, parameters: parameters,
                                          seed: options.seed)
        if let start = options.startPointOfInterestId {
            guard let poi = building.pointOfInterest(idOrName: start) else {
                throw PipelineError.invalidConfiguration("unknown start '\(start)'")
            }
            try localizer.reset(prior: .startPoint(floorId: poi.floorId, position: poi.poi.position,
                                                   radiusMeters: options.startRadiusMeters))
        } else {
            let floorId = options.floorId ?? firstFloor.id
            guard building.floor(id: floorId) != nil else {
                throw PipelineError.invalidConfiguration("unknown floor '\(floorId)'")
            }
            try localizer.reset(prior: .floorOnly(floorId: floorId))
        }
        if let destination = options.destinationId {
            navigator = try Navigator(building: building, destinationId: destination, options: options.navigator)
        }
        sightingSource = try SignSightingSource(options: options, catalogue: building.signCatalogue,
                                                imagesAvailable: imagesAvailable)
        wallKindScheduler = WallKindScheduler(kinds: sightingSource.wallKinds, mode: options.wallKindSchedule)
        if options.useCompass, building.compassHeadingOfMapNorthDeg != nil, let p = options.compassNorthCheck {
            northCheck = CompassNorthCheck(parameters: p)
        }
    }

    /// The north check's verdict when it found the map's north wrong on this walk (see `CompassNorthCheck`);
    /// nil while it has not (or when it is off).
    public var compassNorthVerdict: CompassNorthCheck.Verdict? { northCheck?.verdict }

    /// Processes one frame: motion update, altitude, detection (at most every `detectionIntervalSeconds`),
    /// sign update, guidance.
    public func process(_ frame: PipelineFrame) -> PipelineUpdate {
        var warnings: [String] = []
        if frame.tracking == .notAvailable || frame.cameraPose == nil { corroboration.reset() }
        if isTrackingRestart(frame) {
            // A new VIO origin: no motion update spans the seam, and the sightings' VIO places are in the old frame.
            corroboration.reset()
            localizer.noteVIOReset()
            warnings.append("t=\(frame.t): world tracking restarted (initializing again); the VIO frame is new")
        }
        if let pose = frame.cameraPose {
            localizer.predict(VIOConversion.sample(t: frame.t, pose: pose, tracking: frame.tracking))
            noteInputError("motion update", &warnings)
        } else {
            warnings.append("t=\(frame.t): camera pose is not finite; motion update skipped")
            localizer.predict(VIOSample(t: frame.t, east: .nan, north: .nan, yawRad: .nan, tracking: .notAvailable))
        }
        applyCompassPriorIfDue(frame)
        applyCompassEvidence(frame, &warnings)
        if let altitude = frame.relativeAltitudeMeters, altitude.isFinite {
            localizer.updateAltitude(relativeAltitudeMeters: altitude, t: frame.t)
            noteInputError("altitude", &warnings)
        }

        updatePlanesIfDue(frame, warnings: &warnings)

        var sightings: [SignSighting] = []
        var detectorRan = false
        let due = frame.t - lastDetectionT >= options.detectionIntervalSeconds - 1e-9
        if (due || !frame.measuredObservations.isEmpty), let pose = frame.cameraPose, frame.tracking != .notAvailable {
            switch sightingSource.sightings(for: frame, pose: pose, searchedWallKinds: nextWallKinds()) {
            case .success(let result):
                if let found = result {
                    sightings = corroboration.corroborate(
                        found.sightings.filter { $0.rangeMeters <= options.maximumSightingRangeMeters }, t: frame.t, pose: pose,
                        lock: lockContext())
                    detectorRan = true
                    lastDetectionT = frame.t
                    localizer.update(sightings: sightings, unsearchedKinds: found.unsearchedKinds, t: frame.t)
                    noteInputError("sign update", &warnings)
                }
            case .failure(let error):
                warnings.append("t=\(frame.t): \(error)")
            }
        }

        let estimate = localizer.estimate
        lastHypotheses = estimate.hypotheses
        lastLockedEstimate = estimate.isLocalized ? estimate : nil
        checkNorth(frame, estimate, &warnings)
        var events: [TimedGuidanceEvent] = []
        if let navigator {
            // While tracking is lost the hypotheses are where the traveler was when it was lost, not where they
            // walk now: no exploratory instruction is planned from them, and while not localized the navigator
            // says nothing (the phone's tracking prompt asks for the camera).
            let trackingLost = frame.tracking == .notAvailable
            events = navigator.update(NavigationInput(t: frame.t, positionInMap: estimate.positionInMap,
                                                      floorId: estimate.floorId, headingRad: estimate.headingRad,
                                                      isLocalized: estimate.isLocalized,
                                                      confidence: estimate.confidence,
                                                      hypotheses: trackingLost ? [] : estimate.hypotheses.map {
                                                          PoseCandidate(weight: $0.weight, floorId: $0.floorId,
                                                                        positionInMap: $0.positionInMap,
                                                                        headingRad: $0.headingRad,
                                                                        positionStdMeters: $0.positionStdMeters,
                                                                        headingStdRad: $0.headingStdRad)
                                                      },
                                                      perceivedWalls: estimate.isLocalized || trackingLost
                                                          ? [] : perceivedWalls(frame),
                                                      trackingLost: trackingLost,
                                                      sightingsUnexplained: estimate.sightingsUnexplained))
        }
        var update = PipelineUpdate(t: frame.t, estimate: estimate, sightings: sightings, detectorRan: detectorRan,
                                    events: events, warnings: warnings)
        if let navigator, !estimate.isLocalized {
            update.advice = navigator.currentAdvice
            if let spoken = navigator.lastSpokenAdvice, spoken.t == frame.t { update.spokenAdvice = spoken.advice }
        }
        return update
    }

    /// Whether `frame` starts a restart of world tracking: ARKit initializing again after it tracked (the phone's
    /// `HealthCommand.restartTracking`, or a reset ARKit made), directly or after notAvailable frames (a frame
    /// that was lost does not clear the record: after a restart ARKit may report notAvailable first). Advances the
    /// record of what was tracked before.
    private func isTrackingRestart(_ frame: PipelineFrame) -> Bool {
        let initializing = frame.tracking == .limited && frame.trackingReason == .initializing
        let restart = initializing && trackedBefore
        if initializing {
            trackedBefore = false
        } else if frame.tracking != .notAvailable && frame.cameraPose != nil {
            trackedBefore = true
        }
        return restart
    }

    /// The last frame's locked pose with its floor's signs, for `SightingCorroboration`; nil when not localized.
    private func lockContext() -> SightingCorroboration.Lock? {
        guard let e = lastLockedEstimate, let floor = building.floor(id: e.floorId) else { return nil }
        return SightingCorroboration.Lock(positionInMap: e.positionInMap, headingRad: e.headingRad, signs: floor.signs)
    }

    /// The wall kinds the detector frame about to run looks for (advances the schedule): with `.expected`, the kinds
    /// the localizer's hypotheses expect in view first (`ExpectedSignKinds`, from the previous frame's estimate: the
    /// motion since is a frame's; weighed only for a frame that searches some wall kind). Nil when no schedule
    /// applies (recorded observations used whole).
    private func nextWallKinds() -> Set<String>? {
        guard sightingSource.schedulesWallKinds else { return nil }
        var shares: [String: Double] = [:]
        if wallKindScheduler.mode == .expected && wallKindScheduler.searchesNextFrame {
            shares = ExpectedSignKinds.shares(hypotheses: lastHypotheses, building: building,
                                              kinds: Set(wallKindScheduler.kinds),
                                              halfFieldOfViewRad: 0.5 * options.localizer.horizontalFieldOfViewRad,
                                              maxRangeMeters: options.maximumSightingRangeMeters)
        }
        return wallKindScheduler.next(expectedShares: shares)
    }

    /// The live planes of the current floor as walls in the traveler's frame at this frame's camera pose (none
    /// without a pose or with planes off): the guidance while unsure never leads into a wall the phone sees.
    private func perceivedWalls(_ frame: PipelineFrame) -> [PerceivedWall] {
        guard options.usePlanes, let pose = frame.cameraPose, !planeTable.anchors.isEmpty else { return [] }
        return PlaneConversion.perceivedWalls(planeTable.observations, at: pose)
    }

    /// Takes ARKit plane-anchor events (add / update / remove) that arrived since the last frame; they are
    /// scored at the next `process`. Ignored when `options.usePlanes` is off.
    public func ingest(planes events: [PlaneRecord]) {
        guard options.usePlanes else { return }
        for e in events { planeTable.apply(e) }
    }

    /// Scores the live vertical planes against the walls, at most every `planeUpdateIntervalSeconds`, with a
    /// valid pose; a VIO reset state drops every anchor first (PlaneAnchorTable).
    private func updatePlanesIfDue(_ frame: PipelineFrame, warnings: inout [String]) {
        guard options.usePlanes else { return }
        planeTable.observe(tracking: frame.tracking, reason: frame.trackingReason)
        planeTable.observe(altitudeMeters: frame.relativeAltitudeMeters)
        guard frame.cameraPose != nil, !planeTable.anchors.isEmpty,
              frame.t - lastPlaneUpdateT >= options.planeUpdateIntervalSeconds - 1e-9 else { return }
        lastPlaneUpdateT = frame.t
        localizer.updatePlanes(planeTable.observations, t: frame.t)
        if let e = localizer.lastInputError { warnings.append("t=\(frame.t): planes: \(e)") }
    }

    /// Gives the localizer the compass prior once, at the first frame with a finite compass reading, when the
    /// map knows where its north is and the options enable it. The reading is the camera's heading in degrees
    /// clockwise from magnetic north; in the map frame (radians counter-clockwise from +x) that is
    /// pi/2 - (reading - compassHeadingOfMapNorthDeg) in radians.
    private func applyCompassPriorIfDue(_ frame: PipelineFrame) {
        guard options.useCompass, !compassPriorApplied, let sigmaDeg = options.compassPriorSigmaDeg, sigmaDeg > 0,
              let northDeg = building.compassHeadingOfMapNorthDeg,
              let readingDeg = frame.compassHeadingDeg, readingDeg.isFinite, frame.cameraPose != nil else { return }
        compassPriorApplied = true
        localizer.setCompassPrior(headingInMapRad: Self.headingInMapRad(readingDeg: readingDeg, northDeg: northDeg),
                                  sigmaRad: sigmaDeg * Double.pi / 180)
    }

    /// Gives the localizer every finite compass reading as evidence (it applies one at most once per few meters
    /// walked), converted to the map frame like the prior, with Core Location's accuracy when recorded.
    private func applyCompassEvidence(_ frame: PipelineFrame, _ warnings: inout [String]) {
        guard options.useCompass, !compassOffByNorthCheck, let northDeg = building.compassHeadingOfMapNorthDeg,
              let readingDeg = frame.compassHeadingDeg, frame.cameraPose != nil else { return }
        guard readingDeg.isFinite, readingDeg >= 0, readingDeg <= 360 else {
            warnings.append("t=\(frame.t): compass heading \(readingDeg) is outside 0...360 degrees; ignored")
            return
        }
        let accuracyRad = frame.compassAccuracyDeg.flatMap { $0.isFinite && $0 > 0 && $0 <= 180 ? $0 * Double.pi / 180 : nil }
        localizer.updateCompass(headingInMapRad: Self.headingInMapRad(readingDeg: readingDeg, northDeg: northDeg),
                                accuracyRad: accuracyRad, t: frame.t)
        noteInputError("compass", &warnings)
    }

    /// Feeds the north check (the compass against the localized heading); when it finds the map's north wrong,
    /// warns once and stops the compass evidence for the rest of the session.
    private func checkNorth(_ frame: PipelineFrame, _ estimate: LocalizationEstimate, _ warnings: inout [String]) {
        guard northCheck != nil, let northDeg = building.compassHeadingOfMapNorthDeg else { return }
        let compassInMap = frame.compassHeadingDeg.flatMap { r -> Double? in
            r.isFinite && r >= 0 && r <= 360 ? Self.headingInMapRad(readingDeg: r, northDeg: northDeg) : nil
        }
        let position = frame.cameraPose?.positionInVIOPlane
        guard let verdict = northCheck?.observe(compassInMapRad: compassInMap,
                                                localizedHeadingRad: estimate.isLocalized ? estimate.headingRad : nil,
                                                cameraEastMeters: position?.east, cameraNorthMeters: position?.north)
        else { return }
        compassOffByNorthCheck = true
        warnings.append(String(format: "t=%.1f: the compass reads %.0f degrees %@ the localized heading over %.0f m "
                                   + "walked (%d readings, resultant %.2f): the map's north (compassHeadingOfMapNorthDeg "
                                   + "%.1f) may be wrong; compass evidence off for the rest of the session",
                               frame.t, abs(verdict.offsetDeg), verdict.offsetDeg > 0 ? "counter-clockwise of" : "clockwise of",
                               verdict.walkedMeters, verdict.samples, verdict.resultant, northDeg))
    }

    /// A compass reading (degrees clockwise from magnetic north) as a camera heading in the map frame (radians
    /// counter-clockwise from +x, wrapped to (-pi, pi]), given the map's `compassHeadingOfMapNorthDeg`.
    static func headingInMapRad(readingDeg: Double, northDeg: Double) -> Double {
        let h = Double.pi / 2 - (readingDeg - northDeg) * Double.pi / 180
        return atan2(sin(h), cos(h))
    }

    /// Reports the localizer's last rejected input (NaN, out of range) as a warning of this frame.
    private func noteInputError(_ what: String, _ warnings: inout [String]) {
        if let error = localizer.lastInputError { warnings.append("\(what) ignored by the localizer: \(error)") }
    }

    /// "Where am I?" on request.
    public func whereAmI(t: Double) -> [TimedGuidanceEvent] { navigator?.requestWhereAmI(t: t) ?? [] }
    /// "Repeat" on request.
    public func repeatLast(t: Double) -> [TimedGuidanceEvent] { navigator?.requestRepeat(t: t) ?? [] }
    /// The current route, for drawing.
    public var currentRoute: Route? { navigator?.currentRoute }
    /// True once the navigator announced arrival.
    public var hasArrived: Bool { navigator?.hasArrived ?? false }
    /// A copy of up to `maxCount` particles, for the trainer's picture.
    public func particleSnapshot(maxCount: Int) -> [ParticleSample] { localizer.particleSnapshot(maxCount: maxCount) }
}

/// A pipeline set-up error.
public enum PipelineError: Error, CustomStringConvertible, Sendable {
    /// The options do not fit the map (unknown floor, start, destination) or a model is missing.
    case invalidConfiguration(String)
    /// A frame could not be processed (reported as a warning, never thrown from `process`).
    case frame(String)

    /// Message for people.
    public var description: String {
        switch self {
        case .invalidConfiguration(let m): return m
        case .frame(let m): return m
        }
    }
}
