import Foundation
import Maps

/// Every noise model's parameters. Defaults are the values documented in docs/simulator.md (table "Noise
/// models"); tests in Tests/SimulationTests measure generated data against them.
public struct SimulationParameters: Codable, Sendable, Equatable {
    /// The walking person.
    public var walker = WalkerParameters()
    /// The phone's pose relative to the body.
    public var phone = PhoneParameters()
    /// ARKit visual-inertial odometry errors.
    public var vio = VIOParameters()
    /// The Exit-sign detector and range estimator.
    public var detector = DetectorParameters()
    /// Barometer (CMAltimeter relative altitude).
    public var barometer = BarometerParameters()
    /// Compass (Core Location heading).
    public var compass = CompassParameters()
    /// ARKit vertical plane detection (PlaneSimulator.swift).
    public var planes = PlaneParameters()
    /// Where the building's signs truly hang, and how large they truly are, against the map the localizer reads
    /// (SurveyErrors.swift). None by default: the map is the truth.
    public var survey = SurveyParameters()
    /// The defaults.
    public init() {}
    /// The defaults.
    public static let standard = SimulationParameters()
}

/// The walking person: speed, pauses, sway, corners. Meters, seconds.
public struct WalkerParameters: Codable, Sendable, Equatable {
    /// Bounds of the walking (cruise) speed, m/s: the speed never leaves them except while starting, stopping
    /// or turning around.
    public var minSpeedMetersPerSecond = 0.8
    /// Upper bound of the cruise speed, m/s.
    public var maxSpeedMetersPerSecond = 1.4
    /// The walk's preferred speed is drawn uniformly from this range, m/s.
    public var preferredSpeedRange: ClosedRange<Double> = 0.9...1.3
    /// Standard deviation of the slow speed variation around the preferred speed (Ornstein-Uhlenbeck), m/s.
    public var speedVariationSigma = 0.08
    /// Correlation time of the speed variation, s.
    public var speedVariationTauSeconds = 5.0
    /// Acceleration when starting off, m/s^2.
    public var accelerationMetersPerSecond2 = 0.6
    /// Deceleration when stopping (pauses, turn-arounds, arrival), m/s^2.
    public var decelerationMetersPerSecond2 = 0.8
    /// Mean number of pauses per meter walked (Poisson), 1/m.
    public var pausesPerMeter = 1.0 / 40.0
    /// Pause length range, s.
    public var pauseSecondsRange: ClosedRange<Double> = 1.0...3.0
    /// Amplitude of the body's lateral sway at half the step frequency, m.
    public var swayAmplitudeMeters = 0.03
    /// Standard deviation of the slow lateral wander off the corridor centre line (Ornstein-Uhlenbeck), m.
    public var lateralWanderSigmaMeters = 0.10
    /// Correlation time of the lateral wander, s.
    public var lateralWanderTauSeconds = 4.0
    /// Minimum distance the camera keeps from any wall when the walker leaves the graph's centre line, m.
    public var wallClearanceMeters = 0.25
    /// At a corner, the walker leaves the route this far before the corner and rejoins it as far after it,
    /// measured along the route (drawn uniformly per corner), m: larger values cut the corner more. Limited
    /// by the room to the neighbouring corners, by `cornerCutMaxCorridorWidths` and by the walls.
    public var cornerCutRangeMeters: ClosedRange<Double> = 0.5...3.0
    /// How straight the cut is, drawn uniformly per corner: 0 = the round curve tangent to the route through
    /// the corner's control point (the only shape before corner cutting was widened), 1 = the
    /// straight diagonal from where the walker leaves the route to where it rejoins it.
    public var cornerCutStraightnessRange: ClosedRange<Double> = 0.0...1.0
    /// A cut corner passes at most this many corridor widths from the corner's graph node (the width taken
    /// as twice the corner's distance to the nearest wall, searched to 10 m; in open areas the walls and the
    /// room along the route limit the cut instead).
    public var cornerCutMaxCorridorWidths = 1.0
    /// Probability that a corner is widened (swung wide) instead of cut.
    public var cornerWidenProbability = 0.3
    /// How far a widened corner swings outwards, m.
    public var cornerWidenRangeMeters: ClosedRange<Double> = 0.1...0.4
    /// Maximum body turn rate, rad/s (turning in place at a turn-around).
    public var maxTurnRateRadPerSecond = 2.1
    /// Step frequency at 1.1 m/s, Hz (scales with the square root of speed).
    public var stepFrequencyHz = 1.8
    /// How far down the wrong branch the walker goes before turning around, m.
    public var wrongTurnDistanceRange: ClosedRange<Double> = 3.0...6.0
    /// Standing still before setting off, s.
    public var standBeforeSeconds = 1.5
    /// Standing still after arriving, s.
    public var standAfterSeconds = 1.0
    /// Time spent in an elevator between floors (waiting plus ride), s.
    public var elevatorSeconds = 15.0
    /// Vertical speed on stairs, m/s.
    public var stairsVerticalMetersPerSecond = 0.3
    /// The defaults.
    public init() {}
}

