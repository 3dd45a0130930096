import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// Every committed scenario (Tests/Scenarios/*.json) simulates without error.
final class ScenarioSuiteTests: XCTestCase {
    static let repoRoot = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent().deletingLastPathComponent()
    static let scenarioDirectory = repoRoot.appendingPathComponent("Tests/Scenarios")
    static let sharedData = repoRoot.appendingPathComponent("../shared/data").standardizedFileURL

    private func scenarioFiles() throws -> [URL] {
        try FileManager.default.contentsOfDirectory(at: Self.scenarioDirectory, includingPropertiesForKeys: nil)
            .filter { $0.pathExtension == "json" }.sorted { $0.lastPathComponent < $1.lastPathComponent }
    }

    func testSuiteCoversTheRequiredSituations() throws {
        let scenarios = try scenarioFiles().map { try SimulationScenario.load(contentsOf: $0) }
        XCTAssertGreaterThanOrEqual(scenarios.count, 12)
        XCTAssertEqual(Set(scenarios.map(\.name)).count, scenarios.count, "names are unique")
        for (url, s) in zip(try scenarioFiles(), scenarios) { XCTAssertEqual(url.deletingPathExtension().lastPathComponent, s.name) }
        XCTAssertTrue(scenarios.contains { $0.startKnown }); XCTAssertTrue(scenarios.contains { !$0.startKnown })
        XCTAssertTrue(scenarios.contains { $0.trackingLossAt != nil }); XCTAssertTrue(scenarios.contains { $0.vioResetAt != nil })
        XCTAssertTrue(scenarios.contains { $0.wrongTurn }); XCTAssertTrue(scenarios.contains { $0.carry == .lanyard })
        XCTAssertTrue(scenarios.contains { $0.map.hasPrefix("skeri:") }); XCTAssertTrue(scenarios.contains { $0.map == "office" })
    }

    func testEveryScenarioSimulates() throws {
        var skipped: [String] = []
        for url in try scenarioFiles() {
            let s = try SimulationScenario.load(contentsOf: url)
            if s.map.hasPrefix("skeri"), !FileManager.default.fileExists(atPath: Self.sharedData.appendingPathComponent("skeri_inavigate").path) {
                skipped.append(s.name); continue
            }
            let building = try ScenarioMaps.load(s.map, sharedData: Self.sharedData)
            let w = try WalkSimulator.simulate(building: building, scenario: s)
            XCTAssertGreaterThan(w.frames.count, Int(10 * s.rateHz), s.name)
            XCTAssertGreaterThan(w.observations.count, 0, "\(s.name): no sign observations")
            XCTAssertEqual(w.info.start != nil, s.startKnown, s.name)
            if let floor = ScenarioMaps.skeriFloor(s.map) { XCTAssertEqual(w.truth.first?.floorId, floor, "\(s.name) starts on floor \(floor)") }
            // Ends at the destination.
            let planner = RoutePlanner(building: building)
            let dest = building.graph.nodes[try planner.resolve(s.to).nodeIndex]
            XCTAssertEqual(hypot(w.truth.last!.x - dest.position.x, w.truth.last!.y - dest.position.y), 0, accuracy: 0.1, s.name)
            XCTAssertEqual(w.truth.last!.floorId, dest.floorId, s.name)
        }
        if !skipped.isEmpty { throw XCTSkip("shared data missing at \(Self.sharedData.path); skipped \(skipped)") }
    }

    func testScenarioDefaultsAndErrors() throws {
        let s = try JSONDecoder().decode(SimulationScenario.self, from: Data(#"{"name":"x","from":"a","to":"b","seed":3}"#.utf8))
        XCTAssertEqual(s.map, "office"); XCTAssertEqual(s.rateHz, 30); XCTAssertEqual(s.carry, .handheld)
        XCTAssertFalse(s.startKnown); XCTAssertNil(s.trackingLossAt); XCTAssertEqual(s.detectorRateHz, 10)
        let bad = FileManager.default.temporaryDirectory.appendingPathComponent("bad-scenario-\(getpid()).json")
        try Data(#"{"name":"x","from":"a","to":"b","seed":3,"rateHz":-1}"#.utf8).write(to: bad)
        XCTAssertThrowsError(try SimulationScenario.load(contentsOf: bad)) { XCTAssertTrue("\($0)".contains("rateHz")) }
        try Data(#"{"name":"x","from":"a"}"#.utf8).write(to: bad)
        XCTAssertThrowsError(try SimulationScenario.load(contentsOf: bad)) { XCTAssertTrue("\($0)".contains(bad.lastPathComponent)) }
        XCTAssertThrowsError(try ScenarioMaps.load("/nonexistent/map.json")) {
            guard case .mapUnavailable(let m)? = $0 as? SimulationError else { return XCTFail("\($0)") }
            XCTAssertTrue(m.contains("/nonexistent/map.json"))
        }
    }
}
