import Dispatch
import Foundation
import Maps
import SessionFormat
import WayfinderCore

/// `wayfinder bench`: Swift-side benchmarks, each reported with a baseline measured in the same run.
/// The C++ cores have their own Google Benchmark programs (docs/benchmarks.md).
enum BenchCommand: Subcommand {
    static let name = "bench"
    static let summary = "benchmarks with same-run baselines (navigation, replay pipeline)"
    static let usage = """
    Usage: wayfinder bench [--iterations N] [--bundle BUNDLE --map MAP] [--json]

    Runs on one thread and prints one row per measurement: the time per operation, the baseline measured
    in the same run, and their ratio (baseline / measured; > 1 means faster than the baseline).
      navigation.*  snap + route on a generated 5,000-node building; baseline: linear-scan snapping and an
                    array-based O(V^2) Dijkstra.
      pipeline.*    the whole per-frame pipeline replaying BUNDLE (default: the bundled sample walk) with the
                    default 20,000 particles; baseline: the camera's frame interval (the real-time budget).
    Exit codes: 0 ok, 1 bad input (map, bundle), 2 usage.
    """

    struct Row: Encodable {
        let name: String
        let nanosecondsPerOp: Double
        let baselineNanosecondsPerOp: Double?
        var ratio: Double? { baselineNanosecondsPerOp.map { $0 / nanosecondsPerOp } }
        enum CodingKeys: String, CodingKey { case name, nanosecondsPerOp, baselineNanosecondsPerOp, ratio }
        func encode(to encoder: Encoder) throws {
            var c = encoder.container(keyedBy: CodingKeys.self)
            try c.encode(name, forKey: .name)
            try c.encode(nanosecondsPerOp, forKey: .nanosecondsPerOp)
            try c.encodeIfPresent(baselineNanosecondsPerOp, forKey: .baselineNanosecondsPerOp)
            try c.encodeIfPresent(ratio, forKey: .ratio)
        }
    }

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let iterations = try arguments.intOption("iterations") ?? 2000
        let bundlePath = try arguments.option("bundle") ?? "App/Samples/office-walk"
        let mapPath = try arguments.option("map") ?? "office"
        let json = arguments.flag("json")
        _ = try arguments.positionals()

        var rows: [Row] = []
        progress("bench: navigation (\(iterations) queries)")
        rows += NavigationBench.run(iterations: iterations).map {
            Row(name: $0.name, nanosecondsPerOp: $0.nanosecondsPerOp, baselineNanosecondsPerOp: $0.baselineNanosecondsPerOp)
        }
        progress("bench: pipeline replay of \(bundlePath)")
        rows.append(try pipelineRow(bundlePath: bundlePath, mapPath: mapPath))

        if json {
            let e = JSONEncoder()
            e.outputFormatting = [.prettyPrinted, .sortedKeys]
            print(String(decoding: try e.encode(rows), as: UTF8.self))
        } else {
            print("name".padding(toLength: 64, withPad: " ", startingAt: 0) + "      ns/op   baseline ns/op    ratio")
            for r in rows {
                let base = r.baselineNanosecondsPerOp.map { String(format: "%16.0f", $0) } ?? String(repeating: " ", count: 15) + "-"
                let ratio = r.ratio.map { String(format: "%8.1fx", $0) } ?? "        -"
                print(r.name.padding(toLength: 64, withPad: " ", startingAt: 0) + String(format: "%11.0f", r.nanosecondsPerOp) + base + ratio)
            }
        }
        return 0
    }

    static func pipelineRow(bundlePath: String, mapPath: String) throws -> Row {
        let building = try loadMap(mapPath)
        let bundle = try loadBundle(bundlePath)
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: PipelineOptions()))
        options.snapshotParticleCount = 0
        let t0 = DispatchTime.now().uptimeNanoseconds
        let result = try Replay.run(bundle: bundle, building: building, options: options)
        let elapsed = Double(DispatchTime.now().uptimeNanoseconds - t0)
        let perFrame = elapsed / Double(max(1, result.trace.count))
        let duration = (bundle.frames.last?.t ?? 0) - (bundle.frames.first?.t ?? 0)
        let frameInterval = duration / Double(max(1, bundle.frames.count - 1)) * 1e9
        return Row(name: "pipeline.frame (replay, \(options.pipeline.localizer.particleCount) particles, vs frame interval)",
                   nanosecondsPerOp: perFrame, baselineNanosecondsPerOp: frameInterval)
    }
}
