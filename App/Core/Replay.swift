import Foundation
import Maps
import Localizer
import Navigation
import SessionFormat

/// One line of a replay trace (`wayfinder replay --trace`): the state after one frame.
public struct TraceRecord: Codable, Sendable, Equatable {
    /// Frame time, seconds.
    public var t: Double
    /// Estimated map x, meters.
    public var x: Double
    /// Estimated map y, meters.
    public var y: Double
    /// Estimated floor id.
    public var floorId: String
    /// Estimated heading of the camera, radians CCW from map +x.
    public var headingRad: Double
    /// Localizer confidence 0...1.
    public var confidence: Double
    /// The localizer's `localized` flag (guidance only runs while true).
    public var localized: Bool
    /// Number of surviving hypotheses (clusters).
    public var hypotheses: Int
    /// Sign sightings used on this frame.
    public var sightings: Int
    /// Texts spoken on this frame.
    public var announcements: [String]
    /// Haptic patterns played on this frame.
    public var haptics: [String]
    /// While not localized: the navigator's exploratory advice in force (its action, e.g. "ahead", or
    /// "unsure"); nil when localized or without a navigator.
    public var advice: String? = nil
    /// The exploratory action spoken on this frame ("ahead", "turnAround", "left", "right"), if one was.
    public var spokenAdvice: String? = nil
    /// ARKit tracking when not normal: "limited" or "limited (REASON)" (e.g. "limited (excessiveMotion)"),
    /// or "lost" (not available, or a pose that is not finite); nil while tracking is normal.
    public var tracking: String? = nil
    /// What the phone's `TrackingPromptPolicy` says on this frame ("Slow down", ...), if anything.
    public var trackingPrompt: String? = nil
    /// The frame's sightings as the localizer got them (kind, range, bearing, score, legend read), when any:
    /// what a detector saw, for checking it against truth; nil on frames without sightings.
    public var sightingList: [TraceSighting]? = nil
    /// The localizer's hypotheses (heaviest first) on frames where it is not localized or holds more than one:
    /// what a trainer or a developer reads to see which places the filter still weighs; nil otherwise.
    public var hypothesisList: [TraceHypothesis]? = nil
    /// True on frames where the localizer reports sightings its dominant hypothesis leaves unexplained, from the
    /// second's worth that reaches its margin until one is explained (`LocalizationEstimate.sightingsUnexplained`);
    /// nil otherwise.
    public var sightingsUnexplained: Bool? = nil

    /// Creates a trace record.
    public init(t: Double, x: Double, y: Double, floorId: String, headingRad: Double, confidence: Double, localized: Bool,
                hypotheses: Int, sightings: Int, announcements: [String], haptics: [String]) {
        self.t = t; self.x = x; self.y = y; self.floorId = floorId; self.headingRad = headingRad
        self.confidence = confidence; self.localized = localized; self.hypotheses = hypotheses
        self.sightings = sightings; self.announcements = announcements; self.haptics = haptics
    }
}

/// One sighting in a trace line (`TraceRecord.sightingList`).
public struct TraceSighting: Codable, Sendable, Equatable {
    /// Sign kind, e.g. "exit".
    public var kind: String
    /// Range from the camera, meters.
    public var rangeMeters: Double
    /// Bearing from camera forward, radians, positive to the left.
    public var bearingRad: Double
    /// Detector score 0...1.
    public var score: Double
    /// The legend read, for identifying signs.
    public var text: String?
}

/// One hypothesis in a trace line (`TraceRecord.hypothesisList`).
public struct TraceHypothesis: Codable, Sendable, Equatable {
    /// Normalised weight, 0...1.
    public var weight: Double
    /// Mean position, map frame, meters.
    public var x: Double
    /// Mean position, map frame, meters.
    public var y: Double
    /// Camera heading, radians CCW from map +x.
    public var headingRad: Double
    /// Recent evidence relative to the dominant hypothesis, nats (0 for the dominant; negative = worse).
    public var evidenceNats: Double
    /// Position spread (largest axis std), meters; absent in traces written before it was recorded.
    public var positionStdMeters: Double?
    /// Heading spread (circular std), radians; absent in traces written before the nineteenth stop.
    public var headingStdRad: Double?
}

