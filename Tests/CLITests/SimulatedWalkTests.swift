import Foundation
import XCTest

/// `wayfinder simulate` writes a bundle that `inspect`, `eval` and `render` then read. One short walk on the
/// bundled office (room 105 -> room 108, around one corner, 10 Hz) is simulated once for the whole class.
final class SimulatedWalkTests: XCTestCase {
    /// Per-process folder of the shared walk (removed in the class tearDown).
    private static let sharedDirectory = FileManager.default.temporaryDirectory
        .appendingPathComponent("wf-clitests-sim-\(getpid())", isDirectory: true)
    /// Arguments of the shared walk, without -o.
    private static let walkArguments = ["simulate", "--from", "room-105", "--to", "room-108", "--seed", "11",
                                        "--rate", "10", "--detector-rate", "5"]

    /// The shared simulated bundle's path, simulated on first use.
    private static let sharedWalk: Result<String, CLITestSetupError> = {
        do {
            try FileManager.default.createDirectory(at: sharedDirectory, withIntermediateDirectories: true)
            let out = sharedDirectory.appendingPathComponent("walk-105-108").path
            let r = try CLI.run(walkArguments + ["-o", out, "--overwrite"])
            guard r.exitCode == 0 else { return .failure(.failed("simulate failed: \(r)")) }
            return .success(out)
        } catch {
            return .failure(.failed("\(error)"))
        }
    }()

    override class func tearDown() {
        try? FileManager.default.removeItem(at: sharedDirectory)
        super.tearDown()
    }

    private var directory: URL!

    override func setUpWithError() throws {
        directory = try CLI.makeTemporaryDirectory("sim")
    }

    override func tearDownWithError() throws {
        if let directory { try? FileManager.default.removeItem(at: directory) }
    }

    private func walk() throws -> String { try Self.sharedWalk.value() }

