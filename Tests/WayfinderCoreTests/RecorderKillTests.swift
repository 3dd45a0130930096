import Foundation
import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore
import TestRandom

/// Issue 14, "nothing lost": the phone's recorder (`WalkRecorder` over `BundleWriter`) must lose at most the
/// last line per file whenever the app is killed. The test runs the recorder in a child process (this
/// same test runner, re-executed on `testChildRecorderWritesUntilKilled`), SIGKILLs it at random moments
/// (fixed seed) and checks what is on disk.
final class RecorderKillTests: XCTestCase {
    /// Environment variable telling the child where to record.
    static let childDirectoryVariable = "WAYFINDER_RECORDER_KILL_CHILD_DIR"
    /// Frame rate of the recorded walk, Hz.
    static let rateHz = 30.0
    /// Every `imageEvery`-th frame carries a JPEG.
    static let imageEvery = 10

    /// The frame the child records as number `i` (deterministic, so the parent knows every line).
    static func frame(_ i: Int) -> PipelineFrame {
        let t = Double(i) / rateHz
        let pose = CameraPose(positionInWorld: (x: 0.04 * Double(i), y: 1.4, z: -0.01 * Double(i)),
                              yawRad: 0.001 * Double(i), pitchRad: -0.1, rollRad: -Double.pi / 2)
        return PipelineFrame(t: t, cameraPose: pose, tracking: .normal, intrinsics: .iPhone8Full,
                             relativeAltitudeMeters: 0.001 * Double(i), compassHeadingDeg: Double(i % 360))
    }

    /// The stand-in JPEG of image number `n` (1-based, as the recorder numbers them): 32 KiB, content
    /// depending on `n`, so a torn or swapped image shows.
    static func jpeg(_ n: Int) -> Data {
        Data((0..<(32 << 10)).map { UInt8(truncatingIfNeeded: $0 &* 31 &+ n &* 7) })
    }

    /// The child: records frames as fast as it can until it is killed. Skipped unless the parent set
    /// `childDirectoryVariable`.
    func testChildRecorderWritesUntilKilled() throws {
        guard let path = ProcessInfo.processInfo.environment[Self.childDirectoryVariable] else {
            throw XCTSkip("child process of testRecorderLosesAtMostTheLastLineWhenKilled; runs only when spawned by it")
        }
        let recorder = try WalkRecorder(directory: URL(fileURLWithPath: path), building: try TestData.office(), floorId: "1",
                                        startId: nil, destinationId: "room-102", device: "test", appVersion: "kill test")
        var images = 0
        for i in 0..<2_000_000 {
            var jpeg: Data?
            if i % Self.imageEvery == 0 { images += 1; jpeg = Self.jpeg(images) }
            try recorder.append(frame: Self.frame(i), jpeg: jpeg)
        }
        XCTFail("the child was not killed")
    }

