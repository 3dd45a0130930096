import Foundation
import SessionFormat

/// `wayfinder inspect`: reads a session bundle with the one reader and prints what it holds.
enum InspectCommand: Subcommand {
    static let name = "inspect"
    static let summary = "summarise a recorded session bundle (frames, tracking, observations, warnings)"
    static let usage = """
    Usage: wayfinder inspect BUNDLE... [--json]

    Reads each session bundle directory (docs/session-format.md) and prints its format version, device,
    map id, duration, frame count and rate, share of each tracking state, ARKit path length, observations
    per kind, whether truth is present, image count and the reader's warnings (a cut-off last line, missing
    images). --json prints one JSON object per bundle (an array when several are given).
    A damaged bundle prints the file, line and reason and exits 1.
    Exit codes: 0 ok, 1 a missing or damaged bundle, 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let json = arguments.flag("json")
        let paths = try arguments.positionals()
        guard !paths.isEmpty else { throw CLIError.usage("give a bundle directory (see 'wayfinder inspect --help')") }
        var summaries: [BundleSummary] = []
        for path in paths {
            let bundle: SessionBundle
            do { bundle = try SessionBundle.read(from: URL(fileURLWithPath: path)) } catch let e as BundleError {
                throw CLIError.failure(e.description)
            }
            summaries.append(bundle.summary())
        }
        if json {
            let encoder = JSONEncoder()
            encoder.outputFormatting = [.prettyPrinted, .sortedKeys, .withoutEscapingSlashes]
            let data = summaries.count == 1 ? try encoder.encode(summaries[0]) : try encoder.encode(summaries)
            print(String(decoding: data, as: UTF8.self))
        } else {
            for (path, s) in zip(paths, summaries) {
                if paths.count > 1 { print("== \(path)") }
                print(s.text)
            }
        }
        return 0
    }
}
