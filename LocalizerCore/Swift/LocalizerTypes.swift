import Maps

// Public value types of the particle-filter localizer (module Localizer). Frames and units: map frame x east,
// y north, meters, angles radians counter-clockwise from +x (Maps/Sources/MapModel.swift); VIO plane
// (east, north) = (x_w, -z_w) of the ARKit world (App/SessionFormat/CameraPose.swift). The algorithm is
// described in docs/localizer.md; the C core is LocalizerCore/include/wf_localizer.h.

/// One sign detection in one camera frame.
public struct SignSighting: Sendable {
    /// Sign class, the same string as `Sign.kind` in the map (e.g. "exit"). Kinds the map lacks are ignored.
    public var kind: String
    /// Horizontal distance from the camera to the sign, meters (> 0).
    public var rangeMeters: Double
    /// Horizontal angle from camera forward to the sign, radians, positive to the LEFT (counter-clockwise).
    public var bearingRad: Double
    /// Detector confidence in [0, 1]; a low score makes the sighting count more like clutter.
    public var score: Double
    /// The legend read on the sign when it identifies one (a placard's room number, as text recognition read
    /// it); nil when not read or not identifying. A read legend is matched only to the map's sign of this kind
    /// with this `Sign.text`; an unread placard only to placards without a surveyed text (else it is ignored).
    public var text: String?
    /// The object this sighting sees, as tracked on the VIO plane from frame to frame
    /// (App/Core/SightingCorroboration); nil when not tracked. One object's sightings are not independent evidence:
    /// the localizer bounds what they can say against a pose with no sign there (wf_sign_observation.track_id).
    public var track: SightingTrack?
    /// Creates a sighting.
    public init(kind: String, rangeMeters: Double, bearingRad: Double, score: Double, text: String? = nil,
                track: SightingTrack? = nil) {
        self.kind = kind; self.rangeMeters = rangeMeters; self.bearingRad = bearingRad; self.score = score
        self.text = text
        self.track = track
    }

    /// The key the localizer matches this sighting by (`SignIdentity`).
    var identityKey: String { SignIdentity.key(kind: kind, text: text) }
}

/// The tracked object a sighting sees (wf_sign_observation's track fields).
public struct SightingTrack: Sendable, Equatable {
    /// The object's id (> 0), the same for every sighting of it.
    public var id: UInt32
    /// Where the object's earlier sightings put it, seen from this sighting's camera: horizontal range, meters, and
    /// bearing, radians positive to the left; nil on its first sighting.
    public var earlierRangeMeters: Double?
    /// See `earlierRangeMeters`.
    public var earlierBearingRad: Double?
    /// Creates a track reference.
    public init(id: UInt32, earlierRangeMeters: Double? = nil, earlierBearingRad: Double? = nil) {
        self.id = id; self.earlierRangeMeters = earlierRangeMeters; self.earlierBearingRad = earlierBearingRad
    }
}

/// How sightings are matched to map signs: by kind, and by the legend where it identifies the sign. Each
/// distinct key is one kind id of the C core, so a read room number "402" is a kind of its own with one sign,
/// and the core needs no notion of text.
enum SignIdentity {
    /// `kind` alone, or `kind#text` for an identifying legend.
    static func key(kind: String, text: String?) -> String {
        guard let text else { return kind }
        return kind + "#" + text
    }
}

extension Sign {
    /// The key sightings of this sign are matched by (`SignIdentity`).
    var identityKey: String { SignIdentity.key(kind: kind, text: text) }
}

/// ARKit tracking state of a frame (`ARCamera.TrackingState`).
public enum VIOTracking: Sendable {
    /// Normal tracking.
    case normal
    /// Limited tracking: poses are used with heavier motion noise.
    case limited
    /// No tracking: the pose is ignored; when tracking returns the jump is skipped and uncertainty grows.
    case notAvailable
}