/// The phone's height and orientation relative to the walking body. Angles in degrees.
public struct PhoneParameters: Codable, Sendable, Equatable {
    /// Camera height above the floor, drawn once per walk, m.
    public var cameraHeightRange: ClosedRange<Double> = 1.3...1.5
    /// Vertical bob at the step frequency, m.
    public var bobAmplitudeMeters = 0.02
    /// Handheld: mean pitch drawn once per walk, degrees (positive looking up).
    public var handheldPitchMeanRangeDeg: ClosedRange<Double> = 0.0...12.0
    /// Handheld: pitch always stays in this range, degrees.
    public var handheldPitchLimitsDeg: ClosedRange<Double> = -5.0...20.0
    /// Handheld: slow pitch/roll/yaw wander standard deviation, degrees (Ornstein-Uhlenbeck, tau 3 s).
    public var handheldWanderSigmaDeg = 3.0
    /// Handheld: pitch and roll oscillation at the step frequency, degrees.
    public var handheldStepAmplitudeDeg = 1.0
    /// Hand tremor: white noise per frame on pitch, roll and yaw, degrees.
    public var tremorSigmaDeg = 0.3
    /// Lanyard: mean pitch range, degrees.
    public var lanyardPitchMeanRangeDeg: ClosedRange<Double> = -5.0...5.0
    /// Lanyard: pitch oscillation at the step frequency, degrees.
    public var lanyardPitchAmplitudeDeg = 5.0
    /// Lanyard: roll oscillation at the step frequency, degrees.
    public var lanyardRollAmplitudeDeg = 6.0
    /// Lanyard: yaw swing at half the step frequency (the torso's rotation with each stride), degrees.
    public var lanyardYawAmplitudeDeg = 8.0
    /// Lanyard: slow wander standard deviation, degrees.
    public var lanyardWanderSigmaDeg = 2.0
    /// Correlation time of the slow orientation wander, s.
    public var wanderTauSeconds = 3.0
    /// The defaults.
    public init() {}
}

