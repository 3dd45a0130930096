import Foundation

/// A failing input found by a campaign.
struct Finding {
    /// "crash", "hang" or "property".
    var kind: String
    /// Target name.
    var target: String
    /// Input index under the campaign seed.
    var index: UInt64
    /// Where the reproducer was written (a file for one-file inputs, else a directory).
    var reproducer: String
    /// First line of the report naming the problem (runtime message, property, or time limit).
    var headline: String
    /// The matching known-crash entry, if any.
    var known: KnownCrash?
}

/// Totals of one target's campaign.
struct TargetResult {
    /// Target name.
    var target: String
    /// Worker statistics summed over restarts.
    var stats = WorkerStats()
    /// Failing inputs (known crashes: only the first `keptKnownCrashes`, the rest are counted).
    var findings: [Finding] = []
    /// Crashes matching the known-crash list, all of them.
    var knownCrashCount = 0
    /// Wall time including restarts, seconds.
    var wallSeconds = 0.0
}

/// Options of a campaign.
struct CampaignOptions: Sendable {
    /// Campaign seed.
    var seed: UInt64 = 1
    /// Inputs per target.
    var executions: UInt64 = 10_000
    /// Wall-time cap per target, seconds.
    var secondsPerTarget: Double = 60
    /// Per-input time limit, seconds: an input running longer is a hang.
    var inputTimeLimitSeconds: Double = 10
    /// Stop a target after this many failures.
    var maximumFindings = 3
    /// Directory for reproducers and logs.
    var outputDirectory: URL
    /// Seed-corpus root.
    var corpusRoot: URL
}

/// Runs one target's campaign in child worker processes (this executable, `worker` sub-command), so a crash
/// or a hang ends only the child: the supervisor regenerates the input from its index, writes it as a
/// reproducer, records the child's report, and restarts a worker after it.
func runCampaign(target: FuzzTarget, options o: CampaignOptions) throws -> TargetResult {
    let corpus = try Corpus.of(target, root: o.corpusRoot)
    let generator = InputGenerator(target: target, corpus: corpus, seed: o.seed)
    let work = o.outputDirectory.appendingPathComponent(target.name, isDirectory: true)
    try FileManager.default.createDirectory(at: work, withIntermediateDirectories: true)
    let progress = work.appendingPathComponent("progress.bin").path
    let stderrPath = work.appendingPathComponent("worker-stderr.log").path
    let stdoutPath = work.appendingPathComponent("worker-stdout.log").path
    let exe = URL(fileURLWithPath: "/proc/self/exe").resolvingSymlinksInPath()

    // Scratch files for targets that read from disk: in memory (/dev/shm) when the machine has it.
    let shm = URL(fileURLWithPath: "/dev/shm", isDirectory: true)
    let scratch = (FileManager.default.isWritableFile(atPath: shm.path) ? shm : work)
        .appendingPathComponent("wayfinder-fuzz-\(getpid())-\(target.name)", isDirectory: true)
    defer { try? FileManager.default.removeItem(at: scratch) }
    var result = TargetResult(target: target.name)
    let t0 = Date()
    let deadline = t0.addingTimeInterval(o.secondsPerTarget)
    var next: UInt64 = 0
    let keptKnownCrashes = 5
    while next < o.executions, Date() < deadline, result.findings.filter({ $0.known == nil }).count < o.maximumFindings {
        _ = FileManager.default.createFile(atPath: progress, contents: Data(count: 24))
        _ = FileManager.default.createFile(atPath: stderrPath, contents: nil)
        _ = FileManager.default.createFile(atPath: stdoutPath, contents: nil)
        let p = Process()
        p.executableURL = exe
        p.arguments = ["worker", "--target", target.name, "--seed", String(o.seed), "--start", String(next),
                       "--end", String(o.executions), "--deadline", String(deadline.timeIntervalSince1970),
                       "--progress", progress, "--corpus", o.corpusRoot.path,
                       "--scratch", scratch.path]
        var env = ProcessInfo.processInfo.environment
        env["SWIFT_BACKTRACE"] = env["SWIFT_BACKTRACE"] ?? "enable=yes,interactive=no,color=no,threads=crashed,registers=none,images=none,sanitize=no,symbolicate=fast,limit=24"
        p.environment = env
        p.standardError = FileHandle(forWritingAtPath: stderrPath)
        p.standardOutput = FileHandle(forWritingAtPath: stdoutPath)
        try p.run()

        var lastIndex = readProgress(progress).index
        var lastChange = Date()
        var cpuAtChange = workerCPUSeconds(p.processIdentifier) ?? 0
        var hung = false
        while p.isRunning {
            usleep(20_000)
            let i = readProgress(progress).index
            let cpu = workerCPUSeconds(p.processIdentifier)
            if i != lastIndex { lastIndex = i; lastChange = Date(); cpuAtChange = cpu ?? cpuAtChange }
            // A hang is an input that has used the time limit in CPU seconds (a loaded or niced machine can starve
            // a worker of the CPU for longer than the limit: wall time alone reported false hangs), or that has
            // made no progress for `hangWallFactor` times the limit in wall time (an input blocked in a read).
            let cpuUsed = cpu.map { $0 - cpuAtChange } ?? Date().timeIntervalSince(lastChange)
            let wallUsed = Date().timeIntervalSince(lastChange)
            if cpuUsed > o.inputTimeLimitSeconds || wallUsed > o.inputTimeLimitSeconds * hangWallFactor {
                // A worker that has written its final statistics is exiting (freeing a large heap can take
                // seconds after a 10^6-input run), not hanging on an input: wait for it.
                if let d = FileManager.default.contents(atPath: stdoutPath),
                   let line = String(decoding: d, as: UTF8.self).split(separator: "\n").last,
                   (try? JSONDecoder().decode(WorkerStats.self, from: Data(line.utf8))) != nil {
                    lastChange = Date()
                    continue
                }
                hung = true
                kill(p.processIdentifier, SIGKILL)
                p.waitUntilExit()
                break
            }
        }
        p.waitUntilExit()
        let (reportedAt, acceptedBefore, rejectedBefore) = readProgress(progress)
        if !hung, p.terminationReason == .exit, p.terminationStatus == 0 {
            if let d = FileManager.default.contents(atPath: stdoutPath),
               let line = String(decoding: d, as: UTF8.self).split(separator: "\n").last,
               let s = try? JSONDecoder().decode(WorkerStats.self, from: Data(line.utf8)) {
                result.stats.executions += s.executions; result.stats.accepted += s.accepted
                result.stats.rejected += s.rejected; result.stats.seconds += s.seconds
            }
            break
        }
        // Failure at input `at`: count the inputs before it, write the reproducer and the report.
        // A worker that failed before reporting its first input leaves the zeroed progress: the failure is at
        // `next` (never index arithmetic below it).
        let at = max(reportedAt, next)
        result.stats.executions += Int(at - next) + 1
        result.stats.accepted += acceptedBefore
        result.stats.rejected += rejectedBefore
        let report = String(decoding: FileManager.default.contents(atPath: stderrPath) ?? Data(), as: UTF8.self)
        let kind = hung ? "hang" : (p.terminationReason == .exit && p.terminationStatus == propertyViolationExitCode ? "property" : "crash")
        let frame = report.split(separator: "\n").first { $0.contains(" in wayfinder-fuzz") && $0.contains(" 0x") }
            .map { line -> String in
                let afterAddress = line.split(separator: " ", omittingEmptySubsequences: true).drop { !$0.hasPrefix("0x") }.dropFirst()
                return afterAddress.joined(separator: " ").components(separatedBy: " in wayfinder-fuzz").first ?? ""
            }
        let known = kind == "crash" ? knownCrashes.first { k in k.target == target.name && k.reportContains.allSatisfy { report.contains($0) } } : nil
        next = at + 1
        if known != nil {
            result.knownCrashCount += 1
            if result.knownCrashCount > keptKnownCrashes { continue }
        }
        let input = generator.input(at: at)
        let base = work.appendingPathComponent("\(kind)-\(o.seed)-\(at)")
        let reproducer: URL
        if input.files.count == 1 {
            reproducer = base.appendingPathExtension(URL(fileURLWithPath: input.files[0].name).pathExtension)
            _ = FileManager.default.createFile(atPath: reproducer.path, contents: Data(input.files[0].bytes))
        } else {
            reproducer = base
            try input.write(to: base)
        }
        try Data(report.utf8).write(to: base.appendingPathExtension("log"))
        let headline = hung ? "no progress for \(o.inputTimeLimitSeconds) CPU s or \(o.inputTimeLimitSeconds * hangWallFactor) wall s (per-input limits)"
            : (report.split(separator: "\n").first { $0.contains("Fatal error") || $0.contains("runtime failure") || $0.contains("PROPERTY VIOLATION") }
                ?? report.split(separator: "\n").first { $0.contains("crashed") }).map { $0.trimmingCharacters(in: CharacterSet(charactersIn: "* ")) } ?? "worker ended with \(p.terminationReason == .exit ? "status" : "signal") \(p.terminationStatus)"
        // With the innermost frame in this executable (the project's code, not the runtime's): "function + offset".
        let fullHeadline = frame.map { "\(headline) [\($0)]" } ?? headline
        result.findings.append(Finding(kind: kind, target: target.name, index: at, reproducer: reproducer.path,
                                       headline: fullHeadline, known: known))
    }
    result.wallSeconds = Date().timeIntervalSince(t0)
    return result
}

