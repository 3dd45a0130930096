import Foundation
import Maps
import SessionFormat

/// The ground-truth path of a walk, with cumulative distance, queried by time.
public struct TruthTrack: Sendable {
    /// Truth records, sorted by time.
    public let records: [TruthRecord]
    /// Distance walked from the first record to each record, meters (horizontal, same-floor steps only).
    public let cumulativeDistanceMeters: [Double]

    /// Builds the track; records are sorted by time.
    public init(_ records: [TruthRecord]) {
        let sorted = records.sorted { $0.t < $1.t }
        self.records = sorted
        var cumulative: [Double] = []
        cumulative.reserveCapacity(sorted.count)
        var total = 0.0
        for (i, r) in sorted.enumerated() {
            if i > 0, sorted[i - 1].floorId == r.floorId { total += hypot(r.x - sorted[i - 1].x, r.y - sorted[i - 1].y) }
            cumulative.append(total)
        }
        cumulativeDistanceMeters = cumulative
    }

    /// True when there is no truth.
    public var isEmpty: Bool { records.isEmpty }

    /// Index of the last record at or before `t` (0 when `t` precedes all).
    public func index(at t: Double) -> Int {
        var lo = 0, hi = records.count - 1, best = 0
        while lo <= hi {
            let mid = (lo + hi) / 2
            if records[mid].t <= t { best = mid; lo = mid + 1 } else { hi = mid - 1 }
        }
        return best
    }

    /// Truth state at time `t`, linearly interpolated in position (heading from the earlier record).
    public func state(at t: Double) -> TruthRecord {
        let i = index(at: t)
        let a = records[i]
        guard i + 1 < records.count, records[i + 1].floorId == a.floorId else { return a }
        let b = records[i + 1]
        let span = b.t - a.t
        let f = span > 0 ? max(0, min(1, (t - a.t) / span)) : 0
        return TruthRecord(t: t, x: a.x + f * (b.x - a.x), y: a.y + f * (b.y - a.y), floorId: a.floorId, headingRad: a.headingRad)
    }

    /// Distance walked up to time `t`, meters.
    public func distanceWalked(at t: Double) -> Double {
        let i = index(at: t)
        guard i + 1 < records.count else { return cumulativeDistanceMeters[i] }
        let a = records[i], b = records[i + 1]
        let span = b.t - a.t
        let f = span > 0 ? max(0, min(1, (t - a.t) / span)) : 0
        return cumulativeDistanceMeters[i] + f * (cumulativeDistanceMeters[i + 1] - cumulativeDistanceMeters[i])
    }
}

/// Percentile of a sample by linear interpolation between order statistics (type 7, as numpy's default).
/// Returns nil for an empty sample. `p` in 0...100.
public func percentile(_ values: [Double], _ p: Double) -> Double? {
    guard !values.isEmpty else { return nil }
    let s = values.sorted()
    let rank = (p / 100) * Double(s.count - 1)
    let lo = Int(rank.rounded(.down)), hi = Int(rank.rounded(.up))
    return s[lo] + (rank - Double(lo)) * (s[hi] - s[lo])
}

/// Smallest absolute difference between two angles, radians in 0...pi.
public func angularDistanceRad(_ a: Double, _ b: Double) -> Double {
    var d = (a - b).truncatingRemainder(dividingBy: 2 * .pi)
    if d > .pi { d -= 2 * .pi }
    if d < -.pi { d += 2 * .pi }
    return abs(d)
}
