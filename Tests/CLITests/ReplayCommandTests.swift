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
            let r = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--seed", "1",
                                 "--trace", trace.path], timeoutSeconds: 180)
            let traceText = (try? String(contentsOf: trace, encoding: .utf8)) ?? ""
            let frames = try String(contentsOf: sample.appendingPathComponent("frames.jsonl"), encoding: .utf8)
                .split(separator: "\n").count
            return .success(SampleReplay(exitCode: r.exitCode, stdout: r.stdout, stderr: r.stderr, description: r.description,
                                         traceLines: traceText.split(separator: "\n").map(String.init), frameCount: frames))
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

    func testPrintsTimestampedAnnouncementsStartWalkingFirst() throws {
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
        // The sample starts from its floor only: nothing is known at t = 0, so the first words are "Start walking".
        let start = lines.firstIndex { $0.contains("Start walking") }
        XCTAssertEqual(start, 0, "the first announcement is not 'Start walking': \(r.description)")
        // The sample (room 111 to room 102) turns twice; it is chosen to localize in replay (App/Samples).
        let turn = lines.firstIndex { Self.matches(Self.turnPattern, $0) }
        XCTAssertNotNil(turn, "no turn instruction in the sample replay: \(r.description)")
        if let turn, let start {
            XCTAssertLessThan(start, turn, "a turn instruction came before 'Start walking':\n\(r.stdout)")
        }
        // Progress goes to stderr, never among the announcements.
        XCTAssertFalse(r.stdout.contains("replay:"), r.description)
    }

    func testTraceHasOneJSONLinePerFrameWithTheDocumentedKeys() throws {
        let r = try replay()
        XCTAssertEqual(r.traceLines.count, r.frameCount, "trace lines vs frames: \(r.description)")
        let documented: Set<String> = ["t", "x", "y", "floorId", "headingRad", "confidence", "localized", "hypotheses",
                                       "sightings", "announcements", "haptics"]
        var previousT = -Double.infinity
        var spoken = 0
        for (i, line) in r.traceLines.enumerated() {
            guard let object = try JSONSerialization.jsonObject(with: Data(line.utf8)) as? [String: Any] else {
                XCTFail("trace line \(i + 1) is not a JSON object: \(line)"); continue
            }
            XCTAssertEqual(Set(object.keys), documented, "trace line \(i + 1)")
            let t = try XCTUnwrap(jsonNumber(object["t"]), "line \(i + 1)")
            XCTAssertGreaterThan(t, previousT, "trace time does not increase at line \(i + 1)")
            previousT = t
            let confidence = try XCTUnwrap(jsonNumber(object["confidence"]))
            XCTAssertTrue((0...1).contains(confidence), "confidence \(confidence) at line \(i + 1)")
            XCTAssertNotNil(object["localized"] as? Bool)
            spoken += (object["announcements"] as? [Any])?.count ?? 0
        }
        // Every announcement printed is in the trace, on its frame.
        let printed = r.stdout.split(separator: "\n").filter { !$0.contains("(haptic:") }.count
        XCTAssertEqual(spoken, printed, r.description)
        XCTAssertTrue(r.stderr.contains("trace written"), "no trace confirmation on stderr: \(r.description)")
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
