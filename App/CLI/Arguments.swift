import Foundation

/// A command-line failure with the message shown to the user and the process exit code.
struct CLIError: Error, CustomStringConvertible {
    /// Message printed to stderr, prefixed with "wayfinder: ".
    let description: String
    /// Process exit code: 2 for usage errors, 1 for failures on the input.
    let exitCode: Int32
    /// A usage error (bad flags or arguments), exit code 2.
    static func usage(_ message: String) -> CLIError { CLIError(description: message, exitCode: 2) }
    /// A failure on the input (unreadable file, invalid map...), exit code 1.
    static func failure(_ message: String) -> CLIError { CLIError(description: message, exitCode: 1) }
}

/// Minimal argument list: `--flag value`, `--switch`, and positionals, parsed on demand by each subcommand.
/// Hand-written because Package.swift cannot depend on swift-argument-parser here (no outside packages).
struct ArgumentList {
    private var items: [String]
    /// Wraps the arguments after the subcommand name.
    init(_ items: [String]) { self.items = items }

    /// True when `--help` or `-h` was given.
    var wantsHelp: Bool { items.contains("--help") || items.contains("-h") }

    /// Removes and returns the value of `--name VALUE` (or `--name=VALUE`); nil when absent.
    mutating func option(_ name: String) throws -> String? {
        if let i = items.firstIndex(where: { $0.hasPrefix("--\(name)=") }) {
            let v = String(items[i].dropFirst(name.count + 3))
            items.remove(at: i)
            return v
        }
        guard let i = items.firstIndex(where: { $0 == "--\(name)" || (name.count == 1 && $0 == "-\(name)") }) else { return nil }
        guard i + 1 < items.count, !items[i + 1].hasPrefix("--") else { throw CLIError.usage("--\(name) needs a value") }
        let v = items[i + 1]
        items.removeSubrange(i...(i + 1))
        return v
    }

    /// Like `option` but the flag is mandatory.
    mutating func requiredOption(_ name: String) throws -> String {
        guard let v = try option(name) else { throw CLIError.usage("missing --\(name)") }
        return v
    }

    /// A numeric option; throws a usage error when it is not a finite number.
    mutating func doubleOption(_ name: String) throws -> Double? {
        guard let s = try option(name) else { return nil }
        guard let v = Double(s), v.isFinite else { throw CLIError.usage("--\(name) must be a number, got '\(s)'") }
        return v
    }

    /// An integer option; throws a usage error when it is not an integer.
    mutating func intOption(_ name: String) throws -> Int? {
        guard let s = try option(name) else { return nil }
        guard let v = Int(s) else { throw CLIError.usage("--\(name) must be an integer, got '\(s)'") }
        return v
    }

    /// The particle filter's `--seed N` (a non-negative integer), nil when absent.
    mutating func seedOption() throws -> UInt64? {
        guard let seed = try intOption("seed") else { return nil }
        guard seed >= 0 else { throw CLIError.usage("--seed must be >= 0") }
        return UInt64(seed)
    }

    /// Removes `--name` and returns whether it was present.
    mutating func flag(_ name: String) -> Bool {
        guard let i = items.firstIndex(of: "--\(name)") else { return false }
        items.remove(at: i)
        return true
    }

    /// Removes and returns all remaining positionals; throws on leftover unknown flags.
    mutating func positionals() throws -> [String] {
        if let unknown = items.first(where: { $0.hasPrefix("--") }) { throw CLIError.usage("unknown option \(unknown)") }
        defer { items.removeAll() }
        return items
    }
}

/// One `wayfinder` subcommand. Each lives in its own file and is listed in `Subcommands.all` (main.swift).
protocol Subcommand {
    /// Name typed after `wayfinder`.
    static var name: String { get }
    /// One line for `wayfinder --help`.
    static var summary: String { get }
    /// Full usage text for `wayfinder NAME --help`.
    static var usage: String { get }
    /// Runs with the arguments after the name; returns the exit code (0 success). Throws `CLIError`.
    static func run(_ arguments: inout ArgumentList) throws -> Int32
}

/// Writes progress ("replay:  40%", "eval: BUNDLE") to stderr, only when stderr is a terminal: a log file or a
/// pipe gets no progress chatter (stdout is for results). Warnings and confirmations use `note`.
func progress(_ message: String) {
    guard stderrIsTerminal else { return }
    FileHandle.standardError.write(Data((message + "\n").utf8))
}

/// Writes a warning or a confirmation ("render: wrote walk.html") to stderr, terminal or not.
func note(_ message: String) {
    FileHandle.standardError.write(Data((message + "\n").utf8))
}

/// True when stderr is a terminal (`isatty(2)`), checked once.
let stderrIsTerminal: Bool = isatty(STDERR_FILENO) != 0
