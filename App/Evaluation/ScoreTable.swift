import Foundation

/// Formats walk scores as a fixed-width table for people (the `wayfinder eval` default output).
public enum ScoreTable {
    /// The table: one row per walk, then the aggregate.
    public static func render(_ scores: [WalkScore], aggregate: AggregateScore) -> String {
        func f(_ v: Double?, _ digits: Int = 2) -> String { v.map { String(format: "%.\(digits)f", $0) } ?? "-" }
        let header = ["walk", "conv s", "conv m", "med m", "p90 m", "p95 m", "head°", "loc %", "wrong", "turns", "cued",
                      "miss", "bad", "cue m", "arrive m"]
        var rows: [[String]] = [header]
        for s in scores {
            let l = s.localization, n = s.navigation
            rows.append([s.name, f(l.timeToConvergenceSeconds, 1), f(l.distanceToConvergenceMeters, 1), f(l.medianErrorMeters),
                         f(l.p90ErrorMeters), f(l.p95ErrorMeters), f(l.medianHeadingErrorDeg, 1),
                         String(format: "%.0f", l.fractionLocalized * 100), "\(l.wrongConvergenceEpisodes)",
                         "\(n.expectedTurns.count)", "\(n.cueDistancesBeforeMeters.count)", "\(n.missingInstructions)",
                         "\(n.wrongInstructions)", f(percentile(n.cueDistancesBeforeMeters, 50)), f(n.arrivalDistanceMeters)])
        }
        let widths = header.indices.map { c in rows.map { $0[c].count }.max() ?? 0 }
        var out = rows.map { row in
            row.enumerated().map { c, cell in c == 0 ? cell.padding(toLength: widths[c], withPad: " ", startingAt: 0)
                : String(repeating: " ", count: widths[c] - cell.count) + cell }.joined(separator: "  ")
        }.joined(separator: "\n")
        out += "\n\n"
        out += String(format: "%d walks: converged within 20 m in %.0f%%; median error %@ m, p95 %@ m; confidently wrong %d (max %.1f m walked); turns missing %d, wrong %d; median cue %@ m before the point\n",
                      aggregate.walks, aggregate.convergedWithin20mShare * 100, f(aggregate.medianErrorMeters),
                      f(aggregate.p95ErrorMeters), aggregate.wrongConvergenceEpisodes, aggregate.maxWrongConvergenceDistanceMeters,
                      aggregate.missingInstructions, aggregate.wrongInstructions, f(aggregate.medianCueDistanceBeforeMeters))
        func pct(_ v: Double?) -> String { v.map { String(format: "%.0f%%", $0 * 100) } ?? "-" }
        out += "median convergence distance \(f(aggregate.medianConvergenceDistanceMeters)) m; localized in "
            + "\(pct(aggregate.localizedShareAfterConvergence)) of the frames after convergence"
        if let n = aggregate.floorChangeWalks {
            out += "; \(n) floor changes, relocalized within 10 m in \(pct(aggregate.floorChangeRelocalizedWithin10mShare))"
        }
        out += "; while not localized: directional instruction \(pct(aggregate.directedShareWhileUnsure)) of the time, "
            + "\(aggregate.unsafeUnsureInstructions.map(String.init) ?? "-") unsafe under the true pose\n"
        out += "\"now\" cues ending >= 0.5 m before the control point: \(pct(aggregate.nowCuesEndingInTimeShare)) of "
            + "\(aggregate.nowCues ?? 0)\n"
        return out
    }
}
