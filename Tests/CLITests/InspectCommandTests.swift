import Foundation
import XCTest

/// `wayfinder inspect` on the committed sample walk and on damaged copies of it (docs/session-format.md):
/// a missing mandatory file or a bad line in the middle exits 1 naming file and line; a cut-off last line
/// (a crash while recording) is a warning and exits 0.
final class InspectCommandTests: XCTestCase {
    private var directory: URL!

    override func setUpWithError() throws {
        directory = try CLI.makeTemporaryDirectory("inspect")
    }

    override func tearDownWithError() throws {
        if let directory { try? FileManager.default.removeItem(at: directory) }
    }

    /// A writable copy of the sample bundle in the temporary directory.
    private func copyOfSample(_ name: String) throws -> URL {
        let source = try CLI.requireSampleBundle()
        let copy = directory.appendingPathComponent(name, isDirectory: true)
        try FileManager.default.copyItem(at: source, to: copy)
        return copy
    }

    /// The lines of a JSON-lines file (without their newline).
    private func lines(_ url: URL) throws -> [String] {
        try String(contentsOf: url, encoding: .utf8).split(separator: "\n", omittingEmptySubsequences: true).map(String.init)
    }

    func testSampleBundleSummary() throws {
        let sample = try CLI.requireSampleBundle()
        let frameCount = try lines(sample.appendingPathComponent("frames.jsonl")).count
        let truthCount = try lines(sample.appendingPathComponent("truth.jsonl")).count
        let r = try CLI.run(["inspect", CLI.sampleBundlePath])
        r.assertExit(0)
        r.assertStdout(contains: "format version   1", "map              wayfinder-office",
                       "frames           \(frameCount) at ", "truth            \(truthCount) poses",
                       "warnings         none")
        XCTAssertTrue(r.stdout.contains("observations     "), "\(r)")
    }

    func testSampleBundleJSON() throws {
        let sample = try CLI.requireSampleBundle()
        let frameCount = try lines(sample.appendingPathComponent("frames.jsonl")).count
        let observationCount = try lines(sample.appendingPathComponent("observations.jsonl")).count
        let r = try CLI.run(["inspect", "--json", CLI.sampleBundlePath])
        r.assertExit(0)
        let object = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [String: Any], "\(r)")
        XCTAssertEqual(object["formatVersion"] as? Int, 1)
        XCTAssertEqual(object["frameCount"] as? Int, frameCount)
        XCTAssertEqual(object["observationCount"] as? Int, observationCount)
        XCTAssertEqual(object["hasTruth"] as? Bool, true)
        XCTAssertEqual((object["warnings"] as? [Any])?.count, 0)
        let rate = try XCTUnwrap(jsonNumber(object["frameRateHz"]))
        XCTAssertGreaterThan(rate, 1)
    }

    func testMissingBundleDirectoryExitsOne() throws {
        let path = directory.appendingPathComponent("nothing-here").path
        let r = try CLI.run(["inspect", path])
        r.assertExit(1)
        r.assertStderr(contains: path, "not found")
    }

    func testMissingFramesFileExitsOneNamingIt() throws {
        let bundle = try copyOfSample("no-frames")
        try FileManager.default.removeItem(at: bundle.appendingPathComponent("frames.jsonl"))
        let r = try CLI.run(["inspect", bundle.path])
        r.assertExit(1)
        r.assertStderr(contains: bundle.appendingPathComponent("frames.jsonl").path)
        XCTAssertTrue(r.stdout.isEmpty, "\(r)")
    }

    func testBadLineInTheMiddleNamesFileAndLine() throws {
        let bundle = try copyOfSample("bad-middle")
        let frames = bundle.appendingPathComponent("frames.jsonl")
        var text = try lines(frames)
        XCTAssertGreaterThan(text.count, 60)
        text[49] = "{\"t\": 4.9, \"tracking\": \"normal\", \"cameraToWorld\": [1, 0"   // line 50, cut off mid-file
        try Data((text.joined(separator: "\n") + "\n").utf8).write(to: frames)
        let r = try CLI.run(["inspect", bundle.path])
        r.assertExit(1)
        r.assertStderr(contains: "\(frames.path) line 50")
    }

    func testWrongTypeInTheMiddleNamesFileAndLine() throws {
        let bundle = try copyOfSample("bad-record")
        let observations = bundle.appendingPathComponent("observations.jsonl")
        var text = try lines(observations)
        XCTAssertGreaterThan(text.count, 10)
        text[6] = "{\"t\": \"soon\"}"   // line 7: valid JSON, not an observation
        try Data((text.joined(separator: "\n") + "\n").utf8).write(to: observations)
        let r = try CLI.run(["inspect", bundle.path])
        r.assertExit(1)
        r.assertStderr(contains: "\(observations.path) line 7")
    }

    func testTruncatedLastLineIsAWarningAndExitsZero() throws {
        let bundle = try copyOfSample("cut-last")
        let frames = bundle.appendingPathComponent("frames.jsonl")
        var text = try lines(frames)
        let total = text.count
        let last = text.removeLast()
        let cut = text.joined(separator: "\n") + "\n" + String(last.prefix(last.count / 2))   // no final newline
        try Data(cut.utf8).write(to: frames)
        let r = try CLI.run(["inspect", bundle.path])
        r.assertExit(0)
        r.assertStdout(contains: "frames           \(total - 1) at ", "warnings         1", "\(frames.path) line \(total)")
    }

    func testSeveralBundlesAsJSONArray() throws {
        _ = try CLI.requireSampleBundle()
        let r = try CLI.run(["inspect", "--json", CLI.sampleBundlePath, CLI.sampleBundlePath])
        r.assertExit(0)
        let array = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [Any], "\(r)")
        XCTAssertEqual(array.count, 2)
    }
}
