import Foundation

/// The phone's thermal state, as ProcessInfo reports it.
public enum ThermalLevel: String, Sendable, CaseIterable {
    /// Normal.
    case nominal
    /// Slightly warm.
    case fair
    /// Hot: performance should be reduced.
    case serious
    /// Very hot: reduce work drastically.
    case critical
}

/// Decides which camera frames the sign detector gets. Only detection is throttled: every frame still goes
/// through the motion update (`FrameScheduler`). A frame is sent to the detector when
/// - the detector is idle (a frame that arrives while it is busy keeps its motion update but no image: never
///   queued behind the detector),
/// - at least `1 / rateHz` has passed since the last detection started, where `rateHz` is the smallest of
///   the rate the thermal state and power mode allow (`baseRateHz` x `thermalFactor` x `lowPowerFactor`) and
///   the rate the time budget allows (`budgetShare` of one core / the measured detection time), and
/// - the pipeline is not behind (`backlogFrames` at most `maxBacklogFrames`).
/// A detection that never reports back frees the detector after `busyTimeoutSeconds`. A value type: the
/// adapter owns one (inside `FrameScheduler`) and asks it per frame.
public struct DetectorScheduler: Sendable {
    /// Detector rate when cool and the budget allows, Hz (the paper's app ran the detector at about 10 Hz).
    public var baseRateHz: Double = 10
    /// Rate multipliers per thermal level.
    public static let thermalFactor: [ThermalLevel: Double] = [.nominal: 1, .fair: 0.75, .serious: 0.4, .critical: 0.15]
    /// Rate multiplier while low-power mode is on or the battery is under 20 %.
    public static let lowPowerFactor = 0.6
    /// Share of one CPU core detection may take on average, 0...1 (0.35: the U-Net's 28 ms per frame on the
    /// Linux VM at 10 Hz is 0.28 core, docs/benchmarks.md; a slower frame lowers the rate instead).
    public var budgetShare = 0.35
    /// Weight of the newest duration in the running mean of detection time (exponential smoothing).
    public var durationSmoothing = 0.2
    /// A detection not reported finished after this long frees the detector anyway, seconds.
    public var busyTimeoutSeconds = 2.0
    /// Frames waiting for the pipeline above which no image is attached (the motion updates catch up first).
    public var maxBacklogFrames = 3

    private(set) var busy = false
    private var lastStartT = -Double.infinity
    /// Running mean of the reported detection times, seconds (nil until the first report).
    public private(set) var meanDetectionSeconds: Double?
    /// Current thermal level.
    public var thermal: ThermalLevel = .nominal
    /// Low-power mode or low battery.
    public var lowPower = false

    /// Creates a scheduler.
    public init(baseRateHz: Double = 10) { self.baseRateHz = baseRateHz }

    /// Rate allowed by the thermal state and power mode, Hz.
    public var thermalRateHz: Double {
        baseRateHz * (Self.thermalFactor[thermal] ?? 1) * (lowPower ? Self.lowPowerFactor : 1)
    }

    /// Rate allowed by the time budget, Hz (infinite until a duration was measured).
    public var budgetRateHz: Double {
        guard let d = meanDetectionSeconds, d > 0 else { return .infinity }
        return budgetShare / d
    }

    /// Effective detector rate now, Hz.
    public var rateHz: Double { min(thermalRateHz, budgetRateHz) }

    /// True when the frame at `t` (seconds) should be detected, and marks the detector busy; false = the
    /// frame goes to the motion update without an image. `backlogFrames`: frames already waiting for the
    /// pipeline queue.
    public mutating func shouldDetect(t: Double, backlogFrames: Int = 0) -> Bool {
        if busy, t - lastStartT > busyTimeoutSeconds { busy = false }
        guard !busy, backlogFrames <= maxBacklogFrames, rateHz > 0, t - lastStartT >= 1 / rateHz - 1e-9 else { return false }
        busy = true
        lastStartT = t
        return true
    }

    /// Call when the detector finished the frame it was given, with its wall time in seconds when measured
    /// (feeds the budget; a non-finite or negative duration is ignored).
    public mutating func detectionFinished(durationSeconds: Double? = nil) {
        busy = false
        guard let d = durationSeconds, d.isFinite, d >= 0 else { return }
        meanDetectionSeconds = meanDetectionSeconds.map { $0 + durationSmoothing * (d - $0) } ?? d
    }
}