/// ARKit VIO errors (see docs/simulator.md for what each imitates).
public struct VIOParameters: Codable, Sendable, Equatable {
    /// Magnitude of the scale error |s - 1|, drawn uniformly, sign random (1-5 %).
    public var scaleErrorRange: ClosedRange<Double> = 0.01...0.05
    /// Magnitude of the constant yaw drift rate, drawn uniformly, sign random, degrees per minute.
    public var yawDriftRateRangeDegPerMinute: ClosedRange<Double> = 0.5...2.0
    /// Yaw random walk on top of the drift, degrees per square-root minute.
    public var yawRandomWalkDegPerSqrtMinute = 0.5
    /// Position jitter (white, each axis, not accumulated), m.
    public var positionJitterMeters = 0.002
    /// Orientation jitter (white, each angle), degrees.
    public var orientationJitterDeg = 0.1
    /// Extra position random walk while tracking is limited, m per square-root second (each horizontal axis).
    public var limitedPositionRandomWalkMetersPerSqrtSecond = 0.03
    /// Body turn rate above which ARKit reports `limited`/`excessiveMotion`, degrees per second.
    public var excessiveMotionTurnRateDegPerSecond = 100.0
    /// Mean rate of `limited`/`insufficientFeatures` spells (dark or blank walls), per second.
    public var darkSpellsPerSecond = 1.0 / 120.0
    /// Length of a dark spell, s.
    public var darkSpellSecondsRange: ClosedRange<Double> = 1.0...3.0
    /// Mean rate of relocalization events (a `relocalizing` spell then a jump of the world origin), per second.
    public var relocalizationsPerSecond = 1.0 / 180.0
    /// Length of the `relocalizing` spell before the jump, s.
    public var relocalizingSecondsRange: ClosedRange<Double> = 1.0...2.0
    /// Size of the origin jump after relocalizing (uniform), m; capped at 1 m by the default.
    public var relocalizationJumpMetersRange: ClosedRange<Double> = 0.2...1.0
    /// Standard deviation of the yaw jump after relocalizing, degrees (capped at 3 sigma).
    public var relocalizationYawJumpSigmaDeg = 2.0
    /// `limited`/`initializing` at the session start and after a reset, s.
    public var initializingSeconds = 0.7
    /// `limited`/`relocalizing` after a tracking loss, s.
    public var afterLossRelocalizingSeconds = 1.0
    /// Whether the VIO pose follows the walk through a tracking loss (ARKit relocalized into its old map: the
    /// pose after the loss is the true one in the old frame). False (the default): the pose resumes where it
    /// stopped, the walk during the loss unmeasured.
    public var poseKeptThroughLoss = false
    /// Distance of the session's world origin from the start (the first pose is near the origin), m.
    public var originOffsetMeters = 0.05
    /// The defaults.
    public init() {}
}

/// The sign detector and its range/bearing measurements.
public struct DetectorParameters: Codable, Sendable, Equatable {
    /// Signs farther than this (horizontal range) are never detected, m.
    public var maxRangeMeters = 12.0
    /// Signs closer than this are never detected (the sign fills or leaves the image), m.
    public var minRangeMeters = 0.5
    /// Log-normal range noise: measured = true * exp(N(0, sigma)); the median relative error is 0.6745 sigma
    /// (8.1 % for 0.12, the U-Net column of the paper's Table 1).
    public var rangeLogSigma = 0.12
    /// Systematic relative range error: measured = true * (1 + rangeBias) * exp(N(0, rangeLogSigma)). 0 (the
    /// default) for an unbiased estimator; the real-photo presets below carry the biases measured on real
    /// photos (a mask whose edges sit outside the face reads long, a box taller than the face reads short).
    public var rangeBias = 0.0
    /// Bearing noise standard deviation, degrees.
    public var bearingSigmaDeg = 2.0
    /// Detection probability up to `nearRangeMeters`.
    public var nearDetectionProbability = 0.95
    /// Range up to which the detection probability is `nearDetectionProbability`, m.
    public var nearRangeMeters = 5.0
    /// Detection probability at `midRangeMeters` (linear from near), then linear to `farDetectionProbability`.
    public var midDetectionProbability = 0.85
    /// See `midDetectionProbability`, m.
    public var midRangeMeters = 7.0
    /// Detection probability at `maxRangeMeters`.
    public var farDetectionProbability = 0.3
    /// Body turn rate above which motion blur halves the detection probability, degrees per second.
    public var motionBlurTurnRateDegPerSecond = 60.0
    /// False positives per processed frame (e.g. a red light taken for a sign).
    public var falsePositivesPerFrame = 1.0 / 300.0
    /// Whether the scores tell false positives from signs (the default): a sign scores 0.92 - 0.03 r + N(0, 0.04)
    /// (clamped 0.3-0.99) and a false positive U(0.3, 0.7), so the localizer discounts the false ones as clutter.
    /// false: every observation, a sign's and a false positive's alike, scores `constantScore`. The real
    /// detectors' scores do not tell the two apart: the U-Net reports the mask's mean probability and accepts
    /// nothing under 0.92, the cascade its neighbour count, which the localizer reads as 1 (issue 16); the stress
    /// test without that help (docs/benchmarks.md "Twenty-third stop").
    public var scoresTellFalsePositives = true
    /// Every observation's score when `scoresTellFalsePositives` is false (0...1).
    public var constantScore = 1.0
    /// Look-alikes per meter of wall (0 = none, the default): fixed objects the detector takes for an Exit sign
    /// frame after frame, a poster, a red light or a fiducial marker (the cascade's false positives on the real
    /// photos, issue 16). Unlike `falsePositivesPerFrame`, which lands anywhere each time, a look-alike stays put,
    /// so a sighting of it is confirmed by the next frame's (App/Core/SightingCorroboration) and fits a wrong pose
    /// as well as a sign does. Placed once per walk on both faces of randomly chosen walls (length-weighted), at
    /// an Exit sign's height and size, facing away from its wall; one on a face nobody walks past is never seen.
    public var lookAlikesPerMeterOfWall = 0.0
    /// Share of the frames a look-alike in view is reported in, against an Exit sign at the same range (0...1): it
    /// is seen like a sign (range, face angle, image margin, walls), reported as the floor's false-positive kind
    /// with the signs' range and bearing noise and the false positives' score.
    public var lookAlikeDetectionShare = 0.5
    /// Largest angle between the sign's face normal and the line to the camera at which it is still detected,
    /// degrees (`SignKindSpec.detectorMaxViewAngleDeg`, 75: seen more obliquely, a face is a sliver no detector
    /// finds). Double-sided signs are measured against the nearer face.
    public var maxViewAngleFromNormalDeg = SignKindSpec.detectorMaxViewAngleDeg
    /// Fraction of the image's half-width kept as a margin: a sign whose centre projects closer to the image
    /// border than this is not detected (it is cut off).
    public var imageMargin = 0.03
    /// The defaults.
    public init() {}