/// A sign sighting drawn as a ray from the estimated camera position, for the trainer's picture.
public struct SightingRay: Sendable {
    /// Time, seconds.
    public var t: Double
    /// Sign kind of the sighting (the map's `Sign.kind`, e.g. "exit").
    public var kind: String = ""
    /// Range from the camera, meters.
    public var rangeMeters: Double = 0
    /// Bearing from camera forward, radians, positive to the left.
    public var bearingRad: Double = 0
    /// Floor of the estimate.
    public var floorId: String
    /// Estimated camera position, meters.
    public var from: Point2
    /// Where the sighting puts the sign (range along bearing from the estimated heading), meters.
    public var to: Point2
}

/// Particles at one moment, for drawing.
public struct ParticleSnapshot: Sendable {
    /// Time, seconds.
    public var t: Double
    /// Why this moment was chosen ("start", "first convergence", "middle", "end", or "t=...").
    public var label: String
    /// The particles (a subsample).
    public var particles: [ParticleSample]
}

/// A route the navigator adopted: the first one, or a re-route (the graph nodes visited changed).
public struct RouteChange: Sendable {
    /// Time of the frame on which the new route was in force, seconds.
    public var t: Double
    /// True for every route after the first.
    public var isReroute: Bool
    /// The route's polyline: (floor id, point in meters) per point.
    public var polyline: [(floorId: String, point: Point2)]
}

/// The localizer's hypotheses (clusters of the particle cloud) at one frame, for the trainer's view.
public struct HypothesisSnapshot: Sendable {
    /// Frame time, seconds.
    public var t: Double
    /// The hypotheses, heaviest first as the localizer reports them.
    public var hypotheses: [PoseHypothesis]
}

/// Everything a replay produced.
public struct ReplayResult: Sendable {
    /// One record per frame.
    public var trace: [TraceRecord]
    /// Spoken texts with their times, in order.
    public var announcements: [(t: Double, text: String)]
    /// Haptic patterns with their times.
    public var haptics: [(t: Double, pattern: String)]
    /// Sightings as rays from the estimate.
    public var sightingRays: [SightingRay]
    /// Particle clouds at chosen moments.
    public var particleSnapshots: [ParticleSnapshot]
    /// The last route, as a polyline of (floor, point).
    public var routePolyline: [(floorId: String, point: Point2)]
    /// Frames degraded gracefully, with the reason.
    public var warnings: [String]
    /// What the phone's tracking prompts (`TrackingPromptPolicy`, as `GuidanceSession` runs it) said, with
    /// times: spoken on the phone like announcements, kept apart here so guidance scoring is unchanged.
    public var trackingPrompts: [(t: Double, text: String)] = []
    /// Particle clouds every `Options.particleTimelineIntervalSeconds` (empty when that is nil).
    public var particleTimeline: [ParticleSnapshot] = []
    /// Hypotheses at the same moments as `particleTimeline`.
    public var hypothesisTimeline: [HypothesisSnapshot] = []
    /// Routes adopted during the walk (first route and re-routes), in time order.
    public var routeChanges: [RouteChange] = []
}

/// Replays a recorded-session bundle through exactly the phone's pipeline.
public enum Replay {
    /// Replay settings beyond the pipeline's.
    public struct Options: Sendable {
        /// Pipeline options (start, destination, detector, seeds). Defaults come from session.json.
        public var pipeline: PipelineOptions
        /// Extra moments (seconds) at which to keep particle clouds.
        public var snapshotTimes: [Double] = []
        /// Particles kept per snapshot.
        public var snapshotParticleCount: Int = 1500
        /// When set, keep a particle cloud and the hypotheses every this many seconds (the trainer's
        /// scrubbable view); nil keeps none.
        public var particleTimelineIntervalSeconds: Double? = nil
        /// Particles kept per timeline cloud.
        public var particleTimelineCount: Int = 150
        /// Creates options.
        public init(pipeline: PipelineOptions = PipelineOptions()) { self.pipeline = pipeline }
    }

