import Foundation
import Localizer
import Maps
import SessionFormat

/// Track confirmation of sign sightings in the odometry frame: a sighting counts in full only when an earlier
/// detector frame saw a sign of the same kind at about the same place of the VIO plane.
///
/// Why: a real sign stays where it is while the traveler walks, so the detector sees it again and again at one
/// point of the VIO floor plane (ARKit's drift over a second is centimetres). A false positive of a detector whose
/// score does not tell it apart (a poster or a red light taken for an Exit sign in one frame, issue 16) lands at a
/// fresh place each time. The localizer scores each frame on its own, so a run of such one-frame sightings can
/// happen to fit a look-alike corridor's sign and lock the filter there (docs/benchmarks.md, "Twenty-third stop":
/// conv-4-06 behind the real-photo cascade with uninformative scores). This is the two-detection confirmation of
/// radar track initiation (an M-of-N rule; Blackman, "Multiple-Target Tracking with Radar Applications", 1986),
/// applied before the map is consulted: it needs no hypothesis, only the VIO poses.
///
/// An uncorroborated sighting is not dropped: its score is multiplied by `uncorroboratedScoreFactor`, so the
/// localizer weighs it more like clutter (sensors/sign_measurement_model: clutter share 1 - 0.9 score). A false
/// positive that repeats at one place (a poster seen for seconds) is corroborated like a sign, as before. A
/// sighting whose legend was read (a room number) keeps its score: the reading is an independent check of its own.
/// Uncorroborated sightings are weighed only while the localizer is not localized (no `lock` given): that is when
/// one-frame sightings can build a wrong lock, while a lock is guarded by its hysteresis, and the first sighting of
/// a sign that refutes a wrong lock must count at once (behind the cascade's -25 % range bias, quartering the
/// refuting sightings held skeri-2's wrong lock 0.5 m longer). While localized, the other half: an object seen
/// again (a corroborated sighting) that the locked pose does not explain counts once per
/// `unexplainedObjectRecountMeters` walked, not on every frame, with score 0 in between: one object's frames are not
/// independent evidence, and a look-alike that stays put (a poster seen for a second and a half) otherwise outweighs
/// the whole lock. A sign that refutes a wrong lock still counts on its first frame and once per meter after it.
/// The defaults are the measured ones (docs/benchmarks.md, "Twenty-fourth stop"). And while not localized, an
/// object's sightings repeated from where the camera stood count at `stationaryRepeatScoreFactor` (a standing
/// camera repeats the same errors; "Twenty-seventh stop").
/// Each sighting also carries its object's track (`SignSighting.track`: the id of the object it sees again within
/// `trackMemorySeconds`, and where that object's earlier sightings put it), for the localizer's tracked-object
/// evidence (LocalizerCore pf/track_evidence, docs/localizer.md "Tracked objects"; on unless switched off).
/// Written by hand: no library does this for a stream of range-bearing sightings.
public struct SightingCorroboration: Sendable {
    /// The rule's settings.
    public struct Parameters: Sendable, Equatable {
        /// How far back an earlier sighting can corroborate, seconds (10 detector frames at the phone's 10 Hz).
        public var windowSeconds = 1.0
        /// Gate between the two sightings' sign positions on the VIO plane: `gateBaseMeters` plus
        /// `gateRangeFraction` of the larger range, meters (two frames' independent range errors differ by about
        /// 0.15 of the range at the real detectors' 0.08-0.11 log-normal spread; bearing errors add little).
        public var gateBaseMeters = 0.5
        /// See `gateBaseMeters`.
        public var gateRangeFraction = 0.3
        /// Factor on the score of a sighting no earlier frame corroborates (0...1; 1 = the rule is off).
        public var uncorroboratedScoreFactor = 0.25
        /// While localized: a corroborated sighting that the locked pose does not explain (no map sign of its kind
        /// within 1 m + 0.3 x range of where it puts it) counts again only once the camera moved this far on the VIO
        /// plane since its object last counted, meters; in between it passes with score 0 (it still matches its
        /// kind for the localizer's negative information). One object's frames are not independent evidence: eight
        /// sightings of one look-alike in 1.4 s broke a right lock (docs/benchmarks.md, "Twenty-fourth stop").
        /// 0 = off.
        public var unexplainedObjectRecountMeters = 1.0
        /// How long an object is remembered for its track id, seconds: a sighting within the gate of an earlier one of
        /// its kind from the last `trackMemorySeconds` sees the same object and carries its `SignSighting.track`, so
        /// the localizer counts the object's sightings as one object's (pf/track_evidence: what a look-alike watched for
        /// seconds can say against a pose is bounded). 3 s, the localizer's "track.forget_s": a sign passed out of view
        /// for longer is taken as a new object. 0 = no track ids (every sighting counts on its own).
        public var trackMemorySeconds = 3.0
        /// While not localized: a corroborated sighting of an object whose last full-weight sighting was taken less
        /// than `stationaryRepeatMeters` away on the VIO plane and less than `stationaryRepeatSeconds` ago passes
        /// with its score times `stationaryRepeatScoreFactor`. A camera that stands still sees one object with the
        /// same errors frame after frame (the map's misplaced sign, the detector's reading of that one face), so its
        /// repeats are not independent evidence: at 10 Hz a traveler who paused 3 s counted 30 sightings of one
        /// misplaced sign and the filter locked on the mirror corridor whose sign fitted them a little better
        /// (docs/benchmarks.md "Twenty-seventh stop", conv-3-05 behind survey-rough's first form). Walking at
        /// 0.5 m/s or more the camera moves 5 cm between the phone's 10 Hz detector frames and every sighting counts
        /// in full; standing, one a second per object. 1 = off (`--repeat-factor 1`).
        public var stationaryRepeatScoreFactor = 0.25
        /// See `stationaryRepeatScoreFactor`, meters.
        public var stationaryRepeatMeters = 0.05
        /// See `stationaryRepeatScoreFactor`, seconds.
        public var stationaryRepeatSeconds = 1.0
        /// The defaults.
        public init() {}
    }

