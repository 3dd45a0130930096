import Foundation
import Localizer
import Maps
import XCTest
@testable import WayfinderCore

/// Which wall kinds each detector frame looks for (`WallKindScheduler`) and which kinds the hypotheses expect in view
/// (`ExpectedSignKinds`).
final class WallKindSchedulerTests: XCTestCase {
    private let kinds = ["restroom", "elevator", "stairs", "placard"]

    /// The next `n` frames' kinds; each frame also checks that `searchesNextFrame` said whether it searches any.
    private func frames(_ s: inout WallKindScheduler, _ n: Int, shares: [String: Double] = [:],
                        file: StaticString = #filePath, line: UInt = #line) -> [Set<String>] {
        (0..<n).map { _ in
            let announced = s.searchesNextFrame
            let chosen = s.next(expectedShares: shares)
            XCTAssertEqual(announced, !chosen.isEmpty, file: file, line: line)
            return chosen
        }
    }

    /// `.rotation` is the detector's own schedule (SignDetector's MoreKinds tests): two kinds on every second frame.
    func testRotationIsTheDetectorsSchedule() {
        var s = WallKindScheduler(kinds: kinds, mode: .rotation)
        XCTAssertEqual(frames(&s, 6), [["restroom", "elevator"], [], ["stairs", "placard"], [], ["restroom", "elevator"], []])
        // With nothing expected, `.expected` is the same schedule, whatever shares below the threshold say.
        var e = WallKindScheduler(kinds: kinds)
        XCTAssertEqual(e.mode, .expected)
        XCTAssertEqual(frames(&e, 6, shares: ["placard": WallKindScheduler.minExpectedShare / 2]),
                       [["restroom", "elevator"], [], ["stairs", "placard"], [], ["restroom", "elevator"], []])
    }

    /// An expected kind takes one slot on every searched frame; the other slot still goes round all the kinds, so a kind
    /// no hypothesis expects is looked for too (here every eighth frame at least).
    func testAnExpectedKindIsLookedForOnEverySearchedFrame() {
        var s = WallKindScheduler(kinds: kinds)
        XCTAssertEqual(frames(&s, 10, shares: ["placard": 0.6, "stairs": 0.3]),
                       [["placard", "restroom"], [], ["placard", "elevator"], [], ["placard", "stairs"], [],
                        ["placard", "restroom"], [], ["placard", "elevator"], []])
        // The most expected first; equal shares in the detector's order; one kind per frame: the expected one.
        var one = WallKindScheduler(kinds: kinds, kindsPerFrame: 1, framePeriod: 1)
        XCTAssertEqual(one.next(expectedShares: ["stairs": 0.2, "elevator": 0.2, "placard": 0.1]), ["elevator"])
        XCTAssertEqual(one.next(expectedShares: [:]), ["restroom"])
        var three = WallKindScheduler(kinds: kinds, kindsPerFrame: 3, framePeriod: 1)
        XCTAssertEqual(three.next(expectedShares: ["stairs": 0.2, "elevator": 0.5, "placard": 0.9]),
                       ["placard", "elevator", "restroom"])
    }

    func testEveryFrameAndNothingToSchedule() {
        var all = WallKindScheduler(kinds: kinds, mode: .everyFrame)
        XCTAssertEqual(frames(&all, 3), Array(repeating: Set(kinds), count: 3))
        var wide = WallKindScheduler(kinds: ["restroom", "stairs"], mode: .rotation, kindsPerFrame: 2, framePeriod: 3)
        XCTAssertEqual(frames(&wide, 4), [["restroom", "stairs"], [], [], ["restroom", "stairs"]])
        var none = WallKindScheduler(kinds: [])
        XCTAssertEqual(frames(&none, 2, shares: ["exit": 1]), [[], []])
    }

    /// The office's ground floor: its elevator sign at (19.01, 12.95) faces east into the elevator lobby (a wall at
    /// x = 21 closes the lobby to the east).
    func testTheHypothesesThatSeeASignOfAKindGiveItTheirWeight() throws {
        let office = try TestData.office()
        func hypothesis(_ w: Double, _ x: Double, _ y: Double, _ heading: Double) -> PoseHypothesis {
            PoseHypothesis(weight: w, floorId: "1", positionInMap: Point2(x, y), headingRad: heading,
                           positionStdMeters: 0.3, evidenceNats: 0, headingStdRad: 0.05)
        }
        func shares(_ hs: [PoseHypothesis], kinds: Set<String> = ["elevator", "restroom", "stairs", "placard"],
                    maxRangeMeters: Double = 12) -> [String: Double] {
            ExpectedSignKinds.shares(hypotheses: hs, building: office, kinds: kinds, halfFieldOfViewRad: 0.42,
                                     maxRangeMeters: maxRangeMeters)
        }
        let facingIt = hypothesis(0.7, 20.6, 12.95, Double.pi)
        XCTAssertEqual(shares([facingIt])["elevator"] ?? 0, 0.7, accuracy: 1e-12)
        // Turned away; outside the field of view (0.42 rad either side); beyond the detector's range; behind the
        // lobby's east wall; behind the sign (its back, through the wall it hangs on); a kind not asked about.
        XCTAssertNil(shares([hypothesis(0.7, 20.6, 12.95, 0)])["elevator"])
        XCTAssertNil(shares([hypothesis(0.7, 20.6, 12.95, Double.pi - 0.6)])["elevator"])
        XCTAssertNil(shares([facingIt], maxRangeMeters: 1.5)["elevator"])
        XCTAssertNil(shares([hypothesis(0.7, 22, 12.95, Double.pi)])["elevator"])
        XCTAssertNil(shares([hypothesis(0.7, 17.5, 12.95, 0)])["elevator"])
        XCTAssertNil(shares([facingIt], kinds: ["stairs"])["elevator"])
        // Hypotheses that see it add up; one on a floor the map lacks sees nothing.
        let both = shares([facingIt, hypothesis(0.2, 20.4, 13.3, Double.pi - 0.1), hypothesis(0.1, 20.6, 12.95, Double.pi)])
        XCTAssertEqual(both["elevator"] ?? 0, 1.0, accuracy: 1e-12)
        var elsewhere = facingIt
        elsewhere.floorId = "nowhere"
        XCTAssertTrue(shares([elsewhere]).isEmpty)
    }
}