    /// The U-Net as measured on 357 real iPhone photos of Exit signs taken outside the project (issue 16,
    /// "Where it stands"): recall 0.93 (falling past 7 m), median range error 9.0 % with a +6.8 % bias (reads
    /// long), 0.01 false positives per frame. The log-normal spread 0.11 is the one that, with the bias, gives
    /// a 9.0 % median absolute error (|N(0.068, 0.11)| has median 0.09). A stress test of the localizer
    /// against a real detector's errors, not the simulator's own: `wayfinder eval --sim-detector real-unet`.
    public static var realPhotoUNet: DetectorParameters {
        var d = DetectorParameters()
        d.rangeBias = 0.068
        d.rangeLogSigma = 0.11
        d.nearDetectionProbability = 0.93
        d.midDetectionProbability = 0.85
        d.farDetectionProbability = 0.5
        d.maxRangeMeters = 10
        d.falsePositivesPerFrame = 0.01
        return d
    }

    /// The cascade as measured on the same real photos before its box refinement (issue 16): recall 0.57,
    /// collapsing past 4 m (0.46 at 5 m, 0.29 at 6 m), range error 25 % with a -25 % bias (the box is taller
    /// than the face), 0.06 false positives per frame (posters, ceiling lights, markers). The worst detector
    /// the localizer has been measured behind: `wayfinder eval --sim-detector real-cascade`.
    public static var realPhotoCascade: DetectorParameters {
        var d = DetectorParameters()
        d.rangeBias = -0.25
        d.rangeLogSigma = 0.08
        d.nearDetectionProbability = 0.9
        d.nearRangeMeters = 4
        d.midDetectionProbability = 0.29
        d.midRangeMeters = 6
        d.farDetectionProbability = 0.05
        d.maxRangeMeters = 9
        d.falsePositivesPerFrame = 0.06
        return d
    }

    /// Detection probability of a sign at horizontal range `r` meters (before motion blur).
    public func detectionProbability(rangeMeters r: Double) -> Double {
        if r < minRangeMeters || r > maxRangeMeters { return 0 }
        if r <= nearRangeMeters { return nearDetectionProbability }
        if r <= midRangeMeters {
            return nearDetectionProbability + (midDetectionProbability - nearDetectionProbability) * (r - nearRangeMeters) / (midRangeMeters - nearRangeMeters)
        }
        return midDetectionProbability + (farDetectionProbability - midDetectionProbability) * (r - midRangeMeters) / (maxRangeMeters - midRangeMeters)
    }
}