    /// Where the camera stood on the VIO plane (meters) and when (seconds): the vantage from which an object's
    /// sightings last counted.
    private struct Vantage: Sendable {
        var east: Double
        var north: Double
        var t: Double

        /// Horizontal distance from this vantage to `camera`, meters.
        func distanceMeters(to camera: (east: Double, north: Double)) -> Double {
            hypot(camera.east - east, camera.north - north)
        }
    }

    /// One earlier sighting: its time, kind and where it put the sign on the VIO plane.
    private struct Placed: Sendable {
        var t: Double
        var kind: String
        var east: Double
        var north: Double
        var rangeMeters: Double
        /// The object's track id.
        var trackId: UInt32
        /// Where the camera stood when this object's sightings last counted (the recount rule while localized).
        var counted: Vantage
        /// Where the camera stood, and when, for this object's last full-weight sighting (the stationary repeat
        /// rule while not localized).
        var weighed: Vantage
    }

    /// The locked pose a frame's sightings are checked against (`corroborate`).
    public struct Lock: Sendable {
        /// Camera position in the map frame, meters.
        public var positionInMap: Point2
        /// Camera heading in the map frame, radians CCW from map x.
        public var headingRad: Double
        /// The signs of the locked floor.
        public var signs: [Sign]
        /// Creates a lock context.
        public init(positionInMap: Point2, headingRad: Double, signs: [Sign]) {
            self.positionInMap = positionInMap; self.headingRad = headingRad; self.signs = signs
        }

        /// Whether a map sign of `s`'s kind stands where `s` puts it from this pose.
        func explains(_ s: SignSighting) -> Bool {
            let x = positionInMap.x + s.rangeMeters * cos(headingRad + s.bearingRad)
            let y = positionInMap.y + s.rangeMeters * sin(headingRad + s.bearingRad)
            let gate = 1.0 + 0.3 * s.rangeMeters
            return signs.contains { $0.kind == s.kind && hypot($0.position.x - x, $0.position.y - y) <= gate }
        }
    }

    /// The settings.
    public let parameters: Parameters
    /// The sightings of the last `windowSeconds` (or `trackMemorySeconds`, the longer), oldest first.
    private var recent: [Placed] = []
    /// The last track id given (ids are never reused: the localizer may still hold an old one).
    private var lastTrackId: UInt32 = 0

    /// A rule with `parameters`.
    public init(parameters: Parameters = Parameters()) {
        self.parameters = parameters
    }

    /// Forgets every earlier sighting (the VIO frame was reset or tracking lost: old positions are in another frame).
    public mutating func reset() {
        recent.removeAll()
    }

