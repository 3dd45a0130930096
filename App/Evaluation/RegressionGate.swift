import Foundation

/// Compares an aggregate score with a committed baseline (Tests/Baselines/*.json) and lists every figure
/// that got worse by more than its tolerance. The tolerances are part of the baseline file, so changing a
/// gate is a reviewed change.
public struct RegressionBaseline: Codable, Sendable {
    /// The figures the gate protects.
    public var aggregate: AggregateScore
    /// Allowed worsening of error figures, meters (default 0.15).
    public var errorToleranceMeters: Double
    /// Allowed drop of the converged-within-20-m share (default 0.1).
    public var convergenceShareTolerance: Double
    /// Allowed increase of instruction counts (missing, wrong), absolute (default 0).
    public var instructionCountTolerance: Int
    /// Creates a baseline from figures with default tolerances.
    public init(aggregate: AggregateScore, errorToleranceMeters: Double = 0.15, convergenceShareTolerance: Double = 0.1,
                instructionCountTolerance: Int = 0) {
        self.aggregate = aggregate; self.errorToleranceMeters = errorToleranceMeters
        self.convergenceShareTolerance = convergenceShareTolerance; self.instructionCountTolerance = instructionCountTolerance
    }

    /// Reads a baseline file.
    public static func load(_ url: URL) throws -> RegressionBaseline {
        do { return try JSONDecoder().decode(RegressionBaseline.self, from: Data(contentsOf: url)) } catch {
            throw EvaluationError.badBaseline("\(url.path): cannot read baseline: \(error)")
        }
    }

    /// Writes this baseline (pretty, sorted keys).
    public func write(to url: URL) throws {
        let e = JSONEncoder()
        e.outputFormatting = [.prettyPrinted, .sortedKeys]
        try e.encode(self).write(to: url, options: .atomic)
    }

    /// Rounding slack of the share comparisons: a share is a ratio of small counts, and a drop of exactly the
    /// tolerance (10 of 30 walks against a baseline of 13 of 30, tolerance 0.1) must pass however the
    /// subtraction rounds (13/30 - 0.1 is 5.6e-17 above 10/30 in doubles).
    static let shareRoundingSlack = 1e-9

    /// The regressions of `current` against this baseline; empty when the gate passes.
    public func regressions(of current: AggregateScore) -> [String] {
        var out: [String] = []
        let b = aggregate
        let slack = Self.shareRoundingSlack
        if current.convergedWithin20mShare < b.convergedWithin20mShare - convergenceShareTolerance - slack {
            out.append(String(format: "converged within 20 m: %.2f < baseline %.2f - %.2f", current.convergedWithin20mShare,
                              b.convergedWithin20mShare, convergenceShareTolerance))
        }
        func worse(_ name: String, _ now: Double?, _ then: Double?) {
            guard let then else { return }
            guard let now else { out.append("\(name): no value (baseline \(then))"); return }
            if now > then + errorToleranceMeters {
                out.append(String(format: "%@: %.2f m > baseline %.2f m + %.2f", name, now, then, errorToleranceMeters))
            }
        }
        worse("median error", current.medianErrorMeters, b.medianErrorMeters)
        worse("p95 error", current.p95ErrorMeters, b.p95ErrorMeters)
        if current.wrongConvergenceEpisodes > b.wrongConvergenceEpisodes {
            out.append("confidently-wrong episodes: \(current.wrongConvergenceEpisodes) > baseline \(b.wrongConvergenceEpisodes)")
        }
        if current.missingInstructions > b.missingInstructions + instructionCountTolerance {
            out.append("missing instructions: \(current.missingInstructions) > baseline \(b.missingInstructions)")
        }
        if current.wrongInstructions > b.wrongInstructions + instructionCountTolerance {
            out.append("wrong instructions: \(current.wrongInstructions) > baseline \(b.wrongInstructions)")
        }
        func dropped(_ name: String, _ now: Double?, _ then: Double?) {
            guard let then else { return }
            guard let now else { out.append("\(name): no value (baseline \(then))"); return }
            if now < then - convergenceShareTolerance - slack {
                out.append(String(format: "%@: %.2f < baseline %.2f - %.2f", name, now, then, convergenceShareTolerance))
            }
        }
        dropped("localized share after convergence", current.localizedShareAfterConvergence, b.localizedShareAfterConvergence)
        dropped("relocalized within 10 m of a floor change", current.floorChangeRelocalizedWithin10mShare,
                b.floorChangeRelocalizedWithin10mShare)
        dropped("now cues ending 0.5 m before the point", current.nowCuesEndingInTimeShare, b.nowCuesEndingInTimeShare)
        if let then = b.unsafeUnsureInstructions, (current.unsafeUnsureInstructions ?? 0) > then {
            out.append("unsafe instructions while not localized: \(current.unsafeUnsureInstructions ?? 0) > baseline \(then)")
        }
        return out
    }
}
