import Foundation

/// Watches whether the map's north agrees with the compass, from what the traveler's own walk shows.
///
/// Why: the compass is the one source that tells a building from its mirror or quarter-turned image. A map whose
/// recorded north is wrong (a floor plan turned on import, a sign convention read the wrong way) turns it into
/// the source of a confident wrong start: replayed with every reading turned by 180 degrees, 12 of the 30 walks of
/// the convergence study lock on the mirror image for most of the walk (docs/benchmarks.md, "Fourteenth stop").
/// Nothing inside one walk tells a wrong north from a wrong lock before the signs have spoken; after they have,
/// the residual between the compass and the localized heading does. Real indoor disturbance is spatially
/// correlated but averages out over a walk: on 31 real mall walks the offset left after one north per building
/// was 0-1.5 degrees per site, 15 degrees at most per floor and 22 degrees per walk (docs/compass.md).
///
/// How (written here: no library does it): while the localizer is localized and the camera moves, one residual
/// `reading - localized heading` (both in the map frame) per `sampleSpacingMeters` walked (VIO distance, so
/// standing still adds nothing) joins a circular mean. The samples start again whenever the localized flag drops
/// (a new lock is a new hypothesis to check). When at least `minWalkedMeters` have been walked under one lock and
/// the mean residual is at least `minOffsetDeg` with a mean resultant length of at least `minResultant` (the
/// readings agree with each other: a turned north, not a noisy field), the check reports the offset once.
///
/// What the pipeline does with it: a warning naming the offset and the map field, and no more compass
/// evidence for the rest of the session (`WayfinderPipeline`): the filter then runs as with `--no-compass`, which
/// the gates hold without a confidently-wrong lock. Value type; owns nothing.
public struct CompassNorthCheck: Sendable {
    /// Thresholds of the check.
    public struct Parameters: Sendable, Equatable {
        /// Distance walked under one lock before a verdict, meters. Default 15: three decorrelation
        /// distances of the real field (1/e at 4 m, docs/compass.md), so the field's own offsets average out.
        public var minWalkedMeters = 15.0
        /// One residual per this distance walked, meters.
        public var sampleSpacingMeters = 1.0
        /// Smallest mean residual that counts as a wrong north, degrees. Default 60: above every per-floor
        /// (15) and per-walk (22) offset measured on real walks and above the real per-leg mean error's 90th
        /// percentile (29), and below the quarter turn that makes a wrong north dangerous.
        public var minOffsetDeg = 60.0
        /// Smallest mean resultant length of the residuals (1 = all equal), so a wildly varying compass is not
        /// read as a turned north. Default 0.8 (a circular standard deviation of about 38 degrees).
        public var minResultant = 0.8
        /// The defaults.
        public init() {}
    }

    /// A wrong north, as found.
    public struct Verdict: Sendable, Equatable {
        /// Mean of `compass reading - localized heading`, degrees in (-180, 180] (counter-clockwise positive, as
        /// map-frame angles are).
        public var offsetDeg: Double
        /// Mean resultant length of the residuals, in [0, 1].
        public var resultant: Double
        /// Distance walked under the lock, meters.
        public var walkedMeters: Double
        /// Residuals averaged.
        public var samples: Int
    }

    /// Thresholds in use.
    public let parameters: Parameters
    /// The verdict once the check has found a wrong north (it then stops watching).
    public private(set) var verdict: Verdict?
    private var sumCos = 0.0, sumSin = 0.0, samples = 0
    private var walkedMeters = 0.0, sinceSampleMeters = 0.0
    private var lastEast: Double?, lastNorth: Double?

    /// A check with the given thresholds.
    public init(parameters: Parameters = Parameters()) { self.parameters = parameters }

    /// Feeds one frame. `compassInMapRad`: the compass reading as a camera heading in the map frame (nil when the
    /// frame has none); `localizedHeadingRad`: the localizer's camera heading (map frame) when it is localized,
    /// nil when not; `cameraEastMeters` / `cameraNorthMeters`: the camera's VIO position (nil without a pose).
    /// Returns the verdict on the frame that reaches it, nil on every other frame.
    public mutating func observe(compassInMapRad: Double?, localizedHeadingRad: Double?, cameraEastMeters: Double?,
                                 cameraNorthMeters: Double?) -> Verdict? {
        guard verdict == nil else { return nil }
        guard let heading = localizedHeadingRad, heading.isFinite else {
            restart()
            return nil
        }
        guard let east = cameraEastMeters, let north = cameraNorthMeters, east.isFinite, north.isFinite else { return nil }
        if let e0 = lastEast, let n0 = lastNorth {
            let step = hypot(east - e0, north - n0)
            // A VIO jump (relocalization, reset) is not walking.
            if step < 2 {
                walkedMeters += step
                sinceSampleMeters += step
            }
        }
        lastEast = east
        lastNorth = north
        let first = samples == 0
        guard first || sinceSampleMeters >= parameters.sampleSpacingMeters,
              let reading = compassInMapRad, reading.isFinite else { return nil }
        sinceSampleMeters = 0
        let residual = reading - heading
        sumCos += cos(residual)
        sumSin += sin(residual)
        samples += 1
        guard walkedMeters >= parameters.minWalkedMeters, samples >= 2 else { return nil }
        let n = Double(samples)
        let resultant = hypot(sumCos, sumSin) / n
        let offsetDeg = atan2(sumSin, sumCos) * 180 / Double.pi
        guard resultant >= parameters.minResultant, abs(offsetDeg) >= parameters.minOffsetDeg else { return nil }
        let found = Verdict(offsetDeg: offsetDeg, resultant: resultant, walkedMeters: walkedMeters, samples: samples)
        verdict = found
        return found
    }

    /// Forgets the residuals (the lock dropped).
    private mutating func restart() {
        sumCos = 0
        sumSin = 0
        samples = 0
        walkedMeters = 0
        sinceSampleMeters = 0
        lastEast = nil
        lastNorth = nil
    }
}
