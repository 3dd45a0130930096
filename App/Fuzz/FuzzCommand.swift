import Foundation

// wayfinder-fuzz: the project's mutation fuzzer (docs/fuzzing.md). Sub-commands:
//   list                         the targets
//   run [options]                a bounded campaign; exit 1 on any crash, hang or property violation
//   repro --target T PATH        run one input (file or directory) in this process
//   gen --target T --index I     regenerate input I of a campaign into --out PATH
//   worker ...                   (internal) the child process of `run`

/// Entry point of `wayfinder-fuzz`.
@main
enum FuzzCommand {
    /// Parses the command line and runs the sub-command.
    static func main() {
        let usage = """
        usage: wayfinder-fuzz list
               wayfinder-fuzz run [--target NAME[,NAME...]|all] [--seed N] [--execs N] [--seconds S] [--timeout S]
                                  [--jobs N] [--max-findings N] [--corpus DIR] [--out DIR]
               wayfinder-fuzz repro --target NAME PATH
               wayfinder-fuzz gen --target NAME [--seed N] --index I --out PATH [--corpus DIR]
        defaults: --target all --seed 1 --execs 10000 --seconds 60 (per target) --timeout 10 (per input)
                  --jobs 1 --max-findings 3 --corpus Tests/Fuzz/corpus --out .build/fuzz
        """

        @Sendable func fail(_ message: String) -> Never {
            FileHandle.standardError.write(Data("wayfinder-fuzz: \(message)\n".utf8))
            exit(2)
        }

        var args = Array(CommandLine.arguments.dropFirst())
        guard let command = args.first else { fail("missing sub-command\n\(usage)") }
        args.removeFirst()
        var options: [String: String] = [:]
        var positional: [String] = []
        var k = 0
        while k < args.count {
            if args[k].hasPrefix("--") {
                guard k + 1 < args.count else { fail("\(args[k]) needs a value") }
                options[String(args[k].dropFirst(2))] = args[k + 1]
                k += 2
            } else {
                positional.append(args[k]); k += 1
            }
        }
        func option<T: LosslessStringConvertible>(_ name: String, _ d: T) -> T {
            guard let s = options[name] else { return d }
            guard let v = T(s) else { fail("--\(name): bad value '\(s)'") }
            return v
        }
        func target(_ name: String) -> FuzzTarget {
            guard let t = FuzzTarget.named(name) else {
                fail("unknown target '\(name)' (\(FuzzTarget.all.map(\.name).joined(separator: ", ")))")
            }
            return t
        }
        let corpusRoot = URL(fileURLWithPath: options["corpus"] ?? "Tests/Fuzz/corpus")

        switch command {
        case "list":
            for t in FuzzTarget.all { print("\(t.name.padding(toLength: 15, withPad: " ", startingAt: 0)) \(t.summary)") }
            for t in FuzzTarget.selfTests { print("\(t.name.padding(toLength: 15, withPad: " ", startingAt: 0)) \(t.summary)") }

        case "worker":
            let t = target(options["target"] ?? "")
            do {
                let g = InputGenerator(target: t, corpus: try Corpus.of(t, root: corpusRoot), seed: option("seed", UInt64(1)))
                runWorker(target: t, generator: g, start: option("start", UInt64(0)), end: option("end", UInt64(0)),
                          deadline: Date(timeIntervalSince1970: option("deadline", 0.0)),
                          progressPath: options["progress"] ?? "progress.bin",
                          scratch: URL(fileURLWithPath: options["scratch"] ?? NSTemporaryDirectory()))
            } catch { fail("\(error)") }

        case "repro":
            let t = target(options["target"] ?? "")
            guard let path = positional.first else { fail("repro needs a PATH") }
            do {
                let input = try FuzzInput.load(from: URL(fileURLWithPath: path))
                let scratch = URL(fileURLWithPath: NSTemporaryDirectory()).appendingPathComponent("wayfinder-fuzz-repro-\(getpid())")
                defer { try? FileManager.default.removeItem(at: scratch) }
                do {
                    try t.run(input, scratch)
                    print("accepted")
                } catch let v as PropertyViolation {
                    print("PROPERTY VIOLATION: \(v)")
                    exit(propertyViolationExitCode)
                } catch {
                    print("rejected: \(error)")
                }
            } catch { fail("\(error)") }

        case "gen":
            let t = target(options["target"] ?? "")
            guard let out = options["out"], let index = options["index"].flatMap(UInt64.init) else { fail("gen needs --index and --out") }
            do {
                let g = InputGenerator(target: t, corpus: try Corpus.of(t, root: corpusRoot), seed: option("seed", UInt64(1)))
                let input = g.input(at: index)
                if input.files.count == 1 {
                    _ = FileManager.default.createFile(atPath: out, contents: Data(input.files[0].bytes))
                } else {
                    try input.write(to: URL(fileURLWithPath: out))
                }
            } catch { fail("\(error)") }

        case "run":
            let names = (options["target"] ?? "all") == "all" ? FuzzTarget.all.map(\.name)
                : (options["target"] ?? "").split(separator: ",").map(String.init)
            let targets = names.map(target)
            let o = CampaignOptions(
                seed: option("seed", UInt64(1)), executions: option("execs", UInt64(10_000)),
                secondsPerTarget: option("seconds", 60.0), inputTimeLimitSeconds: option("timeout", 10.0),
                maximumFindings: option("max-findings", 3),
                outputDirectory: URL(fileURLWithPath: options["out"] ?? ".build/fuzz"), corpusRoot: corpusRoot)
            let jobs = max(1, option("jobs", 1))
            print("wayfinder-fuzz: seed \(o.seed), \(o.executions) inputs or \(o.secondsPerTarget) s per target, "
                + "\(o.inputTimeLimitSeconds) s per input, \(jobs) job(s), corpus \(o.corpusRoot.path)")
            /// Results shared by the campaign threads (guarded by `lock`).
            final class Shared: @unchecked Sendable {
                let lock = NSLock()
                var results: [String: TargetResult] = [:]
                var errors: [String] = []
                var nextTarget = 0
            }
            let shared = Shared()
            let threads = (0..<min(jobs, targets.count)).map { _ in
                Thread {
                    while true {
                        shared.lock.lock()
                        let n = shared.nextTarget
                        shared.nextTarget += 1
                        shared.lock.unlock()
                        guard n < targets.count else { return }
                        let t = targets[n]
                        do {
                            let r = try runCampaign(target: t, options: o)
                            let s = r.stats
                            let line = String(format: "%@ %9d execs in %7.1f s (%8.0f/s), accepted %5.1f %%, %d new failure(s), %d known crash(es)",
                                              t.name.padding(toLength: 15, withPad: " ", startingAt: 0), s.executions, r.wallSeconds,
                                              Double(s.executions) / max(r.wallSeconds, 1e-9),
                                              100 * Double(s.accepted) / Double(max(s.accepted + s.rejected, 1)),
                                          r.findings.filter { $0.known == nil }.count, r.knownCrashCount)
                            shared.lock.lock(); shared.results[t.name] = r; print(line); shared.lock.unlock()
                        } catch {
                            shared.lock.lock(); shared.errors.append("\(t.name): \(error)"); shared.lock.unlock()
                        }
                    }
                }
            }
            for t in threads { t.start() }
            while true {
                usleep(50_000)
                shared.lock.lock()
                let done = shared.results.count + shared.errors.count == targets.count
                shared.lock.unlock()
                if done { break }
            }
            let results = shared.results, errors = shared.errors
            var newFailures = 0
            for name in names {
                guard let r = results[name] else { continue }
                for f in r.findings {
                    let tag = f.known.map { "KNOWN (\($0.note))" } ?? "NEW"
                    if f.known == nil { newFailures += 1 }
                    print("\(tag) \(f.kind) in \(f.target), input \(f.index): \(f.headline)\n    reproducer: \(f.reproducer)\n"
                        + "    rerun: wayfinder-fuzz repro --target \(f.target) \(f.reproducer)")
                }
            }
            let total = results.values.reduce(0) { $0 + $1.stats.executions }
            print("wayfinder-fuzz: \(total) executions, \(newFailures) new failure(s), "
                + "\(results.values.reduce(0) { $0 + $1.knownCrashCount }) known crash(es) "
                    + "(\(results.values.filter { $0.knownCrashCount > 0 }.map { "\($0.target): \($0.knownCrashCount)" }.sorted().joined(separator: ", ")))")
            for e in errors { FileHandle.standardError.write(Data("wayfinder-fuzz: \(e)\n".utf8)) }
            exit(newFailures == 0 && errors.isEmpty ? 0 : 1)

        default:
            fail("unknown sub-command '\(command)'\n\(usage)")
        }

    }
}
