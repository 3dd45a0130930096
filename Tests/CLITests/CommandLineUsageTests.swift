import Foundation
import XCTest

/// The command's surface: top-level help, unknown commands, each subcommand's --help, and usage errors
/// (exit 2 with a message naming the offending flag). None of these runs the pipeline.
final class CommandLineUsageTests: XCTestCase {
    /// Every subcommand `wayfinder --help` must list.
    static let subcommands = ["replay", "eval", "render", "bench", "simulate", "validate-map", "places", "import-inavigate",
                              "inspect", "import-occam", "range"]

    func testTopLevelHelpListsEverySubcommandAndExitsZero() throws {
        for flag in ["--help", "-h"] {
            let r = try CLI.run([flag])
            r.assertExit(0)
            r.assertStdout(contains: "Usage: wayfinder <command>")
            // Each command is listed at the start of an indented line, followed by its summary.
            let listed = Set(r.stdoutLines.filter { $0.hasPrefix("  ") }
                .compactMap { $0.split(separator: " ").first.map(String.init) })
            for name in Self.subcommands {
                XCTAssertTrue(listed.contains(name), "--help does not list '\(name)': \(r)")
            }
            XCTAssertTrue(r.stderr.isEmpty, "help wrote to stderr: \(r)")
        }
    }

    func testNoArgumentsPrintsHelpAndExitsTwo() throws {
        let r = try CLI.run([])
        r.assertExit(2)
        r.assertStdout(contains: "Usage: wayfinder", "replay")
    }

    func testUnknownCommandExitsTwoNamingIt() throws {
        let r = try CLI.run(["frobnicate", "--map", "x"])
        r.assertExit(2)
        r.assertStderr(contains: "unknown command 'frobnicate'", "--help")
        XCTAssertTrue(r.stdout.isEmpty, "\(r)")
    }

    func testEverySubcommandHelpExitsZeroWithUsage() throws {
        // Every command with --help; -h (the same switch) once, to keep the number of launches down.
        for (name, flag) in Self.subcommands.map({ ($0, "--help") }) + [("replay", "-h")] {
            let r = try CLI.run([name, flag])
            r.assertExit(0)
            XCTAssertTrue(r.stdout.hasPrefix("Usage: wayfinder \(name)"), "\(name) \(flag) prints no usage line: \(r)")
            XCTAssertGreaterThan(r.stdoutLines.count, 2, "\(name) usage is too short: \(r)")
            XCTAssertTrue(r.stderr.isEmpty, "\(name) \(flag) wrote to stderr: \(r)")
        }
        // --help wins over everything else on the line, even a missing required flag.
        let r = try CLI.run(["replay", "--help", "--seed", "nonsense"])
        r.assertExit(0)
        r.assertStdout(contains: "--trace FILE")
    }

    /// One usage error: the arguments, and the flag (or word) the message must name.
    private func assertUsageError(_ arguments: [String], names fragment: String,
                                  file: StaticString = #filePath, line: UInt = #line) throws {
        let r = try CLI.run(arguments, file: file, line: line)
        r.assertExit(2, file: file, line: line)
        r.assertStderr(contains: "wayfinder \(arguments[0]): ", fragment, file: file, line: line)
        XCTAssertTrue(r.stdout.isEmpty, "usage error wrote to stdout: \(r)", file: file, line: line)
    }

