import XCTest
import Maps
import SessionFormat
@testable import Simulation

/// Bundles: determinism, seeds, the round trip through the project's one reader.
final class BundleOutputTests: XCTestCase {
    private func tempDir(_ name: String) -> URL {
        FileManager.default.temporaryDirectory.appendingPathComponent("wf-sim-\(name)-\(getpid())-\(UUID().uuidString)")
    }

    private func files(_ dir: URL) throws -> [String: Data] {
        var out: [String: Data] = [:]
        let e = FileManager.default.enumerator(at: dir, includingPropertiesForKeys: [.isRegularFileKey])!
        for case let u as URL in e where (try u.resourceValues(forKeys: [.isRegularFileKey]).isRegularFile ?? false) {
            out[String(u.path.dropFirst(dir.path.count))] = try Data(contentsOf: u)
        }
        return out
    }

    func testSameSeedGivesByteIdenticalBundles() throws {
        let s = SimulationScenario(name: "det", from: "room-116", to: "room-103", seed: 77, wrongTurn: true, rateHz: 15)
        let a = tempDir("a"), b = tempDir("b")
        defer { try? FileManager.default.removeItem(at: a); try? FileManager.default.removeItem(at: b) }
        try WalkSimulator.simulate(building: Fixtures.office, scenario: s).write(to: a)
        try WalkSimulator.simulate(building: Fixtures.office, scenario: s).write(to: b)
        let fa = try files(a), fb = try files(b)
        XCTAssertEqual(Set(fa.keys), ["/session.json", "/frames.jsonl", "/observations.jsonl", "/truth.jsonl", "/planes.jsonl"])
        XCTAssertEqual(fa, fb)
    }

    func testDifferentSeedsDiffer() throws {
        let a = try WalkSimulator.simulate(building: Fixtures.office, scenario: SimulationScenario(name: "s", from: "room-101", to: "room-111", seed: 1))
        let b = try WalkSimulator.simulate(building: Fixtures.office, scenario: SimulationScenario(name: "s", from: "room-101", to: "room-111", seed: 2))
        XCTAssertNotEqual(a.truth.map(\.x), b.truth.map(\.x))
        XCTAssertNotEqual(a.diagnostics.vio.scale, b.diagnostics.vio.scale)
        XCTAssertNotEqual(a.observations.map(\.rangeMeters), b.observations.map(\.rangeMeters))
        XCTAssertEqual(a.diagnostics.routeNodeIds, b.diagnostics.routeNodeIds, "same route, different walk")
    }

    func testBundleRoundTripsThroughTheReader() throws {
        let s = SimulationScenario(name: "rt", from: "room-105", to: "room-214", seed: 4, startKnown: false, trackingLossAt: 10)
        let w = try Fixtures.walk(s)
        let dir = tempDir("rt")
        defer { try? FileManager.default.removeItem(at: dir) }
        try w.write(to: dir)
        let bundle = try SessionBundle.read(from: dir)
        XCTAssertTrue(bundle.warnings.isEmpty, "\(bundle.warnings)")
        XCTAssertEqual(bundle.frames, w.frames)
        XCTAssertEqual(bundle.truth, w.truth)
        XCTAssertEqual(bundle.observations, w.observations)
        XCTAssertEqual(bundle.info.mapId, "wayfinder-office")
        XCTAssertEqual(bundle.info.floorId, "1")
        XCTAssertNil(bundle.info.start, "floor-only start")
        XCTAssertEqual(bundle.info.destination, "room-214")
        XCTAssertEqual(bundle.info.device, "simulator")
        XCTAssertEqual(bundle.info.signHeightMeters, 0.21)
        // Writing over an existing bundle needs overwrite.
        XCTAssertThrowsError(try w.write(to: dir))
        XCTAssertNoThrow(try w.write(to: dir, overwrite: true))
    }

