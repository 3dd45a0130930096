import Foundation
import XCTest
import TestRandom

/// Issue 14, "nothing lost": `wayfinder simulate` killed while it writes leaves, in every file, whole lines
/// that are a prefix of the complete bundle (at most the last line cut off), the files consistent in time
/// (interleaved writing in group flushes of 16 lines: at most 15 lines held back in all), and a bundle the
/// reader reads with at most a truncated-last-line warning.
final class SimulateKillTests: XCTestCase {
    /// Lines the simulator holds back at most (App/Simulation `SimulatedWalk.flushEveryLines`).
    private static let flushEveryLines = 16
    /// A walk long enough that writing it takes a good fraction of a second (5,800 frames at 120 Hz).
    private static let arguments = ["simulate", "--from", "room-101", "--to", "room-214", "--seed", "3",
                                    "--rate", "120", "--detector-rate", "60"]
    private static let files = ["frames.jsonl", "truth.jsonl", "observations.jsonl"]

    /// Times (`t`) of each line, parsed.
    private func times(_ lines: [Data.SubSequence]) throws -> [Double] {
        try lines.map { line in
            let object = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(line)) as? [String: Any])
            return try XCTUnwrap(jsonNumber(object["t"]))
        }
    }

    func testKilledSimulateLeavesAConsistentPrefixOfTheBundle() throws {
        guard let exe = CLI.executableURL else { throw XCTSkip("wayfinder executable not found") }
        let scratch = try CLI.makeTemporaryDirectory("simulate-kill")
        defer { try? FileManager.default.removeItem(at: scratch) }
        // The complete bundle, for reference (the simulator is deterministic).
        let reference = scratch.appendingPathComponent("reference")
        let full = try CLI.run(Self.arguments + ["-o", reference.path], timeoutSeconds: 300)
        full.assertExit(0)
        let referenceFramesBytes = try XCTUnwrap(
            FileManager.default.attributesOfItem(atPath: reference.appendingPathComponent("frames.jsonl").path)[.size] as? Int)
        var referenceLines: [String: [Data.SubSequence]] = [:]
        for f in Self.files {
            let data = try Data(contentsOf: reference.appendingPathComponent(f))
            referenceLines[f] = data.split(separator: 0x0A)
        }
        // The write order the simulator promises: per frame, the frame, its truth, then the observations
        // at or before its time. Global position of each line, to measure how far files got ahead of others.
        let frameTimes = try times(referenceLines["frames.jsonl"]!)
        let observationTimes = try times(referenceLines["observations.jsonl"]!)
        var position: [String: [Int]] = ["frames.jsonl": [], "truth.jsonl": [], "observations.jsonl": []]
        var next = 0, o = 0
        for t in frameTimes {
            position["frames.jsonl"]!.append(next); next += 1
            position["truth.jsonl"]!.append(next); next += 1
            while o < observationTimes.count, observationTimes[o] <= t { position["observations.jsonl"]!.append(next); next += 1; o += 1 }
        }
        while o < observationTimes.count { position["observations.jsonl"]!.append(next); next += 1; o += 1 }

        var rng = SplitMix64(seed: 2026)
        var midWrite = 0
        for attempt in 0..<8 {
            let out = scratch.appendingPathComponent("killed-\(attempt)")
            let child = Process()
            child.executableURL = exe
            child.arguments = Self.arguments + ["-o", out.path]
            child.currentDirectoryURL = CLI.repositoryRoot
            child.standardOutput = FileHandle.nullDevice
            child.standardError = FileHandle.nullDevice
            try child.run()
            // Kill at a random moment of the writing: once frames.jsonl has reached a random share of its
            // final size (polled every 0.2 ms; drawing a time instead missed the write on a loaded machine).
            let target = Int(rng.uniform(0.02, 0.98) * Double(referenceFramesBytes))
            let framesPath = out.appendingPathComponent("frames.jsonl").path
            let deadline = Date().addingTimeInterval(120)
            var st = stat()
            while child.isRunning, Date() < deadline, !(stat(framesPath, &st) == 0 && Int(st.st_size) >= target) {
                usleep(200)
            }
            kill(child.processIdentifier, SIGKILL)
            child.waitUntilExit()
            guard FileManager.default.fileExists(atPath: out.appendingPathComponent("frames.jsonl").path) else { continue }

            var kept: [String: Int] = [:]
            for f in Self.files {
                let data = (try? Data(contentsOf: out.appendingPathComponent(f))) ?? Data()
                var lines = data.split(separator: 0x0A, omittingEmptySubsequences: false)
                let tail = lines.removeLast()
                let ref = referenceLines[f]!
                XCTAssertLessThanOrEqual(lines.count, ref.count, "kill \(attempt) \(f)")
                // Whole lines: exactly the reference's first lines (each parseable, nothing lost or reordered).
                for (i, line) in lines.enumerated() where i >= ref.count || Data(line) != Data(ref[i]) {
                    XCTFail("kill \(attempt) \(f) line \(i + 1) differs from the complete bundle"); break
                }
                // After the last newline: nothing, or the beginning of the next line.
                if !tail.isEmpty {
                    XCTAssertTrue(lines.count < ref.count && Data(ref[lines.count]).starts(with: Data(tail)),
                                  "kill \(attempt) \(f): the partial last line is not the start of line \(lines.count + 1)")
                }
                kept[f] = lines.count
            }
            // Consistent in time: lines missing from one file while a later line (in write order) is in another
            // are the ones of the group being written when the kill came: fewer than flushEveryLines.
            let lastKept = Self.files.compactMap { f in kept[f]! > 0 ? position[f]![kept[f]! - 1] : nil }.max() ?? -1
            let overtaken = Self.files.map { f in position[f]!.dropFirst(kept[f]!).filter { $0 < lastKept }.count }.reduce(0, +)
            XCTAssertLessThan(overtaken, Self.flushEveryLines, "kill \(attempt): kept \(kept)")
            if kept["frames.jsonl"]! > 0, kept["frames.jsonl"]! < frameTimes.count {
                midWrite += 1
                // The reader takes the cut-off bundle: every whole line, a cut last line only as a warning.
                let r = try CLI.run(["inspect", out.path])
                r.assertExit(0)
            }
        }
        print("SimulateKillTests: \(midWrite) of 8 kills landed mid-write")
        XCTAssertGreaterThanOrEqual(midWrite, 4, "too few kills landed while the bundle was being written")
    }
}
