import Foundation
import XCTest

/// `wayfinder replay --audio` (the walk's speech and haptics in one WAV), the phrasing flags, and the
/// errors for a missing synthesizer and bad flag values.
final class ReplaySpeechTests: XCTestCase {
    private func requireEspeak() throws {
        let path = ProcessInfo.processInfo.environment["PATH"] ?? ""
        guard path.split(separator: ":").contains(where: { FileManager.default.isExecutableFile(atPath: "\($0)/espeak-ng") }) else {
            throw XCTSkip("espeak-ng is not installed (scripts/setup.sh installs it)")
        }
    }

    private func u32(_ d: Data, _ at: Int) -> Int { d[at..<at + 4].enumerated().reduce(0) { $0 | Int($1.1) << (8 * $1.0) } }

    /// Times of the bundle's first and last frame, seconds.
    private func walkSpan() throws -> (first: Double, last: Double) {
        let frames = try String(contentsOf: CLI.repo(CLI.sampleBundlePath).appendingPathComponent("frames.jsonl"), encoding: .utf8)
            .split(separator: "\n")
        struct T: Decodable { var t: Double }
        let first = try JSONDecoder().decode(T.self, from: Data(frames.first!.utf8)).t
        let last = try JSONDecoder().decode(T.self, from: Data(frames.last!.utf8)).t
        return (first, last)
    }

    func testAudioIsTheWalksTimelineWithSpeechWhereItWasSaid() throws {
        _ = try CLI.requireSampleBundle()
        try requireEspeak()
        let dir = try CLI.makeTemporaryDirectory("audio")
        defer { try? FileManager.default.removeItem(at: dir) }
        let wav = dir.appendingPathComponent("walk.wav")
        let r = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--seed", "1", "--audio", wav.path],
                            timeoutSeconds: 240)
        XCTAssertEqual(r.exitCode, 0, "\(r)")
        XCTAssertTrue(r.stderr.contains("audio written to"), "\(r)")
        let d = try Data(contentsOf: wav)
        XCTAssertEqual(String(decoding: d[0..<4], as: UTF8.self), "RIFF")
        XCTAssertEqual(String(decoding: d[8..<16], as: UTF8.self), "WAVEfmt ")
        XCTAssertEqual(u32(d, 4), d.count - 8, "RIFF size")
        XCTAssertEqual(u32(d, 24), 22_050, "sample rate")
        XCTAssertEqual(Int(d[22]) | Int(d[23]) << 8, 1, "mono")
        XCTAssertEqual(Int(d[34]) | Int(d[35]) << 8, 16, "16-bit")
        XCTAssertEqual(String(decoding: d[36..<40], as: UTF8.self), "data")
        let samples = u32(d, 40) / 2
        XCTAssertEqual(samples * 2 + 44, d.count, "data size")
        // As long as the walk, or longer by the tail of the last utterance (at most 5 s).
        let span = try walkSpan()
        let seconds = Double(samples) / 22_050
        XCTAssertGreaterThanOrEqual(seconds, span.last - span.first - 1e-3)
        XCTAssertLessThanOrEqual(seconds, span.last - span.first + 5)
        // Sound in the half second after each printed announcement, on the walk's clock.
        func energy(_ from: Double, _ to: Double) -> Double {
            let a = max(0, Int(from * 22_050)), b = min(samples, Int(to * 22_050))
            guard b > a else { return 0 }
            var sum = 0.0
            for i in a..<b {
                let s = Double(Int16(bitPattern: UInt16(d[44 + 2 * i]) | UInt16(d[45 + 2 * i]) << 8))
                sum += s * s
            }
            return sum / Double(b - a)
        }
        let times = r.stdoutLines.compactMap { line -> Double? in
            guard line.hasPrefix("["), !line.contains("(haptic:"), let close = line.firstIndex(of: "]") else { return nil }
            return Double(line[line.index(after: line.startIndex)..<close].replacingOccurrences(of: " s", with: "")
                .trimmingCharacters(in: .whitespaces))
        }
        XCTAssertGreaterThanOrEqual(times.count, 3, "\(r)")
        for t in times { XCTAssertGreaterThan(energy(t - span.first, t - span.first + 0.6), 1e4, "speech at \(t) s") }
    }

    func testMissingSynthesizerIsAClearErrorBeforeTheReplay() throws {
        _ = try CLI.requireSampleBundle()
        let r = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--audio", "/tmp/unused.wav",
                             "--espeak", "/nonexistent/espeak-ng"])
        XCTAssertEqual(r.exitCode, 1, "\(r)")
        XCTAssertTrue(r.stderr.contains("--audio: /nonexistent/espeak-ng is not an executable file"), "\(r)")
        XCTAssertTrue(r.stderr.contains("apt-get install espeak-ng"), "\(r)")
        XCTAssertFalse(r.stderr.contains("%"), "said before replaying (no progress): \(r)")
        let s = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--speak", "--espeak", "/nonexistent/espeak-ng"])
        XCTAssertEqual(s.exitCode, 1, "\(s)")
        XCTAssertTrue(s.stderr.contains("--speak: /nonexistent/espeak-ng is not an executable file"), "\(s)")
    }

    func testPhrasingFlagsChangeTheWords() throws {
        _ = try CLI.requireSampleBundle()
        let plain = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--seed", "1"], timeoutSeconds: 240)
        XCTAssertEqual(plain.exitCode, 0, "\(plain)")
        XCTAssertTrue(plain.stdout.contains("Turn right now."), "\(plain)")
        let styled = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--seed", "1", "--units", "feet",
                                  "--clock-face"], timeoutSeconds: 240)
        XCTAssertEqual(styled.exitCode, 0, "\(styled)")
        XCTAssertTrue(styled.stdout.contains("Turn right now, toward 3 o'clock."), "\(styled)")
        // The sample walk's only distance phrase (the route start) is now left out: the first turn's cue is due
        // before it could end. Feet in the words are checked through the navigator (PhrasingAndTimingTests);
        // here no meter may slip through.
        XCTAssertFalse(styled.stdout.contains(" meters"), "\(styled)")
        XCTAssertFalse(styled.stdout.contains(" meter."), "\(styled)")
        let spanish = try CLI.run(["replay", CLI.sampleBundlePath, "--map", CLI.officeMapPath, "--seed", "1", "--language", "es",
                                   "--verbosity", "brief"], timeoutSeconds: 240)
        XCTAssertEqual(spanish.exitCode, 0, "\(spanish)")
        XCTAssertTrue(spanish.stdout.contains("Gire a la derecha ahora."), "\(spanish)")
        XCTAssertTrue(spanish.stdout.contains("Ha llegado."), "\(spanish)")
        XCTAssertFalse(spanish.stdout.contains("Turn"), "\(spanish)")
    }

    func testBadPhrasingValuesAreUsageErrors() throws {
        for (args, message) in [(["--units", "yards"], "--units must be meters, feet or steps"),
                                (["--verbosity", "chatty"], "--verbosity must be brief, normal or detailed"),
                                (["--stride", "3"], "--stride must be a step length in meters"),
                                (["--language", "xx"], "--language xx:")] {
            let r = try CLI.run(["replay", "App/Samples/office-walk", "--map", CLI.officeMapPath] + args)
            XCTAssertEqual(r.exitCode, 2, "\(r)")
            XCTAssertTrue(r.stderr.contains(message), "\(args): \(r)")
        }
    }
}