    /// Fills unset pipeline options from the bundle's session.json (floor, start, destination). Sign sizes come
    /// from the map's sign-kind catalogue, not from the session's recorded `signHeightMeters`.
    public static func options(for bundle: SessionBundle, overriding base: PipelineOptions) -> PipelineOptions {
        var o = base
        if o.floorId == nil { o.floorId = bundle.info.floorId }
        if o.destinationId == nil { o.destinationId = bundle.info.destination }
        if o.startPointOfInterestId == nil { o.startPointOfInterestId = bundle.info.start }
        // The field of view the localizer expects sightings in follows how the phone is held.
        let poses = bundle.frames.lazy.compactMap { f in CameraPose(columnMajor: f.cameraToWorld).map { ($0, f.intrinsics) } }
        if let (pose, intrinsics) = poses.first {
            o.localizer.horizontalFieldOfViewRad = horizontalFieldOfViewRad(intrinsics: intrinsics, rollRad: pose.rollRad)
        }
        return o
    }

    /// Horizontal field of view of the roll-corrected image, radians: the sensor's short side when the
    /// phone is nearer portrait (|sin roll| > sin 45 degrees), its long side when nearer landscape.
    public static func horizontalFieldOfViewRad(intrinsics k: CameraIntrinsics, rollRad: Double) -> Double {
        let portrait = abs(sin(rollRad)) > 0.5.squareRoot()
        return portrait ? 2 * atan(Double(k.height) / 2 / k.fy) : 2 * atan(Double(k.width) / 2 / k.fx)
    }

    /// Most recorded observations given to the localizer for one frame: 64. A camera frame shows a few
    /// signs (the simulator's busiest office frames have under 10 sightings, false alarms included); a
    /// frame with more is damaged input, and each sighting costs a pass over 100,000 particles (200,000
    /// sightings at one instant took over a minute). The highest-scored ones are kept, with a warning.
    public static let maximumObservationsPerFrame = 64

