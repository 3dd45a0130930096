import Foundation
import Maps
import SessionFormat
import WayfinderCore

/// The full score of one walk.
public struct WalkScore: Codable, Sendable {
    /// Name of the walk (bundle folder or scenario name).
    public var name: String
    /// Localization figures.
    public var localization: LocalizationScore
    /// Navigation figures.
    public var navigation: NavigationScore
    /// Frames in the walk.
    public var frames: Int
    /// Duration, seconds.
    public var durationSeconds: Double
    /// Guidance while not localized (nil in scores made before it existed).
    public var unsureGuidance: UnsureGuidanceScore?
}

/// Figures over many walks, the ones the regression gate compares.
public struct AggregateScore: Codable, Sendable, Equatable {
    /// Walks scored.
    public var walks: Int
    /// Share of walks converged within 20 m of walking, 0...1.
    public var convergedWithin20mShare: Double
    /// Median over walks of the median position error after convergence, meters.
    public var medianErrorMeters: Double?
    /// Median over walks of the 95th-percentile error, meters.
    public var p95ErrorMeters: Double?
    /// Total confidently-wrong episodes (localized and > 3 m off).
    public var wrongConvergenceEpisodes: Int
    /// Largest distance walked while confidently wrong, meters.
    public var maxWrongConvergenceDistanceMeters: Double
    /// Expected turns that got no cue.
    public var missingInstructions: Int
    /// Cues in the wrong direction.
    public var wrongInstructions: Int
    /// Median distance of cues before their control point, meters.
    public var medianCueDistanceBeforeMeters: Double?
    /// Median over walks of the distance walked to the first convergence, meters (nil if none converged).
    public var medianConvergenceDistanceMeters: Double?
    /// Share of all frames after each walk's first convergence that were flagged localized, 0...1.
    public var localizedShareAfterConvergence: Double?
    /// Walks with a floor change, and the share of them localized on the new floor within 10 m of walking.
    public var floorChangeWalks: Int?
    public var floorChangeRelocalizedWithin10mShare: Double?
    /// Share of the unlocalized time with a directional exploratory instruction in force, 0...1.
    public var directedShareWhileUnsure: Double?
    /// Exploratory instructions that would lead into a wall, onto stairs or through a door from the true pose.
    public var unsafeUnsureInstructions: Int?
    /// "Now" cues of expected turns (`NavigationScore.nowCueEndBeforeMeters`), over all walks.
    public var nowCues: Int?
    /// Share of those cues that end (model duration) at least 0.5 m of true walking before their control
    /// point, 0...1 (nil when there is none). Issue 17's target: >= 0.95 on the convergence study.
    public var nowCuesEndingInTimeShare: Double?

    /// Aggregates walk scores.
    public init(_ scores: [WalkScore]) {
        walks = scores.count
        let converged = scores.filter { ($0.localization.distanceToConvergenceMeters ?? .infinity) <= 20 }
        convergedWithin20mShare = scores.isEmpty ? 0 : Double(converged.count) / Double(scores.count)
        medianErrorMeters = percentile(scores.compactMap { $0.localization.medianErrorMeters }, 50)
        p95ErrorMeters = percentile(scores.compactMap { $0.localization.p95ErrorMeters }, 50)
        wrongConvergenceEpisodes = scores.map(\.localization.wrongConvergenceEpisodes).reduce(0, +)
        maxWrongConvergenceDistanceMeters = scores.map(\.localization.maxWrongConvergenceDistanceMeters).max() ?? 0
        missingInstructions = scores.map(\.navigation.missingInstructions).reduce(0, +)
        wrongInstructions = scores.map(\.navigation.wrongInstructions).reduce(0, +)
        medianCueDistanceBeforeMeters = percentile(scores.flatMap(\.navigation.cueDistancesBeforeMeters), 50)
        medianConvergenceDistanceMeters = percentile(scores.compactMap { $0.localization.distanceToConvergenceMeters }, 50)
        // Pooled over frames: a walk's share weighted by its frames after convergence.
        var after = 0.0, afterLocalized = 0.0
        for s in scores {
            guard let share = s.localization.localizedShareAfterConvergence,
                  let n = s.localization.framesAfterConvergence else { continue }
            let frames = Double(n)
            after += frames
            afterLocalized += frames * share
        }
        localizedShareAfterConvergence = after > 0 ? afterLocalized / after : nil
        let changed = scores.filter { $0.localization.floorChangeRelocalizationMeters != nil || $0.localization.floorChangeNeverRelocalized }
        if !changed.isEmpty {
            floorChangeWalks = changed.count
            floorChangeRelocalizedWithin10mShare = Double(changed.filter { ($0.localization.floorChangeRelocalizationMeters ?? .infinity) <= 10 }.count)
                / Double(changed.count)
        }
        let ends = scores.flatMap { $0.navigation.nowCueEndBeforeMeters ?? [] }
        nowCues = ends.count
        nowCuesEndingInTimeShare = ends.isEmpty ? nil
            : Double(ends.filter { $0 >= NavigationScore.nowCueEndMarginMeters - 1e-9 }.count) / Double(ends.count)
        let unsure = scores.compactMap(\.unsureGuidance)
        let unsureSeconds = unsure.map(\.unsureSeconds).reduce(0, +)
        if !unsure.isEmpty {
            directedShareWhileUnsure = unsureSeconds > 0 ? unsure.map(\.directedSeconds).reduce(0, +) / unsureSeconds : nil
            unsafeUnsureInstructions = unsure.map(\.unsafeInstructions).reduce(0, +)
        }
    }
}

