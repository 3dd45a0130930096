import XCTest
import Maps
import SessionFormat
import Simulation
@testable import WayfinderCore
@testable import Evaluation

/// The trainer's picture: a simulated SKERI walk rendered to HTML and, through headless Chromium, to PNG.
final class WalkReportTests: XCTestCase {
    static let root = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent().deletingLastPathComponent()

    func scenario() throws -> SimulationScenario {
        try SimulationScenario.load(contentsOf: Self.root.appendingPathComponent("Tests/Scenarios/skeri-3-corridor.json"))
    }

    func testSkeriWalkRendersHTMLAndPNG() throws {
        let shared = Self.root.appendingPathComponent("../shared/data").standardizedFileURL
        guard FileManager.default.fileExists(atPath: shared.appendingPathComponent("skeri_inavigate").path) else {
            throw XCTSkip("../shared/data/skeri_inavigate is not present")
        }
        var s = try scenario()
        s.rateHz = 10
        var options = PipelineOptions()
        options.localizer.particleCount = 5000
        let (score, result, building, bundle) = try ScenarioRunner.score(s, sharedData: shared, options: options)
        let html = WalkReport.html(title: "SKERI walk", building: building, result: result, truth: bundle.truth, score: score)
        XCTAssertTrue(html.hasPrefix("<!DOCTYPE html>"))
        XCTAssertTrue(html.contains("<polyline"), "paths are drawn")
        XCTAssertTrue(html.contains("Exit") || html.contains("exit sign"), "signs are drawn")
        XCTAssertTrue(html.contains("<h2>Announcements</h2>"))
        XCTAssertFalse(html.contains("http://") && html.contains("<script src"), "self-contained")
        for a in result.announcements.prefix(5) { XCTAssertTrue(html.contains(WalkReport.escape(a.text))) }

        try requireChromium()
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-render-\(getpid())")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        defer { try? FileManager.default.removeItem(at: dir) }
        let htmlURL = dir.appendingPathComponent("walk.html"), pngURL = dir.appendingPathComponent("walk.png")
        try Data(html.utf8).write(to: htmlURL)
        try ChromiumScreenshot.capture(html: htmlURL, png: pngURL, width: 1400, height: 1100)
        let size = try XCTUnwrap(ChromiumScreenshot.pngSize(pngURL))
        XCTAssertEqual(size.width, 1400)
        XCTAssertEqual(size.height, 1100)
        let bytes = try FileManager.default.attributesOfItem(atPath: pngURL.path)[.size] as! Int
        XCTAssertGreaterThan(bytes, 40_000, "a blank page compresses to a few KB; the plan and paths do not")
    }

    func testHostileFloorIdNeverBecomesScript() throws {
        // Issue 14: this floor id (made in code, past the map validator, which refuses it) used to close the
        // string of onclick="showFloor('ID')" and run in the browser.
        let hostile = "2');document.title='PWNED';//"
        func floor(_ id: String, _ name: String) -> Floor {
            Floor(id: id, name: name, elevationMeters: id == "1" ? 0 : 3,
                  walls: [Wall(from: Point2(0, 0), to: Point2(10, 0)), Wall(from: Point2(10, 0), to: Point2(10, 4))])
        }
        let building = Building(id: "b", name: "B", floors: [floor("1", "One"), floor(hostile, "Two <b>\"'")],
                                graph: NavigationGraph(nodes: [], edges: []))
        func record(_ t: Double, _ f: String) -> TraceRecord {
            TraceRecord(t: t, x: 1, y: 1, floorId: f, headingRad: 0, confidence: 1, localized: true, hypotheses: 1,
                        sightings: 0, announcements: [], haptics: [])
        }
        let result = ReplayResult(trace: [record(0, "1"), record(1, hostile)], announcements: [], haptics: [], sightingRays: [],
                                  particleSnapshots: [], routePolyline: [], warnings: [])
        let truth = [TruthRecord(t: 0, x: 1, y: 1, floorId: "1", headingRad: 0), TruthRecord(t: 1, x: 1, y: 1, floorId: hostile, headingRad: 0)]
        let html = WalkReport.html(title: "t", building: building, result: result, truth: truth, score: nil)
        XCTAssertFalse(html.contains("onclick"), "no inline event handlers")
        XCTAssertFalse(html.contains("showFloor("), "no script built around data")
        XCTAssertFalse(html.contains("document.title='"), "the id's quotes are escaped wherever it appears")
        XCTAssertTrue(html.contains("data-floor-id=\"2&#39;);document.title=&#39;PWNED&#39;;//\""), "the id survives as inert attribute text")
        XCTAssertTrue(html.contains("<button type=\"button\" data-floor=\"1\" aria-controls=\"floor-section-1\">Two &lt;b&gt;&quot;&#39;</button>"))
        // The only executable script is the fixed player (floor switcher included), identical whatever the map
        // says; the walk's data sits in a JSON element that is never executed.
        let scripts = html.components(separatedBy: "<script>").dropFirst().map { $0.components(separatedBy: "</script>")[0] }
        XCTAssertEqual(scripts.count, 1)
        XCTAssertEqual("<script>" + scripts[0] + "</script>", WalkViewScript.source)
        XCTAssertEqual(html.components(separatedBy: "<script type=\"application/json\" id=\"walk-data\">").count, 2)
        XCTAssertEqual(WalkReport.escape("a&<>\"'b"), "a&amp;&lt;&gt;&quot;&#39;b")

        // In a real browser: the id never runs, and the floor buttons still switch floors.
        try requireChromium()
        let chromium = try XCTUnwrap(ChromiumScreenshot.executable())
        let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-render-hostile-\(getpid())")
        try FileManager.default.createDirectory(at: dir, withIntermediateDirectories: true)
        defer { try? FileManager.default.removeItem(at: dir) }
        // A test-only probe after the page's own script: press the second floor's button.
        let probe = "<script>document.querySelector('nav button[data-floor=\"1\"]').click();</script></body>"
        let page = dir.appendingPathComponent("walk.html")
        try Data(html.replacingOccurrences(of: "</body>", with: probe).utf8).write(to: page)
        let p = Process()
        p.executableURL = URL(fileURLWithPath: chromium)
        p.arguments = ["--headless", "--disable-gpu", "--no-sandbox", "--disable-dev-shm-usage",
                       "--user-data-dir=\(dir.appendingPathComponent("profile").path)", "--dump-dom", page.absoluteString]
        let out = Pipe()
        p.standardOutput = out
        p.standardError = FileHandle.nullDevice
        try p.run()
        let dom = String(decoding: out.fileHandleForReading.readDataToEndOfFile(), as: UTF8.self)
        p.waitUntilExit()
        XCTAssertTrue(dom.contains("<title>t</title>"), "the title was not rewritten by the id: \(dom.prefix(300))")
        XCTAssertFalse(dom.contains("PWNED</title>"))
        XCTAssertTrue(dom.contains("id=\"floor-section-1\" data-floor=\"1\""), "\(dom.prefix(2000))")
        let second = try XCTUnwrap(dom.range(of: "id=\"floor-section-1\""))
        XCTAssertTrue(dom[second.upperBound...].prefix(400).contains("display: block"), "the second floor's button shows it")
        let first = try XCTUnwrap(dom.range(of: "id=\"floor-section-0\""))
        XCTAssertTrue(dom[first.upperBound...].prefix(400).contains("display: none"), "and hides the first")
    }