/// A survey's errors: the map the localizer is given against the building the simulated detector sees
/// (SurveyErrors.swift). A real map's signs were placed by someone with a tape, a floor plan or a phone, and a
/// building mixes sign models of different sizes; the simulator's map is otherwise the truth. Drawn once per walk
/// and sign, from their own random stream (so walks with every setting at zero are those of before).
public struct SurveyParameters: Codable, Sendable, Equatable {
    /// Standard deviation of each sign's true position along its wall from the map's, meters (normal, drawn per
    /// sign). A sign flat on a wall stays on its wall's line (it slides perpendicular to its facing); a projecting
    /// one slides along the corridor it hangs across (along its facing), its faces together; so no wall comes
    /// between.
    public var signAlongWallSigmaMeters = 0.0
    /// Log-normal spread of each sign's true face size against the map's and the catalogue's: a face k times as
    /// large as the catalogue says reads every range 1 / k as long (the detector ranges from the face's apparent
    /// height with the catalogue's height). Per sign, so it is not one common range bias the localizer can learn.
    public var signSizeLogSigma = 0.0
    /// Standard deviation of each wall face's true position along its normal from the map's, meters (normal,
    /// drawn per face of collinear wall segments; ARKit's planes see the true walls, PlaneSimulator.swift). The
    /// walker and the signs' visibility keep the map's walls (a few centimetres).
    public var wallOffsetSigmaMeters = 0.0
    /// The defaults: no survey error.
    public init() {}
}

/// The barometer's relative altitude.
public struct BarometerParameters: Codable, Sendable, Equatable {
    /// White noise of each reading, m.
    public var noiseSigmaMeters = 0.1
    /// Standard deviation of the constant drift rate drawn per walk (weather, temperature), m per minute.
    public var driftRateSigmaMetersPerMinute = 0.03
    /// New readings per second (CMAltimeter delivers about one per second; frames repeat the last one).
    public var updateRateHz = 1.0
    /// The defaults.
    public init() {}
}

/// The compass's heading (Core Location), indoors. Defaults are the fit to 31 real phone walks in two
/// steel-framed malls (raw tilt-compensated magnetometer against the gyro-tracked device heading, one north per
/// building; `scripts/compass_study.py`, docs/compass.md): circular standard deviation 16.8 degrees, |error|
/// median 9.9, 95 % 34.7, 99 % 49.9 degrees, beyond 45 degrees in 1.9 % of the samples, none beyond 90;
/// correlation 1/e after about 4 m walked. See `CompassModel`.
public struct CompassParameters: Codable, Sendable, Equatable {
    /// False: the phone records no compass (older bundles): every frame's `compassHeadingDeg` is nil.
    public var isPresent = true
    /// Standard deviation of the constant bias drawn per floor, degrees (measured floor offsets: 7.3).
    public var floorBiasSigmaDeg = 6.0
    /// Root-mean-square standard deviation of the smooth disturbance field over a floor, degrees.
    public var fieldSigmaDeg = 15.0
    /// Spread between floors of the field's standard deviation: each floor's is `fieldSigmaDeg` times
    /// exp(N(0, s) - s^2) (mean square 1): some floors are calm, some disturbed, which gives the real traces'
    /// peaked centre and heavy shoulders.
    public var fieldSigmaFloorLogSigma = 0.3
    /// Distance at which the field's correlation falls to 1/e (Gaussian correlation exp(-(d / L)^2)), m
    /// (measured: 4.0 m of walking).
    public var fieldCorrelationLengthMeters = 4.0
    /// Number of random Fourier modes of the field (more: closer to Gaussian, slower).
    public var fieldModeCount = 48
    /// Share of the floor (hence of the distance walked) inside a steel hotspot, where large deviations occur.
    public var outlierShare = 0.02
    /// Radius of a hotspot disc, m.
    public var hotspotRadiusMeters = 1.5
    /// Side of the lattice cell that holds at most one hotspot, m.
    public var hotspotCellMeters = 10.0
    /// Range of a hotspot's peak deviation (either sign, smooth bump to 0 at the disc's edge), degrees.
    public var hotspotPeakDeg: ClosedRange<Double> = 40.0...90.0
    /// White noise per reading, degrees.
    public var noiseSigmaDeg = 2.0
    /// Typical reported `headingAccuracy`, degrees (not measured: the real traces carry no accuracy values).
    public var accuracyTypicalDeg = 15.0
    /// Log-normal spread of the walk's typical reported accuracy.
    public var accuracyLogSigma = 0.3
    /// Growth of the reported accuracy per degree of hotspot deviation.
    public var accuracyHotspotGain = 0.5
    /// The defaults (the real-data fit).
    public init() {}

