import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// The committed sample session (App/Samples/office-walk) is exactly what docs/simulator.md's command makes:
/// `wayfinder simulate --map Maps/Buildings/wayfinder-office.json --from room-111 --to room-102 --seed 7
/// --rate 10 --floor-only-start -o App/Samples/office-walk`.
final class SampleSessionTests: XCTestCase {
    static let sample = ScenarioSuiteTests.repoRoot.appendingPathComponent("App/Samples/office-walk")

    func testSampleIsReproducibleFromTheDocumentedCommand() throws {
        let mapPath = "Maps/Buildings/wayfinder-office.json"
        let building = try MapLoader.load(contentsOf: ScenarioSuiteTests.repoRoot.appendingPathComponent(mapPath))
        // What SimulateCommand builds from those flags.
        let scenario = SimulationScenario(name: "cli", map: mapPath, from: "room-111", to: "room-102", seed: 7,
                                          startKnown: false, rateHz: 10)
        let walk = try WalkSimulator.simulate(building: building, scenario: scenario)
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-sample-\(getpid())-\(UUID().uuidString)")
        defer { try? FileManager.default.removeItem(at: dir) }
        try walk.write(to: dir)
        for name in ["session.json", "frames.jsonl", "observations.jsonl", "truth.jsonl"] {
            let committed = try Data(contentsOf: Self.sample.appendingPathComponent(name))
            let fresh = try Data(contentsOf: dir.appendingPathComponent(name))
            XCTAssertEqual(committed, fresh, "\(name) differs: regenerate the sample with the command in docs/simulator.md")
        }
    }

    func testSampleIsSmallFloorOnlyAndCrossesTurns() throws {
        let bundle = try SessionBundle.read(from: Self.sample)
        XCTAssertNil(bundle.info.start, "floor-only start")
        XCTAssertEqual(bundle.info.floorId, "1")
        XCTAssertEqual(bundle.info.destination, "room-102")
        XCTAssertEqual(bundle.frames.count, bundle.truth.count)
        XCTAssertEqual(bundle.frames[1].t - bundle.frames[0].t, 0.1, accuracy: 1e-9)
        var size = 0
        for name in ["session.json", "frames.jsonl", "observations.jsonl", "truth.jsonl"] {
            size += try Data(contentsOf: Self.sample.appendingPathComponent(name)).count
        }
        XCTAssertLessThan(size, 1_000_000)
        // At least two turns of more than 60 degrees in the truth heading (smoothed over 1 s).
        var turns = 0
        var k = 10
        var lastHeading = bundle.truth[0].headingRad
        var accumulated = 0.0
        while k < bundle.truth.count {
            accumulated += wrapAngle(bundle.truth[k].headingRad - lastHeading)
            lastHeading = bundle.truth[k].headingRad
            if abs(accumulated) > 1.05 { turns += 1; accumulated = 0 }
            if k % 30 == 0 { accumulated *= 0.5 }
            k += 10
        }
        XCTAssertGreaterThanOrEqual(turns, 2)
    }
}
