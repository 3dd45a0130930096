import Foundation
import Maps

/// What the walker is doing at a frame.
public enum WalkPhase: String, Codable, Sendable {
    /// Standing still before setting off or after arriving.
    case standing
    /// Walking at the (varying) preferred speed: the cruise speed stays within the walker's speed bounds.
    case cruising
    /// Speeding up or slowing down (setting off, before a pause, a turn-around or the destination, at a corner).
    case changingSpeed
    /// A pause mid-walk.
    case paused
    /// Turning in place (after a wrong turn, before setting off).
    case turning
    /// In the elevator or on the stairs between floors.
    case changingFloor
}

/// The walking body at one frame (map frame of `floorId`).
struct BodyState: Sendable {
    var t: Double
    var floorId: String
    /// Camera position on the floor plan, meters.
    var position: Point2
    /// Height of the floor the walker stands on above the building reference, meters (interpolated between
    /// floors while changing floor).
    var floorElevation: Double
    /// Direction the body faces, radians CCW from +x.
    var headingRad: Double
    /// Speed along the path, m/s.
    var speed: Double
    /// Step phase, radians (advances at the step frequency while walking).
    var stepPhaseRad: Double
    var phase: WalkPhase
}

/// Generates the walking body's trajectory over the walk segments at a fixed frame rate. The model is a
/// kinematic walker (no dynamics beyond acceleration limits): speed follows a preferred speed with slow
/// Ornstein-Uhlenbeck variation, bounded acceleration, anticipation of stops (v <= sqrt(2 a d)), Poisson
/// pauses; the body turns at a bounded rate towards the path's direction a short distance ahead; a lateral
/// offset (sway at half the step frequency plus slow wander) moves the walker off the centre line when,
/// and only as far as, the walls allow.
struct WalkerModel {
    let parameters: WalkerParameters
    let geometry: [String: FloorGeometry]
    /// Elevation of each floor, meters.
    let elevations: [String: Double]
    /// Frame rate, Hz.
    let rateHz: Double
    /// Frame period, seconds.
    var dt: Double { 1 / rateHz }

    /// Safety cap on the number of frames of one walk (4 hours): the walk stops there and the simulator reports
    /// an error instead of looping forever on a degenerate map or parameters.
    static func maxFrames(rateHz: Double) -> Int { Int(4 * 3600 * rateHz) }

