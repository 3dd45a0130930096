import Foundation
import Maps
import XCTest
@testable import Simulation

/// The long-tour option (`SimulationScenario.tourMinutes`, `wayfinder simulate --tour-minutes`): the route
/// chained with its reverse until the planned walking time is reached.
final class TourTests: XCTestCase {
    /// A 2-minute tour on the office lasts at least 2 minutes (planned at the fastest preferred speed), passes
    /// the destination and comes back to the start several times, and never crosses a wall (the simulator
    /// checks every truth step).
    func testTourWalksBackAndForthForTheRequestedTime() throws {
        var s = Fixtures.scenario("tour", from: "room-101", to: "room-111", seed: 5, rateHz: 10)
        let single = try WalkSimulator.simulate(building: Fixtures.office, scenario: s)
        s.tourMinutes = 2
        let tour = try WalkSimulator.simulate(building: Fixtures.office, scenario: s)
        let duration = try XCTUnwrap(tour.truth.last?.t)
        XCTAssertGreaterThanOrEqual(duration, 120)
        XCTAssertGreaterThan(duration, 2 * (single.truth.last?.t ?? 0))
        // Visits of the two ends: truth within 2 m of the single walk's start and end, counted once per arrival.
        let start = try XCTUnwrap(single.truth.first), end = try XCTUnwrap(single.truth.last)
        var arrivals = 0, near: Int? = nil
        for r in tour.truth {
            let atStart = hypot(r.x - start.x, r.y - start.y) < 2, atEnd = hypot(r.x - end.x, r.y - end.y) < 2
            let here = atStart ? 0 : (atEnd ? 1 : nil)
            if let h = here, h != near { arrivals += 1 }
            if here != nil { near = here }
        }
        XCTAssertGreaterThanOrEqual(arrivals, 3, "start, end, start again at least")
    }

    /// Out-of-range tour lengths and a tour with a wrong turn are refused with a message naming the setting.
    func testInvalidTourIsRefused() {
        var s = Fixtures.scenario("tour-bad")
        s.tourMinutes = 0
        XCTAssertThrowsError(try s.validate()) { XCTAssertTrue("\($0)".contains("tourMinutes")) }
        s.tourMinutes = 5
        s.wrongTurn = true
        XCTAssertThrowsError(try s.validate()) { XCTAssertTrue("\($0)".contains("tourMinutes")) }
    }
}
