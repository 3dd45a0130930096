import Foundation

/// Which wall kinds (the sign kinds the detector searches in turn: restroom, elevator and stairs pictograms, room
/// placards, whose cascades run beside the U-Net) each detector frame looks for.
///
/// The cost budget is the detector's (docs/sign-detection.md "Two kinds on every second frame"): `kindsPerFrame` wall
/// kinds on one detector frame in `framePeriod` (2 and 2, the detector's `cascade_wall_kinds_per_frame` and
/// `cascade_wall_kind_frame_period` defaults). Which kinds, by `mode`:
/// - `.expected` (the phone's): first the kinds the localizer's hypotheses expect in view (`ExpectedSignKinds`: the
///   weight share of the hypotheses that see a sign of the kind), most expected first and at least
///   `minExpectedShare`, in up to `kindsPerFrame - 1` slots (at least one); the other slots go round all the kinds
///   in turn, so every kind is still looked for regularly whatever the hypotheses believe. Sensing where the belief
///   expects the information is active perception (Fox, Burgard & Thrun 1998, "Active Markov localization"; here
///   with the sensing cost held fixed). With no kind expected it is the detector's own rotation exactly.
/// - `.rotation`: the detector's own rotation (as before 2026-12-06).
/// - `.everyFrame`: every wall kind on every detector frame (no cost budget).
/// Written by hand: a few lines of scheduling no library provides.
public struct WallKindScheduler: Sendable {
    /// How the kinds of a searched frame are chosen (see the type's documentation).
    public enum Mode: String, Sendable, CaseIterable {
        case expected
        case rotation
        case everyFrame = "every-frame"
    }

    /// The kinds searched in turn, in the detector's order (empty: nothing to schedule).
    public let kinds: [String]
    /// How the kinds of a searched frame are chosen.
    public let mode: Mode
    /// Wall kinds looked for on a searched frame (all of them when <= 0 or >= kinds.count).
    public let kindsPerFrame: Int
    /// One detector frame in this many looks for wall kinds (>= 1).
    public let framePeriod: Int
    /// Smallest weight share of the hypotheses expecting a kind in view that gives it a slot before its turn.
    public static let minExpectedShare = 0.05
    private var frames = 0
    private var cursor = 0

    /// A schedule of `kinds` (in the detector's order).
    public init(kinds: [String], mode: Mode = .expected, kindsPerFrame: Int = 2, framePeriod: Int = 2) {
        self.kinds = kinds
        self.mode = mode
        self.kindsPerFrame = kindsPerFrame
        self.framePeriod = max(1, framePeriod)
    }

    /// Whether the next detector frame looks for any wall kind (what `next` will return is not empty), so a caller
    /// need not weigh the hypotheses' expectations for a frame that searches none.
    public var searchesNextFrame: Bool { !kinds.isEmpty && (mode == .everyFrame || frames % framePeriod == 0) }

    /// The wall kinds the next detector frame looks for; advances the schedule by one frame. `expectedShares`: by
    /// kind, the weight share of the hypotheses that expect a sign of it in view (used by `.expected` only).
    public mutating func next(expectedShares: [String: Double] = [:]) -> Set<String> {
        guard !kinds.isEmpty else { return [] }
        if mode == .everyFrame { return Set(kinds) }
        let searches = searchesNextFrame
        frames += 1
        guard searches else { return [] }
        let slots = kindsPerFrame <= 0 ? kinds.count : min(kindsPerFrame, kinds.count)
        if slots == kinds.count { return Set(kinds) }
        var chosen: [String] = []
        if mode == .expected {
            let expected = kinds.enumerated()
                .compactMap { i, kind -> (Int, String, Double)? in
                    let share = expectedShares[kind] ?? 0
                    return share >= Self.minExpectedShare ? (i, kind, share) : nil
                }
                .sorted { $0.2 != $1.2 ? $0.2 > $1.2 : $0.0 < $1.0 }
            chosen = expected.prefix(max(1, slots - 1)).map(\.1)
        }
        var visited = 0
        while chosen.count < slots && visited < kinds.count {
            let kind = kinds[(cursor + visited) % kinds.count]
            visited += 1
            if !chosen.contains(kind) { chosen.append(kind) }
        }
        cursor = (cursor + visited) % kinds.count
        return Set(chosen)
    }
}