    func testTrueTurnsOnAnLShapedPath() {
        // Walk east 10 m then north 10 m at 1 m/s, passing a control node at the corner.
        var truth: [TruthRecord] = []
        for i in 0...100 { truth.append(TruthRecord(t: Double(i) / 10, x: Double(i) / 10, y: 0, floorId: "1", headingRad: 0)) }
        for i in 1...100 { truth.append(TruthRecord(t: 10 + Double(i) / 10, x: 10, y: Double(i) / 10, floorId: "1", headingRad: .pi / 2)) }
        let graph = NavigationGraph(nodes: [GraphNode(id: "c", kind: .control, floorId: "1", position: Point2(10, 0))], edges: [])
        let building = Building(id: "b", name: "b", floors: [], graph: graph)
        let turns = NavigationScore.trueTurns(truth: TruthTrack(truth), building: building)
        XCTAssertEqual(turns.count, 1)
        XCTAssertEqual(turns[0].direction, "left")
        XCTAssertEqual(turns[0].angleDeg, 90, accuracy: 1)
        // A cue 1 m before the corner counts; a right cue is wrong.
        let score = NavigationScore(announcements: [(9.0, "Turn left now"), (15, "Turn right now")], truth: TruthTrack(truth),
                                    building: building, destination: nil, convergenceT: 0)
        XCTAssertEqual(score.cueDistancesBeforeMeters.count, 1)
        XCTAssertEqual(score.cueDistancesBeforeMeters[0], 1.0, accuracy: 0.05)
        XCTAssertEqual(score.missingInstructions, 0)
        XCTAssertEqual(score.wrongInstructions, 1)
    }
    func testTurnIntoTheDestinationDoorAtTheEndOfTheWalk() {
        // East along y = 7 for 10 m, then right 1 m into a door at (10, 6): the door node and the corridor
        // control point are one turn, and the walk ends at the door.
        var truth: [TruthRecord] = []
        for i in 0...100 { truth.append(TruthRecord(t: Double(i) / 10, x: Double(i) / 10, y: 7, floorId: "1", headingRad: 0)) }
        for i in 1...10 { truth.append(TruthRecord(t: 10 + Double(i) / 10, x: 10, y: 7 - Double(i) / 10, floorId: "1", headingRad: -.pi / 2)) }
        let graph = NavigationGraph(nodes: [GraphNode(id: "cp", kind: .control, floorId: "1", position: Point2(10, 7)),
                                            GraphNode(id: "door", kind: .pointOfInterest, floorId: "1", position: Point2(10, 6))], edges: [])
        let building = Building(id: "b", name: "b", floors: [], graph: graph)
        let turns = NavigationScore.trueTurns(truth: TruthTrack(truth), building: building)
        XCTAssertEqual(turns.map(\.direction), ["right"])
    }
}
