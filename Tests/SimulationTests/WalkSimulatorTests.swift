import XCTest
import Maps
import SessionFormat
@testable import Simulation

final class WalkSimulatorTests: XCTestCase {
    func testSmoke() throws {
        let w = try Fixtures.walk(Fixtures.scenario())
        XCTAssertEqual(w.frames.count, w.truth.count)
        print("frames", w.frames.count, "obs", w.observations.count, "duration", w.truth.last!.t, "route", w.diagnostics.routeNodeIds)
        print("vio", w.diagnostics.vio)
        let tracking = Dictionary(grouping: w.frames, by: { "\($0.tracking)/\($0.trackingReason.map { "\($0)" } ?? "")" }).mapValues(\.count)
        print(tracking)
        print(Dictionary(grouping: w.diagnostics.phases, by: { $0 }).mapValues(\.count))
    }
}
