// The navigator end to end on ASCII fixtures: simulated walks at 1.2 m/s with 10 Hz updates, checking
// what is said and felt, and when.
import Foundation
import Maps
import XCTest
@testable import Navigation
import TestRandom

final class NavigatorTests: XCTestCase {
    /// a(0,8) to b(16,8), down to c(16,4), east to d(36,4), down to e(36,0); 2 m grid.
    let zigzag = FloorPlanFixture(gridMeters: 2).floor("1", map: """
        a-------b
                |
                c---------d
                          |
                          e
        """).build()

    func testNothingIsSaidWhileTrackingIsLostAndNotLocalized() throws {
        // Tracking lost (the pipeline then hands over no hypotheses): no "Start walking" for 20 s (the phone's
        // tracking prompt asks for the camera); once tracking is back the navigator speaks as before.
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a-----------b").build()
        let nav = try Navigator(building: b, destinationId: "b")
        var spoken: [String] = []
        for k in 0..<200 {
            let input = NavigationInput(t: Double(k) * 0.1, positionInMap: Point2(x: 2, y: 0), floorId: "1", headingRad: 0,
                                        isLocalized: false, confidence: 0.9, trackingLost: true)
            spoken += nav.update(input).compactMap(\.spokenText)
        }
        XCTAssertEqual(spoken, [])
        XCTAssertNil(nav.currentAdvice)
        let back = NavigationInput(t: 20, positionInMap: Point2(x: 2, y: 0), floorId: "1", headingRad: 0, isLocalized: false)
        XCTAssertEqual(nav.update(back).compactMap(\.spokenText), ["Start walking."])
    }