    func testSimulatedBundleHasTheFilesAndInspectReadsIt() throws {
        let bundle = try walk()
        for name in ["session.json", "frames.jsonl", "observations.jsonl", "truth.jsonl"] {
            XCTAssertTrue(FileManager.default.fileExists(atPath: "\(bundle)/\(name)"), "simulate wrote no \(name)")
        }
        let r = try CLI.run(["inspect", "--json", bundle])
        r.assertExit(0)
        let s = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [String: Any], "\(r)")
        let rate = try XCTUnwrap(jsonNumber(s["frameRateHz"]))
        XCTAssertEqual(rate, 10, accuracy: 0.1, "--rate 10 gives 10 Hz frames")
        XCTAssertEqual(s["mapId"] as? String, "wayfinder-office")
        XCTAssertEqual(s["hasTruth"] as? Bool, true)
        XCTAssertEqual(s["truthCount"] as? Int, s["frameCount"] as? Int)
        XCTAssertEqual((s["warnings"] as? [Any])?.count, 0)
        // Room 105 (28, 6) to room 108 (34, 12) is about 12 m of corridor: the phone travels 8 to 40 m.
        let path = try XCTUnwrap(jsonNumber(s["pathLengthMeters"]))
        XCTAssertGreaterThan(path, 8)
        XCTAssertLessThan(path, 40)
        let text = try CLI.run(["inspect", bundle])
        text.assertExit(0)
        text.assertStdout(contains: "at 10.00 Hz", "warnings         none")
    }

    func testSameArgumentsGiveTheSameBundleAndExistingBundleIsRefused() throws {
        let reference = try walk()
        let again = directory.appendingPathComponent("again").path
        let r = try CLI.run(Self.walkArguments + ["-o", again])
        r.assertExit(0)
        r.assertStderr(contains: "simulate: ")
        for name in ["session.json", "frames.jsonl", "observations.jsonl", "truth.jsonl"] {
            let a = try Data(contentsOf: URL(fileURLWithPath: "\(reference)/\(name)"))
            let b = try Data(contentsOf: URL(fileURLWithPath: "\(again)/\(name)"))
            XCTAssertEqual(a, b, "\(name) differs between two runs with the same seed")
        }
        // A second run onto the same bundle without --overwrite must not replace it.
        let refused = try CLI.run(Self.walkArguments + ["-o", again])
        refused.assertExit(1)
        refused.assertStderr(contains: again)
    }

    func testUnknownPlaceExitsOneNamingIt() throws {
        let out = directory.appendingPathComponent("never").path
        let r = try CLI.run(["simulate", "--from", "room-105", "--to", "room-999", "--seed", "1", "--rate", "10", "-o", out])
        r.assertExit(1)
        r.assertStderr(contains: "room-999")
        XCTAssertFalse(FileManager.default.fileExists(atPath: "\(out)/frames.jsonl"))
    }

    func testEvalPrintsTheScoreTable() throws {
        let bundle = try walk()
        let r = try CLI.run(["eval", bundle, "--map", CLI.officeMapPath], timeoutSeconds: 180)
        r.assertExit(0)
        let lines = r.stdoutLines
        let header = try XCTUnwrap(lines.first, "\(r)")
        for column in ["walk", "conv s", "med m", "p95 m", "loc %", "turns", "cued", "miss", "arrive m"] {
            XCTAssertTrue(header.contains(column), "table header lacks '\(column)': \(r)")
        }
        XCTAssertTrue(lines.count >= 3, "\(r)")
        XCTAssertTrue(lines[1].hasPrefix("walk-105-108 "), "no row for the walk: \(r)")
        XCTAssertEqual(lines[1].split(separator: " ").count, 15, "the row has one cell per column: \(r)")
        r.assertStdout(contains: "1 walks: converged within 20 m in ")
    }

    func testEvalJSONAndRegressionBaselineRoundTrip() throws {
        let bundle = try walk()
        let baseline = directory.appendingPathComponent("baseline.json").path
        let r = try CLI.run(["eval", bundle, "--map", CLI.officeMapPath, "--json", "--write-baseline", baseline],
                            timeoutSeconds: 180)
        r.assertExit(0)
        let object = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [String: Any], "\(r)")
        XCTAssertEqual((object["walks"] as? [Any])?.count, 1)
        XCTAssertNotNil(object["aggregate"] as? [String: Any])
        XCTAssertTrue(FileManager.default.fileExists(atPath: baseline), "\(r)")
        // The same replay (same seed) cannot regress against its own baseline.
        let gate = try CLI.run(["eval", bundle, "--map", CLI.officeMapPath, "--baseline", baseline], timeoutSeconds: 180)
        gate.assertExit(0)
        gate.assertStderr(contains: "no regression")
    }

    func testEvalOfABundleWithoutTruthFailsNamingIt() throws {
        let bundle = try walk()
        let copy = directory.appendingPathComponent("no-truth")
        try FileManager.default.copyItem(at: URL(fileURLWithPath: bundle), to: copy)
        try FileManager.default.removeItem(at: copy.appendingPathComponent("truth.jsonl"))
        let r = try CLI.run(["eval", copy.path, "--map", CLI.officeMapPath], timeoutSeconds: 180)
        r.assertExit(1)
        r.assertStderr(contains: copy.path)
    }

    /// `--seed` reaches the replays of `eval --scenarios` (the gates replay the suites with seeds 2 and 3): the same
    /// seed gives the same figures, another seed other draws of the filter on the same simulated walk.
    func testEvalScenariosHonoursTheFilterSeed() throws {
        let scenarios = directory.appendingPathComponent("one-scenario")
        try FileManager.default.createDirectory(at: scenarios, withIntermediateDirectories: true)
        try FileManager.default.copyItem(at: CLI.repo("Tests/Scenarios/office-entrance-to-rear-exit.json"),
                                         to: scenarios.appendingPathComponent("office-entrance-to-rear-exit.json"))
        func walkJSON(seed: Int) throws -> String {
            let r = try CLI.run(["eval", "--scenarios", scenarios.path, "--json", "--seed", String(seed)], timeoutSeconds: 180)
            r.assertExit(0)
            let object = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [String: Any], "\(r)")
            let walks = try XCTUnwrap(object["walks"] as? [Any], "\(r)")
            XCTAssertEqual(walks.count, 1, "\(r)")
            let data = try JSONSerialization.data(withJSONObject: walks[0], options: [.sortedKeys])
            return String(decoding: data, as: UTF8.self)
        }
        let first = try walkJSON(seed: 1)
        XCTAssertEqual(try walkJSON(seed: 1), first, "the same seed replays the same walk identically")
        XCTAssertNotEqual(try walkJSON(seed: 7), first, "another seed draws other particles")
    }

    func testEvalOfAMissingScenarioFolderExitsOneNamingIt() throws {
        let missing = directory.appendingPathComponent("no-scenarios-here").path
        let r = try CLI.run(["eval", "--scenarios", missing])
        r.assertExit(1)
        r.assertStderr(contains: "wayfinder eval: ", "no-scenarios-here")
        XCTAssertTrue(r.stdout.isEmpty, "\(r)")
    }

    func testRenderWritesHTMLAndPNG() throws {
        let bundle = try walk()
        let html = directory.appendingPathComponent("walk.html")
        let png = directory.appendingPathComponent("walk.png")
        let chromium = Self.chromiumOnPath()
        var arguments = ["render", bundle, "--map", CLI.officeMapPath, "-o", html.path, "--at", "2,5"]
        if chromium { arguments += ["--png", png.path] }
        let r = try CLI.run(arguments, timeoutSeconds: 180)
        r.assertExit(0)
        r.assertStderr(contains: "render: wrote \(html.path)")
        let page = try String(contentsOf: html, encoding: .utf8)
        XCTAssertTrue(page.lowercased().hasPrefix("<!doctype html"), "not an HTML page: \(page.prefix(200))")
        XCTAssertTrue(page.contains("</html>"))
        XCTAssertTrue(page.contains("<svg"), "the plan is drawn as SVG")
        XCTAssertFalse(page.contains("src=\"http") || page.contains("href=\"http"), "the page must be self-contained")
        if chromium {
            let data = try Data(contentsOf: png)
            XCTAssertEqual(Array(data.prefix(8)), [0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A], "not a PNG")
            XCTAssertGreaterThan(data.count, 10_000, "the screenshot is nearly empty")
        }
    }

    func testBenchReportsRowsWithBaselines() throws {
        let bundle = try walk()
        let r = try CLI.run(["bench", "--iterations", "5", "--bundle", bundle, "--map", CLI.officeMapPath, "--json"],
                            timeoutSeconds: 180)
        r.assertExit(0)
        let rows = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [[String: Any]], "\(r)")
        let names = rows.compactMap { $0["name"] as? String }
        XCTAssertTrue(names.contains { $0.hasPrefix("navigation.") }, "\(names)")
        XCTAssertTrue(names.contains { $0.hasPrefix("pipeline.frame") }, "\(names)")
        for row in rows {
            let ns = try XCTUnwrap(jsonNumber(row["nanosecondsPerOp"]), "\(row)")
            XCTAssertTrue(ns.isFinite && ns > 0, "\(row)")
        }
    }

    /// True when a chromium executable is on PATH (the render command's --png needs one).
    private static func chromiumOnPath() -> Bool {
        let path = ProcessInfo.processInfo.environment["PATH"] ?? "/usr/bin:/bin"
        return path.split(separator: ":").contains { dir in
            ["chromium", "chromium-browser", "google-chrome"].contains {
                FileManager.default.isExecutableFile(atPath: "\(dir)/\($0)")
            }
        }
    }
}