/// One VIO (ARKit) pose, reduced to the floor plane.
public struct VIOSample: Sendable {
    /// Timestamp, seconds (monotonic).
    public var t: Double
    /// Camera position on the VIO plane, meters: east = x_w.
    public var east: Double
    /// Camera position on the VIO plane, meters: north = -z_w.
    public var north: Double
    /// Camera forward yaw on the VIO plane, radians CCW from VIO east (`CameraPose.yawInVIOPlaneRad`).
    public var yawRad: Double
    /// Tracking state of this frame.
    public var tracking: VIOTracking
    /// Creates a sample.
    public init(t: Double, east: Double, north: Double, yawRad: Double, tracking: VIOTracking) {
        self.t = t; self.east = east; self.north = north; self.yawRad = yawRad; self.tracking = tracking
    }
}

/// What is known about the traveler's pose when the filter (re)starts.
public enum LocalizerPrior: Sendable {
    /// Only the floor: particles spread over its walkable space (flood fill from its graph nodes), any heading.
    case floorOnly(floorId: String)
    /// A start point (meters, map frame) within `radiusMeters`, any heading.
    case startPoint(floorId: String, position: Point2, radiusMeters: Double)
}

/// Filter options. Defaults come from the C core (`wf_localizer_options_init`); docs/localizer.md gives the
/// reasoning and textbook source of each.
public struct LocalizerOptions: Sendable {
    /// Particles after a reset (the fixed count when `adaptiveParticleCount` is false). Default 20,000.
    public var particleCount: Int
    /// Bounds for KLD-sampling (Fox 2003). Defaults 2,000 and 100,000.
    public var minParticles: Int
    public var maxParticles: Int
    /// Horizontal field of view of the camera, radians. Default 48 degrees (portrait iPhone).
    public var horizontalFieldOfViewRad: Double
    /// Signs farther than this are never expected to be seen, meters. Default 12.
    public var maxSignRangeMeters: Double
    /// Plainly visible but undetected signs lower a particle's weight. Default true.
    public var negativeInformation: Bool
    /// Augmented-MCL random-particle injection (Probabilistic Robotics Table 8.3). Default true.
    public var recovery: Bool
    /// KLD-sampling adapts the particle count at each resampling. Default true.
    public var adaptiveParticleCount: Bool
    /// Range noise: std = rangeSigmaBaseMeters + rangeSigmaPerMeter * range. Defaults 0.1 m and 0.12.
    public var rangeSigmaBaseMeters: Double
    public var rangeSigmaPerMeter: Double
    /// Bearing noise std, radians. Default 3 degrees.
    public var bearingSigmaRad: Double
    /// Probability that a sighting is a false positive. Default 0.1.
    public var clutterProbability: Double
    /// Walkable cells keep this distance from walls, meters. Default 0.2.
    public var wallClearanceMeters: Double
    /// Cell of the visibility / walkable grids, meters. Default 0.25.
    public var gridCellMeters: Double
    /// A sign is expected to be seen only from at most this angle off its face normal, radians. Default 80
    /// degrees (more obliquely the face is a sliver no detector finds); pi/2 = from anywhere in front.
    public var maxViewAngleFromNormalRad: Double
    /// Share of the particles a start-point reset spreads over the whole floor, because the traveler may have
    /// named the wrong start. Default 0.05; 0 trusts the start completely.
    public var startPointDoubtShare: Double

    /// The defaults of the C core.
    public init() {
        self = LocalizerBridge.defaultOptions()
    }

    init(particleCount: Int, minParticles: Int, maxParticles: Int, horizontalFieldOfViewRad: Double,
         maxSignRangeMeters: Double, negativeInformation: Bool, recovery: Bool, adaptiveParticleCount: Bool,
         rangeSigmaBaseMeters: Double, rangeSigmaPerMeter: Double, bearingSigmaRad: Double,
         clutterProbability: Double, wallClearanceMeters: Double, gridCellMeters: Double,
         maxViewAngleFromNormalRad: Double, startPointDoubtShare: Double) {
        self.particleCount = particleCount; self.minParticles = minParticles; self.maxParticles = maxParticles
        self.horizontalFieldOfViewRad = horizontalFieldOfViewRad; self.maxSignRangeMeters = maxSignRangeMeters
        self.negativeInformation = negativeInformation; self.recovery = recovery
        self.adaptiveParticleCount = adaptiveParticleCount; self.rangeSigmaBaseMeters = rangeSigmaBaseMeters
        self.rangeSigmaPerMeter = rangeSigmaPerMeter; self.bearingSigmaRad = bearingSigmaRad
        self.clutterProbability = clutterProbability; self.wallClearanceMeters = wallClearanceMeters
        self.gridCellMeters = gridCellMeters; self.maxViewAngleFromNormalRad = maxViewAngleFromNormalRad
        self.startPointDoubtShare = startPointDoubtShare
    }
}