    func testOnlyStartWalkingUntilLocalized() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a-----------b").build()
        let nav = try Navigator(building: b, destinationId: "b")
        var w = Walker(start: Point2(x: 2, y: 0), floorId: "1")
        w.unlocalized(nav, seconds: 5)
        XCTAssertEqual(w.spoken, ["Start walking."])
        XCTAssertEqual(w.haptics, [])
        XCTAssertNil(nav.currentRoute)
        w.unlocalized(nav, seconds: 11)
        XCTAssertEqual(w.spoken, ["Start walking.", "Start walking."], "repeated every 15 s while not localized")
        XCTAssertEqual(w.records.filter { !$0.events.isEmpty }.map(\.input.t), [0, 15].map { Double($0) },
                       "nothing else in between")
        // Localized at 16 s while "Start walking." (15 s, 1.15 s long) still plays: it no longer holds, and the
        // route's first phrase cuts it off at once (AnnouncementPolicy.supersede).
        w.run(nav, [.wait(seconds: 0.3)])
        XCTAssertEqual(w.spoken.last, "Go straight ahead, 10 meters.")
        let first = try XCTUnwrap(w.records.last { !$0.events.isEmpty })
        XCTAssertEqual(first.input.t, 16.0, accuracy: 1e-9)
        XCTAssertTrue(first.events.contains { if case .speak(_, _, true) = $0.event { return true } else { return false } })
        XCTAssertNotNil(nav.currentRoute)
    }

    func testFirstInstructionIsComposedWhenItCanBeSpokenNotWhenQueued() throws {
        // 20 m corridor; the answer to "Where am I" (about 2.5 s; an answer to the traveler is not cut off) is
        // playing when the traveler is localized at 0.1 s. The route's first phrase waits for it, and gives the
        // distance from where the traveler is when it is said (walking east at 1.2 m/s), not from where they
        // were when the route was adopted.
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a--------------------b").build()
        let nav = try Navigator(building: b, destinationId: "b")
        var spoken: [(t: Double, text: String, x: Double)] = []
        for k in 0..<40 {
            let t = Double(k) / 10, x = 3 + 1.2 * t
            let events = nav.update(NavigationInput(t: t, positionInMap: Point2(x: x, y: 0), floorId: "1", headingRad: 0,
                                                    isLocalized: k > 0))
            spoken += events.compactMap(\.spokenText).map { (t, $0, x) }
            if k == 0 { spoken += nav.requestWhereAmI(t: t).compactMap(\.spokenText).map { (t, $0, x) } }
        }
        XCTAssertEqual(spoken.first?.text, "Start walking.")
        XCTAssertEqual(spoken.dropFirst().first?.text, "Location not known yet; keep walking slowly.")
        let depart = try XCTUnwrap(spoken.first { $0.text.hasPrefix("Go straight ahead") })
        XCTAssertGreaterThan(depart.t, 1.0, "it waited for the channel")
        // Said at x = 3 + 1.2 t, 21 - x meters from b (at x 21), rounded to 5 m from 10 m up: at adoption (x 3.12,
        // 17.9 m) it was "20 meters"; by the time it is said (x 4.4, 16.6 m) it is 15.
        let remaining = 21 - depart.x
        XCTAssertEqual(depart.text, "Go straight ahead, \(Navigation.PhraseBook.roundedDistanceMeters(remaining)) meters.")
        XCTAssertNotEqual(depart.text, "Go straight ahead, 20 meters.")
    }

    func testFirstInstructionIsRelativeToTheHeading() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: """
            a--------------------b
                      |
                      |
                      c
            """).build()
        // Mid-corridor at x = 12 (snapped between a and b): the route to a leaves the virtual start node
        // westward, whatever the heading; the phrase depends on the heading.
        let cases: [(Double, String)] = [(0, "Turn around, then go 10 meters."), (.pi, "Go straight ahead, 10 meters."),
                                         (.pi / 2, "Turn left, then go 10 meters."), (-.pi / 2, "Turn right, then go 10 meters.")]
        for (heading, expected) in cases {
            let nav = try Navigator(building: b, destinationId: "a")
            let events = nav.update(NavigationInput(t: 0, positionInMap: Point2(x: 12, y: 3), floorId: "1",
                                                    headingRad: heading, isLocalized: true))
            XCTAssertEqual(events.compactMap(\.spokenText), [expected], "heading \(heading)")
            XCTAssertEqual(nav.currentRoute?.nodeIds, ["a"])
        }
    }

    func testLossOfLocalizationMidRoute() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a-------------------b").build()
        let nav = try Navigator(building: b, destinationId: "b")
        var w = Walker(start: Point2(x: 0, y: 0), floorId: "1")
        w.run(nav, [.walk(to: Point2(x: 3, y: 0))])
        XCTAssertEqual(w.spoken, ["Go straight ahead, 20 meters."])
        w.unlocalized(nav, seconds: 1)  // a flicker: nothing
        XCTAssertEqual(w.spoken.count, 1)
        w.run(nav, [.walk(to: Point2(x: 4, y: 0))])
        w.unlocalized(nav, seconds: 4)  // a real loss: "Start walking." once, after 3 s
        XCTAssertEqual(w.spoken.count, 2)
        XCTAssertEqual(w.spoken.last, "Start walking.")
        let said = try XCTUnwrap(w.records.last { $0.events.contains { $0.spokenText == "Start walking." } })
        XCTAssertEqual(said.input.t - w.records.first { !$0.input.isLocalized && $0.input.t > 3.5 }!.input.t, 3.0, accuracy: 0.05)
        // Back on track: the same route goes on, no re-route.
        w.run(nav, [.walk(to: Point2(x: 20, y: 0))])
        XCTAssertTrue(nav.hasArrived)
        XCTAssertEqual(nav.routeCount, 1)
    }

    func testTurnCuesEndHalfAMeterBeforeEachControlPoint() throws {
        let nav = try Navigator(building: zigzag, destinationId: "e")
        var w = Walker(start: zigzag.nodePosition("a"), floorId: "1", headingRad: 0)
        w.run(nav, [.wait(seconds: 0.1)])
        let route = try XCTUnwrap(nav.currentRoute)
        XCTAssertEqual(kindsList(route.maneuvers), "depart,turnRight,turnLeft,turnRight,arrive")
        w.run(nav, route.points.dropFirst().map { .walk(to: $0.position) })
        XCTAssertTrue(nav.hasArrived)
        // Every turn got its cue, started so that at 1.2 m/s it ends 0.5 m (plus the 0.5 m slack) before the
        // control point: "Turn left now." lasts 1.15 s, 1.38 m, so it starts 2.38 m before.
        let cueRecords = w.records.filter { r in r.events.contains { $0.spokenText?.hasSuffix(" now.") ?? false } }
        XCTAssertEqual(cueRecords.compactMap { $0.events.compactMap(\.spokenText).first }, ["Turn right now.", "Turn left now.", "Turn right now."])
        for r in cueRecords {
            let d = try XCTUnwrap(r.nextTurnDistanceMeters)
            let text = try XCTUnwrap(r.events.compactMap(\.spokenText).first)
            let lasts = 1.2 * nav.policy.estimatedDurationSeconds(text)
            XCTAssertGreaterThanOrEqual(d - lasts, 0.5, "ends at least 0.5 m before the turn")
            XCTAssertLessThanOrEqual(d - lasts, 0.5 + nav.options.cueSchedulingSlackMeters + 0.12,
                                     "and not more than one update earlier")
        }
        XCTAssertEqual(w.haptics, [.turnCue, .turnCue, .turnCue, .arrived])
        XCTAssertEqual(w.spoken, [
            "Go straight ahead, 15 meters.",  // 16 m to b, rounded to 5 m above 10 m
            "In 8 meters, turn right.",
            "Turn right now.",
            // b-c is 4 m: "In 3 meters, turn left." would run into the cue due 2.2 m before c: only the cue.
            "Turn left now.",
            "Continue 20 meters.",
            "In 8 meters, turn right.",
            "Turn right now.",
            "In 3 meters, arrive at e.",
            "Arrived. e is ahead.",
        ])
    }

    func testNoisyEstimatesDoNotFlapOrRaiseFalseAlarms() throws {
        // Localizer noise of 0.3 m and 10 deg (seeded), walking the zigzag: one route, no corrections,
        // every turn cued once, ending (true position, 1.2 m/s) before its control point and starting at
        // most 4 m before it (2.4 m without noise; 0.3 m of position noise also moves the speed estimate).
        for seed in [1, 2, 3, 4, 5, 6, 7, 8, 9, 10] as [UInt64] {
            let nav = try Navigator(building: zigzag, destinationId: "e")
            var w = Walker(start: zigzag.nodePosition("a"), floorId: "1")
            w.positionNoiseMeters = 0.3
            w.headingNoiseRad = 10 * .pi / 180
            w.rng = SplitMix64(seed: seed)
            w.run(nav, [.wait(seconds: 0.1)])
            let route = try XCTUnwrap(nav.currentRoute)
            w.run(nav, route.points.dropFirst().map { .walk(to: $0.position) } + [.wait(seconds: 2)])
            XCTAssertTrue(nav.hasArrived, "seed \(seed)")
            XCTAssertEqual(nav.routeCount, 1, "seed \(seed): \(w.spoken)")
            XCTAssertFalse(w.haptics.contains(.wrongWay) || w.haptics.contains(.offRoute), "seed \(seed)")
            let cues = w.records.filter { r in r.events.contains { $0.spokenText?.hasSuffix(" now.") ?? false } }
            XCTAssertEqual(cues.count, 3, "seed \(seed): \(w.spoken)")
            let turns = route.maneuvers.filter(\.kind.isTurn)
            for (r, m) in zip(cues, turns) {
                let p = r.input.positionInMap  // noisy; compare the true walked distance instead
                _ = p
                let k = w.records.firstIndex { $0.input.t == r.input.t }!
                let truth = trueDistanceAlong(route, walkedUpdates: k)
                let before = m.distanceFromStartMeters - truth
                let text = r.events.compactMap(\.spokenText).first ?? ""
                XCTAssertGreaterThanOrEqual(before - 1.2 * nav.policy.estimatedDurationSeconds(text), 0, "seed \(seed) \(m.kind)")
                XCTAssertLessThanOrEqual(before, 4.0, "seed \(seed) \(m.kind)")
            }
        }
    }

    /// Distance walked along `route` after `walkedUpdates` updates at 1.2 m/s (the first update stands
    /// at the start).
    private func trueDistanceAlong(_ route: Route, walkedUpdates k: Int) -> Double {
        // The walker moves in steps of at most 0.12 m, one per update, per segment; recompute them.
        var s = 0.0
        var count = 1
        for i in 1..<route.points.count {
            let len = route.cumulativeMeters[i] - route.cumulativeMeters[i - 1]
            let n = Int((len / 0.12).rounded(.up))
            if count + n > k { return s + len * Double(k - count) / Double(n) }
            count += n
            s += len
        }
        return s
    }

    func testWrongWayAfterTwoSecondsOfWalkingAgainstTheRoute() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a--------------------b").build()
        let nav = try Navigator(building: b, destinationId: "b")
        var w = Walker(start: Point2(x: 10, y: 0), floorId: "1", headingRad: 0)
        w.run(nav, [.wait(seconds: 0.1)])
        XCTAssertEqual(w.spoken, ["Go straight ahead, 10 meters."])
        // Facing west while standing: no warning.
        w.run(nav, [.face(headingRad: .pi), .wait(seconds: 3)])
        XCTAssertEqual(w.haptics, [])
        // Walking west: warned once, about 2 s after starting to move.
        let startT = w.t
        w.run(nav, [.walk(to: Point2(x: 5, y: 0))])
        let warn = try XCTUnwrap(w.records.first { $0.events.contains(.init(t: $0.input.t, event: .haptic(.wrongWay))) })
        XCTAssertGreaterThanOrEqual(warn.input.t - startT, 2.0)
        XCTAssertLessThanOrEqual(warn.input.t - startT, 2.6)
        XCTAssertTrue(warn.events.contains { $0.spokenText == "Wrong way, turn around." })
        XCTAssertFalse(w.haptics.contains(.offRoute), "walking back along the route's own edge is not off route")
        XCTAssertEqual(nav.routeCount, 1)
        // Turning around and walking on: arrival.
        w.run(nav, [.walk(to: Point2(x: 20, y: 0))])
        XCTAssertTrue(nav.hasArrived)
    }

    func testOffRouteAnnouncedThenRerouted() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: """
            a-----------b
            """).build()
        let nav = try Navigator(building: b, destinationId: "b")
        var w = Walker(start: Point2(x: 2, y: 0), floorId: "1", headingRad: 0)
        w.run(nav, [.walk(to: Point2(x: 4, y: 0)), .walk(to: Point2(x: 4, y: 3.5))])
        XCTAssertEqual(w.haptics.filter { $0 == .offRoute }.count, 1)
        let at = try XCTUnwrap(w.records.first { r in r.events.contains { $0.spokenText == "Off route, recalculating." } })
        XCTAssertGreaterThan(at.input.positionInMap.y, 3.0)
        XCTAssertLessThan(at.input.positionInMap.y, 3.2)
        XCTAssertEqual(nav.routeCount, 2)
        // The new route's first instruction follows the correction once it has been said.
        w.run(nav, [.wait(seconds: 3)])
        XCTAssertEqual(w.spoken.last, "Turn right, then go 8 meters.")
    }

    func testRelockAwayFromTheRouteTakesTheRouteAgainWithoutOffRoute() throws {
        // Localized in the upper corridor, then unsure for 5 s (the lock broke); localized again in the lower
        // corridor 8 m away: the estimate moved, not the traveler. The route is taken again silently and its
        // first instruction is said, with no "Off route, recalculating." (safety rank, it would hold back a
        // turn cue due a moment later).
        let b = FloorPlanFixture(gridMeters: 2).floor("1", map: """
            a-------b
                    |
                    |
                    |
                    |
            c-------d
            """).build()
        let nav = try Navigator(building: b, destinationId: "d")
        var w = Walker(start: b.nodePosition("a"), floorId: "1", headingRad: 0)
        w.run(nav, [.walk(to: Point2(x: 4, y: 10))])
        XCTAssertEqual(nav.routeCount, 1)
        w.unlocalized(nav, seconds: 5)
        w.run(nav, [.appear(at: Point2(x: 4, y: 0), floorId: "1"), .face(headingRad: 0), .wait(seconds: 3)])
        XCTAssertEqual(nav.routeCount, 2)
        XCTAssertFalse(w.spoken.contains("Off route, recalculating."), "\(w.spoken)")
        XCTAssertFalse(w.haptics.contains(.offRoute))
        XCTAssertEqual(w.spoken.last, "Go straight ahead, 10 meters.")
        // Walking off the new route afterwards is still a correction.
        w.run(nav, [.walk(to: Point2(x: 8, y: 0)), .walk(to: Point2(x: 8, y: -3.5))])
        XCTAssertTrue(w.spoken.contains("Off route, recalculating."))
    }

    func testSideCorridorReroutesSilently() throws {
        let b = FloorPlanFixture(gridMeters: 2).floor("1", map: """
            a-------b-------c
                    |
                    |
                    d
            """).build()
        let nav = try Navigator(building: b, destinationId: "c")
        var w = Walker(start: b.nodePosition("a"), floorId: "1", headingRad: 0)
        let bp = b.nodePosition("b")
        w.run(nav, [.walk(to: bp), .walk(to: Point2(x: bp.x, y: bp.y - 1.5))])
        XCTAssertEqual(nav.routeCount, 2, "nearer to the side corridor than to the route by more than 1 m")
        XCTAssertFalse(w.spoken.contains("Off route, recalculating."))
        XCTAssertEqual(nav.currentRoute?.nodeIds, ["b", "c"])
    }

    func testHysteresisKeepsRouteAgainstSmallGainsButFollowsAClearChoice() throws {
        // Square loop, 8 m sides, destination d at the far corner: a-b-d and a-c-d are equally long.
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: """
            a-------b
            |       |
            |       |
            |       |
            |       |
            |       |
            |       |
            |       |
            c-------d
            """).build()
        let nav = try Navigator(building: b, destinationId: "d")
        var w = Walker(start: Point2(x: 0.5, y: 8), floorId: "1", headingRad: 0)
        w.run(nav, [.wait(seconds: 0.1)])
        XCTAssertEqual(nav.currentRoute?.nodeIds, ["b", "d"])
        // Estimate jitters onto the other branch: via c is now 0.8 m shorter, under the 2 m hysteresis.
        w.run(nav, [.walk(to: Point2(x: 0, y: 7.6)), .wait(seconds: 2), .walk(to: Point2(x: 0.5, y: 8)), .wait(seconds: 1)])
        XCTAssertEqual(nav.routeCount, 1)
        XCTAssertEqual(nav.currentRoute?.nodeIds, ["b", "d"])
        // Walking down the other branch is a clear choice.
        w.run(nav, [.walk(to: Point2(x: 0, y: 8)), .walk(to: Point2(x: 0, y: 5))])
        XCTAssertEqual(nav.routeCount, 2)
        XCTAssertEqual(nav.currentRoute?.nodeIds, ["c", "d"])
    }

    /// Map for the arrival sides: node p with entrance markers around it, c at the east end.
    let sidesMap = """
          4   1

        a-----p-----c  3

              2
        """

    private func arrivalText(entrance: Character, from: String, to: String = "p", behindDoor: Bool = false) throws -> String? {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: sidesMap)
            .pointOfInterest(node: to, id: "room", name: "Room 312", behindDoor: behindDoor, entrance: entrance).build()
        let nav = try Navigator(building: b, destinationId: "room")
        var w = Walker(start: b.nodePosition(from), floorId: "1")
        w.run(nav, [.walk(to: b.nodePosition(to))])
        XCTAssertTrue(nav.hasArrived)
        return w.spoken.last
    }

    func testArrivalSaysWhichSideAndDoor() throws {
        XCTAssertEqual(try arrivalText(entrance: "1", from: "a"), "Arrived. Room 312 is on your left.")
        XCTAssertEqual(try arrivalText(entrance: "2", from: "a"), "Arrived. Room 312 is on your right.")
        XCTAssertEqual(try arrivalText(entrance: "1", from: "c"), "Arrived. Room 312 is on your right.")
        XCTAssertEqual(try arrivalText(entrance: "4", from: "a"), "Arrived. Room 312 is behind you.")
        XCTAssertEqual(try arrivalText(entrance: "3", from: "a", to: "c"), "Arrived. Room 312 is ahead.")
        XCTAssertEqual(try arrivalText(entrance: "1", from: "a", behindDoor: true), "Arrived. Room 312 is on your left, behind a door.")
    }

    func testArrivalWithinOneMeterAndNothingAfter() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "a-----------b").build()
        let nav = try Navigator(building: b, destinationId: "b")
        var w = Walker(start: Point2(x: 0, y: 0), floorId: "1")
        w.run(nav, [.walk(to: Point2(x: 12, y: 0))])
        let at = try XCTUnwrap(w.records.first { $0.events.contains { $0.spokenText?.hasPrefix("Arrived.") ?? false } })
        XCTAssertGreaterThanOrEqual(at.input.positionInMap.x, 11.0)
        XCTAssertLessThan(at.input.positionInMap.x, 11.13)
        let after = w.records.filter { $0.input.t > at.input.t }.flatMap(\.events)
        XCTAssertEqual(after, [])
    }

    /// What is said and felt (haptics in parentheses) on the walk a -> b -> c -> d of `map` (0.5 m grid) at
    /// 1.2 m/s and 10 Hz, with the lock lost from 6 m before b to `relockPastB` meters past it. Written out
    /// rather than with `Walker`: its legs end on their end points, so a relock 0.9 m past b would first be
    /// localized at c itself, not just after the relock point.
    func arrivalTimeline(map: String, relockPastB: Double) throws -> [String] {
        let b = FloorPlanFixture(gridMeters: 0.5).floor("1", map: map).build()
        let nav = try Navigator(building: b, destinationId: "d")
        let path = ["a", "b", "c", "d"].map { b.nodePosition($0) }
        var legStart = [0.0]
        for i in 1..<path.count { legStart.append(legStart[i - 1] + hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y)) }
        let atB = legStart[1], total = legStart[3]
        var timeline: [String] = []
        var k = 0
        while true {
            let t = Double(k) / 10, s = min(1.2 * t, total)
            let i = min(legStart.lastIndex { $0 <= s } ?? 0, path.count - 2)
            let f = (s - legStart[i]) / (legStart[i + 1] - legStart[i])
            let p = Point2(x: path[i].x + f * (path[i + 1].x - path[i].x), y: path[i].y + f * (path[i + 1].y - path[i].y))
            let heading = atan2(path[i + 1].y - path[i].y, path[i + 1].x - path[i].x)
            let lost = s > atB - 6 && s < atB + relockPastB
            for e in nav.update(NavigationInput(t: t, positionInMap: p, floorId: "1", headingRad: heading, isLocalized: !lost)) {
                if let text = e.spokenText { timeline.append(text) }
                if case .haptic(let h) = e.event { timeline.append("(\(h.rawValue))") }
            }
            k += 1
            if s >= total && t > 1.2 * total + 4 { break }
        }
        return timeline
    }

    func testArrivalIsSaidAndNoStaleTurnCueAfterIt() throws {
        // Two right turns 1 m apart, 1 m before the destination d, and the lock lost for 5 s up to just past the
        // first (b). On relocking one or both turn cues come due and "Arrived" follows within a second. The
        // arrival must be heard (a cue older than 1.5 s is dropped, so it must not wait behind a moot turn cue)
        // and nothing about a turn may be said after it. Before the fix: "Arrived" then "Then turn right." for
        // a relock up to 0.4 m past b; from 0.5 m, "(arrived)" then "Turn right now." and no arrival at all
        // (as on the end-to-end study's conv-2-01).
        let map = "a-----------------b\n                  |\n                d-c"
        for r in stride(from: 0.0, through: 0.9, by: 0.1) {
            let timeline = try arrivalTimeline(map: map, relockPastB: r)
            let arrived = try XCTUnwrap(timeline.lastIndex { $0.hasPrefix("Arrived.") }, "relock \(r) m past b: \(timeline)")
            XCTAssertFalse(timeline[(arrived + 1)...].contains { $0.lowercased().contains("turn") }, "relock \(r): \(timeline)")
            XCTAssertEqual(timeline.filter { $0 == "(arrived)" }.count, 1, "relock \(r): \(timeline)")
            XCTAssertTrue(timeline.contains("Turn right now."), "relock \(r): \(timeline)")
        }
    }

    func testTwoTurnCuesDueAtOnceGiveOneTurnHaptic() throws {
        // Relocking 0.5-0.9 m past the first of two turns 1 m apart brings both turn cues due in one update;
        // the phone reads a haptic's turn side from the batch's speech, so a second haptic would repeat the
        // first turn's side. Before the fix: "(turnCue)", "(turnCue)", "Turn right now." in one batch.
        let map = "a-----------------b\n                  |\n                d-c"
        for r in stride(from: 0.5, through: 0.9, by: 0.1) {
            let timeline = try arrivalTimeline(map: map, relockPastB: r)
            XCTAssertFalse(zip(timeline, timeline.dropFirst()).contains { $0 == "(turnCue)" && $1 == "(turnCue)" },
                           "relock \(r): \(timeline)")
            XCTAssertEqual(timeline.filter { $0 == "(turnCue)" }.count, 1, "relock \(r): \(timeline)")
        }
    }

    func testElevatorRideEndToEnd() throws {
        let b = FloorPlanFixture(gridMeters: 1)
            .floor("1", map: "a-------E")
            .floor("2", map: "        E-----------b")
            .build()
        let nav = try Navigator(building: b, destinationId: "b")
        var w = Walker(start: b.nodePosition("a"), floorId: "1")
        let e = b.nodePosition("E1")
        w.run(nav, [.walk(to: e), .wait(seconds: 6), .changeFloor(to: "2"), .wait(seconds: 1),
                    .walk(to: b.nodePosition("b"))])
        XCTAssertTrue(nav.hasArrived)
        XCTAssertEqual(w.spoken, [
            "Go straight ahead, 8 meters.",
            "Take the elevator to Floor 2.",
            "Now on Floor 2. Continue 10 meters.",  // 12 m, rounded to 5 m
            "In 8 meters, arrive at b.",
            "Arrived. b is ahead.",
        ])
        let cue = try XCTUnwrap(w.records.first { $0.events.contains { $0.spokenText == "Take the elevator to Floor 2." } })
        XCTAssertEqual(8 - cue.input.positionInMap.x, 0.75, accuracy: 0.13)
    }

    func testWhereAmIAndRepeat() throws {
        let b = FloorPlanFixture(gridMeters: 1).floor("1", map: "E-----p-----q-----S")
            .label("E1", "the elevator").label("S1", "stairwell B")
            .pointOfInterest(node: "p", id: "r312", name: "Room 312")
            .build()
        let nav = try Navigator(building: b, destinationId: "S1")
        XCTAssertEqual(nav.requestWhereAmI(t: 0).compactMap(\.spokenText), ["Location not known yet; keep walking slowly."])
        XCTAssertEqual(nav.requestRepeat(t: 0.5).compactMap(\.spokenText), ["No instruction yet."])
        var w = Walker(start: Point2(x: 7, y: 0), floorId: "1", headingRad: 0, t: 5)
        w.run(nav, [.wait(seconds: 0.1)])
        XCTAssertEqual(w.spoken, ["Go straight ahead, 10 meters."])  // 11 m, rounded to 5 m
        let where1 = nav.requestWhereAmI(t: 6)
        XCTAssertEqual(where1, [TimedGuidanceEvent(t: 6, event: .speak(text: "Near Room 312, between the elevator and stairwell B.",
                                                                        priority: .information, interrupt: true))])
        // Repeat gives the last instruction, not the answer to "where am I", even within 10 s.
        XCTAssertEqual(nav.requestRepeat(t: 9).compactMap(\.spokenText), ["Go straight ahead, 10 meters."])
        // Nearer the stairs, at the end of the corridor (nothing labelled beyond): just "near".
        let toElevator = try Navigator(building: b, destinationId: "E1")
        _ = toElevator.update(NavigationInput(t: 20, positionInMap: Point2(x: 17, y: 0), floorId: "1", headingRad: .pi, isLocalized: true))
        XCTAssertEqual(toElevator.requestWhereAmI(t: 21).compactMap(\.spokenText), ["Near stairwell B."])
    }

    func testRouteNotRecomputedWhileOnRoute() throws {
        let nav = try Navigator(building: zigzag, destinationId: "e")
        var w = Walker(start: zigzag.nodePosition("a"), floorId: "1")
        w.run(nav, [.wait(seconds: 0.1)])
        let route = try XCTUnwrap(nav.currentRoute)
        w.run(nav, route.points.dropFirst().map { .walk(to: $0.position) })
        XCTAssertEqual(nav.routeCount, 1)
        XCTAssertEqual(nav.currentRoute, route)
    }

    func testLanguagesAndPhraseFileErrors() throws {
        var options = NavigatorOptions()
        options.language = "xx"
        XCTAssertThrowsError(try Navigator(building: zigzag, destinationId: "e", options: options)) {
            XCTAssertEqual($0 as? NavigationError, .unknownLanguage("xx"))
        }
        XCTAssertEqual(try PhraseBook.load(language: "en-GB").language, "en", "regional code falls back")
        XCTAssertThrowsError(try PhraseBook.load(language: "xx-YY")) {
            XCTAssertEqual($0 as? NavigationError, .unknownLanguage("xx-YY"))
        }
        XCTAssertThrowsError(try PhraseBook.load(language: "../en")) {
            XCTAssertEqual($0 as? NavigationError, .unknownLanguage("../en"))
        }
        let missing = Data(#"{"language": "en", "phrases": {"startWalking": "Go."}}"#.utf8)
        XCTAssertThrowsError(try PhraseBook(language: "en", json: missing, sourceName: "test.json")) {
            XCTAssertTrue("\($0)".contains("test.json: missing key"), "\($0)")
        }
        var all = try PhraseBook.load(language: "en").templates
        all["startWalking"] = "Go {speed}."
        let bad = try JSONSerialization.data(withJSONObject: ["language": "en", "phrases": all])
        XCTAssertThrowsError(try PhraseBook(language: "en", json: bad, sourceName: "bad.json")) {
            XCTAssertTrue("\($0)".contains("'startWalking' uses unknown placeholder {speed}"), "\($0)")
        }
    }

    func testEveryTemplateRendersWithoutLeftoverPlaceholders() throws {
        let book = try PhraseBook.load(language: "en")
        let values = ["distance": "5 meters", "count": "5", "floor": "Floor 2", "destination": "Room 312",
                      "place": "Room 312", "from": "the elevator", "to": "stairwell B"]
        for key in PhraseBook.requiredKeys {
            let text = book.phrase(key, values)
            XCTAssertFalse(text.contains("{"), "\(key): \(text)")
            XCTAssertFalse(text.isEmpty, key)
        }
    }

    func testDistanceRounding() {
        let table: [(Double, Int)] = [(0.2, 1), (1.4, 1), (1.5, 2), (7.6, 8), (9.49, 9), (9.6, 10), (10, 10),
                                      (12.4, 10), (12.5, 15), (17.4, 15), (23, 25), (101, 100)]
        for (m, expected) in table { XCTAssertEqual(PhraseBook.roundedDistanceMeters(m), expected, "\(m) m") }
    }
}