/// Replays and scores walks.
public enum WalkEvaluator {
    /// Replays `bundle` on `building` and scores it against its truth.jsonl. Throws when the bundle has
    /// no truth or the replay cannot start.
    public static func evaluate(name: String, bundle: SessionBundle, building: Building,
                                options: PipelineOptions = PipelineOptions()) throws -> (WalkScore, ReplayResult) {
        guard !bundle.truth.isEmpty else { throw EvaluationError.noTruth(name) }
        try checkTruthFloors(bundle.truth, building: building)
        let pipelineOptions = Replay.options(for: bundle, overriding: options)
        var replayOptions = Replay.Options(pipeline: pipelineOptions)
        replayOptions.snapshotParticleCount = 1200
        let result = try Replay.run(bundle: bundle, building: building, options: replayOptions)
        return (score(name: name, result: result, truth: bundle.truth, building: building,
                      destination: pipelineOptions.destinationId), result)
    }

    /// Throws `EvaluationError.truthFloorNotInMap` for the first truth record whose `floorId` is not a floor
    /// of `building`: scoring it would compare positions in unrelated frames (a silently wrong answer).
    public static func checkTruthFloors(_ truth: [TruthRecord], building: Building) throws {
        let floors = Set(building.floors.map(\.id))
        if let i = truth.firstIndex(where: { !floors.contains($0.floorId) }) {
            throw EvaluationError.truthFloorNotInMap(recordNumber: i + 1, t: truth[i].t, floorId: truth[i].floorId,
                                                     mapId: building.id, mapFloors: building.floors.map(\.id))
        }
    }

    /// Scores a finished replay.
    public static func score(name: String, result: ReplayResult, truth: [TruthRecord], building: Building,
                             destination: String?) -> WalkScore {
        let track = TruthTrack(truth)
        let localization = LocalizationScore(trace: result.trace, truth: track)
        let convergenceT = result.trace.first(where: \.localized)?.t
        let navigation = NavigationScore(announcements: result.announcements, truth: track, building: building,
                                         destination: destination, convergenceT: convergenceT)
        let duration = (result.trace.last?.t ?? 0) - (result.trace.first?.t ?? 0)
        return WalkScore(name: name, localization: localization, navigation: navigation, frames: result.trace.count,
                         durationSeconds: duration,
                         unsureGuidance: UnsureGuidanceScore(trace: result.trace, truth: track, building: building))
    }
}

/// Evaluation failures.
public enum EvaluationError: Error, CustomStringConvertible, Sendable {
    /// The bundle has no truth.jsonl to score against.
    case noTruth(String)
    /// The baseline file is unreadable.
    case badBaseline(String)
    /// truth.jsonl record number `recordNumber` (1-based, file order) names a floor the map does not have.
    case truthFloorNotInMap(recordNumber: Int, t: Double, floorId: String, mapId: String, mapFloors: [String])

    /// Message for people.
    public var description: String {
        switch self {
        case .noTruth(let name): return "\(name): no truth.jsonl, nothing to score against"
        case .badBaseline(let m): return m
        case .truthFloorNotInMap(let n, let t, let floorId, let mapId, let floors):
            return "truth.jsonl: record \(n) (t = \(String(format: "%.3f", t)) s): field floorId '\(floorId)' is not a floor of map '\(mapId)' (its floors: \(floors.joined(separator: ", "))); is the bundle from another building or --map the wrong file?"
        }
    }
}
