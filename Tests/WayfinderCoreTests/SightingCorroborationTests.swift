import XCTest
import Localizer
import Maps
import SessionFormat
@testable import WayfinderCore

/// Track confirmation of sightings on the VIO plane (`SightingCorroboration`): a sign that stays put is confirmed
/// from its second frame on; one-frame sightings at fresh places are not.
final class SightingCorroborationTests: XCTestCase {
    /// A camera at (east, north) on the VIO plane looking along `yawRad` (CCW from VIO east).
    private func pose(east: Double, north: Double, yawRad: Double) -> CameraPose {
        CameraPose(positionInWorld: (east, 1.4, -north), yawRad: yawRad, pitchRad: 0, rollRad: -Double.pi / 2)
    }

    /// The sighting of a sign at (signEast, signNorth) from a camera at (east, north) looking along `yawRad`.
    private func sighting(of signEast: Double, _ signNorth: Double, from east: Double, _ north: Double, yawRad: Double,
                          kind: String = "exit", score: Double = 1, text: String? = nil) -> SignSighting {
        let dx = signEast - east, dy = signNorth - north
        return SignSighting(kind: kind, rangeMeters: hypot(dx, dy), bearingRad: atan2(dy, dx) - yawRad, score: score, text: text)
    }

    func testASignThatStaysPutIsConfirmedFromItsSecondFrameWhileTheCameraWalksAndTurns() {
        var rule = SightingCorroboration()
        let factor = rule.parameters.uncorroboratedScoreFactor
        XCTAssertLessThan(factor, 1)
        // Walking east at 1.2 m/s past a sign at (10, 1.5), the camera swinging +-0.3 rad; 10 Hz.
        for i in 0..<10 {
            let t = 0.1 * Double(i), east = 1.2 * t, yaw = 0.3 * sin(Double(i))
            let out = rule.corroborate([sighting(of: 10, 1.5, from: east, 0, yawRad: yaw, score: 0.9)],
                                       t: t, pose: pose(east: east, north: 0, yawRad: yaw))
            XCTAssertEqual(out[0].score, i == 0 ? 0.9 * factor : 0.9, accuracy: 1e-12, "frame \(i)")
        }
    }

    func testOneFrameSightingsAtFreshPlacesAreNeverConfirmed() {
        var rule = SightingCorroboration()
        // A standing camera; each frame a "sign" 4 m further round a circle of radius 6 m (24 degrees apart).
        for i in 0..<10 {
            let a = 0.4 * Double(i) - 1.8
            let out = rule.corroborate([sighting(of: 6 * cos(a), 6 * sin(a), from: 0, 0, yawRad: 0)],
                                       t: 0.1 * Double(i), pose: pose(east: 0, north: 0, yawRad: 0))
            XCTAssertEqual(out[0].score, rule.parameters.uncorroboratedScoreFactor, accuracy: 1e-12, "frame \(i)")
        }
    }

    func testTheGateGrowsWithRange() {
        // Two frames 1.2 m apart in position measure a sign at 10 m: 2.4 m apart passes the gate at 10 m
        // (0.5 + 0.3 x 10 = 3.5 m), 4 m apart does not.
        for (offset, confirmed) in [(2.4, true), (4.0, false)] {
            var rule = SightingCorroboration()
            // Walking: 0.12 m between the frames (a standing camera's repeats are weighed down, below).
            _ = rule.corroborate([sighting(of: 10, 0, from: 0, 0, yawRad: 0)], t: 0, pose: pose(east: 0, north: 0, yawRad: 0))
            let out = rule.corroborate([sighting(of: 10, offset, from: 0.12, 0, yawRad: 0)], t: 0.1,
                                       pose: pose(east: 0.12, north: 0, yawRad: 0))
            XCTAssertEqual(out[0].score == 1, confirmed, "offset \(offset) m")
        }
    }

