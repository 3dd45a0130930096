import Foundation
import XCTest
#if canImport(Glibc)
import Glibc
#elseif canImport(Darwin)
import Darwin
#endif

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
        // The counts, then the office's two floors, each symmetric under a half turn about the plan's centre
        // (docs/localizer.md "Symmetric twins").
        XCTAssertEqual(r.stdoutLines.count, 3, "\(r)")
        let line = try XCTUnwrap(r.stdoutLines.first)
        XCTAssertTrue(line.hasPrefix("ok: \(CLI.officeMapPath): 2 floors, "), "\(r)")
        for word in ["walls", "signs", "POIs", "nodes"] { XCTAssertTrue(line.contains(word), "\(r)") }
        for symmetry in r.stdoutLines.dropFirst() {
            XCTAssertTrue(symmetry.hasPrefix("  floor "), "\(r)")
            XCTAssertTrue(symmetry.contains("symmetric under a half turn about (20.0, 12.0) (9"), "\(r)")
        }
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

    /// Index of the ground floor's first Exit sign in the office file (placards and pictograms come before it).
    private func firstExitSignIndex() throws -> Int {
        let json = try JSONSerialization.jsonObject(with: Data(officeText.utf8)) as? [String: Any]
        let floors = try XCTUnwrap(json?["floors"] as? [[String: Any]])
        let signs = try XCTUnwrap(floors.first?["signs"] as? [[String: Any]])
        return try XCTUnwrap(signs.firstIndex { $0["kind"] as? String == "exit" })
    }

    func testNaNStringIsRejectedAtItsPath() throws {
        // Keys are sorted in the file: the first "heightMeters" of 0.21 after "signs" is the first Exit sign's.
        let text = try office(replacing: "\"heightMeters\" : 0.21", with: "\"heightMeters\" : \"NaN\"", after: "\"signs\"")
        try assertRejected(text, name: "nan.json", jsonPath: "$.floors[0].signs[\(try firstExitSignIndex())].heightMeters",
                           reason: "NaN")
    }

    func testSignFarFromAnyWallIsRejected() throws {
        let text = try office(replacing: "\"position\" : [6, 7]", with: "\"position\" : [-50, -50]", after: "\"signs\"")
        try assertRejected(text, name: "floating-sign.json", jsonPath: "$.floors[0].signs[\(try firstExitSignIndex())].position",
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

    // MARK: issue 14 (hardening)

    /// The office with one wall added in front of the ground floor's walls (so it is $.floors[0].walls[0]).
    private func officeWithExtraGroundFloorWall(from a: (Double, Double), to b: (Double, Double)) throws -> String {
        try office(replacing: "\"walls\" : [", with: "\"walls\" : [{\"from\": [\(a.0), \(a.1)], \"to\": [\(b.0), \(b.1)]},",
                   after: "\"floors\"")
    }

    func testHugeNumberIsReportedNotACrash() throws {
        // The issue's reproducer: once SIGILL (exit 132) while formatting the error.
        let text = #"{"formatVersion":1,"id":"b","name":"B","floors":[{"id":"1","name":"F","elevationMeters":1e19,"walls":[{"from":[0,0],"to":[1,0]}]}],"graph":{"nodes":[{"id":"n","kind":"control","floorId":"1","position":[0,1]}],"edges":[]}}"#
        try assertRejected(text, name: "huge.json", jsonPath: "$.floors[0].elevationMeters",
                           reason: "elevation (meters) 1e+19 is out of range [-1000, 1000]")
    }

    func testEdgeThroughAWallIsRejectedByValidateMapAndSimulateAlike() throws {
        // The simulator's own check (WalkerTests.testRouteThroughAWallIsRefused) with the same wall across the
        // south corridor: one rule, so validate-map refuses the map too, and simulate says the same.
        let text = try officeWithExtraGroundFloorWall(from: (10, 6.2), to: (10, 7.8))
        let path = try write(text, as: "wall-across-corridor.json")
        let v = try CLI.run(["validate-map", path])
        v.assertExit(1)
        v.assertStderr(contains: "error: \(path): $.graph.edges[", "crosses or touches the wall $.floors[0].walls[0] (from [10, 6.2] to [10, 7.8])")
        let out = directory.appendingPathComponent("bundle").path
        let s = try CLI.run(["simulate", "--map", path, "--from", "room-101", "--to", "room-106", "--seed", "1", "-o", out])
        s.assertExit(1)
        s.assertStderr(contains: "crosses or touches the wall $.floors[0].walls[0]")
        XCTAssertFalse(FileManager.default.fileExists(atPath: out + "/frames.jsonl"), "\(s)")
    }

    func testPointOfInterestInsideAWallIsRejected() throws {
        // The office's first ground-floor point of interest moved onto the wall along y = 0.
        let anchor = "\"pointsOfInterest\" : ["
        guard let a = officeText.range(of: anchor),
              let p = officeText.range(of: "\"position\" : [", range: a.upperBound..<officeText.endIndex),
              let close = officeText.range(of: "]", range: p.upperBound..<officeText.endIndex) else {
            return XCTFail("office layout changed: no point of interest position")
        }
        var text = officeText
        text.replaceSubrange(p.lowerBound..<close.upperBound, with: "\"position\" : [0.5, 0]")
        let r = try CLI.run(["validate-map", try write(text, as: "poi-in-wall.json")])
        r.assertExit(1)
        r.assertStderr(contains: "$.floors[0].pointsOfInterest[0].position: ", "is inside or against a wall",
                       "is 0 m away (at least 0.2 m needed")
    }

    func testScriptInAFloorIdIsRejected() throws {
        let text = try office(replacing: "\"id\" : \"1\"", with: "\"id\" : \"2');document.title='PWNED';//\"", after: "\"floors\"")
        try assertRejected(text, name: "hostile-floor-id.json", jsonPath: "$.floors[0].id",
                           reason: "identifier contains the character U+0027 (') at position 2; identifiers may use only A-Z a-z 0-9 . _ : -")
    }

    func testFloorWiderThanTheCoreAllowsIsRejectedFirst() throws {
        // Within +-100 km per coordinate but 120 km across: validate-map (not the localizer, later) refuses it.
        var text = try officeWithExtraGroundFloorWall(from: (-60000, 0), to: (-59999, 0))
        text = text.replacingOccurrences(of: "\"walls\" : [{", with: "\"walls\" : [{\"from\": [60000, 0], \"to\": [60001, 0]}, {")
        try assertRejected(text, name: "wide.json", jsonPath: "$.floors[0]", reason: "spans 120001 m x ")
    }

    func testNonRegularFilesAndLinkLoopsGiveTheirReason() throws {
        let fifo = directory.appendingPathComponent("pipe.json").path
        XCTAssertEqual(mkfifo(fifo, 0o644), 0)
        let a = directory.appendingPathComponent("loop-a.json").path, b = directory.appendingPathComponent("loop-b.json").path
        try FileManager.default.createSymbolicLink(atPath: a, withDestinationPath: b)
        try FileManager.default.createSymbolicLink(atPath: b, withDestinationPath: a)
        let r = try CLI.run(["validate-map", fifo, "/dev/zero", a], timeoutSeconds: 30)
        r.assertExit(1)
        r.assertStderr(contains: "error: \(fifo): $: not a regular file (it is a FIFO (named pipe))",
                       "error: /dev/zero: $: not a regular file (it is a character device)",
                       "error: \(a): $: too many levels of symbolic links (a symbolic-link loop)", "3 of 3 maps invalid")
        XCTAssertFalse(r.stderr.contains("permission"), "\(r)")
    }
}
