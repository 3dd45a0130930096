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

/// Decides which camera frames go to the sign detector: never queue (a frame that arrives while the
/// detector is busy is dropped), at most `baseRateHz`, and slower when the phone is hot or the battery low.
/// A value type: the iOS adapter owns one and asks it per frame.
public struct DetectorScheduler: Sendable {
    /// Detector rate when cool, Hz (the paper's app ran the detector at about 10 Hz).
    public var baseRateHz: Double = 10
    /// Rate multipliers per thermal level.
    public static let thermalFactor: [ThermalLevel: Double] = [.nominal: 1, .fair: 0.75, .serious: 0.4, .critical: 0.15]
    /// Rate multiplier while low-power mode is on or the battery is under 20 %.
    public static let lowPowerFactor = 0.6

    private(set) var busy = false
    private var lastStartT = -Double.infinity
    /// Current thermal level.
    public var thermal: ThermalLevel = .nominal
    /// Low-power mode or low battery.
    public var lowPower = false

    /// Creates a scheduler.
    public init(baseRateHz: Double = 10) { self.baseRateHz = baseRateHz }

    /// Effective detector rate now, Hz.
    public var rateHz: Double {
        baseRateHz * (Self.thermalFactor[thermal] ?? 1) * (lowPower ? Self.lowPowerFactor : 1)
    }

    /// True when the frame at `t` should be detected (and marks the detector busy); false = drop it.
    public mutating func shouldDetect(t: Double) -> Bool {
        guard !busy, t - lastStartT >= 1 / rateHz - 1e-9 else { return false }
        busy = true
        lastStartT = t
        return true
    }

    /// Call when the detector finished the frame it was given.
    public mutating func detectionFinished() { busy = false }
}