    /// The sightings of the detector frame at `t` taken from the camera at `pose`: with no `lock` (the localizer is
    /// not localized), each uncorroborated one with its score scaled down; with `lock` (it is localized there), each
    /// uncorroborated one as measured and a corroborated one the lock does not explain with score 0 unless its
    /// object is due a recount (`unexplainedObjectRecountMeters`). Each unread sighting gets its object's `track`
    /// (`trackMemorySeconds` > 0). Remembers them for the frames to come either way. Sightings of the same
    /// frame do not corroborate each other. A non-finite pose or sighting is passed through unchanged and not
    /// remembered.
    public mutating func corroborate(_ sightings: [SignSighting], t: Double, pose: CameraPose,
                                     lock: Lock? = nil) -> [SignSighting] {
        let memory = max(parameters.windowSeconds, parameters.trackMemorySeconds)
        recent.removeAll { !(t - $0.t <= memory) || $0.t > t }
        guard parameters.uncorroboratedScoreFactor < 1 || parameters.unexplainedObjectRecountMeters > 0
            || parameters.trackMemorySeconds > 0 || parameters.stationaryRepeatScoreFactor < 1 else { return sightings }
        let factor = lock == nil ? parameters.uncorroboratedScoreFactor : 1
        let camera = pose.positionInVIOPlane
        let yaw = pose.yawInVIOPlaneRad
        var placedNow: [Placed] = []
        var out = sightings
        for i in out.indices {
            let s = out[i]
            // Bearing is positive to the left, i.e. counter-clockwise like the VIO yaw.
            let east = camera.east + s.rangeMeters * cos(yaw + s.bearingRad)
            let north = camera.north + s.rangeMeters * sin(yaw + s.bearingRad)
            guard east.isFinite, north.isFinite, s.rangeMeters.isFinite else { continue }
            // By kind alone: a placard whose legend was read on one frame and not on the next is one sign.
            func sameObject(_ earlier: Placed) -> Bool {
                guard earlier.kind == s.kind else { return false }
                let gate = parameters.gateBaseMeters + parameters.gateRangeFraction * max(earlier.rangeMeters, s.rangeMeters)
                return hypot(earlier.east - east, earlier.north - north) <= gate
            }
            let match = recent.last { t - $0.t <= parameters.windowSeconds && sameObject($0) }
            let corroborated = match != nil
            let track: SightingTrack
            if let earlier = recent.last(where: { t - $0.t <= parameters.trackMemorySeconds && sameObject($0) }) {
                // Where the object's earlier sightings put it (their mean on the VIO plane), seen from here.
                let mine = recent.filter { $0.trackId == earlier.trackId }
                let e = mine.map(\.east).reduce(0, +) / Double(mine.count)
                let n = mine.map(\.north).reduce(0, +) / Double(mine.count)
                track = SightingTrack(id: earlier.trackId, earlierRangeMeters: hypot(e - camera.east, n - camera.north),
                                      earlierBearingRad: remainder(atan2(n - camera.north, e - camera.east) - yaw, 2 * .pi))
            } else {
                lastTrackId &+= 1
                if lastTrackId == 0 { lastTrackId = 1 }
                track = SightingTrack(id: lastTrackId)
            }
            // A read legend (a room number) identifies its sign: its sightings are not a look-alike's.
            if parameters.trackMemorySeconds > 0 && s.text == nil { out[i].track = track }
            let here = Vantage(east: camera.east, north: camera.north, t: t)
            var counted = here
            if let m = match, let lock, parameters.unexplainedObjectRecountMeters > 0,
               m.counted.distanceMeters(to: camera) < parameters.unexplainedObjectRecountMeters, !lock.explains(s) {
                counted = m.counted
                out[i].score = 0
            }
            // A legend read on the sign (a room number) is a second, independent check of its own: a poster or a
            // light is not taken for a placard whose number the map has.
            if !corroborated && s.text == nil { out[i].score = s.score * factor }
            // The same object from where the camera stood a moment ago: a repeat, not new evidence.
            var weighed = here
            if let m = match, lock == nil, s.text == nil, parameters.stationaryRepeatScoreFactor < 1,
               m.weighed.distanceMeters(to: camera) < parameters.stationaryRepeatMeters,
               t - m.weighed.t < parameters.stationaryRepeatSeconds {
                weighed = m.weighed
                out[i].score = s.score * parameters.stationaryRepeatScoreFactor
            }
            placedNow.append(Placed(t: t, kind: s.kind, east: east, north: north, rangeMeters: s.rangeMeters,
                                    trackId: track.id, counted: counted, weighed: weighed))
        }
        recent.append(contentsOf: placedNow)
        return out
    }
}
