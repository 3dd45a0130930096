import Foundation
import XCTest

/// `wayfinder replay` of the committed sample walk on the bundled office: timestamped announcements on
/// stdout, "Start walking" before any turn instruction, and a --trace file with one JSON line per frame.
final class ReplayCommandTests: XCTestCase {
    /// One replay of the sample bundle (with --trace), shared by the tests of this class: replays are the
    /// slowest thing the CLI does.
    private struct SampleReplay: Sendable {
        let exitCode: Int32
        let stdout: String
        let stderr: String
        let description: String
        let traceLines: [String]
        let frameCount: Int
        /// Lines of the `--trace-particles` file (every 2 s, at most 40 particles each).
        let particleLines: [String]
        /// Time of the sample's last frame, seconds.
        let lastFrameT: Double
    }

    private static let sampleReplay: Result<SampleReplay, CLITestSetupError> = {
        let sample = CLI.repo(CLI.sampleBundlePath)
        guard FileManager.default.fileExists(atPath: sample.appendingPathComponent("frames.jsonl").path) else {
            return .failure(.skipped("\(CLI.sampleBundlePath) is not present"))
        }
        do {
            let dir = try CLI.makeTemporaryDirectory("replay")
            defer { try? FileManager.default.removeItem(at: dir) }
            let trace = dir.appendingPathComponent("trace.jsonl")
            let particles = dir.appendingPathComponent("particles.jsonl")
            let r = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--seed", "1",
                                 "--trace", trace.path, "--trace-particles", particles.path,
                                 "--trace-particles-every", "2", "--trace-particles-count", "40"], timeoutSeconds: 180)
            let traceText = (try? String(contentsOf: trace, encoding: .utf8)) ?? ""
            let particleText = (try? String(contentsOf: particles, encoding: .utf8)) ?? ""
            let frameLines = try String(contentsOf: sample.appendingPathComponent("frames.jsonl"), encoding: .utf8)
                .split(separator: "\n")
            let lastFrame = try JSONSerialization.jsonObject(with: Data((frameLines.last ?? "{}").utf8)) as? [String: Any]
            return .success(SampleReplay(exitCode: r.exitCode, stdout: r.stdout, stderr: r.stderr, description: r.description,
                                         traceLines: traceText.split(separator: "\n").map(String.init),
                                         frameCount: frameLines.count,
                                         particleLines: particleText.split(separator: "\n").map(String.init),
                                         lastFrameT: (lastFrame?["t"] as? NSNumber)?.doubleValue ?? .nan))
        } catch {
            return .failure(.failed("\(error)"))
        }
    }()

    private func replay() throws -> SampleReplay {
        let r = try Self.sampleReplay.value()
        XCTAssertEqual(r.exitCode, 0, r.description)
        return r
    }

    /// "[   x.x s] text" announcement lines.
    private static let announcementPattern = try! NSRegularExpression(pattern: #"^\[ *[0-9]+\.[0-9] s\] \S.*$"#)
    /// Words of a turn instruction (Navigation/Locales/en.json), not "Wrong way, turn around".
    private static let turnPattern = try! NSRegularExpression(
        pattern: #"(?i)\b(turn (left|right)|bear (left|right)|sharp (left|right)|u-turn)\b"#)

    private static func matches(_ re: NSRegularExpression, _ s: String) -> Bool {
        re.firstMatch(in: s, range: NSRange(s.startIndex..., in: s)) != nil
    }

    func testPrintsTimestampedAnnouncementsExploratoryGuidanceFirst() throws {
        let r = try replay()
        let lines = r.stdout.split(separator: "\n").map(String.init)
        XCTAssertFalse(lines.isEmpty, r.description)
        var times: [Double] = []
        for line in lines {
            XCTAssertTrue(Self.matches(Self.announcementPattern, line), "not an announcement line: \(line)")
            let inside = line.dropFirst().prefix { $0 != "s" }.trimmingCharacters(in: .whitespaces)
            times.append(Double(inside) ?? -1)
        }
        XCTAssertEqual(times, times.sorted(), "announcement times go back: \(r.stdout)")
        // The sample starts from its floor only: nothing is known at t = 0, so the first words are the
        // exploratory guidance while not localized (never a bare "Start walking").
        let start = lines.firstIndex { $0.contains("not sure where you are yet") || $0.contains("Not sure where you are yet") }
        XCTAssertEqual(start, 0, "the first announcement is not the exploratory guidance: \(r.description)")
        XCTAssertFalse(r.stdout.contains("Start walking"), r.description)
        // The sample (room 111 to room 102) turns twice; it is chosen to localize in replay (App/Samples).
        let turn = lines.firstIndex { Self.matches(Self.turnPattern, $0) }
        XCTAssertNotNil(turn, "no turn instruction in the sample replay: \(r.description)")
        if let turn, let start {
            XCTAssertLessThan(start, turn, "a turn instruction came before the exploratory guidance:\n\(r.stdout)")
        }
        // Progress goes to stderr, never among the announcements.
        XCTAssertFalse(r.stdout.contains("replay:"), r.description)
    }

    func testTraceHasOneJSONLinePerFrameWithTheDocumentedKeys() throws {
        let r = try replay()
        XCTAssertEqual(r.traceLines.count, r.frameCount, "trace lines vs frames: \(r.description)")
        let documented: Set<String> = ["t", "x", "y", "floorId", "headingRad", "confidence", "localized", "hypotheses",
                                       "sightings", "announcements", "haptics"]
        // While not localized: the exploratory advice in force, and the action when one is spoken; while
        // tracking is not normal: its state, and the phone's tracking prompt when one is said; on frames with
        // sightings, the list of them; while not localized or holding several hypotheses, the list of those.
        let optional: Set<String> = ["advice", "spokenAdvice", "tracking", "trackingPrompt", "sightingList", "hypothesisList"]
        var previousT = -Double.infinity
        var spoken = 0
        for (i, line) in r.traceLines.enumerated() {
            guard let object = try JSONSerialization.jsonObject(with: Data(line.utf8)) as? [String: Any] else {
                XCTFail("trace line \(i + 1) is not a JSON object: \(line)"); continue
            }
            XCTAssertEqual(Set(object.keys).subtracting(optional), documented, "trace line \(i + 1)")
            XCTAssertTrue(Set(object.keys).isSubset(of: documented.union(optional)), "trace line \(i + 1)")
            // The list is there exactly when the frame had sightings, one entry per sighting.
            let sightingCount = try XCTUnwrap(jsonNumber(object["sightings"]), "line \(i + 1)")
            let list = object["sightingList"] as? [[String: Any]]
            XCTAssertEqual(list?.count ?? 0, Int(sightingCount), "trace line \(i + 1)")
            XCTAssertEqual(list == nil, sightingCount == 0, "trace line \(i + 1)")
            // The hypotheses are listed exactly when the filter is not localized or holds more than one, with
            // weights in 0...1, the dominant first and the others heaviest first (the dominant's weight is refreshed
            // between two clusterings and the others' are not, so it may read lighter than the second), the number of
            // them at least the count of those above 5 %.
            let localizedFlag = try XCTUnwrap(object["localized"] as? Bool, "line \(i + 1)")
            let hypothesisCount = try XCTUnwrap(jsonNumber(object["hypotheses"]), "line \(i + 1)")
            if let hypotheses = object["hypothesisList"] as? [[String: Any]] {
                XCTAssertTrue(!localizedFlag || hypotheses.count > 1, "trace line \(i + 1)")
                let weights = hypotheses.compactMap { jsonNumber($0["weight"]) }
                XCTAssertEqual(weights.count, hypotheses.count, "trace line \(i + 1)")
                XCTAssertTrue(weights.allSatisfy { (0...1.000_001).contains($0) }, "trace line \(i + 1): \(weights)")
                XCTAssertEqual(Array(weights.dropFirst()), weights.dropFirst().sorted(by: >), "trace line \(i + 1)")
                XCTAssertGreaterThanOrEqual(hypotheses.count, Int(hypothesisCount), "trace line \(i + 1)")
                // Each with its heading spread (circular std, radians, >= 0).
                let headingStds = hypotheses.compactMap { jsonNumber($0["headingStdRad"]) }
                XCTAssertEqual(headingStds.count, hypotheses.count, "trace line \(i + 1)")
                XCTAssertTrue(headingStds.allSatisfy { $0 >= 0 && $0.isFinite }, "trace line \(i + 1): \(headingStds)")
            } else {
                XCTAssertTrue(localizedFlag, "trace line \(i + 1): not localized but no hypothesisList")
            }
            for entry in list ?? [] {
                XCTAssertTrue(Set(entry.keys).isSuperset(of: ["kind", "rangeMeters", "bearingRad", "score"]), "trace line \(i + 1)")
            }
            let t = try XCTUnwrap(jsonNumber(object["t"]), "line \(i + 1)")
            XCTAssertGreaterThan(t, previousT, "trace time does not increase at line \(i + 1)")
            previousT = t
            let confidence = try XCTUnwrap(jsonNumber(object["confidence"]))
            XCTAssertTrue((0...1).contains(confidence), "confidence \(confidence) at line \(i + 1)")
            XCTAssertNotNil(object["localized"] as? Bool)
            spoken += (object["announcements"] as? [Any])?.count ?? 0
            spoken += object["trackingPrompt"] == nil ? 0 : 1
        }
        // Every announcement and tracking prompt printed is in the trace, on its frame.
        let printed = r.stdout.split(separator: "\n").filter { !$0.contains("(haptic:") }.count
        XCTAssertEqual(spoken, printed, r.description)
        XCTAssertTrue(r.stderr.contains("trace written"), "no trace confirmation on stderr: \(r.description)")
    }

    /// `--trace-particles`: one JSON object per dump, every 2 s and at the last frame, each with its time, the
    /// documented columns and at most the asked number of rows of (x, y, heading, scale, weight, floor id).
    func testParticleTraceHasOneLinePerDumpWithTheDocumentedColumns() throws {
        let r = try replay()
        XCTAssertFalse(r.particleLines.isEmpty, "no particle trace: \(r.description)")
        XCTAssertTrue(r.stderr.contains("particle trace written"), r.description)
        var times: [Double] = []
        for (i, line) in r.particleLines.enumerated() {
            guard let object = try JSONSerialization.jsonObject(with: Data(line.utf8)) as? [String: Any] else {
                XCTFail("particle line \(i + 1) is not a JSON object"); continue
            }
            XCTAssertEqual(Set(object.keys), ["t", "count", "columns", "particles"], "particle line \(i + 1)")
            XCTAssertEqual(object["columns"] as? [String], ["xMeters", "yMeters", "headingRad", "scale", "weight", "floorId"])
            let rows = try XCTUnwrap(object["particles"] as? [[Any]], "particle line \(i + 1)")
            XCTAssertEqual(rows.count, (object["count"] as? NSNumber)?.intValue, "particle line \(i + 1)")
            XCTAssertTrue((1...40).contains(rows.count), "particle line \(i + 1): \(rows.count) rows")
            for row in rows {
                XCTAssertEqual(row.count, 6, "particle line \(i + 1)")
                let numbers = row.prefix(5).compactMap { ($0 as? NSNumber)?.doubleValue }
                XCTAssertEqual(numbers.count, 5, "particle line \(i + 1): \(row)")
                XCTAssertTrue(numbers.allSatisfy(\.isFinite), "particle line \(i + 1): \(row)")
                if numbers.count == 5 {
                    XCTAssertTrue(abs(numbers[2]) <= Double.pi + 1e-3, "heading \(numbers[2])")
                    XCTAssertTrue(numbers[3] > 0.5 && numbers[3] < 2, "scale \(numbers[3])")
                    XCTAssertTrue((0...1).contains(numbers[4]), "weight \(numbers[4])")
                }
                XCTAssertEqual(row[5] as? String, "1", "the sample walks the office's floor 1")
            }
            times.append(try XCTUnwrap((object["t"] as? NSNumber)?.doubleValue))
        }
        // Every 2 s from the first frame, and the last frame.
        XCTAssertEqual(times, times.sorted(), "dump times go back")
        for (a, b) in zip(times, times.dropFirst().dropLast()) { XCTAssertEqual(b - a, 2, accuracy: 0.05) }
        XCTAssertEqual(times.last ?? .nan, r.lastFrameT, accuracy: 1e-3)
    }

    func testMissingMapExitsOneNamingTheFile() throws {
        _ = try CLI.requireSampleBundle()
        let r = try CLI.run(["replay", CLI.sampleBundlePath, "--map", "/nonexistent/no-such-map.json"])
        r.assertExit(1)
        r.assertStderr(contains: "wayfinder replay: ", "no-such-map.json")
        XCTAssertTrue(r.stdout.isEmpty, "\(r)")
    }

    func testInvalidMapExitsOneNamingFileAndPath() throws {
        _ = try CLI.requireSampleBundle()
        let dir = try CLI.makeTemporaryDirectory("replay-badmap")
        defer { try? FileManager.default.removeItem(at: dir) }
        let map = dir.appendingPathComponent("broken.json")
        try Data("{\"formatVersion\": 1, \"id\": \"x\"".utf8).write(to: map)
        let r = try CLI.run(["replay", CLI.sampleBundlePath, "--map", map.path])
        r.assertExit(1)
        r.assertStderr(contains: "broken.json", "$")
    }

    func testMissingBundleExitsOneNamingIt() throws {
        let r = try CLI.run(["replay", "/nonexistent/walk-bundle", "--map", CLI.officeMapPath])
        r.assertExit(1)
        r.assertStderr(contains: "/nonexistent/walk-bundle")
    }

    // MARK: Issue 14: hostile bundles

    /// A short copy of the sample walk (its first `frameCount` frames) in a fresh directory, with
    /// session.json edited by `editSession`; the caller removes it.
    private func shortSampleCopy(frameCount: Int = 40, editSession: (inout [String: Any]) -> Void = { _ in }) throws -> URL {
        let sample = try CLI.requireSampleBundle()
        let dir = try CLI.makeTemporaryDirectory("replay-copy")
        var session = try XCTUnwrap(JSONSerialization.jsonObject(
            with: Data(contentsOf: sample.appendingPathComponent("session.json"))) as? [String: Any])
        editSession(&session)
        try JSONSerialization.data(withJSONObject: session).write(to: dir.appendingPathComponent("session.json"))
        let frames = try String(contentsOf: sample.appendingPathComponent("frames.jsonl"), encoding: .utf8)
            .split(separator: "\n").prefix(frameCount)
        try Data((frames.joined(separator: "\n") + "\n").utf8).write(to: dir.appendingPathComponent("frames.jsonl"))
        let lastT = try XCTUnwrap(jsonNumber((try JSONSerialization.jsonObject(with: Data(frames.last!.utf8)) as? [String: Any])?["t"]))
        let observations = try String(contentsOf: sample.appendingPathComponent("observations.jsonl"), encoding: .utf8)
            .split(separator: "\n").filter { line in
                let t = jsonNumber((try? JSONSerialization.jsonObject(with: Data(line.utf8)) as? [String: Any])?["t"])
                return (t ?? .infinity) <= lastT
            }
        try Data(observations.map { $0 + "\n" }.joined().utf8).write(to: dir.appendingPathComponent("observations.jsonl"))
        return dir
    }

    func testBundleOfAnotherBuildingIsWarnedOnStderr() throws {
        let dir = try shortSampleCopy { $0["mapId"] = "skeri-4" }
        defer { try? FileManager.default.removeItem(at: dir) }
        let r = try CLI.run(["replay", dir.path, "--map", CLI.officeMapPath, "--seed", "1"], timeoutSeconds: 180)
        r.assertExit(0)
        r.assertStderr(contains: "warning: \(dir.appendingPathComponent("session.json").path): mapId 'skeri-4' names another building")
        // The matching map gives no such warning.
        let same = try shortSampleCopy()
        defer { try? FileManager.default.removeItem(at: same) }
        let ok = try CLI.run(["replay", same.path, "--map", CLI.officeMapPath, "--seed", "1"], timeoutSeconds: 180)
        ok.assertExit(0)
        XCTAssertFalse(ok.stderr.contains("mapId"), "\(ok)")
    }

    func testFIFOAsFramesFileExitsOneWithoutBlocking() throws {
        let dir = try shortSampleCopy()
        defer { try? FileManager.default.removeItem(at: dir) }
        let frames = dir.appendingPathComponent("frames.jsonl")
        try FileManager.default.removeItem(at: frames)
        XCTAssertEqual(mkfifo(frames.path, 0o644), 0)
        let r = try CLI.run(["replay", dir.path, "--map", CLI.officeMapPath], timeoutSeconds: 60)
        r.assertExit(1)
        r.assertStderr(contains: "\(frames.path): is a FIFO", "not a regular file")
    }

    func testLinkLeavingTheBundleExitsOneNamingIt() throws {
        let dir = try shortSampleCopy()
        defer { try? FileManager.default.removeItem(at: dir) }
        let observations = dir.appendingPathComponent("observations.jsonl")
        try FileManager.default.removeItem(at: observations)
        try FileManager.default.createSymbolicLink(atPath: observations.path, withDestinationPath: "/etc/passwd")
        let r = try CLI.run(["replay", dir.path, "--map", CLI.officeMapPath], timeoutSeconds: 60)
        r.assertExit(1)
        r.assertStderr(contains: observations.path, "/etc/passwd", "outside the bundle")
    }

    func testUnknownSignKindAndFarRangeAreWarnedNamingFileAndLine() throws {
        let dir = try shortSampleCopy()
        defer { try? FileManager.default.removeItem(at: dir) }
        let observations = dir.appendingPathComponent("observations.jsonl")
        var lines = try String(contentsOf: observations, encoding: .utf8).split(separator: "\n").map(String.init)
        XCTAssertFalse(lines.isEmpty, "the short sample has observations")
        let t = try XCTUnwrap(jsonNumber((try JSONSerialization.jsonObject(with: Data(lines.last!.utf8)) as? [String: Any])?["t"]))
        lines.append("{\"bearingRad\":0,\"kind\":\"fire-extinguisher\",\"rangeMeters\":2,\"score\":0.9,\"t\":\(t)}")
        lines.append("{\"bearingRad\":0,\"kind\":\"exit\",\"rangeMeters\":1e300,\"score\":0.9,\"t\":\(t)}")
        try Data((lines.joined(separator: "\n") + "\n").utf8).write(to: observations)
        let r = try CLI.run(["replay", dir.path, "--map", CLI.officeMapPath, "--seed", "1"], timeoutSeconds: 180)
        r.assertExit(0)
        r.assertStderr(contains: "\(observations.path) line \(lines.count - 1): sign kind 'fire-extinguisher' is not on the map",
                       "\(observations.path) line \(lines.count): 1 record dropped as physically implausible")
    }
}

/// Why a class-level fixture is unavailable: skip (input absent) or fail (the command broke).
enum CLITestSetupError: Error, CustomStringConvertible {
    case skipped(String)
    case failed(String)
    var description: String {
        switch self {
        case .skipped(let s): return "skipped: \(s)"
        case .failed(let s): return s
        }
    }
}

extension Result where Failure == CLITestSetupError {
    /// The value, or XCTSkip for a skipped fixture, or a thrown failure.
    func value() throws -> Success {
        switch self {
        case .success(let v): return v
        case .failure(.skipped(let why)): throw XCTSkip(why)
        case .failure(let e): throw e
        }
    }
}
