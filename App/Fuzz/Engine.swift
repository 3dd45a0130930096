import Foundation

/// The seed inputs of one target: every file or directory directly under `<corpus>/<target>/`, in name order.
struct Corpus {
    /// Entry names (file or directory names), aligned with `entries`.
    let names: [String]
    /// The seed inputs.
    let entries: [FuzzInput]

    /// The corpus of `target`: its built-in seeds (self-test targets) or `<root>/<target name>`.
    static func of(_ target: FuzzTarget, root: URL) throws -> Corpus {
        if let seeds = target.builtinSeeds {
            return Corpus(names: seeds.indices.map { "builtin-\($0)" }, entries: seeds)
        }
        return try Corpus(root: root, target: target.name)
    }

    /// A corpus held in memory.
    init(names: [String], entries: [FuzzInput]) { self.names = names; self.entries = entries }

    /// Loads `<root>/<target>`. Throws when the directory is missing or empty.
    init(root: URL, target: String) throws {
        let dir = root.appendingPathComponent(target, isDirectory: true)
        guard let names = try? FileManager.default.contentsOfDirectory(atPath: dir.path).filter({ !$0.hasPrefix(".") }).sorted(),
              !names.isEmpty else {
            throw FuzzError("\(dir.path): no seed corpus for target '\(target)'")
        }
        self.names = names
        entries = try names.map { try FuzzInput.load(from: dir.appendingPathComponent($0)) }
    }
}

/// Builds input number `index` of a campaign: a pure function of (seed, target, index, corpus), so any
/// input (a crash, a hang) can be regenerated from its index without storing every input.
struct InputGenerator {
    /// The target the inputs are for.
    let target: FuzzTarget
    /// Seed inputs.
    let corpus: Corpus
    /// Campaign seed.
    let seed: UInt64

    /// Input `index`: one seed entry, then (95 % of the time) a file-level change for multi-file inputs
    /// (drop an optional file, swap in another entry's file of the same name) and stacked byte mutations of
    /// one file (sometimes two), spliced with the same-named files of the other entries.
    func input(at index: UInt64) -> FuzzInput {
        var rng = SplitMix64(seed: seed, target: target.name, index: index)
        let base = rng.below(corpus.entries.count)
        var input = corpus.entries[base]
        guard !rng.chance(0.05) else { return input }
        func donors(for name: String) -> [[UInt8]] {
            corpus.entries.enumerated().compactMap { (i, e) in
                i == base ? nil : (e.bytes(of: name) ?? (e.files.count == 1 && input.files.count == 1 ? e.files[0].bytes : nil))
            }
        }
        if input.files.count > 1 {
            let r = rng.below(10)
            let droppable = input.files.indices.filter { target.optionalFiles.contains(input.files[$0].name) }
            if r == 0, !droppable.isEmpty {
                input.files.remove(at: rng.pick(droppable))
            } else if r == 1 {
                let i = rng.below(input.files.count)
                if let other = donors(for: input.files[i].name).isEmpty ? nil : rng.pick(donors(for: input.files[i].name)) {
                    input.files[i].bytes = other
                }
            }
        }
        let edits = input.files.count > 1 && rng.chance(0.2) ? 2 : 1
        for _ in 0..<edits {
            let i = rng.below(input.files.count)
            let name = input.files[i].name
            input.files[i].bytes = Mutator.mutate(input.files[i].bytes, donors: donors(for: name),
                                                  binary: target.isBinary(name), rng: &rng)
        }
        return input
    }
}

/// Outcome counts of a worker, printed as one JSON line on its standard output at the end.
struct WorkerStats: Codable, Sendable {
    /// Inputs run.
    var executions: Int = 0
    /// Inputs the target accepted (returned normally).
    var accepted: Int = 0
    /// Inputs the target rejected with an ordinary error.
    var rejected: Int = 0
    /// Wall time of the loop, seconds.
    var seconds: Double = 0
}

/// Exit status of a worker that found a `PropertyViolation`.
let propertyViolationExitCode: Int32 = 70

/// Runs inputs `start ..< end` of one target in this process, stopping early at `deadline`. Before each
/// input the record (index, accepted so far, rejected so far) is written over `progressPath` (3 x 8 bytes,
/// little-endian), so the supervisor knows which input was running when this process crashed or hung, and
/// how the earlier ones ended.
func runWorker(target: FuzzTarget, generator: InputGenerator, start: UInt64, end: UInt64, deadline: Date,
               progressPath: String, scratch: URL) -> Never {
    let fd = open(progressPath, O_WRONLY | O_CREAT, 0o644)
    guard fd >= 0 else { FileHandle.standardError.write(Data("cannot open \(progressPath)\n".utf8)); exit(2) }
    try? FileManager.default.createDirectory(at: scratch, withIntermediateDirectories: true)
    var stats = WorkerStats()
    let t0 = Date()
    var i = start
    while i < end {
        if (i - start) % 64 == 0 && Date() >= deadline { break }
        var record = (i.littleEndian, UInt64(stats.accepted).littleEndian, UInt64(stats.rejected).littleEndian)
        _ = withUnsafeBytes(of: &record) { pwrite(fd, $0.baseAddress, 24, 0) }
        let input = generator.input(at: i)
        do {
            try target.run(input, scratch)
            stats.accepted += 1
        } catch let v as PropertyViolation {
            FileHandle.standardError.write(Data("PROPERTY VIOLATION (\(target.name), input \(i)): \(v)\n".utf8))
            exit(propertyViolationExitCode)
        } catch {
            stats.rejected += 1
        }
        stats.executions += 1
        i += 1
    }
    stats.seconds = Date().timeIntervalSince(t0)
    let line = (try? JSONEncoder().encode(stats)).map { String(decoding: $0, as: UTF8.self) } ?? "{}"
    print(line)
    exit(0)
}