/// The filter's current answer.
public struct LocalizationEstimate: Sendable {
    /// Time of the last input, seconds.
    public var t: Double
    /// Weighted mean position of the dominant hypothesis, meters, map frame.
    public var positionInMap: Point2
    /// Floor of the dominant hypothesis ("" before the first reset).
    public var floorId: String
    /// Camera forward heading in the map frame, radians CCW from +x.
    public var headingRad: Double
    /// Position covariance of the dominant hypothesis, square meters.
    public var covarianceXX: Double
    public var covarianceXY: Double
    public var covarianceYY: Double
    /// Circular standard deviation of the heading, radians.
    public var headingStdRad: Double
    /// 0...1: weight of the dominant hypothesis, reduced by its spread.
    public var confidence: Double
    /// True when the navigator may guide: one hypothesis, heavy and tight for about a second, every rival
    /// refuted by the evidence (hysteresis). Stays false while mirror-image hypotheses survive.
    public var isLocalized: Bool
    /// Hypotheses (clusters) holding more than 5 % of the weight.
    public var hypothesisCount: Int
    /// Current number of particles.
    public var particleCount: Int
    /// The pose hypotheses behind the estimate (clusters holding >= 1 % of the weight, at most 16): first the
    /// dominant one the estimate describes (the heaviest, or while localized the locked one against a refuted
    /// heavier rival, LocalizerCore pf/locked_hypothesis; on frames between two clusterings its weight is
    /// refreshed and the others keep the last clustering's, so it may read a little lighter than the second),
    /// then the others heaviest first. Empty for fakes.
    public var hypotheses: [PoseHypothesis] = []
    /// Sightings of the last hold period (about a second) that the dominant hypothesis explains only as false
    /// positives: the sum of -log(false-positive probability) of their sightings, nats (0 = it explains them all).
    public var unexplainedSightingNats: Double = 0
    /// True from the estimate where `unexplainedSightingNats` reaches the localizer's refutation margin until a
    /// later sighting that the dominant hypothesis explains: a sign was seen that it does not place there, so the
    /// traveler may stand where no hypothesis is (augmented MCL's reason for injecting particles, PR section
    /// 8.3.5, here per hypothesis). While it is true and the traveler is not localized, no directional
    /// instruction is planned from the hypotheses.
    public var sightingsUnexplained: Bool = false

    /// Creates an estimate (for fakes and replays; the localizer makes its own).
    public init(t: Double, positionInMap: Point2, floorId: String, headingRad: Double, covarianceXX: Double,
                covarianceXY: Double, covarianceYY: Double, headingStdRad: Double, confidence: Double,
                isLocalized: Bool, hypothesisCount: Int, particleCount: Int) {
        self.t = t; self.positionInMap = positionInMap; self.floorId = floorId; self.headingRad = headingRad
        self.covarianceXX = covarianceXX; self.covarianceXY = covarianceXY; self.covarianceYY = covarianceYY
        self.headingStdRad = headingStdRad; self.confidence = confidence; self.isLocalized = isLocalized
        self.hypothesisCount = hypothesisCount; self.particleCount = particleCount
    }
}

/// One pose hypothesis of the localizer: a cluster of the particle cloud.
public struct PoseHypothesis: Sendable, Equatable {
    /// Normalised weight, 0...1.
    public var weight: Double
    /// Floor id.
    public var floorId: String
    /// Mean position, meters, map frame.
    public var positionInMap: Point2
    /// Camera heading, radians CCW from map +x.
    public var headingRad: Double
    /// Position spread (largest axis), meters.
    public var positionStdMeters: Double
    /// Recent evidence relative to the dominant hypothesis, nats (0 for the dominant; negative = worse).
    public var evidenceNats: Double
    /// Heading spread (circular std of the camera heading), radians.
    public var headingStdRad: Double

