import Foundation
import SignDetection
import Localizer
import Maps
import Navigation

/// Where sign sightings come from during a run.
public enum SightingSource: String, Sendable, CaseIterable {
    /// Use the observations recorded in the bundle (`observations.jsonl`), e.g. simulated walks.
    case recorded
    /// Run the AdaBoost cascade on the frames' images.
    case cascade
    /// Run the U-Net segmenter (coarse then zoomed) on the frames' images.
    case unet
    /// Prefer images when the bundle has them (U-Net), else recorded observations.
    case automatic
}

/// Everything the pipeline needs to know besides the map. A value; copied into the pipeline.
public struct PipelineOptions: Sendable {
    /// Floor the traveler starts on ("I only know the floor"); nil = the first floor of the building.
    public var floorId: String?
    /// Start point of interest if the traveler chose one (yaw still unknown).
    public var startPointOfInterestId: String?
    /// Radius of the start prior around the chosen start, meters.
    public var startRadiusMeters: Double = 2.0
    /// Destination point-of-interest id (or name); nil = localize only, no guidance.
    public var destinationId: String?
    /// Source of sign sightings.
    public var sightingSource: SightingSource = .automatic
    /// Folder holding the detector models (SignDetector/models); nil = found relative to the package.
    public var modelsDirectory: String?
    /// Sign kinds and their face sizes for the range estimator (paper: h0); nil = the map's
    /// (`Building.signCatalogue`: its "signKinds", or sizes from its signs and the default Exit sign).
    public var signCatalogue: SignCatalogue?
    /// Reads the legend of a sign whose kind reads text (a room-number placard) when the detector did not: on the
    /// iPhone the C++ library is built without tesseract and the app reads the text with Vision
    /// (App/iOS/Sensors/VisionLegendReader.swift). Given the frame and the face's corners in raw pixels (TL, TR,
    /// BR, BL); returns letters, digits and '-' only, or nil. nil here = only the detector's own reading.
    public var legendReader: (@Sendable (ImageBuffer, [PixelPoint]) -> String?)?
    /// How the detector frames choose the wall kinds they look for (`WallKindScheduler`): the kinds the hypotheses
    /// expect in view first, within the detector's budget of two kinds on every second frame (the phone's), that
    /// budget in plain rotation, or every wall kind on every frame.
    public var wallKindSchedule: WallKindScheduler.Mode = .expected
    /// Also apply `wallKindSchedule` to recorded observations (a study of the phone's budget on simulated walks,
    /// whose detector model sights every kind on every frame): a recorded sighting of a wall kind the frame does not
    /// look for is left out and the kind counts as unsearched. Off: recorded observations are the recording
    /// detector's, used whole (its own `FrameRecord.unsearchedSignKinds` respected).
    public var scheduleRecordedSightings = false
    /// Minimum time between two detector runs, seconds (the phone runs the detector at about 10 Hz and
    /// drops frames while it is busy). Also the cadence of "nothing seen" updates for negative information.
    public var detectionIntervalSeconds: Double = 0.1
    /// Particle filter settings. The pipeline starts "I only know the floor" with 100,000 particles (the
    /// reference app's count): fewer leave so few particles per position and heading that one of two
    /// mirror-image hypotheses can die out by chance, and the survivor then looks certain.
    public var localizer: LocalizerOptions = {
        var o = LocalizerOptions()
        o.particleCount = 100_000
        o.maxParticles = max(o.maxParticles, 100_000)
        return o
    }()
    /// Sightings reported farther than this are not given to the localizer, meters. The localizer predicts
    /// signs visible up to this range plus 3 range sigmas (`signHorizonMeters`; 16.6 m for 12 m): a detector
    /// that sees far (the U-Net finds Exit signs 20 m away) measures a sign 14 m away inside the accepted
    /// range, and with the prediction cut at the same 12 m only poses that put some other sign nearer could
    /// explain it. On the end-to-end study that bias locked 4 of 6 walks on a mirror pose (docs/benchmarks.md,
    /// "End to end with the detectors").
    public var maximumSightingRangeMeters: Double = 12
    /// Sightings tracked on the VIO plane (`SightingCorroboration`): while not localized, a sighting no earlier
    /// detector frame saw at about the same place counts more like clutter (`uncorroboratedScoreFactor = 1` turns
    /// it off, CLI `--no-corroboration`); while localized, an object seen again that the locked pose does not
    /// explain counts once per `unexplainedObjectRecountMeters` walked (0 turns it off, CLI
    /// `--recount-unexplained 0`).
    public var sightingCorroboration = SightingCorroboration.Parameters()
    /// Farthest range at which the localizer predicts a sign visible: `maximumSightingRangeMeters` plus 3
    /// range sigmas of the localizer's range noise there, meters.
    public var signHorizonMeters: Double {
        let r = maximumSightingRangeMeters
        return r + 3 * (localizer.rangeSigmaBaseMeters + localizer.rangeSigmaPerMeter * r)
    }
    /// Spread of the compass prior on the camera heading, degrees (indoor magnetic disturbance: the
    /// simulator's field has a 15-degree standard deviation, clipped at 30). Used once, at the first frame with
    /// a compass reading, when the map knows its north (`Building.compassHeadingOfMapNorthDeg`); a fifth of the
    /// prior stays uniform over all headings (LocalizerCore kCompassUniformShare). nil = no compass prior.
    public var compassPriorSigmaDeg: Double? = 30
    /// Compass as evidence (and as the start prior): each finite reading is weighed by the localizer, at most
    /// once per few meters walked (LocalizerCore sensors/compass_model, calibrated in docs/compass.md). Needs
    /// the map's north. false = ignore the compass entirely (CLI `--no-compass`).
    public var useCompass: Bool = true
    /// Watches whether the map's north agrees with the compass while localized (`CompassNorthCheck`): when
    /// the compass reads a consistent 60 degrees or more off the localized heading over 15 m walked, the
    /// pipeline warns and stops the compass evidence for the session. nil = off.
    public var compassNorthCheck: CompassNorthCheck.Parameters? = CompassNorthCheck.Parameters()
    /// Internal localizer model parameters by name (`ParticleLocalizer.setParameter`), e.g.
    /// `["compass.kappa": 8]`; `useCompass == false` overrides its "compass.enabled".
    public var localizerParameters: [String: Double] = [:]
    /// Score ARKit's vertical planes (planes.jsonl in replay, ARPlaneAnchor events on the phone) against the
    /// map's walls. `--no-planes` on the command line turns it off.
    public var usePlanes = true
    /// Minimum time between two plane updates of the localizer, seconds (each anchor is applied at most once
    /// a second by the filter itself).
    public var planeUpdateIntervalSeconds: Double = 0.5
    /// Guidance settings.
    public var navigator: NavigatorOptions = NavigatorOptions()
    /// Random seed of the particle filter (replays are deterministic for a seed).
    public var seed: UInt64 = 1
    /// Creates default options.
    public init() {}
}
