import Foundation
import Maps
import SessionFormat
@testable import Simulation

/// Shared fixtures: the bundled office, loaded once.
enum Fixtures {
    /// The bundled two-floor office.
    static let office: Building = {
        do { return try BundledMaps.office() } catch { fatalError("bundled office failed to load: \(error)") }
    }()

    /// A scenario on the office with the given settings.
    static func scenario(_ name: String = "test", from: String = "room-101", to: String = "room-111", seed: UInt64 = 1,
                         carry: CarryMode = .handheld, rateHz: Double = 30) -> SimulationScenario {
        SimulationScenario(name: name, from: from, to: to, seed: seed, carry: carry, rateHz: rateHz)
    }

    /// Walks cached by (from, to, seed, carry) so statistical tests do not re-simulate.
    nonisolated(unsafe) static var cache: [String: SimulatedWalk] = [:]
    static let lock = NSLock()
    static func walk(_ s: SimulationScenario, parameters: SimulationParameters = .standard) throws -> SimulatedWalk {
        let key = "\(s)|\(parameters)"
        lock.lock(); defer { lock.unlock() }
        if let w = cache[key] { return w }
        let w = try WalkSimulator.simulate(building: office, scenario: s, parameters: parameters)
        cache[key] = w
        return w
    }

    /// Median of a non-empty array.
    static func median(_ xs: [Double]) -> Double {
        let s = xs.sorted()
        return s.count % 2 == 1 ? s[s.count / 2] : 0.5 * (s[s.count / 2 - 1] + s[s.count / 2])
    }
}