    /// Creates a hypothesis.
    public init(weight: Double, floorId: String, positionInMap: Point2, headingRad: Double, positionStdMeters: Double,
                evidenceNats: Double, headingStdRad: Double = 0) {
        self.weight = weight; self.floorId = floorId; self.positionInMap = positionInMap; self.headingRad = headingRad
        self.positionStdMeters = positionStdMeters; self.evidenceNats = evidenceNats; self.headingStdRad = headingStdRad
    }
}

/// A rotation of a floor plan onto itself (wf_localizer_floor_symmetry).
public struct FloorSymmetry: Sendable, Equatable {
    /// Rotation angle, radians: pi/2, pi or 3 pi/2.
    public var angleRad: Double
    /// Fixed point, meters, map frame.
    public var center: Point2
    /// Share of the floor's wall length the rotation lands on a wall, 0...1.
    public var matchedFraction: Double

    /// Creates a symmetry.
    public init(angleRad: Double, center: Point2, matchedFraction: Double) {
        self.angleRad = angleRad; self.center = center; self.matchedFraction = matchedFraction
    }
    /// "a half turn", "a quarter turn", "a three-quarter turn".
    public var turnDescription: String {
        switch Int((angleRad / (Double.pi / 2)).rounded()) {
        case 1: return "a quarter turn"
        case 2: return "a half turn"
        default: return "a three-quarter turn"
        }
    }
}

/// One particle, for drawing.
public struct ParticleSample: Sendable {
    /// Position, meters, map frame.
    public var position: Point2
    /// Camera heading in the map frame, radians.
    public var headingRad: Double
    /// Floor the particle is on.
    public var floorId: String
    /// Normalised weight (over all particles).
    public var weight: Double
    /// VIO scale factor (map meters per VIO meter).
    public var scale: Double

    /// Creates a particle sample with VIO scale 1.
    public init(position: Point2, headingRad: Double, floorId: String, weight: Double) {
        self.init(position: position, headingRad: headingRad, floorId: floorId, weight: weight, scale: 1)
    }

    /// Creates a particle sample with its VIO scale factor.
    public init(position: Point2, headingRad: Double, floorId: String, weight: Double, scale: Double) {
        self.position = position; self.headingRad = headingRad; self.floorId = floorId; self.weight = weight
        self.scale = scale
    }
}

/// Every failure of the localizer, one case per C status (LocalizerCore/include/wf_localizer.h), each with
/// the core's message naming the problem.
public enum LocalizerError: Error, Equatable, Sendable, CustomStringConvertible {
    /// A bad argument or option value (the message names it).
    case invalidArgument(String)
    /// Memory could not be allocated.
    case outOfMemory(String)
    /// The C core does not know the struct version (a build mismatch).
    case unsupportedVersion(String)
    /// The building cannot be used (non-finite coordinates, no floor...).
    case invalidMap(String)
    /// The floor or start point has no walkable space.
    case noWalkableSpace(String)
    /// The filter has not been reset with a prior yet.
    case notInitialized(String)
    /// A NaN or infinite input was ignored.
    case nonFiniteInput(String)
    /// A floor id that the building does not have.
    case unknownFloor(String)
    /// An internal failure of the core (a bug).
    case internalFailure(String)

    /// Human-readable description.
    public var description: String {
        switch self {
        case .invalidArgument(let m): return "invalid argument: \(m)"
        case .outOfMemory(let m): return "out of memory: \(m)"
        case .unsupportedVersion(let m): return "unsupported version: \(m)"
        case .invalidMap(let m): return "invalid map: \(m)"
        case .noWalkableSpace(let m): return "no walkable space: \(m)"
        case .notInitialized(let m): return "not initialized: \(m)"
        case .nonFiniteInput(let m): return "non-finite input: \(m)"
        case .unknownFloor(let id): return "unknown floor '\(id)'"
        case .internalFailure(let m): return "internal failure: \(m)"
        }
    }
}
