// The exploratory instruction while not localized (Navigation/Sources/DisambiguationPlanner.swift): safe under
// every live hypothesis (walls, stairs, doors), informative when the hypotheses predict different views.
import XCTest
import Maps
@testable import Navigation

final class DisambiguationPlannerTests: XCTestCase {
    /// A corridor 20 m long (x 0...20) and 2 m wide (y 0...2), closed at both ends. An Exit sign hangs on the
    /// east end wall facing west; optional stairs landing and door.
    private func corridor(stairsAt: Point2? = nil, doorAt: Point2? = nil) -> Building {
        let walls = [Wall(from: Point2(0, 0), to: Point2(20, 0)), Wall(from: Point2(0, 2), to: Point2(20, 2)),
                     Wall(from: Point2(0, 0), to: Point2(0, 2)), Wall(from: Point2(20, 0), to: Point2(20, 2))]
        let sign = Sign(id: "s1", kind: "exit", position: Point2(19.95, 1), facing: Point2(-1, 0), widthMeters: 0.3,
                        heightMeters: 0.2)
        var nodes = [GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(1, 1)),
                     GraphNode(id: "b", kind: .control, floorId: "1", position: Point2(19, 1))]
        if let stairsAt {
            nodes.append(GraphNode(id: "st", kind: .verticalLink, floorId: "1", position: stairsAt, verticalLink: .stairs))
        }
        let doors = doorAt.map { [Door(id: "d1", position: $0, widthMeters: 0.9)] } ?? []
        let floor = Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: walls, doors: doors, signs: [sign])
        return Building(id: "c", name: "Corridor", floors: [floor],
                        graph: NavigationGraph(nodes: nodes, edges: [GraphEdge(from: "a", to: "b")]))
    }

    func testFacingAWallTheAdviceIsToTurnAround() {
        let planner = DisambiguationPlanner(building: corridor())
        // Both hypotheses face a wall 1.5 m ahead (east end): walking ahead is unsafe under both.
        let h = [PoseCandidate(weight: 0.6, floorId: "1", positionInMap: Point2(18.5, 1), headingRad: 0),
                 PoseCandidate(weight: 0.4, floorId: "1", positionInMap: Point2(18.5, 1.2), headingRad: 0)]
        let advice = planner.advise(h)
        XCTAssertEqual(advice.action, .turnAround)
        XCTAssertGreaterThanOrEqual(advice.safeWalkMeters, 2.0)
        XCTAssertEqual(advice.phraseKey, "disambiguate.turnAround")
    }

    func testAnInstructionMustBeSafeUnderEveryLiveHypothesis() {
        let planner = DisambiguationPlanner(building: corridor())
        // Mirror hypotheses: one at x 4 facing east (10+ m free), one at x 16 facing west (10+ m free) - ahead
        // is safe for both. A third, light (3 %) one facing the east wall at 19 m is not live (no share in the
        // coverage or the information gain), but every instruction must still be safe under it.
        let h = [PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(4, 1), headingRad: 0),
                 PoseCandidate(weight: 0.47, floorId: "1", positionInMap: Point2(16, 1), headingRad: Double.pi),
                 PoseCandidate(weight: 0.03, floorId: "1", positionInMap: Point2(19, 1), headingRad: 0)]
        let advice = planner.advise(h)
        // Turning around tells them apart soonest: the one now facing east at x 16 sees the Exit sign 4 m
        // ahead at once, the other faces a wall - the nearest informative place, 3 m of safe walking for both.
        // (Walking ahead would first split them only after about 6 m, when the east-facing one nears the sign.)
        XCTAssertEqual(advice.action, .turnAround)
        XCTAssertEqual(advice.distinguishingMeters ?? -1, 1.0, accuracy: 1e-9)
        XCTAssertEqual(advice.informationNats, -(0.5 / 0.97 * log(0.5 / 0.97) + 0.47 / 0.97 * log(0.47 / 0.97)), accuracy: 1e-6)
        XCTAssertGreaterThanOrEqual(advice.safeWalkMeters, 3.0)
        let aheadGain = planner.informationGain(.ahead, Array(h.prefix(2)), walkMeters: 10, total: 0.97)
        XCTAssertGreaterThan(aheadGain.atMeters ?? 0, 5.0)
        // Made heavy (10 %), the third hypothesis vetoes walking ahead: it would walk into the end wall.
        var heavy = h
        heavy[2].weight = 0.10
        let vetoed = planner.advise(heavy)
        XCTAssertNotEqual(vetoed.action, .ahead)
        if let action = vetoed.action {
            for c in heavy {
                let free = planner.freeDistance(planner.building.floors[0], from: c.positionInMap,
                                                directionRad: c.headingRad + action.turnRad)
                XCTAssertGreaterThanOrEqual(free, vetoed.safeWalkMeters + 1.0 - 1e-9)
            }
        } else {
            XCTAssertEqual(vetoed.phraseKey, "disambiguate.unsure")
        }
    }

    func testALightUnrefutedRivalStillVetoesAnUnsafeInstruction() {
        let planner = DisambiguationPlanner(building: corridor())
        // The heavy hypothesis walks east from x 4 (10+ m free: "ahead" would be its best). The true place,
        // reported light (2 %) because a wrong named start left few particles there, faces the east wall 1 m
        // away: walking ahead is unsafe there, so ahead is not advised.
        let lone = [PoseCandidate(weight: 0.98, floorId: "1", positionInMap: Point2(4, 1), headingRad: 0)]
        XCTAssertEqual(planner.advise(lone).action, .ahead)
        let withRival = lone + [PoseCandidate(weight: 0.02, floorId: "1", positionInMap: Point2(19, 1), headingRad: 0)]
        let advice = planner.advise(withRival)
        XCTAssertNotEqual(advice.action, .ahead)
        if let action = advice.action {
            XCTAssertGreaterThanOrEqual(planner.safeWalkMeters(action, withRival), 3.0)
        }
        // Below the guard weight (lighter than any rival that keeps the flag off) it is noise and does not veto.
        let noise = lone + [PoseCandidate(weight: 0.0005, floorId: "1", positionInMap: Point2(19, 1), headingRad: 0)]
        XCTAssertEqual(planner.advise(noise).action, .ahead)
    }

    func testNeverTowardStairsOrThroughADoor() {
        let h = [PoseCandidate(weight: 1.0, floorId: "1", positionInMap: Point2(2, 1), headingRad: 0)]
        let free = DisambiguationPlanner(building: corridor()).advise(h)
        XCTAssertEqual(free.action, .ahead)
        XCTAssertEqual(free.safeWalkMeters, 10.0, accuracy: 1e-9)  // look-ahead cap
        // Stairs landing 4 m ahead: the walk stops 1.5 m short of it.
        let stairs = DisambiguationPlanner(building: corridor(stairsAt: Point2(6, 1))).safeWalkMeters(.ahead, h)
        XCTAssertEqual(stairs, 2.5, accuracy: 1e-9)
        // A door 2.5 m ahead: walking ahead would go through it, less than the minimum walk is left.
        let door = DisambiguationPlanner(building: corridor(doorAt: Point2(4.5, 1))).advise(h)
        XCTAssertNotEqual(door.action, .ahead)
    }

    func testAWalkMustAlsoBeSafeFromTheEdgesOfTheHypothesisSpread() {
        // A door in the north wall at x 6. The hypothesis stands at (6, 1.3) facing north: turning left walks
        // west along the corridor, its mean 0.7 m from the door centre, so from the mean the walk is clear.
        let planner = DisambiguationPlanner(building: corridor(doorAt: Point2(6, 2)))
        let sharp = PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(6, 1.3), headingRad: Double.pi / 2)
        XCTAssertEqual(planner.safeWalkMeters(.left, [sharp]), 5.0, accuracy: 1e-9)  // 6 m to the west wall - 1 m margin
        // The same cluster 0.6 m wide: the traveler may stand 0.45 m nearer the door (0.75 std), in the doorway,
        // and walking west from there passes the door centre 0.25 m away.
        var wide = sharp
        wide.positionStdMeters = 0.6
        XCTAssertEqual(planner.safeWalkMeters(.left, [wide]), 0, accuracy: 1e-9)
        XCTAssertNotEqual(planner.advise([wide]).action, .left)
        let inTheDoorway = PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(6, 1.75), headingRad: Double.pi / 2)
        XCTAssertLessThan(planner.safeWalkMeters(.left, [inTheDoorway]), 2.0)  // what `wayfinder eval` calls unsafe
        // Turning right walks east, also past the door: vetoed the same way. Away from the door the wide
        // cluster is still guided: at x 12 turning left leaves 8.8 m (the 11 m the ray looks - 1 m - 2 x 0.6 m).
        XCTAssertEqual(planner.safeWalkMeters(.right, [wide]), 0, accuracy: 1e-9)
        var elsewhere = wide
        elsewhere.positionInMap = Point2(12, 1.3)
        XCTAssertEqual(planner.safeWalkMeters(.left, [elsewhere]), 8.8, accuracy: 1e-9)
    }

    func testAWalkAlongANearWallIsNotAdvisedWhenTheHeadingSpreadsTowardsIt() {
        // Walking east along the corridor 0.5 m from the north wall (y 2), position std 0.2 m (the fan's starts
        // reach 0.15 m to each side). Sharp heading: every start walking east stays clear for 8 m.
        let planner = DisambiguationPlanner(building: corridor())
        let floor = planner.building.floors[0]
        var h = PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(4, 1.5), headingRad: 0, positionStdMeters: 0.2)
        XCTAssertGreaterThanOrEqual(planner.safeWalkMeters(.ahead, [h]), 3.0)
        // Heading std 9 degrees: at 1 std a start 0.15 m nearer the wall meets it 2.2 m on, a walk of 1.2 m before
        // the 1 m margin: not the 2 m every pose of the hypothesis must leave.
        h.headingStdRad = 9 * Double.pi / 180
        let fan = planner.fanWalkMeters(floor, h.positionInMap, spread: 0.2, directionRad: 0, halfAngleRad: 9 * Double.pi / 180)
        XCTAssertEqual(fan, 0.35 / tan(9 * Double.pi / 180) - 1.0, accuracy: 1e-9)
        XCTAssertLessThan(planner.safeWalkMeters(.ahead, [h]), 2.0)
        XCTAssertNotEqual(planner.advise([h]).action, .ahead)
        // The same spread in the middle of the corridor (1 m from each wall) leaves the walk.
        h.positionInMap = Point2(4, 1)
        XCTAssertGreaterThanOrEqual(planner.safeWalkMeters(.ahead, [h]), 3.0)
        // With the fan off, only the mean's and the spread points' walks are checked.
        var noFan = DisambiguationOptions()
        noFan.headingCheckStds = 0
        h.positionInMap = Point2(4, 1.5)
        XCTAssertGreaterThanOrEqual(DisambiguationPlanner(building: corridor(), options: noFan).safeWalkMeters(.ahead, [h]), 3.0)
    }

    func testTheFanSeesAWallEndBetweenTheSpreadPoints() {
        // A stub of wall across the walk 2.5 m ahead, from 0.05 to 0.25 m to the left of the mean's line: the mean
        // walks past it 5 cm away, the spread points (0.3 m to each side) miss it, the starts between them do not.
        var b = corridor()
        b.floors[0].walls.append(Wall(from: Point2(6.5, 1.05), to: Point2(6.5, 1.25)))
        let planner = DisambiguationPlanner(building: b)
        let h = PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(4, 1), headingRad: 0, positionStdMeters: 0.4)
        XCTAssertEqual(planner.fanWalkMeters(b.floors[0], h.positionInMap, spread: 0.4, directionRad: 0, halfAngleRad: 0),
                       1.5, accuracy: 1e-9)
        XCTAssertEqual(planner.safeWalkMeters(.ahead, [h]), 1.5, accuracy: 1e-9)
        var noFan = DisambiguationOptions()
        noFan.headingCheckStds = 0
        XCTAssertGreaterThan(DisambiguationPlanner(building: b, options: noFan).safeWalkMeters(.ahead, [h]), 3.0)
    }

    func testTheFanStopsShortOfADoorAndStairsBesideItsEdge() {
        // A door centre 0.65 m to the side of the walk, 2 m ahead: the mean's walk passes it at 0.65 m (clear), a
        // start 0.3 m towards it at 0.35 m: the fan stops the walk 0.4 m before the door's projection.
        let planner = DisambiguationPlanner(building: corridor(doorAt: Point2(6, 2)))
        let floor = planner.building.floors[0]
        XCTAssertEqual(planner.fanWalkMeters(floor, Point2(4, 1.35), spread: 0.4, directionRad: 0, halfAngleRad: 0),
                       1.6, accuracy: 1e-9)
        XCTAssertGreaterThanOrEqual(planner.fanWalkMeters(floor, Point2(4, 1.35), spread: 0, directionRad: 0, halfAngleRad: 0),
                                    2.0)
        let stairs = DisambiguationPlanner(building: corridor(stairsAt: Point2(7, 1)))
        XCTAssertEqual(stairs.fanWalkMeters(stairs.building.floors[0], Point2(4, 1), spread: 0, directionRad: 0, halfAngleRad: 0),
                       1.5, accuracy: 1e-9)
    }

    func testTheSpreadsEdgesStayOnTheWalkableSideOfAWall() {
        // Mean 0.3 m from the south wall, std 1 m: the point towards that wall stops 0.2 m short of it.
        let planner = DisambiguationPlanner(building: corridor())
        let starts = planner.spreadStarts(planner.building.floors[0], Point2(10, 0.3), spread: 1.0, directionRad: 0)
        XCTAssertEqual(starts.count, 4)
        for p in starts { XCTAssertTrue(p.y > 0 && p.y < 2, "\(p)") }
        XCTAssertEqual(starts.map(\.y).min() ?? -1, 0.2, accuracy: 1e-9)
        XCTAssertEqual(starts.map(\.y).max() ?? -1, 1.05, accuracy: 1e-9)  // 0.75 std towards the north wall
        XCTAssertTrue(planner.spreadStarts(planner.building.floors[0], Point2(10, 1), spread: 0, directionRad: 0).isEmpty)
    }

    func testASpreadCloudGetsNoDirection() {
        // Three light hypotheses holding 30 % of the weight in all: the rest of the cloud is spread over the
        // floor, so no direction is known to be safe where the traveler really is.
        let h = (0..<3).map { k in
            PoseCandidate(weight: 0.1, floorId: "1", positionInMap: Point2(3 + 4 * Double(k), 1), headingRad: 0)
        }
        let advice = DisambiguationPlanner(building: corridor()).advise(h)
        XCTAssertNil(advice.action)
        XCTAssertEqual(advice.phraseKey, "disambiguate.unsure")
    }

    func testOneWideClusterIsNoPoseToPlanFrom() {
        // Early on the whole cloud may be one connected cluster holding all the weight, its mean in the middle
        // of the floor: no direction can be planned from it.
        let h = [PoseCandidate(weight: 1.0, floorId: "1", positionInMap: Point2(10, 1), headingRad: 0, positionStdMeters: 5.8)]
        XCTAssertNil(DisambiguationPlanner(building: corridor()).advise(h).action)
    }

    func testNoSafeActionSaysSoPlainly() {
        // A 2 m x 2 m closet: nothing is 3 m free in any direction.
        let walls = [Wall(from: Point2(0, 0), to: Point2(2, 0)), Wall(from: Point2(0, 2), to: Point2(2, 2)),
                     Wall(from: Point2(0, 0), to: Point2(0, 2)), Wall(from: Point2(2, 0), to: Point2(2, 2))]
        let b = Building(id: "k", name: "Closet", floors: [Floor(id: "1", name: "F", elevationMeters: 0, walls: walls)],
                         graph: NavigationGraph(nodes: [GraphNode(id: "a", kind: .control, floorId: "1", position: Point2(1, 1))],
                                                edges: []))
        let advice = DisambiguationPlanner(building: b).advise(
            [PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(1, 1), headingRad: 0.3)])
        XCTAssertNil(advice.action)
        XCTAssertEqual(advice.phraseKey, "disambiguate.unsure")
    }

    func testSightingsNoHypothesisExplainsLeaveNoDirection() {
        // Mirror hypotheses with a safe walk ahead under both (as in testAnInstructionMustBeSafeUnderEveryLiveHypothesis),
        // but the localizer reports a sign its dominant hypothesis does not place there: the traveler may stand
        // where neither is (office-long-many-turns behind vio-rough: "Turn left" 26.5 m from both), so no walk is
        // planned from them.
        let planner = DisambiguationPlanner(building: corridor())
        let h = [PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(4, 1), headingRad: 0),
                 PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(16, 1), headingRad: Double.pi)]
        XCTAssertNotNil(planner.advise(h).action)
        let unexplained = planner.advise(h, hypothesesExplainSightings: false)
        XCTAssertNil(unexplained.action)
        XCTAssertEqual(unexplained.phraseKey, "disambiguate.unsure")
    }

    func testNavigatorSaysItIsUnsureWhileSightingsAreUnexplained() throws {
        let b = corridor()
        let h = [PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(18.5, 1), headingRad: 0),
                 PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(1.5, 1), headingRad: Double.pi)]
        func spoken(unexplainedUntil: Double) throws -> [(t: Double, text: String)] {
            let nav = try Navigator(building: b, destinationId: "b")
            var said: [(t: Double, text: String)] = []
            for k in 0..<40 {
                let t = Double(k) * 0.5
                let input = NavigationInput(t: t, positionInMap: Point2(18.5, 1), floorId: "1", headingRad: 0,
                                            isLocalized: false, confidence: 0.3, hypotheses: h,
                                            sightingsUnexplained: t < unexplainedUntil)
                for e in nav.update(input) { if case .speak(let text, _, _) = e.event { said.append((t, text)) } }
            }
            return said
        }
        // Unexplained for the first 6 s: the plain advice, no direction; then the directional advice.
        let said = try spoken(unexplainedUntil: 6)
        let beforeSix = said.filter { $0.t < 6 }
        XCTAssertFalse(beforeSix.isEmpty)
        XCTAssertTrue(beforeSix.allSatisfy { $0.text.contains("keep walking slowly") }, "\(said)")
        XCTAssertTrue(said.contains { $0.t >= 6 && $0.text.contains("Turn around") }, "\(said)")
        // Never explained: never a direction.
        XCTAssertFalse(try spoken(unexplainedUntil: 100).contains { $0.text.contains("Turn") || $0.text.contains("Walk straight") })
    }

    func testWhereAmINamesNoProbablePlaceWhileSightingsAreUnexplained() throws {
        // A hypothesis by the corridor's labelled node: "Probably near ..." unless the sightings are unexplained.
        var b = corridor()
        b.graph.nodes[0].label = "the lobby"
        let h = [PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(2, 1), headingRad: 0, positionStdMeters: 0.3)]
        func answer(_ unexplained: Bool) throws -> [String] {
            let nav = try Navigator(building: b, destinationId: "b")
            _ = nav.update(NavigationInput(t: 0, positionInMap: Point2(2, 1), floorId: "1", headingRad: 0, isLocalized: false,
                                           confidence: 0.3, hypotheses: h, sightingsUnexplained: unexplained))
            return nav.requestWhereAmI(t: 0.5).compactMap { e -> String? in
                if case .speak(let text, _, _) = e.event { return text } else { return nil }
            }
        }
        XCTAssertEqual(try answer(false), ["Probably near the lobby, not sure yet."])
        XCTAssertEqual(try answer(true), ["Location not known yet; keep walking slowly."])
    }

    func testNavigatorSpeaksTheAdviceInsteadOfStartWalking() throws {
        let b = corridor()
        let nav = try Navigator(building: b, destinationId: "b")
        let h = [PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(18.5, 1), headingRad: 0),
                 PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(1.5, 1), headingRad: Double.pi)]
        var spoken: [String] = []
        for k in 0..<40 {
            let input = NavigationInput(t: Double(k) * 0.5, positionInMap: Point2(18.5, 1), floorId: "1", headingRad: 0,
                                        isLocalized: false, confidence: 0.3, hypotheses: h)
            for e in nav.update(input) { if case .speak(let text, _, _) = e.event { spoken.append(text) } }
        }
        XCTAssertFalse(spoken.isEmpty)
        XCTAssertFalse(spoken.contains("Start walking."))
        XCTAssertTrue(spoken.allSatisfy { $0.contains("Turn around") }, "\(spoken)")
        XCTAssertLessThanOrEqual(spoken.count, 2)  // 20 s: said once, repeated at most once (15 s)
        // "Where am I" names the dominant hypothesis' surroundings, with its doubt.
        let answer = nav.requestWhereAmI(t: 20.5).compactMap { e -> String? in
            if case .speak(let text, _, _) = e.event { return text } else { return nil }
        }
        XCTAssertEqual(answer.count, 1)
    }

    func testLocalizedTheRoutesFirstInstructionCutsOffTheUnsureAdvice() throws {
        // Unsure at first (the one hypothesis faces the east wall 1.5 m away: "Turn around, then walk straight
        // ahead.", about 4 s of speech), then localized at 2.4 s while that advice still plays: the route's first
        // instruction comes at once and stops it.
        let nav = try Navigator(building: corridor(), destinationId: "a")
        let h = [PoseCandidate(weight: 1, floorId: "1", positionInMap: Point2(18.5, 1), headingRad: 0)]
        var events: [TimedGuidanceEvent] = []
        for k in 0..<20 {
            let t = Double(k) * 0.2, localized = t >= 2.4 - 1e-9
            let input = NavigationInput(t: t, positionInMap: Point2(18.5, 1), floorId: "1", headingRad: localized ? Double.pi : 0,
                                        isLocalized: localized, confidence: localized ? 0.95 : 0.3, hypotheses: h)
            events += nav.update(input)
        }
        let speech = events.compactMap { e -> (t: Double, text: String, interrupt: Bool)? in
            if case .speak(let text, _, let interrupt) = e.event { return (e.t, text, interrupt) } else { return nil }
        }
        XCTAssertEqual(speech.first?.text, "Not sure where you are yet. Turn around, then walk straight ahead.", "\(speech)")
        let afterLock = speech.filter { $0.t >= 2.4 - 1e-9 }
        XCTAssertEqual(afterLock.first?.t ?? -1, 2.4, accuracy: 1e-9, "\(speech)")
        XCTAssertTrue(afterLock.first?.text.hasPrefix("Go straight ahead") ?? false, "\(speech)")
        XCTAssertEqual(afterLock.first?.interrupt, true, "it stops the advice still playing")
    }

    func testAWallThePhoneSeesVetoesTheInstructionEvenWhenTheHypothesesSayItIsFree() throws {
        let planner = DisambiguationPlanner(building: corridor())
        // Both hypotheses stand in the corridor facing along it, 10+ m free ahead and behind. The true place is
        // not among them: the phone sees a wall 1.8 m away, 3 m wide, right across the planned direction.
        let h = [PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(4, 1), headingRad: 0),
                 PoseCandidate(weight: 0.5, floorId: "1", positionInMap: Point2(16, 1), headingRad: Double.pi)]
        let planned = try XCTUnwrap(planner.advise(h).action)
        let a = planned.turnRad, c = cos(a), s = sin(a)
        func turned(_ forward: Double, _ left: Double) -> Point2 { Point2(x: forward * c - left * s, y: forward * s + left * c) }
        let across = PerceivedWall(from: turned(1.8, -1.5), to: turned(1.8, 1.5))
        let vetoed = planner.advise(h, perceivedWalls: [across])
        XCTAssertNotEqual(vetoed.action, planned)
        if let other = vetoed.action {
            XCTAssertGreaterThanOrEqual(PerceivedWall.freeDistance([across], turnRad: other.turnRad, far: 11) - 1, vetoed.safeWalkMeters)
        }
        // A wall beside the planned way (parallel to it, 1 m to its left) leaves it free.
        let beside = PerceivedWall(from: turned(-2, 1), to: turned(6, 1))
        XCTAssertEqual(planner.advise(h, perceivedWalls: [beside]).action, planned)
        // Walls seen on every side: no instruction, said plainly.
        let box = [PerceivedWall(from: Point2(1.5, -1.5), to: Point2(1.5, 1.5)), PerceivedWall(from: Point2(-1.5, -1.5), to: Point2(-1.5, 1.5)),
                   PerceivedWall(from: Point2(-2, 1.2), to: Point2(2, 1.2)), PerceivedWall(from: Point2(-2, -1.2), to: Point2(2, -1.2))]
        let boxed = planner.advise(h, perceivedWalls: box)
        XCTAssertNil(boxed.action)
        XCTAssertEqual(boxed.phraseKey, "disambiguate.unsure")
    }

    func testAPlaneSeenFromTheCameraBecomesAWallInTheTravelersFrame() throws {
        // Camera at VIO (2, 3) facing VIO north (yaw pi/2); a plane 4 m north of it, normal facing south (yaw
        // -pi/2), 2 m wide: a wall 4 m ahead running from 1 m right to 1 m left.
        let w = try XCTUnwrap(PerceivedWall(planeCenterEast: 2, planeCenterNorth: 7, planeNormalYawRad: -Double.pi / 2,
                                            widthMeters: 2, cameraEast: 2, cameraNorth: 3, cameraYawRad: Double.pi / 2))
        let ends = [w.from, w.to].sorted { $0.y < $1.y }
        XCTAssertEqual(ends[0].x, 4, accuracy: 1e-9); XCTAssertEqual(ends[0].y, -1, accuracy: 1e-9)
        XCTAssertEqual(ends[1].x, 4, accuracy: 1e-9); XCTAssertEqual(ends[1].y, 1, accuracy: 1e-9)
        XCTAssertEqual(PerceivedWall.freeDistance([w], turnRad: 0, far: 11), 4, accuracy: 1e-9)
        XCTAssertEqual(PerceivedWall.freeDistance([w], turnRad: Double.pi / 2, far: 11), 11)
        XCTAssertNil(PerceivedWall(planeCenterEast: .nan, planeCenterNorth: 7, planeNormalYawRad: 0, widthMeters: 2,
                                   cameraEast: 2, cameraNorth: 3, cameraYawRad: 0))
        XCTAssertNil(PerceivedWall(planeCenterEast: 2, planeCenterNorth: 7, planeNormalYawRad: 0, widthMeters: 0,
                                   cameraEast: 2, cameraNorth: 3, cameraYawRad: 0))
    }
}