/// The worker's progress record: index of the input running (or last run), inputs accepted and rejected
/// before it.
/// Wall time without progress that counts as a hang, in multiples of the per-input CPU limit.
let hangWallFactor = 6.0

/// CPU time (user + system) the process has used, seconds, from /proc/PID/stat (fields 14 and 15, in clock
/// ticks); nil where /proc is unavailable (the wall-time backstop then stands alone).
func workerCPUSeconds(_ pid: Int32) -> Double? {
    guard let d = FileManager.default.contents(atPath: "/proc/\(pid)/stat") else { return nil }
    let text = String(decoding: d, as: UTF8.self)
    // The command name (field 2) is in parentheses and may hold spaces: split after its closing parenthesis.
    guard let close = text.lastIndex(of: ")") else { return nil }
    let fields = text[text.index(after: close)...].split(separator: " ")
    // After ")": field 3 is fields[0], so utime (14) is fields[11] and stime (15) fields[12].
    guard fields.count > 12, let u = Double(fields[11]), let st = Double(fields[12]) else { return nil }
    let ticks = Double(sysconf(Int32(_SC_CLK_TCK)))
    return ticks > 0 ? (u + st) / ticks : nil
}

private func readProgress(_ path: String) -> (index: UInt64, accepted: Int, rejected: Int) {
    guard let d = FileManager.default.contents(atPath: path), d.count >= 24 else { return (0, 0, 0) }
    let b = [UInt8](d)
    func word(_ k: Int) -> UInt64 { (0..<8).reduce(UInt64(0)) { $0 | UInt64(b[8 * k + $1]) << (8 * UInt64($1)) } }
    return (word(0), Int(word(1)), Int(word(2)))
}