    /// Runs the bundle frame by frame. `progress` is called with the fraction done (for stderr output).
    ///
    /// Checks made on the way, each reported in `ReplayResult.warnings` (first) rather than failing:
    /// session.json's `mapId` naming another building than `building`; observations of a sign kind the
    /// map lacks (ignored; the localizer could not use them); more than `maximumObservationsPerFrame`
    /// observations on one frame (the rest dropped); observations outside the frames' time span (dropped);
    /// frames naming images that are not there. Where sightings come from:
    /// - `.recorded`: observations.jsonl.
    /// - `.cascade`, `.unet`: the detector on the frames whose image is present; no sightings elsewhere.
    /// - `.automatic`: like `.unet` when at least one named image is present, and then a frame whose image
    ///   is missing falls back to its recorded observations; like `.recorded` when no image is present
    ///   (a bundle naming images it lacks still replays its observations).
    public static func run(bundle: SessionBundle, building: Building, options: Options,
                           progress: ((Double) -> Void)? = nil) throws -> ReplayResult {
        var warnings: [String] = []
        let sessionPath = bundle.url.appendingPathComponent(sessionFileName).path
        if let mapId = bundle.info.mapId, mapId != building.id {
            warnings.append("\(sessionPath): mapId '\(mapId)' names another building than the map given "
                + "('\(building.id)', \(building.name)); replaying on the given map anyway: positions and directions "
                + "are likely wrong")
        }

        // Plane-anchor events, like observations, go with the latest frame at or before their time.
        var planesByFrame = [[PlaneRecord]](repeating: [], count: bundle.frames.count)
        let frameTimes = bundle.frames.map(\.t)
        for p in bundle.planes {
            if let idx = frameIndex(atOrBefore: p.t, in: frameTimes) { planesByFrame[idx].append(p) }
        }

        // Images actually present (regular files inside the bundle), and the sighting source they allow.
        let source = options.pipeline.sightingSource
        var presentImagePaths = [String?](repeating: nil, count: bundle.frames.count)
        var namedImages = 0, firstMissing: Int?
        for (i, f) in bundle.frames.enumerated() where f.image != nil {
            namedImages += 1
            presentImagePaths[i] = bundle.presentImageURL(for: f)?.path
            if presentImagePaths[i] == nil, firstMissing == nil { firstMissing = i }
        }
        let presentImages = presentImagePaths.lazy.filter { $0 != nil }.count
        let imageMode: Bool
        switch source {
        case .recorded: imageMode = false
        case .cascade, .unet: imageMode = true
        case .automatic: imageMode = presentImages > 0
        }
        if let first = firstMissing, source != .recorded {
            let missing = namedImages - presentImages
            let what = "\(missing) of \(namedImages) frames name images missing from images/ (first at t=\(bundle.frames[first].t))"
            switch (source, imageMode) {
            case (.automatic, false):
                warnings.append("--detector auto: \(what), none is present: using the recorded observations")
            case (.automatic, true):
                warnings.append("--detector auto: \(what): those frames use their recorded observations")
            default:
                warnings.append("--detector \(source.rawValue): \(what): no sign sightings on those frames")
            }
        }
        let pipeline = try WayfinderPipeline(building: building, options: options.pipeline, imagesAvailable: imageMode)

        let observationsByFrame = assignObservations(bundle: bundle, building: building, warnings: &warnings)
        let imagesDirectory = bundle.url.appendingPathComponent(imagesDirectoryName)
        var result = ReplayResult(trace: [], announcements: [], haptics: [], sightingRays: [], particleSnapshots: [],
                                  routePolyline: [], warnings: warnings)
        let n = bundle.frames.count
        let middleIndex = n / 2
        var wasLocalized = false
        var pendingSnapshotTimes = options.snapshotTimes.sorted()
        var trackingPrompts = TrackingPromptPolicy()
        var lastTimelineT = -Double.infinity
        var lastRouteNodes: [String]?
        for (i, record) in bundle.frames.enumerated() {
            // In image mode a frame gets recorded observations only as the fallback for its missing image
            // (used by `.automatic`); the detector's frames use the image.
            let fallback = imageMode && record.image != nil && presentImagePaths[i] == nil
            var frame = PipelineFrame(record: record, imagesDirectory: imagesDirectory,
                                      observations: !imageMode || fallback ? observationsByFrame[i] : [])
            frame.imagePath = presentImagePaths[i]
            if !planesByFrame[i].isEmpty { pipeline.ingest(planes: planesByFrame[i]) }
            let update = pipeline.process(frame)
            result.warnings.append(contentsOf: update.warnings)
            let e = update.estimate
            var spoken: [String] = []
            var haptics: [String] = []
            for event in update.events {
                switch event.event {
                case .speak(let text, _, _):
                    spoken.append(text)
                    result.announcements.append((event.t, text))
                case .haptic(let pattern):
                    haptics.append("\(pattern)")
                    result.haptics.append((event.t, "\(pattern)"))
                }
            }
            for s in update.sightings {
                let angle = e.headingRad + s.bearingRad
                result.sightingRays.append(SightingRay(t: e.t, kind: s.kind, rangeMeters: s.rangeMeters, bearingRad: s.bearingRad,
                                                       floorId: e.floorId, from: e.positionInMap,
                                                       to: Point2(x: e.positionInMap.x + s.rangeMeters * cos(angle),
                                                                  y: e.positionInMap.y + s.rangeMeters * sin(angle))))
            }
            result.trace.append(TraceRecord(t: record.t, x: e.positionInMap.x, y: e.positionInMap.y, floorId: e.floorId,
                                            headingRad: e.headingRad, confidence: e.confidence, localized: e.isLocalized,
                                            hypotheses: e.hypothesisCount, sightings: update.sightings.count,
                                            announcements: spoken, haptics: haptics))
            if !update.sightings.isEmpty {
                result.trace[result.trace.count - 1].sightingList = update.sightings.map {
                    TraceSighting(kind: $0.kind, rangeMeters: $0.rangeMeters, bearingRad: $0.bearingRad, score: $0.score, text: $0.text)
                }
            }
            if !e.isLocalized || e.hypotheses.count > 1 {
                result.trace[result.trace.count - 1].hypothesisList = e.hypotheses.map {
                    TraceHypothesis(weight: $0.weight, x: $0.positionInMap.x, y: $0.positionInMap.y, headingRad: $0.headingRad,
                                    evidenceNats: $0.evidenceNats, positionStdMeters: $0.positionStdMeters,
                                    headingStdRad: $0.headingStdRad)
                }
            }
            if e.sightingsUnexplained { result.trace[result.trace.count - 1].sightingsUnexplained = true }
            if let advice = update.advice { result.trace[result.trace.count - 1].advice = advice.action?.rawValue ?? "unsure" }
            if let spokenAdvice = update.spokenAdvice?.action {
                result.trace[result.trace.count - 1].spokenAdvice = spokenAdvice.rawValue
            }
            // The phone's tracking prompts, exactly as GuidanceSession runs them (no luma: images are optional).
            let trackingState: TrackingState = frame.cameraPose == nil ? .notAvailable : frame.tracking
            switch trackingState {
            case .normal: break
            case .limited:
                result.trace[result.trace.count - 1].tracking = frame.trackingReason.map { "limited (\($0.rawValue))" } ?? "limited"
            case .notAvailable: result.trace[result.trace.count - 1].tracking = "lost"
            }
            if let prompt = trackingPrompts.update(t: record.t, state: trackingState, reason: frame.trackingReason) {
                result.trace[result.trace.count - 1].trackingPrompt = prompt
                result.trackingPrompts.append((record.t, prompt))
            }
            if let interval = options.particleTimelineIntervalSeconds, record.t - lastTimelineT >= interval - 1e-9 || i == n - 1 {
                lastTimelineT = record.t
                result.particleTimeline.append(ParticleSnapshot(t: record.t, label: "timeline",
                                                                particles: pipeline.particleSnapshot(maxCount: options.particleTimelineCount)))
                result.hypothesisTimeline.append(HypothesisSnapshot(t: record.t, hypotheses: e.hypotheses))
            }
            if let route = pipeline.currentRoute, route.nodeIds != lastRouteNodes {
                result.routeChanges.append(RouteChange(t: record.t, isReroute: lastRouteNodes != nil,
                                                       polyline: route.points.map { ($0.floorId, $0.position) }))
                lastRouteNodes = route.nodeIds
            }
            var label: String?
            if i == 0 { label = "start" } else if i == middleIndex { label = "middle" } else if i == n - 1 { label = "end" }
            if e.isLocalized && !wasLocalized { label = "first convergence" }
            if let next = pendingSnapshotTimes.first, record.t >= next {
                pendingSnapshotTimes.removeFirst()
                label = label ?? String(format: "t=%.1f s", next)
            }
            if let label {
                result.particleSnapshots.append(ParticleSnapshot(t: record.t, label: label,
                                                                 particles: pipeline.particleSnapshot(maxCount: options.snapshotParticleCount)))
            }
            wasLocalized = wasLocalized || e.isLocalized
            if i % 200 == 0 { progress?(Double(i) / Double(max(n, 1))) }
        }
        if let route = pipeline.currentRoute {
            result.routePolyline = route.points.map { ($0.floorId, $0.position) }
        }
        progress?(1)
        return result
    }