    func testOnlyAnEarlierFrameOfTheSameKindWithinTheWindowConfirms() {
        let p = pose(east: 0, north: 0, yawRad: 0)
        let exit = sighting(of: 5, 0, from: 0, 0, yawRad: 0)
        let restroom = sighting(of: 5, 0, from: 0, 0, yawRad: 0, kind: "restroom")
        var rule = SightingCorroboration()
        // Two sightings of one frame do not confirm each other.
        XCTAssertEqual(rule.corroborate([exit, exit], t: 0, pose: p).map(\.score), [0.25, 0.25])
        // Another kind at the same place does not confirm.
        XCTAssertEqual(rule.corroborate([restroom], t: 0.1, pose: p)[0].score, 0.25, accuracy: 1e-12)
        // The window: 1 s after the last exit sighting still confirms, 1.5 s after does not.
        XCTAssertEqual(rule.corroborate([exit], t: 1.0, pose: p)[0].score, 1, accuracy: 1e-12)
        XCTAssertEqual(rule.corroborate([exit], t: 2.5, pose: p)[0].score, 0.25, accuracy: 1e-12)
    }

    func testAReadLegendKeepsItsScoreAndResetForgets() {
        let p = pose(east: 0, north: 0, yawRad: 0)
        var rule = SightingCorroboration()
        let placard = sighting(of: 2, 1, from: 0, 0, yawRad: 0, kind: "placard", score: 0.8, text: "402")
        XCTAssertEqual(rule.corroborate([placard], t: 0, pose: p)[0].score, 0.8, accuracy: 1e-12)
        _ = rule.corroborate([sighting(of: 5, 0, from: 0, 0, yawRad: 0)], t: 0.1, pose: p)
        rule.reset()
        XCTAssertEqual(rule.corroborate([sighting(of: 5, 0, from: 0, 0, yawRad: 0)], t: 0.2, pose: p)[0].score, 0.25,
                       accuracy: 1e-12)
    }

    func testUnweighedFramesPassScoresThroughButStillConfirmTheNext() {
        // While localized (a lock given, here one that explains the sighting) an uncorroborated sighting is not
        // weighed: the score passes as measured, and the position is kept.
        var rule = SightingCorroboration()
        let p = pose(east: 0, north: 0, yawRad: 0)
        let lock = SightingCorroboration.Lock(positionInMap: Point2(0, 0), headingRad: 0,
                                              signs: [Sign(id: "e", kind: "exit", position: Point2(5, 0), facing: Point2(-1, 0),
                                                           widthMeters: 0.3, heightMeters: 0.15)])
        XCTAssertEqual(rule.corroborate([sighting(of: 5, 0, from: 0, 0, yawRad: 0, score: 0.9)], t: 0, pose: p,
                                        lock: lock)[0].score, 0.9)
        XCTAssertEqual(rule.corroborate([sighting(of: 5, 0.3, from: 0.1, 0, yawRad: 0, score: 0.9)], t: 0.1,
                                        pose: pose(east: 0.1, north: 0, yawRad: 0))[0].score,
                       0.9, "confirmed by the unweighed frame")
        XCTAssertEqual(rule.corroborate([sighting(of: -5, 0, from: 0, 0, yawRad: 0, score: 0.9)], t: 0.2, pose: p)[0].score,
                       0.9 * 0.25, accuracy: 1e-12, "a fresh place")
    }