    /// No compass in the bundle.
    public static var absent: CompassParameters { var p = CompassParameters(); p.isPresent = false; return p }

    /// A clean compass (no floor bias, field or hotspots; white noise only), for tests and ablations.
    public static var undisturbed: CompassParameters {
        var p = CompassParameters(); p.floorBiasSigmaDeg = 0; p.fieldSigmaDeg = 0; p.outlierShare = 0; return p
    }

    /// Standard deviation of the error the model generates at a random point of a random floor, degrees:
    /// floor bias, field, hotspots (share times the mean square of the bump, E[peak^2] * 1/5 over the disc
    /// area for the (1 - r^2)^2 profile) and white noise, added in quadrature.
    public var expectedErrorSigmaDeg: Double {
        let a = hotspotPeakDeg.lowerBound, b = hotspotPeakDeg.upperBound
        let meanPeakSquared = (a * a + a * b + b * b) / 3
        let hotspotVariance = outlierShare * meanPeakSquared / 5
        return (floorBiasSigmaDeg * floorBiasSigmaDeg + fieldSigmaDeg * fieldSigmaDeg + hotspotVariance
                + noiseSigmaDeg * noiseSigmaDeg).squareRoot()
    }

    /// Throws `SimulationError.invalidScenario` naming the first unusable compass parameter.
    func validate() throws {
        func bad(_ s: String) -> SimulationError { .invalidScenario("parameters: compass \(s)") }
        let sigmas = [floorBiasSigmaDeg, fieldSigmaDeg, fieldSigmaFloorLogSigma, noiseSigmaDeg, accuracyTypicalDeg, accuracyLogSigma, accuracyHotspotGain]
        guard sigmas.allSatisfy({ $0.isFinite && $0 >= 0 }) else {
            throw bad("floorBiasSigmaDeg, fieldSigmaDeg, fieldSigmaFloorLogSigma, noiseSigmaDeg and the accuracy settings must be finite and non-negative")
        }
        guard fieldCorrelationLengthMeters.isFinite, fieldCorrelationLengthMeters > 0 else {
            throw bad("fieldCorrelationLengthMeters must be positive, got \(fieldCorrelationLengthMeters)")
        }
        guard fieldModeCount >= 1, fieldModeCount <= 4096 else { throw bad("fieldModeCount must be in 1...4096, got \(fieldModeCount)") }
        guard outlierShare.isFinite, (0...0.5).contains(outlierShare) else { throw bad("outlierShare must be in 0...0.5, got \(outlierShare)") }
        guard hotspotRadiusMeters.isFinite, hotspotRadiusMeters > 0, hotspotCellMeters.isFinite,
              hotspotCellMeters >= 2 * hotspotRadiusMeters else {
            throw bad("hotspotRadiusMeters must be positive and hotspotCellMeters at least twice it")
        }
        guard Double.pi * hotspotRadiusMeters * hotspotRadiusMeters >= outlierShare * hotspotCellMeters * hotspotCellMeters else {
            throw bad("outlierShare \(outlierShare) needs more than one hotspot per \(hotspotCellMeters)-m cell: enlarge hotspotRadiusMeters")
        }
        guard hotspotPeakDeg.lowerBound.isFinite, hotspotPeakDeg.upperBound.isFinite, hotspotPeakDeg.lowerBound >= 0,
              hotspotPeakDeg.upperBound <= 180 else { throw bad("hotspotPeakDeg must lie in 0...180") }
    }
}