    func run(segments: [WalkSegment], startHeading: Double, rng: inout SeededRandom) -> [BodyState] {
        let p = parameters
        var states: [BodyState] = []
        var heading = startHeading
        var stepPhase = 0.0
        let preferred = rng.uniform(p.preferredSpeedRange.lowerBound, p.preferredSpeedRange.upperBound)
        var speedOU = OrnsteinUhlenbeck(sigma: p.speedVariationSigma, tauSeconds: p.speedVariationTauSeconds, rng: &rng)
        var wander = OrnsteinUhlenbeck(sigma: p.lateralWanderSigmaMeters, tauSeconds: p.lateralWanderTauSeconds, rng: &rng)
        let cap = Self.maxFrames(rateHz: rateHz)
        var nextPauseAt = rng.exponential(ratePerSecond: p.pausesPerMeter)   // meters walked
        var walked = 0.0
        var lastPosition: Point2?

        func emit(_ floorId: String, _ pos: Point2, _ elev: Double, _ v: Double, _ phase: WalkPhase) {
            let t = Double(states.count) / rateHz   // from the frame index: no accumulated rounding
            states.append(BodyState(t: t, floorId: floorId, position: pos, floorElevation: elev, headingRad: heading,
                                    speed: v, stepPhaseRad: stepPhase, phase: phase))
            lastPosition = pos
        }
        func turnTowards(_ target: Double) -> Double {
            let err = wrapAngle(target - heading)
            let maxStep = p.maxTurnRateRadPerSecond * dt
            // First-order approach with a rate limit: smooth at small errors, bounded at large ones.
            let step = max(-maxStep, min(maxStep, err * min(1, dt * 6)))
            heading = wrapAngle(heading + step)
            return abs(wrapAngle(target - heading))
        }

        var firstLegFloor: String?
        var firstLegStart: Point2?
        for seg in segments {
            if case .leg(let leg) = seg { firstLegFloor = leg.floorId; firstLegStart = leg.points.first; break }
            if case .vertical(let f, _, let fp, _, _, _, _) = seg { firstLegFloor = f; firstLegStart = fp; break }
        }
        var currentElevation = firstLegFloor.flatMap { elevations[$0] } ?? 0
        if let f = firstLegFloor, let s = firstLegStart {
            let n = Int((p.standBeforeSeconds / dt).rounded())
            for _ in 0..<max(1, n) { emit(f, s, currentElevation, 0, .standing) }
        }

        for seg in segments {
            switch seg {
            case .vertical(let fromFloor, let toFloor, let fromPos, let toPos, let fromElev, let toElev, let kind):
                let duration = kind == .elevator ? p.elevatorSeconds : max(3, abs(toElev - fromElev) / p.stairsVerticalMetersPerSecond)
                let n = max(2, Int((duration / dt).rounded()))
                for k in 0..<n {
                    let f = Double(k) / Double(n - 1)
                    // Elevator: waits 60 % of the time, rides 40 % (smooth step); stairs: linear climb.
                    var g: Double
                    if kind == .elevator {
                        let r = max(0, min(1, (f - 0.6) / 0.4)); g = r * r * (3 - 2 * r)
                    } else { g = f }
                    g = max(0, min(1, g))
                    currentElevation = fromElev + g * (toElev - fromElev)
                    let onTo = g >= 0.5
                    emit(onTo ? toFloor : fromFloor, onTo ? toPos : fromPos, currentElevation, 0, .changingFloor)
                }
                currentElevation = toElev
            case .leg(let leg):
                let geo = geometry[leg.floorId] ?? FloorGeometry(walls: [])
                currentElevation = elevations[leg.floorId] ?? currentElevation
                var hint = 0, aheadHint = 0
                var s = 0.0, v = 0.0
                // Turn in place towards the leg's direction first.
                let initial = leg.tangent(at: 0, hint: &hint)
                while abs(wrapAngle(initial - heading)) > radians(25) && states.count < cap {
                    _ = turnTowards(initial)
                    emit(leg.floorId, lastPosition ?? leg.points[0], currentElevation, 0, .turning)
                }
                var pauseLeft = 0.0
                var pausing = false
                let length = leg.length
                while s < length && states.count < cap {
                    let vPref = max(p.minSpeedMetersPerSecond, min(p.maxSpeedMetersPerSecond,
                                                                  preferred + speedOU.step(dt: dt, rng: &rng)))
                    var target = vPref
                    var limited = false
                    let remaining = length - s
                    if !pausing && walked >= nextPauseAt && remaining > 2 && s > 1 { pausing = true; pauseLeft = rng.uniform(p.pauseSecondsRange.lowerBound, p.pauseSecondsRange.upperBound) }
                    if pausing { target = 0; limited = true }
                    // Heading error ahead: slow for sharp corners (never below the cruise floor unless nearly
                    // turning around).
                    let aheadDir = leg.tangent(at: min(length, s + 0.4), hint: &aheadHint)
                    let err = abs(wrapAngle(aheadDir - heading))
                    if err > radians(60) { target = min(target, p.minSpeedMetersPerSecond); limited = true }
                    if err > radians(100) { target = min(target, vPref * max(0, cos(err - radians(100)) * 0.3)); limited = true }
                    let vStop = (2 * p.decelerationMetersPerSecond2 * remaining).squareRoot()
                    if vStop < target { target = vStop; limited = true }
                    if target > v { v = min(target, v + p.accelerationMetersPerSecond2 * dt) } else { v = max(target, v - p.decelerationMetersPerSecond2 * dt) }
                    v = min(v, vStop)
                    let phase: WalkPhase
                    if pausing && v <= 1e-9 {
                        v = 0
                        pauseLeft -= dt
                        if pauseLeft <= 0 { pausing = false; nextPauseAt = walked + rng.exponential(ratePerSecond: p.pausesPerMeter) }
                        phase = .paused
                    } else {
                        phase = (!limited && abs(v - vPref) < 1e-9) ? .cruising : .changingSpeed
                    }
                    s += v * dt
                    walked += v * dt
                    if length - s < 0.01 && v < 0.05 { s = length }
                    s = min(s, length)
                    // Heading follows the path a short distance ahead.
                    let dir = leg.tangent(at: min(length, s + 0.25), hint: &aheadHint)
                    _ = turnTowards(dir)
                    if v > 0.1 {
                        let f = p.stepFrequencyHz * (v / 1.1).squareRoot()
                        stepPhase = (stepPhase + 2 * Double.pi * f * dt).truncatingRemainder(dividingBy: 2 * Double.pi * 1000)
                    }
                    // Position: centre line plus lateral offset faded in and out at the leg's ends.
                    let centre = leg.position(at: s, hint: &hint)
                    let tang = leg.tangent(at: s, hint: &hint)
                    let fade = min(1, s / 1.0, (length - s) / 1.0)
                    // The wander only evolves while walking: a person standing still does not drift sideways.
                    let lateral = v > 0.1 ? wander.step(dt: dt, rng: &rng) : wander.value
                    let offset = fade * (lateral + p.swayAmplitudeMeters * sin(stepPhase / 2))
                    let n = Point2(-sin(tang), cos(tang))
                    var pos = centre
                    for scale in [1.0, 0.5, 0.25] {
                        let cand = Point2(centre.x + scale * offset * n.x, centre.y + scale * offset * n.y)
                        if geo.segmentCrossesWall(centre, cand) { continue }
                        if geo.clearance(at: cand, maxMeters: p.wallClearanceMeters + 0.01) < p.wallClearanceMeters { continue }
                        if let last = lastPosition, geo.segmentCrossesWall(last, cand) { continue }
                        pos = cand
                        break
                    }
                    emit(leg.floorId, pos, currentElevation, v, phase)
                }
            }
        }
        if let last = states.last {
            let n = Int((p.standAfterSeconds / dt).rounded())
            for _ in 0..<max(1, n) { emit(last.floorId, last.position, currentElevation, 0, .standing) }
        }
        return states
    }
}