    /// A standing camera sees one sign with the same errors frame after frame: while not localized its repeats
    /// count at `stationaryRepeatScoreFactor` of their score, one a second in full; walking at 0.6 m/s (6 cm a
    /// frame) every corroborated sighting counts in full; localized, the rule is off; factor 1 turns it off.
    func testAStandingCameraCountsOneObjectOnceASecond() {
        var rule = SightingCorroboration()
        let repeatFactor = rule.parameters.stationaryRepeatScoreFactor, first = rule.parameters.uncorroboratedScoreFactor
        XCTAssertLessThan(repeatFactor, 1)
        var full: [Int] = []
        for i in 0..<25 {
            // Standing at the origin, swaying 2 cm; the sign 5 m ahead.
            let east = 0.02 * sin(Double(i)), t = 0.1 * Double(i)
            let out = rule.corroborate([sighting(of: 5, 0, from: east, 0, yawRad: 0, score: 0.8)], t: t,
                                       pose: pose(east: east, north: 0, yawRad: 0))
            if i == 0 { XCTAssertEqual(out[0].score, 0.8 * first, accuracy: 1e-12) }
            else if abs(out[0].score - 0.8) < 1e-12 { full.append(i) }
            else { XCTAssertEqual(out[0].score, 0.8 * repeatFactor, accuracy: 1e-12, "frame \(i)") }
        }
        XCTAssertEqual(full, [10, 20])
        // Walking at 0.6 m/s past the sign: every corroborated frame in full.
        var walking = SightingCorroboration()
        for i in 0..<10 {
            let east = 0.06 * Double(i), t = 0.1 * Double(i)
            let out = walking.corroborate([sighting(of: 5, 1, from: east, 0, yawRad: 0, score: 0.8)], t: t,
                                          pose: pose(east: east, north: 0, yawRad: 0))
            XCTAssertEqual(out[0].score, i == 0 ? 0.8 * first : 0.8, accuracy: 1e-12, "frame \(i)")
        }
        // Localized: as measured.
        var locked = SightingCorroboration()
        let lock = SightingCorroboration.Lock(positionInMap: Point2(0, 0), headingRad: 0,
                                              signs: [Sign(id: "e", kind: "exit", position: Point2(5, 0), facing: Point2(-1, 0),
                                                           widthMeters: 0.3, heightMeters: 0.15)])
        for i in 0..<5 {
            let out = locked.corroborate([sighting(of: 5, 0, from: 0, 0, yawRad: 0, score: 0.8)], t: 0.1 * Double(i),
                                         pose: pose(east: 0, north: 0, yawRad: 0), lock: lock)
            XCTAssertEqual(out[0].score, 0.8, accuracy: 1e-12)
        }
        // Factor 1: off.
        var parameters = SightingCorroboration.Parameters()
        parameters.stationaryRepeatScoreFactor = 1
        var off = SightingCorroboration(parameters: parameters)
        for i in 0..<5 {
            let out = off.corroborate([sighting(of: 5, 0, from: 0, 0, yawRad: 0, score: 0.8)], t: 0.1 * Double(i),
                                      pose: pose(east: 0, north: 0, yawRad: 0))
            XCTAssertEqual(out[0].score, i == 0 ? 0.8 * first : 0.8, accuracy: 1e-12)
        }
    }

    func testWhileLockedAnObjectTheLockDoesNotExplainCountsOncePerMeterWalked() {
        // Locked, walking east at 0.12 m per frame past a look-alike at (6, 2) where the map has no sign: it counts
        // on its first frame, then again only once the camera has moved 1 m since it last counted (score 0 in
        // between). With a map sign there (the lock explains it), every frame counts.
        for (signs, everyFrame) in [([Sign](), false),
                                    ([Sign(id: "e", kind: "exit", position: Point2(6, 2.3), facing: Point2(-1, 0),
                                           widthMeters: 0.3, heightMeters: 0.15)], true)] {
            var rule = SightingCorroboration()
            var counted: [Int] = []
            for i in 0..<20 {
                let east = 0.12 * Double(i)
                // The map frame is the VIO frame here (a lock that is right).
                let lock = SightingCorroboration.Lock(positionInMap: Point2(east, 0), headingRad: 0, signs: signs)
                let out = rule.corroborate([sighting(of: 6, 2, from: east, 0, yawRad: 0)], t: 0.1 * Double(i),
                                           pose: pose(east: east, north: 0, yawRad: 0), lock: lock)
                if out[0].score == 1 { counted.append(i) } else { XCTAssertEqual(out[0].score, 0) }
            }
            XCTAssertEqual(counted, everyFrame ? Array(0..<20) : [0, 9, 18], "signs \(signs.count)")
        }
    }