extension SimulationParameters {
    /// Checks that the parameters the models divide by or loop on are usable; throws
    /// `SimulationError.invalidScenario` naming the first bad one.
    public func validate() throws {
        func bad(_ s: String) -> SimulationError { .invalidScenario("parameters: \(s)") }
        let w = walker
        guard w.minSpeedMetersPerSecond > 0, w.maxSpeedMetersPerSecond >= w.minSpeedMetersPerSecond else {
            throw bad("walker speeds must satisfy 0 < min <= max")
        }
        guard w.accelerationMetersPerSecond2 > 0, w.decelerationMetersPerSecond2 > 0 else { throw bad("walker acceleration and deceleration must be positive") }
        guard w.maxTurnRateRadPerSecond > 0 else { throw bad("walker maxTurnRateRadPerSecond must be positive") }
        guard w.stepFrequencyHz > 0 else { throw bad("walker stepFrequencyHz must be positive") }
        guard w.pausesPerMeter >= 0, w.pauseSecondsRange.lowerBound >= 0 else { throw bad("walker pauses must be non-negative") }
        guard w.elevatorSeconds > 0, w.stairsVerticalMetersPerSecond > 0 else { throw bad("walker elevator and stairs timings must be positive") }
        guard w.wallClearanceMeters >= 0 else { throw bad("walker wallClearanceMeters must be non-negative") }
        guard w.cornerCutRangeMeters.lowerBound >= 0, w.cornerCutStraightnessRange.lowerBound >= 0,
              w.cornerCutStraightnessRange.upperBound <= 1, w.cornerCutMaxCorridorWidths >= 0 else {
            throw bad("walker corner cutting: cornerCutRangeMeters must be >= 0, cornerCutStraightnessRange within 0...1, cornerCutMaxCorridorWidths >= 0")
        }
        guard detector.maxRangeMeters > detector.minRangeMeters, detector.rangeLogSigma >= 0, detector.bearingSigmaDeg >= 0 else {
            throw bad("detector ranges must satisfy min < max and noise must be non-negative")
        }
        guard detector.maxViewAngleFromNormalDeg > 0, detector.maxViewAngleFromNormalDeg <= 90 else {
            throw bad("detector maxViewAngleFromNormalDeg must be in (0, 90]")
        }
        guard detector.rangeBias.isFinite, detector.rangeBias > -1 else { throw bad("detector rangeBias must be finite and > -1") }
        guard (0...1).contains(detector.falsePositivesPerFrame) else { throw bad("detector falsePositivesPerFrame must be in 0...1") }
        guard (0...1).contains(detector.constantScore) else { throw bad("detector constantScore must be in 0...1") }
        guard detector.lookAlikesPerMeterOfWall.isFinite, detector.lookAlikesPerMeterOfWall >= 0, detector.lookAlikesPerMeterOfWall <= 10 else {
            throw bad("detector lookAlikesPerMeterOfWall must be in 0...10")
        }
        guard (0...1).contains(detector.lookAlikeDetectionShare) else { throw bad("detector lookAlikeDetectionShare must be in 0...1") }
        guard barometer.updateRateHz > 0 else { throw bad("barometer updateRateHz must be positive") }
        guard vio.darkSpellsPerSecond >= 0, vio.relocalizationsPerSecond >= 0 else { throw bad("VIO event rates must be non-negative") }
        try compass.validate()
        guard survey.signAlongWallSigmaMeters.isFinite, survey.signAlongWallSigmaMeters >= 0, survey.signAlongWallSigmaMeters <= 5 else {
            throw bad("survey signAlongWallSigmaMeters must be in 0...5")
        }
        guard survey.wallOffsetSigmaMeters.isFinite, survey.wallOffsetSigmaMeters >= 0, survey.wallOffsetSigmaMeters <= 2 else {
            throw bad("survey wallOffsetSigmaMeters must be in 0...2")
        }
        guard survey.signSizeLogSigma.isFinite, survey.signSizeLogSigma >= 0, survey.signSizeLogSigma <= 1 else {
            throw bad("survey signSizeLogSigma must be in 0...1")
        }
    }
}
