import Foundation
import SessionFormat
import WayfinderCore

/// Localization figures of one walk, scored against truth.
/// Errors are horizontal distances between the estimate and the interpolated truth at the same time;
/// a wrong floor counts as an infinite error (reported as `wrongFloorSeconds`, excluded from percentiles).
public struct LocalizationScore: Codable, Sendable, Equatable {
    /// Seconds from the first frame to the first frame flagged `localized`; nil if never.
    public var timeToConvergenceSeconds: Double?
    /// Meters walked (truth) before the first `localized` frame; nil if never.
    public var distanceToConvergenceMeters: Double?
    /// Median position error over all frames after first convergence, meters.
    public var medianErrorMeters: Double?
    /// 90th percentile of the same, meters.
    public var p90ErrorMeters: Double?
    /// 95th percentile of the same, meters.
    public var p95ErrorMeters: Double?
    /// Median heading error after convergence, degrees.
    public var medianHeadingErrorDeg: Double?
    /// Share of frames flagged `localized`, 0...1.
    public var fractionLocalized: Double
    /// Separate episodes of "localized but more than `wrongThresholdMeters` off" (confidently wrong).
    public var wrongConvergenceEpisodes: Int
    /// Total duration of those episodes, seconds.
    public var wrongConvergenceSeconds: Double
    /// Largest distance walked during one such episode before it ended, meters (0 when none).
    public var maxWrongConvergenceDistanceMeters: Double
    /// Seconds the estimate's floor differed from the true floor after convergence.
    public var wrongFloorSeconds: Double
    /// Meters walked in the whole walk.
    public var walkedMeters: Double
    /// Share of the frames after the first convergence that are flagged `localized` (the steady lock), 0...1;
    /// nil if never converged.
    public var localizedShareAfterConvergence: Double?
    /// Frames from the first convergence on (the denominator of `localizedShareAfterConvergence`).
    public var framesAfterConvergence: Int?
    /// After the last true floor change (truth floorId switches): meters walked from arriving on the new floor
    /// until the first frame localized on it (0 when the flag never dropped); nil without a floor change;
    /// `Double.infinity` is not used: `floorChangeNeverRelocalized` says so.
    public var floorChangeRelocalizationMeters: Double?
    /// True when the walk changed floor and was never localized on the new floor afterwards.
    public var floorChangeNeverRelocalized: Bool = false

    /// Error beyond which a localized estimate counts as confidently wrong, meters.
    public static let wrongThresholdMeters = 3.0
    /// After a true floor change, an estimate still on the previous floor is "riding", not wrong, this long, s
    /// (the barometer needs 1.5 s at rest to settle after the ride).
    public static let floorChangeGraceSeconds = 5.0

    /// Scores a trace against the truth track.
    public init(trace: [TraceRecord], truth: TruthTrack) {
        walkedMeters = truth.cumulativeDistanceMeters.last ?? 0
        fractionLocalized = trace.isEmpty ? 0 : Double(trace.filter(\.localized).count) / Double(trace.count)
        wrongConvergenceEpisodes = 0
        wrongConvergenceSeconds = 0
        maxWrongConvergenceDistanceMeters = 0
        wrongFloorSeconds = 0
        guard !truth.isEmpty, let first = trace.first else { return }
        scoreFloorChange(trace: trace, truth: truth)
        guard let convergedIndex = trace.firstIndex(where: \.localized) else { return }
        let later = trace[convergedIndex...]
        localizedShareAfterConvergence = Double(later.filter(\.localized).count) / Double(later.count)
        framesAfterConvergence = later.count
        let converged = trace[convergedIndex]
        timeToConvergenceSeconds = converged.t - first.t
        distanceToConvergenceMeters = truth.distanceWalked(at: converged.t) - truth.distanceWalked(at: first.t)

        var errors: [Double] = []
        var headingErrorsDeg: [Double] = []
        var episodeStart: (t: Double, walked: Double)?
        for (i, r) in trace.enumerated() where i >= convergedIndex {
            let dt = i + 1 < trace.count ? trace[i + 1].t - r.t : 0
            let s = truth.state(at: r.t)
            let sameFloor = s.floorId == r.floorId
            let error = sameFloor ? hypot(r.x - s.x, r.y - s.y) : Double.infinity
            if sameFloor {
                errors.append(error)
                headingErrorsDeg.append(angularDistanceRad(r.headingRad, s.headingRad) * 180 / .pi)
            } else {
                wrongFloorSeconds += dt
            }
            // Riding between floors: the truth switches floor mid-ride, the barometer settles seconds later. A
            // localized estimate still on the floor the walker left less than `floorChangeGraceSeconds` ago is
            // counted in wrongFloorSeconds, not as a confidently-wrong episode (floor changes have their own
            // figure, floorChangeRelocalizationMeters).
            let riding = !sameFloor && truth.state(at: r.t - Self.floorChangeGraceSeconds).floorId == r.floorId
            let wrong = r.localized && error > Self.wrongThresholdMeters && !riding
            if wrong {
                wrongConvergenceSeconds += dt
                if episodeStart == nil {
                    episodeStart = (r.t, truth.distanceWalked(at: r.t))
                    wrongConvergenceEpisodes += 1
                }
                if let e = episodeStart {
                    maxWrongConvergenceDistanceMeters = max(maxWrongConvergenceDistanceMeters, truth.distanceWalked(at: r.t) - e.walked)
                }
            } else {
                episodeStart = nil
            }
        }
        medianErrorMeters = percentile(errors, 50)
        p90ErrorMeters = percentile(errors, 90)
        p95ErrorMeters = percentile(errors, 95)
        medianHeadingErrorDeg = percentile(headingErrorsDeg, 50)
    }

    /// Finds the last switch of the true floor and how far the walker went on the new floor before a frame
    /// was localized there.
    private mutating func scoreFloorChange(trace: [TraceRecord], truth: TruthTrack) {
        var lastChange: (t: Double, floor: String)?
        var previous: String?
        for r in trace {
            let floor = truth.state(at: r.t).floorId
            if let previous, previous != floor { lastChange = (r.t, floor) }
            previous = floor
        }
        guard let change = lastChange else { return }
        let start = truth.distanceWalked(at: change.t)
        if let hit = trace.first(where: { $0.t >= change.t && $0.localized && $0.floorId == change.floor }) {
            floorChangeRelocalizationMeters = truth.distanceWalked(at: hit.t) - start
        } else {
            floorChangeNeverRelocalized = true
        }
    }
}
