import Foundation
import XCTest

/// What one run of the `wayfinder` executable produced.
struct CLIResult: CustomStringConvertible {
    /// Process exit status (or the terminating signal's number when it was killed).
    let exitCode: Int32
    /// Everything written to stdout, decoded as UTF-8.
    let stdout: String
    /// Everything written to stderr, decoded as UTF-8.
    let stderr: String
    /// The arguments it was run with (for failure messages).
    let arguments: [String]

    /// Failure-message form: the command line, the exit code and the tails of both streams.
    var description: String {
        "wayfinder \(arguments.joined(separator: " ")) -> exit \(exitCode)\n--- stdout (tail):\n\(stdout.suffix(1500))\n--- stderr (tail):\n\(stderr.suffix(1500))"
    }

    /// stdout split into lines, empty lines dropped.
    var stdoutLines: [String] { stdout.split(separator: "\n").map(String.init) }
}

/// Runs the built `wayfinder` executable as a subprocess, from the repository root (so the CLI's default
/// paths such as SignDetector/models resolve as they do for a user running it from a checkout).
enum CLI {
    /// Repository root: this file is Tests/CLITests/CLIHarness.swift.
    static let repositoryRoot: URL = URL(fileURLWithPath: #filePath).resolvingSymlinksInPath()
        .deletingLastPathComponent().deletingLastPathComponent().deletingLastPathComponent()

    /// The bundled office map, as a path relative to the repository root.
    static let officeMapPath = "Maps/Buildings/wayfinder-office.json"
    /// The committed sample walk (made by the simulator; may be absent while it lands).
    static let sampleBundlePath = "App/Samples/office-walk"

    /// Where the `wayfinder` executable is, or nil. Looked up, in order: $WAYFINDER_CLI; the build products
    /// directory holding the test runner (on Linux the .xctest runner sits next to `wayfinder`; on macOS the
    /// .xctest bundle does); `.build/debug/wayfinder` under the repository root.
    static let executableURL: URL? = {
        let fm = FileManager.default
        if let env = ProcessInfo.processInfo.environment["WAYFINDER_CLI"], fm.isExecutableFile(atPath: env) {
            return URL(fileURLWithPath: env)
        }
        var directories: [URL] = []
        let runner = URL(fileURLWithPath: CommandLine.arguments.first ?? "").resolvingSymlinksInPath()
        directories.append(runner.deletingLastPathComponent())
        directories.append(Bundle.main.bundleURL)
        directories.append(Bundle.main.bundleURL.deletingLastPathComponent())
        for b in Bundle.allBundles + Bundle.allFrameworks where b.bundleURL.pathExtension == "xctest" {
            directories.append(b.bundleURL.deletingLastPathComponent())
        }
        // Walk up from the runner: .../WayfinderPackageTests.xctest/Contents/MacOS/WayfinderPackageTests on macOS.
        var up = runner.deletingLastPathComponent()
        for _ in 0..<4 {
            up = up.deletingLastPathComponent()
            directories.append(up)
        }
        directories.append(repositoryRoot.appendingPathComponent(".build/debug"))
        for d in directories {
            let candidate = d.appendingPathComponent("wayfinder")
            var isDir: ObjCBool = false
            if fm.fileExists(atPath: candidate.path, isDirectory: &isDir), !isDir.boolValue,
               fm.isExecutableFile(atPath: candidate.path) {
                return candidate
            }
        }
        return nil
    }()

    /// Runs `wayfinder ARGUMENTS` in the repository root and waits for it (killed after `timeoutSeconds`).
    /// stdout and stderr go to temporary files, so neither pipe can fill up and stall the child.
    static func run(_ arguments: [String], timeoutSeconds: Double = 120,
                    file: StaticString = #filePath, line: UInt = #line) throws -> CLIResult {
        guard let exe = executableURL else {
            XCTFail("wayfinder executable not found next to the test runner (\(CommandLine.arguments.first ?? "?")); "
                + "set WAYFINDER_CLI", file: file, line: line)
            throw CocoaError(.fileNoSuchFile)
        }
        let scratch = FileManager.default.temporaryDirectory
            .appendingPathComponent("wf-cli-out-\(UUID().uuidString)", isDirectory: true)
        try FileManager.default.createDirectory(at: scratch, withIntermediateDirectories: true)
        defer { try? FileManager.default.removeItem(at: scratch) }
        let outURL = scratch.appendingPathComponent("stdout"), errURL = scratch.appendingPathComponent("stderr")
        _ = FileManager.default.createFile(atPath: outURL.path, contents: nil)
        _ = FileManager.default.createFile(atPath: errURL.path, contents: nil)
        let outHandle = try FileHandle(forWritingTo: outURL), errHandle = try FileHandle(forWritingTo: errURL)

        let process = Process()
        process.executableURL = exe
        process.arguments = arguments
        process.currentDirectoryURL = repositoryRoot
        process.standardOutput = outHandle
        process.standardError = errHandle
        process.standardInput = FileHandle.nullDevice
        try process.run()
        let pid = process.processIdentifier
        let killer = DispatchWorkItem { kill(pid, SIGKILL) }
        DispatchQueue.global().asyncAfter(deadline: .now() + timeoutSeconds, execute: killer)
        process.waitUntilExit()
        killer.cancel()
        try outHandle.close()
        try errHandle.close()
        let result = CLIResult(
            exitCode: process.terminationStatus,
            stdout: String(decoding: try Data(contentsOf: outURL), as: UTF8.self),
            stderr: String(decoding: try Data(contentsOf: errURL), as: UTF8.self),
            arguments: arguments)
        if process.terminationReason == .uncaughtSignal {
            XCTFail("wayfinder was killed by signal \(process.terminationStatus) (crash or \(timeoutSeconds) s timeout): \(result)",
                    file: file, line: line)
        }
        return result
    }

    /// A fresh empty directory under the system temporary directory; the caller removes it.
    static func makeTemporaryDirectory(_ label: String) throws -> URL {
        let url = FileManager.default.temporaryDirectory
            .appendingPathComponent("wf-clitests-\(label)-\(UUID().uuidString)", isDirectory: true)
        try FileManager.default.createDirectory(at: url, withIntermediateDirectories: true)
        return url
    }

    /// Absolute URL of a repository-relative path.
    static func repo(_ relativePath: String) -> URL { repositoryRoot.appendingPathComponent(relativePath) }

    /// Skips the test when the committed sample walk is not in the tree yet.
    static func requireSampleBundle() throws -> URL {
        let url = repo(sampleBundlePath)
        guard FileManager.default.fileExists(atPath: url.appendingPathComponent("frames.jsonl").path) else {
            throw XCTSkip("\(sampleBundlePath) is not present")
        }
        return url
    }
}

/// Assertions on a finished run, each failure message showing the command and its output.
extension CLIResult {
    /// Asserts the exit status.
    func assertExit(_ expected: Int32, file: StaticString = #filePath, line: UInt = #line) {
        XCTAssertEqual(exitCode, expected, "unexpected exit status: \(self)", file: file, line: line)
    }

    /// Asserts that stderr contains every one of `fragments`.
    func assertStderr(contains fragments: String..., file: StaticString = #filePath, line: UInt = #line) {
        for f in fragments {
            XCTAssertTrue(stderr.contains(f), "stderr lacks \"\(f)\": \(self)", file: file, line: line)
        }
    }

    /// Asserts that stdout contains every one of `fragments`.
    func assertStdout(contains fragments: String..., file: StaticString = #filePath, line: UInt = #line) {
        for f in fragments {
            XCTAssertTrue(stdout.contains(f), "stdout lacks \"\(f)\": \(self)", file: file, line: line)
        }
    }
}

/// A JSON number from `JSONSerialization` as a Double, whether it was written as an integer or not.
func jsonNumber(_ value: Any?) -> Double? {
    switch value {
    case let d as Double: return d
    case let i as Int: return Double(i)
    case let n as NSNumber: return n.doubleValue
    default: return nil
    }
}