    func testKnownStartNamesTheStartPlace() throws {
        let w = try WalkSimulator.simulate(building: Fixtures.office, scenario: SimulationScenario(
            name: "k", from: "Room 101", to: "room-103", seed: 1, startKnown: true, rateHz: 10))
        XCTAssertEqual(w.info.start, "room-101")
    }

    func testDeclaredStartNamesTheWrongPlaceAndMustExist() throws {
        var scenario = SimulationScenario(name: "d", from: "room-101", to: "room-103", seed: 1, rateHz: 10, declaredStart: "Room 112")
        let w = try WalkSimulator.simulate(building: Fixtures.office, scenario: scenario)
        XCTAssertEqual(w.info.start, "room-112")
        let truthStart = try XCTUnwrap(w.truth.first)
        let room101 = try XCTUnwrap(Fixtures.office.pointOfInterest(idOrName: "room-101")).poi.position
        XCTAssertLessThan(hypot(truthStart.x - room101.x, truthStart.y - room101.y), 3, "the walk still begins at `from`")
        scenario.declaredStart = "no-such-room"
        XCTAssertThrowsError(try WalkSimulator.simulate(building: Fixtures.office, scenario: scenario)) { e in
            XCTAssertTrue("\(e)".contains("declaredStart") && "\(e)".contains("no-such-room"), "\(e)")
        }
    }

    /// Issue 14, "nothing lost": the files used to be written in batches of 512 lines with every
    /// observation last, so a kill lost up to 511 lines per file and all observations. Now they are written
    /// interleaved in time order in group flushes of `SimulatedWalk.flushEveryLines`: looked at mid-write,
    /// the files on disk always hold every line appended so far except at most flushEveryLines - 1 in all.
    func testFilesAreWrittenInterleavedInTimeOrderInSmallBatches() throws {
        let w = try Fixtures.walk(SimulationScenario(name: "il", from: "room-101", to: "room-111", seed: 5, rateHz: 10))
        XCTAssertGreaterThan(w.observations.count, 20, "the walk has observations to interleave")
        let dir = tempDir("interleave")
        defer { try? FileManager.default.removeItem(at: dir) }
        func linesOnDisk(_ name: String) -> Int {
            ((try? Data(contentsOf: dir.appendingPathComponent(name))) ?? Data()).reduce(0) { $0 + ($1 == 0x0A ? 1 : 0) }
        }
        var checked = 0, observationsSeenMidWrite = 0
        try w.write(to: dir, overwrite: false) { i in
            guard i % 9 == 0 else { return }
            checked += 1
            let appendedObservations = w.observations.prefix { $0.t <= w.frames[i].t }.count
            let appended = [i + 1, i + 1, appendedObservations]
            let onDisk = [linesOnDisk("frames.jsonl"), linesOnDisk("truth.jsonl"), linesOnDisk("observations.jsonl")]
            for (a, d) in zip(appended, onDisk) { XCTAssertLessThanOrEqual(d, a) }
            let pending = zip(appended, onDisk).map { $0 - $1 }.reduce(0, +)
            XCTAssertLessThan(pending, SimulatedWalk.flushEveryLines,
                              "frame \(i): appended \(appended), on disk \(onDisk): more than a small batch held back")
            if i < w.frames.count - 1 { observationsSeenMidWrite = max(observationsSeenMidWrite, onDisk[2]) }
        }
        XCTAssertGreaterThan(checked, 10)
        XCTAssertGreaterThan(observationsSeenMidWrite, 0, "observations reach the disk while frames are still being written")
        XCTAssertEqual(SimulatedWalk.flushEveryLines, 16)
        // The finished bundle is still complete and byte-for-byte what the reader reads back.
        let b = try SessionBundle.read(from: dir)
        XCTAssertEqual(b.frames, w.frames)
        XCTAssertEqual(b.observations, w.observations)
        XCTAssertEqual(b.truth, w.truth)
    }
}