    /// Recorded observations per frame (each belongs to the latest frame at or before its time), after
    /// dropping, with one warning per cause: observations before the first frame or later than the last
    /// frame by more than the longest frame interval, kinds the map lacks, and the lowest-scored ones beyond
    /// `maximumObservationsPerFrame` on a frame.
    static func assignObservations(bundle: SessionBundle, building: Building,
                                   warnings: inout [String]) -> [[ObservationRecord]] {
        var byFrame = [[ObservationRecord]](repeating: [], count: bundle.frames.count)
        let mapKinds = Set(building.floors.flatMap { $0.signs.map(\.kind) })
        var unknownKinds: [String: (count: Int, first: Int)] = [:]
        var beforeFirstFrame: (count: Int, first: Int)?, afterLastFrame: (count: Int, first: Int)?
        let frameTimes = bundle.frames.map(\.t)
        // An observation later than the last frame by more than the longest frame interval has no frame.
        let longestGap = zip(frameTimes, frameTimes.dropFirst()).map { $1 - $0 }.max() ?? 0
        let lastUsable = (frameTimes.last ?? 0) + longestGap + 1e-6
        for (k, o) in bundle.observations.enumerated() {
            if o.t > lastUsable {
                afterLastFrame = ((afterLastFrame?.count ?? 0) + 1, afterLastFrame?.first ?? k)
                continue
            }
            guard mapKinds.contains(o.kind) else {
                let u = unknownKinds[o.kind]
                unknownKinds[o.kind] = ((u?.count ?? 0) + 1, u?.first ?? k)
                continue
            }
            let idx = frameIndex(atOrBefore: o.t, in: frameTimes) ?? -1
            if idx >= 0 {
                byFrame[idx].append(o)
            } else {
                beforeFirstFrame = ((beforeFirstFrame?.count ?? 0) + 1, beforeFirstFrame?.first ?? k)
            }
        }
        let known = mapKinds.isEmpty ? "the map has no signs" : "map sign kinds: \(mapKinds.sorted().joined(separator: ", "))"
        for (kind, u) in unknownKinds.sorted(by: { $0.value.first < $1.value.first }) {
            warnings.append("\(bundle.observationLocation(u.first)): sign kind '\(kind)' is not on the map '\(building.id)' "
                + "(\(known)); \(u.count) observation\(u.count == 1 ? "" : "s") of this kind ignored")
        }
        if let b = beforeFirstFrame {
            warnings.append("\(bundle.observationLocation(b.first)): \(b.count) observation\(b.count == 1 ? "" : "s") "
                + "before the first frame (t=\(frameTimes.first ?? 0)) ignored")
        }
        if let a = afterLastFrame {
            warnings.append("\(bundle.observationLocation(a.first)): \(a.count) observation\(a.count == 1 ? "" : "s") "
                + "after the last frame (t=\(frameTimes.last ?? 0)) ignored")
        }
        var capped = 0, dropped = 0, firstCapped: Int?
        var byFrameCounts: [Int: Int] = [:]
        for i in byFrame.indices where byFrame[i].count > maximumObservationsPerFrame {
            capped += 1
            byFrameCounts[i] = byFrame[i].count
            dropped += byFrame[i].count - maximumObservationsPerFrame
            if firstCapped == nil { firstCapped = i }
            // Keep the highest scores; ties keep file order.
            let order = byFrame[i].indices.sorted { a, b in
                byFrame[i][a].score != byFrame[i][b].score ? byFrame[i][a].score > byFrame[i][b].score : a < b
            }
            byFrame[i] = order.prefix(maximumObservationsPerFrame).sorted().map { byFrame[i][$0] }
        }
        if let f = firstCapped {
            warnings.append("\(bundle.observationsFile.path): \(capped) frame\(capped == 1 ? " has" : "s have") more than "
                + "\(maximumObservationsPerFrame) observations (first: the frame at t=\(frameTimes[f]), "
                + "\(byFrameCounts[f] ?? 0) observations); kept the \(maximumObservationsPerFrame) highest-scored per frame, "
                + "\(dropped) observations dropped")
        }
        return byFrame
    }

    /// Index of the latest frame at or before `t` (1 us tolerance) in the sorted `frameTimes`; nil before the first.
    static func frameIndex(atOrBefore t: Double, in frameTimes: [Double]) -> Int? {
        var lo = 0, hi = frameTimes.count - 1, idx = -1
        while lo <= hi {
            let mid = (lo + hi) / 2
            if frameTimes[mid] <= t + 1e-6 { idx = mid; lo = mid + 1 } else { hi = mid - 1 }
        }
        return idx >= 0 ? idx : nil
    }
}
