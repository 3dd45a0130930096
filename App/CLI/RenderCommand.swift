import Evaluation
import Foundation
import WayfinderCore

/// `wayfinder render`: the trainer's HTML (and PNG) picture of a walk.
enum RenderCommand: Subcommand {
    static let name = "render"
    static let summary = "draw a walk for a trainer: plan, truth, estimate, particles, sightings, announcements"
    static let usage = """
    Usage: wayfinder render BUNDLE --map MAP -o WALK.html [--png WALK.png] [--at T1,T2,...] [--to DEST] [--seed N]

    Replays BUNDLE through the pipeline and writes a static, self-contained HTML page: the floor plan with
    walls, signs and graph; the true path (if truth.jsonl is present) and the estimate coloured by error;
    particle clouds at the start, first convergence, middle, end and at each --at time (seconds); sign
    sightings as rays; the announcements numbered where they were spoken, a timeline and summary figures.
    --png also screenshots the page with headless Chromium.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let mapPath = try arguments.requiredOption("map")
        let out = try arguments.requiredOption("o")
        let png = try arguments.option("png")
        var pipeline = PipelineOptions()
        pipeline.destinationId = try arguments.option("to")
        if let seed = try arguments.seedOption() { pipeline.seed = seed }
        var times: [Double] = []
        if let at = try arguments.option("at") {
            for part in at.split(separator: ",") {
                guard let v = Double(part.trimmingCharacters(in: .whitespaces)), v.isFinite else {
                    throw CLIError.usage("--at takes comma-separated seconds, got '\(part)'")
                }
                times.append(v)
            }
        }
        let positionals = try arguments.positionals()
        guard positionals.count == 1 else { throw CLIError.usage("expected one BUNDLE directory (see --help)") }
        let building = try loadMap(mapPath)
        let bundle = try loadBundle(positionals[0])
        var options = Replay.Options(pipeline: Replay.options(for: bundle, overriding: pipeline))
        options.snapshotTimes = times
        options.snapshotParticleCount = 1200
        let result: ReplayResult
        do { result = try Replay.run(bundle: bundle, building: building, options: options) } catch {
            throw CLIError.failure("\(positionals[0]): \(error)")
        }
        let score: WalkScore? = bundle.truth.isEmpty ? nil : WalkEvaluator.score(
            name: bundle.url.lastPathComponent, result: result, truth: bundle.truth, building: building,
            destination: options.pipeline.destinationId)
        let html = WalkReport.html(title: "Walk \(bundle.url.lastPathComponent)", building: building, result: result,
                                   truth: bundle.truth, score: score)
        let htmlURL = URL(fileURLWithPath: out)
        do { try Data(html.utf8).write(to: htmlURL, options: .atomic) } catch {
            throw CLIError.failure("cannot write \(out): \(error.localizedDescription)")
        }
        progress("render: wrote \(out)")
        if let png {
            do { try ChromiumScreenshot.capture(html: htmlURL, png: URL(fileURLWithPath: png)) } catch {
                throw CLIError.failure("\(error)")
            }
            progress("render: wrote \(png)")
        }
        return 0
    }
}