    func testRecorderLosesAtMostTheLastLineWhenKilled() throws {
        #if os(Linux)
        let runner = URL(fileURLWithPath: CommandLine.arguments[0]).resolvingSymlinksInPath()
        guard runner.lastPathComponent.hasSuffix(".xctest") else {
            throw XCTSkip("not run from the .xctest runner (\(runner.path)); cannot spawn the child")
        }
        let encoder = JSONEncoder()
        encoder.outputFormatting = [.sortedKeys, .withoutEscapingSlashes]
        var rng = SplitMix64(seed: 14)
        var framesPerKill: [Int] = []
        for kill in 0..<8 {
            let dir = FileManager.default.temporaryDirectory.appendingPathComponent("wf-recorder-kill-\(kill)-\(UUID().uuidString)")
            defer { try? FileManager.default.removeItem(at: dir) }
            let child = Process()
            child.executableURL = runner
            child.arguments = ["WayfinderCoreTests.RecorderKillTests/testChildRecorderWritesUntilKilled"]
            var environment = ProcessInfo.processInfo.environment
            environment[Self.childDirectoryVariable] = dir.path
            child.environment = environment
            child.standardOutput = FileHandle.nullDevice
            child.standardError = FileHandle.nullDevice
            try child.run()
            // Wait for the recording to start (session.json is written first), then kill at a random moment.
            let deadline = Date().addingTimeInterval(60)
            while !FileManager.default.fileExists(atPath: dir.appendingPathComponent("frames.jsonl").path), Date() < deadline,
                  child.isRunning {
                usleep(2000)
            }
            usleep(UInt32(Double.random(in: 0.005...0.4, using: &rng) * 1e6))
            Foundation.kill(child.processIdentifier, SIGKILL)
            child.waitUntilExit()
            XCTAssertEqual(child.terminationReason, .uncaughtSignal, "kill \(kill): the child ended by itself")

            // frames.jsonl: every complete line is exactly frame i's record, in order; after the last newline
            // at most a prefix of the next frame's line.
            let raw = try Data(contentsOf: dir.appendingPathComponent("frames.jsonl"))
            var lines = raw.split(separator: 0x0A, omittingEmptySubsequences: false)
            let tail = lines.removeLast()   // the bytes after the last newline (empty when the file ends in one)
            var images = 0
            var expectedLines: [Data] = []
            for i in 0...lines.count {
                var name: String?
                if i % Self.imageEvery == 0 { images += 1; name = String(format: "%06d.jpg", images) }
                let record = try XCTUnwrap(FrameConversion.record(of: Self.frame(i), imageName: name))
                expectedLines.append(try encoder.encode(record))
            }
            for (i, line) in lines.enumerated() where Data(line) != expectedLines[i] {
                XCTFail("kill \(kill): line \(i + 1) is not frame \(i)'s record: \(String(decoding: line, as: UTF8.self))")
                break
            }
            XCTAssertTrue(expectedLines[lines.count].starts(with: tail), "kill \(kill): the partial last line is not frame \(lines.count)'s")
            framesPerKill.append(lines.count)
            // Killed before the first frame line: the reader refuses a bundle without frames (noFrames).
            guard !lines.isEmpty else {
                XCTAssertEqual(bundleKind(dir), .noFrames, "kill \(kill)")
                continue
            }
            // The reader reads it: every complete frame, a cut-off last line only as a warning.
            let bundle = try SessionBundle.read(from: dir)
            XCTAssertEqual(bundle.frames.count, lines.count, "kill \(kill)")
            XCTAssertTrue(bundle.warnings.allSatisfy { $0.kind == .truncatedLastLine }, "kill \(kill): \(bundle.warnings)")
            XCTAssertEqual(bundle.frames.map(\.t), (0..<lines.count).map { Double($0) / Self.rateHz })
            // Images: every one a kept frame names is there, whole; at most one more (written just before
            // its frame line, when the kill fell in between).
            var named = 0
            for f in bundle.frames {
                guard let name = f.image, let n = Int(name.prefix(6)) else { continue }
                named += 1
                XCTAssertEqual(try? Data(contentsOf: bundle.imagesDirectory.appendingPathComponent(name)), Self.jpeg(n),
                               "kill \(kill): image \(name) missing or torn")
            }
            let onDisk = ((try? FileManager.default.contentsOfDirectory(atPath: bundle.imagesDirectory.path)) ?? [])
                .filter { $0.hasSuffix(".jpg") && !$0.hasPrefix(".") }
            XCTAssertTrue(onDisk.count == named || onDisk.count == named + 1, "kill \(kill): \(onDisk.count) images for \(named) frames naming one")
        }
        print("RecorderKillTests: frames kept per kill \(framesPerKill)")
        XCTAssertGreaterThan(framesPerKill.filter { $0 > 0 }.count, 4, "the kills should land while frames are being written: \(framesPerKill)")
        #else
        throw XCTSkip("spawning the test runner as a child is implemented for Linux's xctest runner only")
        #endif
    }
}

/// The kind of the `BundleError` reading `dir` throws, nil when it reads.
private func bundleKind(_ dir: URL) -> BundleError.Kind? {
    do { _ = try SessionBundle.read(from: dir); return nil } catch let e as BundleError { return e.kind } catch { return nil }
}
