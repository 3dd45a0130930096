import Foundation
import XCTest

/// `wayfinder validate-map` on the bundled office and on damaged copies written to a temporary directory:
/// each damage must exit 1 with "error: FILE: JSONPATH: reason" on stderr (docs/map-format.md, validation rules).
final class ValidateMapCommandTests: XCTestCase {
    private var directory: URL!
    private var officeText = ""

    override func setUpWithError() throws {
        directory = try CLI.makeTemporaryDirectory("maps")
        officeText = try String(contentsOf: CLI.repo(CLI.officeMapPath), encoding: .utf8)
    }

    override func tearDownWithError() throws {
        if let directory { try? FileManager.default.removeItem(at: directory) }
    }

    /// The office text with the first `target` after the first `anchor` replaced; fails when either is absent
    /// (the office file changed layout and this test must follow).
    private func office(replacing target: String, with replacement: String, after anchor: String) throws -> String {
        guard let a = officeText.range(of: anchor) else {
            XCTFail("anchor \(anchor) not in the office map"); throw CocoaError(.fileReadCorruptFile)
        }
        guard let t = officeText.range(of: target, range: a.lowerBound..<officeText.endIndex) else {
            XCTFail("\(target) not found after \(anchor) in the office map"); throw CocoaError(.fileReadCorruptFile)
        }
        var text = officeText
        text.replaceSubrange(t, with: replacement)
        return text
    }

    /// Writes `text` as NAME in the temporary directory and returns its path.
    private func write(_ text: String, as name: String) throws -> String {
        let url = directory.appendingPathComponent(name)
        try Data(text.utf8).write(to: url)
        return url.path
    }

    /// Validates a damaged map and checks exit 1 and the message "error: PATH: JSONPATH: ...reason...".
    private func assertRejected(_ text: String, name: String, jsonPath: String, reason: String,
                                file: StaticString = #filePath, line: UInt = #line) throws {
        let path = try write(text, as: name)
        let r = try CLI.run(["validate-map", path], file: file, line: line)
        r.assertExit(1, file: file, line: line)
        r.assertStderr(contains: "error: \(path): \(jsonPath): ", reason, file: file, line: line)
        XCTAssertFalse(r.stdout.contains("ok:"), "a damaged map was reported ok: \(r)", file: file, line: line)
    }

    func testBundledOfficeIsValid() throws {
        let r = try CLI.run(["validate-map", CLI.officeMapPath])
        r.assertExit(0)
        XCTAssertEqual(r.stdoutLines.count, 1, "\(r)")
        let line = try XCTUnwrap(r.stdoutLines.first)
        XCTAssertTrue(line.hasPrefix("ok: \(CLI.officeMapPath): 2 floors, "), "\(r)")
        for word in ["walls", "signs", "POIs", "nodes"] { XCTAssertTrue(line.contains(word), "\(r)") }
        XCTAssertEqual(r.stderr, "", "\(r)")
    }

    func testBundledOfficeByNameMatchesTheFile() throws {
        let byName = try CLI.run(["validate-map", "bundled:office"])
        byName.assertExit(0)
        let byFile = try CLI.run(["validate-map", CLI.officeMapPath])
        // Same counts whichever way the office is named.
        XCTAssertEqual(byName.stdout.replacingOccurrences(of: "bundled:office", with: CLI.officeMapPath), byFile.stdout)
    }

    func testTruncatedJSONIsRejectedAtTheDocumentRoot() throws {
        let text = String(officeText.prefix(officeText.count * 2 / 5))
        try assertRejected(text, name: "truncated.json", jsonPath: "$", reason: "not valid JSON")
    }

    func testDanglingEdgeIsRejectedAtItsEnd() throws {
        let text = try office(replacing: "\"to\" : \"room-101\"", with: "\"to\" : \"room-999\"", after: "\"edges\"")
        try assertRejected(text, name: "dangling-edge.json", jsonPath: "$.graph.edges[0].to", reason: "room-999")
    }

    func testOverflowingNumberIsRejectedAtItsPath() throws {
        // 1e999 is valid JSON syntax but no finite double: the loader must name where it is.
        let text = try office(replacing: "\"from\" : [0, 0]", with: "\"from\" : [1e999, 0]", after: "\"walls\"")
        try assertRejected(text, name: "overflow.json", jsonPath: "$.floors[0].walls[0].from[0]", reason: "finite")
    }

    func testNaNStringIsRejectedAtItsPath() throws {
        // Keys are sorted in the file: the first "heightMeters" after "signs" is the first sign's.
        let text = try office(replacing: "\"heightMeters\" : 0.21", with: "\"heightMeters\" : \"NaN\"", after: "\"signs\"")
        try assertRejected(text, name: "nan.json", jsonPath: "$.floors[0].signs[0].heightMeters", reason: "NaN")
    }

    func testSignFarFromAnyWallIsRejected() throws {
        let text = try office(replacing: "\"position\" : [6, 7]", with: "\"position\" : [-50, -50]", after: "\"signs\"")
        try assertRejected(text, name: "floating-sign.json", jsonPath: "$.floors[0].signs[0].position",
                           reason: "not on a wall")
    }

    func testMissingFileExitsOneNamingIt() throws {
        let path = directory.appendingPathComponent("no-such-map.json").path
        let r = try CLI.run(["validate-map", path])
        r.assertExit(1)
        r.assertStderr(contains: path, "no such file")
    }

    func testSeveralMapsReportEachAndCountFailures() throws {
        let bad = try write(String(officeText.prefix(100)), as: "cut.json")
        let r = try CLI.run(["validate-map", CLI.officeMapPath, bad])
        r.assertExit(1)
        r.assertStdout(contains: "ok: \(CLI.officeMapPath)")
        r.assertStderr(contains: "error: \(bad): $: ", "1 of 2 maps invalid")
    }
}
