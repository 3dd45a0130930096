import Foundation
import Maps
import Navigation
import WayfinderCore

/// How the traveler was guided while the localizer was not sure (issue 15, "guided disambiguation"): the
/// share of that time with a directional instruction in force, and every spoken instruction checked against
/// the TRUE pose with the planner's own safety rules (a walk of at least the planner's minimum, clear of
/// walls, stairs landings and doors). The planner only knows the hypotheses; this checks it against truth.
public struct UnsureGuidanceScore: Codable, Sendable, Equatable {
    /// Seconds not localized (with a navigator running).
    public var unsureSeconds: Double
    /// Seconds of those with a directional exploratory instruction in force (not "keep walking slowly").
    public var directedSeconds: Double
    /// Directional instructions spoken.
    public var spokenInstructions: Int
    /// Of those, instructions that would lead into a wall, onto stairs or through a door from the true pose:
    /// less than `safeWalkMeters` of free walking under the planner's clearance rules.
    public var unsafeInstructions: Int
    /// Each unsafe instruction: when it was spoken, what it said and how far the true pose could walk.
    public var unsafeMoments: [UnsafeMoment]

    /// One instruction that was unsafe from the true pose (`wayfinder eval --explain` lists them).
    public struct UnsafeMoment: Codable, Sendable, Equatable {
        /// Time of the spoken instruction, seconds on the trace's clock.
        public var t: Double
        /// The instruction (`ExploratoryAction` raw value).
        public var action: String
        /// Free walking that instruction leaves from the true pose, meters (< `safeWalkMeters`).
        public var freeWalkMeters: Double
    }

    /// Free walking an instruction must leave from the true pose, meters (the planner asks 1 m more).
    public static let safeWalkMeters = 2.0

    /// Scores a trace against the truth on `building`.
    public init(trace: [TraceRecord], truth: TruthTrack, building: Building) {
        unsureSeconds = 0
        directedSeconds = 0
        spokenInstructions = 0
        unsafeInstructions = 0
        unsafeMoments = []
        let planner = DisambiguationPlanner(building: building)
        for (i, r) in trace.enumerated() {
            let dt = i + 1 < trace.count ? trace[i + 1].t - r.t : 0
            if let advice = r.advice {
                unsureSeconds += dt
                if advice != "unsure" { directedSeconds += dt }
            }
            guard let spoken = r.spokenAdvice, let action = ExploratoryAction(rawValue: spoken) else { continue }
            spokenInstructions += 1
            let s = truth.state(at: r.t)
            let truePose = PoseCandidate(weight: 1, floorId: s.floorId, positionInMap: Point2(x: s.x, y: s.y),
                                         headingRad: s.headingRad)
            let free = planner.safeWalkMeters(action, [truePose])
            if free < Self.safeWalkMeters - 1e-9 {
                unsafeInstructions += 1
                unsafeMoments.append(UnsafeMoment(t: r.t, action: spoken, freeWalkMeters: free))
            }
        }
    }
}