    func testMissingRequiredFlagsExitTwoNamingTheFlag() throws {
        let bundle = CLI.sampleBundlePath, map = CLI.officeMapPath
        try assertUsageError(["replay", bundle], names: "--map")
        try assertUsageError(["render", bundle, "-o", "/tmp/never-written.html"], names: "--map")
        try assertUsageError(["eval", bundle], names: "--map")
        try assertUsageError(["render", bundle, "--map", map], names: "-o")
        try assertUsageError(["range"], names: "--input")
        try assertUsageError(["replay", "--map", map], names: "BUNDLE")
        try assertUsageError(["simulate", "--to", "room-103", "--seed", "1", "-o", "/tmp/never"], names: "--from")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "-o", "/tmp/never"], names: "--seed")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "--seed", "1"], names: "-o")
        try assertUsageError(["import-inavigate", "/nonexistent-dir"], names: "-o")
        try assertUsageError(["import-occam", "/nonexistent.json"], names: "-o")
        try assertUsageError(["validate-map"], names: "map file")
        try assertUsageError(["inspect"], names: "bundle")
        try assertUsageError(["replay", bundle, "--map"], names: "--map needs a value")
    }

    func testBadNumbersExitTwoNamingTheFlag() throws {
        let bundle = CLI.sampleBundlePath, map = CLI.officeMapPath
        try assertUsageError(["replay", bundle, "--map", map, "--seed", "seven"], names: "--seed")
        try assertUsageError(["render", bundle, "--map", map, "-o", "/tmp/never-written.html", "--seed", "1.5"],
                             names: "--seed")
        try assertUsageError(["eval", bundle, "--map", map, "--seed", "x"], names: "--seed")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "--seed", "1", "--rate", "fast",
                              "-o", "/tmp/never"], names: "--rate")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "--seed", "1", "--rate", "nan",
                              "-o", "/tmp/never"], names: "--rate")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "--seed", "-3", "-o", "/tmp/never"],
                             names: "--seed")
        try assertUsageError(["import-inavigate", "/nonexistent-dir", "-o", "/tmp/never.json", "--floor-height", "tall"],
                             names: "--floor-height")
        try assertUsageError(["import-inavigate", "/nonexistent-dir", "-o", "/tmp/never.json", "--snap", "-1"],
                             names: "--snap")
        try assertUsageError(["bench", "--iterations", "many"], names: "--iterations")
    }

    func testBadChoicesAndUnknownOptionsExitTwo() throws {
        let bundle = CLI.sampleBundlePath, map = CLI.officeMapPath
        try assertUsageError(["replay", bundle, "--map", map, "--detector", "magic"], names: "--detector")
        try assertUsageError(["eval", bundle, "--map", map, "--detector", "magic"], names: "--detector")
        try assertUsageError(["replay", bundle, "--map", map, "--bogus"], names: "--bogus")
        try assertUsageError(["range", "--input", "Tests/Fixtures/range/observations.csv", "--method", "guess"],
                             names: "--method")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "--seed", "1", "--carry", "pocket",
                              "-o", "/tmp/never"], names: "--carry")
        try assertUsageError(["render", bundle, "--map", map, "-o", "/tmp/never-written.html", "--at", "1,soon"],
                             names: "--at")
        try assertUsageError(["eval", "--scenarios", "Tests/Scenarios", "--sim-detector", "perfect"], names: "--sim-detector")
        try assertUsageError(["eval", bundle, "--map", map, "--sim-detector", "real-unet"], names: "--sim-detector")
        try assertUsageError(["simulate", "--from", "room-101", "--to", "room-103", "--seed", "1", "--sim-detector", "x",
                              "-o", "/tmp/never"], names: "--sim-detector")
        for bias in ["-1", "nan", "short"] {
            try assertUsageError(["eval", "--scenarios", "Tests/Scenarios", "--sim-range-bias", bias], names: "--sim-range-bias")
        }
        try assertUsageError(["eval", bundle, "--map", map, "--sim-range-bias", "-0.1"], names: "--sim-detector")
        try assertUsageError(["eval", bundle, "--map", map, "--sim-params", "Tests/StressProfiles/vio-rough.json"],
                             names: "--sim-params")
    }

    /// A stress-profile file that cannot be read, or names a key the simulator does not have, is a bad-input
    /// failure (exit 1) naming the file and the problem; nothing is simulated.
    func testABadParameterFileNamesTheFileAndTheKey() throws {
        let out = try CLI.makeTemporaryDirectory("sim-params")
        let missing = out.appendingPathComponent("absent.json").path
        let base = ["simulate", "--from", "room-101", "--to", "room-103", "--seed", "1", "-o", out.appendingPathComponent("b").path]
        var r = try CLI.run(base + ["--sim-params", missing])
        r.assertExit(1)
        r.assertStderr(contains: missing, "cannot read")
        let misspelt = out.appendingPathComponent("typo.json")
        try Data(#"{"vio": {"scaleErorRange": [0.01, 0.1]}}"#.utf8).write(to: misspelt)
        r = try CLI.run(base + ["--sim-params", misspelt.path])
        r.assertExit(1)
        r.assertStderr(contains: misspelt.path, "vio.scaleErorRange")
        XCTAssertFalse(FileManager.default.fileExists(atPath: out.appendingPathComponent("b").path))
    }
}