    func testFactorOneLeavesEverySightingAsMeasured() {
        var parameters = SightingCorroboration.Parameters()
        parameters.uncorroboratedScoreFactor = 1
        var rule = SightingCorroboration(parameters: parameters)
        let s = [sighting(of: 5, 2, from: 0, 0, yawRad: 0.2, score: 0.7)]
        let out = rule.corroborate(s, t: 0, pose: pose(east: 0, north: 0, yawRad: 0.2))
        XCTAssertEqual(out[0].score, 0.7)
    }

    func testANonFiniteSightingPassesThroughAndIsNotRemembered() {
        var rule = SightingCorroboration()
        let p = pose(east: 0, north: 0, yawRad: 0)
        let bad = SignSighting(kind: "exit", rangeMeters: .nan, bearingRad: 0, score: 1)
        XCTAssertTrue(rule.corroborate([bad], t: 0, pose: p)[0].rangeMeters.isNaN)
        XCTAssertEqual(rule.corroborate([sighting(of: 5, 0, from: 0, 0, yawRad: 0)], t: 0.1, pose: p)[0].score, 0.25,
                       accuracy: 1e-12)
    }

    func testAnObjectSeenAgainKeepsItsTrackIdAndWhereItsEarlierSightingsPutIt() {
        var rule = SightingCorroboration()
        // A sign at (10, 1.5) seen while walking east, then nothing for 2 s (out of view), then again.
        var ids: [UInt32] = []
        for i in 0..<5 {
            let t = 0.1 * Double(i), east = 1.2 * t
            let out = rule.corroborate([sighting(of: 10, 1.5, from: east, 0, yawRad: 0.1)], t: t,
                                       pose: pose(east: east, north: 0, yawRad: 0.1))
            let track = try! XCTUnwrap(out[0].track)
            ids.append(track.id)
            if i == 0 {
                XCTAssertNil(track.earlierRangeMeters)
            } else {
                // The earlier sightings put it exactly at the sign: seen from here, the sign's own range and bearing.
                XCTAssertEqual(try! XCTUnwrap(track.earlierRangeMeters), hypot(10 - east, 1.5), accuracy: 1e-9)
                XCTAssertEqual(try! XCTUnwrap(track.earlierBearingRad), atan2(1.5, 10 - east) - 0.1, accuracy: 1e-9)
            }
        }
        XCTAssertEqual(Set(ids).count, 1)
        let later = rule.corroborate([sighting(of: 10, 1.5, from: 3, 0, yawRad: 0)], t: 2.4, pose: pose(east: 3, north: 0, yawRad: 0))
        XCTAssertEqual(later[0].track?.id, ids[0], "seen again within trackMemorySeconds: the same object")
        // Another sign 5 m away, and the first one after more than trackMemorySeconds: new objects.
        let other = rule.corroborate([sighting(of: 15, 1.5, from: 3, 0, yawRad: 0)], t: 2.5, pose: pose(east: 3, north: 0, yawRad: 0))
        XCTAssertNotEqual(other[0].track?.id, ids[0])
        let muchLater = rule.corroborate([sighting(of: 10, 1.5, from: 4, 0, yawRad: 0)], t: 6.0, pose: pose(east: 4, north: 0, yawRad: 0))
        XCTAssertNotEqual(muchLater[0].track?.id, ids[0])
        XCTAssertNotEqual(muchLater[0].track?.id, other[0].track?.id)
    }

    func testAReadLegendAndAZeroMemoryCarryNoTrack() {
        var rule = SightingCorroboration()
        let read = rule.corroborate([sighting(of: 5, 1, from: 0, 0, yawRad: 0, kind: "placard", text: "102")], t: 0,
                                    pose: pose(east: 0, north: 0, yawRad: 0))
        XCTAssertNil(read[0].track, "a read room number identifies its sign")
        var parameters = SightingCorroboration.Parameters()
        parameters.trackMemorySeconds = 0
        var untracked = SightingCorroboration(parameters: parameters)
        let out = untracked.corroborate([sighting(of: 5, 1, from: 0, 0, yawRad: 0)], t: 0, pose: pose(east: 0, north: 0, yawRad: 0))
        XCTAssertNil(out[0].track)
    }
}
